"""Mesh quality summary: the numbers that decide whether an explicit run is stable and cheap."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from batball.mesh.hexa import characteristic_lengths, hex_volumes, scaled_jacobians
from batball.mesh.mesh import Mesh
from batball.units import IN


@dataclass(frozen=True)
class MeshQuality:
    """Size and quality of a hexahedral mesh.

    Attributes:
        n_points: number of nodes.
        n_cells: number of hexahedra.
        min_scaled_jacobian: smallest Verdict scaled Jacobian, dimensionless (1 = cube).
        min_characteristic_length: smallest LS-DYNA solid time-step length, m.
        min_volume: smallest cell volume, m^3 (negative if any cell is inverted).
        volume: total volume, m^3.
    """

    n_points: int
    n_cells: int
    min_scaled_jacobian: float
    min_characteristic_length: float
    min_volume: float
    volume: float

    def describe(self) -> str:
        """One human-readable line, lengths in inches."""
        length_in = self.min_characteristic_length / IN
        return (
            f"{self.n_cells} hexes, {self.n_points} nodes, "
            f"min scaled Jacobian {self.min_scaled_jacobian:.2f}, "
            f"smallest length {length_in:.3f} in"
        )


def mesh_quality(mesh: Mesh) -> MeshQuality:
    """Size and quality numbers of a hexahedral mesh (see :class:`MeshQuality`)."""
    volumes = hex_volumes(mesh.points, mesh.cells)
    return MeshQuality(
        n_points=mesh.n_points,
        n_cells=mesh.n_cells,
        min_scaled_jacobian=float(np.min(scaled_jacobians(mesh.points, mesh.cells))),
        min_characteristic_length=float(np.min(characteristic_lengths(mesh.points, mesh.cells))),
        min_volume=float(np.min(volumes)),
        volume=float(np.sum(volumes)),
    )
