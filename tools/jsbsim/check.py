#!/usr/bin/env python3
"""Sanity checks of the c172p parameter set and the JSBSim flight-data files.

    python3 tools/jsbsim/check.py                       # everything, default files
    python3 tools/jsbsim/check.py --csv a.csv b.csv     # data checks of other files
    python3 tools/jsbsim/check.py --skip-jsbsim         # only what needs no JSBSim run

1. Trim: a small independent implementation of the Beard & McLain equations of
   flight-model.md, trimmed with the TOML for straight and level flight at JSBSim's trim
   airspeed, compared with JSBSim's trim (alpha, de, throttle; da, dr, phi for information).
2. Command timing (JSBSim at 400 Hz): a command set one step before t acts from t.
3. Per CSV: the control-step sign checks of jsbsim-notes.md (de step -> qdot < 0, da -> pdot > 0,
   dr -> rdot < 0), read from the jump in the rate's difference quotient at the step's row;
   kinematic consistency (Euler angles differenced between rows vs the Euler kinematics of the
   recorded p, q, r averaged over the interval, and vs central differences); position
   differences vs the recorded NED velocity; airspeed vs |v| (still air).
4. Replay: the Beard & McLain model (RK4) driven by each file's controls from the file's
   states, over windows after each input, against JSBSim (RMS differences), with and without
   the catalogue effect prop_torque.
5. Wind: the doublets flown again with a steady wind; air-relative quantities must match the
   still-air flight.
"""

from __future__ import annotations

import argparse
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

G0 = 9.80665
D2R = math.pi / 180.0
R2D = 180.0 / math.pi


# ------------------------------------------------------------------------------ TOML
def load_params(path: str) -> dict:
    if tomllib is not None:
        with open(path, "rb") as f:
            return tomllib.load(f)
    # Minimal reader for the flat layout we write (tables of `key = number`).
    out, cur = {}, None
    for line in open(path):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if line.startswith("["):
            cur = out.setdefault(line.strip("[]"), {})
        else:
            k, v = [x.strip() for x in line.split("=", 1)]
            (cur if cur is not None else out)[k] = v.strip('"') if v.startswith('"') else float(v)
    return out


# ------------------------------------------------------------------------------ B&M model
class BM:
    """Beard & McLain fixed-wing forces, moments and state derivative (flight-model.md)."""

    def __init__(self, P: dict, k_torque: float = 0.0):
        self.P = P
        m = P["mass"]
        self.mass = m["mass_kg"]
        jx, jy, jz, jxz = m["jx"], m["jy"], m["jz"], m["jxz"]
        gam = jx * jz - jxz * jxz
        self.G = [None,
                  jxz * (jx - jy + jz) / gam, (jz * (jz - jy) + jxz * jxz) / gam, jz / gam,
                  jxz / gam, (jz - jx) / jy, jxz / jy, ((jx - jy) * jx + jxz * jxz) / gam,
                  jx / gam]
        self.jy = jy
        self.k_torque = k_torque

    def forces_moments(self, x, ctrl):
        """x = [pn, pe, pd, u, v, w, phi, theta, psi, p, q, r]; ctrl = (dt, de, da, dr) rad.
        Returns body force (N) and moment (N m), gravity and thrust included."""
        P = self.P
        g, lo, la, pr = P["geometry"], P["longitudinal"], P["lateral"], P["propulsion"]
        _, _, _, u, v, w, phi, theta, _psi, p, q, r = x
        dt, de, da, dr = ctrl
        va = math.sqrt(u * u + v * v + w * w)
        alpha = math.atan2(w, u)
        beta = math.asin(v / va)
        rho = g["rho"]
        qbar = 0.5 * rho * va * va
        S, b, c = g["s_wing"], g["b"], g["c"]
        M, a0 = lo["m_blend"], lo["alpha0"]
        e1, e2 = math.exp(-M * (alpha - a0)), math.exp(M * (alpha + a0))
        sig = (1 + e1 + e2) / ((1 + e1) * (1 + e2))
        cl_lin = lo["c_l_0"] + lo["c_l_alpha"] * alpha
        sgn = 1.0 if alpha >= 0 else -1.0
        CL = (1 - sig) * cl_lin + sig * 2 * sgn * math.sin(alpha) ** 2 * math.cos(alpha)
        AR = b * b / S
        CD = lo["c_d_p"] + cl_lin ** 2 / (math.pi * g["e"] * AR)
        cq, bp = c / (2 * va), b / (2 * va)
        lift = qbar * S * (CL + lo["c_l_q"] * cq * q + lo["c_l_delta_e"] * de)
        drag = qbar * S * (CD + lo["c_d_q"] * cq * q + lo["c_d_delta_e"] * de)
        ca, sa = math.cos(alpha), math.sin(alpha)
        fx = -drag * ca + lift * sa
        fz = -drag * sa - lift * ca
        fy = qbar * S * (la["c_y_0"] + la["c_y_beta"] * beta + la["c_y_p"] * bp * p
                         + la["c_y_r"] * bp * r + la["c_y_delta_a"] * da
                         + la["c_y_delta_r"] * dr)
        l_ = qbar * S * b * (la["c_ell_0"] + la["c_ell_beta"] * beta + la["c_ell_p"] * bp * p
                             + la["c_ell_r"] * bp * r + la["c_ell_delta_a"] * da
                             + la["c_ell_delta_r"] * dr)
        m_ = qbar * S * c * (lo["c_m_0"] + lo["c_m_alpha"] * alpha + lo["c_m_q"] * cq * q
                             + lo["c_m_delta_e"] * de)
        n_ = qbar * S * b * (la["c_n_0"] + la["c_n_beta"] * beta + la["c_n_p"] * bp * p
                             + la["c_n_r"] * bp * r + la["c_n_delta_a"] * da
                             + la["c_n_delta_r"] * dr)
        fx += 0.5 * rho * pr["s_prop"] * pr["c_prop"] * ((pr["k_motor"] * dt) ** 2 - va * va)
        l_ += -self.k_torque * dt * dt  # catalogue effect prop_torque (0 = baseline)
        mg = self.mass * G0
        fx += -mg * math.sin(theta)
        fy += mg * math.cos(theta) * math.sin(phi)
        fz += mg * math.cos(theta) * math.cos(phi)
        return (fx, fy, fz), (l_, m_, n_)

    def deriv(self, x, ctrl):
        (fx, fy, fz), (l_, m_, n_) = self.forces_moments(x, ctrl)
        _, _, _, u, v, w, phi, theta, psi, p, q, r = x
        G = self.G
        cf, sf, ct, st, cp, sp = (math.cos(phi), math.sin(phi), math.cos(theta),
                                  math.sin(theta), math.cos(psi), math.sin(psi))
        R = [[ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp],
             [ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp],
             [-st, sf * ct, cf * ct]]
        pos = [R[i][0] * u + R[i][1] * v + R[i][2] * w for i in range(3)]
        m = self.mass
        return [
            pos[0], pos[1], pos[2],
            r * v - q * w + fx / m, p * w - r * u + fy / m, q * u - p * v + fz / m,
            p + (q * sf + r * cf) * st / ct, q * cf - r * sf, (q * sf + r * cf) / ct,
            G[1] * p * q - G[2] * q * r + G[3] * l_ + G[4] * n_,
            G[5] * p * r - G[6] * (p * p - r * r) + m_ / self.jy,
            G[7] * p * q - G[1] * q * r + G[4] * l_ + G[8] * n_,
        ]

    def rk4(self, x, ctrl, h):
        k1 = self.deriv(x, ctrl)
        k2 = self.deriv([a + 0.5 * h * b for a, b in zip(x, k1)], ctrl)
        k3 = self.deriv([a + 0.5 * h * b for a, b in zip(x, k2)], ctrl)
        k4 = self.deriv([a + h * b for a, b in zip(x, k3)], ctrl)
        return [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(x, k1, k2, k3, k4)]


def solve(f, x0, tol=1e-12, it=50):
    """Newton with a finite-difference Jacobian (small systems)."""
    x = list(x0)
    n = len(x)
    for _ in range(it):
        r = f(x)
        if max(abs(v) for v in r) < tol:
            break
        J = [[0.0] * n for _ in range(n)]
        for j in range(n):
            h = 1e-7 * max(1.0, abs(x[j]))
            xp = list(x)
            xp[j] += h
            rp = f(xp)
            for i in range(n):
                J[i][j] = (rp[i] - r[i]) / h
        # Gaussian elimination.
        A = [J[i][:] + [-r[i]] for i in range(n)]
        for col in range(n):
            piv = max(range(col, n), key=lambda i: abs(A[i][col]))
            A[col], A[piv] = A[piv], A[col]
            for i in range(col + 1, n):
                fct = A[i][col] / A[col][col]
                for j in range(col, n + 1):
                    A[i][j] -= fct * A[col][j]
        dx = [0.0] * n
        for i in reversed(range(n)):
            dx[i] = (A[i][n] - sum(A[i][j] * dx[j] for j in range(i + 1, n))) / A[i][i]
        x = [a + b for a, b in zip(x, dx)]
    return x, max(abs(v) for v in f(x))


def bm_trim(bm: BM, va: float):
    """Straight and level trim: (alpha, de, dt) from udot = wdot = qdot = 0 (wings level,
    beta = 0), then (phi, da, dr) from vdot = pdot = rdot = 0 with that longitudinal trim."""
    def state(alpha, phi=0.0):
        return [0, 0, 0, va * math.cos(alpha), 0.0, va * math.sin(alpha), phi, alpha, 0.0,
                0.0, 0.0, 0.0]

    def lon(z):
        a, de, dt = z
        d = bm.deriv(state(a), (dt, de, 0.0, 0.0))
        return [d[3], d[5], d[10]]

    (a, de, dt), res1 = solve(lon, [0.02, 0.05, 0.6])

    def lat(z):
        phi, da, dr = z
        d = bm.deriv(state(a, phi), (dt, de, da, dr))
        return [d[4], d[9], d[11]]

    (phi, da, dr), res2 = solve(lat, [0.0, 0.0, 0.0])
    return dict(alpha=a, de=de, throttle=dt, phi=phi, da=da, dr=dr, residual=max(res1, res2))


# ------------------------------------------------------------------------------ CSV
def read_csv(path: str):
    meta, header, rows = {}, None, []
    for line in open(path):
        line = line.strip()
        if not line:
            continue
        if line.startswith("#"):
            if ":" in line:
                k, v = line[1:].split(":", 1)
                meta[k.strip()] = v.strip()
            continue
        if header is None:
            header = line.split(",")
            continue
        rows.append([float(x) for x in line.split(",")])
    cols = {h: [r[i] for r in rows] for i, h in enumerate(header)}
    return meta, cols


def unwrap(deg):
    out = [deg[0]]
    for a in deg[1:]:
        d = a - out[-1]
        d -= 360.0 * round(d / 360.0)
        out.append(out[-1] + d)
    return out


def euler_rates(phi, th, p, q, r):
    """Euler-angle rates (rad/s) from body rates."""
    return (p + (q * math.sin(phi) + r * math.cos(phi)) * math.tan(th),
            q * math.cos(phi) - r * math.sin(phi),
            (q * math.sin(phi) + r * math.cos(phi)) / math.cos(th))


def rms(xs):
    return math.sqrt(sum(x * x for x in xs) / len(xs)) if xs else float("nan")


def data_checks(path: str) -> dict:
    meta, c = read_csv(path)
    t = c["time_s"]
    n = len(t)
    phi = [x * D2R for x in c["roll_deg"]]
    th = [x * D2R for x in c["pitch_deg"]]
    psi = [x * D2R for x in unwrap(c["yaw_deg"])]
    p = [x * D2R for x in c["p_dps"]]
    q = [x * D2R for x in c["q_dps"]]
    r = [x * D2R for x in c["r_dps"]]
    out = {"file": os.path.relpath(path, REPO), "rows": n, "bytes": os.path.getsize(path),
           "meta": meta}

    # Kinematics, interval form: (angle[k+1]-angle[k])/dt vs the mean of the Euler rates at
    # both ends (exact for rates that are linear over the interval; controls change at rows).
    mis = [[], [], []]
    for k in range(n - 1):
        h = t[k + 1] - t[k]
        e0 = euler_rates(phi[k], th[k], p[k], q[k], r[k])
        e1 = euler_rates(phi[k + 1], th[k + 1], p[k + 1], q[k + 1], r[k + 1])
        num = ((phi[k + 1] - phi[k]) / h, (th[k + 1] - th[k]) / h, (psi[k + 1] - psi[k]) / h)
        for i in range(3):
            mis[i].append((num[i] - 0.5 * (e0[i] + e1[i])) * R2D)
    out["kin_interval_rms_dps"] = [rms(m) for m in mis]
    out["kin_interval_max_dps"] = [max(abs(x) for x in m) for m in mis]
    # The same away from control changes (> 0.5 s after any surface or throttle change):
    # right after a step the rates curve sharply and the trapezoid's O(h^2) error shows.
    steps = [t[k] for k in range(1, n) if any(
        abs(c[col][k] - c[col][k - 1]) > 1e-3
        for col in ("elevator_deg", "aileron_deg", "rudder_deg", "throttle"))]
    calm = [k for k in range(n - 1)
            if not any(0.0 <= t[k] - ts < 0.5 for ts in steps)]
    out["kin_calm_rms_dps"] = [rms([m[k] for k in calm]) for m in mis]
    out["calm_fraction"] = len(calm) / (n - 1)
    # Central differences -> body rates (p, q, r) vs recorded.
    mis2 = [[], [], []]
    for k in range(1, n - 1):
        h = t[k + 1] - t[k - 1]
        dphi, dth, dpsi = ((phi[k + 1] - phi[k - 1]) / h, (th[k + 1] - th[k - 1]) / h,
                           (psi[k + 1] - psi[k - 1]) / h)
        pb = dphi - dpsi * math.sin(th[k])
        qb = dth * math.cos(phi[k]) + dpsi * math.sin(phi[k]) * math.cos(th[k])
        rb = -dth * math.sin(phi[k]) + dpsi * math.cos(phi[k]) * math.cos(th[k])
        for i, (a, b) in enumerate(((pb, p[k]), (qb, q[k]), (rb, r[k]))):
            mis2[i].append((a - b) * R2D)
    out["kin_central_rms_dps"] = [rms(m) for m in mis2]
    out["kin_central_max_dps"] = [max(abs(x) for x in m) for m in mis2]

    # Position differences vs NED velocity (interval mean).
    pm = [[], [], []]
    for k in range(n - 1):
        h = t[k + 1] - t[k]
        for i, (pc, vc) in enumerate((("north_m", "vn_mps"), ("east_m", "ve_mps"),
                                      ("down_m", "vd_mps"))):
            pm[i].append((c[pc][k + 1] - c[pc][k]) / h - 0.5 * (c[vc][k] + c[vc][k + 1]))
    out["pos_rms_mps"] = [rms(m) for m in pm]
    out["pos_max_mps"] = [max(abs(x) for x in m) for m in pm]
    speed = [math.sqrt(c["vn_mps"][k] ** 2 + c["ve_mps"][k] ** 2 + c["vd_mps"][k] ** 2)
             for k in range(n)]
    out["airspeed_minus_speed_max"] = max(abs(a - b) for a, b in zip(c["airspeed_mps"], speed))

    # Sign checks at control steps: jump of the rate's difference quotient at the step row.
    signs = []
    for col, rate, expect in (("elevator_deg", q, -1), ("aileron_deg", p, +1),
                              ("rudder_deg", r, -1)):
        u = c[col]
        for k in range(2, n - 1):
            du = u[k] - u[k - 1]
            if abs(du) < 0.5:
                continue
            h = t[k + 1] - t[k]
            after = (rate[k + 1] - rate[k]) / h
            before = (rate[k] - rate[k - 1]) / h
            earlier = (rate[k - 1] - rate[k - 2]) / h
            jump = (after - before) * R2D
            pre = (before - earlier) * R2D
            signs.append(dict(t=t[k], col=col, du=du, jump=jump, pre=pre,
                              ok=(jump * du * expect > 0)))
    out["signs"] = signs
    return out


# ------------------------------------------------------------------------------ replay
def replay(path: str, P: dict, windows, k_torque=0.0, sub=4):
    """B&M replay (RK4, sub steps per row) from the file's state at each window start, the
    file's controls held per row; RMS differences over each window."""
    _, c = read_csv(path)
    t = c["time_s"]
    bm = BM(P, k_torque)
    out = []
    for (t0, t1) in windows:
        k0 = min(range(len(t)), key=lambda k: abs(t[k] - t0))
        k1 = min(range(len(t)), key=lambda k: abs(t[k] - t1))
        phi, th, psi = (c["roll_deg"][k0] * D2R, c["pitch_deg"][k0] * D2R,
                        c["yaw_deg"][k0] * D2R)
        from c172p_sim import euler_to_dcm, mat_vec, transpose
        R = euler_to_dcm(phi, th, psi)
        uvw = mat_vec(transpose(R), [c["vn_mps"][k0], c["ve_mps"][k0], c["vd_mps"][k0]])
        x = [c["north_m"][k0], c["east_m"][k0], c["down_m"][k0], *uvw, phi, th, psi,
             c["p_dps"][k0] * D2R, c["q_dps"][k0] * D2R, c["r_dps"][k0] * D2R]
        err = {k: [] for k in ("roll", "pitch", "yaw", "va", "p", "q", "r", "alt")}
        for k in range(k0, k1):
            ctrl = (c["throttle"][k], c["elevator_deg"][k] * D2R, c["aileron_deg"][k] * D2R,
                    c["rudder_deg"][k] * D2R)
            h = (t[k + 1] - t[k]) / sub
            for _ in range(sub):
                x = bm.rk4(x, ctrl, h)
            j = k + 1
            dy = x[8] * R2D - c["yaw_deg"][j]
            dy -= 360.0 * round(dy / 360.0)
            err["roll"].append(x[6] * R2D - c["roll_deg"][j])
            err["pitch"].append(x[7] * R2D - c["pitch_deg"][j])
            err["yaw"].append(dy)
            err["va"].append(math.sqrt(x[3] ** 2 + x[4] ** 2 + x[5] ** 2) - c["airspeed_mps"][j])
            err["p"].append(x[9] * R2D - c["p_dps"][j])
            err["q"].append(x[10] * R2D - c["q_dps"][j])
            err["r"].append(x[11] * R2D - c["r_dps"][j])
            err["alt"].append(-(x[2] - c["down_m"][j]))
        out.append(((t0, t1), {k: rms(v) for k, v in err.items()}))
    return out


REPLAY_WINDOWS = {
    "doublets": [(2.0, 10.0), (12.0, 20.0), (22.0, 30.0), (32.0, 45.0), (0.0, 50.0)],
    "steps": [(3.0, 13.0), (19.0, 29.0), (31.0, 44.0), (0.0, 50.0)],
    "validation": [(2.0, 12.0), (15.0, 25.0), (27.0, 35.0), (37.0, 50.0), (0.0, 50.0)],
}


# ------------------------------------------------------------------------------ JSBSim checks
def timing_check():
    """Set an elevator step one integration step before t = 1 s: q(t) must be untouched and
    q(t + dt) changed; set it just before t's step instead (the naive way) and the change
    appears one step later."""
    from c172p_sim import C172P
    res = {}
    for mode in ("none", "early", "naive"):
        s = C172P()
        tr = s.trim(50.0, 1000.0, 47.4, 8.5)
        s.restart(tr)
        qs = {}
        n_t = 400  # t = 1 s
        for i in range(1, n_t + 4):
            if (mode == "early" and i == n_t) or (mode == "naive" and i == n_t + 1):
                s.command(tr["de"] + 2 * D2R, tr["da"], tr["dr"], tr["throttle"])
            s.fdm.run()
            qs[i] = s["velocities/q-rad_sec"]
        res[mode] = qs
    n_t = 400
    out = {}
    for mode in ("early", "naive"):
        out[mode] = [(res[mode][i] - res["none"][i]) * R2D for i in (n_t, n_t + 1, n_t + 2)]
    return out


def kinematics_400hz(duration=30.0):
    """Doublets flown at 400 Hz output, unrounded: interval-form Euler kinematics mismatch
    and position differences vs velocity (RMS, max) without the CSV's rounding."""
    import fly
    rows, _ = fly.fly("doublets", duration, 400.0, 50.0, 1000.0, 47.4, 8.5, 0.0)
    mis = [[], [], []]
    pos = [[], [], []]
    psi_prev = rows[0]["psi"]
    for a, b in zip(rows, rows[1:]):
        h = b["t"] - a["t"]
        e0 = euler_rates(a["phi"], a["theta"], a["p"], a["q"], a["r"])
        e1 = euler_rates(b["phi"], b["theta"], b["p"], b["q"], b["r"])
        dpsi = b["psi"] - psi_prev
        dpsi -= 2 * math.pi * round(dpsi / (2 * math.pi))
        psi_prev = b["psi"]
        num = ((b["phi"] - a["phi"]) / h, (b["theta"] - a["theta"]) / h, dpsi / h)
        for i in range(3):
            mis[i].append((num[i] - 0.5 * (e0[i] + e1[i])) * R2D)
        for i, (pk, vk) in enumerate((("north", "vn"), ("east", "ve"), ("down", "vd"))):
            pos[i].append((b[pk] - a[pk]) / h - 0.5 * (a[vk] + b[vk]))
    return ([rms(m) for m in mis], [max(abs(x) for x in m) for m in mis],
            [rms(m) for m in pos], [max(abs(x) for x in m) for m in pos])


def wind_check(wind=(5.0, -3.0, 0.0), duration=30.0):
    import fly
    a, _ = fly.fly("doublets", duration, 25.0, 50.0, 1000.0, 47.4, 8.5, 0.0)
    b, _ = fly.fly("doublets", duration, 25.0, 50.0, 1000.0, 47.4, 8.5, 0.0, wind)
    keys = ("va", "alpha", "beta", "phi", "theta", "p", "q", "r")
    d = {k: max(abs(x[k] - y[k]) for x, y in zip(a, b)) for k in keys}
    gs = max(abs((y["north"] - x["north"]) - wind[0] * x["t"]) for x, y in zip(a, b))
    return d, gs


# ------------------------------------------------------------------------------ main
def variant_checks():
    """Changed aircraft (c172p_variant.py) and turbulence: the coefficient checks, the
    aileron's roll acceleration per degree with ClDa x 0.75 vs unchanged (doublets at 400 Hz,
    the aileron step at 13 s), the payload's mass, and that a turbulence seed reproduces."""
    import fly
    from c172p_variant import Variant, check_scales
    out = {}
    for name, f in (("Clda", 0.75), ("Cnr", 1.4), ("Cmalpha", 0.85)):
        v = Variant({name: f})
        root = v.build()
        (n, (o, c)), = check_scales(root, v.scales).items()
        out[n] = (f, o, c)

    def pdot_jump(variant):
        rows, _ = fly.fly("doublets", 13.5, 400.0, 50.0, 1000.0, 47.4, 8.5, 0.0,
                          variant=variant)
        k = 13 * 400
        pd = lambda i: (rows[i + 1]["p"] - rows[i]["p"]) * 400.0  # noqa: E731
        return (pd(k) - pd(k - 1)) / (rows[k]["da"] - rows[k - 1]["da"])
    j0, j1 = pdot_jump(None), pdot_jump(Variant({"Clda": 0.75}))
    rows, info = fly.fly("doublets", 1.0, 25.0, 50.0, 1000.0, 47.4, 8.5, 0.0,
                         variant=Variant(payload_kg=80.0))
    rows0, _ = fly.fly("doublets", 1.0, 25.0, 50.0, 1000.0, 47.4, 8.5, 0.0)
    mass = (rows0[0]["mass_kg"], rows[0]["mass_kg"])
    turb = [fly.fly("sequence", 5.0, 25.0, 50.0, 1000.0, 47.4, 8.5, 0.0, turbulence="light",
                    turbulence_seed=sd, inputs_seed=8)[0] for sd in (8, 8, 9)]
    same = all(a["turb"] == b["turb"] and a["phi"] == b["phi"] for a, b in zip(turb[0], turb[1]))
    differ = any(a["turb"] != b["turb"] for a, b in zip(turb[0], turb[2]))
    gmax = max(abs(x) for r in turb[0] for x in r["turb"][:3])
    return out, (j0, j1), mass, (same, differ, gmax)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--toml", default=os.path.join(REPO, "assets", "aircraft", "c172p.toml"))
    ap.add_argument("--csv", nargs="*", default=[
        os.path.join(REPO, "tests", "data", f"jsbsim-c172p-{m}.csv")
        for m in ("doublets", "steps", "validation")])
    ap.add_argument("--skip-jsbsim", action="store_true",
                    help="skip the checks that run JSBSim (trim reference, timing, wind)")
    ap.add_argument("--k-torque", type=float, default=None,
                    help="k_torque for the prop_torque replay variant (default: fitted)")
    args = ap.parse_args(argv)
    P = load_params(args.toml)

    print("== 1. Trim: Beard & McLain with", os.path.relpath(args.toml, REPO))
    k_torque = args.k_torque
    if not args.skip_jsbsim:
        from c172p_sim import C172P, LBF_FT
        s = C172P()
        tr = s.trim(50.0, 1000.0, 47.4, 8.5)
        if k_torque is None:
            k_torque = -s["moments/l-prop-lbsft"] * LBF_FT / tr["throttle"] ** 2
        ref = dict(alpha=tr["alpha"], de=tr["de"], throttle=tr["throttle"], phi=tr["phi"],
                   da=tr["da"], dr=tr["dr"])
        va = tr["va"]
    else:
        ref, va = None, 50.0
    for label, kt in (("baseline", 0.0), (f"+ prop_torque k={k_torque or 0:.0f} N m",
                                           k_torque or 0.0)):
        bt = bm_trim(BM(P, kt), va)
        print(f"  {label}: residual {bt['residual']:.1e}")
        for k, unit in (("alpha", "deg"), ("de", "deg"), ("throttle", ""), ("phi", "deg"),
                        ("da", "deg"), ("dr", "deg")):
            f = R2D if unit else 1.0
            line = f"    {k:<9}{bt[k] * f:10.4f} {unit:<4}"
            if ref:
                diff = bt[k] - ref[k]
                pct = f" ({100 * diff / ref[k]:+.2f}%)" if abs(ref[k]) > 1e-3 else ""
                line += f"  JSBSim {ref[k] * f:10.4f}  diff {diff * f:+.4f}{pct}"
            print(line)

    if not args.skip_jsbsim:
        print("\n== 2. Command timing (q change from a +2 deg elevator step, deg/s, at t, t+dt,"
              " t+2dt)")
        tc = timing_check()
        for mode, v in tc.items():
            print(f"  set {'one step early' if mode == 'early' else 'at t (naive)':<15}: "
                  + ", ".join(f"{x:+.6f}" for x in v))

    print("\n== 3. Data checks")
    for path in args.csv:
        r = data_checks(path)
        print(f"  {r['file']}: {r['rows']} rows, {r['bytes']} bytes")
        print("    Euler kinematics, interval form RMS (max) deg/s: "
              + ", ".join(f"{n} {a:.5f} ({b:.4f})" for n, a, b in zip(
                  ("roll", "pitch", "yaw"), r["kin_interval_rms_dps"],
                  r["kin_interval_max_dps"])))
        print("    same, away from control changes ({:.0f}% of intervals), RMS deg/s: ".format(
            100 * r["calm_fraction"]) + ", ".join(f"{n} {a:.5f}" for n, a in zip(
                ("roll", "pitch", "yaw"), r["kin_calm_rms_dps"])))
        print("    body rates from central differences, RMS (max) deg/s: "
              + ", ".join(f"{n} {a:.4f} ({b:.3f})" for n, a, b in zip(
                  ("p", "q", "r"), r["kin_central_rms_dps"], r["kin_central_max_dps"])))
        print("    position differences - NED velocity, RMS (max) m/s: "
              + ", ".join(f"{n} {a:.4f} ({b:.4f})" for n, a, b in zip(
                  ("N", "E", "D"), r["pos_rms_mps"], r["pos_max_mps"])))
        print(f"    max |airspeed - |v|| {r['airspeed_minus_speed_max']:.5f} m/s")
        for sg in r["signs"]:
            rate = {"elevator_deg": "qdot", "aileron_deg": "pdot", "rudder_deg": "rdot"}[sg["col"]]
            print(f"    t {sg['t']:6.2f}: {sg['col'][:-4]:<8} step {sg['du']:+7.3f} deg -> "
                  f"{rate} jump {sg['jump']:+9.3f} deg/s^2 (row before: {sg['pre']:+.4f}) "
                  f"{'OK' if sg['ok'] else 'WRONG SIGN'}")

    print("\n== 4. Replay: B&M from the file's state, file's controls; RMS differences")
    for path in args.csv:
        name = os.path.basename(path).replace("jsbsim-c172p-", "").replace(".csv", "")
        wins = REPLAY_WINDOWS.get(name, [(0.0, 10.0)])
        for label, kt in (("baseline", 0.0), ("+prop_torque", k_torque or 0.0)):
            for (t0, t1), e in replay(path, P, wins, kt):
                print(f"  {name:<10} {label:<13} {t0:4.0f}-{t1:4.0f} s: roll {e['roll']:6.2f} "
                      f"pitch {e['pitch']:5.2f} yaw {e['yaw']:6.2f} deg, Va {e['va']:5.2f} m/s, "
                      f"alt {e['alt']:6.2f} m, p {e['p']:5.2f} q {e['q']:5.2f} r {e['r']:5.2f}"
                      " deg/s")

    if not args.skip_jsbsim:
        print("\n== 5. Wind: doublets 30 s with wind (5, -3, 0) m/s vs still air, max |diff|")
        d, gs = wind_check()
        print("  " + ", ".join(f"{k} {v * (1 if k == 'va' else R2D):.2e}" for k, v in d.items())
              + " (m/s, deg, deg/s)")
        print(f"  north drift minus wind*t: max {gs:.3f} m")
        print("\n== 6. Kinematics at 400 Hz, unrounded (doublets, 30 s)")
        km, kx, pm, px = kinematics_400hz()
        print("  Euler kinematics RMS (max) deg/s: " + ", ".join(
            f"{n} {a:.2e} ({b:.2e})" for n, a, b in zip(("roll", "pitch", "yaw"), km, kx)))
        print("  position differences - velocity RMS (max) m/s: " + ", ".join(
            f"{n} {a:.2e} ({b:.2e})" for n, a, b in zip(("N", "E", "D"), pm, px)))
        print("\n== 7. Changed aircraft and turbulence (c172p_variant.py, fly.py --turbulence)")
        sc, (j0, j1), mass, (same, differ, gmax) = variant_checks()
        for n, (f, o, c) in sc.items():
            print(f"  aero/coefficient/{n} x {f:g} at the probe state: {o:.6g} -> {c:.6g} "
                  f"(ratio {c / o:.12f})")
        print(f"  pdot jump per aileron degree at 13 s: unchanged {j0:+.2f}, ClDa x 0.75 "
              f"{j1:+.2f} deg/s^2 per deg (ratio {j1 / j0:.4f})")
        print(f"  payload 80 kg: mass at the start {mass[0]:.3f} -> {mass[1]:.3f} kg "
              f"(+{mass[1] - mass[0]:.6f})")
        print(f"  light turbulence, 5 s: same seed reproduces: {same}; another seed differs: "
              f"{differ}; max |gust| {gmax:.2f} m/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
