"""Run the barrel compression test (seed Table 2) into the results store, summarised with units.

Two folders, each keyed by the hash of its inputs:

* ``runs/prestress-<hash>/``: the interference-fit state of a bat and mesh, ``prestress.npz``
  (displacements, insert contact forces and pressures, closed gaps), like LS-DYNA's ``drdisp``
  file: computed once, then read as the initial state of every later test of that bat.
* ``runs/barrel-<hash>/``: ``summary.json`` (preload and final load beside Table 2, the
  interference pressure, the insert-barrel contact forces split top and bottom),
  ``force_travel.csv`` and ``force_travel.png`` (the force-displacement curve) and
  ``prestress.png`` (the fringe of the pre-stress in the barrel and insert, seed Figure 10).
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from batball.lab.barrel import (
    BarrelResult,
    CompressionCurve,
    halves,
    insert_cosines,
    membrane_stress,
    run_barrel_compression,
    table2_loads,
    von_mises,
)
from batball.lab.barrel_explicit import (
    ExplicitBarrelOptions,
    ExplicitCurve,
    run_explicit_compression,
)
from batball.mesh.bat import DEFAULT_AXIAL_SIZE, DEFAULT_CIRCUMFERENTIAL
from batball.models.barrel import (
    BarrelModel,
    BarrelTestOptions,
    Prestress,
    build_barrel_model,
    compute_prestress,
    contact_areas,
    load_axes,
    thin_ring_interference_pressure,
)
from batball.results.store import (
    atomic_path,
    load_cached_summary,
    load_stored_arrays,
    run_folder,
    write_arrays_atomic,
    write_csv_atomic,
    write_json_atomic,
    write_summary,
)
from batball.specs.bat import BatSpec, bat_spec_to_toml_dict
from batball.units import IN, LBF, PSI
from batball.version import __version__

PRESTRESS_FILE = "prestress.npz"


def seed_table2() -> dict[str, dict[str, float]]:
    """Seed Table 2 (lbf), from ``specs/seed.py``: preload (the first 0.02 in) and final load
    (the further 0.05 in), experiment and the seed's LS-DYNA model. The table gives whole
    pounds; the rounding to 1e-6 lbf only removes the N -> lbf round trip's last bits."""
    from batball.specs.seed import load_seed_tables

    b = load_seed_tables().barrel
    return {
        "experiment": {"preload_lbf": round(b.preload_exp / LBF, 6),
                       "final_load_lbf": round(b.final_load_exp / LBF, 6)},
        "seed_lsdyna": {"preload_lbf": round(b.preload_fe / LBF, 6),
                        "final_load_lbf": round(b.final_load_fe / LBF, 6)},
    }  # fmt: skip


def prestress_inputs(spec: BatSpec, circumferential: int, axial_size: float,
                     options: BarrelTestOptions, ramp_steps: int) -> dict[str, Any]:  # fmt: skip
    """What the pre-stressed state depends on (its store key)."""
    return {
        "bat": bat_spec_to_toml_dict(spec),
        "mesh": {"circumferential": circumferential, "axial_size_m": axial_size},
        "penalty_factor": options.penalty_factor,
        "ramp_steps": ramp_steps,
        "batball": __version__,
    }


def save_prestress(folder: Path, prestress: Prestress, summary: dict[str, Any]) -> None:
    """Write ``prestress.npz`` then the folder's summary (atomic, summary last)."""
    write_arrays_atomic(folder / PRESTRESS_FILE, dataclasses.asdict(prestress))
    write_summary(folder, summary)


def load_prestress(folder: Path, model: BarrelModel) -> Prestress | None:
    """The stored state if the folder is complete and its arrays fit ``model``, else None."""
    data = load_stored_arrays(folder, PRESTRESS_FILE)
    try:
        stored = Prestress(**data) if data is not None else None
    except TypeError:  # other fields: written by another version
        return None
    if stored is None or stored.u.size != 6 * model.mesh.n_points \
            or stored.active.size != model.interference.n_gaps:
        return None
    return stored


def obtain_prestress(model: BarrelModel, folder: Path, *, ramp_steps: int,
                     reuse: bool) -> tuple[Prestress, bool]:  # fmt: skip
    """The stored pre-stress of this bat and mesh, or a new one stored; and whether reused."""
    stored = load_prestress(folder, model) if reuse else None
    if stored is not None:
        return stored, True
    start = time.perf_counter()
    prestress = compute_prestress(model, ramp_steps=ramp_steps)
    summary = {"test": "prestress", "bat": model.spec.name,
               "mean_pressure_psi": interference_pressure(model, prestress) / PSI,
               "wall_seconds": time.perf_counter() - start}  # fmt: skip
    save_prestress(folder, prestress, summary)
    return prestress, False


def interference_pressure(model: BarrelModel, prestress: Prestress) -> float:
    """Mean contact pressure over the insert's outer surface, Pa."""
    return float(prestress.contact_force.sum() / contact_areas(model).sum())


def table2_summary(spec: BatSpec, curves: list[CompressionCurve],
                   options: BarrelTestOptions) -> dict[str, Any]:  # fmt: skip
    """What both solvers' summaries report: Table 2's loads beside the seed's, the fit's
    nominal numbers, the insert's contact split on the first orientation, the protocol."""
    preloads, finals = (loads / LBF for loads in table2_loads(curves, options))
    curve = curves[0]
    end = options.preload_travel + options.final_travel
    levels = [np.argmin(np.abs(curve.travel - t)) for t in (options.preload_travel, end)]
    return {
        "test": "barrel",
        "bat": spec.name,
        "preload_lbf": float(preloads.mean()),
        "final_load_lbf": float(finals.mean()),
        "orientations_deg": list(options.orientations_deg),
        "preload_by_orientation_lbf": preloads.tolist(),
        "final_load_by_orientation_lbf": finals.tolist(),
        "seed_table2": seed_table2(),
        "interference_in": spec.insert.interference / IN if spec.insert else 0.0,
        "interference_pressure_thin_ring_psi": thin_ring_interference_pressure(spec) / PSI,
        "insert_contact_lbf": {
            "preload": {
                "top": curve.insert_top[levels[0]] / LBF,
                "bottom": curve.insert_bottom[levels[0]] / LBF,
            },
            "final": {
                "top": curve.insert_top[levels[1]] / LBF,
                "bottom": curve.insert_bottom[levels[1]] / LBF,
            },
            "orientation_deg": curve.orientation_deg,
        },  # fmt: skip
        "insert_friction": options.insert_friction,
        "platen_friction": options.platen_friction,
        "platen_diameter_in": options.platen_diameter / IN,
        "platen_from_cap_in": options.distance_from_cap / IN,
    }


def summarise_barrel(result: BarrelResult, wall_seconds: float) -> dict[str, Any]:
    """The summary a person reads: each number's unit is in its key."""
    model, prestress = result.model, result.prestress
    summary = table2_summary(model.spec, list(result.curves), result.options)
    stress = membrane_stress(model, prestress.u)[:, 1] / PSI
    barrel_cells = np.concatenate([model.mesh.cell_sets[p.name] for p in model.spec.parts
                                   if p.name.startswith("barrel")])  # fmt: skip
    cosine = insert_cosines(model, load_axes(result.curves[0].orientation_deg)[0])
    fit_split = halves(prestress.contact_force, cosine)
    summary["insert_contact_lbf"] = {
        "prestress": dict(zip(("top", "bottom"), np.array(fit_split) / LBF, strict=True)),
        **summary["insert_contact_lbf"],
    }
    summary.update({
        "interference_pressure_psi": interference_pressure(model, prestress) / PSI,
        "interference_pressure_range_psi": [
            float(prestress.contact_pressure.min() / PSI),
            float(prestress.contact_pressure.max() / PSI),
        ],
        "prestress_hoop_stress_median_psi": {
            "barrel": float(np.median(stress[barrel_cells])),
            "insert": float(np.median(stress[model.mesh.cell_sets["insert"]])),
        },
        "triangular_solves": int(sum(c.iterations for c in result.curves)),
        "factorisations": int(sum(c.factorisations for c in result.curves)),
        "n_shells": model.mesh.n_cells,
        "n_points": model.mesh.n_points,
        "wall_seconds": wall_seconds,
    })  # fmt: skip
    return summary


def write_curve(folder: Path, result: BarrelResult) -> None:
    """``force_travel.csv`` and ``.png``: the first orientation's force-travel curve."""
    at_fit = result.prestress.contact_force.sum() / 2 / LBF  # zero travel: the fit alone
    write_curve_of(folder, result.curves[0], at_fit, result.options)


def write_curve_of(folder: Path, curve: CompressionCurve, at_fit: float,
                   options: BarrelTestOptions) -> None:  # fmt: skip
    """``force_travel.csv`` and ``.png`` of ``curve``, the insert's halves carrying ``at_fit``
    lbf each at zero travel."""
    columns = {"travel_in": np.r_[0.0, curve.travel / IN],
               "force_lbf": np.r_[0.0, curve.force / LBF],
               "insert_top_lbf": np.r_[at_fit, curve.insert_top / LBF],
               "insert_bottom_lbf": np.r_[at_fit, curve.insert_bottom / LBF]}  # fmt: skip
    write_csv_atomic(folder / "force_travel.csv", columns)
    plot_curve(folder / "force_travel.png", columns, options)


def plot_curve(path: Path, columns: dict[str, np.ndarray], options: BarrelTestOptions) -> None:
    """Force against platen travel with the seed's Table 2 points (F(0.02), F(0.07))."""
    from batball.results.plots import new_figure

    fig, ax = new_figure(figsize=(6, 4))
    ax.plot(columns["travel_in"], columns["force_lbf"], "o-", label="batball")
    travels = [options.preload_travel / IN, (options.preload_travel + options.final_travel) / IN]
    table2 = seed_table2()
    for key, marker, label in (("experiment", "s", "experiment (seed Table 2)"),
                               ("seed_lsdyna", "^", "seed LS-DYNA")):  # fmt: skip
        row = table2[key]
        forces = [row["preload_lbf"], row["preload_lbf"] + row["final_load_lbf"]]
        ax.plot(travels, forces, marker, label=label)
    ax.set_xlabel("platen travel (in)")
    ax.set_ylabel("platen force (lbf)")
    ax.set_title("Barrel compression, 6 in from the end cap")
    ax.legend()
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


def plot_prestress(path: Path, model: BarrelModel, prestress: Prestress) -> None:
    """Von Mises of the mean (membrane) stress, psi, on the unrolled barrel and insert."""
    from matplotlib.collections import PolyCollection

    from batball.results.plots import new_figure

    stress = von_mises(membrane_stress(model, prestress.u)) / PSI
    assert model.spec.insert is not None
    fig, axes = new_figure(2, 1, figsize=(8, 6), sharex=True)
    outer = np.setdiff1d(np.arange(model.mesh.n_cells), model.mesh.cell_sets["insert"])
    for ax, cells, title in ((axes[0], outer, "outer wall"),
                             (axes[1], model.mesh.cell_sets["insert"], "insert")):  # fmt: skip
        corners = model.mesh.points[model.mesh.cells[cells]]
        phi = np.degrees(np.arctan2(corners[..., 2], corners[..., 1]))
        centre = phi.mean(axis=1, keepdims=True)
        phi = centre + (phi - centre + 180.0) % 360.0 - 180.0  # unwrap across the seam
        keep = corners[:, :, 0].mean(axis=1) > model.spec.insert.start - 2 * IN
        polygons = np.stack([corners[keep, :, 0] / IN, phi[keep]], axis=-1)
        collection = PolyCollection(list(polygons), array=stress[cells][keep], cmap="jet")
        ax.add_collection(collection)
        ax.autoscale()
        ax.set_ylabel("angle (deg)")
        ax.set_title(f"{title}: von Mises of the mean stress after the fit (psi)")
        fig.colorbar(collection, ax=ax)
    axes[1].set_xlabel("x from the knob end (in)")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


def run_barrel_test(
    spec: BatSpec,
    *,
    runs_dir: Path,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
    options: BarrelTestOptions | None = None,
    ramp_steps: int = 1,
    reuse: bool = True,
) -> tuple[dict[str, Any], Path]:
    """Pre-stress (or reuse it), compress at every orientation; the summary and the run folder."""
    options = (BarrelTestOptions() if options is None else options).for_bat(spec)
    base = prestress_inputs(spec, circumferential, axial_size, options, ramp_steps)
    folder = run_folder(runs_dir, "barrel", {**base, "protocol": repr(options)})
    cached = load_cached_summary(folder) if reuse else None
    if cached is not None:
        return cached, folder
    start = time.perf_counter()
    model = build_barrel_model(spec, circumferential=circumferential, axial_size=axial_size,
                               penalty_factor=options.penalty_factor)  # fmt: skip
    prestress_folder = run_folder(runs_dir, "prestress", base)
    prestress, reused = obtain_prestress(model, prestress_folder, ramp_steps=ramp_steps,
                                         reuse=reuse)  # fmt: skip
    result = run_barrel_compression(model, prestress, options)
    summary = summarise_barrel(result, time.perf_counter() - start)
    summary.update(run_folder=folder.as_posix(), prestress_folder=prestress_folder.as_posix(),
                   prestress_reused=reused)  # fmt: skip
    write_curve(folder, result)
    plot_prestress(folder / "prestress.png", model, prestress)
    write_summary(folder, summary)
    return summary, folder


def orientation_file(folder: Path, angle: float) -> Path:
    """Where one orientation of the explicit test is kept until the run completes."""
    return folder / f"orientation_{angle:+g}deg.json"


def save_orientation(folder: Path, run: ExplicitCurve) -> None:
    """One finished orientation, atomically (SI arrays), so an interrupted run resumes."""
    c = run.curve
    write_json_atomic(orientation_file(folder, c.orientation_deg), {
        "orientation_deg": c.orientation_deg, "travel_m": c.travel.tolist(),
        "force_n": c.force.tolist(), "insert_top_n": c.insert_top.tolist(),
        "insert_bottom_n": c.insert_bottom.tolist(), "kinetic_ratio": run.kinetic_ratio.tolist(),
        "drift": run.drift.tolist(), "travel_error_m": run.travel_error.tolist(),
        "cycles": run.cycles, "seconds": run.seconds,
    })  # fmt: skip


def load_orientations(folder: Path) -> dict[float, ExplicitCurve]:
    """The orientations an interrupted run of this folder finished, by angle (deg)."""
    done = {}
    for path in sorted(folder.glob("orientation_*deg.json")):
        d = json.loads(path.read_text())
        curve = CompressionCurve(d["orientation_deg"], np.array(d["travel_m"]),
                                 np.array(d["force_n"]), np.array(d["insert_top_n"]),
                                 np.array(d["insert_bottom_n"]), d["cycles"])  # fmt: skip
        done[float(d["orientation_deg"])] = ExplicitCurve(
            curve, np.array(d["kinetic_ratio"]), np.array(d["drift"]),
            np.array(d["travel_error_m"]), d["cycles"], d["seconds"])  # fmt: skip
    return done


#: How the explicit test's shells are named in its summary.
EXPLICIT_SHELLS = {"mitc4": "co-rotational MITC4 shells",
                   "bt": "Belytschko-Tsay shells (hourglass ratio {r:g})"}


def run_explicit_barrel_test(spec: BatSpec, *, runs_dir: Path, options: BarrelTestOptions,
                             explicit: ExplicitBarrelOptions, reuse: bool = True,
                             ) -> tuple[dict[str, Any], Path]:  # fmt: skip
    """The test on the explicit, geometrically nonlinear shells
    (:mod:`batball.lab.barrel_explicit`): fit, squeeze at every orientation; the summary and the
    run folder ``barrel-explicit-<hash>`` (``summary.json``, ``force_travel.csv`` / ``.png``).
    The relaxed fit is kept in ``fit-<hash>`` and reused by later runs of the same bat model
    (:mod:`batball.lab.fit_store`); each orientation is kept as it finishes
    (``orientation_<deg>deg.json``), so an interrupted run resumes after the last one done."""
    options = options.for_bat(spec)
    inputs = {"bat": bat_spec_to_toml_dict(spec), "protocol": repr(options),
              "explicit": repr(explicit), "batball": __version__}  # fmt: skip
    folder = run_folder(runs_dir, "barrel-explicit", inputs)
    cached = load_cached_summary(folder) if reuse else None
    if cached is not None:
        return cached, folder
    start = time.perf_counter()
    state, runs = run_explicit_compression(
        spec, options, explicit, finished=load_orientations(folder),
        record=lambda run: save_orientation(folder, run), store=runs_dir, reuse=reuse,
    )  # fmt: skip
    curves = [r.curve for r in runs]
    summary = table2_summary(spec, curves, options)
    summary.update({
        "solver": "explicit: "
                  + EXPLICIT_SHELLS[explicit.shell].format(r=explicit.hourglass_ratio)
                  + ", dynamic relaxation, geometrically nonlinear",
        "shell": explicit.shell,
        "interference_pressure_psi": state.fit_pressure / PSI,
        "prestress_kinetic_ratio": state.prestress_kinetic_ratio,
        "prestress_reused": state.fit_reused,
        "settling": {
            "largest_kinetic_ratio": float(max(r.kinetic_ratio.max() for r in runs)),
            "largest_force_drift": float(max(np.abs(r.drift).max() for r in runs)),
            "largest_travel_error_in": float(max(np.abs(r.travel_error).max() for r in runs) / IN),
        },
        "cycles": int(sum(r.cycles for r in runs)),
        "time_step_s": state.bat.stable_step,
        "n_shells": int(state.bat.cells.shape[0]),
        "n_points": int(state.points.shape[0]),
        "wall_seconds": time.perf_counter() - start,
    })  # fmt: skip
    write_curve_of(folder, curves[0], state.fit_pressure_force / 2 / LBF, options)
    summary["run_folder"] = folder.as_posix()
    write_summary(folder, summary)
    return summary, folder
