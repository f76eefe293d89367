"""The coupled cycle's update (solvers/ball_bat.advance_ball, advance_bat), split over threads:
the motion is the central-difference formula node by node, the same bits on any thread count,
and the bookkeeping sums are the NumPy sums of the same terms (to round-off: the threads' parts
are added in another order, 1e-12 relative allowed against about 1e-14 seen). Likewise the
ball's slot sum (take_slot_forces: the NumPy sum exactly, slots cleared) and the insert fit's
relaxation step (central_difference: the formula, then the velocities scaled, and each node's
m v^2; add_and_clear: the contact forces added, the held nodes' zeroed), and the impact
solver's update (explicit_kernels.assemble_and_update). The coupled cycle's step (smallest_step:
NumPy's minimum, or the first step that is not positive) and its bookkeeping (close_cycle: the
energies and the history row as NumPy's sums of the same terms give them, the same bits)."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from batball.solvers.ball_bat import (
    HISTORY_COLUMNS,
    add_and_clear,
    advance_ball,
    advance_bat,
    central_difference,
    close_cycle,
    kinetic_energy,
    smallest_step,
    take_slot_forces,
)
from batball.solvers.explicit_kernels import assemble_and_update, sum_blocks

N = 5000
H, DT_OLD, DT_NEW = 1.0e-7, 1.0e-7, 1.1e-7
PIVOT = np.array([0.1, 0.2, 0.0])


@pytest.fixture
def threads():  # noqa: ANN201
    before = numba.get_num_threads()
    yield (1, min(2, numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(before)


def test_the_ball_update_is_the_formula_and_its_sums_on_any_thread_count(threads) -> None:  # noqa: ANN001
    rng = np.random.default_rng(3)
    f, c = rng.normal(size=(N, 3)), 0.1 * rng.normal(size=(N, 3))
    m, v0, x0 = rng.uniform(1, 2, N), rng.normal(size=(N, 3)), rng.normal(size=(N, 3))
    v = v0 + H * (f + c) / m[:, None]
    x = x0 + DT_NEW * v
    r = x - PIVOT
    expected = [np.sum(c * 0.5 * (v0 * DT_OLD + v * DT_NEW)), np.sum(0.5 * m[:, None] * v * v),
                *np.sum(m[:, None] * v, axis=0),
                np.sum(m * (r[:, 0] * v[:, 1] - r[:, 1] * v[:, 0])), np.sum(c[:, 1])]  # fmt: skip
    for count in threads:
        numba.set_num_threads(count)
        velocity, points, out = v0.copy(), x0.copy(), np.zeros(7)
        advance_ball(f, c, m, velocity, points, PIVOT, H, DT_OLD, DT_NEW, out)
        np.testing.assert_allclose(velocity, v, rtol=1e-14, atol=0)
        np.testing.assert_allclose(points, x, rtol=1e-14, atol=1e-300)
        np.testing.assert_allclose(out, expected, rtol=1e-12)


def test_the_bat_update_moves_free_nodes_and_turns_the_band_on_any_thread_count(threads) -> None:  # noqa: ANN001
    rng = np.random.default_rng(4)
    f, c = rng.normal(size=(N, 6)), 0.1 * rng.normal(size=(N, 3))
    m, v0, x0 = rng.uniform(1, 2, (N, 6)), rng.normal(size=(N, 6)), rng.normal(size=(N, 3))
    moving = rng.uniform(size=N) > 0.05
    band = np.flatnonzero(~moving)
    inertia = 3.0
    r0 = x0 - PIVOT
    fx, fy = f[band, 0] + c[band, 0], f[band, 1] + c[band, 1]
    torque = np.sum(r0[band, 0] * fy - r0[band, 1] * fx + f[band, 5])
    w = 0.5 + H * torque / inertia
    full_c = np.hstack([c, np.zeros((N, 3))])
    v = v0 + H * (f + full_c) / m
    v[band] = 0.0
    v[band, 0], v[band, 1], v[band, 5] = -w * r0[band, 1], w * r0[band, 0], w
    x = x0 + DT_NEW * v[:, :3]
    r = x - PIVOT
    step = 0.5 * (v0 * DT_OLD + v * DT_NEW)
    expected = [np.sum(f * step), np.sum(full_c * step), np.sum(0.5 * m * v * v),
                np.sum(m[:, 0] * (r[:, 0] * v[:, 1] - r[:, 1] * v[:, 0]) + m[:, 5] * v[:, 5]),
                0.0]  # fmt: skip
    motions = []
    for count in threads:
        numba.set_num_threads(count)
        velocity, points, omega, out = v0.copy(), x0.copy(), np.array([0.5]), np.zeros(5)
        advance_bat(f.copy(), c, m, velocity, points, moving, band, PIVOT, inertia, omega, 0.0,
                    np.zeros((N, 6)), H, DT_OLD, DT_NEW, out)  # fmt: skip
        np.testing.assert_allclose(velocity, v, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(points, x, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(out[:4], expected[:4], rtol=1e-12)
        assert out[4] == 0.0 and omega[0] == pytest.approx(w, rel=1e-14)
        motions.append((velocity, points))
    for a, b in zip(motions[0], motions[-1], strict=True):
        np.testing.assert_array_equal(a, b)  # the motion does not depend on the threads


def test_the_ball_slot_sum_is_the_numpy_sum_and_clears_the_slots(threads) -> None:  # noqa: ANN001
    rng = np.random.default_rng(5)
    slots = rng.normal(size=(2, N, 3))
    expected = slots[0] + slots[1]  # two slots: one addition, exact in any order
    for count in threads:
        numba.set_num_threads(count)
        work, forces = slots.copy(), np.zeros((N, 3))
        take_slot_forces(work, forces)
        np.testing.assert_array_equal(forces, expected)
        assert not work.any()


def test_the_relaxation_step_is_the_formula_on_any_thread_count(threads) -> None:  # noqa: ANN001
    rng = np.random.default_rng(6)
    f, m = rng.normal(size=(N, 6)), rng.uniform(1, 2, (N, 6))
    v0, x0 = rng.normal(size=(N, 6)), rng.normal(size=(N, 3))
    moving, factor = rng.uniform(size=N) > 0.05, 0.995
    v = v0 + H * f / m
    x = x0.copy()
    x[moving] += DT_NEW * v[moving, :3]
    for count in threads:
        numba.set_num_threads(count)
        velocity, points, node_kinetic = v0.copy(), x0.copy(), np.zeros(N)
        central_difference(f, m, velocity, H, DT_NEW, points, moving, factor, node_kinetic)
        np.testing.assert_allclose(velocity, factor * v, rtol=1e-14, atol=0)
        np.testing.assert_allclose(points, x, rtol=1e-14, atol=1e-300)
        np.testing.assert_allclose(node_kinetic, (m * (factor * v) ** 2).sum(axis=1), rtol=1e-13)
        assert kinetic_energy(node_kinetic) == pytest.approx(0.5 * np.sum(m * (factor * v) ** 2),
                                                             rel=1e-12)  # fmt: skip


def test_the_fit_forces_take_the_contact_and_drop_the_held_nodes_on_any_thread_count(
    threads,  # noqa: ANN001
) -> None:
    rng = np.random.default_rng(7)
    f0, contact0 = rng.normal(size=(N, 6)), rng.normal(size=(N + 7, 3))
    held = np.array([3, 1200, N - 1])
    expected = f0.copy()
    expected[:, :3] += contact0[:N]
    expected[held] = 0.0
    for count in threads:
        numba.set_num_threads(count)
        forces, contact = f0.copy(), contact0.copy()
        add_and_clear(forces, contact, held)
        np.testing.assert_array_equal(forces, expected)
        assert not contact[:N].any()
        np.testing.assert_array_equal(contact[N:], contact0[N:])  # rows past the bat's kept


def slot_problem(rng: np.random.Generator, ranges: np.ndarray,
                 n: int) -> tuple[np.ndarray, ...]:  # fmt: skip
    """An impact update's input on ``n`` nodes: three slots of random forces, each zero outside
    its node range in ``ranges``, the masses (1 to 2) and random x^n and v^(n-1/2)."""
    slots = np.zeros((3, n, 3))
    for slot, (lo, hi) in enumerate(ranges):
        slots[slot, lo:hi] = rng.normal(size=(hi - lo, 3))
    mass = 1.0 + rng.random(n)
    x0, v0 = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    return slots, mass, x0, v0


@pytest.mark.parametrize("damping", [0.0, 2.0e4])
def test_the_impact_update_sums_the_slots_and_steps_by_the_formula(threads, damping) -> None:  # noqa: ANN001
    """solvers/explicit_kernels.assemble_and_update, undamped and damped: three slots with
    overlapping node ranges (a slot's forces are zero outside its range, as the element kernel
    leaves them); the step is the damped central-difference formula on the slots' sum taken in
    slot order (to 1e-14: the kernel contracts multiply-adds), the same bits on any thread
    count; the slots are cleared; the sums are NumPy's to round-off (1e-12)."""
    ranges = np.array([[0, 2000], [1500, 3600], [3000, N]])
    slots, mass, x0, v0 = slot_problem(np.random.default_rng(7), ranges, N)
    half = 0.5 * (DT_OLD + DT_NEW)
    force = (slots[0] + slots[1]) + slots[2]
    keep, scale = 1.0 - 0.5 * damping * half, 1.0 / (1.0 + 0.5 * damping * half)
    v = (keep * v0 + force * (half / mass)[:, None]) * scale
    x = x0 + DT_NEW * v
    mean = 0.5 * (v0 + v)
    kinetic = 0.5 * (mass * (v * v).sum(1)).sum()
    dissipated = (damping * mass * half * (mean * mean).sum(1)).sum()
    expected_sums = [kinetic, 0.0, dissipated, *(mass[:, None] * v).sum(0)]
    results = []
    for count in threads:
        numba.set_num_threads(count)
        work, points, velocities = slots.copy(), x0.copy(), v0.copy()
        sums = np.zeros(6)
        assemble_and_update(work, ranges, mass, damping, DT_OLD, DT_NEW, points, velocities,
                            sums, (np.zeros(N), sum_blocks(N)))  # fmt: skip
        assert not work.any()
        np.testing.assert_allclose(velocities, v, rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(points, x, rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(sums, expected_sums, rtol=1e-12)
        results.append((points, velocities, sums))
    for a, b in zip(results[0], results[-1], strict=True):
        np.testing.assert_array_equal(a, b)  # not even the sums depend on the threads


@pytest.mark.parametrize("n", [1, 13, 300, 600])
def test_the_impact_update_with_fewer_sum_blocks_than_slots(threads, n: int) -> None:  # noqa: ANN001
    """assemble_and_update gives each slot a run of whole SUM_BLOCK-node blocks; with fewer
    blocks than slots (a coarse ball on several threads) some runs are empty. Undamped: the step
    is v + h f / m (to 1e-14), the slots are cleared, the kinetic energy and momentum are
    NumPy's to 1e-12 (each block's sums are in lanes of 8 nodes; 13 and 300 nodes leave a
    block a part-filled last lane), and the result is the same bits on any thread count."""
    ranges = np.array([[0, max(1, n // 2)], [n // 3, n], [0, n]])
    slots, mass, x0, v0 = slot_problem(np.random.default_rng(9), ranges, n)
    half = 0.5 * (DT_OLD + DT_NEW)
    v = v0 + ((slots[0] + slots[1]) + slots[2]) * (half / mass)[:, None]
    results = []
    for count in threads:
        numba.set_num_threads(count)
        work, points, velocities, sums = slots.copy(), x0.copy(), v0.copy(), np.zeros(6)
        assemble_and_update(work, ranges, mass, 0.0, DT_OLD, DT_NEW, points, velocities, sums,
                            (np.zeros(n), sum_blocks(n)))  # fmt: skip
        assert not work.any()
        np.testing.assert_allclose(velocities, v, rtol=1e-14, atol=1e-14)
        assert sums[0] == pytest.approx(0.5 * (mass * (velocities**2).sum(1)).sum(), rel=1e-12)
        np.testing.assert_allclose(sums[3:], (mass[:, None] * velocities).sum(0), rtol=1e-12)
        results.append((points, velocities, sums))
    for a, b in zip(results[0], results[-1], strict=True):
        np.testing.assert_array_equal(a, b)


def test_the_smallest_step_or_the_first_cell_that_has_none() -> None:
    steps = np.random.default_rng(11).uniform(1e-8, 1e-7, 1000)
    assert smallest_step(steps) == (steps.min(), -1)
    for bad in (0.0, -1e-9, np.nan):
        broken = steps.copy()
        broken[[7, 500]] = bad
        step, cell = smallest_step(broken)
        assert cell == 7 and (step == bad or np.isnan(bad) and np.isnan(step))


@pytest.mark.parametrize("rigid", [False, True])
@pytest.mark.parametrize("n_slots", [1, 2, 5])
def test_the_cycle_bookkeeping_is_numpys(rigid: bool, n_slots: int) -> None:
    rng = np.random.default_rng(n_slots)
    scale = 10.0 ** rng.integers(-6, 3, size=6)
    energies, increments = rng.normal(size=6) * scale, rng.normal(size=(n_slots, 3))
    ball, bat = rng.normal(size=7), rng.normal(size=5)
    kinetic0, time, mass, inertia = 39.8, 1.23e-4, 0.19, 0.031
    row = np.zeros(len(HISTORY_COLUMNS))
    got = energies.copy()
    balance = close_cycle(got, increments, ball, bat, rigid, kinetic0, time, mass, inertia, 12,
                          340, row)  # fmt: skip
    expected = energies.copy()
    expected[:3] += increments.sum(axis=0)
    if not rigid:
        expected[3] -= bat[0]
        expected[5] -= bat[4]
    expected[4] -= ball[0] + bat[1]
    kinetic = ball[1] + bat[2]
    expected_balance = kinetic + expected.sum() - kinetic0
    expected_row = (time, ball[6], *(ball[2:5] / mass), bat[3] / inertia, bat[3] + ball[5],
                    kinetic, *expected, expected_balance, 12, 340)  # fmt: skip
    np.testing.assert_array_equal(got, expected)
    assert balance == expected_balance
    np.testing.assert_array_equal(row, expected_row)
