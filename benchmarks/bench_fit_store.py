"""A BBS run that relaxes the insert's fit against one that restores it from the store.

Runs the same batted-ball-speed test ``--pairs`` times as (fresh, reused) pairs, alternating in
one process so both see the same machine: "fresh" empties the store's ``fit-*`` folders first
and relaxes the fit; "reused" restores it (lab/fit_store.py). Prints wall seconds, the BBS
and the fit pressure of each run; the two kinds must agree to the last digit. Usage:

    PYTHONPATH=src python benchmarks/bench_fit_store.py --ball type2 --speed-mph 110
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

from batball.lab.bbs import IN, MPH, run_bbs
from batball.models.bbs import BbsSetup
from batball.specs import load_ball_spec, load_bat_spec

PSI = 6894.757293168  # Pa


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ball", default="type2")
    parser.add_argument("--speed-mph", type=float, default=110.0)
    parser.add_argument("--ball-divisions", type=int, default=12)
    parser.add_argument("--circumferential", type=int, default=48)
    parser.add_argument("--axial-size-in", type=float, default=0.1)
    parser.add_argument("--pairs", type=int, default=2)
    args = parser.parse_args()
    bat, ball = load_bat_spec("default"), load_ball_spec(args.ball)
    setup = BbsSetup(speed=args.speed_mph * MPH, ball_divisions=args.ball_divisions,
                     circumferential=args.circumferential,
                     axial_size=args.axial_size_in * IN)  # fmt: skip
    store = Path(tempfile.mkdtemp(prefix="fit-store-"))
    print("run    restored  wall_s   BBS_mph    fit_psi")
    for _ in range(args.pairs):
        for label in ("fresh", "reused"):
            if label == "fresh":
                for folder in store.glob("fit-*"):
                    shutil.rmtree(folder)
            start = time.perf_counter()
            result = run_bbs(bat, ball, setup, store=store)
            wall = time.perf_counter() - start
            print(f"{label:6} {result.run.prestress_reused!s:9} {wall:6.1f}  "
                  f"{result.measures.bbs / MPH:9.4f}  "
                  f"{result.run.interference_pressure / PSI:9.3f}", flush=True)  # fmt: skip
    shutil.rmtree(store)


if __name__ == "__main__":
    main()
