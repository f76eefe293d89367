"""Run a ball-compression test into the results store and summarise it with units.

``runs/compression-<hash>/`` holds ``summary.json``, ``curve.csv`` (plate travel, mean plate
force and the top-bottom difference), ``force_displacement.png``, ``history.csv`` (every step's
plate forces and energies), ``ball.toml``, ``fields.pvd`` (the squeezed ball for ParaView, the
fields of :mod:`batball.solvers.frames`) and ``target.pvd`` (the two plates, the top one moving).
Runs with the same inputs are reused.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from batball.lab.compression import CompressionResult, run_compression
from batball.lab.impact_run import ball_test_inputs, write_ball_fields
from batball.mesh import mesh_quality
from batball.models.ball import ball_hourglass
from batball.models.compression import CompressionSetup
from batball.results.plots import plot_lines
from batball.results.store import (
    run_folder,
    run_or_reuse,
    write_csv_atomic,
    write_summary,
    write_text_atomic,
)
from batball.solvers.explicit import ENERGY_COLUMNS
from batball.specs import BallSpec, ball_spec_to_toml_dict
from batball.units import IN, LBF, OZ


def summarise_compression(result: CompressionResult, wall_seconds: float) -> dict[str, Any]:
    """The summary a person reads: each number's unit is in its key."""
    run, setup = result.run, result.setup
    energies = run.energies[-1]
    internal = float(energies[ENERGY_COLUMNS.index("internal")])
    quality = mesh_quality(result.mesh)
    return {
        "test": "compression",
        "compression_lbf": result.compression / LBF,
        "compression_fit_lbf": result.compression_fit / LBF,
        "displacement_in": setup.displacement / IN,
        "rate_in_per_min": setup.rate / IN * 60.0,
        "loading_time_s": setup.displacement / setup.rate,
        "ball": result.ball.name,
        "ball_mass_oz": result.ball.mass / OZ,
        "plate_force_difference_fraction": float(
            abs(result.force_difference[-1]) / max(result.compression, 1e-300)
        ),
        "kinetic_to_internal_energy": result.kinetic_to_internal,
        "max_penetration_in": run.max_penetration / IN,
        "max_deflection_in": result.max_deflection / IN,
        "energy_balance_error": result.energy_balance_error,
        "hourglass_energy_fraction": float(
            energies[ENERGY_COLUMNS.index("hourglass")] / max(internal, 1e-300)
        ),
        "mass_scale": result.mass_scale,
        "mass_damping_per_s": result.damping,
        "quasi_static_ratio": setup.quasi_static_ratio,
        "damping_ratio": setup.damping_ratio,
        "n_cells": result.mesh.n_cells,
        "n_points": result.mesh.n_points,
        "min_scaled_jacobian": quality.min_scaled_jacobian,
        "n_steps": run.n_steps,
        "wall_seconds": wall_seconds,
        "solver_seconds": run.wall_seconds,
        "hourglass_type": ball_hourglass(setup.hourglass, result.ball).type,
        "hourglass_coefficient": ball_hourglass(setup.hourglass, result.ball).coefficient,
        "bulk_viscosity": setup.bulk_viscosity.enabled,
        "contact_soft": setup.contact.soft,
        **({"contact_sfs": setup.contact.sfs} if setup.contact.sfs != 1.0 else {}),
    }


def write_compression_outputs(
    folder: Path, result: CompressionResult, summary: dict[str, Any]
) -> None:
    """All files of a finished run; summary.json last, so a folder without it is unfinished."""
    import tomli_w

    run, setup = result.run, result.setup
    write_csv_atomic(
        folder / "curve.csv",
        {
            "displacement_in": result.displacement / IN,
            "force_lbf": result.force / LBF,
            "top_minus_bottom_force_lbf": result.force_difference / LBF,
        },
    )
    history = {
        "time_s": run.time,
        "displacement_in": setup.rate * run.time / IN,
        "top_plate_force_lbf": run.reaction[:, 0, 2] / LBF,
        "bottom_plate_force_lbf": -run.reaction[:, 1, 2] / LBF,
    }
    for k, name in enumerate(ENERGY_COLUMNS):
        history[f"{name}_energy_j"] = run.energies[:, k]
    write_csv_atomic(folder / "history.csv", history)
    write_text_atomic(folder / "ball.toml", tomli_w.dumps(ball_spec_to_toml_dict(result.ball)))
    d_in = setup.displacement / IN
    plot_lines(
        folder / "force_displacement.png",
        [(result.displacement / IN, result.force / LBF, "mean plate force")],
        xlabel="plate travel (in)",
        ylabel="force (lbf)",
        title=f"Compression of ball {result.ball.name} at {summary['rate_in_per_min']:g} in/min",
        points=[(d_in, result.compression / LBF, f"{result.compression / LBF:.0f} lbf")],
    )
    write_ball_fields(folder, result.mesh, run, result.targets)
    write_summary(folder, summary)


def run_compression_test(
    ball: BallSpec,
    setup: CompressionSetup,
    *,
    runs_dir: Path,
    reuse: bool = True,
    progress: Callable[[float], None] | None = None,
) -> tuple[dict[str, Any], Path]:
    """Run (or reuse) a compression test; returns its summary and its run folder."""
    folder = run_folder(runs_dir, "compression", ball_test_inputs(ball, setup))
    return run_or_reuse(
        folder, reuse, lambda: run_compression(ball, setup, progress=progress),
        summarise_compression,
        lambda result, summary: write_compression_outputs(folder, result, summary),
    )
