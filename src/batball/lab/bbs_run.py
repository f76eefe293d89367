"""Run a batted-ball-speed test into the results store and summarise it with units.

``runs/bbs-<hash>/`` holds ``summary.json``, ``history.csv`` (time, contact force, ball velocity,
bat angular velocity, angular momentum about the pivot, energies), ``force_time.png`` (the
ball-bat contact force), ``barrel_deformation.png`` (the barrel's radial deflection at the
peak force, unrolled) and, for ParaView, ``ball.pvd`` (the ball's hexes) and ``bat.pvd`` (the
bat's shell mid-surface as quads), each with its per-frame VTU files, at the same few dozen
instants (the fields of :mod:`batball.solvers.frames`). Runs with the same inputs are reused.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Any

import numpy as np

from batball.lab.bbs import BbsResult, run_bbs
from batball.mesh import Mesh, ShellMesh
from batball.models.ball import ball_hourglass, with_ball_hourglass
from batball.models.bbs import BbsSetup, with_bat_friction
from batball.results.fields import write_time_series
from batball.results.plots import plot_force_time
from batball.results.store import (
    atomic_path,
    load_cached_summary,
    run_folder,
    write_csv_atomic,
    write_summary,
)
from batball.solvers.frames import BALL_CELL_FIELDS, Frame
from batball.specs import BallSpec, BatSpec, ball_spec_to_toml_dict, bat_spec_to_toml_dict
from batball.units import IN, LBF, MPH, OZ_IN2, PSI
from batball.version import __version__


def bbs_inputs(bat: BatSpec, ball: BallSpec, setup: BbsSetup) -> dict[str, Any]:
    """Everything that determines a run, JSON-able: the key of its run folder."""
    setup = with_bat_friction(with_ball_hourglass(setup, ball), bat)
    return {
        "bat": bat_spec_to_toml_dict(bat),
        "ball": ball_spec_to_toml_dict(ball),
        "setup": dataclasses.asdict(setup),
        "batball": __version__,
    }


def summarise_bbs(result: BbsResult, wall_seconds: float) -> dict[str, Any]:
    """The summary a person reads: each number's unit is in its key."""
    m, run, setup = result.measures, result.run, result.setup
    n_shells = result.model.bat_mesh.n_cells
    n_hexes = result.model.ball_cells.shape[0]
    return {
        "test": "bbs",
        "bat": result.bat.name,
        "ball": result.ball.name,
        "bbs_mph": m.bbs / MPH,
        "collision_efficiency": m.collision_efficiency,
        "bbcor": m.bbcor,
        "bbcor_from_bat_rotation": m.bbcor_from_bat,
        "k": m.k,
        "inbound_mph": m.inbound_speed / MPH,
        "rebound_mph": m.rebound_speed / MPH,
        "pitch_speed_mph": setup.pitch_speed / MPH,
        "swing_speed_mph": setup.swing_speed / MPH,
        "peak_force_lbf": m.peak_force / LBF,
        "peak_force_unfiltered_lbf": m.peak_force_raw / LBF,
        "contact_time_ms": m.contact_time * 1e3,
        "energy_balance_error": m.energy_balance_error,
        "angular_momentum_change": m.angular_momentum_change,
        "rebound_drift_mph": m.rebound_drift / MPH,
        "pivot_moi_oz_in2": m.pivot_inertia / OZ_IN2,
        "model_pivot_moi_oz_in2": m.model_pivot_inertia / OZ_IN2,
        "mass_scaling": setup.mass_scaling,
        "insert_friction": setup.insert_friction,
        "bat_shell": setup.bat_shell,
        "ball_hourglass_type": ball_hourglass(setup.hourglass, result.ball).type,
        "ball_hourglass_coefficient": ball_hourglass(setup.hourglass, result.ball).coefficient,
        **({"ball_contact_sfs": setup.contact.sfs} if setup.contact.sfs != 1.0 else {}),
        "added_mass_g": float(result.model.added_mass.sum() * 1e3),
        "added_mass_percent": float(
            100 * result.model.added_mass.sum() / result.model.coupled.bat.mass[:, 0].sum()
        ),
        "time_step_s": float(result.model.coupled.bat.stable_step),
        "pivot_to_impact_in": m.z / IN,
        "rigid_bat": setup.rigid_bat,
        "prestress": setup.prestress,
        # None without a pre-stress (a rigid bat, no insert): JSON has no NaN
        "prestress_kinetic_ratio": finite_or_none(run.prestress_kinetic_ratio),
        "interference_pressure_psi": finite_or_none(run.interference_pressure / PSI),
        "prestress_reused": run.prestress_reused,
        "n_shells": n_shells,
        "n_hexes": n_hexes,
        "n_steps": run.n_steps,
        "end_time_ms": float(run.column("time_s")[-1] * 1e3),
        "wall_seconds": wall_seconds,
        "solver_seconds": run.wall_seconds,
        "element_cycles_per_second": (n_shells + n_hexes) * run.n_steps / run.wall_seconds,
        "phase_seconds": run.phase_seconds,
    }


def finite_or_none(value: float) -> float | None:
    """``value``, or None where it is NaN or infinite (a quantity the run did not have)."""
    return float(value) if np.isfinite(value) else None


def write_history(folder: Path, result: BbsResult) -> None:
    """history.csv of the run, display units in the column names."""
    run = result.run
    columns = {
        "time_ms": run.column("time_s") * 1e3,
        "contact_force_lbf": run.column("contact_force_n") / LBF,
        "ball_velocity_y_mph": run.column("ball_vy") / MPH,
        "bat_angular_velocity_rad_s": run.column("bat_omega_rad_s"),
        "angular_momentum_kg_m2_s": run.column("angular_momentum"),
    }
    for name in ("kinetic", "ball_internal", "ball_hourglass", "ball_bulk_viscosity",
                 "bat_internal", "contact", "balance_error"):  # fmt: skip
        columns[f"{name}_energy_j"] = run.column(f"{name}_j")
    columns["ball_nodes_in_contact"] = run.column("ball_nodes_in_contact")
    columns["insert_nodes_in_contact"] = run.column("insert_nodes_in_contact")
    write_csv_atomic(folder / "history.csv", columns)


def write_bbs_fields(folder: Path, result: BbsResult) -> None:
    """``ball.pvd`` and ``bat.pvd``: the run's frames of ball and bat (reference points of the
    model as built, displacement from them)."""
    coupled, run = result.model.coupled, result.run
    n_bat = coupled.n_bat
    ball = Mesh(coupled.points[n_bat:], result.model.ball_cells)
    bat = ShellMesh(coupled.points[:n_bat], result.model.bat_mesh.cells)
    for path, mesh, frames, cell_names in (
        (folder / "ball.pvd", ball, run.ball_frames, BALL_CELL_FIELDS),
        (folder / "bat.pvd", bat, run.bat_frames, ("von_mises",)),
    ):
        data: Frame = dict(frames)
        displacement = data.pop("displacement")
        cells = {name: data.pop(name) for name in cell_names if name in data}
        write_time_series(path, mesh, run.frame_times, displacement, point_data=data,
                          cell_data=cells)  # fmt: skip


def plot_barrel_deformation(path: Path, result: BbsResult) -> None:
    """Radial deflection of the outer wall at the peak contact force (in), on the unrolled
    barrel around the impact point; the rigid rotation about the pivot removed."""
    from matplotlib.collections import PolyCollection

    from batball.results.plots import new_figure

    mesh = result.model.bat_mesh
    u = result.run.peak_displacement[: mesh.n_points].copy()
    points = mesh.points
    # each ring's mean displacement (the bat's rigid turn and bending) removed: what is left is
    # the wall's deformation within the section
    outer = mesh.point_sets["outer"]
    _, ring = np.unique(np.round(points[outer, 0], 9), return_inverse=True)
    for k in range(3):
        u[outer, k] -= (np.bincount(ring, u[outer, k]) / np.bincount(ring))[ring]
    radial = (points[:, 1] * u[:, 1] + points[:, 2] * u[:, 2]) / np.hypot(
        points[:, 1], points[:, 2]
    )
    near = np.abs(points[:, 0] - result.model.impact_x) < 4 * IN
    cells = np.setdiff1d(np.arange(mesh.n_cells), mesh.cell_sets.get("insert", []))
    cells = cells[near[mesh.cells[cells]].all(axis=1)]
    corners = points[mesh.cells[cells]]
    phi = np.degrees(np.arctan2(corners[..., 2], corners[..., 1]))
    first = phi[:, :1]
    phi = first + (phi - first + 180.0) % 360.0 - 180.0  # corners contiguous across +-180 deg
    value = radial[mesh.cells[cells]].mean(axis=1)
    fig, ax = new_figure(figsize=(7, 4))
    collection = PolyCollection(
        list(np.stack([corners[..., 0] / IN, phi], axis=-1)), array=value / IN, cmap="jet"
    )
    ax.add_collection(collection)
    ax.autoscale()
    ax.set_xlabel("x from the knob end (in)")
    ax.set_ylabel("angle from the impact side (deg)")
    ax.set_title("barrel radial deflection at peak force (in), each ring's mean motion removed")
    fig.colorbar(collection, ax=ax)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


def run_bbs_test(
    bat: BatSpec, ball: BallSpec, setup: BbsSetup, *, runs_dir: Path, reuse: bool = True
) -> tuple[dict[str, Any], Path]:
    """Run (or reuse) a batted-ball-speed test; returns its summary and its run folder."""
    folder = run_folder(runs_dir, "bbs", bbs_inputs(bat, ball, setup))
    cached = load_cached_summary(folder) if reuse else None
    if cached is not None:
        return cached, folder
    start = time.perf_counter()
    result = run_bbs(bat, ball, setup, store=runs_dir, reuse=reuse)
    summary = summarise_bbs(result, time.perf_counter() - start)
    summary["run_folder"] = folder.as_posix()
    write_history(folder, result)
    title = f"BBS {ball.name} on {bat.name} at {setup.speed / MPH:.0f} mph"
    run = result.run
    plot_force_time(folder / "force_time.png", run.column("time_s"),
                    run.column("contact_force_n"), title=title)  # fmt: skip
    if not setup.rigid_bat:
        plot_barrel_deformation(folder / "barrel_deformation.png", result)
    write_bbs_fields(folder, result)
    write_summary(folder, summary)
    return summary, folder
