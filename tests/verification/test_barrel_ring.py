"""A thin ring squeezed between two rigid platens against Roark's diametral-load closed form.

Roark's Formulas for Stress and Strain (7th ed.), Table 9.2 case 1, thin circular ring under two
equal and opposite point loads P along a diameter: the diameter along the load shortens by

    delta = (pi / 4 - 2 / pi) P R^3 / (E I) = 0.1488 P R^3 / (E I)

(Castigliano, bending only; docs/physics.md section 5.1 quotes 0.149). A short free tube with
Poisson's ratio 0 under a uniform line load along two opposite generators is that ring per unit
length: I = t^3 / 12 per unit length, no anticlastic coupling. Membrane and shear corrections
are of order (t / R)^2 = 4e-4 here.

The load is applied as the barrel test applies it: rigid cylinders (here with their axes along
the tube, radius 1 m, nearly flat) pressing the shells' outer surfaces through penalty contact,
the bottom one fixed and the top one moved by d, so delta = d.
"""

from __future__ import annotations

import numpy as np
import pytest

from batball.contact.shell_contact import rigid_cylinder_gaps
from batball.elements.shell_stiffness import assemble_shell_stiffness, shell_section
from batball.materials.laminate import Laminate, Ply
from batball.materials.orthotropic import isotropic_lamina
from batball.mesh.bat import revolve_rings
from batball.mesh.shell import ShellMesh
from batball.solvers.static_contact import FactorReuse, solve_static_contact

E = 70e9  # Pa
THICKNESS = 0.6e-3  # m
RADIUS = 30e-3  # m, mid-surface
LENGTH = 10e-3  # m
PLATEN_RADIUS = 1.0  # m
ROARK = np.pi / 4 - 2 / np.pi  # 0.14878


def squeezed_ring(around: int, travel: float,
                  reuse: FactorReuse | None = None) -> tuple[float, np.ndarray]:  # fmt: skip
    """Platen force (N) for a top-platen travel (m), and the radial displacement of the nodes."""
    rings = 5
    points, cells = revolve_rings(np.linspace(0, LENGTH, rings), np.full(rings, RADIUS),
                                  circumferential=around)  # fmt: skip
    mesh = ShellMesh(points=points, cells=cells, point_sets={}, cell_sets={})
    layer = Ply(isotropic_lamina(name="nu0", density=2700.0, youngs_modulus=E,
                                 poissons_ratio=0.0), THICKNESS, 0.0)  # fmt: skip
    section = shell_section([Laminate((layer,))], np.zeros(mesh.n_cells, dtype=np.int64))
    stiffness = assemble_shell_stiffness(mesh, section)
    nodes = np.arange(mesh.n_points)
    offsets = np.full(nodes.size, 0.5 * THICKNESS)
    ring_stiffness = E * THICKNESS**3 / 12 * LENGTH / (ROARK * RADIUS**3)  # N/m, whole tube
    penalty = np.full(nodes.size, 1e4 * ring_stiffness / rings)
    reach = RADIUS + 0.5 * THICKNESS + PLATEN_RADIUS
    x_axis = np.array([1.0, 0.0, 0.0])
    top = rigid_cylinder_gaps(points, nodes=nodes, offsets=offsets, radius=PLATEN_RADIUS,
                              axis_point=np.array([0.0, reach - travel, 0.0]),
                              axis_direction=x_axis, stiffness=penalty)  # fmt: skip
    bottom = rigid_cylinder_gaps(points, nodes=nodes, offsets=offsets, radius=PLATEN_RADIUS,
                                 axis_point=np.array([0.0, -reach, 0.0]),
                                 axis_direction=x_axis, stiffness=penalty)  # fmt: skip
    # The seed's supports: the ring at mid-length held axially, the top and bottom nodes sideways.
    middle_ring = np.arange(around) + around * (rings // 2)
    top_bottom = middle_ring[[0, around // 2]]  # phi = 0 and 180 deg: y = +-R
    fixed = np.concatenate([6 * middle_ring, 6 * top_bottom + 2])
    solution = solve_static_contact(stiffness, [top, bottom], fixed_dofs=fixed,
                                    closed_within=1e-12, reuse=reuse)  # fmt: skip
    u = solution.u.reshape(-1, 6)
    radial = np.einsum("ni,ni->n", u[:, 1:3], points[:, 1:]) / RADIUS
    force_top, force_bottom = solution.forces[0].sum(), solution.forces[1].sum()
    assert force_top == pytest.approx(force_bottom, rel=1e-6)  # equilibrium
    return force_top, radial


@pytest.mark.parametrize(("around", "tolerance"), [(32, 0.03), (64, 0.01)])
def test_diametral_stiffness_matches_roark(around: int, tolerance: float) -> None:
    """P = d E I / (0.1488 R^3): within 3 % on 32 quads around, 1 % on 64 (flat facets
    converge from the stiff side; the penalty adds 1e-4)."""
    travel = 10e-6
    force, _ = squeezed_ring(around, travel)
    expected = travel * E * THICKNESS**3 / 12 * LENGTH / (ROARK * RADIUS**3)
    assert force == pytest.approx(expected, rel=tolerance)


def test_the_sides_bulge_out_by_roark() -> None:
    """Roark Table 9.2 case 1: the horizontal diameter grows by (2/pi - 1/2) P R^3 / (E I)
    = 0.1366 P R^3 / (E I), i.e. 0.918 times the vertical shortening; within 2 % on 64 around."""
    around, travel = 64, 10e-6
    force, radial = squeezed_ring(around, travel)
    per_length = force / LENGTH
    sides = radial.reshape(-1, around)[:, [around // 4, 3 * around // 4]].sum(axis=1)  # z = +-R
    expected = (2 / np.pi - 0.5) * per_length * RADIUS**3 / (E * THICKNESS**3 / 12)
    np.testing.assert_allclose(sides, expected, rtol=0.02)


def test_a_kept_factorisation_gives_the_fresh_answer() -> None:
    """Three travels solved on one kept factor (CG, the platen normals barely change) agree with
    fresh factorisations to 1e-8."""
    reuse = FactorReuse()
    for travel in (5e-6, 10e-6, 20e-6):
        kept, _ = squeezed_ring(32, travel, reuse)
        fresh, _ = squeezed_ring(32, travel)
        assert kept == pytest.approx(fresh, rel=1e-8)
    assert reuse.factorisations == 1 and reuse.cg_solves >= 2
