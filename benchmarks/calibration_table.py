"""Markdown tables of the calibration reports in benchmarks/calibration/*.json.

Usage: python benchmarks/calibration_table.py NAME [NAME ...]   (NAME = a report's file stem)
       python benchmarks/calibration_table.py --compare BALL   (BALL-mat006 beside BALL-prony3)
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


def _cost(rows: list[dict]) -> float:
    """Half the sum of squared goal-normalised errors (the optimiser's cost, unit weights)."""
    return 0.5 * sum((r["fitted_pct"] / r["goal_pct"]) ** 2 for r in rows)


def comparison(ball: str) -> str:
    """MAT_006 fit beside the prony3 fit of ``ball``, cell by cell (both full-mesh reports)."""
    fits = {m: json.loads((HERE / f"{ball}-{m}.json").read_text()) for m in ("mat006", "prony3")}
    lines = [
        f"**{ball}: MAT_006 against prony3** (both on the 12-division mesh)",
        "",
        "| cell | experiment | seed LS-DYNA | MAT_006 fit | prony3 fit | seed % | MAT_006 % "
        "| prony3 % | goal | closer |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    rows = {m: {r["target"]: r for r in f["targets"]} for m, f in fits.items()}
    for label, a in rows["mat006"].items():
        b = rows["prony3"][label]
        digits = 3 if a["unit"] in ("", "ms") else 0
        unit = f" {a['unit']}" if a["unit"] else ""
        cells = [f"{v:.{digits}f}{unit}" for v in (a["measured"], a["seed_fe"], a["fitted"])]
        pcts = [a["seed_fe_pct"], a["fitted_pct"], b["fitted_pct"]]
        closer = "tie" if abs(abs(pcts[1]) - abs(pcts[2])) < 0.05 else (
            "MAT_006" if abs(pcts[1]) < abs(pcts[2]) else "prony3")  # fmt: skip
        lines.append(
            f"| {label} | {' | '.join(cells)} | {b['fitted']:.{digits}f}{unit} | "
            + " | ".join(
                f"**{p:+.1f} %**" if abs(p) <= a["goal_pct"] else f"{p:+.1f} %" for p in pcts
            )
            + f" | {a['goal_pct']:.0f} % | {closer} |"
        )
    lines.append("")
    for m, f in fits.items():
        within = sum(abs(r["fitted_pct"]) <= r["goal_pct"] for r in f["targets"])
        params = ", ".join(f"{k} = {v}" for k, v in f["parameters"].items())
        lines.append(
            f"* {m}: cost {_cost(f['targets']):.2f}, {within}/8 cells within the goal, "
            f"{f['runs_computed']} runs, {f['wall_seconds'] / 60:.1f} min; {params}."
        )
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    if sys.argv[1:2] == ["--compare"]:
        print("\n".join(comparison(ball) for ball in sys.argv[2:]))
    else:
        print("\n".join(table(name) for name in sys.argv[1:]))
