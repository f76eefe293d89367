"""Run the bat's free-free modal test into the results store, summarised with units.

``runs/modal-<hash>/`` holds ``summary.json`` (every mode's frequency and label, the first two
bending and hoop frequencies beside the seed's Table 3), ``modes.png`` (the four picked shapes)
and ``modes.vtu`` (all mode shapes as point data, for ParaView). Runs with the same inputs are
reused.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from batball.lab.modal import BatModes, bat_modes
from batball.mesh.bat import DEFAULT_AXIAL_SIZE, DEFAULT_CIRCUMFERENTIAL
from batball.results.store import atomic_path, run_folder, run_or_reuse, write_summary
from batball.specs.bat import BatSpec, bat_spec_to_toml_dict
from batball.units import IN
from batball.version import __version__


def seed_table3() -> dict[str, dict[str, list[float]]]:
    """Seed Table 3 (Hz), experiment and the seed's LS-DYNA model, from ``specs/seed.py``."""
    from batball.specs.seed import load_seed_tables

    m = load_seed_tables().modal
    return {
        "bending_hz": {"experiment": [m.bending_1_exp, m.bending_2_exp],
                       "seed_lsdyna": [m.bending_1_fe, m.bending_2_fe]},
        "hoop_hz": {"experiment": [m.hoop_1_exp, m.hoop_2_exp],
                    "seed_lsdyna": [m.hoop_1_fe, m.hoop_2_fe]},
    }  # fmt: skip


#: The summary's description of each insert model.
INSERT_DESCRIPTIONS = {
    "bonded": "bonded to the barrel (tied rigidly)",
    "contact": "pre-stressed interference-fit contact: radial springs, frictionless sliding",
}


def summarise_modes(spec: BatSpec, modes: BatModes, wall_seconds: float, *,
                    insert: str = "contact") -> dict[str, Any]:  # fmt: skip
    """The summary a person reads: each number's unit is in its key."""
    bending, hoop = modes.first("bending"), modes.first("hoop")
    return {
        "test": "modal",
        "bat": spec.name,
        "insert": INSERT_DESCRIPTIONS[insert],
        "bending_hz": [float(modes.frequencies[i]) for i in bending],
        "hoop_hz": [float(modes.frequencies[i]) for i in hoop],
        "seed_table3": seed_table3(),
        "n_modes": int(modes.frequencies.size),
        "n_rigid": int(sum(label == "rigid" for label in modes.labels)),
        "frequencies_hz": [float(f) for f in modes.frequencies],
        "labels": list(modes.labels),
        "n_shells": modes.mesh.n_cells,
        "n_points": modes.mesh.n_points,
        "wall_seconds": wall_seconds,
    }


def write_vtu(path: Path, modes: BatModes) -> None:
    """All mode shapes as VTK point data ``mode_<k>_<f>Hz`` (displacement, 3 components)."""
    import meshio

    data = {f"mode_{k:02d}_{f:.0f}Hz": modes.shapes[:, :3, k]
            for k, f in enumerate(modes.frequencies)}  # fmt: skip
    mesh = meshio.Mesh(modes.mesh.points, [("quad", modes.mesh.cells)], point_data=data)
    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format="vtu")


def plot_modes(path: Path, modes: BatModes) -> None:
    """The four picked shapes: deformed outer wall seen from the side (x-y), with the frequency."""
    from batball.results.plots import new_figure

    picked = [("bending", i) for i in modes.first("bending")] + [
        ("hoop", i) for i in modes.first("hoop")
    ]
    n_outer = modes.mesh.point_sets["outer"].size
    points = modes.mesh.points[:n_outer]
    fig, axes = new_figure(len(picked), 1, figsize=(9, 2.2 * len(picked)), squeeze=False)
    for ax, (label, index) in zip(axes[:, 0], picked, strict=True):
        u = modes.shapes[:n_outer, :3, index]
        deformed = points + 0.1 * u / np.abs(u).max()  # 0.1 m peak displacement
        ax.scatter(deformed[:, 0] / IN, deformed[:, 1] / IN, s=0.2, c="tab:red")
        ax.scatter(points[:, 0] / IN, points[:, 1] / IN, s=0.1, c="0.7")
        ax.set_title(f"{label} {modes.frequencies[index]:.0f} Hz")
        ax.set_ylabel("y (in)")
    axes[-1, 0].set_xlabel("x from the knob end (in)")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


def run_modal_test(
    spec: BatSpec,
    *,
    runs_dir: Path,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
    n_modes: int = 30,
    reuse: bool = True,
    insert: str = "contact",
) -> tuple[dict[str, Any], Path]:
    """Compute (or reuse) a bat's free-free modes; returns the summary and the run folder.
    ``insert``: "bonded" or "contact" (:func:`batball.lab.modal.bat_modes`)."""
    inputs = {
        "bat": bat_spec_to_toml_dict(spec),
        "mesh": {"circumferential": circumferential, "axial_size_m": axial_size},
        "n_modes": n_modes,
        "batball": __version__,
    }
    if insert != "bonded":  # the bonded runs keep their store keys
        inputs["insert"] = insert
    folder = run_folder(runs_dir, "modal", inputs)

    def write(modes: Any, summary: dict[str, Any]) -> None:
        plot_modes(folder / "modes.png", modes)
        write_vtu(folder / "modes.vtu", modes)
        write_summary(folder, summary)

    return run_or_reuse(
        folder, reuse,
        lambda: bat_modes(spec, circumferential=circumferential, axial_size=axial_size,
                          n_modes=n_modes, insert=insert),
        lambda modes, seconds: summarise_modes(spec, modes, seconds, insert=insert), write,
    )  # fmt: skip
