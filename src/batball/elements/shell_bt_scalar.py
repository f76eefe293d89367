"""The layered Belytschko-Tsay shell's force kernel as one scalar loop over the cells.

This is the kernel :mod:`batball.elements.shell_bt` ran before its blocked (SIMD) form, kept
unchanged as the reference the blocked kernel is tested against
(``tests/unit/elements/test_shell_bt_kernel.py``): the same element (see that module's docs),
written per cell with small work arrays.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from batball.numerics import FASTMATH

_HG = np.array([1.0, -1.0, 1.0, -1.0])


@nb.njit(inline="always", fastmath=FASTMATH)
def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for two 3-vectors."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])  # fmt: skip


@nb.njit(inline="always", fastmath=FASTMATH)
def rotate(frame: np.ndarray, vector: np.ndarray, out: np.ndarray, transpose: bool) -> None:
    """out = frame @ vector (to the element frame) or frame.T @ vector (back), 3-vectors."""
    for a in range(3):
        total = 0.0
        for k in range(3):
            total += (frame[k, a] if transpose else frame[a, k]) * vector[k]
        out[a] = total


@nb.njit(inline="always", fastmath=FASTMATH)
def element_geometry(x: np.ndarray, frame: np.ndarray, b: np.ndarray) -> float:
    """Frame rows e1, e2, e3 into ``frame`` (3, 3), B1, B2 into ``b`` (2, 4); returns the area.

    Args:
        x: current node coordinates (4, 3), m; overwritten by the local coordinates (x, y, z).
    """
    # scalar arithmetic: no temporary arrays in the per-cell loop (they cost more than the math)
    a0, a1, a2 = x[2, 0] - x[0, 0], x[2, 1] - x[0, 1], x[2, 2] - x[0, 2]  # r31
    c0, c1, c2 = x[3, 0] - x[1, 0], x[3, 1] - x[1, 1], x[3, 2] - x[1, 2]  # r42
    n0, n1, n2 = a1 * c2 - a2 * c1, a2 * c0 - a0 * c2, a0 * c1 - a1 * c0  # e3 = r31 x r42
    norm = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    n0, n1, n2 = n0 / norm, n1 / norm, n2 / norm
    d0, d1, d2 = x[1, 0] - x[0, 0], x[1, 1] - x[0, 1], x[1, 2] - x[0, 2]  # edge 1-2
    along = d0 * n0 + d1 * n1 + d2 * n2
    d0, d1, d2 = d0 - along * n0, d1 - along * n1, d2 - along * n2
    norm = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    d0, d1, d2 = d0 / norm, d1 / norm, d2 / norm  # e1
    frame[0, 0], frame[0, 1], frame[0, 2] = d0, d1, d2
    frame[1, 0], frame[1, 1], frame[1, 2] = n1 * d2 - n2 * d1, n2 * d0 - n0 * d2, n0 * d1 - n1 * d0
    frame[2, 0], frame[2, 1], frame[2, 2] = n0, n1, n2
    m0 = 0.25 * (x[0, 0] + x[1, 0] + x[2, 0] + x[3, 0])
    m1 = 0.25 * (x[0, 1] + x[1, 1] + x[2, 1] + x[3, 1])
    m2 = 0.25 * (x[0, 2] + x[1, 2] + x[2, 2] + x[3, 2])
    for i in range(4):
        r0, r1, r2 = x[i, 0] - m0, x[i, 1] - m1, x[i, 2] - m2
        for a in range(3):
            x[i, a] = frame[a, 0] * r0 + frame[a, 1] * r1 + frame[a, 2] * r2
    area = 0.5 * ((x[2, 0] - x[0, 0]) * (x[3, 1] - x[1, 1])
                  + (x[1, 0] - x[3, 0]) * (x[2, 1] - x[0, 1]))  # fmt: skip
    half = 0.5 / area
    b[0, 0], b[0, 1] = half * (x[1, 1] - x[3, 1]), half * (x[2, 1] - x[0, 1])
    b[0, 2], b[0, 3] = half * (x[3, 1] - x[1, 1]), half * (x[0, 1] - x[2, 1])
    b[1, 0], b[1, 1] = half * (x[3, 0] - x[1, 0]), half * (x[0, 0] - x[2, 0])
    b[1, 2], b[1, 3] = half * (x[1, 0] - x[3, 0]), half * (x[2, 0] - x[0, 0])
    return area


@nb.njit(inline="always", fastmath=FASTMATH)
def strain_rates(v: np.ndarray, b: np.ndarray, rates: np.ndarray) -> None:
    """Membrane (3), curvature (3) and transverse shear (2) rates into ``rates`` (8,).

    Args:
        v: local velocities (4, 6): v_x, v_y, v_z (m/s), omega_x, omega_y, omega_z (rad/s).
        b: B1, B2 (2, 4), 1/m.
    """
    rates[:] = 0.0
    for i in range(4):
        b1, b2 = b[0, i], b[1, i]
        rates[0] += b1 * v[i, 0]
        rates[1] += b2 * v[i, 1]
        rates[2] += b2 * v[i, 0] + b1 * v[i, 1]
        rates[3] += b1 * v[i, 4]
        rates[4] -= b2 * v[i, 3]
        rates[5] += b2 * v[i, 4] - b1 * v[i, 3]
        rates[6] += b1 * v[i, 2] + 0.25 * v[i, 4]
        rates[7] += b2 * v[i, 2] - 0.25 * v[i, 3]


@nb.njit(inline="always", fastmath=FASTMATH)
def layer_resultants(stress: np.ndarray, q: np.ndarray, z: np.ndarray, t: np.ndarray,
                     rates: np.ndarray, dt: float, resultants: np.ndarray) -> None:  # fmt: skip
    """Update each layer's stress (n_layers, 3) by Qbar_k (d + z_k kappa) dt; N, M into
    ``resultants[0:6]`` (N/m, N)."""
    resultants[:6] = 0.0
    for k in range(z.size):
        for i in range(3):
            rate = 0.0
            for j in range(3):
                rate += q[k, i, j] * (rates[j] + z[k] * rates[3 + j])
            stress[k, i] += rate * dt
            resultants[i] += t[k] * stress[k, i]
            resultants[3 + i] += z[k] * t[k] * stress[k, i]


@nb.njit(inline="always", fastmath=FASTMATH)
def hourglass_update(x: np.ndarray, b: np.ndarray, v: np.ndarray, area: float,
                     moduli: np.ndarray, ratio: float, dt: float, hg: np.ndarray,
                     gamma: np.ndarray) -> None:  # fmt: skip
    """Hourglass shape vector into ``gamma`` (4,) and the generalised stresses ``hg`` (5,)."""
    hx = x[0, 0] - x[1, 0] + x[2, 0] - x[3, 0]
    hy = x[0, 1] - x[1, 1] + x[2, 1] - x[3, 1]
    bb = 0.0
    for i in range(4):
        gamma[i] = _HG[i] - hx * b[0, i] - hy * b[1, i]
        bb += b[0, i] ** 2 + b[1, i] ** 2
    c_m = ratio * moduli[0] * area * bb / 8.0
    c_b = ratio * moduli[1] * area * bb / 16.0
    c_w = ratio * moduli[2] * moduli[3] ** 2 * bb / 12.0
    for i in range(4):
        g = gamma[i] * dt
        hg[0] += c_m * g * v[i, 0]
        hg[1] += c_m * g * v[i, 1]
        hg[2] += c_b * g * v[i, 3]
        hg[3] += c_b * g * v[i, 4]
        hg[4] += c_w * g * v[i, 2]


@nb.njit(inline="always", fastmath=FASTMATH)
def local_nodal_forces(b: np.ndarray, area: float, r: np.ndarray, shear: np.ndarray,
                       hg: np.ndarray, gamma: np.ndarray, f: np.ndarray) -> None:  # fmt: skip
    """Forces and moments (4, 6) in the element frame from N, M (``r``), Q and hourglass."""
    for i in range(4):
        b1, b2, g = b[0, i], b[1, i], gamma[i]
        f[i, 0] = area * (b1 * r[0] + b2 * r[2]) + g * hg[0]
        f[i, 1] = area * (b2 * r[1] + b1 * r[2]) + g * hg[1]
        f[i, 2] = area * (b1 * shear[0] + b2 * shear[1]) + g * hg[4]
        f[i, 3] = area * (-b2 * r[4] - b1 * r[5] - 0.25 * shear[1]) + g * hg[2]
        f[i, 4] = area * (b1 * r[3] + b2 * r[5] + 0.25 * shear[0]) + g * hg[3]
        f[i, 5] = 0.0


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def bt_force_kernel_scalar(points: np.ndarray, cells: np.ndarray, velocity: np.ndarray, dt: float,
                    cell_laminate: np.ndarray, layer_stiffness: np.ndarray,
                    layer_z: np.ndarray, layer_thickness: np.ndarray, shear: np.ndarray,
                    moduli: np.ndarray, ratio: float, layer_stress: np.ndarray,
                    shear_force: np.ndarray, hourglass: np.ndarray,
                    forces: np.ndarray) -> None:  # fmt: skip
    """Advance every cell's stresses by dt and write its nodal forces (n_cells, 4, 6), global.

    The cells run in parallel chunks; a cell writes only its own rows, so there is no race and
    the result does not depend on the number of threads."""
    n_cells = cells.shape[0]
    n_chunks = max(1, min(n_cells, 64))  # enough for the threads' load balance
    for chunk in nb.prange(n_chunks):
        x, v, f = np.empty((4, 3)), np.empty((4, 6)), np.empty((4, 6))
        frame, b = np.empty((3, 3)), np.empty((2, 4))
        rates, resultants, gamma = np.empty(8), np.empty(6), np.empty(4)
        for c in range(chunk * n_cells // n_chunks, (chunk + 1) * n_cells // n_chunks):
            for i in range(4):
                x[i] = points[cells[c, i]]
            area = element_geometry(x, frame, b)
            for i in range(4):
                rotate(frame, velocity[cells[c, i], :3], v[i, :3], False)
                rotate(frame, velocity[cells[c, i], 3:], v[i, 3:], False)
            strain_rates(v, b, rates)
            lam = cell_laminate[c]
            layer_resultants(layer_stress[c], layer_stiffness[lam], layer_z[lam],
                             layer_thickness[lam], rates, dt, resultants)  # fmt: skip
            h = shear[lam]
            shear_force[c, 0] += (h[0, 0] * rates[6] + h[0, 1] * rates[7]) * dt
            shear_force[c, 1] += (h[1, 0] * rates[6] + h[1, 1] * rates[7]) * dt
            hourglass_update(x, b, v, area, moduli[lam], ratio, dt, hourglass[c], gamma)
            local_nodal_forces(b, area, resultants, shear_force[c], hourglass[c], gamma, f)
            for i in range(4):
                rotate(frame, f[i, :3], forces[c, i, :3], True)
                rotate(frame, f[i, 3:], forces[c, i, 3:], True)
