"""The foam law for a block of points at once gives each point the bits of the one-point law."""

from __future__ import annotations

import numpy as np
import pytest

from batball.materials.foam import P_E, P_TC
from batball.materials.foam_update import (
    EIGEN_LANES,
    EIGEN_V,
    H_RATE,
    H_WMAX,
    LAW_D,
    LAW_LOADING,
    LAW_RATE,
    LAW_SIGMA,
    LAW_TANGENT,
    LAW_WMAX,
    N_HISTORY,
    block_principal_stress,
    block_symmetric_eigen,
    eigen_block,
    law_block,
    principal_stress,
)
from batball.specs import MaterialSpec, load_ball_spec

N_POINTS = 320
WEIGHT = 0.3  # the rate filter's weight of a step's new rate


def _material(name: str, **changes: float) -> MaterialSpec:
    material = load_ball_spec(name).material
    return MaterialSpec(
        law=material.law, values=dict(material.values) | changes, curves=material.curves
    )


def _points(rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    """b = F F^T (n, 3, 3) of small, moderate and large deformations (compression past the
    curve's last point and tension past TC among them) and the exact cases b = I and diagonal;
    D (n, 6) [1/s] (a fifth zero); the stored filtered rate [1/s] and W_max [J/m^3] (a third of
    W_max zero, a third large enough that the point unloads)."""
    f = np.eye(3) + rng.normal(0.0, 0.15, (N_POINTS, 3, 3))
    f[:80] = np.eye(3) + rng.normal(0.0, 1e-4, (80, 3, 3))
    f[80:110] = np.diag([0.5, 1.0, 1.0]) + rng.normal(0.0, 0.05, (30, 3, 3))
    f[110:130] = np.diag([0.01, 1.0, 1.0]) + rng.normal(0.0, 0.002, (20, 3, 3))
    f[130:150] = np.diag([1.6, 1.0, 1.0]) + rng.normal(0.0, 0.05, (20, 3, 3))
    b = np.einsum("nij,nkj->nik", f, f)
    b[-3:] = [np.eye(3), np.diag([0.09, 1.0, 1.0]), np.diag([4.0, 0.25, 1.0])]
    d = rng.normal(0.0, 300.0, (N_POINTS, 6))
    d[::5] = 0.0
    rate = np.abs(rng.normal(0.0, 500.0, N_POINTS))
    rate[::7] = 0.0
    w_max = np.abs(rng.normal(0.0, 2e4, N_POINTS))
    w_max[::3] = 0.0
    w_max[1::3] *= 50.0
    return b, d, rate, w_max


def _one_point(b, vectors, d, rate, w_max, table):
    """The one-point law: (sigma (9,), tangent, new rate, new W_max)."""
    dd = d
    d_full = np.array([[dd[0], dd[3], dd[5]], [dd[3], dd[1], dd[4]], [dd[5], dd[4], dd[2]]])
    history = np.zeros(N_HISTORY)
    history[H_RATE], history[H_WMAX] = rate, w_max
    scratch = np.zeros((6, 3, 3))
    tangent = principal_stress(b.copy(), vectors.copy(), d_full, WEIGHT, history, table, scratch)
    return scratch[3].reshape(9).copy(), tangent, history[H_RATE], history[H_WMAX]


def _run(table, b, d, rate, w_max, lanes):
    """The block law over consecutive groups of ``lanes`` points (the rest of a block holds
    what the previous group left there, as in the kernel): the points whose results differ
    from the one-point law's in any bit, how many unloaded, and the filtered rates."""
    eig, law = eigen_block(), law_block()
    eig_rows, law_rows = eig.reshape(-1, EIGEN_LANES), law.reshape(-1, EIGEN_LANES)
    mismatched, unloading, rates_seen = [], 0, []
    for start in range(0, len(b), lanes):
        n = min(lanes, len(b) - start)
        points = slice(start, start + n)
        eig_rows[:9, :n] = b[points].reshape(n, 9).T
        block_symmetric_eigen(eig, n)
        law_rows[LAW_D : LAW_D + 6, :n] = d[points].T
        law_rows[LAW_RATE, :n], law_rows[LAW_WMAX, :n] = rate[points], w_max[points]
        block_principal_stress(law, eig, n, WEIGHT, table)
        for lane in range(n):
            expected = _one_point(
                eig_rows[:9, lane].reshape(3, 3),
                eig_rows[EIGEN_V : EIGEN_V + 9, lane].reshape(3, 3),
                d[start + lane], rate[start + lane], w_max[start + lane], table,
            )  # fmt: skip
            got = (law_rows[LAW_SIGMA : LAW_SIGMA + 9, lane], law_rows[LAW_TANGENT, lane],
                   law_rows[LAW_RATE, lane], law_rows[LAW_WMAX, lane])  # fmt: skip
            if not all(
                np.array_equal(g, x, equal_nan=True) for g, x in zip(got, expected, strict=True)
            ):
                mismatched.append(start + lane)
        unloading += int(np.sum(law_rows[LAW_LOADING, :n] == 0.0))
        rates_seen.extend(law_rows[LAW_RATE, :n])
    return mismatched, unloading, np.array(rates_seen)


MATERIALS = [("type1-fit", {}), ("foam057", {}), ("foam083", {}), ("foam083", {"rate_filter": 1e9})]


@pytest.mark.parametrize(("name", "changes"), MATERIALS)
@pytest.mark.parametrize("lanes", [1, 7, EIGEN_LANES])
def test_a_block_gives_each_point_the_bits_of_one_at_a_time(
    name: str, changes: dict[str, float], lanes: int
) -> None:
    """Each lane does the one-point law's operations in the same order (its branches as
    selects, its curve scans a point at a time across the lanes; no fast-math in either), so
    sigma, the tangent, the filtered rate and W_max agree bit for bit. The points cover both
    sides of every branch: tension below and above TC, compression on and past the curve,
    loading and unloading, and (MAT_083) rates below, between and above the rate curves."""
    # a tension cut-off that the stretched points pass (the example balls' is out of reach)
    table = _material(name, tension_cutoff=1e6, **changes).foam_table().arrays()
    b, d, rate, w_max = _points(np.random.default_rng(3))
    mismatched, unloading, rates_seen = _run(table, b, d, rate, w_max, lanes)
    assert mismatched == []
    # the inputs reach both sides of the branches
    strains = np.sqrt(np.linalg.eigvalsh(b)) - 1.0
    young, cutoff = table[0][P_E], table[0][P_TC]
    assert np.sum(strains < 0.0) > 100 and np.sum(young * strains > cutoff) > 10
    assert np.sum(-strains > table[2][0][table[4][0] - 1]) > 10  # past the curve's last point
    assert 10 < unloading < N_POINTS - 10
    curve_rates = table[1]
    if len(curve_rates) > 1 and changes:
        between = (rates_seen > curve_rates[0]) & (rates_seen < curve_rates[-1])
        assert np.sum(between) > 10 and np.sum(rates_seen >= curve_rates[-1]) > 0


@pytest.mark.parametrize(("name", "changes"), MATERIALS)
def test_a_failing_point_gives_the_one_point_bits_too(name: str, changes: dict[str, float]) -> None:
    """NaN and infinite input (a run going unstable) gives each lane what the one-point law
    gives, NaN included, so the solver's checks see the same values; the block's curve and
    rate indices are counts of comparisons, so they stay inside the tables."""
    table = _material(name, **changes).foam_table().arrays()
    rng = np.random.default_rng(5)
    b, d, rate, w_max = (x[:64] for x in _points(rng))
    b[0:4] = np.nan
    b[4:8, 0, 0] = np.inf
    b[8:12, 1, 1] = -1.0
    d[12:20] = np.nan
    rate[20:28] = np.nan
    rate[28:32] = np.inf
    w_max[32:40] = np.nan
    assert _run(table, b, d, rate, w_max, EIGEN_LANES)[0] == []
