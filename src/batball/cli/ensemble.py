"""``batball ensemble STUDY.toml``: batted-ball speed with its uncertainty, an ensemble of bats
consistent with the bat's measurements times balls consistent with the ball's
(:mod:`batball.calibrate.ensemble`)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from batball.cli.options import add_store_options


def add_ensemble_parser(sub: Any) -> None:
    """``batball ensemble``."""
    help_text = ("batted-ball speed with a prediction interval: bats drawn from the fitted "
                 "bat's posterior times the ball models that fit the ball's tests, each pair "
                 "through the BBS test; the interval, the bat's and the ball's share of it, "
                 "and the probability of each ranking")  # fmt: skip
    p = sub.add_parser("ensemble", help=help_text, description=help_text)
    p.add_argument("study", type=Path, help="the ensemble file (TOML; docs/ensemble.md)")
    p.add_argument("--out", type=Path, default=None,
                   help="where members.csv, summary.json and the page index.html go (default "
                   "ensembles/<study name>/)")  # fmt: skip
    p.add_argument("--workers", type=int, default=None,
                   help="local process pool size (default: CPU cores; 0: this process)")
    p.add_argument("--scheduler", default=None,
                   help="Dask scheduler address instead of the local pool (one you trust: Dask "
                   "exchanges pickled data, and unpickling runs code)")  # fmt: skip
    add_store_options(p)
    p.add_argument("--json", action="store_true", help="print summary.json on stdout")
    p.set_defaults(handler=run_ensemble_command)


def run_ensemble_command(args: argparse.Namespace) -> int:
    """Run the ensemble, write its files, print its cells."""
    from batball.calibrate.ensemble import load_ensemble_study, run_ensemble
    from batball.errors import SpecError

    study = load_ensemble_study(args.study)
    if args.workers is not None and args.workers < 0:
        raise SpecError("workers", args.workers, "0 (this process) or a positive pool size")
    out = args.out if args.out is not None else Path("ensembles") / study.name
    result = run_ensemble(
        study, out_dir=out, runs_dir=args.runs_dir, workers=args.workers,
        scheduler=args.scheduler, reuse=not args.no_reuse,
        log=lambda text: print(f"batball ensemble: {text}", file=sys.stderr),
    )  # fmt: skip
    from batball.report.ensemble_page import write_ensemble_page

    page = write_ensemble_page(out)
    if args.json:
        print(json.dumps(result.summary, indent=2))
    else:
        print(describe_ensemble(result.summary, out, page))
    return 0


def describe_ensemble(s: dict[str, Any], out: Path, page: Path) -> str:
    """Each cell's mean and 95 % interval with the bat's and the ball's share, each trend and
    ranking, in mph; where the files are."""
    n_bats = len(s["bats"])
    lines = [f"ensemble {s['study']} on {s['bat']}: {n_bats} bats x {len(s['balls'])} ball "
             f"models, {s['members']} members ({len(s['failed'])} failed), "
             f"{s['wall_seconds']:.0f} s"]  # fmt: skip
    lines.append("  cell: mean [95 % interval] mph; sd of the bat's part, the ball's part")
    for c in s["cells"]:
        st = c["stats"]
        exp = (f"; experiment {c['experiment_mph']:.4g} "
               f"({'inside' if st['low'] <= c['experiment_mph'] <= st['high'] else 'OUTSIDE'})"
               if "experiment_mph" in c else "")  # fmt: skip
        lines.append(f"  {c['ball']} @ {c['speed_mph']:.4g} mph: {st['mean']:.2f} "
                     f"[{st['low']:.2f}, {st['high']:.2f}]; bat {st['sd_bat']:.2f}, ball "
                     f"{st['sd_ball']:.2f}{exp}")  # fmt: skip
    for t in s["trends"]:
        st = t["stats"]
        exp = f"; experiment {t['experiment_mph']:+.2f}" if "experiment_mph" in t else ""
        lines.append(f"  {t['ball']} from {t['from_mph']:.4g} to {t['to_mph']:.4g} mph: "
                     f"{st['mean']:+.2f} [{st['low']:+.2f}, {st['high']:+.2f}]{exp}")  # fmt: skip
    for r in s["rankings"]:
        lines.append(f"  P({r['first']} faster than {r['second']} at {r['speed_mph']:.4g} mph) "
                     f"= {r['probability_first_faster']:.2f}")  # fmt: skip
    lines.append(f"  page: {page}; members: {out / 'members.csv'}; summary: {out / 'summary.json'}")
    return "\n".join(lines)
