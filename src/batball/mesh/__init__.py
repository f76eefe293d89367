"""Meshes: the hex :class:`Mesh` and quad :class:`ShellMesh` containers, the O-grid ball, the bat's
shells, geometry and quality numbers."""

from batball.mesh.ball import make_ball_mesh
from batball.mesh.bat import make_bat_mesh
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
from batball.mesh.shell import (
    ShellMesh,
    ShellQuality,
    quad_areas,
    quad_aspect_ratios,
    quad_normals,
    quad_scaled_jacobians,
    shell_quality,
)

__all__ = [
    "Mesh",
    "MeshQuality",
    "ShellMesh",
    "ShellQuality",
    "boundary_faces",
    "characteristic_lengths",
    "hex_volumes",
    "make_ball_mesh",
    "make_bat_mesh",
    "make_box_mesh",
    "mesh_quality",
    "quad_areas",
    "quad_aspect_ratios",
    "quad_normals",
    "quad_scaled_jacobians",
    "scaled_jacobians",
    "shell_quality",
    "surface_point_ids",
]
