"""Cross-check of a synthetic comparison (docs/notes/calibration-routes.md): each ball the routes
fitted (MAT_006 or Prony), run in every route's impact tests (flat wall at 60 and 95 mph,
cylinder at 95 and 110 mph) on the 8-division ball, beside the truth. The balls are rebuilt from
the JSON's 5-figure parameters.

Run: ``PYTHONPATH=src NUMBA_NUM_THREADS=1 python benchmarks/routes/cross_check.py
[RESULT.json TRUTH.toml]`` (default: the Prony truth's ``synthetic-8div-16x0.4in.json`` and
``synthetic/true-ball.toml``; the foam truth: ``foam-8div-16x0.4in.json
synthetic-foam/true-ball.toml``).
"""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

from batball.calibrate.evaluate import RunRequest, run_request
from batball.specs import BallSpec, MaterialSpec, load_ball_spec
from batball.units import parse_quantity

HERE = Path(__file__).resolve().parent
MPH, LBF, IN = 0.44704, 4.4482216152605, 0.0254


def fitted_balls(result: str, truth: str) -> dict[str, BallSpec]:
    """The truth and the routes' balls of a comparison (MAT_006 and Prony laws)."""
    report = json.loads((HERE / "results" / result).read_text())
    base = load_ball_spec("type1")
    balls = {"truth": load_ball_spec(HERE / truth)}
    for row in report["routes"]:
        v = {
            k: parse_quantity(s, "frequency" if k.startswith("beta") else "pressure", field=k)
            for k, s in row["parameters"].items()
        }
        material = MaterialSpec(law=row["law"], values=v)
        balls[row["route"]] = dataclasses.replace(base, material=material)
    return balls


def main(
    result: str = "synthetic-8div-16x0.4in.json", truth: str = "synthetic/true-ball.toml"
) -> None:
    for name, ball in fitted_balls(result, truth).items():
        cells = []
        for test, mph in (("cor", 60), ("cor", 95), ("ccor", 95), ("ccor", 110)):
            m = run_request(RunRequest(ball, test, mph * MPH, 8))["measures"]
            cells.append(
                f"{test}@{mph}: e {m['restitution']:.4f} F {m['peak_force'] / LBF:.0f} lbf "
                f"DS {m['dynamic_stiffness'] / LBF * IN:.0f} lbf/in "
                f"tc {m['contact_time'] * 1e3:.3f} ms"
            )
        print(name, " | ".join(cells))


if __name__ == "__main__":
    main(*sys.argv[1:])
