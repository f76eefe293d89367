"""Regenerate the tables of docs/notes/ball-impact.md: the seed's four CCOR cases on the full ball.

Usage: python benchmarks/ball_impact_table.py [--hourglass-type 1] [--hourglass-coefficient 0.1]
       [--divisions 12]

Prints a Markdown table: batball beside the seed's experiment and LS-DYNA ("FE") columns, with
the % difference from LS-DYNA, for ball types 1 and 2 at 95 and 110 mph.
"""

from __future__ import annotations

import argparse

from batball.lab.impact import run_impact
from batball.models.impact import ImpactSetup
from batball.solvers.explicit import HourglassControl
from batball.specs import load_ball_spec
from batball.specs.seed import load_seed_tables

MPH, LBF, LBF_PER_IN = 0.44704, 4.4482216152605, 4.4482216152605 / 0.0254


def row(ball: str, mph: int, setup: ImpactSetup) -> str:
    seed = load_seed_tables().ball_impact(ball, mph)
    m = run_impact(load_ball_spec(ball), setup).measures

    def pct(ours: float, theirs: float) -> str:
        return f"{100 * (ours / theirs - 1):+.1f} %"

    return (
        f"| {ball[-1]} @ {mph} mph "
        f"| {seed.ccor_exp:.3f} / {seed.ccor_fe:.3f} / {m.restitution:.3f} "
        f"({m.restitution - seed.ccor_fe:+.3f}) "
        f"| {seed.ds_exp / LBF_PER_IN:.0f} / {seed.ds_fe / LBF_PER_IN:.0f} / "
        f"{m.dynamic_stiffness / LBF_PER_IN:.0f} ({pct(m.dynamic_stiffness, seed.ds_fe)}) "
        f"| {seed.peak_exp / LBF:.0f} / {seed.peak_fe / LBF:.0f} / {m.peak_force / LBF:.0f} "
        f"({pct(m.peak_force, seed.peak_fe)}) "
        f"| {seed.contact_exp * 1e3:.2f} / {seed.contact_fe * 1e3:.2f} / "
        f"{m.contact_time * 1e3:.3f} ({pct(m.contact_time, seed.contact_fe)}) |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hourglass-type", type=int, default=1)
    parser.add_argument("--hourglass-coefficient", type=float, default=0.1)
    parser.add_argument("--divisions", type=int, default=12)
    args = parser.parse_args()
    hourglass = HourglassControl(type=args.hourglass_type, coefficient=args.hourglass_coefficient)
    print("| ball @ speed | CCOR exp / FE / batball | DS lb/in exp / FE / batball "
          "| peak lbf exp / FE / batball | contact ms exp / FE / batball |")
    print("|---|---|---|---|---|")
    for ball, mph in (("type1", 95), ("type1", 110), ("type2", 95), ("type2", 110)):
        setup = ImpactSetup(test="ccor", speed=mph * MPH, divisions=args.divisions,
                            hourglass=hourglass)
        print(row(ball, mph, setup), flush=True)


if __name__ == "__main__":
    main()
