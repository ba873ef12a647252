#!/usr/bin/env python3
"""Fly JSBSim's c172p headless and write wireflight flight-data CSV (docs/flight-data.md).

    python3 tools/jsbsim/fly.py doublets   --rate 25 --duration 50 --out tests/data/jsbsim-c172p-doublets.csv
    python3 tools/jsbsim/fly.py steps      --rate 25 --duration 50 --out tests/data/jsbsim-c172p-steps.csv
    python3 tools/jsbsim/fly.py validation --rate 25 --duration 50 --out tests/data/jsbsim-c172p-validation.csv
    python3 tools/jsbsim/fly.py doublets --noise --seed 7 --wind 5,-3,0 --out /tmp/windy.csv
    python3 tools/jsbsim/fly.py sequence --inputs-seed 4 --seed 4 --noise --rate 25 \
        --scale Clda=0.75 --out /tmp/clda075.csv          # a changed c172p (c172p_variant.py)
    python3 tools/jsbsim/fly.py sequence --inputs-seed 8 --turbulence light --turbulence-seed 8 \
        --out /tmp/turb.csv                               # + turb_* gust truth columns

Manoeuvres (all start from a full trim in still air at --airspeed/--altitude, heading
--heading; with --wind the aircraft is restarted from that trim with ground velocity = air
velocity + wind, so it starts steady relative to the air):

* doublets:   open loop. Elevator doublet +-3 deg (1 s each way) at 3 s, aileron doublet +-3 deg
              at 13 s, rudder doublet +-3 deg at 23 s, throttle step +0.15 from 33 s to 43 s.
* steps:      a simple digital autopilot (runs at the output rate) follows bank steps
              (+20 deg at 4 s, 0 at 14 s, -20 deg at 20 s, 0 at 30 s) and pitch steps (+4 deg
              at 32 s, -3 deg at 38 s, back to trim pitch at 44 s) while holding airspeed with
              the throttle and damping sideslip with the rudder.
* validation: open loop, for held-out validation: elevator 3-2-1-1 (+-2 deg, 0.5 s unit) at
              3 s, rudder doublet +-4 deg at 16 s, aileron 3-2-1-1 (+-2 deg, 0.5 s unit) at
              28 s, throttle step -0.12 from 38 s.
* sequence:   open loop, drawn from --inputs-seed (different seeds, different flights): one
              doublet or 3-2-1-1 on each of elevator, aileron and rudder in a random order, a
              fourth on a random surface, then a throttle step (see class Sequence).

A changed aircraft: --scale NAME=F multiplies aero/coefficient/NAME of c172p.xml by F
(checked in JSBSim before flying), --payload-kg adds a payload at the CG (c172p_variant.py).
--turbulence light|moderate|severe (with --turbulence-seed) switches on JSBSim's Dryden
milspec turbulence and writes the gusts as extra turb_* columns. Such flights, and every
sequence flight, carry `# jsbsim_change`, `# jsbsim_turbulence`, `# jsbsim_mass_kg` and
`# jsbsim_manoeuvre` metadata lines.

All inputs are relative to the trim values. Controls are zero-order hold from each row's time:
each row's command is set one integration step before the row's time (a command set before
run() acts one step late in JSBSim), so the state at a row has not yet felt that row's command
and the command acts from the row's time until the next row. Surfaces are JSBSim's actual
positions in Beard & McLain's convention (da = (left - right)/2); throttle is the command.
Commands are rounded to the CSV's resolution before JSBSim gets them (throttle to 1e-4), so the
recorded controls are what the aircraft received.

Positions, velocities and attitude are in the flat north-east-down tangent frame at the start
point (the metadata origin), rotated from JSBSim's ECEF position and body->ECEF attitude;
p, q, r are JSBSim's body rates relative to the Earth. Integration: dt = 1/400 s,
rotational integrators Adams-Bashforth 2. Files are written atomically (temp + rename).
Needs only the `jsbsim` package.
"""

from __future__ import annotations

import argparse
import math
import os
import random
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from c172p_sim import C172P, DT, JSBSIM_VERSION  # noqa: E402
from c172p_variant import Variant, parse_scale  # noqa: E402

D2R = math.pi / 180.0
R2D = 180.0 / math.pi


# ------------------------------------------------------------------------------ manoeuvres
def pulse_train(t: float, start: float, pieces) -> float:
    """pieces: [(duration, value), ...] from `start`; 0 outside."""
    t0 = start
    for dur, val in pieces:
        if t0 <= t < t0 + dur - 1e-9:
            return val
        t0 += dur
    return 0.0


class Doublets:
    name = "doublets"
    description = ("elevator doublet +-3 deg at 3 s, aileron doublet +-3 deg at 13 s, rudder "
                   "doublet +-3 deg at 23 s (1 s each way), throttle +0.15 from 33 s to 43 s")

    def __init__(self, trim, rate):
        self.trim = trim

    def controls(self, t, s):
        tr = self.trim
        a = 3.0 * D2R
        de = tr["de"] + pulse_train(t, 3.0, [(1.0, a), (1.0, -a)])
        da = tr["da"] + pulse_train(t, 13.0, [(1.0, a), (1.0, -a)])
        dr = tr["dr"] + pulse_train(t, 23.0, [(1.0, a), (1.0, -a)])
        dt = tr["throttle"] + pulse_train(t, 33.0, [(10.0, 0.15)])
        return de, da, dr, dt


class Validation:
    name = "validation"
    description = ("elevator 3-2-1-1 +-2 deg (0.5 s unit) at 3 s, rudder doublet +-4 deg "
                   "(1 s each way) at 16 s, aileron 3-2-1-1 +-2 deg (0.5 s unit) at 28 s, "
                   "throttle -0.12 from 38 s")

    def __init__(self, trim, rate):
        self.trim = trim

    def controls(self, t, s):
        tr = self.trim
        a2, a4 = 2.0 * D2R, 4.0 * D2R
        u = 0.5
        de = tr["de"] + pulse_train(t, 3.0, [(3 * u, a2), (2 * u, -a2), (u, a2), (u, -a2)])
        dr = tr["dr"] + pulse_train(t, 16.0, [(1.0, a4), (1.0, -a4)])
        da = tr["da"] + pulse_train(t, 28.0, [(3 * u, a2), (2 * u, -a2), (u, a2), (u, -a2)])
        dt = tr["throttle"] + pulse_train(t, 38.0, [(1e9, -0.12)])
        return de, da, dr, dt


class Steps:
    """Successive-loop autopilot (Beard & McLain ch. 6, reduced), run at the output rate:

    roll:     da = da_trim + k_phi (phi_c - phi) - k_p p
    pitch:    de = de_trim - k_th (th_c - th) + k_q q - k_i int(th_c - th)   (de < 0: nose up)
    airspeed: dt = dt_trim + k_v (V_c - Va) + k_iv int(V_c - Va), clamped to 0..1
    sideslip: dr = dr_trim - k_b beta

    Gains from the c172p's roll (pdot ~ 27 da - 6.3 p) and pitch (qdot ~ -25 de - 3.3 q -
    34 alpha) dynamics at 50 m/s."""

    name = "steps"
    description = ("autopilot bank steps +20 deg at 4 s, 0 at 14 s, -20 deg at 20 s, 0 at "
                   "30 s; pitch steps +4 deg at 32 s, -3 deg at 38 s, trim pitch at 44 s; "
                   "airspeed held by throttle, sideslip damped by rudder")
    K_PHI, K_P = 0.35, 0.05
    K_TH, K_Q, K_I = 1.2, 0.25, 0.6
    K_V, K_IV = 0.04, 0.01
    K_B = 0.8

    def __init__(self, trim, rate):
        self.trim = trim
        self.h = 1.0 / rate
        self.int_th = 0.0
        self.int_v = 0.0

    def targets(self, t):
        phi_c = pulse_train(t, 4.0, [(10.0, 20.0), (6.0, 0.0), (10.0, -20.0)]) * D2R
        th_c = self.trim["theta"] + pulse_train(t, 32.0, [(6.0, 4.0), (6.0, -3.0)]) * D2R
        return phi_c, th_c, self.trim["va"]

    def controls(self, t, s):
        tr = self.trim
        phi_c, th_c, v_c = self.targets(t)
        e_th = th_c - s["theta"]
        e_v = v_c - s["va"]
        da = tr["da"] + self.K_PHI * (phi_c - s["phi"]) - self.K_P * s["p"]
        de = tr["de"] - self.K_TH * e_th + self.K_Q * s["q"] - self.K_I * self.int_th
        dt = tr["throttle"] + self.K_V * e_v + self.K_IV * self.int_v
        dr = tr["dr"] - self.K_B * s["beta"]
        # Integrate after use (the command at t uses the integral up to t); anti-windup by
        # stopping the throttle integral while saturated.
        self.int_th += e_th * self.h
        if 0.0 < dt < 1.0:
            self.int_v += e_v * self.h
        lim = lambda x, lo, hi: max(lo, min(hi, x))  # noqa: E731
        return (lim(de, -25 * D2R, 20 * D2R), lim(da, -15 * D2R, 15 * D2R),
                lim(dr, -15 * D2R, 15 * D2R), lim(dt, 0.0, 1.0))


class Sequence:
    """Open loop, drawn from --inputs-seed: one input on each of elevator, aileron and rudder
    in a random order, a fourth on a random surface, then a throttle step. Each input is a
    doublet (unit 0.6..1.2 s) or a 3-2-1-1 (unit 0.3..0.6 s) with a random sign and amplitude
    (elevator 1.5..3 deg, aileron and rudder 2..4 deg); inputs start 8.5..9.5 s apart from
    2..3 s; the throttle step (+-0.08..0.15, 6..10 s long) follows the last one. Times are
    multiples of 0.1 s so that the inputs switch on rows at 10, 20, 25 or 50 Hz. Different
    seeds give different flights of the same aircraft."""

    name = "sequence"
    AMP = {"elevator": (1.5, 3.0), "aileron": (2.0, 4.0), "rudder": (2.0, 4.0)}

    def __init__(self, trim, rate, seed=1):
        self.trim = trim
        rng = random.Random(seed)
        r01 = lambda x: round(x, 1)  # noqa: E731
        axes = ["elevator", "aileron", "rudder"]
        rng.shuffle(axes)
        axes.append(rng.choice([a for a in self.AMP if a != axes[-1]]))
        t = r01(rng.uniform(2.0, 3.0))
        self.inputs = []  # (axis, start, pieces, text)
        for ax in axes:
            lo, hi = self.AMP[ax]
            amp = round(rng.uniform(lo, hi), 1) * rng.choice((1, -1))
            if rng.random() < 0.5:
                u = r01(rng.uniform(0.6, 1.2))
                pieces = [(u, amp), (u, -amp)]
                shape = f"doublet {amp:+g}/{-amp:+g} deg, {u:g} s each way"
            else:
                u = r01(rng.uniform(0.3, 0.6))
                pieces = [(3 * u, amp), (2 * u, -amp), (u, amp), (u, -amp)]
                shape = f"3-2-1-1 {amp:+g} deg, {u:g} s unit"
            self.inputs.append((ax, t, [(d, v * D2R) for d, v in pieces],
                                f"{ax} {shape} at {t:g} s"))
            t = r01(t + rng.uniform(8.5, 9.5))
        dthr = round(rng.uniform(0.08, 0.15), 2) * rng.choice((1, -1))
        dur = r01(rng.uniform(6.0, 10.0))
        self.throttle = (t, dur, dthr)
        self.description = (f"inputs seed {seed}: " + "; ".join(x[3] for x in self.inputs)
                            + f"; throttle {dthr:+g} from {t:g} s for {dur:g} s")

    def controls(self, t, s):
        tr = self.trim
        d = {"elevator": 0.0, "aileron": 0.0, "rudder": 0.0}
        for ax, start, pieces, _ in self.inputs:
            d[ax] += pulse_train(t, start, pieces)
        t0, dur, dthr = self.throttle
        dt = tr["throttle"] + pulse_train(t, t0, [(dur, dthr)])
        return (tr["de"] + d["elevator"], tr["da"] + d["aileron"], tr["dr"] + d["rudder"], dt)


MANOEUVRES = {m.name: m for m in (Doublets, Steps, Validation, Sequence)}


# ------------------------------------------------------------------------------ flying
def quantise_command(cmd):
    """Round commands to the CSV's resolution (surfaces 1e-4 deg, throttle 1e-4)."""
    de, da, dr, dt = cmd
    q = lambda x: round(x * R2D, 4) * D2R  # noqa: E731
    return q(de), q(da), q(dr), round(dt, 4)


TURBULENCE = {  # MIL-F-8785C reference values (FGWinds.h): W20 (ft/s), severity index
    "light": (25.0, 3), "moderate": (50.0, 4), "severe": (75.0, 6),
}


def fly(manoeuvre: str, duration: float, rate: float, airspeed: float, altitude: float,
        lat: float, lon: float, heading: float, wind=(0.0, 0.0, 0.0), variant=None,
        turbulence=None, turbulence_seed=1, inputs_seed=1, record=None):
    """Fly and return (rows, info). rows: list of sample dicts (SI, radians) with the command.

    variant: a c172p_variant.Variant (scaled coefficients, payload) or None; turbulence:
    None or a key of TURBULENCE (Dryden milspec, switched on after the trim and the restart,
    seeded with turbulence_seed); the gusts are recorded in each row as `turb`. record: None
    or a function of the C172P whose value each row keeps as `record` (more of JSBSim's state
    than the CSV holds)."""
    steps_per_row = round(1.0 / (rate * DT))
    if abs(steps_per_row * rate * DT - 1.0) > 1e-9:
        raise SystemExit(f"--rate must divide {1 / DT:.0f} Hz (got {rate})")
    root = variant.build() if variant is not None else None
    sim = C172P(root=root)
    trim = sim.trim(airspeed, altitude, lat, lon, heading)
    cls = MANOEUVRES[manoeuvre]
    man = cls(trim, rate, inputs_seed) if cls is Sequence else cls(trim, rate)
    n_rows = int(round(duration * rate)) + 1

    # Row 0: its command is in place before the (re)start computes the first derivatives.
    s = dict(trim)
    cmd = quantise_command(man.controls(0.0, s))
    sim.command(*cmd)
    sim.restart(trim, wind)
    if turbulence:
        w20, sev = TURBULENCE[turbulence]
        sim["simulation/randomseed"] = turbulence_seed
        sim["atmosphere/turb-type"] = 3
        sim["atmosphere/turbulence/milspec/windspeed_at_20ft_AGL-fps"] = w20
        sim["atmosphere/turbulence/milspec/severity"] = sev
    origin = sim.set_origin()

    def sample():
        st = sim.sample()
        if turbulence:
            st["turb"] = turbulence_truth(sim)
        if record is not None:
            st["record"] = record(sim)
        return st

    rows = []
    s = sample()
    s["mass_kg"] = sim.mass_props()["mass_kg"]
    s["cmd"] = cmd
    rows.append(s)
    for k in range(1, n_rows):
        t_k = k / rate
        for j in range(steps_per_row):
            if j == steps_per_row - 1:
                # One step before the row's time: this row's command, so that it acts from t_k.
                cmd = quantise_command(man.controls(t_k, sim.sample()))
                sim.command(*cmd)
            sim.fdm.run()
        s = sample()
        if abs(s["t"] - t_k) > 1e-6:
            raise RuntimeError(f"time mismatch {s['t']} vs {t_k}")
        s["t"] = t_k
        s["cmd"] = cmd
        rows.append(s)
    info = dict(trim=trim, origin=origin, man=man, mass_start=rows[0]["mass_kg"],
                mass_end=sim["inertia/mass-slugs"],
                fuel_end=sim["propulsion/total-fuel-lbs"],
                variant=variant, turbulence=turbulence, turbulence_seed=turbulence_seed)
    return rows, info


def turbulence_truth(sim):
    """JSBSim's gust velocity (m/s, local NED at the aircraft, which differs from the flat
    frame by the angle travelled over the Earth: < 0.03 deg per 3 km) and gust rates
    (deg/s, body axes)."""
    f = sim.fdm
    return (f["atmosphere/turb-north-fps"] * 0.3048, f["atmosphere/turb-east-fps"] * 0.3048,
            f["atmosphere/turb-down-fps"] * 0.3048, f["atmosphere/p-turb-rad_sec"] * R2D,
            f["atmosphere/q-turb-rad_sec"] * R2D, f["atmosphere/r-turb-rad_sec"] * R2D)


# ------------------------------------------------------------------------------ CSV
COLUMNS = ["time_s", "north_m", "east_m", "down_m", "roll_deg", "pitch_deg", "yaw_deg",
           "vn_mps", "ve_mps", "vd_mps", "p_dps", "q_dps", "r_dps", "airspeed_mps",
           "throttle", "elevator_deg", "aileron_deg", "rudder_deg"]


# Gust truth (JSBSim's turbulence, not read by wireflight): velocity of the air's gust, m/s,
# north/east/down (JSBSim's local NED at the aircraft), and gust rates, deg/s, body axes.
TURB_COLUMNS = ["turb_north_mps", "turb_east_mps", "turb_down_mps", "turb_p_dps",
                "turb_q_dps", "turb_r_dps"]


def wrap180(x):
    x = math.fmod(x + 180.0, 360.0)
    if x <= 0:
        x += 360.0
    return x - 180.0


def num(x: float, dec: int) -> str:
    s = f"{x:.{dec}f}"
    if s.startswith("-") and float(s) == 0.0:
        s = s[1:]
    return s


def csv_text(rows, info, args, noise) -> str:
    rng = random.Random(args.seed)
    npos, nang, nvel, nrate = noise

    def g(sd):
        return rng.gauss(0.0, sd) if sd > 0 else 0.0

    o = info["origin"]
    man = info["man"]
    w = args.wind
    wind_txt = "still air" if not any(w) else f"steady wind NED ({w[0]:g}, {w[1]:g}, {w[2]:g}) m/s"
    noise_txt = ("noise-free" if not any(noise) else
                 f"noise (1 sigma) {npos:g} m, {nang:g} deg, {nvel:g} m/s, {nrate:g} deg/s, "
                 f"seed {args.seed}")
    tr = info["trim"]
    var = info["variant"]
    change = var.describe() if var is not None else "none"
    turb = info["turbulence"]
    if turb:
        w20, sev = TURBULENCE[turb]
        turb_txt = (f"Dryden milspec turbulence {turb} (windspeed_at_20ft_AGL {w20:g} ft/s, "
                    f"severity {sev}), seed {info['turbulence_seed']}")
    else:
        turb_txt = "none"
    aircraft_txt = "c172p" if change == "none" else f"c172p changed ({change})"
    lines = [
        f"# source: JSBSim {JSBSIM_VERSION} {aircraft_txt} {man.name}: {man.description}; "
        f"from full trim "
        f"at {tr['va']:.1f} m/s true airspeed, {args.altitude:g} m, heading {args.heading:g} deg "
        f"(alpha {tr['alpha'] * R2D:.3f} deg, elevator {tr['de'] * R2D:.3f} deg, throttle "
        f"{tr['throttle']:.4f}); {wind_txt}"
        + ("" if not turb else f"; {turb_txt} (truth in the turb_* columns)")
        + f"; dt 1/400 s, AB2 rotational integrators; {noise_txt}; made by tools/jsbsim/fly.py",
        "# vehicle: fixed-wing",
        f"# aircraft: {aircraft_meta(args)}",
        f"# latitude_deg: {o['lat']:.8f}",
        f"# longitude_deg: {o['lon']:.8f}",
        f"# altitude_m: {o['alt']:.3f}",
    ]
    # The flights of tests/data (fixed manoeuvres, unchanged, calm) keep their exact text.
    if change != "none" or turb or man.name == "sequence":
        lines += [
            f"# jsbsim_change: {change}",
            f"# jsbsim_turbulence: {turb_txt}",
            f"# jsbsim_mass_kg: {info['mass_start']:.3f}",
            f"# jsbsim_manoeuvre: {man.name}"
            + (f" (inputs seed {args.inputs_seed})" if man.name == "sequence" else ""),
        ]
    lines.append(",".join(COLUMNS + (TURB_COLUMNS if turb else [])))
    for s in rows:
        de, da, dr = s["de"], s["da"], s["dr"]
        vals = [
            num(s["t"], 4),
            num(s["north"] + g(npos), 3), num(s["east"] + g(npos), 3),
            num(s["down"] + g(npos), 3),
            num(wrap180(s["phi"] * R2D + g(nang)), 4), num(s["theta"] * R2D + g(nang), 4),
            num(wrap180(s["psi"] * R2D + g(nang)), 4),
            num(s["vn"] + g(nvel), 4), num(s["ve"] + g(nvel), 4), num(s["vd"] + g(nvel), 4),
            num(s["p"] * R2D + g(nrate), 4), num(s["q"] * R2D + g(nrate), 4),
            num(s["r"] * R2D + g(nrate), 4),
            num(s["va"] + g(nvel), 4),
            num(s["cmd"][3], 4),
            num(de * R2D, 4), num(da * R2D, 4), num(dr * R2D, 4),
        ]
        if turb:
            vals += [num(x, 4) for x in s["turb"]]
        lines.append(",".join(vals))
    return "\n".join(lines) + "\n"


def write_atomic(path: str, text: str) -> None:
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".csv", dir=d)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file normal permissions
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def triple(text: str):
    parts = [float(x) for x in text.split(",")]
    if len(parts) != 3:
        raise argparse.ArgumentTypeError("expected three numbers N,E,D")
    return tuple(parts)


def aircraft_meta(args):
    """The `# aircraft:` value: as given, or the repository's c172p.toml relative to the
    folder of the output file (wireflight resolves metadata paths from the data file's
    folder)."""
    if args.aircraft:
        return args.aircraft
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    toml = os.path.join(repo, "assets", "aircraft", "c172p.toml")
    out_dir = os.path.dirname(os.path.abspath(args.out or "."))
    return os.path.relpath(toml, out_dir)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("manoeuvre", choices=sorted(MANOEUVRES))
    ap.add_argument("--out", help="CSV to write (default jsbsim-c172p-<manoeuvre>.csv here)")
    ap.add_argument("--duration", type=float, default=50.0, help="seconds (default 50)")
    ap.add_argument("--rate", type=float, default=50.0,
                    help="output rate, Hz; must divide 400 (default 50)")
    ap.add_argument("--airspeed", type=float, default=50.0, help="trim true airspeed, m/s")
    ap.add_argument("--altitude", type=float, default=1000.0, help="start altitude, m")
    ap.add_argument("--latitude", type=float, default=47.4, help="start latitude, deg")
    ap.add_argument("--longitude", type=float, default=8.5, help="start longitude, deg")
    ap.add_argument("--heading", type=float, default=0.0, help="start heading, deg")
    ap.add_argument("--wind", type=triple, default=(0.0, 0.0, 0.0),
                    help="steady wind N,E,D in m/s (the air moves that way), default 0,0,0; "
                         "write --wind=-5,3,0 when it starts with a minus")
    ap.add_argument("--seed", type=int, default=1, help="noise seed (default 1)")
    ap.add_argument("--noise", action="store_true",
                    help="add noise: 0.05 m, 0.05 deg, 0.05 m/s, 0.2 deg/s (1 sigma)")
    ap.add_argument("--noise-pos", type=float, help="position noise, m (overrides --noise)")
    ap.add_argument("--noise-angle", type=float, help="attitude noise, deg")
    ap.add_argument("--noise-vel", type=float, help="velocity and airspeed noise, m/s")
    ap.add_argument("--noise-rate", type=float, help="body-rate noise, deg/s")
    ap.add_argument("--aircraft", default=None,
                    help="value of the `# aircraft:` metadata (default: the path of "
                         "assets/aircraft/c172p.toml relative to the output file's folder, "
                         "which is where wireflight resolves it from)")
    ap.add_argument("--inputs-seed", type=int, default=1,
                    help="seed of the `sequence` manoeuvre's inputs (default 1)")
    ap.add_argument("--scale", action="append", default=[], metavar="NAME=F",
                    help="fly a changed c172p: aero/coefficient/NAME times F (repeatable; "
                         "NAME as in c172p.xml, any case: Clda, Cnr, Cmalpha, ...)")
    ap.add_argument("--payload-kg", type=float, default=0.0,
                    help="fly a changed c172p: this payload at the CG, kg")
    ap.add_argument("--turbulence", choices=sorted(TURBULENCE),
                    help="JSBSim's Dryden (milspec) turbulence from the start; the gusts are "
                         "written as extra turb_* columns")
    ap.add_argument("--turbulence-seed", type=int, default=1,
                    help="JSBSim's simulation/randomseed for the turbulence (default 1)")
    args = ap.parse_args(argv)
    try:
        scales = dict(parse_scale(x) for x in args.scale)
    except ValueError as e:
        ap.error(str(e))
    variant = Variant(scales, args.payload_kg) if scales or args.payload_kg else None

    base = (0.05, 0.05, 0.05, 0.2) if args.noise else (0.0, 0.0, 0.0, 0.0)
    noise = tuple(v if v is not None else b for v, b in zip(
        (args.noise_pos, args.noise_angle, args.noise_vel, args.noise_rate), base))
    out = args.out or f"jsbsim-c172p-{args.manoeuvre}.csv"
    rows, info = fly(args.manoeuvre, args.duration, args.rate, args.airspeed, args.altitude,
                     args.latitude, args.longitude, args.heading, args.wind, variant,
                     args.turbulence, args.turbulence_seed, args.inputs_seed)
    text = csv_text(rows, info, args, noise)
    write_atomic(out, text)
    last = rows[-1]
    print(f"wrote {out}: {len(rows)} rows, {len(text.encode())} bytes; end: "
          f"N {last['north']:.1f} E {last['east']:.1f} D {last['down']:.1f} m, "
          f"Va {last['va']:.2f} m/s, roll {last['phi'] * R2D:.1f} pitch {last['theta'] * R2D:.1f} "
          f"yaw {last['psi'] * R2D:.1f} deg; fuel left {info['fuel_end']:.2f} lb")
    if variant is not None:
        print(f"changed c172p: {variant.describe()} (checked in JSBSim); the true change of the "
              f"parameter set: python3 tools/jsbsim/c172p_params.py --compare "
              + " ".join([f"--scale {n}={f:g}" for n, f in variant.scales.items()]
                         + ([f"--payload-kg {variant.payload_kg:g}"] if variant.payload_kg
                            else [])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
