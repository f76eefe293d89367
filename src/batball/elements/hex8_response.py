"""Pointwise response of the one-point hex on x^n: pressure, bulk viscosity, hourglass control,
nodal forces and the stable step, as Numba functions on scalars and tuples.

Everything is written on the element's modal sums (``hex8_geometry``): X_k and V_k of the node
coordinates and velocities, G_k = dV/dX_k, with modes 4..7 the hourglass base vectors Gamma.
Then B_a = sum_k H_ka G_k, sum_a |B_a|^2 = 8 sum_k |G_k|^2 and sum_a v_a Gamma_ma = V_(m+4).
The Flanagan-Belytschko vectors gamma_ma = Gamma_ma - X_(m+4) . B_a / V give the rate
V_(m+4) - L X_(m+4) (L on x^n) and the forces Q_m Gamma_ma - (sum_m Q_m X_(m+4)^T / V) B_a.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from batball.elements.hex8_geometry import dot, nodal_sums
from batball.elements.hex8_kinematics import Modes, Tensor, Voigt, velocity_gradient
from batball.elements.vector_math import cbrt, like, log
from batball.numerics import FASTMATH


@nb.njit(inline="always", fastmath=FASTMATH)
def pressure_and_viscosity(
    vol: float,
    v0: float,
    rho0: float,
    bulk_modulus: float,
    modulus: float,
    trd: float,
    q1: float,
    q2: float,
) -> tuple[float, float, float, float, float]:
    """Density [kg/m^3], wave speed [m/s], p = K ln(V0/V) [Pa], q [Pa] and l = V^(1/3) [m].

    q = rho l (Q1 l tr(D)^2 - Q2 c tr(D)) under compression (LS-DYNA's bulk viscosity).
    """
    ratio = v0 / vol
    rho = rho0 * ratio
    c = np.sqrt(modulus / rho)
    p = bulk_modulus * log(ratio)
    length = cbrt(vol)
    zero = like(vol, 0.0)
    bulk_q = rho * length * (q1 * length * trd * trd - q2 * c * trd) if trd < zero else zero
    return rho, c, p, bulk_q, length


@nb.njit(inline="always", fastmath=FASTMATH)
def _hourglass_coefficient(g, vol, rho, c, length, hg_coefficient, stiff):
    """kappa = QM rho c^2 sum_a |B_a|^2 / (3 V) [N/m] or a_h = QH rho V^(2/3) c / 4 [N s/m]."""
    if stiff:
        bb = dot(g[0], g[0]) + dot(g[1], g[1]) + dot(g[2], g[2])
        bb += dot(g[3], g[3]) + dot(g[4], g[4]) + dot(g[5], g[5])
        return hg_coefficient * rho * c * c * (like(bb, 8.0) * bb) / (like(vol, 3.0) * vol)
    return hg_coefficient * rho * length * length * c / like(c, 4.0)


@nb.njit(inline="always", fastmath=FASTMATH)
def _mode_rate(v, x, lc, fb):
    """Hourglass rate of one mode: V_k, less L X_k for the Flanagan-Belytschko gamma [m/s]."""
    if not fb:
        return v
    return (
        v[0] - (lc[0] * x[0] + lc[1] * x[1] + lc[2] * x[2]),
        v[1] - (lc[3] * x[0] + lc[4] * x[1] + lc[5] * x[2]),
        v[2] - (lc[6] * x[0] + lc[7] * x[1] + lc[8] * x[2]),
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _mode_force(old, rate, coefficient, dt, stiff):
    """Generalised force of one mode [N] and its work over the step [J].

    Viscous: coefficient rate. Stiffness: the stored force ``old`` plus coefficient dt rate.
    """
    if stiff:
        new = (
            old[0] + coefficient * dt * rate[0],
            old[1] + coefficient * dt * rate[1],
            old[2] + coefficient * dt * rate[2],
        )
        half = like(dt, 0.5)
        mean = (half * (old[0] + new[0]), half * (old[1] + new[1]), half * (old[2] + new[2]))
        return new, dot(mean, rate) * dt
    force = (coefficient * rate[0], coefficient * rate[1], coefficient * rate[2])
    return force, dot(force, rate) * dt


@nb.njit(inline="always", fastmath=FASTMATH)
def hourglass_forces(
    g: Modes,
    v: Modes,
    x: Modes,
    hg_old: Modes,
    vol: float,
    rho: float,
    c: float,
    length: float,
    dt: float,
    hg_coefficient: float,
    fb: bool,
    stiff: bool,
) -> tuple[Modes, float]:
    """Generalised forces Q_m of the four hourglass modes (3-tuples) [N] and their work [J].

    LS-DYNA IHQ 1 (viscous on Gamma: not fb), 2/3 (viscous on gamma: fb) and 4/5 (stiffness on
    gamma: fb and stiff, ``hg_old`` the stored forces).
    """
    coefficient = _hourglass_coefficient(g, vol, rho, c, length, hg_coefficient, stiff)
    lc = velocity_gradient(v, g, vol)  # on x^n, for gamma
    f0, w0 = _mode_force(hg_old[0], _mode_rate(v[3], x[3], lc, fb), coefficient, dt, stiff)
    f1, w1 = _mode_force(hg_old[1], _mode_rate(v[4], x[4], lc, fb), coefficient, dt, stiff)
    f2, w2 = _mode_force(hg_old[2], _mode_rate(v[5], x[5], lc, fb), coefficient, dt, stiff)
    f3, w3 = _mode_force(hg_old[3], _mode_rate(v[6], x[6], lc, fb), coefficient, dt, stiff)
    return (f0, f1, f2, f3), w0 + w1 + w2 + w3


@nb.njit(inline="always", fastmath=FASTMATH)
def _moment(hg, x, i, j, inv):
    """sum_m Q_mi X_(m+4),j / V over the four hourglass modes [Pa]."""
    return (hg[0][i] * x[3][j] + hg[1][i] * x[4][j] + hg[2][i] * x[5][j] + hg[3][i] * x[6][j]) * inv


@nb.njit(inline="always", fastmath=FASTMATH)
def element_stress(
    s_inf: Voigt, h: Voigt, mean_stress: float, hg: Modes, x: Modes, vol: float, fb: bool
) -> Tensor:
    """sigma = s_inf + h - (p + q) I, less sum_m Q_m X_(m+4)^T / V for gamma (9-tuple) [Pa]."""
    sxx, syy, szz = s_inf[0] + h[0], s_inf[1] + h[1], s_inf[2] + h[2]
    sxx, syy, szz = sxx - mean_stress, syy - mean_stress, szz - mean_stress
    sxy, syz, szx = s_inf[3] + h[3], s_inf[4] + h[4], s_inf[5] + h[5]
    if not fb:
        return (sxx, sxy, szx, sxy, syy, syz, szx, syz, szz)
    inv = like(vol, 1.0) / vol
    return (
        sxx - _moment(hg, x, 0, 0, inv),
        sxy - _moment(hg, x, 0, 1, inv),
        szx - _moment(hg, x, 0, 2, inv),
        sxy - _moment(hg, x, 1, 0, inv),
        syy - _moment(hg, x, 1, 1, inv),
        syz - _moment(hg, x, 1, 2, inv),
        szx - _moment(hg, x, 2, 0, inv),
        syz - _moment(hg, x, 2, 1, inv),
        szz - _moment(hg, x, 2, 2, inv),
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _modal_force(sigma, g, i):
    """Component i of -sigma g."""
    return -(sigma[3 * i] * g[0] + sigma[3 * i + 1] * g[1] + sigma[3 * i + 2] * g[2])


@nb.njit(inline="always", fastmath=FASTMATH)
def nodal_forces(sigma: Tensor, g: Modes, hg: Modes, i: int, ok: bool) -> tuple[float, ...]:
    """Component i of f_a = -sigma B_a - sum_m Q_m Gamma_ma at the 8 nodes [N]; 0 if not ok."""
    f = nodal_sums(
        _modal_force(sigma, g[0], i),
        _modal_force(sigma, g[1], i),
        _modal_force(sigma, g[2], i),
        _modal_force(sigma, g[3], i) - hg[0][i],
        _modal_force(sigma, g[4], i) - hg[1][i],
        _modal_force(sigma, g[5], i) - hg[2][i],
        -hg[3][i],
    )
    zero = like(f[0], 0.0)
    return (
        f[0] if ok else zero,
        f[1] if ok else zero,
        f[2] if ok else zero,
        f[3] if ok else zero,
        f[4] if ok else zero,
        f[5] if ok else zero,
        f[6] if ok else zero,
        f[7] if ok else zero,
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def stable_step(area: float, vol: float, trd: float, c: float, q1: float, q2: float) -> float:
    """LS-DYNA solid step L_e / (Q + sqrt(Q^2 + c^2)), L_e = V / A_max [s]; 0 unless V > 0.

    Q = Q2 c + Q1 L_e |tr D| under compression (LS-DYNA Theory Manual, time step control);
    ``area`` is A_max (:func:`batball.elements.hex8_geometry.modal_largest_face_area`).
    """
    le = vol / area
    zero = like(vol, 0.0)
    qv = q2 * c + q1 * le * abs(trd) if trd < zero else zero
    step = le / (qv + np.sqrt(qv * qv + c * c))
    return step if vol > zero else zero


@nb.njit(inline="always", fastmath=FASTMATH)
def _select3(a, b, ok):
    """a if ok else b for 3-tuples."""
    return (a[0] if ok else b[0], a[1] if ok else b[1], a[2] if ok else b[2])


@nb.njit(inline="always", fastmath=FASTMATH)
def _keep_if(new, old, ok):
    """new if ok else old for four 3-tuples."""
    return (
        _select3(new[0], old[0], ok),
        _select3(new[1], old[1], ok),
        _select3(new[2], old[2], ok),
        _select3(new[3], old[3], ok),
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def element_response(
    x: Modes,
    v: Modes,
    g: Modes,
    s_inf: Voigt,
    h: Voigt,
    hg_old: Modes,
    state: tuple[float, float, float, float, float, float],
    material: tuple[float, float, float],
    controls: tuple[float, float, float, float],
    fb: bool,
    stiff: bool,
) -> tuple[float, Modes, tuple[tuple[float, ...], ...], float, tuple[float, float, float]]:
    """Everything of one element on x^n after the deviatoric update.

    Args:
        x, v: modal sums X_1..X_7, V_1..V_7 (3-tuples) [m], [m/s]; g: G_1..G_6 [m^2].
        s_inf, h: updated deviatoric stresses (Voigt) [Pa]; hg_old: stored hourglass forces [N].
        state: (V, V0 [m^3], tr D [1/s], mid-step V [m^3], deviatoric work [J/m^3], p_old [Pa]).
        material: (density [kg/m^3], K, K + 4/3 G0 [Pa]).
        controls: (dt [s], Q1, Q2, QH/QM).
        fb, stiff: hourglass form (see :func:`hourglass_forces`).

    Returns:
        The pressure and hourglass state to store, the nodal forces (three 8-tuples, x, y, z
        components) [N], the wave speed c [m/s] (for :func:`stable_step`, which the caller
        takes with the largest face area) and the (internal, hourglass, bulk viscosity) work
        [J]; an element without positive volume keeps p and Q and gets no forces and no work.
    """
    vol, v0, trd, vmid, dev_work, p_old = state
    dt, q1, q2, hg_coefficient = controls
    rho, c, p, bulk_q, length = pressure_and_viscosity(
        vol, v0, material[0], material[1], material[2], trd, q1, q2
    )
    hg, hg_work = hourglass_forces(
        g, v, x, hg_old, vol, rho, c, length, dt, hg_coefficient, fb, stiff
    )
    sigma = element_stress(s_inf, h, p + bulk_q, hg, x, vol, fb)
    zero = like(vol, 0.0)
    ok = vol > zero
    forces = (
        nodal_forces(sigma, g, hg, 0, ok),
        nodal_forces(sigma, g, hg, 1, ok),
        nodal_forces(sigma, g, hg, 2, ok),
    )
    internal = (dev_work - like(vol, 0.5) * (p_old + p) * trd * dt) * vmid
    bulk = -bulk_q * trd * dt * vmid
    work = (internal if ok else zero, hg_work if ok else zero, bulk if ok else zero)
    hg_kept = _keep_if(hg, hg_old, ok and stiff)  # only the stiffness form has a state
    return p if ok else p_old, hg_kept, forces, c, work
