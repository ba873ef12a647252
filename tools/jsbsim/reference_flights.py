#!/usr/bin/env python3
"""Make a set of c172p flights for judging a test flight against reference flights.

    python3 tools/jsbsim/reference_flights.py --out-dir /work/scratch/jsbsim
    python3 tools/jsbsim/reference_flights.py --out-dir DIR --true-changes   # + true sets

Every flight is `fly.py sequence` (open loop; one input on each of elevator, aileron and
rudder in a random order, a fourth input and a throttle step, drawn from the inputs seed),
50 s at 25 Hz with the standard noise (0.05 m, 0.05 deg, 0.05 m/s, 0.2 deg/s), each with its
own inputs and noise seed, so that no two flights are copies:

    ref-1, ref-2   unchanged c172p, calm (seeds 1, 2): the reference flights
    control        unchanged c172p, calm (seed 3): a test flight that should be judged normal
    clda075        ClDa x 0.75 (aileron power; seed 4)
    cnr140         Cnr x 1.4 (yaw damping; seed 5)
    cmalpha085     Cmalpha x 0.85 (pitch stiffness; seed 6)
    payload80      +80 kg at the CG (seed 7)
    turb-light     unchanged c172p in light Dryden turbulence (seed 8, turbulence seed 8)

With --true-changes, c172p_params.py --compare is run for each changed aircraft: it prints
the true change of the parameter set and writes the changed set next to the flights
(`<name>-true.toml`; 12-16 s each). The commands are printed before they run, so the set
can be remade one flight at a time.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import c172p_params  # noqa: E402
import fly  # noqa: E402

COMMON = ["sequence", "--rate", "25", "--duration", "50", "--noise"]

FLIGHTS = [  # (name, seed, extra fly.py options)
    ("ref-1", 1, []),
    ("ref-2", 2, []),
    ("control", 3, []),
    ("clda075", 4, ["--scale", "Clda=0.75"]),
    ("cnr140", 5, ["--scale", "Cnr=1.4"]),
    ("cmalpha085", 6, ["--scale", "Cmalpha=0.85"]),
    ("payload80", 7, ["--payload-kg", "80"]),
    ("turb-light", 8, ["--turbulence", "light", "--turbulence-seed", "8"]),
]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--out-dir", required=True, help="folder for the CSV files")
    ap.add_argument("--true-changes", action="store_true",
                    help="also print the true change of the parameter set of each changed "
                         "aircraft and write it as <name>-true.toml")
    ap.add_argument("--only", help="comma-separated names of the flights to make")
    args = ap.parse_args(argv)
    only = set(args.only.split(",")) if args.only else None
    for name, seed, extra in FLIGHTS:
        if only and name not in only:
            continue
        out = os.path.join(args.out_dir, name + ".csv")
        fa = COMMON + ["--inputs-seed", str(seed), "--seed", str(seed)] + extra + ["--out", out]
        print("$ python3 tools/jsbsim/fly.py " + shlex.join(fa), flush=True)
        t0 = time.monotonic()
        fly.main(fa)
        print(f"  ({time.monotonic() - t0:.1f} s)", flush=True)
        change = [x for x in extra if x not in ("--turbulence", "light", "--turbulence-seed")]
        if args.true_changes and extra and extra[0] in ("--scale", "--payload-kg"):
            toml = os.path.join(args.out_dir, name + "-true.toml")
            pa = ["--compare"] + change + ["--out", toml]
            print("$ python3 tools/jsbsim/c172p_params.py " + shlex.join(pa), flush=True)
            t0 = time.monotonic()
            c172p_params.main(pa)
            print(f"  ({time.monotonic() - t0:.1f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
