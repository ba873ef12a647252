#!/usr/bin/env python3
"""Measure JSBSim's milspec gust process itself over long records: its intensity and time scales.

    python3 tools/jsbsim/turb_process.py --duration 600 --seeds 5,13,21

A 50 s test flight holds only a few of the gusts' time scales, so the sample σ of its gust
columns scatters by tens of percent around the process's σ. This script flies the trimmed
c172p open loop (controls held at the trim) at 50 m/s and 1000 m in JSBSim's `light`
turbulence (the setting of `fly.py --turbulence light`) for --duration seconds per seed and
prints, for the north, east and down gusts:

* σ: the sample standard deviation over the whole record;
* τ: the time scale of a first-order process with that σ and the record's one-step increments,
  −h / ln(1 − var(Δg) / (2σ²)), h the sampling step;
* the 1/e lag of the sample autocorrelation;

and JSBSim's model values: σ = `jsbsim_intensity_mps(h)` (MIL-F-8785C's table as JSBSim's
FGWinds interpolates it), u first-order with τ_u = L/V, v and w first-order with L/(2V)
(MIL-STD-1797A's form, as FGWinds flies it for `turb-type` 3), L = 1750 ft above 2000 ft.
"""

from __future__ import annotations

import argparse
import math

from c172p_sim import C172P, DT
from fly import TURBULENCE

FT = 0.3048
# MIL-F-8785C, Fig. 7: the gust intensity σ (ft/s) exceeded with probability 10⁻² (JSBSim's
# severity index 3, light) against the altitude (ft); FGWinds interpolates linearly.
SEVERITY3_ALT_FT = [500.0, 1750.0, 3750.0, 7500.0, 15000.0, 25000.0, 35000.0, 45000.0]
SEVERITY3_SIGMA_FPS = [6.6, 6.9, 7.4, 6.7, 4.6, 2.7, 0.4, 0.0]


def jsbsim_intensity_mps(h_m: float) -> float:
    """JSBSim's light (severity 3) gust σ at a height above 2000 ft, m/s (same on every axis)."""
    h = h_m / FT
    if h <= 2000.0 or h >= SEVERITY3_ALT_FT[-1]:
        raise ValueError(f"height {h:.0f} ft: only the table above 2000 ft is written here")
    for (a0, a1), (s0, s1) in zip(zip(SEVERITY3_ALT_FT, SEVERITY3_ALT_FT[1:]),
                                  zip(SEVERITY3_SIGMA_FPS, SEVERITY3_SIGMA_FPS[1:])):
        if a0 <= h <= a1:
            return (s0 + (h - a0) / (a1 - a0) * (s1 - s0)) * FT
    raise AssertionError("unreachable")


def stats(x, h):
    n = len(x)
    m = sum(x) / n
    d = [v - m for v in x]
    var = sum(v * v for v in d) / n
    inc = [b - a for a, b in zip(x, x[1:])]
    var_inc = sum(v * v for v in inc) / len(inc)
    tau = -h / math.log(1.0 - var_inc / (2.0 * var))
    lag = float("nan")
    for k in range(1, n // 2, 4):
        r = sum(d[i] * d[i + k] for i in range(0, n - k, 5)) / len(range(0, n - k, 5)) / var
        if r < math.exp(-1.0):
            lag = k * h
            break
    return math.sqrt(var), tau, lag


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=600.0, help="seconds per seed")
    ap.add_argument("--seeds", default="5,13,21", help="turbulence seeds, comma-separated")
    args = ap.parse_args()
    w20, severity = TURBULENCE["light"]
    every = 10  # samples at 40 Hz
    h = every * DT
    for seed in [int(s) for s in args.seeds.split(",")]:
        sim = C172P()
        trim = sim.trim(50.0, 1000.0, 47.4, 8.5, 0.0)
        sim.restart(trim)
        sim["simulation/randomseed"] = seed
        sim["atmosphere/turb-type"] = 3
        sim["atmosphere/turbulence/milspec/windspeed_at_20ft_AGL-fps"] = w20
        sim["atmosphere/turbulence/milspec/severity"] = severity
        g = ([], [], [])
        heights, speeds = [], []
        for k in range(int(round(args.duration / DT))):
            sim.fdm.run()
            if k % every == 0:
                for axis, name in zip(g, ["north", "east", "down"]):
                    axis.append(sim[f"atmosphere/turb-{name}-fps"] * FT)
                heights.append(sim["position/h-agl-ft"] * FT)
                speeds.append(sim["velocities/vt-fps"] * FT)
        h_mean = sum(heights) / len(heights)
        v_mean = sum(speeds) / len(speeds)
        l_m = 1750.0 * FT
        print(f"seed {seed}: {args.duration:g} s, height {min(heights):.0f}..{max(heights):.0f} m "
              f"(mean {h_mean:.0f}), airspeed {min(speeds):.1f}..{max(speeds):.1f} m/s "
              f"(mean {v_mean:.1f})")
        print(f"  JSBSim's model: sigma {jsbsim_intensity_mps(h_mean):.3f} m/s on every axis; "
              f"tau {l_m / v_mean:.2f} s (north), {l_m / (2 * v_mean):.2f} s (east, down)")
        for name, x in zip(["north", "east", "down"], g):
            s, tau, lag = stats(x, h)
            print(f"  {name:5}: sigma {s:.3f} m/s, tau {tau:.2f} s, 1/e lag {lag:.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
