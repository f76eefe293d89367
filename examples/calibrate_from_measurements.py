"""Calibrate a ball's MAT_006 viscoelastic constants to your own CCOR-test measurements.

Your lab measured a ball on the ASTM F2845 cylinder at two speeds (the numbers below are a
hypothetical ball's, near the seed study's type 1); they go into a CSV
(``quantity,speed,value``, units in the strings), and batball fits the ball model to them,
starting from the seed study's type-1 ball. The study file stores every simulation, so running
the script again resumes rather than repeats.

    python examples/calibrate_from_measurements.py          # 8-division ball: 10-20 minutes
    BATBALL_EXAMPLE_TINY=1 python examples/calibrate_from_measurements.py   # a tiny budget

Writes ``my_ball.toml``, which every test takes: ``batball bbs --ball my_ball.toml``.
"""

import os
from pathlib import Path

from batball.calibrate import OptimiserOptions, load_targets
from batball.calibrate.command import run_calibration, save_ball
from batball.specs import load_ball_spec


def main() -> None:
    """Run it (a function, so that the process pool's workers can import this file)."""
    Path("my_measurements.csv").write_text(
        "quantity,speed,value\n"
        "ccor,95 mph,0.390\n"
        "dynamic_stiffness,95 mph,7300 lbf/in\n"
        "peak_force,95 mph,4750 lbf\n"
        "contact_time,95 mph,1.02 ms\n"
        "ccor,110 mph,0.365\n"
        "dynamic_stiffness,110 mph,7350 lbf/in\n"
        "peak_force,110 mph,5600 lbf\n"
        "contact_time,110 mph,1.00 ms\n",
        encoding="utf-8",
    )
    targets = load_targets("my_measurements.csv")

    tiny = bool(os.environ.get("BATBALL_EXAMPLE_TINY"))
    options = (
        OptimiserOptions(global_points=1, coarse_divisions=3, coarse_evaluations=2,
                         fine_divisions=None)
        if tiny
        else OptimiserOptions(global_points=8, coarse_divisions=8, coarse_evaluations=20,
                              fine_divisions=None)
    )
    start = load_ball_spec("type1")
    ball, summary = run_calibration(start, options, study=Path("runs/my-ball.db"), targets=targets,
                                    workers=0 if tiny else None)
    for row in summary["targets"]:
        print(f"{row['target']:<28} measured {row['measured']:9.4g}  model {row['fitted']:9.4g} "
              f"{row['unit']:<7} ({row['fitted_pct']:+.1f} %)")
    print("fitted:", {k: f"{v:.4g}" for k, v in ball.material.values.items()}, "(SI)")
    save_ball(ball, Path("my_ball.toml"))
    print("wrote my_ball.toml")


if __name__ == "__main__":
    main()
