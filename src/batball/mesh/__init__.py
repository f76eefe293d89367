"""Meshes: the :class:`Mesh` container, hex8 geometry, the O-grid ball, and quality numbers."""

from batball.mesh.ball import make_ball_mesh
from batball.mesh.box import make_box_mesh
from batball.mesh.hexa import (
    boundary_faces,
    characteristic_lengths,
    hex_volumes,
    scaled_jacobians,
    surface_point_ids,
)
from batball.mesh.mesh import Mesh
from batball.mesh.quality import MeshQuality, mesh_quality

__all__ = [
    "Mesh",
    "MeshQuality",
    "boundary_faces",
    "characteristic_lengths",
    "hex_volumes",
    "make_ball_mesh",
    "make_box_mesh",
    "mesh_quality",
    "scaled_jacobians",
    "surface_point_ids",
]
