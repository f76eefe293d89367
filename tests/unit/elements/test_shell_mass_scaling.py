"""Selective mass scaling of the explicit shells (LS-DYNA DT2MS < 0).

A plate with one column of narrow cells (0.4 of the others' width): the narrow cells set the
stable step. Scaling to the wide cells' step must (1) leave the wide cells untouched, (2) give the
narrow cells the step of a laminate whose density is raised by the same factor (the plate wave
speed goes as 1 / sqrt(density): an independent route through the laminate), and (3) make the
central-difference scheme stable at the target step: omega_max dt < 2 for the assembled BT
stiffness and the scaled lumped mass, where without the added mass omega_max dt > 2.
"""

from __future__ import annotations

import numpy as np
import pytest

from batball.elements.shell_bt import small_displacement_forces
from batball.elements.shell_bt_section import layered_section
from batball.elements.shell_explicit import (
    TIME_STEP_FACTOR,
    cell_stable_steps,
    lumped_shell_mass,
    selective_mass_scaling,
)
from batball.materials.laminate import Laminate, Ply
from batball.materials.orthotropic import isotropic_lamina

#: x stations of the plate's columns: the first column is 4 mm wide, the others 10 mm [m].
X_STATIONS = np.array([0.0, 0.004, 0.014, 0.024, 0.034])
Y_STATIONS = np.array([0.0, 0.01, 0.02])
THICKNESS = 1e-3  # m


DENSITY = 2700.0  # kg/m^3


def aluminium(density: float = DENSITY) -> Laminate:
    """A 1-mm aluminium plate of two layers."""
    layer = isotropic_lamina(name="aluminium", density=density, youngs_modulus=70e9,
                             poissons_ratio=0.3)  # fmt: skip
    return Laminate((Ply(layer, 0.5 * THICKNESS, 0.0), Ply(layer, 0.5 * THICKNESS, 0.0)))


def plate() -> tuple[np.ndarray, np.ndarray]:
    """(points (15, 3), cells (8, 4)) of the plate; cells 0 and 1 are the narrow ones."""
    x, y = np.meshgrid(X_STATIONS, Y_STATIONS, indexing="ij")
    points = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    ny = Y_STATIONS.size
    i, j = np.meshgrid(np.arange(X_STATIONS.size - 1), np.arange(ny - 1), indexing="ij")
    first = (i * ny + j).ravel()
    return points, np.stack([first, first + ny, first + ny + 1, first + 1], axis=1)


def highest_frequency(points: np.ndarray, cells: np.ndarray, mass: np.ndarray,
                      section: object) -> float:  # fmt: skip
    """omega_max [rad/s] of the free plate: the assembled BT stiffness over the lumped mass."""
    n_dofs = 6 * points.shape[0]
    columns = [small_displacement_forces(points, cells, section,  # type: ignore[arg-type]
                                         np.eye(1, n_dofs, k).reshape(-1, 6)).ravel()
               for k in range(n_dofs)]  # fmt: skip
    stiffness = np.array(columns).T
    m = mass.ravel()
    scaled = stiffness / np.sqrt(np.outer(m, m))
    return float(np.sqrt(np.linalg.eigvalsh(0.5 * (scaled + scaled.T)).max()))


def test_mass_goes_only_to_the_cells_below_the_target_and_brings_them_to_it() -> None:
    points, cells = plate()
    section = layered_section([aluminium()], np.zeros(len(cells), dtype=np.int64))
    steps = TIME_STEP_FACTOR * cell_stable_steps(points, cells, section)
    narrow = np.array([0, 1])
    target = float(steps[2:].min())  # the wide cells' step
    assert steps[narrow].max() == pytest.approx(target / 2.5, rel=1e-12)  # L_s = 4 vs 10 mm
    added = selective_mass_scaling(points, cells, section, target)
    assert np.all(added[2:] == 0.0)
    m0 = DENSITY * THICKNESS
    factor = 1.0 + added[narrow] / m0
    # (2): a laminate of density raised by the factor reaches the target on its own
    heavier = layered_section([aluminium(), aluminium(DENSITY * float(factor[0]))],
                              np.array([1, 1, 0, 0, 0, 0, 0, 0]))  # fmt: skip
    scaled_steps = TIME_STEP_FACTOR * cell_stable_steps(points, cells, heavier)
    np.testing.assert_allclose(scaled_steps[narrow], target, rtol=1e-12)
    assert factor == pytest.approx(6.25, rel=1e-12)  # (10 / 4)^2


def test_scaled_plate_is_stable_at_the_target_step() -> None:
    points, cells = plate()
    section = layered_section([aluminium()], np.zeros(len(cells), dtype=np.int64))
    target = float(TIME_STEP_FACTOR * cell_stable_steps(points, cells, section)[2:].min())
    areal = DENSITY * THICKNESS + selective_mass_scaling(points, cells, section, target)
    scaled = lumped_shell_mass(points, cells, section, areal_mass=areal)
    plain = lumped_shell_mass(points, cells, section)
    assert highest_frequency(points, cells, scaled, section) * target < 2.0
    assert highest_frequency(points, cells, plain, section) * target > 2.0
    # the total added is what the two narrow cells needed: 5.25 m0 A each
    added = scaled[:, 0].sum() - plain[:, 0].sum()
    assert added == pytest.approx(2 * 5.25 * DENSITY * THICKNESS * 0.004 * 0.01, rel=1e-12)
