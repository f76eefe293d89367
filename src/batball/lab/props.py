"""Bat mass properties (ASTM F2398): weight, balance point, MOI about the 6-in pivot and the CM.

Definitions (``docs/physics.md`` section 5.2 and section 8, case 20): the balance
point is the distance of the centre of mass from the knob end along the bat axis; the MOI is taken
about the pivot axis, perpendicular to the bat axis (here the z axis through x = 6 in), so a mass
at (x, y, z) contributes m r_perp^2 with r_perp^2 = (x - x_pivot)^2 + y^2.

The shell mass is integrated exactly over each flat quad: areal mass sum(rho_k t_k) of the part's
layup, plus the part's lumped (non-structural) mass spread uniformly over its area, times the
bilinear area element, by 2 x 2 Gauss points. For a flat quad the area element is linear in each
parametric direction and the integrands are at most quadratic, so 2 x 2 Gauss is exact. LS-DYNA
instead lumps each shell's mass to its four nodes; that leaves mass and balance point unchanged on
these (trapezoidal, nearly rectangular) quads and adds m h^2/6 to the MOI (h the axial element
size), 0.04 oz in^2 on the default bat: 6 parts per million of 6920 oz in^2, far below the 0.5 %
the seed is matched to, so exact integration is kept as the cleaner number.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from batball.mesh.bat import DEFAULT_AXIAL_SIZE, DEFAULT_CIRCUMFERENTIAL, make_bat_mesh
from batball.mesh.shell import ShellMesh
from batball.models.bat import bat_areal_mass
from batball.specs.bat import BatSpec
from batball.units import IN

#: F2398 pivot: 6 in from the knob end.
DEFAULT_PIVOT = 6.0 * IN

_GAUSS = 1.0 / np.sqrt(3.0)
#: (xi, eta) of the 2 x 2 Gauss points, unit weights.
_GAUSS_POINTS = np.array(
    [[-_GAUSS, -_GAUSS], [_GAUSS, -_GAUSS], [_GAUSS, _GAUSS], [-_GAUSS, _GAUSS]]
)
_CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


@dataclass(frozen=True)
class MassProperties:
    """Mass properties of a body along the x axis, SI.

    Attributes:
        mass: kg.
        balance_point: x of the centre of mass (from the knob end), m.
        moi_pivot: moment of inertia about the pivot axis (parallel to z through x = pivot), kg m^2.
        moi_cm: moment of inertia about the parallel axis through the centre of mass, kg m^2.
        pivot: x of the pivot axis, m.
    """

    mass: float
    balance_point: float
    moi_pivot: float
    moi_cm: float
    pivot: float


def gauss_points_and_weights(mesh: ShellMesh) -> tuple[np.ndarray, np.ndarray]:
    """2 x 2 Gauss points of every quad and their area weights.

    Returns:
        points (n_cells, 4, 3), m; weights (n_cells, 4), m^2 (the area element times the unit
        Gauss weight; they sum to each flat quad's area).
    """
    shape = (
        0.25
        * (1 + _GAUSS_POINTS[:, None, 0] * _CORNERS[None, :, 0])
        * (1 + _GAUSS_POINTS[:, None, 1] * _CORNERS[None, :, 1])
    )  # (4 gauss, 4 nodes)
    d_xi = 0.25 * _CORNERS[None, :, 0] * (1 + _GAUSS_POINTS[:, None, 1] * _CORNERS[None, :, 1])
    d_eta = 0.25 * _CORNERS[None, :, 1] * (1 + _GAUSS_POINTS[:, None, 0] * _CORNERS[None, :, 0])
    x = mesh.points[mesh.cells]  # (n_cells, 4 nodes, 3)
    points = np.einsum("gn,cnk->cgk", shape, x)
    tangent_xi = np.einsum("gn,cnk->cgk", d_xi, x)
    tangent_eta = np.einsum("gn,cnk->cgk", d_eta, x)
    weights = np.linalg.norm(np.cross(tangent_xi, tangent_eta), axis=2)
    return points, weights


def shell_mass_properties(
    mesh: ShellMesh, areal_mass: np.ndarray, *, pivot: float = DEFAULT_PIVOT
) -> MassProperties:
    """Mass, centre of mass and MOI (about the z-parallel axes) of shells of given areal mass.

    Args:
        mesh: the shells, bat axis along x.
        areal_mass: mass per unit area of each quad, shape (n_cells,), kg/m^2.
        pivot: x of the pivot axis, m.
    """
    points, weights = gauss_points_and_weights(mesh)
    dm = weights * areal_mass[:, None]  # (n_cells, 4) kg
    mass = float(dm.sum())
    centre = np.einsum("cg,cgk->k", dm, points) / mass
    x, y = points[..., 0], points[..., 1]
    moi_pivot = float(np.sum(dm * ((x - pivot) ** 2 + y**2)))
    moi_cm = float(np.sum(dm * ((x - centre[0]) ** 2 + (y - centre[1]) ** 2)))
    return MassProperties(mass, float(centre[0]), moi_pivot, moi_cm, pivot)


def bat_mass_properties(
    spec: BatSpec,
    *,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
    pivot: float = DEFAULT_PIVOT,
) -> tuple[MassProperties, ShellMesh]:
    """Mass properties of a bat from its shell mesh (ASTM F2398 definitions).

    Args:
        spec: the bat.
        circumferential: quads around the circumference.
        axial_size: largest element length along the meridian, m.
        pivot: pivot distance from the knob end, m (6 in).

    Returns:
        The properties and the mesh they were computed on.
    """
    mesh = make_bat_mesh(spec, circumferential=circumferential, axial_size=axial_size)
    return shell_mass_properties(mesh, bat_areal_mass(spec, mesh), pivot=pivot), mesh
