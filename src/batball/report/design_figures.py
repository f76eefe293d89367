"""Figures of a design study's page, drawn from ``designs.csv``'s rows (values in the units of
their column names) and ``summary.json``'s influences.

- a scatter matrix (lower triangle) of the parameters and the objectives' responses;
- the objectives' trade-off: the first two objectives' responses with the Pareto front, or, with
  one objective, its response against a parameter;
- each parameter's standardised regression coefficient on chosen responses, as bars.

Feasible designs are filled circles, infeasible ones crosses, the best design a star; designs
rerun on the confirmation mesh are left out of the matrix (they repeat screened designs).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from batball.results.plots import new_figure
from batball.results.store import atomic_path

Row = Mapping[str, Any]

FEASIBLE = {"marker": "o", "color": "tab:blue", "s": 28, "alpha": 0.8}
INFEASIBLE = {"marker": "x", "color": "tab:red", "s": 30, "alpha": 0.8}
BEST = {"marker": "*", "color": "gold", "edgecolors": "black", "s": 240, "zorder": 5}
CONFIRMED = {"marker": "^", "color": "none", "edgecolors": "tab:green", "s": 60, "zorder": 4}
#: The size (inches) and resolution of the trade-off and influence figures.
FIGSIZE = (6.0, 4.3)
DPI = 120
#: The widest scatter matrix, inches.
MATRIX_INCHES = 12.0


@dataclass(frozen=True)
class Axis:
    """One plotted quantity: its ``designs.csv`` column and its axis label (with the unit)."""

    column: str
    label: str


def save(fig: Any, path: Path) -> None:
    """Write ``fig`` to ``path`` as PNG, atomically."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")


def values(rows: Sequence[Row], column: str) -> np.ndarray:
    """``column`` of ``rows`` as an (n_rows,) float array (NaN where empty)."""
    return np.array([np.nan if r.get(column) is None else float(r[column]) for r in rows])


def scatter_designs(ax: Any, rows: Sequence[Row], x: str, y: str, best: str | None) -> None:
    """Feasible designs as circles, infeasible as crosses, ``best`` as a star."""
    feasible = np.array([bool(r["feasible"]) for r in rows], dtype=bool)
    xs, ys = values(rows, x), values(rows, y)
    if feasible.any():
        ax.scatter(xs[feasible], ys[feasible], label="feasible", **FEASIBLE)
    if not feasible.all():
        ax.scatter(xs[~feasible], ys[~feasible], label="infeasible", **INFEASIBLE)
    ax.margins(0.08)  # the star at an edge of the design space stays whole
    chosen = [r for r in rows if r["design"] == best]
    if chosen:
        ax.scatter(values(chosen, x), values(chosen, y), label="best design", **BEST)


def plot_scatter_matrix(path: Path, rows: Sequence[Row], axes: Sequence[Axis],
                        best: str | None) -> None:  # fmt: skip
    """Every pair of ``axes`` (k >= 2) in the lower triangle of a (k-1) x (k-1) grid, as PNG."""
    k = len(axes)
    side = min(MATRIX_INCHES, 1.0 + 2.8 * (k - 1))
    fig, grid = new_figure(k - 1, k - 1, figsize=(side, side), dpi=100, squeeze=False,
                           sharex="col", sharey="row")  # fmt: skip
    for i in range(1, k):
        for j in range(k - 1):
            ax = grid[i - 1, j]
            if j >= i:
                ax.set_visible(False)
                continue
            scatter_designs(ax, rows, axes[j].column, axes[i].column, best)
            ax.grid(alpha=0.3)
            if i == k - 1:
                ax.set_xlabel(axes[j].label, fontsize=9)
            if j == 0:
                ax.set_ylabel(axes[i].label, fontsize=9)
    handles, labels = grid[0, 0].get_legend_handles_labels()
    if k > 2:
        fig.legend(handles, labels, loc="upper right", fontsize=9)
    else:
        grid[0, 0].legend(fontsize=8)
    fig.tight_layout()
    save(fig, path)


def plot_tradeoff(path: Path, rows: Sequence[Row], x: Axis, y: Axis, *, front: Sequence[str],
                  ranked: Sequence[str], confirmed: Sequence[Row] = (),
                  limits: Sequence[tuple[str, float, str]] = (), title: str) -> None:  # fmt: skip
    """``y`` against ``x`` for every screened design, the Pareto front joined by a line, the
    ranked designs numbered, confirmation reruns as triangles, constraint limits dashed.

    Args:
        front: the front's design ids; ranked: the best designs' ids, best first.
        limits: (axis "x" or "y", limit in the axis' unit, label) per constraint on x or y.
    """
    fig, ax = new_figure(figsize=FIGSIZE, dpi=DPI)
    scatter_designs(ax, rows, x.column, y.column, ranked[0] if ranked else None)
    on_front = [r for r in rows if r["design"] in set(front)]
    if on_front:
        xs, ys = values(on_front, x.column), values(on_front, y.column)
        order = np.argsort(xs)
        ax.plot(xs[order], ys[order], "-", color="tab:purple", lw=1.2, zorder=3)
        ax.scatter(xs, ys, marker="o", s=90, facecolors="none", edgecolors="tab:purple",
                   zorder=3, label="Pareto front")  # fmt: skip
    for px, py, text in rank_labels(rows, x, y, ranked):
        ax.annotate(text, (px, py), xytext=(7, 5), textcoords="offset points", fontsize=9)
    if confirmed:
        ax.scatter(values(confirmed, x.column), values(confirmed, y.column),
                   label="rerun on the confirmation mesh", **CONFIRMED)  # fmt: skip
    draw_limits(ax, rows, x, y, limits)
    ax.set_xlabel(x.label)
    ax.set_ylabel(y.label)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, path)


def rank_labels(rows: Sequence[Row], x: Axis, y: Axis,
                ranked: Sequence[str]) -> list[tuple[float, float, str]]:  # fmt: skip
    """(x, y, "1, 2") per ranked design, designs within 2 % of the axes' spans of a better
    one sharing its label (one label each would print over one another)."""
    by_id = {r["design"]: r for r in rows}
    xs, ys = values(rows, x.column), values(rows, y.column)
    span_x, span_y = float(np.ptp(xs)) or 1.0, float(np.ptp(ys)) or 1.0
    labels: list[tuple[float, float, list[str]]] = []
    for rank, design in enumerate(ranked, start=1):
        if design not in by_id:
            continue
        px, py = float(by_id[design][x.column]), float(by_id[design][y.column])
        near = [
            lab
            for lab in labels
            if abs(lab[0] - px) < 0.02 * span_x and abs(lab[1] - py) < 0.02 * span_y
        ]
        if near:
            near[0][2].append(str(rank))
        else:
            labels.append((px, py, [str(rank)]))
    return [(px, py, ", ".join(ranks)) for px, py, ranks in labels]


def draw_limits(ax: Any, rows: Sequence[Row], x: Axis, y: Axis,
                limits: Sequence[tuple[str, float, str]]) -> None:  # fmt: skip
    """Dashed lines at the constraint limits that lie near the designs (a far one would squash
    the designs into a corner)."""
    for where, limit, label in limits:
        data = values(rows, x.column if where == "x" else y.column)
        low, high = float(np.nanmin(data)), float(np.nanmax(data))
        pad = 0.5 * (high - low) if high > low else abs(high) * 0.05
        if not low - pad <= limit <= high + pad:
            continue
        line = ax.axvline if where == "x" else ax.axhline
        line(limit, color="k", ls="--", lw=0.9, label=label)


def plot_influence(path: Path, influence: Mapping[str, Mapping[str, float]],
                   parameters: Sequence[str], responses: Sequence[Axis], *,
                   title: str) -> None:  # fmt: skip
    """Grouped bars: each parameter's standardised regression coefficient on each response
    (``influence[response][parameter]``, R² under ``"r2"``), as PNG."""
    fig, ax = new_figure(figsize=(max(FIGSIZE[0], 1.6 + 1.4 * len(parameters)), FIGSIZE[1]),
                         dpi=DPI)  # fmt: skip
    width = 0.8 / len(responses)
    positions = np.arange(len(parameters), dtype=float)
    for i, response in enumerate(responses):
        coefficients = [influence[response.column].get(p, np.nan) for p in parameters]
        r2 = influence[response.column].get("r2", np.nan)
        ax.bar(positions + (i - 0.5 * (len(responses) - 1)) * width, coefficients, width,
               label=f"{response.label}, R² {r2:.2f}")  # fmt: skip
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xticks(positions)
    ax.set_xticklabels(parameters)
    ax.set_xlabel("parameter")
    ax.set_ylabel("standardised coefficient\n(response SD per parameter SD)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3, axis="y")
    ax.margins(y=0.35)  # room for the legend above or below the bars
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    save(fig, path)
