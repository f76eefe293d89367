"""Geometry of the trilinear 8-node hexahedron, as Numba kernels.

Node order is LS-DYNA's (and VTK's): 1-2-3-4 the bottom face counter-clockwise seen from the top,
5-6-7-8 the top face. Reference coordinates of node k are ``REFERENCE_CORNERS[k]``.

The uniform-strain gradient operator of Flanagan & Belytschko (1981, IJNME 17:679) is used: the
vectors B_I = dV/dx_I (area units), the derivative of the exact trilinear volume with respect to
node I's coordinates, so that tr(D) V = dV/dt holds exactly. The closed form for node 1 was derived
with SymPy (volume = integral of det J over the reference cube); the other nodes follow by the
rotations of the reference cube (``NODE_PERMUTATIONS``), and every component by the cyclic
permutation of x, y, z. The exact volume is then V = (1/3) sum_I x_I . B_I (V is homogeneous of
degree 3 in the coordinates).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from batball.elements.vector_math import like
from batball.numerics import FASTMATH

REFERENCE_CORNERS = np.array(
    [
        [-1, -1, -1],
        [1, -1, -1],
        [1, 1, -1],
        [-1, 1, -1],
        [-1, -1, 1],
        [1, -1, 1],
        [1, 1, 1],
        [-1, 1, 1],
    ],
    dtype=np.float64,
)

#: Row I is an orientation-preserving relabelling of the reference cube that maps node 0 to node I;
#: the node-0 formula of dV/dx evaluated on relabelled nodes gives node I's derivative.
NODE_PERMUTATIONS = np.array(
    [
        [0, 1, 2, 3, 4, 5, 6, 7],
        [1, 0, 4, 5, 2, 3, 7, 6],
        [2, 3, 0, 1, 6, 7, 4, 5],
        [3, 2, 6, 7, 0, 1, 5, 4],
        [4, 5, 1, 0, 7, 6, 2, 3],
        [5, 4, 7, 6, 1, 0, 3, 2],
        [6, 7, 3, 2, 5, 4, 0, 1],
        [7, 6, 5, 4, 3, 2, 1, 0],
    ],
    dtype=np.int64,
)

#: Flanagan-Belytschko hourglass base vectors, shape (4, 8):
#: eta*zeta, zeta*xi, xi*eta and xi*eta*zeta at the corners.
HOURGLASS_BASE = np.array(
    [
        [1, 1, -1, -1, -1, -1, 1, 1],
        [1, -1, -1, 1, -1, 1, 1, -1],
        [1, -1, 1, -1, 1, -1, 1, -1],
        [-1, 1, -1, 1, 1, -1, 1, -1],
    ],
    dtype=np.float64,
)

#: The six faces of a hex as node indices, each ordered so its normal points outward.
HEX_FACES = np.array(
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
    dtype=np.int64,
)


@nb.njit(inline="always", fastmath=FASTMATH)
def _node0_derivative(y1, y2, y3, y4, y5, y7, z1, z2, z3, z4, z5, z7):
    """12 dV/dx_0 as a function of the y and z coordinates of nodes 1, 2, 3, 4, 5 and 7."""
    return (
        y1 * (z4 + z5 - z2 - z3)
        + y2 * (z1 - z3)
        + y3 * (z1 + z2 - z4 - z7)
        + y4 * (z3 + z7 - z1 - z5)
        + y5 * (z4 - z1)
        + y7 * (z3 - z4)
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _component(
    xe: np.ndarray, j: int, k: int, n1: int, n2: int, n3: int, n4: int, n5: int, n7: int
) -> float:
    """12 dV/dx_node along the axis whose cyclic successors are j and k."""
    return _node0_derivative(
        xe[3 * n1 + j],
        xe[3 * n2 + j],
        xe[3 * n3 + j],
        xe[3 * n4 + j],
        xe[3 * n5 + j],
        xe[3 * n7 + j],
        xe[3 * n1 + k],
        xe[3 * n2 + k],
        xe[3 * n3 + k],
        xe[3 * n4 + k],
        xe[3 * n5 + k],
        xe[3 * n7 + k],
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _node_derivative(
    xe: np.ndarray, b: np.ndarray, node: int, n1: int, n2: int, n3: int, n4: int, n5: int, n7: int
) -> None:
    """Row ``node`` of dV/dx from the relabelled neighbours (literal indices, so it unrolls)."""
    b[3 * node] = _component(xe, 1, 2, n1, n2, n3, n4, n5, n7) * (1.0 / 12.0)
    b[3 * node + 1] = _component(xe, 2, 0, n1, n2, n3, n4, n5, n7) * (1.0 / 12.0)
    b[3 * node + 2] = _component(xe, 0, 1, n1, n2, n3, n4, n5, n7) * (1.0 / 12.0)


@nb.njit(inline="always", fastmath=FASTMATH)
def volume_derivatives(xe: np.ndarray, b: np.ndarray) -> float:
    """Fill ``b`` (24,) with dV/dx_I (m^2) for element coordinates ``xe`` (24,) [m].

    Both are flat, node-major: entry 3 I + i is node I's component i. The node arguments below
    are the rows of ``NODE_PERMUTATIONS`` at positions 1, 2, 3, 4, 5, 7.

    Returns:
        The exact trilinear volume (m^3); negative if the element is inverted.
    """
    _node_derivative(xe, b, 0, 1, 2, 3, 4, 5, 7)
    _node_derivative(xe, b, 1, 0, 4, 5, 2, 3, 6)
    _node_derivative(xe, b, 2, 3, 0, 1, 6, 7, 5)
    _node_derivative(xe, b, 3, 2, 6, 7, 0, 1, 4)
    _node_derivative(xe, b, 4, 5, 1, 0, 7, 6, 3)
    _node_derivative(xe, b, 5, 4, 7, 6, 1, 0, 2)
    _node_derivative(xe, b, 6, 7, 3, 2, 5, 4, 1)
    _node_derivative(xe, b, 7, 6, 5, 4, 3, 2, 0)
    volume = 0.0
    for m in range(24):
        volume += xe[m] * b[m]
    return volume * (1.0 / 3.0)


@nb.njit(inline="always", fastmath=FASTMATH)
def largest_face_area(xe: np.ndarray) -> float:
    """Largest face area (m^2) of a hex with flat coordinates ``xe`` (24,); |d13 x d24| / 2."""
    largest = 0.0
    for f in range(6):
        a = 3 * HEX_FACES[f, 0]
        b = 3 * HEX_FACES[f, 1]
        c = 3 * HEX_FACES[f, 2]
        d = 3 * HEX_FACES[f, 3]
        p0 = xe[c] - xe[a]
        p1 = xe[c + 1] - xe[a + 1]
        p2 = xe[c + 2] - xe[a + 2]
        q0 = xe[d] - xe[b]
        q1 = xe[d + 1] - xe[b + 1]
        q2 = xe[d + 2] - xe[b + 2]
        c0 = p1 * q2 - p2 * q1
        c1 = p2 * q0 - p0 * q2
        c2 = p0 * q1 - p1 * q0
        area = 0.5 * np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
        largest = max(largest, area)
    return largest


@nb.njit(cache=True)
def volume_derivatives_batch(
    points: np.ndarray, cells: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Volume derivatives (n_cells, 8, 3) [m^2] and exact volumes (n_cells,) [m^3] of many hexes."""
    n_cells = cells.shape[0]
    b_all = np.empty((n_cells, 24))
    volumes = np.empty(n_cells)
    xe = np.empty(24)
    for e in range(n_cells):
        for a in range(8):
            for i in range(3):
                xe[3 * a + i] = points[cells[e, a], i]
        volumes[e] = volume_derivatives(xe, b_all[e])
    return b_all.reshape((n_cells, 8, 3)), volumes


# --- modal form: the same exact volume and derivatives, written on the corner-sign modes ----------
#
# With X_k = sum_a H_ka x_a over the corners, H_k the signs of the modes k = 1..7 (xi, eta, zeta,
# eta zeta, zeta xi, xi eta, xi eta zeta; rows 0..2 of HOURGLASS_BASE are modes 4..6 and row 3 is
# mode 7), the trilinear map is x = (1/8) sum_k X_k phi_k and the exact volume is
#   V = (1/64) ([X1, X2, X3] + ([X1, X6, X5] + [X6, X2, X4] + [X5, X4, X3]) / 3),
# ([a, b, c] = a . (b x c); the xi eta zeta mode drops out), so dV/dx_a = sum_k H_ka G_k with
# G_k = dV/dX_k. Sharing the cross products makes this about half the work of the node-wise form.

#: A 3-vector as a tuple (x, y, z), so that it lives in registers inside Numba loops.
Vector = tuple[float, float, float]


@nb.njit(inline="always", fastmath=FASTMATH)
def modal_sums(
    c0: float, c1: float, c2: float, c3: float, c4: float, c5: float, c6: float, c7: float
) -> tuple[float, ...]:
    """Butterfly sums sum_a H_ka c_a of one coordinate for the modes k = 1..7 (a 7-tuple)."""
    p0, m0 = c1 + c0, c1 - c0  # eta -, zeta -
    p1, m1 = c2 + c3, c2 - c3  # eta +, zeta -
    p2, m2 = c5 + c4, c5 - c4  # eta -, zeta +
    p3, m3 = c6 + c7, c6 - c7  # eta +, zeta +
    pp0, pm0, pp1, pm1 = p0 + p1, p1 - p0, p2 + p3, p3 - p2
    mp0, mm0, mp1, mm1 = m0 + m1, m1 - m0, m2 + m3, m3 - m2
    return (mp0 + mp1, pm0 + pm1, pp1 - pp0, pm1 - pm0, mp1 - mp0, mm0 + mm1, mm1 - mm0)


@nb.njit(inline="always", fastmath=FASTMATH)
def modes_of_components(sx: tuple, sy: tuple, sz: tuple) -> tuple:
    """The modal sums X_1..X_7 as 3-tuples from the x, y and z components' 7-tuples."""
    return (
        (sx[0], sy[0], sz[0]),
        (sx[1], sy[1], sz[1]),
        (sx[2], sy[2], sz[2]),
        (sx[3], sy[3], sz[3]),
        (sx[4], sy[4], sz[4]),
        (sx[5], sy[5], sz[5]),
        (sx[6], sy[6], sz[6]),
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def nodal_sums(
    f1: float, f2: float, f3: float, f4: float, f5: float, f6: float, f7: float
) -> tuple[float, ...]:
    """The transpose of :func:`modal_sums`: sum_k H_ka F_k at the eight corners (an 8-tuple)."""
    a_lo, bx_lo, by_lo, c_lo = -f3, f1 - f5, f2 - f4, f6 - f7  # zeta -
    a_hi, bx_hi, by_hi, c_hi = f3, f1 + f5, f2 + f4, f6 + f7  # zeta +
    p_lo_m, q_lo_m, p_lo_p, q_lo_p = a_lo - by_lo, bx_lo - c_lo, a_lo + by_lo, bx_lo + c_lo
    p_hi_m, q_hi_m, p_hi_p, q_hi_p = a_hi - by_hi, bx_hi - c_hi, a_hi + by_hi, bx_hi + c_hi
    return (
        p_lo_m - q_lo_m,
        p_lo_m + q_lo_m,
        p_lo_p + q_lo_p,
        p_lo_p - q_lo_p,
        p_hi_m - q_hi_m,
        p_hi_m + q_hi_m,
        p_hi_p + q_hi_p,
        p_hi_p - q_hi_p,
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def cross(a: Vector, b: Vector) -> Vector:
    """a x b of two 3-tuples."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@nb.njit(inline="always", fastmath=FASTMATH)
def dot(a: Vector, b: Vector) -> float:
    """a . b of two 3-tuples."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@nb.njit(inline="always", fastmath=FASTMATH)
def _combine(a: Vector, b: Vector, wa: float, wb: float) -> Vector:
    """wa a + wb b of two 3-tuples."""
    return (wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2])


@nb.njit(inline="always", fastmath=FASTMATH)
def modal_volume_gradient(
    x1: Vector, x2: Vector, x3: Vector, x4: Vector, x5: Vector, x6: Vector
) -> tuple[Vector, Vector, Vector, Vector, Vector, Vector, float]:
    """G_k = dV/dX_k (k = 1..6, 3-tuples, m^2) and the exact volume V (m^3) from modal sums."""
    c23, c31, c12 = cross(x2, x3), cross(x3, x1), cross(x1, x2)
    c65, c46, c54 = cross(x6, x5), cross(x4, x6), cross(x5, x4)
    c62, c35, c16 = cross(x6, x2), cross(x3, x5), cross(x1, x6)
    c43, c51, c24 = cross(x4, x3), cross(x5, x1), cross(x2, x4)
    main, side = like(x1[0], 1.0 / 64.0), like(x1[0], 1.0 / 192.0)
    volume = main * dot(x1, c23) + side * (dot(x5, c16) + dot(x4, c62) + dot(x4, c35))
    return (
        _combine(c23, c65, main, side),
        _combine(c31, c46, main, side),
        _combine(c12, c54, main, side),
        _combine(c62, c35, side, side),
        _combine(c16, c43, side, side),
        _combine(c51, c24, side, side),
        volume,
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _face_area_squared(a: Vector, b: Vector, c: Vector, d: Vector, sign: float) -> float:
    """|(a + sign b) x (c + sign d)|^2 for 3-tuples: (16 x the area of one face)^2."""
    one = like(a[0], 1.0)
    n = cross(_combine(a, b, one, sign), _combine(c, d, one, sign))
    return dot(n, n)


@nb.njit(inline="always", fastmath=FASTMATH)
def modal_largest_face_area(
    x1: Vector, x2: Vector, x3: Vector, x4: Vector, x5: Vector, x6: Vector
) -> float:
    """Largest face area (m^2) from modal sums; each is |d13 x d24| / 2 (:func:`largest_face_area`).

    On the face zeta = -/+1, x = (1/8) (X0 -/+ X3 + (X1 -/+ X5) xi + (X2 -/+ X4) eta + ...), so its
    area is |(X1 -/+ X5) x (X2 -/+ X4)| / 16; the faces xi = -/+1 and eta = -/+1 alike.
    """
    plus, minus = like(x1[0], 1.0), like(x1[0], -1.0)
    largest = max(
        _face_area_squared(x1, x5, x2, x4, minus),
        _face_area_squared(x1, x5, x2, x4, plus),
        _face_area_squared(x2, x6, x3, x5, minus),
        _face_area_squared(x2, x6, x3, x5, plus),
        _face_area_squared(x1, x6, x3, x4, minus),
        _face_area_squared(x1, x6, x3, x4, plus),
    )
    return np.sqrt(largest) * like(largest, 1.0 / 16.0)
