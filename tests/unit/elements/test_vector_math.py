"""The vectorisable ln and cube root against NumPy (the C library) over the whole double range."""

from __future__ import annotations

import numba as nb
import numpy as np

from batball.elements.vector_math import cbrt, log
from batball.numerics import FASTMATH


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def log_all(x: np.ndarray) -> np.ndarray:
    out = np.empty_like(x)
    for i in range(x.shape[0]):
        out[i] = log(x[i])
    return out


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def cbrt_all(x: np.ndarray) -> np.ndarray:
    out = np.empty_like(x)
    for i in range(x.shape[0]):
        out[i] = cbrt(x[i])
    return out


def samples() -> np.ndarray:
    """Positive doubles from the smallest subnormal to the largest finite, dense near 1."""
    rng = np.random.default_rng(5)
    largest = np.finfo(np.float64).max
    edges = [5e-324, 1e-310, np.finfo(np.float64).smallest_normal, 0.5, 1.0, 2.0, 2**0.5, largest]
    return np.concatenate(
        [
            np.exp(rng.uniform(-744.0, 709.0, 100_000)),
            1.0 + rng.uniform(-0.5, 0.5, 100_000),
            1.0 + 1e-9 * rng.standard_normal(1_000),
            edges,
        ]
    )


def ulps(actual: np.ndarray, expected: np.ndarray) -> np.ndarray:
    return np.abs(actual - expected) / np.spacing(np.abs(expected))


def test_log_is_within_two_ulp_of_the_c_library() -> None:
    x = samples()
    assert ulps(log_all(x), np.log(x)).max() <= 2.0  # fast math may contract the sum into FMAs


def test_cbrt_is_within_one_ulp_of_the_c_library_for_both_signs() -> None:
    x = samples()
    x = np.concatenate([x, -x])
    assert ulps(cbrt_all(x), np.cbrt(x)).max() <= 1.0


def test_special_values_follow_the_c_library() -> None:
    x = np.array([0.0, np.inf, -np.inf, np.nan, -1.0])
    with np.errstate(divide="ignore", invalid="ignore"):
        np.testing.assert_array_equal(log_all(x), np.log(x))
    np.testing.assert_array_equal(cbrt_all(x), np.cbrt(x))
