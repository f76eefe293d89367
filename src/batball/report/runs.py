"""What the report is made of: each test's runs and the figures drawn from them."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class ReportFigure:
    """A PNG to show: its file, its name under ``out_dir/figures``, caption and page section."""

    source: Path
    name: str
    caption: str
    section: str


@dataclass(frozen=True)
class TestRun:
    """One run of a test: its summary and folder, whether it was reused, and what it measured."""

    label: str
    summary: dict[str, Any]
    folder: Path
    reused: bool
    seconds: float  # wall time in this invocation (near 0 when reused)
    values: dict[str, float]
    figures: tuple[ReportFigure, ...] = ()
