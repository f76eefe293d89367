"""Run the mass-properties test (ASTM F2398) into the results store, summarised with units.

``runs/props-<hash>/`` holds ``summary.json``, ``bat.toml`` (the bat as run) and ``bat.png`` (the
shell mesh coloured by part). Runs with the same inputs are reused.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from batball.lab.props import DEFAULT_PIVOT, MassProperties, bat_mass_properties
from batball.mesh.bat import DEFAULT_AXIAL_SIZE, DEFAULT_CIRCUMFERENTIAL
from batball.mesh.shell import ShellMesh, shell_quality
from batball.results.store import run_folder, run_or_reuse, write_summary, write_text_atomic
from batball.specs.bat import BatSpec, bat_spec_to_toml_dict
from batball.units import IN, OZ, OZ_IN2
from batball.version import __version__


def props_inputs(
    spec: BatSpec, *, circumferential: int, axial_size: float, pivot: float
) -> dict[str, Any]:
    """Everything that determines a props run, JSON-able (the key of its run folder)."""
    return {
        "bat": bat_spec_to_toml_dict(spec),
        "mesh": {"circumferential": circumferential, "axial_size_m": axial_size},
        "pivot_m": pivot,
        "batball": __version__,
    }


def summarise_props(
    spec: BatSpec, props: MassProperties, mesh: ShellMesh, wall_seconds: float
) -> dict[str, Any]:
    """The summary a person reads: each number's unit is in its key."""
    quality = shell_quality(mesh)
    return {
        "test": "props",
        "bat": spec.name,
        "weight_oz": props.mass / OZ,
        "balance_point_in": props.balance_point / IN,
        "moi_pivot_oz_in2": props.moi_pivot / OZ_IN2,
        "moi_cm_oz_in2": props.moi_cm / OZ_IN2,
        "pivot_in": props.pivot / IN,
        "length_in": spec.length / IN,
        "n_shells": mesh.n_cells,
        "n_points": mesh.n_points,
        "min_area_in2": quality.min_area / IN**2,
        "max_aspect_ratio": quality.max_aspect_ratio,
        "min_scaled_jacobian": quality.min_scaled_jacobian,
        "wall_seconds": wall_seconds,
    }


def run_props_test(
    spec: BatSpec,
    *,
    runs_dir: Path,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
    pivot: float = DEFAULT_PIVOT,
    reuse: bool = True,
) -> tuple[dict[str, Any], Path]:
    """Compute (or reuse) a bat's mass properties; returns the summary and the run folder."""
    import tomli_w

    from batball.results.bat_figures import plot_bat_mesh

    inputs = props_inputs(spec, circumferential=circumferential, axial_size=axial_size,
                          pivot=pivot)  # fmt: skip
    folder = run_folder(runs_dir, "props", inputs)

    def write(result: Any, summary: dict[str, Any]) -> None:
        write_text_atomic(folder / "bat.toml", tomli_w.dumps(inputs["bat"]))
        plot_bat_mesh(folder / "bat.png", spec, result[1])
        write_summary(folder, summary)

    return run_or_reuse(
        folder, reuse,
        lambda: bat_mass_properties(spec, circumferential=circumferential,
                                    axial_size=axial_size, pivot=pivot),
        lambda result, seconds: summarise_props(spec, result[0], result[1], seconds), write,
    )  # fmt: skip
