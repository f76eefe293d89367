"""The foam element kernel on one homogeneously deformed hex against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from batball.elements.hex8_foam import (
    N_FOAM_HISTORY,
    compute_foam_forces,
    foam_reference_gradients,
)
from batball.elements.hex8_geometry import REFERENCE_CORNERS
from batball.mesh.ball import make_ball_mesh
from batball.specs import load_ball_spec

SIDE = 0.01  # m
DENSITY = 400.0  # kg/m^3


def _run(points: np.ndarray, reference: np.ndarray, name: str = "foam057"):
    """Forces (8, 3) [N], volume, stable step of one cell deformed from ``reference``."""
    material = load_ball_spec(name).material
    cells = np.arange(8)[None, :]
    forces = np.zeros((1, 8, 3))  # one slot of the 8 nodes
    volume, step = np.zeros(1), np.zeros(1)
    energy = np.zeros((1, 3))
    compute_foam_forces(
        points, np.zeros((8, 3)), cells, foam_reference_gradients(cells, reference), 1e-7,
        DENSITY, np.array([SIDE**3]),
        material.foam_table().arrays(), np.zeros((1, N_FOAM_HISTORY)), np.zeros((1, 4, 3)),
        1, 0.1, 1.5, 0.06, forces, volume, step, energy,
    )  # fmt: skip
    return forces[0], volume[0], step[0], energy


def test_uniaxial_compression_gives_the_curve_force_on_each_face() -> None:
    reference = 0.5 * SIDE * (REFERENCE_CORNERS + 1.0)
    s = 0.25
    points = reference * np.array([1.0 - s, 1.0, 1.0])
    forces, volume, step, energy = _run(points, reference)
    material = load_ball_spec("foam057").material
    curve = material.curves[0]
    nominal = np.interp(s, curve.strain, curve.stress)  # Pa; the sides keep their area SIDE^2
    plus_x = REFERENCE_CORNERS[:, 0] > 0
    assert forces[plus_x, 0].sum() == pytest.approx(nominal * SIDE**2, rel=1e-12)
    assert forces[~plus_x, 0].sum() == pytest.approx(-nominal * SIDE**2, rel=1e-12)
    assert np.abs(forces[:, 1:]).max() < 1e-12 * nominal * SIDE**2  # no lateral coupling
    assert volume == pytest.approx(SIDE**3 * (1.0 - s), rel=1e-12)
    # L_e = V / A_max = SIDE (1 - s); c^2 = E_eff / rho, rho = rho0 / (1 - s); DAMP reduction
    e_eff = material.values["curve_scale"] * curve.max_slope()
    c = np.sqrt(e_eff / (DENSITY / (1.0 - s)))
    damp = material.values["damp"]
    assert step == pytest.approx(SIDE * (1.0 - s) / c / (damp + np.sqrt(1 + damp**2)), rel=1e-12)
    assert np.abs(energy).max() == 0.0  # at rest: no work


@pytest.mark.parametrize("name", ["foam057", "foam083"])
def test_rigidly_rotated_element_has_rotated_forces(name: str) -> None:
    reference = 0.5 * SIDE * (REFERENCE_CORNERS + 1.0)
    stretch = np.array([[0.8, 0.05, 0.0], [0.0, 0.95, 0.02], [0.03, 0.0, 1.05]])
    angle = 0.7
    r = np.array(
        [[np.cos(angle), -np.sin(angle), 0.0], [np.sin(angle), np.cos(angle), 0.0], [0, 0, 1]]
    )
    forces, *_ = _run(reference @ stretch.T, reference, name)
    rotated, *_ = _run(reference @ stretch.T @ r.T, reference, name)
    assert np.abs(rotated - forces @ r.T).max() < 1e-10 * np.abs(forces).max()


def test_each_cell_is_the_same_whichever_cells_share_its_block() -> None:
    """The kernel decomposes b = F F^T for blocks of cells at once; a cell's stress, history,
    volume and step must not depend on its block-mates. The cells of a randomly deformed coarse
    ball (189, not a whole number of blocks) run in order and reversed: every per-cell output is
    the same bits, the nodal forces the same to summation round-off (1e-12 of the largest)."""
    mesh = make_ball_mesh(0.05, divisions=3)
    cells = mesh.cells.astype(np.int32)
    rng = np.random.default_rng(5)
    points = mesh.points * (1.0 + rng.normal(0.0, 0.05, mesh.points.shape))
    velocities = rng.normal(0.0, 5.0, mesh.points.shape)
    table = load_ball_spec("type1-fit").material.foam_table().arrays()
    volume0 = np.full(mesh.n_cells, (0.1 / 3) ** 3)

    # a history per cell: half the cells unloading from a larger W_max, a filtered rate
    base = np.zeros((mesh.n_cells, N_FOAM_HISTORY))
    base[::2, 12] = 1e6  # W_max [J/m^3]
    base[:, 13] = rng.uniform(0.0, 100.0, mesh.n_cells)  # filtered strain rate [1/s]

    def run(order: np.ndarray) -> tuple[np.ndarray, ...]:
        n = len(order)
        history, hg_state = base[order].copy(), np.zeros((n, 4, 3))
        forces, volume, step = np.zeros((1,) + points.shape), np.zeros(n), np.zeros(n)
        compute_foam_forces(
            points, velocities, cells[order], foam_reference_gradients(cells[order], mesh.points),
            1e-7, DENSITY, volume0[order], table, history, hg_state, 4, 0.1, 1.5, 0.06, forces,
            volume, step, np.zeros((1, 3)),
        )  # fmt: skip
        back = np.argsort(order)
        return history[back], hg_state[back], volume[back], step[back], forces[0]

    forward = run(np.arange(mesh.n_cells))
    backward = run(np.arange(mesh.n_cells)[::-1])
    for a, b in zip(forward[:4], backward[:4], strict=True):
        assert np.array_equal(a, b)
    assert np.abs(forward[4] - backward[4]).max() <= 1e-12 * np.abs(forward[4]).max()


def test_a_cell_without_volume_keeps_its_history_and_adds_no_forces() -> None:
    """An inverted cell (its top and bottom faces swapped: negative volume) beside a compressed
    one: the kernel must leave the inverted cell's whole history row as it was (the law's
    filtered rate and W_max included), give it a zero step and no nodal forces, and still
    update the healthy cell. The rows start from random values, so a row rewritten from
    anything else cannot match."""
    corners = REFERENCE_CORNERS * SIDE / 2.0
    reference = np.vstack([corners, corners + [3.0 * SIDE, 0.0, 0.0]])
    points = reference.copy()
    points[:8, 2] *= 0.9  # compressed 10 %
    points[8:, 2] *= -1.0  # inverted
    cells = np.arange(16, dtype=np.int32).reshape(2, 8)
    rng = np.random.default_rng(11)
    history = rng.uniform(0.1, 1.0, (2, N_FOAM_HISTORY))
    before = history.copy()
    forces, volume, step = np.zeros((1, 16, 3)), np.zeros(2), np.zeros(2)
    compute_foam_forces(
        points, np.zeros((16, 3)), cells, foam_reference_gradients(cells, reference), 1e-7,
        DENSITY, np.full(2, SIDE**3), load_ball_spec("type1-fit").material.foam_table().arrays(),
        history, np.zeros((2, 4, 3)), 1, 0.1, 1.5, 0.06, forces, volume, step, np.zeros((1, 3)),
    )  # fmt: skip
    assert volume[1] < 0.0 and step[1] == 0.0
    assert np.array_equal(history[1], before[1])
    assert np.all(forces[0, 8:] == 0.0)
    assert volume[0] > 0.0 and step[0] > 0.0
    assert not np.array_equal(history[0], before[0])
    assert np.abs(forces[0, :8]).max() > 0.0
