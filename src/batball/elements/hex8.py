"""One-point (uniform-strain) hexahedron for explicit dynamics: LS-DYNA solid ELFORM 1.

Each step, for every element (``compute_hex8_forces``):

1. the velocity gradient L = sum_I v_I (x) B_I / V from v^(n-1/2) on the mid-step geometry
   x^(n-1/2) = x^n - dt/2 v^(n-1/2) (Flanagan & Belytschko 1981 uniform strain);
2. the stored deviatoric stresses rotated by the Hughes-Winget (Cayley) rotation of W dt, which is
   exactly orthogonal, so the update is objective (physics.md section 6.8);
3. the material update (MAT_006, physics.md section 1.3) and the pressure p = K ln(V0/V);
4. bulk viscosity q = rho l (Q1 l tr(D)^2 - Q2 c tr(D)) for tr(D) < 0, l = V^(1/3) (LS-DYNA's
   default Q1 = 1.5, Q2 = 0.06; physics.md section 6.2);
5. nodal forces f_I = -sigma B_I on the geometry x^n, plus hourglass forces:
   LS-DYNA IHQ = 1 (viscous on the base vectors Gamma, a_h = QH rho V^(2/3) c / 4),
   IHQ = 2 (Flanagan-Belytschko viscous on the orthogonalised gamma, same coefficient) or
   IHQ = 4 (Flanagan-Belytschko stiffness, incremental hourglass "stress" with
   kappa = QM (K + 4/3 G0) sum(B.B) / (3 V); the exact LS-DYNA constant is not public, this is
   the Flanagan-Belytschko form with a coefficient of the same order);
6. the element's stable step L_e / (Q + sqrt(Q^2 + c^2)) with L_e = V / A_max and
   Q = Q2 c + Q1 L_e |tr(D)| under compression (LS-DYNA Theory Manual, time step control).

Energies are integrated per element with the midpoint rule: internal (stress power, including the
viscoelastic dissipation), hourglass and bulk-viscosity work.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from batball.elements.hex8_geometry import HOURGLASS_BASE, largest_face_area, volume_derivatives
from batball.materials.viscoelastic import update_viscoelastic_deviator
from batball.numerics import FASTMATH

#: LS-DYNA hourglass types (IHQ) the solid element supports.
HOURGLASS_TYPES = {
    1: "LS-DYNA standard viscous",
    2: "Flanagan-Belytschko viscous",
    3: "Flanagan-Belytschko viscous",
    4: "Flanagan-Belytschko stiffness",
    5: "Flanagan-Belytschko stiffness",
}

#: Columns of the per-chunk energy increments written by the kernel.
ENERGY_INTERNAL, ENERGY_HOURGLASS, ENERGY_BULK_VISCOSITY = 0, 1, 2


@nb.njit(inline="always", fastmath=FASTMATH)
def rotate_voigt(s: np.ndarray, q: np.ndarray, t: np.ndarray) -> None:
    """s <- Q s Q^T for a symmetric tensor in Voigt order (xx, yy, zz, xy, yz, zx), in place."""
    s00, s11, s22, s01, s12, s20 = s[0], s[1], s[2], s[3], s[4], s[5]
    for i in range(3):
        t[i, 0] = q[i, 0] * s00 + q[i, 1] * s01 + q[i, 2] * s20
        t[i, 1] = q[i, 0] * s01 + q[i, 1] * s11 + q[i, 2] * s12
        t[i, 2] = q[i, 0] * s20 + q[i, 1] * s12 + q[i, 2] * s22
    s[0] = t[0, 0] * q[0, 0] + t[0, 1] * q[0, 1] + t[0, 2] * q[0, 2]
    s[1] = t[1, 0] * q[1, 0] + t[1, 1] * q[1, 1] + t[1, 2] * q[1, 2]
    s[2] = t[2, 0] * q[2, 0] + t[2, 1] * q[2, 1] + t[2, 2] * q[2, 2]
    s[3] = t[0, 0] * q[1, 0] + t[0, 1] * q[1, 1] + t[0, 2] * q[1, 2]
    s[4] = t[1, 0] * q[2, 0] + t[1, 1] * q[2, 1] + t[1, 2] * q[2, 2]
    s[5] = t[2, 0] * q[0, 0] + t[2, 1] * q[0, 1] + t[2, 2] * q[0, 2]


@nb.njit(inline="always", fastmath=FASTMATH)
def cayley_rotation(w01: float, w12: float, w20: float, dt: float, q: np.ndarray) -> None:
    """Hughes-Winget rotation Q = (I - W dt/2)^-1 (I + W dt/2), written into ``q`` (3, 3).

    With S = W dt / 2 (skew) and theta^2 = |axial(S)|^2 this is Q = I + 2 (S + S^2) / (1 + theta^2).
    """
    a = 0.5 * dt * w01  # S[0,1]
    b = 0.5 * dt * w12  # S[1,2]
    c = 0.5 * dt * w20  # S[2,0]
    theta2 = a * a + b * b + c * c
    scale = 2.0 / (1.0 + theta2)
    # S = [[0, a, -c], [-a, 0, b], [c, -b, 0]];  S^2 = w w^T - theta2 I with w = (b, c, a)
    q[0, 0] = 1.0 + scale * (b * b - theta2)
    q[1, 1] = 1.0 + scale * (c * c - theta2)
    q[2, 2] = 1.0 + scale * (a * a - theta2)
    q[0, 1] = scale * (a + b * c)
    q[1, 0] = scale * (-a + b * c)
    q[1, 2] = scale * (b + c * a)
    q[2, 1] = scale * (-b + c * a)
    q[2, 0] = scale * (c + a * b)
    q[0, 2] = scale * (-c + a * b)


@nb.njit(inline="always", fastmath=FASTMATH)
def velocity_gradient(ve: np.ndarray, b: np.ndarray, volume: float, lg: np.ndarray) -> None:
    """L_ij = sum_I v_Ii B_Ij / V into ``lg`` (3, 3) [1/s]; ``ve``, ``b`` flat (24,)."""
    inv = 1.0 / volume
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for a in range(8):
                acc += ve[3 * a + i] * b[3 * a + j]
            lg[i, j] = acc * inv


@nb.njit(inline="always", fastmath=FASTMATH)
def orthogonal_hourglass_vectors(
    xe: np.ndarray, b: np.ndarray, volume: float, gam: np.ndarray
) -> None:
    """Flanagan-Belytschko gamma_ak = Gamma_ak - (1/V) (sum_m x_m Gamma_am) . B_k, shape (4, 8)."""
    inv = 1.0 / volume
    for al in range(4):
        h0 = 0.0
        h1 = 0.0
        h2 = 0.0
        for m in range(8):
            g = HOURGLASS_BASE[al, m]
            h0 += xe[3 * m] * g
            h1 += xe[3 * m + 1] * g
            h2 += xe[3 * m + 2] * g
        for k in range(8):
            gam[al, k] = (
                HOURGLASS_BASE[al, k]
                - (h0 * b[3 * k] + h1 * b[3 * k + 1] + h2 * b[3 * k + 2]) * inv
            )


@nb.njit(inline="always", fastmath=FASTMATH)
def hourglass_forces(
    ve: np.ndarray,
    gam: np.ndarray,
    f: np.ndarray,
    hg: np.ndarray,
    hg_type: int,
    viscous_coefficient: float,
    stiffness: float,
    dt: float,
) -> float:
    """Add hourglass forces to ``f`` (24,); return the hourglass work over ``dt`` [J].

    Args:
        ve: (24,) nodal velocities [m/s], node-major.
        gam: (4, 8) hourglass shape vectors (Gamma for IHQ 1, gamma otherwise).
        hg: (4, 3) accumulated hourglass forces of the stiffness form [N], updated in place.
        hg_type: LS-DYNA IHQ.
        viscous_coefficient: a_h [N s/m]; stiffness: kappa [N/m].
    """
    work = 0.0
    for al in range(4):
        for i in range(3):
            rate = 0.0
            for k in range(8):
                rate += ve[3 * k + i] * gam[al, k]
            if hg_type >= 4:
                old = hg[al, i]
                hg[al, i] = old + stiffness * dt * rate
                generalized = hg[al, i]
                work += 0.5 * (old + generalized) * rate * dt
            else:
                generalized = viscous_coefficient * rate
                work += generalized * rate * dt
            for k in range(8):
                f[3 * k + i] -= generalized * gam[al, k]
    return work


@nb.njit(inline="always", fastmath=FASTMATH)
def stable_step(
    volume: float, largest_area: float, c: float, trd: float, q1: float, q2: float
) -> float:
    """LS-DYNA solid time step L_e / (Q + sqrt(Q^2 + c^2)), L_e = V / A_max [s]."""
    le = volume / largest_area
    qv = 0.0
    if trd < 0.0:
        qv = q2 * c + q1 * le * abs(trd)
    return le / (qv + np.sqrt(qv * qv + c * c))


@nb.njit(inline="always", fastmath=FASTMATH)
def _gather(
    points: np.ndarray, values: np.ndarray, nodes: np.ndarray, xe: np.ndarray, ve: np.ndarray
) -> None:
    """Copy the element's node coordinates and velocities into flat ``xe`` and ``ve`` (24,)."""
    for a in range(8):
        n = nodes[a]
        for i in range(3):
            xe[3 * a + i] = points[n, i]
            ve[3 * a + i] = values[n, i]


@nb.njit(inline="always", fastmath=FASTMATH)
def _update_deviator(
    e: int,
    lg: np.ndarray,
    dt: float,
    consts: np.ndarray,
    s_inf: np.ndarray,
    h: np.ndarray,
    q: np.ndarray,
    t: np.ndarray,
    de: np.ndarray,
) -> tuple[float, float]:
    """Rotate and advance element ``e``'s deviatoric stress; return (tr D, deviatoric work/V)."""
    trd = lg[0, 0] + lg[1, 1] + lg[2, 2]
    cayley_rotation(
        0.5 * (lg[0, 1] - lg[1, 0]), 0.5 * (lg[1, 2] - lg[2, 1]), 0.5 * (lg[2, 0] - lg[0, 2]), dt, q
    )
    rotate_voigt(s_inf[e], q, t)
    rotate_voigt(h[e], q, t)
    third = trd / 3.0
    de[0] = (lg[0, 0] - third) * dt
    de[1] = (lg[1, 1] - third) * dt
    de[2] = (lg[2, 2] - third) * dt
    de[3] = 0.5 * (lg[0, 1] + lg[1, 0]) * dt
    de[4] = 0.5 * (lg[1, 2] + lg[2, 1]) * dt
    de[5] = 0.5 * (lg[2, 0] + lg[0, 2]) * dt
    work = 0.0
    for c in range(6):
        weight = 1.0 if c < 3 else 2.0
        work += 0.5 * weight * (s_inf[e, c] + h[e, c]) * de[c]
    update_viscoelastic_deviator(s_inf[e], h[e], de, consts[1], consts[2], consts[3], dt)
    for c in range(6):
        weight = 1.0 if c < 3 else 2.0
        work += 0.5 * weight * (s_inf[e, c] + h[e, c]) * de[c]
    return trd, work


@nb.njit(inline="always", fastmath=FASTMATH)
def _stress_forces(
    e: int, b: np.ndarray, s_inf: np.ndarray, h: np.ndarray, mean_stress: float, f: np.ndarray
) -> None:
    """f_I = -sigma B_I with sigma = s_inf + h - mean_stress I (mean_stress = p + q)."""
    sxx = s_inf[e, 0] + h[e, 0] - mean_stress
    syy = s_inf[e, 1] + h[e, 1] - mean_stress
    szz = s_inf[e, 2] + h[e, 2] - mean_stress
    sxy = s_inf[e, 3] + h[e, 3]
    syz = s_inf[e, 4] + h[e, 4]
    szx = s_inf[e, 5] + h[e, 5]
    for a in range(8):
        b0 = b[3 * a]
        b1 = b[3 * a + 1]
        b2 = b[3 * a + 2]
        f[3 * a] = -(sxx * b0 + sxy * b1 + szx * b2)
        f[3 * a + 1] = -(sxy * b0 + syy * b1 + syz * b2)
        f[3 * a + 2] = -(szx * b0 + syz * b1 + szz * b2)


@nb.njit(inline="always", fastmath=FASTMATH)
def _hourglass(
    xe: np.ndarray, ve: np.ndarray, b: np.ndarray, vol: float, rho: float, c: float,
    length: float, gam: np.ndarray, f: np.ndarray, hg: np.ndarray, hg_type: int,
    coefficient: float, dt: float,
) -> float:
    """Hourglass shape vectors and coefficients of one element, then its hourglass forces."""
    if hg_type == 1:
        gam[:, :] = HOURGLASS_BASE
    else:
        orthogonal_hourglass_vectors(xe, b, vol, gam)
    viscous = coefficient * rho * length * length * c / 4.0
    bb = 0.0
    for m in range(24):
        bb += b[m] * b[m]
    stiffness = coefficient * rho * c * c * bb / (3.0 * vol)
    return hourglass_forces(ve, gam, f, hg, hg_type, viscous, stiffness, dt)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def compute_hex8_forces(
    points: np.ndarray,
    velocities: np.ndarray,
    cells: np.ndarray,
    dt: float,
    cell_material: np.ndarray,
    material_constants: np.ndarray,
    densities: np.ndarray,
    volume0: np.ndarray,
    s_inf: np.ndarray,
    h: np.ndarray,
    pressure: np.ndarray,
    hg_state: np.ndarray,
    hg_type: int,
    hg_coefficient: float,
    q1: float,
    q2: float,
    cell_forces: np.ndarray,
    cell_volume: np.ndarray,
    cell_dt: np.ndarray,
    energy_increments: np.ndarray,
) -> None:
    """Element forces, stress update and stable steps of all hexes for one explicit cycle.

    Args:
        points: (n_points, 3) coordinates x^n [m]; velocities: (n_points, 3) v^(n-1/2) [m/s].
        cells: (n_cells, 8) node ids; dt: the step dt^(n-1/2) [s] that led to x^n.
        cell_material: (n_cells,) row of ``material_constants`` (n_materials, 4: K, G0, G_inf
            [Pa], beta [1/s]) and ``densities`` (n_materials,) [kg/m^3] for each cell.
        volume0: (n_cells,) initial volumes [m^3].
        s_inf, h: (n_cells, 6) MAT_006 deviatoric stresses [Pa]; pressure: (n_cells,) [Pa];
            hg_state: (n_cells, 4, 3) stiffness-form hourglass forces [N] (all updated in place).
        hg_type, hg_coefficient: LS-DYNA IHQ and QH/QM. q1, q2: bulk viscosity (0, 0 = off).
        cell_forces: (n_cells, 24) out, nodal forces [N] (node-major);
        cell_volume: (n_cells,) out [m^3];
        cell_dt: (n_cells,) out, stable steps [s] (0 where the volume is not positive).
        energy_increments: (n_chunks, 3) out: internal, hourglass, bulk-viscosity work [J].
    """
    n_cells = cells.shape[0]
    n_chunks = energy_increments.shape[0]
    for chunk in nb.prange(n_chunks):
        xe = np.empty(24)
        ve = np.empty(24)
        b = np.empty(24)
        gam = np.empty((4, 8))
        lg = np.empty((3, 3))
        q = np.empty((3, 3))
        t = np.empty((3, 3))
        de = np.empty(6)
        e_int = 0.0
        e_hg = 0.0
        e_bv = 0.0
        for e in range(chunk * n_cells // n_chunks, (chunk + 1) * n_cells // n_chunks):
            consts = material_constants[cell_material[e]]
            _gather(points, velocities, cells[e], xe, ve)
            for m in range(24):  # mid-step geometry x^(n-1/2)
                xe[m] -= 0.5 * dt * ve[m]
            vmid = volume_derivatives(xe, b)
            velocity_gradient(ve, b, vmid, lg)
            trd, dev_work = _update_deviator(e, lg, dt, consts, s_inf, h, q, t, de)
            _gather(points, velocities, cells[e], xe, ve)
            vol = volume_derivatives(xe, b)
            cell_volume[e] = vol
            f = cell_forces[e]
            if not vol > 0.0:
                f[:] = 0.0
                cell_dt[e] = 0.0
                continue
            rho = densities[cell_material[e]] * volume0[e] / vol
            c = np.sqrt((consts[0] + 4.0 / 3.0 * consts[1]) / rho)
            p_new = consts[0] * np.log(volume0[e] / vol)
            bulk_q = 0.0
            length = np.cbrt(vol)
            if trd < 0.0:
                bulk_q = rho * length * (q1 * length * trd * trd - q2 * c * trd)
            e_int += (dev_work - 0.5 * (pressure[e] + p_new) * trd * dt) * vmid
            e_bv -= bulk_q * trd * dt * vmid
            pressure[e] = p_new
            _stress_forces(e, b, s_inf, h, p_new + bulk_q, f)
            e_hg += _hourglass(xe, ve, b, vol, rho, c, length, gam, f, hg_state[e], hg_type,
                               hg_coefficient, dt)
            cell_dt[e] = stable_step(vol, largest_face_area(xe), c, trd, q1, q2)
        energy_increments[chunk, ENERGY_INTERNAL] = e_int
        energy_increments[chunk, ENERGY_HOURGLASS] = e_hg
        energy_increments[chunk, ENERGY_BULK_VISCOSITY] = e_bv
