"""Side-by-side errors of the calibrated ball models (issue 5's model comparison).

Reads benchmarks/calibration/<ball>-<model>.json for the models whose report exists and prints,
per ball, each target's error against the seed's experiment (%), the number of targets within
the issue's goals and the RMS of the goal-normalised residuals (pct / goal), the calibration's
own objective.

Usage: python benchmarks/foam_comparison_table.py [ball ...]   (default: type1 type2)
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).parent / "calibration"
MODELS = ("mat006", "prony3", "mat057", "mat083")


def comparison(ball: str) -> str:
    reports = {}
    for model in MODELS:
        path = HERE / f"{ball}-{model}.json"
        if path.is_file() and path.stat().st_size > 0:
            reports[model] = json.loads(path.read_text())
    if not reports:
        return f"(no reports for {ball})"
    names = list(reports)
    head = " | ".join(f"{m} ({reports[m]['divisions']}-div)" for m in names)
    lines = [f"**{ball}**", "", f"| target | measured | {head} | goal |",
             "|---" * (len(names) + 3) + "|"]  # fmt: skip
    first = reports[names[0]]["targets"]
    for i, target in enumerate(first):
        cells = []
        for m in names:
            r = reports[m]["targets"][i]
            text = f"{r['fitted_pct']:+.1f} %"
            cells.append(f"**{text}**" if abs(r["fitted_pct"]) <= r["goal_pct"] else text)
        digits = 3 if target["unit"] in ("", "ms") else 0
        measured = f"{target['measured']:.{digits}f} {target['unit']}".strip()
        goal = f"{target['goal_pct']:.0f} %"
        lines.append(f"| {target['target']} | {measured} | {' | '.join(cells)} | {goal} |")
    within, rms = [], []
    for m in names:
        targets = reports[m]["targets"]
        within.append(
            f"{sum(abs(t['fitted_pct']) <= t['goal_pct'] for t in targets)}/{len(targets)}"
        )
        residuals = [t["fitted_pct"] / t["goal_pct"] for t in targets]
        rms.append(f"{math.sqrt(sum(r * r for r in residuals) / len(residuals)):.2f}")
    lines.append(f"| within goal | | {' | '.join(within)} | |")
    lines.append(f"| RMS of error/goal | | {' | '.join(rms)} | |")
    params = "; ".join(
        f"{m}: " + ", ".join(f"{k} = {v}" for k, v in reports[m]["parameters"].items())
        for m in names
    )
    return "\n".join(lines) + f"\n\nFitted: {params}.\n"


if __name__ == "__main__":
    for ball in sys.argv[1:] or ["type1", "type2"]:
        print(comparison(ball))
