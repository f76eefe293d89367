"""Coulomb friction in the penalty statics (solvers/static_contact.solve_frictional_step) on a
slider with closed-form answers: a node pressed onto a fixed one by an overlap, held by a
spring along x and pulled by P. It sticks while the stick spring's traction stays below mu f_n,
then slips with traction mu f_n; unloaded after slipping it stays displaced (the spring cannot
pull it back against friction)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from batball.contact.shell_contact import PenaltyGaps, gap_matrix
from batball.solvers.static_contact import CoulombFriction, solve_frictional_step

K_X, K_Y, K_N, K_T = 1e4, 1e6, 1e7, 1e9  # N/m
OVERLAP = 1e-4  # m
MU = 0.3
NODES, WEIGHTS = np.array([[1, 0]]), np.array([[1.0, -1.0]])  # master (node 1) minus slave
FIXED = np.array([2, 3, 4, 5, *range(6, 12)])  # the slave moves in x and y, the master not


def slider() -> tuple[sp.csr_matrix, list[PenaltyGaps], CoulombFriction]:
    diagonal = np.ones(12)
    diagonal[0], diagonal[1] = K_X, K_Y
    normal = PenaltyGaps(gap_matrix(NODES, WEIGHTS, np.array([[0.0, 1.0, 0.0]]), 2),
                         np.array([-OVERLAP]), np.array([K_N]))  # fmt: skip
    slips = (gap_matrix(NODES, WEIGHTS, np.array([[1.0, 0.0, 0.0]]), 2),
             gap_matrix(NODES, WEIGHTS, np.array([[0.0, 0.0, 1.0]]), 2))  # fmt: skip
    friction = CoulombFriction(slips, ((0,),), np.array([K_T]), MU)
    return sp.diags(diagonal).tocsr(), [normal], friction


def step(pull: float, anchor: np.ndarray):  # noqa: ANN201
    stiffness, gaps, friction = slider()
    loads = np.zeros(12)
    loads[0] = pull
    return solve_frictional_step(stiffness, gaps, friction, anchor, fixed_dofs=FIXED,
                                 loads=loads, rtol=1e-12)  # fmt: skip


F_N = K_N * OVERLAP * K_Y / (K_Y + K_N)  # the normal force: the gap and the y spring in series


def test_a_small_pull_sticks_with_the_stick_spring_in_parallel() -> None:
    pull = 0.5 * MU * F_N
    state = step(pull, np.zeros((1, 2)))
    u_x = pull / (K_X + K_T)
    assert state.stick[0]
    assert state.solution.u[0] == pytest.approx(u_x, rel=1e-9)
    assert state.solution.forces[0][0] == pytest.approx(F_N, rel=1e-9)
    assert state.traction[0, 0] == pytest.approx(-K_T * u_x, rel=1e-9)  # s = -u_x


def test_a_large_pull_slips_at_the_coulomb_limit_and_stays_put_when_released() -> None:
    pull = 1.5 * MU * F_N
    state = step(pull, np.zeros((1, 2)))
    slipped = (pull - MU * F_N) / K_X
    assert not state.stick[0]
    assert state.solution.u[0] == pytest.approx(slipped, rel=1e-6)
    assert state.traction[0, 0] == pytest.approx(-MU * F_N, rel=1e-6)
    # released: the stick spring, anchored where the slip ended, holds the node against the x
    # spring; u = (k_t u_1 - mu f_n) / (k_x + k_t) (module docs), about u_1
    released = step(0.0, state.anchor)
    assert released.stick[0]
    expected = (K_T * slipped - MU * F_N) / (K_X + K_T)
    assert released.solution.u[0] == pytest.approx(expected, rel=1e-6)
    assert released.solution.u[0] > 0.99 * slipped
