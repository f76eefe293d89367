"""Figures of the reproduction report drawn from several runs' ``history.csv`` files.

- force against time for each ball at both speeds (the seed's Figure 15 shows ball type 2), with the
  seed's measured and LS-DYNA peak loads (Table 7) as reference lines: the seed's curves themselves
  are published only as pictures;
- the energy histories of every CCOR run (kinetic, internal, hourglass, contact, balance error).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from batball.results.store import atomic_path
from batball.units import LBF

if TYPE_CHECKING:
    from batball.report.runs import ReportFigure, TestRun

ENERGIES = ("kinetic", "internal", "hourglass", "contact", "balance_error")
SPEED_COLOURS = {95: "tab:blue", 110: "tab:red"}


def read_history(folder: Path) -> dict[str, np.ndarray]:
    """A run's ``history.csv`` as ``{column name: (n_samples,) array}`` (units in the names)."""
    data = np.genfromtxt(folder / "history.csv", delimiter=",", names=True)
    names = data.dtype.names or ()
    return {name: np.asarray(data[name], dtype=np.float64) for name in names}


def _speed(run: TestRun) -> int:
    """The run's nominal inbound speed, mph (95 or 110)."""
    return round(float(run.summary["inbound_mph"]))


def _save(fig: Any, path: Path) -> None:
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")


def plot_force_time_cases(figures_dir: Path, runs: Sequence[TestRun]) -> tuple[ReportFigure, ...]:
    """One PNG per ball: batball's force-time curves at each speed, the seed's peaks as lines."""
    from batball.report.runs import ReportFigure
    from batball.results.plots import new_figure
    from batball.specs import load_seed_tables

    seed = load_seed_tables()
    figures = []
    for ball in sorted({str(r.summary["ball"]) for r in runs}):
        fig, ax = new_figure(figsize=(6.4, 4.0), dpi=110)
        for run in (r for r in runs if r.summary["ball"] == ball):
            mph, history = _speed(run), read_history(run.folder)
            colour = SPEED_COLOURS.get(mph, "k")
            ax.plot(
                history["time_ms"],
                history["contact_force_lbf"],
                color=colour,
                lw=1.3,
                label=f"batball {mph} mph",
            )
            row = seed.ball_impact(ball, mph)
            ax.axhline(
                row.peak_exp / LBF,
                color=colour,
                ls="--",
                lw=0.8,
                label=f"seed experiment peak {mph} mph",
            )
            ax.axhline(
                row.peak_fe / LBF,
                color=colour,
                ls=":",
                lw=0.8,
                label=f"seed LS-DYNA peak {mph} mph",
            )
        ax.set_xlabel("time (ms)")
        ax.set_ylabel("force on the load cell (lbf)")
        ax.set_title(f"CCOR force against time, ball {ball} (cf. seed Figure 15)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
        name = f"figure15_{ball}.png"
        _save(fig, figures_dir / name)
        figures.append(
            ReportFigure(
                figures_dir / name,
                name,
                f"Force against time, {ball}, 95 and 110 mph; dashed: the "
                "seed's measured peak, dotted: its LS-DYNA peak (Table 7)",
                "force-time",
            )
        )
    return tuple(figures)


def plot_energy_histories(figures_dir: Path, runs: Sequence[TestRun]) -> ReportFigure:
    """One PNG with a panel per CCOR run: the energies (J) against time (ms)."""
    from batball.report.runs import ReportFigure
    from batball.results.plots import new_figure

    n_columns = 2
    n_rows = max(1, -(-len(runs) // n_columns))
    fig, axes = new_figure(n_rows, n_columns, figsize=(9.0, 3.0 * n_rows), dpi=100, squeeze=False)
    for ax, run in zip(axes.flat, runs, strict=False):
        history = read_history(run.folder)
        for energy in ENERGIES:
            ax.plot(
                history["time_ms"],
                history[f"{energy}_energy_j"],
                lw=1.1,
                label=energy.replace("_", " "),
            )
        ax.set_title(run.label, fontsize=10)
        ax.set_xlabel("time (ms)")
        ax.set_ylabel("energy (J)")
        ax.grid(alpha=0.3)
    for ax in axes.flat[len(runs) :]:
        ax.set_visible(False)
    axes.flat[0].legend(fontsize=7)
    name = "energies_ccor.png"
    _save(fig, figures_dir / name)
    return ReportFigure(
        figures_dir / name,
        name,
        "Energy histories of the CCOR runs: kinetic, internal, hourglass, contact "
        "and the balance error (total minus initial)",
        "energy",
    )
