"""Explicit internal forces of the layered Belytschko-Tsay shell (LS-DYNA ELFORM 2).

One in-plane integration point, one through-thickness point per layer (``*PART_COMPOSITE``,
:mod:`batball.elements.shell_bt_section`), co-rotational frame and Belytschko-Tsay hourglass
control; physics.md section 6.4, after Belytschko, Lin & Tsay (1984) and the LS-DYNA Theory
Manual (Hallquist 2006, section 7).

* Frame: e3 along r31 x r42, e1 along edge 1-2 projected on the plane, e2 = e3 x e1, rebuilt
  every step from the current coordinates (so rigid rotations strain nothing); nodes projected on
  the plane through the centroid give the local (x, y).
* Rotations are rotation-vector components, as in :mod:`batball.elements.shell_stiffness`: a
  point at height z moves by theta x z e3, i.e. u = u0 + z theta_y, v = v0 - z theta_x. So
  kappa_x = theta_y,x, kappa_y = -theta_x,y, 2 kappa_xy = theta_y,y - theta_x,x,
  gamma_xz = w,x + theta_y, gamma_yz = w,y - theta_x (the sign-flipped form of the LS-DYNA
  equations in physics.md, where M = -int z sigma dz; the two are the same element).
* Rate form: the strain rates at the centre (B1 = dN/dx, B2 = dN/dy) times dt update each layer's
  stress in the co-rotational frame, sigma_k += Qbar_k (d + z_k kappa_dot) dt, and the transverse
  shear force Q += H gamma_dot dt. Forces follow from virtual work on A (N . eps + M . kappa +
  Q . gamma); the drilling moment is zero (LS-DYNA m_z = 0).
* Hourglass: gamma_I = h_I - (h . x) B1_I - (h . y) B2_I with h = (1, -1, 1, -1); the hourglass
  rates q_M (in-plane, 2), q_B (rotations, 2), q_W (warping) are integrated into generalised
  stresses with the rate constants C_M = r A_max A (B.B)/8, C_B = r D_max A (B.B)/16,
  C_W = r H_max t^2 (B.B)/12: the physics.md constants E t A/8, E t^3 A/192, kappa G t^3/12 with
  E t, E t^3 / 12 and kappa G t replaced by the laminate's largest A, D and H diagonals.

With zero initial state, ``dt = 1`` and the velocities set to a small displacement field, one call
gives the linear internal force K_BT u (:func:`small_displacement_forces`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

from batball.elements.shell_bt_section import LayeredSection
from batball.numerics import FASTMATH

#: Belytschko-Tsay hourglass ratios r (membrane, bending, warping); physics.md section 6.4.
HOURGLASS_RATIO = 0.01
_HG = np.array([1.0, -1.0, 1.0, -1.0])


@dataclass(frozen=True)
class ShellForceState:
    """The evolving stresses of the layered BT shells (co-rotational frame), updated in place.

    Attributes:
        layer_stress: (sigma_xx, sigma_yy, sigma_xy) per layer, (n_cells, n_layers, 3), Pa.
        shear_force: transverse shear resultants (Q_x, Q_y), (n_cells, 2), N/m.
        hourglass: generalised hourglass stresses (membrane x, y; bending x, y; warping),
            (n_cells, 5), N, N m, N.
    """

    layer_stress: np.ndarray
    shear_force: np.ndarray
    hourglass: np.ndarray


def initial_force_state(section: LayeredSection) -> ShellForceState:
    """A stress-free state for every cell of ``section``."""
    n_cells, n_layers = section.n_cells, section.layer_z.shape[1]
    return ShellForceState(np.zeros((n_cells, n_layers, 3)), np.zeros((n_cells, 2)),
                           np.zeros((n_cells, 5)))  # fmt: skip


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
def bt_force_kernel(points: np.ndarray, cells: np.ndarray, velocity: np.ndarray, dt: float,
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


def bt_internal_forces(
    points: np.ndarray,
    cells: np.ndarray,
    section: LayeredSection,
    velocity: np.ndarray,
    dt: float,
    state: ShellForceState,
    *,
    hourglass_ratio: float = HOURGLASS_RATIO,
) -> np.ndarray:
    """Internal force vector of the BT shells after advancing their stresses by one step.

    Args:
        points: current node coordinates, (n_points, 3), m.
        cells: (n_cells, 4) node indices.
        section: layer data of the cells.
        velocity: (v_x, v_y, v_z, omega_x, omega_y, omega_z) per node (global axes, the
            mid-step velocities of the central-difference scheme), (n_points, 6), m/s and rad/s.
        dt: time step, s.
        state: the cells' stresses, updated in place.
        hourglass_ratio: r of the Belytschko-Tsay hourglass constants.

    Returns:
        f_int, forces and moments on the nodes, (n_points, 6), N and N m (M a = f_ext - f_int).
    """
    forces = np.empty((cells.shape[0], 4, 6))
    bt_force_kernel(np.ascontiguousarray(points, dtype=np.float64), cells.astype(np.int64),
                    np.ascontiguousarray(velocity, dtype=np.float64), float(dt),
                    section.cell_laminate, section.layer_stiffness, section.layer_z,
                    section.layer_thickness, section.shear, section.hourglass_moduli,
                    float(hourglass_ratio), state.layer_stress, state.shear_force,
                    state.hourglass, forces)  # fmt: skip
    dofs = (6 * cells[:, :, None] + np.arange(6)).ravel()
    summed = np.bincount(dofs, weights=forces.ravel(), minlength=6 * points.shape[0])
    return summed.reshape(points.shape[0], 6)


def small_displacement_forces(
    points: np.ndarray, cells: np.ndarray, section: LayeredSection, displacement: np.ndarray,
    *, hourglass_ratio: float = HOURGLASS_RATIO,
) -> np.ndarray:  # fmt: skip
    """Linear internal force K_BT u of a small displacement and rotation field from rest.

    Args:
        points: reference coordinates, (n_points, 3), m.
        cells: (n_cells, 4).
        section: layer data.
        displacement: (u_x, u_y, u_z, theta_x, theta_y, theta_z), (n_points, 6), m and rad.

    Returns:
        (n_points, 6), N and N m.
    """
    state = initial_force_state(section)
    return bt_internal_forces(points, cells, section, displacement, 1.0, state,
                              hourglass_ratio=hourglass_ratio)  # fmt: skip
