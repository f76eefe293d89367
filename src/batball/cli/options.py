"""Command-line options made from the lab registry's declarations, and what every command
shares: the results store, ``--json`` and the progress bar."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from batball.lab.protocol import Option
from batball.lab.registry import SUBJECT_DEFAULTS, SUBJECT_HELP


def add_options(p: argparse.ArgumentParser, options: Iterable[Option]) -> None:
    """One argument per declared option; values stay as typed, parsed by the option itself."""
    for option in options:
        if option.kind == "flag":
            action = "store_false" if option.default else "store_true"
            p.add_argument(*option.flags, dest=option.name, action=action,
                           help=option.help_line.replace("%", "%%"))  # fmt: skip
            continue
        # a choice is checked by the option itself (one line naming it), not by argparse
        metavar = "{" + ",".join(option.choices) + "}" if option.kind == "choice" else None
        p.add_argument(*option.flags, dest=option.name, default=option.default, metavar=metavar,
                       help=option.help_line.replace("%", "%%"))  # fmt: skip


def add_subject(p: argparse.ArgumentParser, kind: str) -> None:
    """``--ball`` or ``--bat``: an embedded name or a TOML file."""
    p.add_argument(f"--{kind}", default=SUBJECT_DEFAULTS[kind],
                   help=f"{SUBJECT_HELP[kind]} (default {SUBJECT_DEFAULTS[kind]!r})")  # fmt: skip


def add_store_options(p: argparse.ArgumentParser) -> None:
    """Where runs are stored, and whether a stored run with the same inputs is reused."""
    p.add_argument("--runs-dir", type=Path, default=Path("runs"), help="results store (runs/)")
    p.add_argument("--no-reuse", action="store_true", help="run even if the same run is stored")


def add_json_option(p: argparse.ArgumentParser) -> None:
    """``--json``: one JSON object on stdout instead of the short report."""
    p.add_argument("--json", action="store_true", help="print one JSON object")


def progress_bar(
    end_time: float, enabled: bool, unit: str = "ms"
) -> tuple[Callable[[float], None], Any]:
    """A tqdm bar over simulated time (in ``unit``, ms or s) on stderr; only on a terminal."""
    from tqdm import tqdm

    factor = 1e3 if unit == "ms" else 1.0
    bar = tqdm(
        total=round(end_time * factor, 3),
        unit=unit,
        desc="simulated",
        leave=False,
        disable=None if enabled else True,
        bar_format="{l_bar}{bar}| {n:.2f}/{total} " + unit,
    )

    def update(t: float) -> None:
        bar.n = round(t * factor, 3)
        bar.refresh()

    return update, bar
