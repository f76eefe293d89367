"""The mesh container shared by every layer: meshio's names and array orientation.

Hexahedra use the LS-DYNA ``*ELEMENT_SOLID`` / VTK_HEXAHEDRON node order: nodes 1-2-3-4 form the
bottom face, counter-clockwise seen from the top (so the volume is positive), and nodes 5-6-7-8
the top face, node 4+i above node i.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import ClassVar

import numpy as np


def _frozen_sets(sets: Mapping[str, np.ndarray]) -> Mapping[str, np.ndarray]:
    """Contiguous int64 copies of named index sets, behind a read-only mapping."""
    return MappingProxyType(
        {name: np.ascontiguousarray(ids, dtype=np.int64) for name, ids in sets.items()}
    )


@dataclass(frozen=True)
class CellMesh:
    """Points, one kind of cell, and named sets, checked and stored contiguous and read-only.

    Subclasses fix the cell kind with ``NODES_PER_CELL``.

    Attributes:
        points: node coordinates, shape (n_points, 3), m, float64, C-contiguous.
        cells: connectivity, shape (n_cells, NODES_PER_CELL), int64 zero-based node indices in
            LS-DYNA/VTK order, C-contiguous.
        point_sets: named node index arrays, each shape (n,), int64.
        cell_sets: named cell index arrays, each shape (n,), int64.
    """

    NODES_PER_CELL: ClassVar[int] = 0

    points: np.ndarray
    cells: np.ndarray
    point_sets: Mapping[str, np.ndarray] = field(default_factory=dict)
    cell_sets: Mapping[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        points = np.ascontiguousarray(self.points, dtype=np.float64)
        cells = np.ascontiguousarray(self.cells, dtype=np.int64)
        per_cell = self.NODES_PER_CELL
        if points.ndim != 2 or points.shape[1] != 3:
            raise ValueError(f"points must have shape (n_points, 3), got {points.shape}")
        if cells.ndim != 2 or cells.shape[1] != per_cell:
            raise ValueError(f"cells must have shape (n_cells, {per_cell}), got {cells.shape}")
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
        """Number of cells."""
        return int(self.cells.shape[0])


@dataclass(frozen=True)
class Mesh(CellMesh):
    """An unstructured hexahedral mesh: ``cells`` has shape (n_cells, 8)."""

    NODES_PER_CELL: ClassVar[int] = 8
