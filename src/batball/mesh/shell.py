"""Four-node shell meshes: the :class:`ShellMesh` container and quad geometry and quality.

Quads use the LS-DYNA ``*ELEMENT_SHELL`` / VTK_QUAD node order: nodes 1-2-3-4 counter-clockwise
seen from the side the normal points to; the normal is (x3 - x1) x (x4 - x2). The material a-axis
of a layered shell with AOPT = 0 follows edge 1-2 (physics.md section 6.5).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from batball.mesh.mesh import _frozen_sets


@dataclass(frozen=True)
class ShellMesh:
    """An unstructured four-node shell (quad) mesh on a mid-surface.

    Attributes:
        points: node coordinates, shape (n_points, 3), m, float64, C-contiguous.
        cells: quad connectivity, shape (n_cells, 4), int64 zero-based node indices in LS-DYNA/VTK
            order, C-contiguous.
        point_sets: named node index arrays, each shape (n,), int64.
        cell_sets: named cell index arrays, each shape (n,), int64.
    """

    points: np.ndarray
    cells: np.ndarray
    point_sets: Mapping[str, np.ndarray] = field(default_factory=dict)
    cell_sets: Mapping[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        points = np.ascontiguousarray(self.points, dtype=np.float64)
        cells = np.ascontiguousarray(self.cells, dtype=np.int64)
        if points.ndim != 2 or points.shape[1] != 3:
            raise ValueError(f"points must have shape (n_points, 3), got {points.shape}")
        if cells.ndim != 2 or cells.shape[1] != 4:
            raise ValueError(f"cells must have shape (n_cells, 4), got {cells.shape}")
        if cells.size and (cells.min() < 0 or cells.max() >= points.shape[0]):
            raise ValueError("cells refer to nodes outside 0 .. n_points - 1")
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "cells", cells)
        object.__setattr__(self, "point_sets", _frozen_sets(self.point_sets))
        object.__setattr__(self, "cell_sets", _frozen_sets(self.cell_sets))

    @property
    def n_points(self) -> int:
        """Number of nodes."""
        return int(self.points.shape[0])

    @property
    def n_cells(self) -> int:
        """Number of quads."""
        return int(self.cells.shape[0])


def quad_areas(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Areas of quads, half the norm of the diagonals' cross product (exact for planar quads).

    Args:
        points: (n_points, 3), m.
        cells: (n_cells, 4) node indices.

    Returns:
        (n_cells,) areas, m^2.
    """
    x = points[cells]
    return 0.5 * np.linalg.norm(np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]), axis=1)


def quad_normals(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Unit normals (x3 - x1) x (x4 - x2) / |...| of quads, shape (n_cells, 3)."""
    x = points[cells]
    normal = np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])
    return normal / np.linalg.norm(normal, axis=1, keepdims=True)


def quad_edge_lengths(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Lengths of edges 1-2, 2-3, 3-4, 4-1, shape (n_cells, 4), m."""
    x = points[cells]
    return np.linalg.norm(np.roll(x, -1, axis=1) - x, axis=2)


def quad_aspect_ratios(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Longest over shortest edge of each quad, shape (n_cells,) (1 for a square)."""
    edges = quad_edge_lengths(points, cells)
    return edges.max(axis=1) / edges.min(axis=1)


def quad_scaled_jacobians(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Smallest corner sine of each quad, measured against its normal, shape (n_cells,).

    The Verdict quad scaled Jacobian: 1 for a rectangle, <= 0 for a folded or inverted corner.
    """
    x = points[cells]
    normal = quad_normals(points, cells)
    forward = np.roll(x, -1, axis=1) - x  # edge from corner i to i+1
    backward = np.roll(x, 1, axis=1) - x  # edge from corner i to i-1
    corner = np.einsum("cij,cj->ci", np.cross(forward, backward), normal)
    lengths = np.linalg.norm(forward, axis=2) * np.linalg.norm(backward, axis=2)
    return np.min(corner / lengths, axis=1)


@dataclass(frozen=True)
class ShellQuality:
    """Size and quality of a shell mesh.

    Attributes:
        n_points: number of nodes.
        n_cells: number of quads.
        area: total area, m^2.
        min_area: smallest quad area, m^2 (0 for a degenerate quad).
        max_aspect_ratio: largest longest/shortest edge ratio.
        min_scaled_jacobian: smallest corner sine (<= 0: folded or inverted).
        min_edge: shortest edge, m (sets the explicit time step of a shell).
    """

    n_points: int
    n_cells: int
    area: float
    min_area: float
    max_aspect_ratio: float
    min_scaled_jacobian: float
    min_edge: float


def shell_quality(mesh: ShellMesh) -> ShellQuality:
    """Size and quality numbers of a shell mesh (see :class:`ShellQuality`)."""
    areas = quad_areas(mesh.points, mesh.cells)
    return ShellQuality(
        n_points=mesh.n_points,
        n_cells=mesh.n_cells,
        area=float(areas.sum()),
        min_area=float(areas.min()),
        max_aspect_ratio=float(quad_aspect_ratios(mesh.points, mesh.cells).max()),
        min_scaled_jacobian=float(quad_scaled_jacobians(mesh.points, mesh.cells).min()),
        min_edge=float(quad_edge_lengths(mesh.points, mesh.cells).min()),
    )
