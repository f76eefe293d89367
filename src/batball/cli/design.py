"""``batball design STUDY.toml``: a bat design study (:mod:`batball.design`), its page, its best
designs as bat specs."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from batball.cli.options import add_store_options


def add_design_parser(sub: Any) -> None:
    """``batball design``."""
    help_text = ("explore bat designs over a design space against certification limits: "
                 "sampling, a local search, the best confirmed on a finer mesh")
    p = sub.add_parser("design", help=help_text, description=help_text)
    p.add_argument("study", type=Path, help="the study file (TOML; docs/design.md)")
    p.add_argument("--out", type=Path, default=None,
                   help="the study's folder (default designs/<study name>/)")  # fmt: skip
    p.add_argument("--workers", type=int, default=None,
                   help="local process pool size (default: CPU cores; 0: this process)")
    p.add_argument("--scheduler", default=None,
                   help="Dask scheduler address instead of the local pool (one you trust: Dask "
                   "exchanges pickled data, and unpickling runs code)")  # fmt: skip
    add_store_options(p)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print summary.json on stdout")
    p.set_defaults(handler=run_design_command)


def run_design_command(args: argparse.Namespace) -> int:
    """Run the study, write its page, say where it is and what was best."""
    from batball.design import load_design_study, run_design_study
    from batball.errors import SpecError

    study = load_design_study(args.study)
    if args.workers is not None and args.workers < 0:
        raise SpecError("workers", args.workers, "0 (this process) or a positive pool size")
    out = args.out if args.out is not None else Path("designs") / study.name
    result = run_design_study(
        study, out_dir=out, runs_dir=args.runs_dir, workers=args.workers,
        scheduler=args.scheduler, reuse=not args.no_reuse, progress=not args.no_progress,
        log=lambda text: print(f"batball design: {text}", file=sys.stderr),
    )  # fmt: skip
    from batball.report.design_page import write_design_page

    page = write_design_page(out)
    if args.json:
        print((out / "summary.json").read_text(encoding="utf-8"))
        return 0
    print(describe_design(json.loads((out / "summary.json").read_text(encoding="utf-8")), page))
    return 0 if result.ranking and any(d.feasible for d in result.ranking) else 1


def describe_design(s: dict[str, Any], page: Path) -> str:
    """The study in a few lines: counts, the best designs with their margins, where the page is."""
    counts = ", ".join(f"{n} {stage}" for stage, n in s["designs"].items() if n)
    lines = [f"design study {s['study']} on {s['bat']}: {counts} designs, {s['feasible']} "
             f"feasible, {s['wall_seconds']:.0f} s ({s['mesh']})"]  # fmt: skip
    units = s["responses"]
    shown = [o["response"] for o in s["objectives"]] or list(units)[:3]
    for rank, best in enumerate(s["best"], start=1):
        params = ", ".join(f"{k} {v:.4g}" for k, v in best["parameters"].items())
        values = ", ".join(f"{r} {best['responses'][r]:.4g} {units[r]}".rstrip() for r in shown)
        margins = ", ".join(f"{k.removeprefix('margin_')} {v:+.3g}"
                            for k, v in best["margins"].items())  # fmt: skip
        lines.append(f"  {rank}. {best['design']}: {params} -> {values}"
                     + (f"; margins {margins}" if margins else ""))  # fmt: skip
        if "confirmed" in best:
            c = best["confirmed"]
            values = ", ".join(f"{r} {c['responses'][r]:.4g}" for r in shown)
            lines.append(f"     confirmed on {c['mesh']}: {values}, "
                         f"{'feasible' if c['feasible'] else 'NOT feasible'}")  # fmt: skip
    offset = s.get("confirmation_offset") or {}
    if offset:
        lines.append("  the finer mesh minus the screening mesh (mean over the confirmed): "
                     + ", ".join(f"{r} {offset[r]:+.3g}" for r in shown if r in offset)
                     + ": read screening margins against it")  # fmt: skip
    if s.get("confirm_mesh") and s["designs"].get("confirm"):
        sure = s.get("best_confirmed")
        lines.append(f"  best design feasible on the confirmation mesh: {sure}" if sure else
                     f"  no design was feasible on the confirmation mesh ({s['confirm_mesh']}): "
                     "more confirmation rounds ([confirm] rounds) or a wider design space")
    for row in s.get("league_balls", []):
        lines.append(f"  league ball {row['ball']} from {row['prior']} on "
                     f"{row['ball_divisions']} divisions: COR {row['cor']:.3f}, compression "
                     f"{row['compression_lbf']:.0f} lbf")  # fmt: skip
    if not s["best"]:
        lines.append("  no feasible design: widen the design space or relax a constraint")
    lines.append(f"page: {page.as_posix()}")
    return "\n".join(lines)
