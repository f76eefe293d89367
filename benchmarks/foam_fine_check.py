"""Re-run calibrated balls on another mesh and print their errors against the seed's targets.

The foam calibrations (benchmarks/calibrate_foam_balls.sh) fit on the 8-division ball only; the
MAT_006 fits ended on the 12-division (seed) ball. This re-evaluates saved fits on the
12-division ball so that the comparison in docs/notes/foams.md is on one mesh.

Usage: python benchmarks/foam_fine_check.py [--divisions N] NAME [NAME ...]
(NAME = a fitted ball's stem in benchmarks/calibration, e.g. type1-mat057)
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

from batball.calibrate import seed_targets
from batball.calibrate.targets import QUANTITIES
from batball.lab.impact import run_impact
from batball.models.impact import ImpactSetup
from batball.specs import load_ball_spec

HERE = Path(__file__).parent / "calibration"


def check(name: str, divisions: int) -> dict:
    ball = load_ball_spec(HERE / f"{name}.toml")
    targets = seed_targets(name.split("-")[0])
    start = time.perf_counter()
    measures = {}
    for test, speed in sorted({(QUANTITIES[t.quantity].test, t.speed) for t in targets}):
        setup = ImpactSetup(test=test, speed=speed, divisions=divisions)
        measures[test, speed] = run_impact(ball, setup).measures
    rows = []
    for t in targets:
        q = QUANTITIES[t.quantity]
        value = getattr(measures[q.test, t.speed], q.attribute)
        pct = 100.0 * (value - t.value) / t.value
        rows.append({"target": f"{t.quantity} @ {t.speed / 0.44704:.0f} mph", "pct": pct,
                     "goal_pct": 100.0 * q.tolerance})  # fmt: skip
    rms = math.sqrt(sum((r["pct"] / r["goal_pct"]) ** 2 for r in rows) / len(rows))
    within = sum(abs(r["pct"]) <= r["goal_pct"] for r in rows)
    return {"name": name, "divisions": divisions, "rows": rows, "rms": rms, "within": within,
            "seconds": time.perf_counter() - start}  # fmt: skip


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--divisions", type=int, default=12)
    parser.add_argument("names", nargs="+")
    args = parser.parse_args()
    for name in args.names:
        print(json.dumps(check(name, args.divisions)))
