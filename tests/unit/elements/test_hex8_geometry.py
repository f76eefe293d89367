"""Hex8 volume derivatives against finite differences of the exact (Gauss-quadrature) volume."""

from __future__ import annotations

import numba as nb
import numpy as np
import pytest

from batball.elements.hex8_geometry import (
    REFERENCE_CORNERS,
    largest_face_area,
    modal_largest_face_area,
    modal_sums,
    modal_volume_gradient,
    nodal_sums,
    volume_derivatives,
)

GAUSS = 1.0 / np.sqrt(3.0)


def gauss_volume(x: np.ndarray) -> float:
    """Volume of a trilinear hex (8, 3) by 2x2x2 Gauss quadrature of det J (exact)."""
    signs = REFERENCE_CORNERS
    total = 0.0
    for xi in np.array(np.meshgrid(*[[-GAUSS, GAUSS]] * 3)).reshape(3, -1).T:
        dn = np.empty((8, 3))
        for a in range(3):
            factors = 1.0 + signs * xi
            factors[:, a] = signs[:, a]
            dn[:, a] = np.prod(factors, axis=1) / 8.0
        total += np.linalg.det(x.T @ dn)
    return float(total)


def distorted_hex(seed: int, offset: float = 0.0) -> np.ndarray:
    """A hex (8, 3) [m] about 2 x 3 x 1.5 cm, its corners moved randomly by up to ~15 %."""
    rng = np.random.default_rng(seed)
    x = 0.5 * (REFERENCE_CORNERS + 1.0) * [0.02, 0.03, 0.015]
    return x + 0.002 * rng.standard_normal((8, 3)) + offset


@nb.njit
def node_wise(x: np.ndarray) -> tuple[np.ndarray, float, float]:
    b = np.empty(24)
    volume = volume_derivatives(x.ravel(), b)
    return b.reshape((8, 3)), volume, largest_face_area(x.ravel())


@nb.njit
def modal(x: np.ndarray) -> tuple[np.ndarray, float, float]:
    sx = modal_sums(x[0, 0], x[1, 0], x[2, 0], x[3, 0], x[4, 0], x[5, 0], x[6, 0], x[7, 0])
    sy = modal_sums(x[0, 1], x[1, 1], x[2, 1], x[3, 1], x[4, 1], x[5, 1], x[6, 1], x[7, 1])
    sz = modal_sums(x[0, 2], x[1, 2], x[2, 2], x[3, 2], x[4, 2], x[5, 2], x[6, 2], x[7, 2])
    m = [(sx[k], sy[k], sz[k]) for k in range(7)]
    g1, g2, g3, g4, g5, g6, volume = modal_volume_gradient(m[0], m[1], m[2], m[3], m[4], m[5])
    g = (g1, g2, g3, g4, g5, g6)
    b = np.empty((8, 3))
    for i in range(3):
        f = nodal_sums(g[0][i], g[1][i], g[2][i], g[3][i], g[4][i], g[5][i], 0.0)
        for a in range(8):
            b[a, i] = f[a]
    return b, volume, modal_largest_face_area(m[0], m[1], m[2], m[3], m[4], m[5])


def finite_difference_gradient(x: np.ndarray, step: float = 1e-6) -> np.ndarray:
    """dV/dx (8, 3) by central differences of the Gauss-quadrature volume (exact to O(step^2))."""
    grad = np.empty((8, 3))
    for a in range(8):
        for i in range(3):
            plus, minus = x.copy(), x.copy()
            plus[a, i] += step
            minus[a, i] -= step
            grad[a, i] = (gauss_volume(plus) - gauss_volume(minus)) / (2.0 * step)
    return grad


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_volume_derivatives_match_finite_differences_of_the_exact_volume(seed: int) -> None:
    x = distorted_hex(seed)
    b, volume, _ = node_wise(x)
    expected = finite_difference_gradient(x)
    # V is cubic in x, so the central difference is exact up to step^2 * |d3V| and round-off
    assert np.abs(b - expected).max() < 1e-7 * np.abs(expected).max()
    assert volume == pytest.approx(gauss_volume(x), rel=1e-12)


@pytest.mark.parametrize("seed", [3, 4, 5])
def test_modal_form_gives_the_same_derivatives_volume_and_face_area(seed: int) -> None:
    x = distorted_hex(seed, offset=0.05)  # away from the origin, as in a real mesh
    b_node, volume_node, area_node = node_wise(x)
    b_modal, volume_modal, area_modal = modal(x)
    assert np.abs(b_modal - b_node).max() < 1e-13 * np.abs(b_node).max()
    assert volume_modal == pytest.approx(volume_node, rel=1e-12)
    assert area_modal == pytest.approx(area_node, rel=1e-14)


def test_unit_cube_face_area_and_derivatives() -> None:
    b, volume, area = modal(0.5 * (REFERENCE_CORNERS + 1.0))
    assert volume == pytest.approx(1.0, abs=1e-15)
    assert area == pytest.approx(1.0, abs=1e-15)
    # dV/dx_a of the unit cube: a quarter of each of the three faces at the corner, outward
    np.testing.assert_allclose(b, 0.25 * REFERENCE_CORNERS, atol=1e-15)


@nb.njit
def transforms(c: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    modes = np.array(modal_sums(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]))
    nodes = np.array(nodal_sums(f[0], f[1], f[2], f[3], f[4], f[5], f[6]))
    return modes, nodes


def test_nodal_sums_are_the_transpose_of_modal_sums() -> None:
    # <H c, f> = <c, H^T f> with H the (7, 8) corner signs of the modes xi .. xi eta zeta
    rng = np.random.default_rng(11)
    c, f = rng.standard_normal(8), rng.standard_normal(7)
    modes, nodes = transforms(c, f)
    assert modes @ f == pytest.approx(c @ nodes, rel=1e-13)
    xi, eta, zeta = REFERENCE_CORNERS.T
    signs = np.array([xi, eta, zeta, eta * zeta, zeta * xi, xi * eta, xi * eta * zeta])
    np.testing.assert_allclose(modes, signs @ c, rtol=1e-14, atol=1e-14)
