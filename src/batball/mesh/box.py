"""Structured hexahedral box: bars and blocks for verification cases."""

from __future__ import annotations

import numpy as np

from batball.mesh.ball import _hex_cells
from batball.mesh.mesh import Mesh


def make_box_mesh(lengths: tuple[float, float, float], divisions: tuple[int, int, int]) -> Mesh:
    """A box [0, Lx] x [0, Ly] x [0, Lz] split into nx x ny x nz equal hexes.

    Args:
        lengths: (Lx, Ly, Lz) [m]; divisions: (nx, ny, nz).

    Returns:
        The mesh, with point sets "x0" and "x1" (the nodes on the faces x = 0 and x = Lx).
    """
    nx, ny, nz = divisions
    axes = [np.linspace(0.0, length, n + 1) for length, n in zip(lengths, divisions, strict=True)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    ids = np.arange((nx + 1) * (ny + 1) * (nz + 1)).reshape(nx + 1, ny + 1, nz + 1)
    points = grid.reshape(-1, 3)
    return Mesh(
        points=points,
        cells=_hex_cells(ids),
        point_sets={"x0": ids[0].ravel(), "x1": ids[-1].ravel()},
    )
