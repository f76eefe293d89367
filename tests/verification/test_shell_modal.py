"""Verification of the MITC4 layered shell and the free-free modal solver against closed forms.

References (``docs/physics.md`` section 8): case 8 (free-free aluminium tube, Timoshenko),
case 13 (n = 2 ovalling of a long thin tube, Love/Fluegge ring), case 10 (NAFEMS FV12 free plate);
plus the membrane and bending patch tests of MacNeal & Harder (1985) on a distorted patch.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from batball.elements.shell_stiffness import (
    assemble_shell_mass,
    assemble_shell_stiffness,
    shell_section,
)
from batball.materials.laminate import Laminate, Ply
from batball.materials.orthotropic import OrthotropicLamina, isotropic_lamina
from batball.mesh.bat import revolve_rings
from batball.mesh.shell import ShellMesh
from batball.solvers.modal import ModalResult, free_free_modes

ALUMINIUM = isotropic_lamina(name="al", density=2810.0, youngs_modulus=71.7e9,
                             poissons_ratio=0.33)  # fmt: skip
STEEL = isotropic_lamina(name="steel", density=8000.0, youngs_modulus=200e9, poissons_ratio=0.3)
OUTER_DIAMETER = 57.15e-3  # m (2.25 in)


def single_layer_modes(
    mesh: ShellMesh, material: OrthotropicLamina, thickness: float, *, n_modes: int,
    shift_hz: float,
) -> ModalResult:  # fmt: skip
    """Modes of a one-material shell mesh (consistent mass)."""
    section = shell_section([Laminate((Ply(material, thickness, 0.0),))],
                            np.zeros(mesh.n_cells, dtype=np.int64))  # fmt: skip
    stiffness = assemble_shell_stiffness(mesh, section)
    mass = assemble_shell_mass(mesh, section)
    return free_free_modes(stiffness, mass, n_modes=n_modes, shift_hz=shift_hz)


def tube_mesh(*, wall: float, length: float, circumferential: int, axial: int) -> ShellMesh:
    """A uniform tube of the 2.25-in outer diameter on its mid-surface."""
    x = np.linspace(0.0, length, axial + 1)
    radius = np.full(x.shape, 0.5 * (OUTER_DIAMETER - wall))
    points, cells = revolve_rings(x, radius, circumferential=circumferential)
    return ShellMesh(points, cells)


def test_free_free_tube_bending_matches_timoshenko() -> None:
    """Case 8: modes 1-2 454.19 and 1191.02 Hz (Timoshenko), within 1.5 %; each in two planes."""
    mesh = tube_mesh(wall=2.5e-3, length=0.8636, circumferential=24, axial=60)
    result = single_layer_modes(mesh, ALUMINIUM, 2.5e-3, n_modes=12, shift_hz=10.0)
    assert result.n_rigid == 6
    assert np.all(np.abs(result.frequencies[:6]) < 1.0)
    flexible = result.flexible_frequencies
    np.testing.assert_allclose(flexible[[0, 1]], 454.19, rtol=0.015)
    np.testing.assert_allclose(flexible[[2, 3]], 1191.02, rtol=0.015)


def test_long_tube_ovalling_matches_ring_formula() -> None:
    """Case 13: n = 2 ovalling of a long tube (L/R = 32), 2208.8 Hz for h = 2.5 mm, within 2 %.

    Uniform ovalling needs little axial resolution, so the tube has 10 rings of 32 quads; the
    lowest n = 2 pair (uniform ovalling) lies above the first two bending pairs and torsion.
    """
    mesh = tube_mesh(wall=2.5e-3, length=0.8636, circumferential=32, axial=10)
    result = single_layer_modes(mesh, ALUMINIUM, 2.5e-3, n_modes=14, shift_hz=10.0)
    near = result.flexible_frequencies[np.abs(result.flexible_frequencies - 2208.8) < 0.1 * 2208.8]
    assert near.size >= 2
    np.testing.assert_allclose(near[:2], 2208.8, rtol=0.02)


def square_plate_mesh(divisions: int, side: float) -> ShellMesh:
    """A flat square of ``divisions``^2 quads in the x-y plane."""
    s = np.linspace(0.0, side, divisions + 1)
    x, y = np.meshgrid(s, s, indexing="ij")
    points = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    i, j = np.meshgrid(np.arange(divisions), np.arange(divisions), indexing="ij")
    first = (i * (divisions + 1) + j).ravel()
    cells = np.stack([first, first + divisions + 1, first + divisions + 2, first + 1], axis=1)
    return ShellMesh(points, cells)


def test_nafems_fv12_free_plate() -> None:
    """Case 10: modes 7-9 of the free 10 m plate, 1.622, 2.360, 2.922 Hz, within 2 % (16 x 16)."""
    result = single_layer_modes(square_plate_mesh(16, 10.0), STEEL, 0.05, n_modes=9,
                                shift_hz=0.1)  # fmt: skip
    assert result.n_rigid == 6
    np.testing.assert_allclose(result.frequencies[6:9], [1.622, 2.360, 2.922], rtol=0.02)


#: MacNeal-Harder distorted patch: 0.24 x 0.12 plate, four inner nodes.
PATCH_POINTS = np.array(
    [[0.0, 0.0], [0.24, 0.0], [0.24, 0.12], [0.0, 0.12],
     [0.04, 0.02], [0.18, 0.03], [0.16, 0.08], [0.08, 0.08]]
)  # fmt: skip
PATCH_CELLS = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 7]])


def solve_patch(exact: np.ndarray, thickness: float) -> np.ndarray:
    """Interior dofs of the patch with the boundary nodes prescribed to ``exact`` (8, 6)."""
    points = np.column_stack([PATCH_POINTS, np.zeros(8)])
    mesh = ShellMesh(points, PATCH_CELLS)
    section = shell_section([Laminate((Ply(STEEL, thickness, 0.0),))], np.zeros(5, np.int64))
    stiffness = assemble_shell_stiffness(mesh, section).tocsc()
    boundary = (6 * np.arange(4)[:, None] + np.arange(6)).ravel()
    inner = (6 * np.arange(4, 8)[:, None] + np.arange(6)).ravel()
    rhs = -stiffness[inner][:, boundary] @ exact[:4].ravel()
    return np.asarray(spla.spsolve(stiffness[inner][:, inner], rhs)).reshape(4, 6)


def test_membrane_patch_reproduces_linear_field() -> None:
    """u = 1e-3 (x + y/2), v = 1e-3 (y + x/2): the inner nodes take the exact linear field."""
    x, y = PATCH_POINTS[:, 0], PATCH_POINTS[:, 1]
    exact = np.zeros((8, 6))
    exact[:, 0], exact[:, 1] = 1e-3 * (x + 0.5 * y), 1e-3 * (y + 0.5 * x)
    exact[:, 5] = 0.5 * (0.5e-3 - 0.5e-3)  # in-plane rotation (v,x - u,y)/2 = 0
    np.testing.assert_allclose(solve_patch(exact, 1e-3), exact[4:], atol=1e-12)


@pytest.mark.parametrize("thickness", [1e-3, 1e-2])
def test_bending_patch_reproduces_constant_curvature(thickness: float) -> None:
    """w = 1e-3 (x^2 + x y + y^2)/2 with zero transverse shear (theta_2 = -w,x, theta_1 = w,y)."""
    x, y = PATCH_POINTS[:, 0], PATCH_POINTS[:, 1]
    exact = np.zeros((8, 6))
    exact[:, 2] = 0.5e-3 * (x**2 + x * y + y**2)
    exact[:, 3] = 1e-3 * (0.5 * x + y)  # theta_1 = w,y
    exact[:, 4] = -1e-3 * (x + 0.5 * y)  # theta_2 = -w,x
    np.testing.assert_allclose(solve_patch(exact, thickness), exact[4:], atol=1e-10)
