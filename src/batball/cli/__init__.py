"""The command line: ``batball <test> ...``; ``--json`` prints one JSON object on stdout.

The virtual tests' subcommands are made from the lab registry (:mod:`batball.cli.lab_tests`); the
bat fit, the LS-DYNA decks and the studies (reproduce, calibrate, the calibration routes) have
modules of their own. Bad input exits with status 2 and one line naming the field, the value and
what is allowed; a numerical failure exits with status 3 and says where and when.
"""

from __future__ import annotations

import argparse
import re
import sqlite3
import sys
from collections.abc import Sequence
from typing import NoReturn

from batball.cli.bat import add_fit_bat_parser
from batball.cli.decks import add_export_parser, add_run_deck_parser
from batball.cli.design import add_design_parser
from batball.cli.ensemble import add_ensemble_parser
from batball.cli.lab_tests import add_lab_test_parsers
from batball.cli.studies import add_calibrate_parser, add_reproduce_parser, add_routes_parsers
from batball.errors import SimulationError, SpecError
from batball.version import __version__

#: What ``batball --help`` says first.
DESCRIPTION = ("batball, a virtual bat-and-ball laboratory: each virtual test is a subcommand; "
               "--json prints one JSON object on stdout.")  # fmt: skip


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose errors are one line like every other bad input's: the option
    named first, then what is wrong, then where the options are listed (exit status 2)."""

    def error(self, message: str) -> NoReturn:
        match = re.match(r"argument ([^:]+): (.*)", message, flags=re.DOTALL)
        if match:  # "argument -o/--output: ..." -> "output: ..."
            flag = match.group(1).split("/")[-1].lstrip("-")
            message = f"{flag}: {match.group(2)}"
        message = " ".join(message.split())
        self.exit(2, f"batball: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    """The ``batball`` parser with its subcommands (each made by the same parser class)."""
    parser = OneLineParser(prog="batball", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"batball {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    add_reproduce_parser(sub)  # the main job first in the help
    add_lab_test_parsers(sub)
    add_fit_bat_parser(sub)
    add_calibrate_parser(sub)
    add_design_parser(sub)
    add_ensemble_parser(sub)
    add_export_parser(sub)
    add_run_deck_parser(sub)
    add_routes_parsers(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``batball`` command; with no arguments, its help."""
    parser = build_parser()
    if not (sys.argv[1:] if argv is None else argv):
        parser.print_help()
        return 0
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a one-line option error (status 2)
        return exc.code if isinstance(exc.code, int) else 0
    try:
        return int(args.handler(args))
    except SpecError as exc:
        print(f"batball: error: {exc}", file=sys.stderr)
        return 2
    except SimulationError as exc:
        print(f"batball: simulation stopped: {exc}", file=sys.stderr)
        return 3
    except UnicodeDecodeError as exc:  # a text file that is not UTF-8 (a data or targets file)
        print(f"batball: error: an input file is not UTF-8 text ({exc.reason} at byte "
              f"{exc.start})", file=sys.stderr)  # fmt: skip
        return 2
    except OSError as exc:  # an output path in a missing folder, a folder given as a file, ...
        where = exc.filename if exc.filename is not None else "a file"
        print(f"batball: error: {where}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except sqlite3.DatabaseError as exc:
        print(f"batball: error: study file: {exc} (expected a study written by batball "
              "calibrate)", file=sys.stderr)  # fmt: skip
        return 2
