"""Four-node shell meshes: the :class:`ShellMesh` container and quad geometry and quality.

Quads use the LS-DYNA ``*ELEMENT_SHELL`` / VTK_QUAD node order: nodes 1-2-3-4 counter-clockwise
seen from the side the normal points to; the normal is (x3 - x1) x (x4 - x2). The material a-axis
of a layered shell with AOPT = 0 follows edge 1-2 (docs/physics.md section 6.5).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from batball.mesh.mesh import CellMesh


@dataclass(frozen=True)
class ShellMesh(CellMesh):
    """An unstructured four-node shell (quad) mesh on a mid-surface: ``cells`` is (n_cells, 4)."""

    NODES_PER_CELL: ClassVar[int] = 4


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
