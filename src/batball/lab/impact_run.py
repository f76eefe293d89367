"""Run a ball-impact test into the results store and summarise it with units.

``runs/<test>-<hash>/`` holds ``summary.json``, ``history.csv`` (time, load-cell force, ball
velocity, energies), ``force_time.png``, ``ball.toml`` (the ball as run), ``fields.pvd`` with its
per-frame VTU files (the ball for ParaView: displacement, velocity, contact force and pressure,
stress, von Mises stress, pressure, volumetric strain; :mod:`batball.solvers.frames`) and
``target.pvd`` (the target's surface, frame by frame). Runs with the same inputs are reused.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.lab.impact import ImpactResult, run_impact
from batball.mesh import Mesh, mesh_quality
from batball.models.ball import ball_hourglass, with_ball_hourglass
from batball.models.impact import ImpactSetup
from batball.results.fields import write_target_series, write_time_series
from batball.results.plots import plot_force_time
from batball.results.store import (
    run_folder,
    run_or_reuse,
    write_csv_atomic,
    write_summary,
    write_text_atomic,
)
from batball.solvers.explicit import BALANCE, ENERGY_COLUMNS, ExplicitResult
from batball.solvers.frames import BALL_CELL_FIELDS
from batball.specs import BallSpec, ball_spec_to_toml_dict
from batball.units import IN, LBF, MPH, OZ
from batball.version import __version__

LBF_PER_IN = LBF / IN  # N/m
HOURGLASS = ENERGY_COLUMNS.index("hourglass")


def ball_test_inputs(ball: BallSpec, setup: Any) -> dict[str, Any]:
    """Everything that determines a ball test's run (the ball, the test's setup dataclass, the
    batball version), JSON-able: the key of its run folder; the hourglass control the run uses
    is in the setup's part, whether the test or the ball names it."""
    setup = with_ball_hourglass(setup, ball)
    return {
        "ball": ball_spec_to_toml_dict(ball),
        "setup": dataclasses.asdict(setup),
        "batball": __version__,
    }


def summarise(result: ImpactResult, wall_seconds: float) -> dict[str, Any]:
    """The summary a person reads: each number's unit is in its key."""
    m, run, setup = result.measures, result.run, result.setup
    kinetic0 = 0.5 * run.mass * m.inbound_speed**2
    quality = mesh_quality(result.mesh)
    return {
        "test": setup.test,
        setup.test: m.restitution,
        "ds_lbf_per_in": m.dynamic_stiffness / LBF_PER_IN,
        "peak_force_lbf": m.peak_force / LBF,
        "contact_time_ms": m.contact_time * 1e3,
        "contact_time_threshold_fraction_of_peak": setup.contact_threshold,
        "element_precision": setup.precision,
        "time_of_peak_ms": m.time_of_peak * 1e3,
        "inbound_mph": m.inbound_speed / MPH,
        "rebound_mph": m.rebound_speed / MPH,
        "ball": result.ball.name,
        "ball_mass_oz": run.mass / OZ,
        "energy_balance_error": float(np.abs(run.energies[:, BALANCE]).max() / kinetic0),
        "hourglass_energy_fraction": float(run.energies[-1, HOURGLASS] / kinetic0),
        "max_penetration_in": run.max_penetration / IN,
        "max_deflection_in": result.max_deflection / IN,
        "initial_kinetic_energy_j": kinetic0,
        "n_cells": result.mesh.n_cells,
        "n_points": result.mesh.n_points,
        "min_scaled_jacobian": quality.min_scaled_jacobian,
        "min_characteristic_length_in": quality.min_characteristic_length / IN,
        "n_steps": run.n_steps,
        "end_time_ms": float(run.time[-1] * 1e3),
        "wall_seconds": wall_seconds,
        "solver_seconds": run.wall_seconds,
        "element_cycles_per_second": result.mesh.n_cells * run.n_steps / run.wall_seconds,
        "hourglass_type": ball_hourglass(setup.hourglass, result.ball).type,
        "hourglass_coefficient": ball_hourglass(setup.hourglass, result.ball).coefficient,
        "bulk_viscosity": setup.bulk_viscosity.enabled,
        "contact_soft": setup.contact.soft,
        **({"contact_sfs": setup.contact.sfs} if setup.contact.sfs != 1.0 else {}),
    }


def write_history(folder: Path, result: ImpactResult) -> None:
    """history.csv: time, load-cell force, ball centre-of-mass velocity and the energies."""
    run = result.run
    columns = {
        "time_ms": run.time * 1e3,
        "contact_force_lbf": result.load_cell / LBF,
        "ball_velocity_z_mph": run.com_velocity[:, 2] / MPH,
        "ball_speed_mph": np.linalg.norm(run.com_velocity, axis=1) / MPH,
    }
    for k, name in enumerate(ENERGY_COLUMNS):
        columns[f"{name}_energy_j"] = run.energies[:, k]
    columns["contact_nodes"] = run.contact_nodes
    write_csv_atomic(folder / "history.csv", columns)


def write_outputs(folder: Path, result: ImpactResult, summary: dict[str, Any]) -> None:
    """All files of a finished run; summary.json last, so a folder without it is unfinished."""
    import tomli_w

    write_history(folder, result)
    write_text_atomic(folder / "ball.toml", tomli_w.dumps(ball_spec_to_toml_dict(result.ball)))
    title = (
        f"{result.setup.test.upper()} {result.ball.name} at "
        f"{result.measures.inbound_speed / MPH:.0f} mph"
    )
    plot_force_time(
        folder / "force_time.png",
        result.run.time,
        result.load_cell,
        title=title,
        threshold=result.setup.contact_threshold * result.measures.peak_force,
    )
    write_ball_fields(folder, result.mesh, result.run, result.targets)
    write_summary(folder, summary)


def write_ball_fields(
    folder: Path, mesh: Mesh, run: ExplicitResult, targets: tuple[RigidPlane | RigidCylinder, ...]
) -> None:
    """``fields.pvd`` (the ball's frames, :mod:`batball.solvers.frames`) and ``target.pvd``
    (the targets' surfaces, moving with their prescribed velocities) in ``folder``."""
    data = dict(run.frame_data)
    displacement = data.pop("displacement")
    cells = {name: data.pop(name) for name in BALL_CELL_FIELDS if name in data}
    write_time_series(folder / "fields.pvd", mesh, run.frame_times, displacement,
                      point_data=data, cell_data=cells)  # fmt: skip
    if targets:
        center = mesh.points.mean(axis=0)
        size = 2.5 * float(np.ptp(mesh.points[:, 0]))  # a flat wall's square: beyond the ball
        write_target_series(folder / "target.pvd", targets, run.frame_times, center=center,
                            size=size)  # fmt: skip


def run_impact_test(
    ball: BallSpec,
    setup: ImpactSetup,
    *,
    runs_dir: Path,
    reuse: bool = True,
    progress: Callable[[float], None] | None = None,
) -> tuple[dict[str, Any], Path]:
    """Run (or reuse) an impact test; returns its summary and its run folder."""
    folder = run_folder(runs_dir, setup.test, ball_test_inputs(ball, setup))
    return run_or_reuse(
        folder, reuse, lambda: run_impact(ball, setup, progress=progress), summarise,
        lambda result, summary: write_outputs(folder, result, summary),
    )
