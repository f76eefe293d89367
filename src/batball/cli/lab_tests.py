"""One subcommand per entry of the lab registry (:data:`batball.lab.registry.LAB_TESTS`)."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from batball.cli.options import (
    add_json_option,
    add_options,
    add_store_options,
    add_subject,
    progress_bar,
)
from batball.lab.registry import LAB_TESTS, load_subject
from batball.results.store import check_output_folder
from batball.units import summary_in_si


def add_lab_test_parsers(sub: Any) -> None:
    """``batball ccor``, ``cor``, ``compression``, ``props``, ``modal``, ``barrel``, ``bbs``."""
    for test in LAB_TESTS.values():
        p = sub.add_parser(test.name, help=test.help, description=test.help)
        for kind in test.subjects:
            add_subject(p, kind)
        add_options(p, test.options)
        add_store_options(p)
        add_json_option(p)
        p.add_argument("--units", choices=("us", "si"), default="us",
                       help="the units results are shown in: us (lbf, in, mph, oz; the "
                       "standards' units, as stored) or si (N, m, m/s, kg)")  # fmt: skip
        p.set_defaults(handler=run_lab_test_command, lab_test=test.name)


def run_lab_test_command(args: argparse.Namespace) -> int:
    """Check every option, load the subjects, run (or reuse) the test and report it."""
    test = LAB_TESTS[args.lab_test]
    setup = test.setup(**{o.name: getattr(args, o.name) for o in test.options})
    subjects = {kind: load_subject(kind, getattr(args, kind)) for kind in test.subjects}
    check_output_folder("runs-dir", args.runs_dir)
    span, unit = test.span(setup) if test.span is not None else (0.0, "s")
    update, bar = progress_bar(span, enabled=test.span is not None, unit=unit)
    try:
        summary, _ = test.execute(subjects, setup, runs_dir=args.runs_dir, reuse=not args.no_reuse,
                              progress=update)  # fmt: skip
    finally:
        bar.close()
    for warning in summary["warnings"]:
        print(f"batball: warning: {warning}", file=sys.stderr)
    if args.units == "si":
        summary = summary_in_si(summary)
        print(json.dumps(summary, indent=2) if args.json else describe_any(summary))
        return 0
    print(json.dumps(summary, indent=2) if args.json else test.describe(summary))
    return 0


def describe_any(summary: dict[str, Any]) -> str:
    """Every number and word of a summary, one per line, as its key names it (the key carries
    the unit)."""
    rows = [(k, v) for k, v in summary.items() if isinstance(v, int | float | str | bool)]
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"  {k:<{width}}  {v:.6g}" if isinstance(v, float) else f"  {k:<{width}}  {v}"
                     for k, v in rows)  # fmt: skip
