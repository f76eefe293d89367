"""Pointwise stress update of the foam laws MAT_057 and MAT_083 (Numba).

The law and its sources are described in :mod:`batball.materials.foam`. Here: loading-curve
interpolation, the curve energy, a Jacobi eigen-decomposition of b = F F^T, and the update of one
point from its deformation gradient; the decomposition and the update also for a block of points
at once (SIMD across the points, the same bits as one at a time), as the foam kernel runs them.
The table arrays are those of
:meth:`batball.materials.foam.FoamLaw.foam_table`: ``params`` (columns ``P_*``), ``rates``
(n_curves,), ``strains``/``stresses`` (n_curves, n_max), ``counts`` (n_curves,), ``energies``
(n_max,). A point's history row holds ``H_*``.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from batball.materials.foam import (
    KIND_MAT083,
    P_E,
    P_HU,
    P_KIND,
    P_RATE_FILTER,
    P_SHAPE,
    P_TC,
)

# Columns of a point's history: the Maxwell rate stress of MAT_057 (Voigt, 6), the total stress
# of the last step (Voigt, 6; for the energy), W_max [J/m^3], the filtered strain rate [1/s].
H_RATE_STRESS, H_STRESS, H_WMAX, H_RATE = 0, 6, 12, 13
N_HISTORY = 14


@nb.njit(inline="always")
def _segment(strains: np.ndarray, count: int, s: float) -> int:
    """The segment k (points k, k+1) holding strain s; the last one beyond the curve."""
    k = 0
    while k < count - 2 and s > strains[k + 1]:
        k += 1
    return k


@nb.njit(inline="always")
def _segment_slope(strains: np.ndarray, stresses: np.ndarray, k: int) -> float:
    """The slope of segment k (points k, k+1) of a curve."""
    return (stresses[k + 1] - stresses[k]) / (strains[k + 1] - strains[k])


@nb.njit(inline="always")
def _segment_stress(strains: np.ndarray, stresses: np.ndarray, k: int, s: float) -> float:
    """The stress at strain s on the line of segment k of a curve [Pa]."""
    return stresses[k] + _segment_slope(strains, stresses, k) * (s - strains[k])


@nb.njit(inline="always")
def curve_stress(strains: np.ndarray, stresses: np.ndarray, count: int, s: float) -> float:
    """Loading-curve stress at compressive strain s >= 0 [Pa]: linear between points, extended
    with the last segment's slope beyond the last point (LS-DYNA's curve extrapolation)."""
    return _segment_stress(strains, stresses, _segment(strains, count, s), s)


@nb.njit(inline="always")
def _rate_outside(rates: np.ndarray, rate: float) -> tuple[bool, bool]:
    """Whether ``rate`` is at or below MAT_083's first curve's rate (or there is one curve),
    and whether it is at or above the last's: there the first or last curve alone applies."""
    return rate <= rates[0] or rates.shape[0] == 1, rate >= rates[rates.shape[0] - 1]


@nb.njit(inline="always")
def curve_energy(
    strains: np.ndarray, stresses: np.ndarray, energies: np.ndarray, count: int, s: float
) -> float:
    """Energy density int_0^s f(x) dx under the piecewise-linear curve [J/m^3]."""
    k = _segment(strains, count, s)
    d = s - strains[k]
    return energies[k] + stresses[k] * d + 0.5 * _segment_slope(strains, stresses, k) * d * d


@nb.njit(inline="always")
def rate_curve_stress(
    rates: np.ndarray,
    strains: np.ndarray,
    stresses: np.ndarray,
    counts: np.ndarray,
    rate: float,
    s: float,
) -> float:
    """MAT_083's table: the stress at strain s, linear in the rate between the two curves that
    bracket ``rate``; the first curve below the lowest rate, the last above the highest."""
    n = rates.shape[0]
    slowest, fastest = _rate_outside(rates, rate)
    if slowest:
        return curve_stress(strains[0], stresses[0], counts[0], s)
    if fastest:
        return curve_stress(strains[n - 1], stresses[n - 1], counts[n - 1], s)
    j = 0
    while rate > rates[j + 1]:
        j += 1
    w = (rate - rates[j]) / (rates[j + 1] - rates[j])
    low = curve_stress(strains[j], stresses[j], counts[j], s)
    high = curve_stress(strains[j + 1], stresses[j + 1], counts[j + 1], s)
    return (1.0 - w) * low + w * high


@nb.njit(inline="always")
def _rotate(a: np.ndarray, v: np.ndarray, p: int, q: int) -> None:
    """One Jacobi rotation zeroing a[p, q] of the symmetric a; accumulates it into v."""
    theta = (a[q, q] - a[p, p]) / (2.0 * a[p, q])
    t = np.sign(theta) / (abs(theta) + np.sqrt(theta * theta + 1.0)) if theta != 0.0 else 1.0
    c = 1.0 / np.sqrt(t * t + 1.0)
    s = t * c
    for k in range(3):  # columns p, q of a V-style rotation: a <- J^T a J
        akp, akq = a[k, p], a[k, q]
        a[k, p], a[k, q] = c * akp - s * akq, s * akp + c * akq
    for k in range(3):
        apk, aqk = a[p, k], a[q, k]
        a[p, k], a[q, k] = c * apk - s * aqk, s * apk + c * aqk
    for k in range(3):
        vkp, vkq = v[k, p], v[k, q]
        v[k, p], v[k, q] = c * vkp - s * vkq, s * vkp + c * vkq


@nb.njit
def symmetric_eigen(a: np.ndarray, v: np.ndarray) -> None:
    """Eigen-decomposition of the symmetric 3x3 ``a`` by cyclic Jacobi rotations, in place:
    on return the diagonal of ``a`` holds the eigenvalues and the columns of ``v`` the unit
    eigenvectors (Golub & Van Loan, Matrix Computations, section 8.5). Exact for repeated
    eigenvalues, which a closed-form cubic solution is not (the undeformed b = I)."""
    v[:, :] = 0.0
    v[0, 0] = v[1, 1] = v[2, 2] = 1.0
    scale = abs(a[0, 0]) + abs(a[1, 1]) + abs(a[2, 2])
    for _sweep in range(12):
        off = abs(a[0, 1]) + abs(a[1, 2]) + abs(a[0, 2])
        if off <= 1e-15 * scale:
            return
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if a[p, q] != 0.0:
                _rotate(a, v, p, q)


#: Points a block of :func:`block_symmetric_eigen` holds (its lanes), and the foam kernel's
#: block of cells. On an AVX2 EPYC (Zen 3) the foam kernel ran 2-6 % faster on one thread with
#: 32 than with 16 (more lanes' chains of divisions and square roots to overlap in a rotation),
#: 4-9 % slower with 64 (its block arrays outgrow the L1 cache); two threads alike.
EIGEN_LANES = 32
# Rows of its block (each EIGEN_LANES wide): entry (i, j) of the matrix at row 3 i + j, of the
# eigenvectors at EIGEN_V + 3 i + j, then a lane's "done" flag and its scale, and a rotation's
# c, s and whether the lane turns. One array, rows a constant EIGEN_LANES apart: LLVM can then
# prove that the rows do not overlap.
EIGEN_V, EIGEN_DONE, EIGEN_SCALE = 9, 18, 19
EIGEN_COS, EIGEN_SIN, EIGEN_TURN = 20, 21, 22
EIGEN_ROWS = 23


@nb.njit
def eigen_block() -> np.ndarray:
    """Work space for :func:`block_symmetric_eigen`."""
    return np.zeros(EIGEN_ROWS * EIGEN_LANES)


@nb.njit(inline="always")
def _at(row: int, lane: int) -> int:
    """Index of ``row``, ``lane`` in an eigen block."""
    return row * EIGEN_LANES + lane


@nb.njit(inline="always")
def _turn(w, i, j, e, c, s, turn):
    """Rows i, j of lane e <- (c x - s y, s x + c y) where ``turn``, else kept."""
    x, y = w[_at(i, e)], w[_at(j, e)]
    w[_at(i, e)] = c * x - s * y if turn else x
    w[_at(j, e)] = s * x + c * y if turn else y


def _make_block_rotation(p: int, q: int):
    """The Jacobi rotation (p, q) of :func:`_rotate` over every lane of a block, in its order of
    operations: a <- J^T a J by columns, then rows, and v <- v J; a lane turns only if it is not
    done and its a[p, q] is not zero (straight-line code, so that LLVM vectorises the lanes)."""
    pp, pq, qq = 3 * p + p, 3 * p + q, 3 * q + q

    @nb.njit(inline="always", error_model="numpy")
    def rotate(w):
        # the angles first: a loop of independent chains of divisions and square roots, short
        # enough for the processor to overlap the lanes' chains
        for e in range(EIGEN_LANES):
            apq = w[_at(pq, e)]
            theta = (w[_at(qq, e)] - w[_at(pp, e)]) / (2.0 * apq)
            sign = 1.0 if theta > 0.0 else (-1.0 if theta < 0.0 else theta)  # np.sign
            t = sign / (abs(theta) + np.sqrt(theta * theta + 1.0)) if theta != 0.0 else 1.0
            c = 1.0 / np.sqrt(t * t + 1.0)
            w[_at(EIGEN_COS, e)] = c
            w[_at(EIGEN_SIN, e)] = t * c
            w[_at(EIGEN_TURN, e)] = 1.0 if w[_at(EIGEN_DONE, e)] == 0.0 and apq != 0.0 else 0.0
        for e in range(EIGEN_LANES):
            c, s = w[_at(EIGEN_COS, e)], w[_at(EIGEN_SIN, e)]
            turn = w[_at(EIGEN_TURN, e)] != 0.0
            _turn(w, p, q, e, c, s, turn)  # columns p, q of rows 0, 1, 2
            _turn(w, 3 + p, 3 + q, e, c, s, turn)
            _turn(w, 6 + p, 6 + q, e, c, s, turn)
            _turn(w, 3 * p, 3 * q, e, c, s, turn)  # then rows p, q of columns 0, 1, 2
            _turn(w, 3 * p + 1, 3 * q + 1, e, c, s, turn)
            _turn(w, 3 * p + 2, 3 * q + 2, e, c, s, turn)
            _turn(w, EIGEN_V + p, EIGEN_V + q, e, c, s, turn)  # the eigenvectors' columns
            _turn(w, EIGEN_V + 3 + p, EIGEN_V + 3 + q, e, c, s, turn)
            _turn(w, EIGEN_V + 6 + p, EIGEN_V + 6 + q, e, c, s, turn)

    return rotate


_rotate_01 = _make_block_rotation(0, 1)
_rotate_02 = _make_block_rotation(0, 2)
_rotate_12 = _make_block_rotation(1, 2)


@nb.njit(error_model="numpy")
def block_symmetric_eigen(w: np.ndarray, n: int) -> None:
    """:func:`symmetric_eigen` of lanes 0..n-1 of the block ``w`` (rows ``EIGEN_*``; the
    matrices in rows 0..8) at once, in place: each lane's result is the same, bit for bit, as
    ``symmetric_eigen`` of its matrix (the same checks and rotations in the same order; a lane
    stops where that function returns). On return rows 0, 4, 8 hold the eigenvalues and rows
    EIGEN_V.. the eigenvectors (columns). The sweeps run SIMD across the lanes, which hides the
    latency of the divisions and square roots a single decomposition waits on (measured: 397
    against 74 ns a matrix)."""
    for e in range(EIGEN_LANES):
        for k in range(9):
            w[_at(EIGEN_V + k, e)] = 1.0 if k % 4 == 0 else 0.0
        w[_at(EIGEN_DONE, e)] = 0.0 if e < n else 1.0
        w[_at(EIGEN_SCALE, e)] = abs(w[_at(0, e)]) + abs(w[_at(4, e)]) + abs(w[_at(8, e)])
    for _sweep in range(12):
        remaining = 0
        for e in range(EIGEN_LANES):
            off = abs(w[_at(1, e)]) + abs(w[_at(5, e)]) + abs(w[_at(2, e)])
            done = w[_at(EIGEN_DONE, e)] != 0.0 or off <= 1e-15 * w[_at(EIGEN_SCALE, e)]
            w[_at(EIGEN_DONE, e)] = 1.0 if done else 0.0
            remaining += 0 if done else 1
        if remaining == 0:
            return
        _rotate_01(w)
        _rotate_02(w)
        _rotate_12(w)


@nb.njit(inline="always")
def tension_stress_energy(e: float, young: float, cutoff: float) -> tuple[float, float]:
    """Tension (e >= 0): nominal stress min(E e, TC) [Pa] and its energy density [J/m^3]."""
    if young * e <= cutoff:
        return young * e, 0.5 * young * e * e
    return cutoff, 0.5 * cutoff * cutoff / young + cutoff * (e - cutoff / young)


@nb.njit(inline="always")
def hysteresis_factor(w: float, w_max: float, hu: float, shape: float) -> float:
    """1 - D with D = (1 - HU) (1 - (W / W_max)^SHAPE) while unloading (W < W_max), else 1."""
    if w >= w_max or w_max <= 0.0:
        return 1.0
    return 1.0 - (1.0 - hu) * (1.0 - (max(w, 0.0) / w_max) ** shape)


@nb.njit(inline="always")
def curve_slope(strains: np.ndarray, stresses: np.ndarray, count: int, s: float) -> float:
    """The loading curve's slope at compressive strain s [Pa]."""
    return _segment_slope(strains, stresses, _segment(strains, count, s))


@nb.njit(inline="always")
def principal_nominal_stresses(
    stretches: np.ndarray,
    rate: float,
    history: np.ndarray,
    table: tuple[np.ndarray, ...],
    out: np.ndarray,
) -> float:
    """Nominal stresses tau_i [Pa] (tension positive) of the three principal stretches into
    ``out`` (3,), updating W_max in ``history``; returns the largest Cauchy tangent
    lambda_i^2 / J d tau_i / d e_i [Pa] (E for a direction in tension or on a MAT_083 rate
    curve, whose slopes E_eff covers); > the nominal one where a point is compressed in more
    than one direction (sigma_i = tau_i lambda_i / J).

    Loading (W >= W_max): the loading curve (MAT_083: interpolated at ``rate``); unloading: the
    first curve times 1 - D (:func:`hysteresis_factor`); tension E e up to TC, undamaged.
    While unloading the tangent is (1 - D) f' + (1 - HU) SHAPE (W / W_max)^(SHAPE - 1) f^2 / W_max
    (dW / de_i = f_i): up to 1 + 2 SHAPE (1 - HU) times the loading slope at the turning point,
    which the time step must see (LAW90 likewise updates an effective modulus).
    """
    params, rates, strains, stresses, counts, energies = table
    young, cutoff = params[P_E], params[P_TC]
    w = 0.0
    for i in range(3):
        e = stretches[i] - 1.0
        if e < 0.0:
            w += curve_energy(strains[0], stresses[0], energies, counts[0], -e)
        else:
            w += tension_stress_energy(e, young, cutoff)[1]
    w_max = history[H_WMAX]
    loading = w >= w_max
    factor = hysteresis_factor(w, w_max, params[P_HU], params[P_SHAPE])
    growth = 0.0  # d(1 - D)/dW while unloading
    if loading:
        history[H_WMAX] = w
    elif w > 0.0:
        shape = params[P_SHAPE]
        growth = (1.0 - params[P_HU]) * shape * (w / w_max) ** (shape - 1.0) / w_max
    rated = params[P_KIND] == KIND_MAT083 and loading
    jacobian = stretches[0] * stretches[1] * stretches[2]
    tangent = 0.0
    for i in range(3):
        e = stretches[i] - 1.0
        slope = young
        if e >= 0.0:
            out[i] = tension_stress_energy(e, young, cutoff)[0]
        elif rated:
            out[i] = -rate_curve_stress(rates, strains, stresses, counts, rate, -e)
        else:
            f = curve_stress(strains[0], stresses[0], counts[0], -e)
            out[i] = -factor * f
            slope = factor * curve_slope(strains[0], stresses[0], counts[0], -e) + growth * f * f
        # the Cauchy tangent d sigma_i / d ln lambda_i = lambda_i^2 / J d tau_i / d e_i
        tangent = max(tangent, slope * stretches[i] * stretches[i] / jacobian)
    return tangent


@nb.njit(inline="always")
def rate_filter_weight(cutoff: float, dt: float) -> float:
    """The weight of a step's new rate in :func:`filtered_rate`: 1 - exp(-cutoff dt), cut-off
    ``cutoff`` [1/s] (as 2 pi f); the same for every point of a material in a step."""
    return 1.0 - np.exp(-2.0 * np.pi * cutoff * dt)


@nb.njit(inline="always")
def filtered_rate(previous: float, rate: float, weight: float) -> float:
    """First-order low-pass filter of the strain rate (``weight``: :func:`rate_filter_weight`)."""
    return previous + weight * (rate - previous)


@nb.njit(inline="always")
def left_cauchy_green(f: tuple) -> tuple:
    """b = F F^T (9-tuple, row-major) of F (9-tuple, row-major), each entry summed over k in
    order (the foam kernel's first pass and :func:`foam_stress`)."""
    return (
        f[0] * f[0] + f[1] * f[1] + f[2] * f[2],
        f[0] * f[3] + f[1] * f[4] + f[2] * f[5],
        f[0] * f[6] + f[1] * f[7] + f[2] * f[8],
        f[3] * f[0] + f[4] * f[1] + f[5] * f[2],
        f[3] * f[3] + f[4] * f[4] + f[5] * f[5],
        f[3] * f[6] + f[4] * f[7] + f[5] * f[8],
        f[6] * f[0] + f[7] * f[1] + f[8] * f[2],
        f[6] * f[3] + f[7] * f[4] + f[8] * f[5],
        f[6] * f[6] + f[7] * f[7] + f[8] * f[8],
    )


@nb.njit
def foam_stress(
    f: np.ndarray,
    d: np.ndarray,
    dt: float,
    history: np.ndarray,
    table: tuple[np.ndarray, ...],
    scratch: np.ndarray,
) -> float:
    """Foam Cauchy stress of one point from its deformation gradient, into ``scratch[3]``;
    returns the largest principal Cauchy tangent modulus [Pa] (:func:`principal_nominal_stresses`).

    Args:
        f: (3, 3) deformation gradient F; d: (3, 3) rate of deformation D [1/s] (MAT_083's rate).
        dt: the step [s]; history: the point's row (``H_*``), W_max and the rate updated.
        table: the material's packed arrays (module docstring).
        scratch: (4, 3, 3) work space; on return scratch[3] is sigma [Pa] (symmetric).
    """
    b, vectors = scratch[0], scratch[1]
    bt = left_cauchy_green(
        (f[0, 0], f[0, 1], f[0, 2], f[1, 0], f[1, 1], f[1, 2], f[2, 0], f[2, 1], f[2, 2])
    )
    for k in range(9):
        b[k // 3, k % 3] = bt[k]
    symmetric_eigen(b, vectors)
    weight = rate_filter_weight(table[0][P_RATE_FILTER], dt)
    return principal_stress(b, vectors, d, weight, history, table, scratch)


@nb.njit(inline="always")
def principal_stress(
    b: np.ndarray,
    vectors: np.ndarray,
    d: np.ndarray,
    weight: float,
    history: np.ndarray,
    table: tuple[np.ndarray, ...],
    scratch: np.ndarray,
) -> float:
    """:func:`foam_stress` once b = F F^T is decomposed: ``b``'s diagonal holds its eigenvalues
    (the squared principal stretches) and ``vectors``' columns its unit eigenvectors; ``weight``
    is the step's :func:`rate_filter_weight`. Writes sigma [Pa] into ``scratch[3]`` and returns
    the largest principal Cauchy tangent [Pa]."""
    sigma = scratch[3]
    stretches = scratch[2, 0]
    for i in range(3):
        stretches[i] = np.sqrt(max(b[i, i], 1e-300))
    # MAT_083's scalar rate: true strain rate along the most compressed direction (RFLAG = 0)
    m = np.argmin(stretches)
    rate = 0.0
    for i in range(3):
        for j in range(3):
            rate -= vectors[i, m] * d[i, j] * vectors[j, m]
    history[H_RATE] = filtered_rate(history[H_RATE], max(rate, 0.0), weight)
    tau = scratch[2, 1]
    tangent = principal_nominal_stresses(stretches, history[H_RATE], history, table, tau)
    jacobian = stretches[0] * stretches[1] * stretches[2]
    # the principal Cauchy stresses tau_k lambda_k / J, formed once (sigma shares the scratch
    # array with tau and the stretches, so the compiler could not hoist them out of the loop)
    cauchy = (tau[0] * stretches[0] / jacobian, tau[1] * stretches[1] / jacobian,
              tau[2] * stretches[2] / jacobian)  # fmt: skip
    for i in range(3):
        for j in range(3):
            total = 0.0
            for k in range(3):
                total += cauchy[k] * vectors[i, k] * vectors[j, k]
            sigma[i, j] = total
    return tangent


# Rows of a law block (each EIGEN_LANES wide) for :func:`block_principal_stress`.
# In: the rate of deformation D (Voigt, tensor shear components) [1/s], and from the point's
# history its filtered rate [1/s] and W_max [J/m^3] (updated in place).
LAW_D, LAW_RATE, LAW_WMAX = 0, 6, 7
# Out: sigma (3 x 3, row-major) [Pa] and the largest principal Cauchy tangent [Pa].
LAW_SIGMA, LAW_TANGENT = 8, 17
# Between the passes: the three stretches, compressive strains -e_i and segments of the first
# curve; W, 1 - D, d(1 - D)/dW and whether loading (1.0 or 0.0); MAT_083's three stresses on
# its rate curves, its lower curve and rate bracket j, and the segments of the lower curve and
# of curve j + 1 (three each).
LAW_STRETCH, LAW_STRAIN, LAW_SEGMENT = 18, 21, 24
LAW_ENERGY, LAW_FACTOR, LAW_GROWTH, LAW_LOADING = 27, 28, 29, 30
LAW_RATED, LAW_CURVE, LAW_CURVE_SEGMENT = 31, 34, 36
# Direction i's segment of the first curve, row LAW_KNOT + 5 i + K_*: the strain, stress and
# energy at its first point and the strain and stress at its second.
LAW_KNOT = 42
K_STRAIN, K_NEXT_STRAIN, K_STRESS, K_NEXT_STRESS, K_ENERGY = range(5)
LAW_ROWS = 57


@nb.njit
def law_block() -> np.ndarray:
    """Work space for :func:`block_principal_stress` (zeros: the lanes past a block's cells
    compute on finite numbers)."""
    return np.zeros(LAW_ROWS * EIGEN_LANES)


@nb.njit(inline="always")
def _smallest(s0: float, s1: float, s2: float) -> int:
    """np.argmin of (s0, s1, s2): the first smallest, or the first NaN."""
    m = 0 if s0 == s0 else 3
    m = 1 if m == 0 and (s1 < s0 or s1 != s1) else m
    m = 2 if m == 0 and (s2 < s0 or s2 != s2) else m
    m = 2 if m == 1 and s1 == s1 and (s2 < s1 or s2 != s2) else m
    return 0 if m == 3 else m


@nb.njit(inline="always")
def _column(eig: np.ndarray, row: int, e: int, m: int) -> float:
    """Entry m of the three in rows row..row+2 of lane e (selects, not an index: the loop stays
    SIMD)."""
    a, b, c = eig[_at(row, e)], eig[_at(row + 1, e)], eig[_at(row + 2, e)]
    return a if m == 0 else (b if m == 1 else c)


@nb.njit(inline="always")
def _index(law: np.ndarray, row: int, e: int) -> np.uint64:
    """A count kept in a law row, as an unsigned index (no negative-index wraparound, whose
    branch would keep the loop from vectorising)."""
    return np.uint64(np.int32(law[_at(row, e)]))


@nb.njit(error_model="numpy")
def _block_stretches(law: np.ndarray, eig: np.ndarray, weight: float) -> None:
    """Pass 1: the principal stretches, the compressive strains and the filtered rate."""
    for e in range(EIGEN_LANES):
        s0 = np.sqrt(max(eig[_at(0, e)], 1e-300))
        s1 = np.sqrt(max(eig[_at(4, e)], 1e-300))
        s2 = np.sqrt(max(eig[_at(8, e)], 1e-300))
        m = _smallest(s0, s1, s2)
        d = (law[_at(LAW_D, e)], law[_at(LAW_D + 1, e)], law[_at(LAW_D + 2, e)],
             law[_at(LAW_D + 3, e)], law[_at(LAW_D + 4, e)], law[_at(LAW_D + 5, e)])  # fmt: skip
        v0 = _column(eig, EIGEN_V, e, m)
        v1 = _column(eig, EIGEN_V + 3, e, m)
        v2 = _column(eig, EIGEN_V + 6, e, m)
        # -v^T D v over the full matrix, entry by entry in row order, as the one-point routine
        rate = 0.0
        rate -= v0 * d[0] * v0
        rate -= v0 * d[3] * v1
        rate -= v0 * d[5] * v2
        rate -= v1 * d[3] * v0
        rate -= v1 * d[1] * v1
        rate -= v1 * d[4] * v2
        rate -= v2 * d[5] * v0
        rate -= v2 * d[4] * v1
        rate -= v2 * d[2] * v2
        law[_at(LAW_RATE, e)] = filtered_rate(law[_at(LAW_RATE, e)], max(rate, 0.0), weight)
        law[_at(LAW_STRETCH, e)] = s0
        law[_at(LAW_STRETCH + 1, e)] = s1
        law[_at(LAW_STRETCH + 2, e)] = s2
        law[_at(LAW_STRAIN, e)] = -(s0 - 1.0)
        law[_at(LAW_STRAIN + 1, e)] = -(s1 - 1.0)
        law[_at(LAW_STRAIN + 2, e)] = -(s2 - 1.0)


@nb.njit(error_model="numpy")
def _block_segments(law: np.ndarray, strains: np.ndarray, count: int) -> None:
    """Pass 2: each direction's segment of the curve ``strains`` at its compressive strain,
    :func:`_segment`'s scan one point at a time across the lanes (a lane stops where the scan
    stops)."""
    for e in range(EIGEN_LANES):
        for i in range(3):
            law[_at(LAW_SEGMENT + i, e)] = 0.0
    for k in range(count - 2):
        point = strains[k + 1]
        for e in range(EIGEN_LANES):
            for i in range(3):
                at_k = law[_at(LAW_SEGMENT + i, e)] == k
                beyond = law[_at(LAW_STRAIN + i, e)] > point
                law[_at(LAW_SEGMENT + i, e)] += 1.0 if at_k and beyond else 0.0


@nb.njit
def _block_knots(law: np.ndarray, strains: np.ndarray, stresses: np.ndarray,
                 energies: np.ndarray) -> None:  # fmt: skip
    """Pass 2b, one lane at a time (indexed loads): each direction's segment into the LAW_KNOT
    rows, so that the passes that use them vectorise."""
    for e in range(EIGEN_LANES):
        for i in range(3):
            k = _index(law, LAW_SEGMENT + i, e)
            above = k + np.uint64(1)
            row = LAW_KNOT + 5 * i
            law[_at(row + K_STRAIN, e)] = strains[k]
            law[_at(row + K_NEXT_STRAIN, e)] = strains[above]
            law[_at(row + K_STRESS, e)] = stresses[k]
            law[_at(row + K_NEXT_STRESS, e)] = stresses[above]
            law[_at(row + K_ENERGY, e)] = energies[k]


@nb.njit(inline="always")
def _knot_slope(law: np.ndarray, e: int, i: int) -> float:
    """The slope of direction i's segment (:func:`_segment_slope` of the LAW_KNOT rows)."""
    row = LAW_KNOT + 5 * i
    rise = law[_at(row + K_NEXT_STRESS, e)] - law[_at(row + K_STRESS, e)]
    return rise / (law[_at(row + K_NEXT_STRAIN, e)] - law[_at(row + K_STRAIN, e)])


@nb.njit(error_model="numpy")
def _block_energy(law: np.ndarray, table: tuple[np.ndarray, ...]) -> None:
    """Pass 3: W on the first loading curve and in tension, and whether it is loading."""
    params = table[0]
    young, cutoff = params[P_E], params[P_TC]
    for e in range(EIGEN_LANES):
        w = 0.0
        for i in range(3):
            s = law[_at(LAW_STRAIN + i, e)]
            row = LAW_KNOT + 5 * i
            d = s - law[_at(row + K_STRAIN, e)]
            curve = (law[_at(row + K_ENERGY, e)] + law[_at(row + K_STRESS, e)] * d
                     + 0.5 * _knot_slope(law, e, i) * d * d)  # fmt: skip
            tension = tension_stress_energy(-s, young, cutoff)[1]
            w += curve if -s < 0.0 else tension
        law[_at(LAW_ENERGY, e)] = w
        law[_at(LAW_LOADING, e)] = 1.0 if w >= law[_at(LAW_WMAX, e)] else 0.0


@nb.njit
def _block_factors(law: np.ndarray, n: int, params: np.ndarray) -> None:
    """Pass 4, one lane at a time (its powers are library calls): 1 - D and d(1 - D)/dW, and
    W_max where loading."""
    hu, shape = params[P_HU], params[P_SHAPE]
    for e in range(n):
        w, w_max = law[_at(LAW_ENERGY, e)], law[_at(LAW_WMAX, e)]
        growth = 0.0
        if w >= w_max:
            law[_at(LAW_WMAX, e)] = w
        elif w > 0.0:
            growth = (1.0 - hu) * shape * (w / w_max) ** (shape - 1.0) / w_max
        law[_at(LAW_FACTOR, e)] = hysteresis_factor(w, w_max, hu, shape)
        law[_at(LAW_GROWTH, e)] = growth


@nb.njit(error_model="numpy")
def _block_rate_curves(law: np.ndarray, table: tuple[np.ndarray, ...]) -> None:
    """Pass 5 (MAT_083): :func:`rate_curve_stress` of each direction into the LAW_RATED rows,
    its scans over the rates and each curve's points one step at a time across the lanes."""
    rates, strains, stresses, counts = table[1], table[2], table[3], table[4]
    n_rates = rates.shape[0]
    for e in range(EIGEN_LANES):
        law[_at(LAW_CURVE + 1, e)] = 0.0
    for j in range(n_rates - 2):
        for e in range(EIGEN_LANES):
            at_j = law[_at(LAW_CURVE + 1, e)] == j
            law[_at(LAW_CURVE + 1, e)] += (
                1.0 if at_j and law[_at(LAW_RATE, e)] > rates[j + 1] else 0.0
            )
    for e in range(EIGEN_LANES):
        low, high = _rate_outside(rates, law[_at(LAW_RATE, e)])
        law[_at(LAW_CURVE, e)] = (
            0.0 if low else (n_rates - 1.0 if high else law[_at(LAW_CURVE + 1, e)])
        )
        for c in range(6):
            law[_at(LAW_CURVE_SEGMENT + c, e)] = 0.0
    for k in range(counts.max() - 2):
        for e in range(EIGEN_LANES):
            for c in range(2):
                # the lower curve, then j + 1 (the last where there is one curve)
                curve = min(int(law[_at(LAW_CURVE + c, e)]) + c, n_rates - 1)
                running = k < counts[curve] - 2
                for i in range(3):
                    row = LAW_CURVE_SEGMENT + 3 * c + i
                    beyond = law[_at(LAW_STRAIN + i, e)] > strains[curve, k + 1]
                    law[_at(row, e)] += 1.0 if running and law[_at(row, e)] == k and beyond else 0.0
    for e in range(EIGEN_LANES):
        rate = law[_at(LAW_RATE, e)]
        low, high = _rate_outside(rates, rate)
        j = int(law[_at(LAW_CURVE + 1, e)])
        above_j = min(j + 1, n_rates - 1)  # one curve: j + 1 would be past the table
        first = int(law[_at(LAW_CURVE, e)])
        weight = (rate - rates[j]) / (rates[above_j] - rates[j])
        for i in range(3):
            s = law[_at(LAW_STRAIN + i, e)]
            k = int(law[_at(LAW_CURVE_SEGMENT + i, e)])
            below = _segment_stress(strains[first], stresses[first], k, s)
            k = int(law[_at(LAW_CURVE_SEGMENT + 3 + i, e)])
            above = _segment_stress(strains[above_j], stresses[above_j], k, s)
            mixed = (1.0 - weight) * below + weight * above
            law[_at(LAW_RATED + i, e)] = below if low or high else mixed


@nb.njit(inline="always")
def _nominal(law, e, i, stretch, rated, factor, growth, young, cutoff):
    """Direction i's nominal stress and tangent d tau / d e (:func:`principal_nominal_stresses`
    with its branches as selects)."""
    strain = stretch - 1.0
    s = law[_at(LAW_STRAIN + i, e)]
    row = LAW_KNOT + 5 * i
    slope = _knot_slope(law, e, i)
    f = law[_at(row + K_STRESS, e)] + slope * (s - law[_at(row + K_STRAIN, e)])
    compressed = (
        (-law[_at(LAW_RATED + i, e)], young)
        if rated
        else (-factor * f, factor * slope + growth * f * f)
    )
    stretched = (tension_stress_energy(strain, young, cutoff)[0], young)
    return stretched if strain >= 0.0 else compressed


@nb.njit(error_model="numpy")
def _block_stress(law: np.ndarray, eig: np.ndarray, table: tuple[np.ndarray, ...]) -> None:
    """Pass 6: the nominal stresses, the largest Cauchy tangent and sigma."""
    params = table[0]
    young, cutoff = params[P_E], params[P_TC]
    mat083 = params[P_KIND] == KIND_MAT083
    for e in range(EIGEN_LANES):
        s0, s1, s2 = (law[_at(LAW_STRETCH, e)], law[_at(LAW_STRETCH + 1, e)],
                      law[_at(LAW_STRETCH + 2, e)])  # fmt: skip
        factor, growth = law[_at(LAW_FACTOR, e)], law[_at(LAW_GROWTH, e)]
        rated = mat083 and law[_at(LAW_LOADING, e)] != 0.0
        jacobian = s0 * s1 * s2
        tau0, t0 = _nominal(law, e, 0, s0, rated, factor, growth, young, cutoff)
        tau1, t1 = _nominal(law, e, 1, s1, rated, factor, growth, young, cutoff)
        tau2, t2 = _nominal(law, e, 2, s2, rated, factor, growth, young, cutoff)
        tangent = max(0.0, t0 * s0 * s0 / jacobian)
        tangent = max(tangent, t1 * s1 * s1 / jacobian)
        tangent = max(tangent, t2 * s2 * s2 / jacobian)
        cauchy = (tau0 * s0 / jacobian, tau1 * s1 / jacobian, tau2 * s2 / jacobian)
        for i in range(3):
            for j in range(3):
                total = 0.0
                for k in range(3):
                    vi = eig[_at(EIGEN_V + 3 * i + k, e)]
                    vj = eig[_at(EIGEN_V + 3 * j + k, e)]
                    total += cauchy[k] * vi * vj
                law[_at(LAW_SIGMA + 3 * i + j, e)] = total
        law[_at(LAW_TANGENT, e)] = tangent


@nb.njit
def block_principal_stress(
    law: np.ndarray, eig: np.ndarray, n: int, weight: float, table: tuple[np.ndarray, ...]
) -> None:
    """:func:`principal_stress` of lanes 0..n-1 at once, their b decomposed in the eigen block
    ``eig`` (:func:`block_symmetric_eigen`) and their D, filtered rate and W_max in the rows
    LAW_D, LAW_RATE and LAW_WMAX of ``law``: sigma into the LAW_SIGMA rows, the tangent into
    LAW_TANGENT, the new rate and W_max in place. The same operations in the same order for
    each lane as the one-point routine, the same bits; its branches become selects (both
    sides computed, one kept) and its curve scans run one point at a time across the lanes, so
    that the passes vectorise; only the powers of the unloading damage go one lane at a time."""
    _block_stretches(law, eig, weight)
    _block_segments(law, table[2][0], table[4][0])
    _block_knots(law, table[2][0], table[3][0], table[5])
    _block_energy(law, table)
    _block_factors(law, n, table[0])
    if table[0][P_KIND] == KIND_MAT083:
        _block_rate_curves(law, table)
    _block_stress(law, eig, table)
