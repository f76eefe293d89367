"""A shaded picture of the bat's shell mesh, coloured by part.

The quads are projected orthographically (a small painter's-algorithm renderer on a 2-D
``PolyCollection``: exact aspect ratio, dimensioned in inches, fast for 20,000 quads). Each quad is
shaded by the angle between its normal and the light. The lower panel zooms on the barrel with the
front half of the outer wall cut away over the insert, so the double wall shows.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from batball.mesh.shell import ShellMesh, quad_normals
from batball.results.store import atomic_path
from batball.specs.bat import BatSpec
from batball.units import IN

#: Colours by part-name prefix: handle blues, taper greens, barrel oranges, insert gold.
PART_COLOURS: dict[str, tuple[str, ...]] = {
    "knob": ("#6a3d9a",),
    "handle": ("#1f78b4", "#4a9bd1", "#a6cee3"),
    "taper": ("#33a02c", "#8fd175"),
    "barrel": ("#e66101", "#fdb863", "#d94801"),
    "endcap": ("#7f3b08",),
    "insert": ("#f1c40f",),
}
_FALLBACK = ("#999999", "#666666")


def part_colours(names: list[str]) -> dict[str, str]:
    """A colour per cell-set name, by name prefix (``handle-2`` -> the second handle blue)."""
    used: dict[str, int] = {}
    colours = {}
    for name in names:
        prefix = name.split("-")[0]
        palette = PART_COLOURS.get(prefix, _FALLBACK)
        colours[name] = palette[used.get(prefix, 0) % len(palette)]
        used[prefix] = used.get(prefix, 0) + 1
    return colours


def camera_basis(yaw_deg: float, pitch_deg: float) -> np.ndarray:
    """Rows: screen right, screen up, toward the viewer, shape (3, 3); yaw about y, pitch about x.

    At yaw = pitch = 0 the viewer looks down -z: the bat axis (x) runs left to right, y is up.
    """
    yaw, pitch = np.radians(yaw_deg), np.radians(pitch_deg)
    rotate_y = np.array([[np.cos(yaw), 0, np.sin(yaw)], [0, 1, 0], [-np.sin(yaw), 0, np.cos(yaw)]])
    rotate_x = np.array(
        [[1, 0, 0], [0, np.cos(pitch), -np.sin(pitch)], [0, np.sin(pitch), np.cos(pitch)]]
    )
    return rotate_x @ rotate_y


def shaded_faces(
    mesh: ShellMesh, colours: np.ndarray, basis: np.ndarray, keep: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Screen polygons, shaded RGBA colours and depths of the kept quads, far to near.

    Args:
        mesh: the shells, m.
        colours: RGB per cell, shape (n_cells, 3) in [0, 1].
        basis: :func:`camera_basis`, shape (3, 3).
        keep: which cells to draw, shape (n_cells,), bool.

    Returns:
        polygons (n_kept, 4, 2) in inches, colours (n_kept, 4) RGBA, order of drawing applied.
    """
    view = mesh.points @ basis.T / IN  # (n_points, 3): right, up, depth
    normals = quad_normals(mesh.points, mesh.cells) @ basis.T
    facing = normals[:, 2]
    light = np.array([-0.35, 0.55, 0.76])
    lit = np.abs(normals @ light)
    shade = np.where(facing >= 0.0, 0.35 + 0.65 * lit, 0.25 + 0.35 * lit)  # inside walls darker
    rgba = np.column_stack([colours * shade[:, None], np.ones(mesh.n_cells)])
    depth = view[mesh.cells, 2].mean(axis=1)
    order = np.flatnonzero(keep)[np.argsort(depth[keep], kind="stable")]
    return view[mesh.cells[order]][..., :2], rgba[order], depth[order]


def cell_colours(mesh: ShellMesh) -> tuple[np.ndarray, dict[str, str]]:
    """RGB per cell (n_cells, 3) from its cell set, and the colour of each set."""
    from matplotlib.colors import to_rgb

    named = part_colours(list(mesh.cell_sets))
    colours = np.full((mesh.n_cells, 3), 0.6)
    for name, cells in mesh.cell_sets.items():
        colours[cells] = to_rgb(named[name])
    return colours, named


def _draw(ax: Any, mesh: ShellMesh, colours: np.ndarray, keep: np.ndarray, edges: bool) -> None:
    """Draw the kept quads on ``ax`` (screen coordinates in inches)."""
    from matplotlib.collections import PolyCollection

    polygons, rgba, _ = shaded_faces(mesh, colours, camera_basis(0.0, 20.0), keep)
    collection = PolyCollection(
        list(polygons), facecolors=rgba, edgecolors=(0.1, 0.1, 0.1, 0.35) if edges else rgba,
        linewidths=0.15 if edges else 0.3,
    )  # fmt: skip
    ax.add_collection(collection)
    ax.set_aspect("equal")
    ax.autoscale_view()


def plot_bat_mesh(path: Path, spec: BatSpec, mesh: ShellMesh, *, title: str = "") -> None:
    """The whole bat (top) and the barrel cut open over the insert (bottom), as PNG.

    Args:
        path: the PNG to write (atomically).
        spec: the bat (for the insert's span).
        mesh: its shell mesh with one cell set per part and ``"insert"``.
        title: figure title; the bat's name and element count by default.
    """
    from matplotlib.patches import Patch

    from batball.results.plots import new_figure

    colours, named = cell_colours(mesh)
    fig, (top, bottom) = new_figure(2, 1, figsize=(12.0, 4.9), dpi=150,
                                      gridspec_kw={"height_ratios": [1.0, 1.5]})  # fmt: skip
    _draw(top, mesh, colours, np.ones(mesh.n_cells, dtype=bool), edges=False)
    top.set_title(title or f"{spec.name}: {mesh.n_cells:,} four-node shells, coloured by part")
    bottom.set_title("barrel, front half of the outer wall cut away over the insert (mesh edges)")
    _draw(bottom, mesh, colours, barrel_cutaway(spec, mesh), edges=True)
    bottom.set_xlim(spec.length / IN - 15.0, spec.length / IN + 0.3)
    for ax in (top, bottom):
        ax.set_xlabel("x from the knob end (in)")
        ax.set_ylabel("in")
        ax.grid(alpha=0.2)
    handles = [Patch(color=c, label=name) for name, c in named.items()]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    with atomic_path(path) as tmp:
        fig.savefig(tmp)


def barrel_cutaway(spec: BatSpec, mesh: ShellMesh) -> np.ndarray:
    """Cells to draw in the zoom: all but the outer wall's front half (z > 0) over the insert."""
    keep = np.ones(mesh.n_cells, dtype=bool)
    if spec.insert is None:
        return keep
    centres = mesh.points[mesh.cells].mean(axis=1)
    outer = np.ones(mesh.n_cells, dtype=bool)
    outer[mesh.cell_sets["insert"]] = False
    window = (centres[:, 0] > spec.insert.start) & (centres[:, 0] < spec.insert.end)
    keep[outer & window & (centres[:, 2] > 0.0)] = False
    return keep
