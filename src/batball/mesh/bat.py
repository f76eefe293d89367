"""The bat's shell mesh: four-node quads on the mid-surface of the revolved profile.

Axes: x is the bat axis from the knob end (x = 0) to the end cap (x = length); y, z span the
cross-section, a node at angle phi lies at (x, r cos phi, r sin phi). Each quad's edge 1-2 runs
along +x, so the material a-axis of every ply follows the bat axis as the seed's AOPT = 3 does,
and edge 1-4 runs along -phi, so the normal points outward (from the bore to the outer surface),
the direction in which layups are listed (inner ply first).

The outer shell lies at r = R_outer(x) - t(x)/2, with t the wall of the part at x (the mean of the
two parts at a part boundary). The insert is a separate surface with its own nodes, at
r = R_insert_outer - t_insert/2, where R_insert_outer is the barrel's bore radius plus the
interference: the overlap the interference-fit pre-stress removes.
"""

from __future__ import annotations

import math

import numpy as np

from batball.mesh.shell import ShellMesh
from batball.specs.bat import BatSpec
from batball.units import IN

#: Quads around the circumference and axial element size that give about the seed's 20,494 shells
#: on the default bat (48 x 0.1 in: 20,688 quads; barrel quads 0.147 x 0.1 in).
DEFAULT_CIRCUMFERENTIAL = 48
DEFAULT_AXIAL_SIZE = 0.1 * IN


def make_bat_mesh(
    spec: BatSpec,
    *,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
) -> ShellMesh:
    """Quad shells of the bat's outer wall (one cell set per part) and of its insert.

    Args:
        spec: the bat.
        circumferential: quads around the circumference (>= 3).
        axial_size: largest element length along the meridian, m (> 0).

    Returns:
        A :class:`ShellMesh`; ``cell_sets`` has one entry per part name plus ``"insert"`` (when
        the bat has one); ``point_sets`` has ``"outer"`` and ``"insert"`` (the nodes of each
        surface) and ``"knob_end"``, ``"cap_end"`` (the end rings of the outer surface).

    Raises:
        ValueError: ``circumferential`` < 3 or ``axial_size`` <= 0.
    """
    if circumferential < 3 or not (math.isfinite(axial_size) and axial_size > 0.0):
        raise ValueError(f"need circumferential >= 3 and axial_size > 0, got "
                         f"{circumferential}, {axial_size}")  # fmt: skip
    x = outer_ring_positions(spec, axial_size=axial_size)
    radius = outer_ring_radii(spec, x)
    points, cells = revolve_rings(x, radius, circumferential=circumferential)
    cell_sets = part_cell_sets(spec, x, circumferential=circumferential)
    point_sets = {
        "outer": np.arange(points.shape[0]),
        "knob_end": np.arange(circumferential),
        "cap_end": np.arange(points.shape[0] - circumferential, points.shape[0]),
    }
    if spec.insert is not None:
        insert_points, insert_cells = insert_surface(spec, circumferential, axial_size)
        offset = points.shape[0]
        cell_sets["insert"] = np.arange(cells.shape[0], cells.shape[0] + insert_cells.shape[0])
        point_sets["insert"] = np.arange(offset, offset + insert_points.shape[0])
        points = np.vstack([points, insert_points])
        cells = np.vstack([cells, insert_cells + offset])
    return ShellMesh(points=points, cells=cells, point_sets=point_sets, cell_sets=cell_sets)


def outer_rings(mesh: ShellMesh) -> np.ndarray:
    """The outer surface's nodes ring by ring, (n_rings, circumferential): x increasing along
    axis 0, angle 2 pi j / circumferential along axis 1 (:func:`make_bat_mesh`'s numbering)."""
    return mesh.point_sets["outer"].reshape(-1, mesh.point_sets["knob_end"].size)


def part_cell_sets(spec: BatSpec, x: np.ndarray, *, circumferential: int) -> dict[str, np.ndarray]:
    """Cell indices of each part on the outer surface (rings ``x``, ``circumferential`` quads each).

    Returns:
        ``{part name: cell indices}``, each shape (n,), int64; band i holds cells
        ``i * circumferential ... (i + 1) * circumferential - 1``.
    """
    band_middle = 0.5 * (x[:-1] + x[1:])
    starts = np.array([part.start for part in spec.parts])
    cell_part = np.repeat(np.searchsorted(starts, band_middle, side="right") - 1, circumferential)
    return {p.name: np.flatnonzero(cell_part == k) for k, p in enumerate(spec.parts)}


def subdivide(breaks: np.ndarray, meridian: np.ndarray, *, axial_size: float) -> np.ndarray:
    """Axial positions of the rings: each interval between ``breaks`` cut into equal pieces.

    Args:
        breaks: interval ends, shape (n_breaks,), m, increasing.
        meridian: meridian (slant) length of each interval, shape (n_breaks - 1,), m.
        axial_size: largest piece along the meridian, m.

    Returns:
        Ring positions, shape (n_rings,), m, containing every break exactly.
    """
    counts = np.maximum(1, np.ceil(meridian / axial_size - 1e-9).astype(np.int64))
    pieces = [
        np.linspace(a, b, n, endpoint=False)
        for a, b, n in zip(breaks[:-1], breaks[1:], counts, strict=True)
    ]
    return np.concatenate([*pieces, breaks[-1:]])


def outer_ring_positions(spec: BatSpec, *, axial_size: float) -> np.ndarray:
    """Rings of the outer surface: at every profile station, part boundary and insert end.

    Returns:
        Axial positions, shape (n_rings,), m, increasing from 0 to the bat's length.
    """
    breaks = [x for x, _ in spec.stations] + [p.start for p in spec.parts]
    if spec.insert is not None:
        breaks += [spec.insert.start, spec.insert.end]
    breaks_array = np.unique(np.array(breaks + [spec.length]))
    radius = spec.outer_radius(breaks_array)
    meridian = np.hypot(np.diff(breaks_array), np.diff(radius))
    return subdivide(breaks_array, meridian, axial_size=axial_size)


def outer_ring_radii(spec: BatSpec, x: np.ndarray) -> np.ndarray:
    """Mid-surface radius at rings ``x`` (m): R_outer - t/2, t averaged over parts meeting at x.

    Args:
        spec: the bat.
        x: ring positions, shape (n_rings,), m; part boundaries must appear exactly.

    Returns:
        Radii, shape (n_rings,), m.
    """
    starts = np.array([part.start for part in spec.parts])
    walls = np.array([spec.laminate(part.layup).thickness for part in spec.parts])
    last = len(spec.parts) - 1
    after = np.clip(np.searchsorted(starts, x, side="right") - 1, 0, last)
    before = np.clip(np.searchsorted(starts, x, side="left") - 1, 0, last)
    return spec.outer_radius(x) - 0.25 * (walls[after] + walls[before])


def insert_surface(
    spec: BatSpec, circumferential: int, axial_size: float
) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 3) and quads (n_cells, 4) of the insert's mid-surface (own node numbering)."""
    insert = spec.insert
    assert insert is not None
    breaks = np.array([insert.start, insert.end])
    x = subdivide(breaks, np.diff(breaks), axial_size=axial_size)
    wall = spec.laminate(insert.layup).thickness
    radius = np.full(x.shape, spec.insert_outer_radius() - 0.5 * wall)
    return revolve_rings(x, radius, circumferential=circumferential)


def revolve_rings(
    x: np.ndarray, radius: np.ndarray, *, circumferential: int
) -> tuple[np.ndarray, np.ndarray]:
    """Revolve rings (x_i, r_i) about the x axis into quads with edge 1-2 along +x, normal out.

    Args:
        x: ring positions, shape (n_rings,), m.
        radius: ring radii, shape (n_rings,), m.
        circumferential: nodes (and quads) around each ring.

    Returns:
        points (n_rings * circumferential, 3), m, node ``i * circumferential + j`` on ring i at
        angle 2 pi j / circumferential; cells ((n_rings - 1) * circumferential, 4).
    """
    phi = 2.0 * np.pi * np.arange(circumferential) / circumferential
    points = np.empty((x.size, circumferential, 3))
    points[..., 0] = x[:, None]
    points[..., 1] = radius[:, None] * np.cos(phi)
    points[..., 2] = radius[:, None] * np.sin(phi)
    ring = np.arange(x.size - 1)[:, None] * circumferential
    j = np.arange(circumferential)[None, :]
    j_next = (j + 1) % circumferential
    # 1 -> 2 along +x at angle phi_{j+1}; 4 at phi_j: edge 1-4 along -phi, normal outward.
    cells = np.stack(
        [ring + j_next, ring + circumferential + j_next, ring + circumferential + j, ring + j],
        axis=-1,
    )
    return points.reshape(-1, 3), cells.reshape(-1, 4)
