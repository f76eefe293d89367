"""The explicit solver's step choice (solvers/explicit_kernels.next_step): TSSFAC times the
smallest element step, the first such element named when the step fails; a zero step (an
element without positive volume) is FAIL_INVERTED, a NaN step FAIL_NON_FINITE, a step below
MIN_STEP_RATIO of the first FAIL_STEP_COLLAPSE. The expectations are NumPy's min and argmin."""

from __future__ import annotations

import numpy as np
import pytest

from batball.solvers import explicit_kernels as kern


def _limits(tssfac: float = 0.9, min_ratio: float = 0.1) -> np.ndarray:
    limits = np.zeros(8)
    limits[kern.TSSFAC] = tssfac
    limits[kern.MIN_STEP_RATIO] = min_ratio
    return limits


def _choose(cell_dt: np.ndarray, first_dt: float = 0.0) -> tuple[float, np.ndarray, np.ndarray]:
    clock, counters = np.zeros(5), np.full(2, -7, dtype=np.int64)
    clock[kern.FIRST_DT] = first_dt
    return kern.next_step(cell_dt, clock, counters, _limits()), clock, counters


@pytest.mark.parametrize("n", [1, 2, 7, 16, 33, 1000])
def test_the_step_is_tssfac_times_the_smallest_and_the_first_step_is_kept(n: int) -> None:
    rng = np.random.default_rng(n)
    cell_dt = rng.uniform(1e-7, 2e-7, n)
    dt, clock, counters = _choose(cell_dt)
    assert dt == 0.9 * cell_dt.min()
    assert clock[kern.FIRST_DT] == dt
    assert counters[kern.ELEMENT] == -7  # named only when the step fails
    dt, clock, _ = _choose(cell_dt, first_dt=1e-7)
    assert dt == 0.9 * cell_dt.min() and clock[kern.FIRST_DT] == 1e-7


@pytest.mark.parametrize("bad", [0.0, -0.0])
def test_a_zero_step_is_an_inverted_element_the_first_such_named(bad: float) -> None:
    cell_dt = np.linspace(1e-7, 2e-7, 50)
    cell_dt[[17, 31]] = bad
    status, _, counters = _choose(cell_dt)
    assert status == kern.FAIL_INVERTED and counters[kern.ELEMENT] == 17


@pytest.mark.parametrize("nan", [np.nan, -np.nan])
def test_a_nan_step_is_non_finite_the_first_nan_named(nan: float) -> None:
    cell_dt = np.linspace(1e-7, 2e-7, 50)
    cell_dt[[23, 40]] = nan
    cell_dt[30] = 0.0  # a NaN is reported before a zero step
    status, _, counters = _choose(cell_dt)
    assert status == kern.FAIL_NON_FINITE and counters[kern.ELEMENT] == 23


def test_a_collapsed_step_names_the_first_smallest_element() -> None:
    cell_dt = np.full(40, 1e-7)
    cell_dt[[9, 12]] = 1e-9  # 0.9e-9 < 0.1 x the first step 1e-7
    clock, counters = np.zeros(5), np.zeros(2, dtype=np.int64)
    clock[kern.FIRST_DT] = 1e-7
    status = kern.next_step(cell_dt, clock, counters, _limits())
    assert status == kern.FAIL_STEP_COLLAPSE and counters[kern.ELEMENT] == 9
    assert clock[kern.DT] == 0.9 * 1e-9
