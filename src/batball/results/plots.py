"""Figures a person reads: every axis names its unit."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from batball.results.store import atomic_path
from batball.units import LBF


def new_figure(*grid: int, figsize: tuple[float, float], dpi: float | None = None,
               **subplots: Any) -> tuple[Any, Any]:  # fmt: skip
    """A matplotlib Figure and its axes (``Figure.subplots(*grid, **subplots)``), made without
    pyplot: no backend is chosen or changed (a notebook's stays as it was), nothing is
    registered with pyplot's figure manager, and the figure is freed with its last reference.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, dpi=dpi)
    return fig, fig.subplots(*grid, **subplots)


def plot_force_time(
    path: Path, time: np.ndarray, force: np.ndarray, *, title: str, threshold: float | None = None
) -> None:
    """Load-cell force against time, in ms and lbf, written atomically as PNG.

    Args:
        time: (n,) [s]; force: (n,) [N]; threshold: the contact-time level [N], drawn if given.
    """
    level = None if threshold is None else (threshold / LBF, "contact-time level")
    plot_lines(
        path,
        [(time * 1e3, force / LBF, "load cell")],
        xlabel="time (ms)",
        ylabel="force (lbf)",
        title=title,
        level=level,
    )


def plot_lines(
    path: Path,
    lines: list[tuple[np.ndarray, np.ndarray, str]],
    *,
    xlabel: str,
    ylabel: str,
    title: str,
    level: tuple[float, str] | None = None,
    points: list[tuple[float, float, str]] | None = None,
) -> None:
    """Labelled curves (already in display units), a dashed level and marked points, as PNG.

    Args:
        lines: (x, y, label) per curve; xlabel, ylabel: axis names with their units.
        level: (y, label) of a horizontal dashed line; points: (x, y, label) markers.
    """

    fig, ax = new_figure(figsize=(6.4, 4.0), dpi=120)
    for x, y, label in lines:
        ax.plot(x, y, lw=1.2, label=label)
    if level is not None:
        ax.axhline(level[0], color="0.6", lw=0.8, ls="--", label=level[1])
    for px, py, plabel in points or []:
        ax.plot([px], [py], "o", color="tab:red", label=plabel)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="best")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp)
