"""Cross-check of the synthetic comparison (docs/calibration-routes.md): each MAT_006 ball the
impact routes fitted, run in the other route's tests (flat wall at 60 and 95 mph, cylinder at 95
and 110 mph) on the 8-division ball, beside the truth. The balls are rebuilt from the JSON's
5-figure parameters.

Run: ``PYTHONPATH=src NUMBA_NUM_THREADS=1 python benchmarks/routes/cross_check.py``.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

from batball.calibrate.evaluate import RunRequest, run_request
from batball.specs import BallSpec, MaterialSpec, load_ball_spec
from batball.units import parse_quantity

HERE = Path(__file__).resolve().parent
MPH, LBF, IN = 0.44704, 4.4482216152605, 0.0254
DIMS = {"bulk_modulus": "pressure", "g0": "pressure", "g_inf": "pressure", "beta": "frequency"}


def fitted_balls() -> dict[str, BallSpec]:
    """The truth and the impact routes' MAT_006 balls of the synthetic comparison."""
    report = json.loads((HERE / "results" / "synthetic-8div-16x0.4in.json").read_text())
    base = load_ball_spec("type1")
    balls = {"truth": load_ball_spec(HERE / "synthetic" / "true-ball.toml")}
    for row in report["routes"]:
        if row["law"] == "mat006":
            v = {k: parse_quantity(s, DIMS[k], field=k) for k, s in row["parameters"].items()}
            material = MaterialSpec(law="mat006", values=v)
            balls[row["route"]] = dataclasses.replace(base, material=material)
    return balls


def main() -> None:
    for name, ball in fitted_balls().items():
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
    main()
