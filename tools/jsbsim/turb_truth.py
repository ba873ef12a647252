#!/usr/bin/env python3
"""Record the gust truth of a turbulent `fly.py` flight in its header and keep the file small.

    python3 tools/jsbsim/turb_truth.py tests/data/jsbsim-c172p-turb-light-1.csv

Adds `# jsbsim_gust_intensity_mps: north=… east=… down=…` (the σ of JSBSim's gust process
at the flight's mean height, the same on every axis: `turb_process.jsbsim_intensity_mps`, the
number an estimate of the intensity is judged against), `# jsbsim_gust_sigma_mps: north=…
east=… down=…` (the sample standard deviation of the `turb_north/east/down_mps` columns over
the flight, m/s: one stretch of turbulence, which scatters around the intensity) and
`# jsbsim_gust_correlation_s: north=… east=… down=…` (the lag at which each column's
autocorrelation first falls below 1/e, s), drops the rotary gust columns (`turb_p/q/r_dps`)
and writes the gust columns with 3 decimals, so a 50 s flight at 25 Hz stays under 200 kB.
The file is rewritten through a temporary file and a rename.
"""

from __future__ import annotations

import math
import os
import sys

from turb_process import jsbsim_intensity_mps

KEEP = ["turb_north_mps", "turb_east_mps", "turb_down_mps"]
DROP = ["turb_p_dps", "turb_q_dps", "turb_r_dps"]


def efold_lag(x, dt):
    n = len(x)
    m = sum(x) / n
    d = [v - m for v in x]
    var = sum(v * v for v in d) / n
    for lag in range(1, n // 2):
        r = sum(d[i] * d[i + lag] for i in range(n - lag)) / (n - lag) / var
        if r < math.exp(-1.0):
            return lag * dt
    return float("nan")


def main(path: str) -> int:
    with open(path) as f:
        lines = f.read().splitlines()
    head = [l for l in lines if l.startswith("#")]
    head = [l for l in head if not l.startswith("# jsbsim_gust_")]
    meta = dict(l[2:].split(": ", 1) for l in head if ": " in l)
    if "severity 3)" not in meta.get("jsbsim_turbulence", ""):
        raise SystemExit(f"{path}: the intensity is written here for JSBSim's light turbulence "
                         f"(severity 3) only, not {meta.get('jsbsim_turbulence', 'none')!r}")
    body = [l for l in lines if not l.startswith("#")]
    cols = body[0].split(",")
    rows = [r.split(",") for r in body[1:]]
    idx = {c: i for i, c in enumerate(cols)}
    t = [float(r[idx["time_s"]]) for r in rows]
    dt = t[1] - t[0]
    sig, lag = [], []
    for c in KEEP:
        x = [float(r[idx[c]]) for r in rows]
        m = sum(x) / len(x)
        sig.append(math.sqrt(sum((v - m) ** 2 for v in x) / len(x)))
        lag.append(efold_lag(x, dt))
    names = ["north", "east", "down"]
    # FGWinds takes the height above the ground; JSBSim's ground here is at sea level.
    height = float(meta["altitude_m"]) - sum(float(r[idx["down_m"]]) for r in rows) / len(rows)
    intensity = jsbsim_intensity_mps(height)
    head.append("# jsbsim_gust_intensity_mps: " + " ".join(f"{n}={intensity:.4f}" for n in names))
    head.append("# jsbsim_gust_sigma_mps: " + " ".join(f"{n}={s:.4f}" for n, s in zip(names, sig)))
    head.append("# jsbsim_gust_correlation_s: " + " ".join(f"{n}={v:.2f}" for n, v in zip(names, lag)))
    keep = [i for i, c in enumerate(cols) if c not in DROP]
    out = [",".join(cols[i] for i in keep)]
    for r in rows:
        out.append(",".join(f"{float(r[i]):.3f}" if cols[i] in KEEP else r[i] for i in keep))
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(head + out) + "\n")
    os.replace(tmp, path)
    print(f"{path}: gust intensity {intensity:.3f} m/s; sample σ N/E/D {sig[0]:.3f}/{sig[1]:.3f}/{sig[2]:.3f} m/s, "
          f"1/e lag {lag[0]:.2f}/{lag[1]:.2f}/{lag[2]:.2f} s, {os.path.getsize(path)} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]) if len(sys.argv) == 2 else 2)
