"""Markdown tables of the calibration reports in benchmarks/calibration/*.json.

Usage: python benchmarks/calibration_table.py NAME [NAME ...]   (NAME = a report's file stem)
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

HERE = Path(__file__).parent / "calibration"


def table(name: str) -> str:
    s = json.loads((HERE / f"{name}.json").read_text())
    lines = [
        f"**{name}** ({s['model']}, {s['divisions']}-division mesh; {s['runs_computed']} runs, "
        f"{s['wall_seconds'] / 60:.1f} min)",
        "",
        "| target | measured | fitted | seed LS-DYNA | fitted vs exp | seed vs exp | goal |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in s["targets"]:
        digits = 3 if r["unit"] in ("", "ms") else 0
        unit = f" {r['unit']}" if r["unit"] else ""

        def num(v: float | None, digits: int = digits, unit: str = unit) -> str:
            return "-" if v is None else f"{v:.{digits}f}{unit}"

        fit = f"{r['fitted_pct']:+.1f} %"
        if abs(r["fitted_pct"]) <= r["goal_pct"]:
            fit = f"**{fit}**"
        used = "" if r["used_in_fit"] else " (predicted)"
        seed = "-" if r["seed_fe_pct"] is None else f"{r['seed_fe_pct']:+.1f} %"
        lines.append(
            f"| {r['target']}{used} | {num(r['measured'])} | {num(r['fitted'])} | "
            f"{num(r['seed_fe'])} | {fit} | {seed} | {r['goal_pct']:.0f} % |"
        )
    params = ", ".join(f"{k} = {v}" for k, v in s["parameters"].items())
    lines += ["", f"Fitted: {params}.", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    print("\n".join(table(name) for name in sys.argv[1:]))
