"""Explicit internal forces of the statics' MITC4 shell in a co-rotational frame.

The one-point Belytschko-Tsay shells (:mod:`batball.elements.shell_bt`) carry artificial
hourglass stiffness that sets part of the answer under a nearly point load: the barrel test's
platens (docs/notes/barrel.md, "Why r = 1 stays 7-8 % soft"). This module gives the explicit solvers
the fully integrated MITC4 element of the statics (:mod:`batball.elements.shell_stiffness`:
2 x 2 Gauss membrane and bending with the centre-sampled membrane shear, MITC4 transverse
shear, the drilling penalty), made geometrically nonlinear by the element-independent
co-rotational formulation (EICR; Rankin & Nour-Omid 1988, Felippa & Haugen, CMAME 194 (2005)
2285-2335):

* Each node carries its total rotation R_a (3 x 3, global), advanced every cycle by the
  rotation the angular velocity makes over the step, R_a <- exp(dt omega_a) R_a (Rodrigues).
  These are the state (``CorotationalState.history``, stored by the fit store as the BT
  shells' stresses are).
* Each cell's frame E (rows e1, e2, e3) is the BT shell's, rebuilt from the current corners
  (e3 along r31 x r42, e1 along edge 1-2 projected, e2 = e3 x e1); E0 the same frame of the
  undeformed cell. The deformational displacement of corner a in the frame is
  u_a = E (x_a - c) - E0 (X_a - C), c and C the centroids, and its deformational rotation the
  rotation vector of E R_a E0^T (an exact logarithm).
* Local forces f = K0 d, K0 the MITC4 stiffness of the undeformed cell in its frame (24 x 24,
  linear elastic laminate: the strains stay small, the rotations need not). K0 annihilates the
  rigid motions of the undeformed cell, so f sums to zero; its moment about the current
  centroid is second order in the strain and is removed by the smallest couple w x p_a
  (p_a the current corner positions about c) that cancels it, the role EICR's projector plays.
  The rotational Jacobian H of the logarithm is taken as the identity (deformational
  rotations of the order of the strains).
* The forces are turned back to global axes, f_global = E^T f, moments likewise.

With the nodes barely moved the forces equal the statics' K u (``tests/unit/elements/
test_shell_corotational.py``); a rigid rotation of any size strains nothing.

The kernel runs the cells in chunks of up to CHUNK cells of one kind (one shape and section,
hence one K0), each chunk in one pass through a small work array that stays in cache, and
adds each corner's forces into its node as soon as the chunk has made them, in cell order (the
same sums on any number of threads). The gather of the corners' positions and rotations and
that scatter go node by node (each node's values moved by vector loads and stores); every other
step is a SIMD loop over the chunk's cells. Cost: a
force evaluation takes 1.2-1.4 times the BT kernel's on the full bat (benchmarks/RESULTS.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np
from scipy.sparse.linalg import LinearOperator, eigsh

from batball.elements.hex8_geometry import cross
from batball.elements.shell_bt import Vec3, dot3, element_frame
from batball.elements.shell_stiffness import (
    DRILLING_FACTOR,
    ShellSection,
    element_frames,
    local_stiffness,
)
from batball.elements.vector_math import gather_columns, interleave_rows, subtract_record
from batball.errors import SimulationError
from batball.numerics import FASTMATH

#: The explicit solvers' shell elements: the co-rotational MITC4 of this module, or the
#: one-point Belytschko-Tsay shells of :mod:`batball.elements.shell_bt`.
SHELLS = ("mitc4", "bt")


@dataclass(frozen=True)
class CorotationalState:
    """The nodes' total rotations, updated in place.

    Attributes:
        history: (n_points, 3, 3) rotation matrices R_a (global; identity undeformed).
    """

    history: np.ndarray


def initial_rotations(n_points: int) -> CorotationalState:
    """Every node unrotated."""
    return CorotationalState(np.tile(np.eye(3), (n_points, 1, 1)))


#: Below this squared angle [rad^2] the rotation's sin(p) / p and (1 - cos(p)) / p^2 are their
#: series to p^6: the first term left out is below 3e-22 of the sum, far under double
#: precision; the series is a few multiply-adds where sin and cos are calls (at the
#: batted-ball-speed test's step, 0.2 us, the angle stays below 1e-4 rad up to 500 rad/s), and
#: it avoids the cancellation of 1 - cos(p), which costs (1 - cos(p)) / p^2 about eps / p^2 of
#: its relative accuracy (5e-9 at p = 1e-4).
SERIES_ANGLE2 = 1e-4


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def advance_rotations(rotations: np.ndarray, velocity: np.ndarray, dt: float,
                      runs: tuple[np.ndarray, np.ndarray]) -> None:  # fmt: skip
    """R_a <- exp(dt omega_a) R_a for every node (Rodrigues), omega the global rotation rates
    ``velocity[:, 3:6]`` [rad/s] over the last step ``dt`` [s]. The nodes go in ``runs``
    (order, start; :func:`rotation_runs`): run r updates ``order[start[r]:start[r + 1]]``, on
    the thread that then runs the force kernel's run r, which reads them (each node's update
    is its own: the same bits in any order)."""
    order, start = runs
    for run in nb.prange(start.shape[0] - 1):
        for i in range(start[run], start[run + 1]):
            n = order[i]
            p0, p1, p2 = dt * velocity[n, 3], dt * velocity[n, 4], dt * velocity[n, 5]
            angle2 = p0 * p0 + p1 * p1 + p2 * p2
            if angle2 == 0.0:
                continue
            if angle2 < SERIES_ANGLE2:
                a = 1.0 - angle2 * (1.0 / 6.0 - angle2 * (1.0 / 120.0 - angle2 * (1.0 / 5040.0)))
                b = 0.5 - angle2 * (1.0 / 24.0 - angle2 * (1.0 / 720.0 - angle2 * (1.0 / 40320.0)))
            else:
                angle = np.sqrt(angle2)
                a, b = np.sin(angle) / angle, (1.0 - np.cos(angle)) / angle2
            # Q = I + a [p]x + b [p]x^2, [p]x^2 = p p^T - |p|^2 I
            q00, q11, q22 = 1.0 + b * (p0 * p0 - angle2), 1.0 + b * (p1 * p1 - angle2), \
                1.0 + b * (p2 * p2 - angle2)
            q01, q10 = b * p0 * p1 - a * p2, b * p0 * p1 + a * p2
            q02, q20 = b * p0 * p2 + a * p1, b * p0 * p2 - a * p1
            q12, q21 = b * p1 * p2 - a * p0, b * p1 * p2 + a * p0
            for j in range(3):
                r0, r1, r2 = rotations[n, 0, j], rotations[n, 1, j], rotations[n, 2, j]
                rotations[n, 0, j] = q00 * r0 + q01 * r1 + q02 * r2
                rotations[n, 1, j] = q10 * r0 + q11 * r1 + q12 * r2
                rotations[n, 2, j] = q20 * r0 + q21 * r1 + q22 * r2


#: Cells per task of the parallel loops, and the width of the kernel's SIMD loops: every column
#: is computed, a chunk's columns past its last cell repeating it, so a kind whose cells do not
#: fill whole chunks pays for empty columns. A bat's kinds are its rings (cells of one shape),
#: so their sizes are multiples of the cells around: 48 on the default mesh, whose 20,928 cells
#: then fill 436 chunks with no empty column, where chunks of 64 computed 22,464 columns (89 of
#: its 97 kinds are single rings of 48). On the AVX-512 Xeon the full-size bat's force call took
#: 0.84-0.94 of the time with 64 on two threads, on one within the host's noise (RESULTS.md).
CHUNK = 48

# A chunk's work array ``w`` holds one row per quantity and one column per cell (structure of
# arrays, row r of column col at [r * CHUNK + col], the rows constant: LLVM then sees that the
# loops over the columns carry no dependence and vectorises them): the current frame E's rows,
# the corners' cosines, the 24 deformational dofs (dof k of corner a at row W_D + dof(a, k),
# k = 0..2 the displacements, 3..5 the rotations; later the global forces), the 24 local forces
# (alike from W_F; once turned to global axes, the same rows hold the scatter's records,
# :func:`corner_record`), and the corners' squared sines. Before the local forces are made, the
# rows from W_F on hold what the cells' corners are gathered into: corner a's current
# coordinate k at row W_X + 3 a + k and its total rotation's entry (i, j) at row W_R + 9 a +
# 3 i + j; the centroid's coordinates at rows W_M..W_M + 2 (for :func:`corner_loop`). The
# corners' reference positions are read from the chunk's constants where they are needed, not
# copied here: at 88 rows the array (33 KiB) fits a 48 KiB first-level data cache
# (benchmarks/RESULTS.md).
W_FRAME, W_COS, W_D, W_F, W_SINE2 = 0, 9, 13, 37, 61
W_X, W_R, W_M, W_ROWS = 37, 49, 85, 88
#: Rows of a chunk's constants (``CorotationalShellForces.constants``): the undeformed frame E0
#: (row-major) and the corners' reference positions, one column per cell.
C_FRAME0, C_REF, C_ROWS = 0, 9, 21


#: The group of each of a corner's dofs k = 0..5 (u, v, w, theta_x, theta_y, theta_z in the
#: cell's frame) in the work array's 24 dof rows: the membrane translations u of the four
#: corners first, then v, the bending rotations theta_x and theta_y, the normal translations w,
#: the drilling rotations theta_z (:func:`dof`). In that order the MITC4 K0 has whole 4 x 4
#: blocks of zeros, which :func:`local_product` skips: w enters only the transverse shear (with
#: theta_x, theta_y), and the drilling penalty ties theta_z to u and v only (10 of the 36
#: blocks).
DOF_GROUP = (0, 1, 4, 2, 3, 5)


@nb.njit(inline="always")
def dof(a: int, k: int) -> int:
    """The row of dof ``k`` (0..5) of corner ``a`` among the work array's 24 dof rows."""
    group = 4 if k == 2 else (k - 1 if k == 3 or k == 4 else k)  # DOF_GROUP[k]
    return 4 * group + a


#: PRODUCT_ORDER[r] = 6 a + k, the element dof (corner a, dof k) at dof row r.
PRODUCT_ORDER = np.argsort([4 * DOF_GROUP[k] + a for a in range(4) for k in range(6)])


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def load_dofs(w: np.ndarray, base: int, a: int, k: int, col: int) -> Vec3:
    """Dofs ``k`` to ``k + 2`` of corner ``a`` of column ``col``, of the 24 dof rows from row
    ``base`` (W_D or W_F)."""
    return (w[(base + dof(a, k)) * CHUNK + col], w[(base + dof(a, k + 1)) * CHUNK + col],
            w[(base + dof(a, k + 2)) * CHUNK + col])


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def load3(w: np.ndarray, row: int, col: int) -> Vec3:
    """Rows ``row`` to ``row + 2`` of column ``col`` of the work array."""
    return w[row * CHUNK + col], w[(row + 1) * CHUNK + col], w[(row + 2) * CHUNK + col]


#: Columns the corner gather fills at once (CHUNK is a multiple of it): one 256-bit vector
#: of doubles; _corner_offsets and gather_corners spell out the four.
GATHER_COLUMNS = 4


@nb.njit(inline="always")
def _corner_offsets(cells: np.ndarray, c: tuple, a: int, size: int) -> tuple:
    """Flat offsets of corner ``a``'s node of the GATHER_COLUMNS cells ``c`` in an array of
    ``size`` values a node (unsigned)."""
    u = np.uint64(size)
    return (u * np.uint64(cells[c[0], a]), u * np.uint64(cells[c[1], a]),
            u * np.uint64(cells[c[2], a]), u * np.uint64(cells[c[3], a]))  # fmt: skip


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def gather_corners(points: np.ndarray, cells: np.ndarray, rotations: np.ndarray, first: int,
                   stop: int, w: np.ndarray) -> None:  # fmt: skip
    """The corners' positions and total rotations of cells ``first`` to ``stop`` into the work
    array's rows W_X and W_R, cell first + col in column col, the columns past the last cell
    repeating it; GATHER_COLUMNS columns at a time (:func:`vector_math.gather_columns`: each
    node's values loaded in pairs, each row's columns stored as one vector)."""
    xs, rs = points.reshape(-1), rotations.reshape(-1)
    last, stride = stop - 1, np.uint64(CHUNK)
    for col in range(0, CHUNK, GATHER_COLUMNS):
        c = (min(first + col, last), min(first + col + 1, last),
             min(first + col + 2, last), min(first + col + 3, last))  # fmt: skip
        for a in range(4):
            gather_columns(w, np.uint64((W_X + 3 * a) * CHUNK + col), stride, xs,
                           _corner_offsets(cells, c, a, 3), 3)  # fmt: skip
            gather_columns(w, np.uint64((W_R + 9 * a) * CHUNK + col), stride, rs,
                           _corner_offsets(cells, c, a, 9), 9)  # fmt: skip


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def frame_row_times(e: Vec3, w: np.ndarray, a: int, col: int) -> Vec3:
    """The row vector e^T R_a of corner ``a``'s rotation in column ``col`` (rows W_R)."""
    r = (W_R + 9 * a) * CHUNK + col
    return (e[0] * w[r] + e[1] * w[r + 3 * CHUNK] + e[2] * w[r + 6 * CHUNK],
            e[0] * w[r + CHUNK] + e[1] * w[r + 4 * CHUNK] + e[2] * w[r + 7 * CHUNK],
            e[0] * w[r + 2 * CHUNK] + e[1] * w[r + 5 * CHUNK] + e[2] * w[r + 8 * CHUNK])


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def deformation(constants: np.ndarray, w: np.ndarray) -> None:
    """The work array's columns, from their corners gathered (:func:`gather_corners`) and the
    chunk's ``constants`` (C_ROWS * CHUNK,): the current frame's rows and the centroid, then
    for each corner its deformational displacements (local frame) and, of its rotation in the
    frames, E R_a E0^T, the cosine and the sine vector s (the axial vector of the skew part,
    in the rotation rows, which :func:`rotation_vectors` turns into the rotation vector).
    Every load and store is a row of a column: SIMD loops over the columns, the frames and
    centroids first, then one loop a corner (:func:`corner_loop`). As one loop it held E, E0
    and the centroid through all four corners, more values than AVX2's sixteen vector
    registers (173 stack moves in an iteration of 644 instructions; benchmarks/RESULTS.md)."""
    for col in range(CHUNK):
        x0, x1 = load3(w, W_X, col), load3(w, W_X + 3, col)
        x2, x3 = load3(w, W_X + 6, col), load3(w, W_X + 9, col)
        e1, e2, e3 = element_frame(x0, x1, x2, x3)
        for k in range(3):
            w[(W_FRAME + k) * CHUNK + col] = e1[k]
            w[(W_FRAME + 3 + k) * CHUNK + col] = e2[k]
            w[(W_FRAME + 6 + k) * CHUNK + col] = e3[k]
        w[W_M * CHUNK + col] = 0.25 * (x0[0] + x1[0] + x2[0] + x3[0])
        w[(W_M + 1) * CHUNK + col] = 0.25 * (x0[1] + x1[1] + x2[1] + x3[1])
        w[(W_M + 2) * CHUNK + col] = 0.25 * (x0[2] + x1[2] + x2[2] + x3[2])
    # straight-line code: a loop over the corners here would be the innermost loop that LLVM
    # tries to vectorise, instead of the loop over the columns
    corner_loop(constants, w, 0)
    corner_loop(constants, w, 1)
    corner_loop(constants, w, 2)
    corner_loop(constants, w, 3)


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def corner_loop(constants: np.ndarray, w: np.ndarray, a: int) -> None:
    """Corner ``a`` of :func:`deformation` in every column."""
    for col in range(CHUNK):
        e1, e2 = load3(w, W_FRAME, col), load3(w, W_FRAME + 3, col)
        e3, m = load3(w, W_FRAME + 6, col), load3(w, W_M, col)
        f0 = load3(constants, C_FRAME0, col)
        f1 = load3(constants, C_FRAME0 + 3, col)
        f2 = load3(constants, C_FRAME0 + 6, col)
        corner_deformation((e1, e2, e3), m, (f0, f1, f2), constants, w, a, col)


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def corner_deformation(frame: tuple, m: Vec3, frame0: tuple, constants: np.ndarray,
                       w: np.ndarray, a: int, col: int) -> None:  # fmt: skip
    """Corner ``a`` of :func:`deformation`: its deformational displacement and rotation's
    cosine and sine vector, with the current ``frame`` E, centroid ``m`` and the undeformed
    frame ``frame0`` E0."""
    e1, e2, e3 = frame
    f0, f1, f2 = frame0
    ref = load3(constants, C_REF + 3 * a, col)
    x = load3(w, W_X + 3 * a, col)
    p = (x[0] - m[0], x[1] - m[1], x[2] - m[2])
    w[(W_D + dof(a, 0)) * CHUNK + col] = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2] - ref[0]
    w[(W_D + dof(a, 1)) * CHUNK + col] = e2[0] * p[0] + e2[1] * p[1] + e2[2] * p[2] - ref[1]
    w[(W_D + dof(a, 2)) * CHUNK + col] = e3[0] * p[0] + e3[1] * p[1] + e3[2] * p[2] - ref[2]
    # the corner's rotation in the frames, E R_a E0^T, row by row
    r0 = frame_row_times(e1, w, a, col)
    r1 = frame_row_times(e2, w, a, col)
    r2 = frame_row_times(e3, w, a, col)
    m01, m02, m10 = dot3(r0, f1), dot3(r0, f2), dot3(r1, f0)
    m12, m20, m21 = dot3(r1, f2), dot3(r2, f0), dot3(r2, f1)
    w[(W_D + dof(a, 3)) * CHUNK + col] = 0.5 * (m21 - m12)
    w[(W_D + dof(a, 4)) * CHUNK + col] = 0.5 * (m02 - m20)
    w[(W_D + dof(a, 5)) * CHUNK + col] = 0.5 * (m10 - m01)
    w[(W_COS + a) * CHUNK + col] = 0.5 * (dot3(r0, f0) + dot3(r1, f1) + dot3(r2, f2) - 1.0)


#: Below this squared sine (and at a positive cosine, a rotation under 5.7 degrees) a rotation's
#: angle / sine is its series, asin(s) / s to s^14: the first term left out, 6435/557056 s^16,
#: is below 1.2e-18 of the sum, under double precision's rounding; above it, atan2
#: (:func:`rotation_vectors`), a scalar call. In a full-size BBS impact up to a quarter of the
#: corners turn by more than 0.57 degrees (sine^2 1e-4), none by more than 3.2 (3e-3), and they
#: lie in the chunks of one thread's run (benchmarks/RESULTS.md).
SERIES_SINE2 = 1e-2


@nb.njit(inline="always", fastmath=FASTMATH)
def angle_over_sine(sine2: float) -> float:
    """asin(s) / s to s^14 (Horner) from s^2: the sum over n of (2n)! / (4^n n!^2 (2n + 1))
    s^(2n) (:data:`SERIES_SINE2`)."""
    tail = 231.0 / 13312.0 + sine2 * (143.0 / 10240.0)
    tail = 63.0 / 2816.0 + sine2 * tail
    tail = 35.0 / 1152.0 + sine2 * tail
    tail = 5.0 / 112.0 + sine2 * tail
    tail = 3.0 / 40.0 + sine2 * tail
    return 1.0 + sine2 * (1.0 / 6.0 + sine2 * tail)


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def rotation_vectors(w: np.ndarray, n: int) -> None:
    """The corners' rotation vectors (axis times angle, an exact logarithm) in the work array's
    rotation rows (dofs 3..5 of corner a), from the sine vectors s there and the cosines: s times
    angle / |s|. The series is taken over all CHUNK columns at once (the SIMD loop); the few
    corners with a larger angle, among the first ``n`` columns, are then redone with atan2."""
    for col in range(CHUNK):
        for a in range(4):
            s = load_dofs(w, W_D, a, 3, col)
            sine2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2]
            series = angle_over_sine(sine2)
            small = sine2 < SERIES_SINE2 and w[(W_COS + a) * CHUNK + col] > 0.0
            factor = series if small else 1.0
            w[(W_SINE2 + a) * CHUNK + col] = sine2  # the test below is this one's
            for k in range(3):
                w[(W_D + dof(a, 3 + k)) * CHUNK + col] = factor * s[k]
    for col in range(n):
        for a in range(4):
            sine2, cosine = w[(W_SINE2 + a) * CHUNK + col], w[(W_COS + a) * CHUNK + col]
            if sine2 < SERIES_SINE2 and cosine > 0.0:
                continue  # scaled by the series above
            s = load_dofs(w, W_D, a, 3, col)  # not scaled (factor 1 above)
            sine = np.sqrt(sine2)
            factor = np.arctan2(sine, cosine) / sine
            for k in range(3):
                w[(W_D + dof(a, 3 + k)) * CHUNK + col] = factor * s[k]


def product_blocks(stiffness: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each kind's K0 (n_kinds, 24, 24) in the order of the work array's dof rows
    (:data:`PRODUCT_ORDER`), and which of its 4 x 4 blocks hold a non-zero entry, (n_kinds, 6,
    6) (uint8): the blocks :func:`local_product` sweeps."""
    ordered = np.ascontiguousarray(stiffness[:, PRODUCT_ORDER][:, :, PRODUCT_ORDER])
    nonzero = (ordered != 0.0).reshape(-1, 6, 4, 6, 4).any(axis=(2, 4))
    return ordered, nonzero.astype(np.uint8)


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def local_product(stiffness: np.ndarray, nonzero: np.ndarray, w: np.ndarray) -> None:
    """f = K d on the work array's dof rows, K (24, 24) in their order (:data:`DOF_GROUP`) and
    ``nonzero`` (6, 6) its 4 x 4 blocks that are not all zero (:func:`product_blocks`): a block
    at a time swept across all CHUNK columns (a constant trip count; each loaded column of d
    serves four rows of f, each loaded column of f four of d: 2.3 times the speed of a row at a
    time, the SIMD loop near the machine's multiply-add rate), the blocks of zeros skipped. Each
    sum runs over the dof rows in order."""
    for i in range(0, 24, 4):
        f0, f1 = (W_F + i) * CHUNK, (W_F + i + 1) * CHUNK
        f2, f3 = (W_F + i + 2) * CHUNK, (W_F + i + 3) * CHUNK
        for col in range(CHUNK):
            w[f0 + col] = 0.0
            w[f1 + col] = 0.0
            w[f2 + col] = 0.0
            w[f3 + col] = 0.0
        for j in range(0, 24, 4):
            if nonzero[i // 4, j // 4] == 0:
                continue
            d0, d1 = (W_D + j) * CHUNK, (W_D + j + 1) * CHUNK
            d2, d3 = (W_D + j + 2) * CHUNK, (W_D + j + 3) * CHUNK
            k00, k01, k02, k03 = stiffness[i, j], stiffness[i, j + 1], stiffness[i, j + 2], \
                stiffness[i, j + 3]
            k10, k11, k12, k13 = stiffness[i + 1, j], stiffness[i + 1, j + 1], \
                stiffness[i + 1, j + 2], stiffness[i + 1, j + 3]
            k20, k21, k22, k23 = stiffness[i + 2, j], stiffness[i + 2, j + 1], \
                stiffness[i + 2, j + 2], stiffness[i + 2, j + 3]
            k30, k31, k32, k33 = stiffness[i + 3, j], stiffness[i + 3, j + 1], \
                stiffness[i + 3, j + 2], stiffness[i + 3, j + 3]
            for col in range(CHUNK):
                a, b, c, d = w[d0 + col], w[d1 + col], w[d2 + col], w[d3 + col]
                w[f0 + col] = w[f0 + col] + k00 * a + k01 * b + k02 * c + k03 * d
                w[f1 + col] = w[f1 + col] + k10 * a + k11 * b + k12 * c + k13 * d
                w[f2 + col] = w[f2 + col] + k20 * a + k21 * b + k22 * c + k23 * d
                w[f3 + col] = w[f3 + col] + k30 * a + k31 * b + k32 * c + k33 * d


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def balance_moment(constants: np.ndarray, w: np.ndarray, col: int) -> None:
    """Remove from column ``col``'s local forces (rows W_F..) their moment M about the current
    centroid by the forces c x p_a, J c = -M, J = sum (|p|^2 I - p p^T), p_a = reference + d
    the corners' current local positions (module docs), the reference positions from the
    chunk's ``constants``."""
    mx = my = mz = 0.0
    j00 = j11 = j22 = j01 = j02 = j12 = 0.0
    for a in range(4):
        ref, u = load3(constants, C_REF + 3 * a, col), load_dofs(w, W_D, a, 0, col)
        p = (ref[0] + u[0], ref[1] + u[1], ref[2] + u[2])
        t = cross(p, load_dofs(w, W_F, a, 0, col))
        rotational = load_dofs(w, W_F, a, 3, col)
        mx += t[0] + rotational[0]
        my += t[1] + rotational[1]
        mz += t[2] + rotational[2]
        pp = dot3(p, p)
        j00 += pp - p[0] * p[0]
        j11 += pp - p[1] * p[1]
        j22 += pp - p[2] * p[2]
        j01 -= p[0] * p[1]
        j02 -= p[0] * p[2]
        j12 -= p[1] * p[2]
    # w = -J^-1 M by the adjugate of the symmetric J
    a00, a11, a22 = j11 * j22 - j12 * j12, j00 * j22 - j02 * j02, j00 * j11 - j01 * j01
    a01, a02, a12 = j02 * j12 - j01 * j22, j01 * j12 - j02 * j11, j01 * j02 - j00 * j12
    det = j00 * a00 + j01 * a01 + j02 * a02
    couple = (-(a00 * mx + a01 * my + a02 * mz) / det, -(a01 * mx + a11 * my + a12 * mz) / det,
              -(a02 * mx + a12 * my + a22 * mz) / det)  # fmt: skip
    for a in range(4):
        ref, u = load3(constants, C_REF + 3 * a, col), load_dofs(w, W_D, a, 0, col)
        t = cross(couple, (ref[0] + u[0], ref[1] + u[1], ref[2] + u[2]))
        for k in range(3):
            w[(W_F + dof(a, k)) * CHUNK + col] += t[k]


#: How :func:`scatter_chunk` takes a corner's forces to its node (:func:`corner_kinds`): minus
#: them added to the node's forces, or setting them (the node's first corner), or stored in the
#: chunk's shared corners (a node whose corners two runs of chunks make).
ADD, FIRST, SHARED = 0, 1, 2


@nb.njit(inline="always")
def run_count(n_runs: int, n_chunks: int) -> int:
    """The runs of consecutive chunks the chunks are split into, given ``n_runs`` asked for: at
    least one, at most one a chunk (:func:`run_start`)."""
    return max(1, min(n_runs, n_chunks))


@nb.njit(inline="always")
def run_start(run: int, runs: int, n_chunks: int) -> int:
    """The first chunk of run ``run`` of ``runs`` (:func:`run_count`); run r holds chunks
    run_start(r) to run_start(r + 1) - 1."""
    return run * n_chunks // runs


def run_bounds(n_runs: int, n_chunks: int) -> np.ndarray:
    """The runs' first chunks and then ``n_chunks``, (runs + 1,), for ``n_runs`` asked for:
    :func:`run_count` and :func:`run_start`, the kernel's own rules, in Python."""
    runs = run_count.py_func(n_runs, n_chunks)
    return np.array([run_start.py_func(r, runs, n_chunks) for r in range(runs + 1)])


def corner_kinds(cells: np.ndarray, chunk_start: np.ndarray, corners: tuple,
                 n_runs: int) -> np.ndarray:  # fmt: skip
    """Each corner's kind (ADD, FIRST or SHARED), corner a of cell c at 4 c + a (int8), when the
    chunks (``chunk_start``, :func:`kind_chunks`) run in ``n_runs`` runs (:func:`run_count`):
    SHARED where one of the node's corners is in a chunk of another run (``corners``, from
    :func:`node_corners`: the chunks of the node's first and last corner), else FIRST for the
    node's first corner, else ADD. Taken once a number of runs, not in every call."""
    n_chunks = chunk_start.size - 1
    bounds = run_bounds(n_runs, n_chunks)
    run = np.searchsorted(bounds, np.arange(n_chunks), side="right") - 1
    cell_run = np.repeat(run, np.diff(chunk_start))
    begin, end = bounds[cell_run][:, None], bounds[cell_run + 1][:, None]
    first_chunk, last_chunk, first_corner = corners[4], corners[5], corners[6]
    shared = (first_chunk[cells] < begin) | (last_chunk[cells] >= end)
    first = first_corner[cells] == 4 * np.arange(cells.shape[0])[:, None] + np.arange(4)
    return np.where(shared, SHARED, np.where(first, FIRST, ADD)).astype(np.int8).ravel()


def rotation_runs(first_chunk: np.ndarray, n_chunks: int,
                  n_runs: int) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The nodes by the run of the chunk of their first corner (``first_chunk``, from
    :func:`node_corners`; a node of no cell with run 0) when ``n_chunks`` chunks run in
    ``n_runs`` runs (:func:`run_count`): (order, (n_nodes,); start, (runs + 1,)), run r's nodes
    at ``order[start[r]:start[r + 1]]`` in increasing order. :func:`advance_rotations` updates
    each run's nodes on the thread that runs its chunks: with the nodes split in halves instead,
    nearly every rotation the kernel read had been written by the other core (the default bat's
    chunks go by kind, not along the bat)."""
    bounds = run_bounds(n_runs, n_chunks)
    runs = bounds.size - 1
    run = np.clip(np.searchsorted(bounds, first_chunk, side="right") - 1, 0, runs - 1)
    order = np.argsort(run, kind="stable")
    start = np.searchsorted(run[order], np.arange(runs + 1))
    return order.astype(np.int64), start.astype(np.int64)


#: Columns :func:`scatter_chunk` turns into records at once (CHUNK is a multiple of it).
RECORD_COLUMNS = 4


@nb.njit(inline="always")
def corner_rows(a: int, col: int) -> tuple:
    """The offsets (unsigned) of column ``col`` of corner ``a``'s six global forces and moments
    in the work array, dof 0..5 (rows W_D + dof(a, k))."""
    return (np.uint64((W_D + dof(a, 0)) * CHUNK + col), np.uint64((W_D + dof(a, 1)) * CHUNK + col),
            np.uint64((W_D + dof(a, 2)) * CHUNK + col), np.uint64((W_D + dof(a, 3)) * CHUNK + col),
            np.uint64((W_D + dof(a, 4)) * CHUNK + col),
            np.uint64((W_D + dof(a, 5)) * CHUNK + col))  # fmt: skip


@nb.njit(inline="always")
def corner_record(a: int, col: int) -> np.uint64:
    """Where corner ``a`` of column ``col`` has its six global forces and moments as one
    record (:func:`scatter_chunk`): the rows from W_F, which the local forces have left."""
    return np.uint64(W_F * CHUNK + 6 * (a * CHUNK + col))


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def scatter_chunk(w: np.ndarray, cells: np.ndarray, first: int, stop: int, kinds: np.ndarray,
                  shared: np.ndarray, out: np.ndarray) -> None:  # fmt: skip
    """The global corner forces of cells ``first`` to ``stop`` (the work array's rows W_D..)
    into their nodes, by each corner's kind (``kinds``, :func:`corner_kinds`): a node whose
    corners are all made by this run of chunks gets minus each corner's forces in ``out``
    (n_points, 6), the first corner's setting it (0 - f), the next ones' subtracted, so in cell
    order; a node whose corners two runs make gets its corners stored in the chunk's ``shared``
    (24 * CHUNK,), dof k of column col at [k * CHUNK + col], for :func:`gather_node` after the
    parallel loop.

    Each corner's six values are first made one record of the work array (rows to records,
    RECORD_COLUMNS columns at a time: :func:`vector_math.interleave_rows`), so that a node's
    update is two vector loads, subtractions and stores (:func:`vector_math.subtract_record`)
    at one unsigned offset of a flat view of ``out``. Read row by row and indexed by (node,
    dof), each value had its own load, subtraction, store and negative-index check.
    """
    for col in range(0, CHUNK, RECORD_COLUMNS):
        for a in range(4):
            interleave_rows(w, corner_rows(a, col), corner_record(a, col), RECORD_COLUMNS)
    flat, row = out.reshape(-1), np.uint64(CHUNK)
    for col in range(stop - first):
        c = first + col
        for a in range(4):
            at = corner_record(a, col)
            kind = kinds[np.uint64(4 * c + a)]
            if kind == SHARED:
                into = np.uint64(6 * a * CHUNK + col)
                for k in range(6):
                    shared[into + np.uint64(k) * row] = w[at + np.uint64(k)]
                continue
            subtract_record(flat, np.uint64(6) * np.uint64(cells[c, a]), w, at, kind != FIRST)


@nb.njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def chunk_forces(points: np.ndarray, cells: np.ndarray, rotations: np.ndarray,
                 constants: np.ndarray, stiffness: np.ndarray, nonzero: np.ndarray,
                 first: int, stop: int, kinds: np.ndarray, shared: np.ndarray,
                 out: np.ndarray) -> None:  # fmt: skip
    """Cells ``first`` to ``stop`` (at most CHUNK, sharing ``stiffness`` (24, 24) and its
    ``nonzero`` blocks, :func:`product_blocks`): their corner forces and moments in global
    axes, into their nodes (:func:`scatter_chunk`). Every
    step but the scatter is a loop over all CHUNK columns of the chunk's work array (in cache
    from one step to the next), the columns past the last cell repeating it: the gather
    (:func:`gather_corners`) with vector loads and stores of its own, the others SIMD loops
    across the columns. A call, not inlined, so that the parallel
    loop's array analysis does not see the frame's tuples."""
    w = np.empty(W_ROWS * CHUNK)
    gather_corners(points, cells, rotations, first, stop, w)
    deformation(constants, w)
    rotation_vectors(w, stop - first)
    local_product(stiffness, nonzero, w)
    for col in range(CHUNK):
        balance_moment(constants, w, col)
        e1, e2 = load3(w, W_FRAME, col), load3(w, W_FRAME + 3, col)
        e3 = load3(w, W_FRAME + 6, col)
        for a in range(4):  # each corner's forces and moments alike: E^T g, in d's rows
            for b in range(0, 6, 3):
                g = load_dofs(w, W_F, a, b, col)
                for i in range(3):
                    w[(W_D + dof(a, b + i)) * CHUNK + col] = \
                        e1[i] * g[0] + e2[i] * g[1] + e3[i] * g[2]
    scatter_chunk(w, cells, first, stop, kinds, shared, out)


@nb.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def gather_node(n: int, corner_start: np.ndarray, corner_slot: np.ndarray, flat: np.ndarray,
                out: np.ndarray) -> None:  # fmt: skip
    """out[n] (6,) = minus the sum of node ``n``'s corner forces in the flat store ``flat``:
    its corners are at ``corner_slot[corner_start[n]:corner_start[n + 1]]`` (their first dof;
    the next at + CHUNK each), in increasing cell order."""
    t0 = t1 = t2 = t3 = t4 = t5 = 0.0
    for e in range(corner_start[n], corner_start[n + 1]):
        at = corner_slot[e]
        t0 -= flat[at]
        t1 -= flat[at + CHUNK]
        t2 -= flat[at + 2 * CHUNK]
        t3 -= flat[at + 3 * CHUNK]
        t4 -= flat[at + 4 * CHUNK]
        t5 -= flat[at + 5 * CHUNK]
    out[n, 0], out[n, 1], out[n, 2], out[n, 3], out[n, 4], out[n, 5] = t0, t1, t2, t3, t4, t5


@nb.njit(parallel=True, cache=True)
def cell_and_node_forces(points: np.ndarray, cells: np.ndarray, rotations: np.ndarray,
                         constants: np.ndarray, product: tuple, chunks: tuple,
                         corners: tuple, kinds: np.ndarray, shared: np.ndarray,
                         out: np.ndarray, n_runs: int) -> None:  # fmt: skip
    """The nodes' forces, minus the sums of their cells' corner forces, into ``out``
    (n_points, 6).

    ``product`` is each kind's K0 as :func:`product_blocks` gives it; ``chunks`` (chunk_start,
    (n_chunks + 1,); chunk_kind, (n_chunks,)) are the tasks, a chunk of cells of one kind
    each, with their ``constants`` (n_chunks, C_ROWS * CHUNK); ``corners``
    (:func:`node_corners`) where each node's corners are, ``kinds`` (:func:`corner_kinds`, for
    the same ``n_runs``) how each corner reaches its node. The chunks run in one parallel loop,
    in ``n_runs`` runs of consecutive chunks (:func:`run_count`; one a thread: the caller
    passes :func:`numba.get_num_threads`, as a kernel that calls it is not cached). A run adds
    each corner's forces into its node as soon as the chunk has made them, if the node's corners
    are all in the run; the corners of the few nodes that two runs share go to ``shared``
    (n_chunks, 24 * CHUNK) and are summed after the loop. Either way each node's sum runs over
    its corners in cell order, so the forces are the same on any number of threads.
    """
    chunk_start, chunk_kind = chunks
    stiffness, nonzero = product
    corner_start, corner_slot, node_start, nodes, first_chunk = corners[:5]
    n_chunks = chunk_kind.shape[0]
    n_runs = run_count(n_runs, n_chunks)
    for run in nb.prange(n_runs):
        begin, end = run_start(run, n_runs, n_chunks), run_start(run + 1, n_runs, n_chunks)
        for t in range(begin, end):
            kind = chunk_kind[t]
            chunk_forces(points, cells, rotations, constants[t], stiffness[kind],
                         nonzero[kind], chunk_start[t], chunk_start[t + 1], kinds,
                         shared[t], out)  # fmt: skip
    flat = shared.ravel()
    for run in range(n_runs):  # the nodes two runs share, and those of no cell
        begin, end = run_start(run, n_runs, n_chunks), run_start(run + 1, n_runs, n_chunks)
        for i in range(node_start[begin], node_start[end]):
            if first_chunk[nodes[i]] < begin:
                gather_node(nodes[i], corner_start, corner_slot, flat, out)


def kind_chunks(kind_start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's tasks: runs of at most CHUNK consecutive cells of one kind.

    Returns:
        (first cell of each chunk, then n_cells, (n_chunks + 1,); each chunk's kind).
    """
    starts, kinds = [], []
    for k in range(kind_start.size - 1):
        first = np.arange(kind_start[k], kind_start[k + 1], CHUNK)
        starts.append(first)
        kinds.append(np.full(first.size, k))
    start = np.append(np.concatenate(starts), kind_start[-1]).astype(np.int64)
    return start, np.concatenate(kinds).astype(np.int64)


def node_corners(cells: np.ndarray, chunk_start: np.ndarray, n_points: int) -> tuple:
    """Each node's cell corners for :func:`cell_and_node_forces`, as int64 arrays:

    * corner_start (n_points + 1,) and corner_slot: node n's corners, in increasing cell order,
      at ``corner_slot[corner_start[n]:corner_start[n + 1]]``, the flat position of the
      corner's first dof in the kernel's (n_chunks, 24 * CHUNK) store of shared corners;
    * node_start (n_chunks + 1,) and nodes (n_points,): the nodes whose last corner is in chunk
      t at ``nodes[node_start[t]:node_start[t + 1]]`` (a node of no cell with chunk 0's);
    * first_chunk and last_chunk (n_points,): the chunks of each node's first and last corner
      (-1 and 0 for a node of no cell);
    * first_corner (n_points,): each node's first corner, 4 * cell + corner (-1: no cell).
    """
    n_cells = cells.shape[0]
    chunk = np.repeat(np.arange(chunk_start.size - 1), np.diff(chunk_start))
    col = np.arange(n_cells) - chunk_start[chunk]
    corner = np.arange(4)[None, :]
    position = chunk[:, None] * 24 * CHUNK + 6 * corner * CHUNK + col[:, None]
    slot = np.argsort(cells.ravel(), kind="stable")  # cell * 4 + corner, by node then cell
    start = np.searchsorted(cells.ravel()[slot], np.arange(n_points + 1))
    corner_chunk = np.repeat(chunk, 4)[slot]  # non-decreasing within each node's corners
    used = start[1:] > start[:-1]
    first, last = np.full(n_points, -1), np.zeros(n_points, np.int64)
    first[used], last[used] = corner_chunk[start[:-1][used]], corner_chunk[start[1:][used] - 1]
    first_corner = np.full(n_points, -1)
    first_corner[used] = slot[start[:-1][used]]
    nodes = np.argsort(last, kind="stable")
    node_start = np.searchsorted(last[nodes], np.arange(chunk_start.size))
    return tuple(a.astype(np.int64) for a in (start, position.ravel()[slot], node_start, nodes,
                                              first, last, first_corner))  # fmt: skip


def chunk_constants(frames0: np.ndarray, reference: np.ndarray,
                    chunk_start: np.ndarray) -> np.ndarray:  # fmt: skip
    """Each chunk's constants as :func:`deformation` reads them, (n_chunks, C_ROWS * CHUNK): the
    cells' undeformed frames ``frames0`` (n_cells, 3, 3) and corners' reference positions
    ``reference`` (n_cells, 4, 3), a row per value and a column per cell, the columns past a
    chunk's last cell repeating it."""
    n_chunks = chunk_start.size - 1
    cell = np.minimum(chunk_start[:-1, None] + np.arange(CHUNK), chunk_start[1:, None] - 1)
    rows = np.concatenate([frames0.reshape(-1, 9), reference.reshape(-1, 12)], axis=1)
    return np.ascontiguousarray(rows[cell].transpose(0, 2, 1).reshape(n_chunks, C_ROWS * CHUNK))


#: Corner coordinates that differ by less than this are the same cell shape [m].
SHAPE_TOLERANCE = 1e-12


def distinct_cells(reference: np.ndarray, section: ShellSection) -> tuple[np.ndarray, np.ndarray]:
    """Cells of one shape (local corner coordinates to ``SHAPE_TOLERANCE``) and section share a
    stiffness: on a bat mesh every cell of a ring does, about a fiftieth of the cells.

    Returns:
        (first cell of each distinct kind, (n_kinds,); each cell's kind, (n_cells,)).
    """
    n_cells = reference.shape[0]
    key = np.hstack([np.round(reference.reshape(n_cells, -1) / SHAPE_TOLERANCE),
                     section.abd.reshape(n_cells, -1), section.shear.reshape(n_cells, -1)])
    _, first, kind = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return first, kind.ravel().astype(np.int64)


class CorotationalShellForces:
    """The shells' nodal forces (minus the internal forces) by the co-rotational MITC4 element,
    with the call of :class:`batball.solvers.ball_bat.ShellForces`; ``state`` holds the
    nodes' rotations, advanced by each call.

    Args:
        points: (n_points, 3) the undeformed nodes [m] (the element's reference).
        cells: (n_cells, 4) node ids.
        section: per-cell MITC4 section constants (:func:`batball.elements.shell_stiffness.
            shell_section`).
        drilling_factor: alpha of the drilling penalty.
        state: the nodes' rotations to start from and update (default: unrotated).
    """

    def __init__(self, points: np.ndarray, cells: np.ndarray, section: ShellSection, *,
                 drilling_factor: float = DRILLING_FACTOR,
                 state: CorotationalState | None = None) -> None:  # fmt: skip
        frames, local = element_frames(points, cells)
        relative = points[cells] - points[cells].mean(axis=1, keepdims=True)
        reference = np.einsum("cnk,cak->cna", relative, frames)
        first, kind = distinct_cells(reference, section)
        order = np.argsort(kind, kind="stable")  # cells of a kind together, for one product
        self.cells = np.ascontiguousarray(cells[order], dtype=np.int64)
        self.frames0 = np.ascontiguousarray(frames[order])
        self.kind_start = np.searchsorted(kind[order], np.arange(first.size + 1))
        local_section = ShellSection(*(a[first] for a in (section.abd, section.shear,
                                                          section.areal_mass,
                                                          section.rotary_inertia)))  # fmt: skip
        stiffness = local_stiffness(local[first], local_section, drilling_factor)
        self.stiffness = np.ascontiguousarray(stiffness)
        self.product = product_blocks(self.stiffness)  # K0 as the kernel takes it
        self.state = initial_rotations(points.shape[0]) if state is None else state
        self.chunk_start, self.chunk_kind = kind_chunks(self.kind_start)
        self.corners = node_corners(self.cells, self.chunk_start, points.shape[0])
        self.shared = np.zeros((self.chunk_kind.size, 24 * CHUNK))  # see cell_and_node_forces
        # the undeformed frames and the corners' reference positions, in the kernel's layout
        self.constants = chunk_constants(self.frames0, reference[order], self.chunk_start)
        self._kinds: dict[int, np.ndarray] = {}  # corner_kinds by the number of runs asked for
        self._runs: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # rotation_runs, alike

    def corner_kinds(self, n_runs: int) -> np.ndarray:
        """:func:`corner_kinds` of these cells for ``n_runs`` runs, taken once."""
        if n_runs not in self._kinds:
            self._kinds[n_runs] = corner_kinds(self.cells, self.chunk_start, self.corners, n_runs)
        return self._kinds[n_runs]

    def rotation_runs(self, n_runs: int) -> tuple[np.ndarray, np.ndarray]:
        """:func:`rotation_runs` of these nodes for ``n_runs`` runs, taken once."""
        if n_runs not in self._runs:
            self._runs[n_runs] = rotation_runs(self.corners[4], self.chunk_kind.size, n_runs)
        return self._runs[n_runs]

    def __call__(self, points: np.ndarray, velocity: np.ndarray, dt: float,
                 out: np.ndarray) -> None:  # fmt: skip
        """Forces on the nodes, (n, 6), into ``out`` from x^n (n, 3) and v^(n-1/2) (n, 6) over
        the last step ``dt`` [s] (which first advances the nodes' rotations)."""
        rotations, n_runs = self.state.history, nb.get_num_threads()
        advance_rotations(rotations, velocity, dt, self.rotation_runs(n_runs))
        cell_and_node_forces(points, self.cells, rotations, self.constants, self.product,
                             (self.chunk_start, self.chunk_kind), self.corners,
                             self.corner_kinds(n_runs), self.shared, out, n_runs)  # fmt: skip


@nb.njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def scaled_stiffness_product(x: np.ndarray, cells: np.ndarray, kinds: np.ndarray,
                             stiffness: np.ndarray, frames: np.ndarray, scale: np.ndarray,
                             y: np.ndarray) -> None:  # fmt: skip
    """y = S K S x without K: K the undeformed shells' stiffness, the sum over the cells of
    T^T K0 T (K0 = ``stiffness[kinds[c]]``, (24, 24), in the cell's frame, T its ``frames``
    (n_cells, 3, 3), rows e_a, on each corner's translations and rotations), S = diag(``scale``);
    x, y (6 n_points,)."""
    y[:] = 0.0
    local = np.empty(24)
    force = np.empty(24)
    for c in range(cells.shape[0]):
        f = frames[c]
        for a in range(4):
            for b in range(2):  # translations, rotations
                d = 6 * cells[c, a] + 3 * b
                g0, g1, g2 = scale[d] * x[d], scale[d + 1] * x[d + 1], scale[d + 2] * x[d + 2]
                for i in range(3):
                    local[6 * a + 3 * b + i] = f[i, 0] * g0 + f[i, 1] * g1 + f[i, 2] * g2
        k = stiffness[kinds[c]]
        for i in range(24):
            total = 0.0
            for j in range(24):
                total += k[i, j] * local[j]
            force[i] = total
        for a in range(4):
            for b in range(2):
                d = 6 * cells[c, a] + 3 * b
                h0, h1, h2 = force[6 * a + 3 * b], force[6 * a + 3 * b + 1], \
                    force[6 * a + 3 * b + 2]
                for j in range(3):
                    y[d + j] += scale[d + j] * (f[0, j] * h0 + f[1, j] * h1 + f[2, j] * h2)


def critical_step(shells: CorotationalShellForces, mass: np.ndarray) -> float:
    """The undeformed shells' critical step 2 / omega_max [s] with the lumped ``mass`` (n, 6):
    omega_max^2 the largest eigenvalue of M^-1/2 K M^-1/2 (Lanczos, to 1e-4), its products
    taken cell by cell (:func:`scaled_stiffness_product`): on the full bat 0.2 s against
    1.3 s and 0.4 GB for assembling K (each cell's 24 x 24 in global axes, then the sparse
    matrix)."""
    kinds = np.repeat(np.arange(shells.stiffness.shape[0]), np.diff(shells.kind_start))
    scale = 1.0 / np.sqrt(mass.ravel())
    product = np.empty(scale.size)

    def matvec(x: np.ndarray) -> np.ndarray:
        vector = np.ascontiguousarray(x, dtype=np.float64).ravel()
        scaled_stiffness_product(vector, shells.cells, kinds, shells.stiffness, shells.frames0,
                                 scale, product)  # fmt: skip
        return product.copy()

    operator = LinearOperator((scale.size, scale.size), matvec=matvec, dtype=np.float64)
    start = np.ones(scale.size)  # a fixed start: the same step run after run
    largest = eigsh(operator, k=1, which="LA", tol=1e-4, v0=start,
                    return_eigenvectors=False)[0]  # fmt: skip
    return float(2.0 / np.sqrt(largest))


def check_time_step(shells: CorotationalShellForces, mass: np.ndarray, dt: float, *,
                    limit: float = 0.9) -> None:  # fmt: skip
    """Refuse a step ``dt`` [s] above ``limit`` (TSSFAC) times :func:`critical_step`: the step
    the runs take is the BT shells' estimate (area / longest side / wave speed), which is
    checked here against the MITC4 element's own highest frequency (on the bat meshes the
    estimate is 0.54-0.56 of the critical step, mass scaling included)."""
    critical = critical_step(shells, mass)
    if dt > limit * critical:
        raise SimulationError(f"explicit step {dt:.3e} s exceeds {limit:g} x the co-rotational "
                              f"MITC4 shells' critical step {critical:.3e} s")  # fmt: skip


#: The explicit step over the co-rotational shells' critical step when they set it: at this
#: step (omega_max dt = 1.6) the barrel test's platen penalty (k dt^2 / m = 0.2) and the
#: insert's (below 0.12) raise the highest frequency by under 4 %, well inside the limit 2.
STEP_FACTOR = 0.8


def shells_and_step(points: np.ndarray, cells: np.ndarray, section: ShellSection,
                    mass: np.ndarray, *, factor: float = STEP_FACTOR,
                    ) -> tuple[CorotationalShellForces, float]:  # fmt: skip
    """The co-rotational shells of a bat with lumped ``mass`` (n, 6) and their own explicit
    step, ``factor`` times :func:`critical_step` [s] rounded down to three significant digits
    (a stored fit's key holds the step: the Lanczos tolerance must not change it), where the
    BT shells' estimate, 0.54-0.56 of the critical step on the bat meshes, would take about
    1.45 times the cycles."""
    shells = CorotationalShellForces(points, cells, section)
    step = factor * critical_step(shells, mass)
    unit = 10.0 ** (np.floor(np.log10(step)) - 2)
    return shells, float(np.floor(step / unit) * unit)


def checked_shells(points: np.ndarray, cells: np.ndarray, section: ShellSection,
                   mass: np.ndarray, dt: float, *,
                   state: CorotationalState | None = None) -> CorotationalShellForces:  # fmt: skip
    """The co-rotational shells of a bat whose explicit step ``dt`` [s] with lumped ``mass``
    (n, 6) has been checked against them (:func:`check_time_step`)."""
    shells = CorotationalShellForces(points, cells, section, state=state)
    check_time_step(shells, mass, dt)
    return shells
