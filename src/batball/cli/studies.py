"""The studies: ``batball reproduce`` (the seed study as one report), ``calibrate`` and the
calibration routes (``compare-calibrations``, ``synthetic-data``, ``synthetic-noise``)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from batball.cli.bat import add_bat_mesh_options
from batball.cli.options import add_store_options


def add_reproduce_parser(sub: Any) -> None:
    """``batball reproduce``: every available test of the seed study, as an HTML report."""
    help_text = ("rerun the seed study (Tables 1-9) with the model of record and the seed's "
                 "balls as a solver check, and write an HTML report with figures")
    p = sub.add_parser("reproduce", help=help_text, description=help_text)
    p.add_argument(
        "--quick",
        action="store_true",
        help="coarse meshes (ball divisions 6, 16 bat shells around): a first look whose "
        "values are indicative (no verdicts)",
    )
    p.add_argument("--out", type=Path, default=Path("report"), help="report folder (report/)")
    p.add_argument(
        "--calibrate",
        action=argparse.BooleanOptionalAction,
        default=False,
        help="also refit the seed's balls with MAT_006 (batball calibrate; off by default: the "
        "model of record's fitted balls are embedded)",
    )
    p.add_argument("--ensemble", type=Path, default=None,
                   help="the folder of a batball ensemble run: the report shows its Table 9 "
                   "intervals (docs/ensemble.md)")  # fmt: skip
    add_store_options(p)
    p.add_argument("--json", action="store_true", help="print summary.json on stdout")
    p.set_defaults(handler=run_reproduce_command)  # fmt: skip


def run_reproduce_command(args: argparse.Namespace) -> int:
    """``batball reproduce``; progress on stderr, the report's path (or its JSON) on stdout."""
    from batball.report.reproduce import dump_summary, reproduce
    from batball.report.reproduce_setup import FULL_MESHES, QUICK_MESHES, ReproduceOptions

    calibrate = args.calibrate
    flag = ["--calibrate"] if calibrate else []
    command = " ".join(["batball", "reproduce", *(["--quick"] if args.quick else []), *flag,
                        "--out", args.out.as_posix(), "--runs-dir", args.runs_dir.as_posix(),
                        *(["--no-reuse"] if args.no_reuse else []),
                        *(["--ensemble", args.ensemble.as_posix()] if args.ensemble else []),
                        ])  # fmt: skip
    options = ReproduceOptions(out_dir=args.out, runs_dir=args.runs_dir,
                               meshes=QUICK_MESHES if args.quick else FULL_MESHES,
                               reuse=not args.no_reuse, command=command,
                               calibrate=calibrate, ensemble=args.ensemble)  # fmt: skip
    result = reproduce(options)
    for warning in result.warnings:
        print(f"batball: warning: {warning}", file=sys.stderr)
    print(dump_summary(result) if args.json else describe_reproduction(result))
    return 0


def describe_reproduction(result: Any) -> str:
    """Where the report is, how batball compares with the seed's LS-DYNA, what is missing."""
    from batball.report.reproduce_html import counts_text, verdict_counts

    counts = verdict_counts(result)
    missing = (
        ", ".join(o.test.name for o in result.outcomes if not o.available and not o.skipped)
        or "none"
    )
    skipped = [f"  {o.test.name} {o.missing}" for o in result.outcomes if o.skipped]
    verdicts = (
        ["  coarse meshes: every value is indicative, no verdicts (run without --quick)"]
        if result.indicative else
        [f"  predicted cells: batball {counts_text(counts['predicted'])} than the seed's LS-DYNA",
         f"  fitted cells: {counts_text(counts['fitted'])}"]
    )  # fmt: skip
    return "\n".join([
        f"report: {(result.options.out_dir / 'index.html').as_posix()}",
        *verdicts,
        f"  not yet available: {missing}",
        *skipped,
        f"  {result.seconds:.1f} s",
    ])  # fmt: skip


def add_calibrate_parser(sub: Any) -> None:
    """``batball calibrate``: fit a ball's material model to measured impact data."""
    from batball.calibrate.command import add_calibrate_arguments, run_calibrate_command

    help_text = "fit a ball's material model to measured CCOR, DS, peak force and contact time"
    p = sub.add_parser("calibrate", help=help_text, description=help_text)
    add_calibrate_arguments(p)
    p.set_defaults(handler=run_calibrate_command)


def add_routes_parsers(sub: Any) -> None:
    """``batball compare-calibrations``, ``synthetic-data`` and ``synthetic-noise``."""
    from batball.calibrate.routes_command import (
        add_compare_arguments,
        add_noise_arguments,
        add_synthetic_arguments,
        run_compare_command,
        run_noise_command,
        run_synthetic_command,
    )

    help_text = "calibrate a ball by each route with data (flat COR, CCOR, DMA) and compare BBS"
    p = sub.add_parser("compare-calibrations", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    add_compare_arguments(p)
    add_store_options(p)
    p.set_defaults(handler=run_compare_command)
    help_text = "measure a known true ball with the virtual tests: each route's data files"
    p = sub.add_parser("synthetic-data", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    add_synthetic_arguments(p)
    add_store_options(p)
    p.set_defaults(handler=run_synthetic_command)
    help_text = "seeded noisy copies of a synthetic route data set (assumed lab repeatability)"
    p = sub.add_parser("synthetic-noise", help=help_text, description=help_text)
    add_noise_arguments(p)
    p.set_defaults(handler=run_noise_command)
