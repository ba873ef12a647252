#!/usr/bin/env python3
"""What the c172p parameter set lacks in turbulence: JSBSim's own force and moment against the
set's, at JSBSim's own air-relative state.

    python3 tools/jsbsim/model_error.py                  # calm and light turbulence, ~4 s

The analysis's flight model is never JSBSim's aircraft; reference flights measure how far it is
off in calm air. In turbulence the aircraft meets states calm flights do not (sideslips and
angles of attack from the gusts, rotation of the air), and the part of the model's error that
grows there is what a filter-error fit against calm references takes for a changed number.
This script measures that part directly. It flies the `sequence` manoeuvre (`fly.py`), calm
and in JSBSim's light milspec turbulence, and at every 25 Hz sample compares the aerodynamic
plus propulsive force and moment JSBSim computed (body axes, about the CG) with those of
`assets/aircraft/c172p.toml` (Beard & McLain's equations, `check.py`'s `BM`) evaluated at the
same air-relative velocity, controls and rates. It prints the difference's mean and standard
deviation per axis four ways, each adding one thing JSBSim's c172p has and the set does not:

1. the set as the analysis flies it: the body rates in its damping terms;
2. with JSBSim's aerodynamic rates instead (the rotary gusts p_g, q_g, r_g enter every damping
   and rate term: `velocities/{p,q,r}-aero-rad_sec`);
3. with JSBSim's alpha-dot terms (CLadot, Cmadot) taken out of its side, as the set has none;
4. with JSBSim's drag from sideslip (CDbeta, 0.17 |β|) added to the set's side.

What a step removes in turbulence and not in calm air is an effect turbulence exposes.
"""

from __future__ import annotations

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fly  # noqa: E402
from c172p_sim import C172P, FT, SLUG_FT3  # noqa: E402
from check import BM, G0, load_params  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SET = os.path.join(HERE, "..", "..", "assets", "aircraft", "c172p.toml")
# JSBSim's c172p: aero/coefficient/CDbeta = 0.17·|β| (c172p.xml).
CD_BETA = 0.17
AXES = ["X N", "Y N", "Z N", "L N·m", "M N·m", "N N·m"]


def fly_recording(inputs_seed: int, turbulence: str | None, turbulence_seed: int,
                  duration: float, rate: float) -> list[dict]:
    """Fly the sequence manoeuvre (`fly.fly`) and keep, per sample, JSBSim's force and moment
    and the air-relative state (SI, radians)."""

    def record(sim: C172P) -> dict:
        f = sim.fdm
        aero_f, aero_m = sim.aero_fm(remove_alphadot=False)
        no_ad_f, no_ad_m = sim.aero_fm(remove_alphadot=True)
        prop_f, prop_m = sim.prop_fm()
        return dict(
            total=[a + p for a, p in zip(aero_f + aero_m, prop_f + prop_m)],
            without_alphadot=[a + p for a, p in zip(no_ad_f + no_ad_m, prop_f + prop_m)],
            uvw_air=[f[f"velocities/{c}-aero-fps"] * FT for c in "uvw"],
            rates_air=[f[f"velocities/{c}-aero-rad_sec"] for c in "pqr"],
            rho=f["atmosphere/rho-slugs_ft3"] * SLUG_FT3)

    rows, _ = fly.fly("sequence", duration, rate, 50.0, 1000.0, 47.4, 8.5, 0.0,
                      turbulence=turbulence, turbulence_seed=turbulence_seed,
                      inputs_seed=inputs_seed, record=record)
    return [dict(row["record"], rates=[row["p"], row["q"], row["r"]], alpha=row["alpha"],
                 beta=row["beta"], va=row["va"],
                 controls=(row["cmd"][3], row["de"], row["da"], row["dr"]))
            for row in rows]


def differences(rows: list[dict], bm: BM, s_wing: float, air_rates: bool, alphadot: bool,
                cd_beta: bool) -> list[list[float]]:
    """JSBSim minus the set, per sample: X, Y, Z (N), L, M, N (N·m)."""
    out = []
    for r in rows:
        rates = r["rates_air"] if air_rates else r["rates"]
        x = [0.0, 0.0, 0.0, *r["uvw_air"], 0.0, 0.0, 0.0, *rates]
        (fx, fy, fz), (l_, m_, n_) = bm.forces_moments(x, r["controls"])
        fz -= bm.mass * G0  # the set's gravity at zero attitude
        if cd_beta:
            drag = CD_BETA * abs(r["beta"]) * 0.5 * r["rho"] * r["va"] ** 2 * s_wing
            fx -= drag * math.cos(r["alpha"])
            fz -= drag * math.sin(r["alpha"])
        jsb = r["total"] if alphadot else r["without_alphadot"]
        out.append([j - m for j, m in zip(jsb, (fx, fy, fz, l_, m_, n_))])
    return out


def mean_sd(column: list[float]) -> tuple[float, float]:
    m = sum(column) / len(column)
    return m, math.sqrt(sum((v - m) ** 2 for v in column) / len(column))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--calm-seeds", default="1,13",
                    help="inputs seeds of the calm flights (default 1,13)")
    ap.add_argument("--turbulent-seeds", default="13,5",
                    help="seeds of the turbulent flights, inputs and gusts (default 13,5)")
    ap.add_argument("--duration", type=float, default=50.0, help="seconds per flight (50)")
    args = ap.parse_args(argv)
    params = load_params(SET)
    bm = BM(params)
    s_wing = params["geometry"]["s_wing"]
    flights = []
    for seed in (int(s) for s in args.calm_seeds.split(",") if s):
        flights.append((f"calm, seed {seed}", fly_recording(seed, None, 0, args.duration, 25.0)))
    for seed in (int(s) for s in args.turbulent_seeds.split(",") if s):
        flights.append((f"light, seed {seed}",
                        fly_recording(seed, "light", seed, args.duration, 25.0)))
    steps = [("the set (body rates)", False, True, False),
             ("+ rotary gusts in the rates", True, True, False),
             ("+ alpha-dot terms", True, False, False),
             ("+ drag from sideslip", True, False, True)]
    print("JSBSim minus the set: mean / standard deviation per axis")
    print(f"{'':30s}{'flight':17s}" + "".join(f"{a:>14s}" for a in AXES))
    for label, air_rates, alphadot, cd_beta in steps:
        for i, (name, rows) in enumerate(flights):
            d = differences(rows, bm, s_wing, air_rates, alphadot, cd_beta)
            cells = [mean_sd([row[k] for row in d]) for k in range(6)]
            print(f"{label if i == 0 else '':30s}{name:17s}"
                  + "".join(f"{m:>7.0f} /{s:>5.0f}" for m, s in cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
