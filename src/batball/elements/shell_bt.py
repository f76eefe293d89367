"""Explicit internal forces of the layered Belytschko-Tsay shell (LS-DYNA ELFORM 2).

One in-plane integration point, one through-thickness point per layer (``*PART_COMPOSITE``,
:mod:`batball.elements.shell_bt_section`), co-rotational frame and Belytschko-Tsay hourglass
control; docs/physics.md section 6.4, after Belytschko, Lin & Tsay (1984) and the LS-DYNA Theory
Manual (Hallquist 2006, section 7).

* Frame: e3 along r31 x r42, e1 along edge 1-2 projected on the plane, e2 = e3 x e1, rebuilt
  every step from the current coordinates (so rigid rotations strain nothing); nodes projected on
  the plane through the centroid give the local (x, y).
* Rotations are rotation-vector components, as in :mod:`batball.elements.shell_stiffness`: a
  point at height z moves by theta x z e3, i.e. u = u0 + z theta_y, v = v0 - z theta_x. So
  kappa_x = theta_y,x, kappa_y = -theta_x,y, 2 kappa_xy = theta_y,y - theta_x,x,
  gamma_xz = w,x + theta_y, gamma_yz = w,y - theta_x (the sign-flipped form of the LS-DYNA
  equations in docs/physics.md section 6.4, where M = -int z sigma dz; the same element).
* Rate form: the strain rates at the centre (B1 = dN/dx, B2 = dN/dy) times dt update each layer's
  stress in the co-rotational frame, sigma_k += Qbar_k (d + z_k kappa_dot) dt, and the transverse
  shear force Q += H gamma_dot dt. Forces follow from virtual work on A (N . eps + M . kappa +
  Q . gamma); the drilling moment is zero (LS-DYNA m_z = 0).
* Hourglass: gamma_I = h_I - (h . x) B1_I - (h . y) B2_I with h = (1, -1, 1, -1); the hourglass
  rates q_M (in-plane, 2), q_B (rotations, 2), q_W (warping) are integrated into generalised
  stresses with the rate constants C_M = r A_max A (B.B)/8, C_B = r D_max A (B.B)/16,
  C_W = r H_max t^2 (B.B)/12: the constants E t A/8, E t^3 A/192, kappa G t^3/12 of
  docs/physics.md section 6.4 with E t, E t^3 / 12 and kappa G t replaced by the laminate's largest
  A, D and H diagonals.

With zero initial state, ``dt = 1`` and the velocities set to a small displacement field, one call
gives the linear internal force K_BT u (:func:`small_displacement_forces`).

The kernel runs SIMD across blocks of 16 cells of one laminate, the state kept in its block
layout (comments at ``BLOCK`` and ``N_STATE_ROWS``); :mod:`batball.elements.shell_bt_scalar` is
the former one-cell-at-a-time kernel, kept as the reference it is tested against.

One module (about 740 lines) because the block kernel, its state layout and the small-
displacement force that tests it read the same block constants; the section and the scalar
reference kernel are already their own modules.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

from batball.elements.shell_bt_section import LayeredSection
from batball.numerics import FASTMATH

#: Belytschko-Tsay hourglass ratios r (membrane, bending, warping); docs/physics.md section 6.4.
HOURGLASS_RATIO = 0.01


# The kernel runs the cells in blocks of up to BLOCK consecutive cells of one laminate, as the
# hex kernel (batball.elements.hex8_block): a block's nodes are gathered into one scratch vector
# ``w`` in structure-of-arrays form, row r of slot e at ``w[r * BLOCK + e]``, advanced by loops
# over its slots whose bodies are straight-line arithmetic on scalars and tuples (which LLVM
# vectorises across the slots; the laminate's constants are scalars shared by the block), and
# the forces scattered back. The rows:
BLOCK = 16
R_X = 0  # 12 node coordinates (node-major, 3 a + i) [m]
R_V = 12  # 24 node velocities and rotation rates (6 a + i) [m/s, rad/s]; then the 24 forces
R_FRAME = 36  # 9 frame rows e1, e2, e3 (3 a + i)
R_B = 45  # 8: B1 of nodes 0..3, then B2 [1/m]
R_AREA = 53  # area [m^2]
R_GAMMA = 54  # 4 hourglass shape vector
R_RATE = 58  # 6 membrane and curvature rates [1/s, 1/(m s)]
R_RES = 64  # 6 resultants N [N/m] and M [N]
R_SHEAR = 70  # 2 transverse shear forces Q [N/m] (state)
R_HOURGLASS = 72  # 5 generalised hourglass stresses (state)
N_ROWS = 77

# The shells' state is kept between steps in the kernel's block layout (as the hex kernel's
# history): block b's row of ``ShellForceState.history`` holds, for its cell e, row r at
# r * BLOCK + e: rows 0-1 the transverse shear forces, 2-6 the hourglass stresses (copied to and
# from the scratch rows R_SHEAR..R_HOURGLASS + 4), then the layer stresses sigma_xx, sigma_yy,
# sigma_xy [Pa] of layer k in rows 3 k + i. The layer loop updates them where they lie, GROUP
# layers at a time as straight-line code at constant rows, over all BLOCK slots (a loop over a
# runtime layer index, or over n < BLOCK slots, was not vectorised: LLVM could then neither prove
# the rows apart nor drop Numba's negative-index checks); the layers are padded with zero ones
# to whole groups.
GROUP = 5
N_STATE_ROWS = 7
S_LAYERS = N_STATE_ROWS  # first row of the layer stresses in a history row


@nb.njit
def padded_layer_count(n_layers: int) -> int:
    """Layers of the kernel's arrays for ``n_layers``: whole groups of GROUP."""
    return -(-n_layers // GROUP) * GROUP


def shell_blocks(cell_laminate: np.ndarray) -> np.ndarray:
    """First cell of each kernel block, then n_cells, (n_blocks + 1,): runs of at most BLOCK
    consecutive cells of one laminate."""
    lam = np.asarray(cell_laminate)
    starts, c = [], 0
    while c < lam.size:
        stop = c + 1
        while stop < min(c + BLOCK, lam.size) and lam[stop] == lam[c]:
            stop += 1
        starts.append(c)
        c = stop
    return np.array([*starts, lam.size], dtype=np.int64)


@dataclass(frozen=True)
class ShellForceState:
    """The evolving stresses of the layered BT shells (co-rotational frame), updated in place.

    Kept in the kernel's block layout (module comment at ``N_STATE_ROWS``); the properties give
    the element-wise arrays (copies).

    Attributes:
        block_start: first cell of each block, then n_cells, (n_blocks + 1,), int
            (:func:`shell_blocks`).
        history: (n_blocks, (N_STATE_ROWS + 3 n_padded) * BLOCK), SI units, n_padded =
            :func:`padded_layer_count` of n_layers.
        n_layers: layers of the section.
    """

    block_start: np.ndarray
    history: np.ndarray
    n_layers: int

    def columns(self) -> np.ndarray:
        """The history cell by cell, (n_cells, N_STATE_ROWS + 3 n_padded) (a copy)."""
        n_blocks, width = self.history.shape
        slots = self.history.reshape(n_blocks, width // BLOCK, BLOCK).transpose(0, 2, 1)
        used = np.arange(BLOCK)[None, :] < np.diff(self.block_start)[:, None]
        return slots[used]

    @property
    def layer_stress(self) -> np.ndarray:
        """(sigma_xx, sigma_yy, sigma_xy) per layer, (n_cells, n_layers, 3), Pa (a copy)."""
        stress = self.columns()[:, S_LAYERS : S_LAYERS + 3 * self.n_layers]
        return stress.reshape(-1, self.n_layers, 3)

    @property
    def shear_force(self) -> np.ndarray:
        """Transverse shear resultants (Q_x, Q_y), (n_cells, 2), N/m (a copy)."""
        return self.columns()[:, 0:2]

    @property
    def hourglass(self) -> np.ndarray:
        """Generalised hourglass stresses (membrane x, y; bending x, y; warping), (n_cells, 5),
        N, N m, N (a copy)."""
        return self.columns()[:, 2:7]


def pack_force_state(
    cell_laminate: np.ndarray,
    layer_stress: np.ndarray,
    shear_force: np.ndarray | None = None,
    hourglass: np.ndarray | None = None,
) -> ShellForceState:
    """The state of cells with the element-wise ``layer_stress`` (n_cells, n_layers, 3) [Pa],
    ``shear_force`` (n_cells, 2) [N/m] and ``hourglass`` (n_cells, 5) (zero where not given)."""
    n_cells, n_layers = layer_stress.shape[:2]
    block_start = shell_blocks(cell_laminate)
    n_blocks = block_start.size - 1
    rows = N_STATE_ROWS + 3 * padded_layer_count(n_layers)
    columns = np.zeros((n_cells, rows))
    columns[:, S_LAYERS : S_LAYERS + 3 * n_layers] = layer_stress.reshape(n_cells, -1)
    if shear_force is not None:
        columns[:, 0:2] = shear_force
    if hourglass is not None:
        columns[:, 2:7] = hourglass
    slots = np.zeros((n_blocks, BLOCK, rows))
    used = np.arange(BLOCK)[None, :] < np.diff(block_start)[:, None]
    slots[used] = columns
    history = np.ascontiguousarray(slots.transpose(0, 2, 1)).reshape(n_blocks, -1)
    return ShellForceState(block_start, history, n_layers)


def initial_force_state(section: LayeredSection) -> ShellForceState:
    """A stress-free state for every cell of ``section``."""
    n_layers = section.layer_z.shape[1]
    return pack_force_state(section.cell_laminate, np.zeros((section.n_cells, n_layers, 3)))


Vec3 = tuple[float, float, float]


@nb.njit(inline="always")
def at(row: int, e: int) -> int:
    """Index of row ``row``, slot ``e`` in the block scratch."""
    return row * BLOCK + e


@nb.njit(inline="always", fastmath=FASTMATH)
def load3(w: np.ndarray, row: int, e: int) -> Vec3:
    """The 3-tuple in rows row..row+2."""
    return (w[at(row, e)], w[at(row + 1, e)], w[at(row + 2, e)])


@nb.njit(inline="always", fastmath=FASTMATH)
def store3(w: np.ndarray, row: int, e: int, a: Vec3) -> None:
    """Write the 3-tuple ``a`` to rows row..row+2."""
    w[at(row, e)] = a[0]
    w[at(row + 1, e)] = a[1]
    w[at(row + 2, e)] = a[2]


@nb.njit(inline="always", fastmath=FASTMATH)
def dot3(a: Vec3, b: Vec3) -> float:
    """a . b, summed left to right."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@nb.njit(inline="always", fastmath=FASTMATH)
def element_frame(x0: Vec3, x1: Vec3, x2: Vec3, x3: Vec3) -> tuple[Vec3, Vec3, Vec3]:
    """The co-rotational frame (e1, e2, e3) of a quadrilateral with corners x0..x3 [m]: e3 along
    r31 x r42, e1 along edge 1-2 projected on the plane, e2 = e3 x e1."""
    a0, a1, a2 = x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]  # r31
    c0, c1, c2 = x3[0] - x1[0], x3[1] - x1[1], x3[2] - x1[2]  # r42
    n0, n1, n2 = a1 * c2 - a2 * c1, a2 * c0 - a0 * c2, a0 * c1 - a1 * c0
    norm = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    n0, n1, n2 = n0 / norm, n1 / norm, n2 / norm
    d0, d1, d2 = x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]  # edge 1-2
    along = d0 * n0 + d1 * n1 + d2 * n2
    d0, d1, d2 = d0 - along * n0, d1 - along * n1, d2 - along * n2
    norm = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    d0, d1, d2 = d0 / norm, d1 / norm, d2 / norm
    e2 = (n1 * d2 - n2 * d1, n2 * d0 - n0 * d2, n0 * d1 - n1 * d0)
    return (d0, d1, d2), e2, (n0, n1, n2)


@nb.njit(inline="always", fastmath=FASTMATH)
def local_xy(e1: Vec3, e2: Vec3, m: Vec3, x: Vec3) -> tuple[float, float]:
    """In-plane local coordinates (x, y) [m] of the point ``x`` about the centroid ``m``."""
    r = (x[0] - m[0], x[1] - m[1], x[2] - m[2])
    return dot3(e1, r), dot3(e2, r)


@nb.njit(inline="always", fastmath=FASTMATH)
def local_velocity(e1: Vec3, e2: Vec3, e3: Vec3, w: np.ndarray, row: int, e: int):
    """A node's velocity (v_x, v_y, v_z) [m/s] and rotation rates (omega_x, omega_y) [rad/s] in
    the element frame, from the global values in rows row..row+5 (omega_z is not used)."""
    v, omega = load3(w, row, e), load3(w, row + 3, e)
    return dot3(e1, v), dot3(e2, v), dot3(e3, v), dot3(e1, omega), dot3(e2, omega)


@nb.njit(inline="always", fastmath=FASTMATH)
def to_global(e1: Vec3, e2: Vec3, e3: Vec3, f: float, g: float, h: float) -> Vec3:
    """frame.T @ (f, g, h): a local vector back to global axes."""
    return (e1[0] * f + e2[0] * g + e3[0] * h, e1[1] * f + e2[1] * g + e3[1] * h,
            e1[2] * f + e2[2] * g + e3[2] * h)  # fmt: skip


@nb.njit(inline="always", fastmath=FASTMATH)
def moment_to_global(e1: Vec3, e2: Vec3, f: float, g: float) -> Vec3:
    """frame.T @ (f, g, 0): a local moment (no drilling part) back to global axes."""
    return (e1[0] * f + e2[0] * g, e1[1] * f + e2[1] * g, e1[2] * f + e2[2] * g)


@nb.njit(inline="always", fastmath=FASTMATH)
def local_geometry(x0: Vec3, x1: Vec3, x2: Vec3, x3: Vec3) -> tuple:
    """The co-rotational frame (e1, e2, e3), the nodes' local x and y (4-tuples) on the plane
    through the centroid, the area and B1 = dN/dx, B2 = dN/dy (4-tuples) of one quad."""
    e1, e2, e3 = element_frame(x0, x1, x2, x3)
    m = (0.25 * (x0[0] + x1[0] + x2[0] + x3[0]), 0.25 * (x0[1] + x1[1] + x2[1] + x3[1]),
         0.25 * (x0[2] + x1[2] + x2[2] + x3[2]))  # fmt: skip
    p0, q0 = local_xy(e1, e2, m, x0)
    p1, q1 = local_xy(e1, e2, m, x1)
    p2, q2 = local_xy(e1, e2, m, x2)
    p3, q3 = local_xy(e1, e2, m, x3)
    area = 0.5 * ((p2 - p0) * (q3 - q1) + (p1 - p3) * (q2 - q0))
    half = 0.5 / area
    b1 = (half * (q1 - q3), half * (q2 - q0), half * (q3 - q1), half * (q0 - q2))
    b2 = (half * (p3 - p1), half * (p0 - p2), half * (p1 - p3), half * (p2 - p0))
    return (e1, e2, e3), (p0, p1, p2, p3), (q0, q1, q2, q3), area, b1, b2


@nb.njit(inline="always", fastmath=FASTMATH)
def strain_rates(b1: tuple, b2: tuple, u0: tuple, u1: tuple, u2: tuple, u3: tuple) -> tuple:
    """Membrane rates (d_x, d_y, 2 d_xy), curvature rates (kappa_x, kappa_y, 2 kappa_xy) and
    transverse shear rates (gamma_xz, gamma_yz) from the nodes' local velocities u (6-tuples),
    summed over the nodes in order (as the reference kernel)."""
    d0 = b1[0] * u0[0] + b1[1] * u1[0] + b1[2] * u2[0] + b1[3] * u3[0]
    d1 = b2[0] * u0[1] + b2[1] * u1[1] + b2[2] * u2[1] + b2[3] * u3[1]
    d2 = ((b2[0] * u0[0] + b1[0] * u0[1]) + (b2[1] * u1[0] + b1[1] * u1[1])
          + (b2[2] * u2[0] + b1[2] * u2[1]) + (b2[3] * u3[0] + b1[3] * u3[1]))  # fmt: skip
    k0 = b1[0] * u0[4] + b1[1] * u1[4] + b1[2] * u2[4] + b1[3] * u3[4]
    k1 = -b2[0] * u0[3] - b2[1] * u1[3] - b2[2] * u2[3] - b2[3] * u3[3]
    k2 = ((b2[0] * u0[4] - b1[0] * u0[3]) + (b2[1] * u1[4] - b1[1] * u1[3])
          + (b2[2] * u2[4] - b1[2] * u2[3]) + (b2[3] * u3[4] - b1[3] * u3[3]))  # fmt: skip
    g0 = ((b1[0] * u0[2] + 0.25 * u0[4]) + (b1[1] * u1[2] + 0.25 * u1[4])
          + (b1[2] * u2[2] + 0.25 * u2[4]) + (b1[3] * u3[2] + 0.25 * u3[4]))  # fmt: skip
    g1 = ((b2[0] * u0[2] - 0.25 * u0[3]) + (b2[1] * u1[2] - 0.25 * u1[3])
          + (b2[2] * u2[2] - 0.25 * u2[3]) + (b2[3] * u3[2] - 0.25 * u3[3]))  # fmt: skip
    return (d0, d1, d2), (k0, k1, k2), (g0, g1)


@nb.njit(inline="always", fastmath=FASTMATH)
def hourglass_vector(p: tuple, q: tuple, b1: tuple, b2: tuple) -> tuple:
    """gamma = h - (h . x) B1 - (h . y) B2 with h = (1, -1, 1, -1) (a 4-tuple), and sum B.B."""
    hx, hy = p[0] - p[1] + p[2] - p[3], q[0] - q[1] + q[2] - q[3]
    h0, h1 = 1.0 - hx * b1[0] - hy * b2[0], -1.0 - hx * b1[1] - hy * b2[1]
    h2, h3 = 1.0 - hx * b1[2] - hy * b2[2], -1.0 - hx * b1[3] - hy * b2[3]
    bb = ((b1[0] * b1[0] + b2[0] * b2[0]) + (b1[1] * b1[1] + b2[1] * b2[1])
          + (b1[2] * b1[2] + b2[2] * b2[2]) + (b1[3] * b1[3] + b2[3] * b2[3]))  # fmt: skip
    return (h0, h1, h2, h3), bb


@nb.njit(inline="always", fastmath=FASTMATH)
def hourglass_increment(old: float, c: float, t: tuple, u0: tuple, u1: tuple, u2: tuple,
                        u3: tuple, i: int) -> float:  # fmt: skip
    """old + c gamma_I dt u_I[i], each node's increment added in turn (as the reference)."""
    return old + c * t[0] * u0[i] + c * t[1] * u1[i] + c * t[2] * u2[i] + c * t[3] * u3[i]


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def block_kinematics(w: np.ndarray, n: int, dt: float, shear: tuple[float, float, float, float],
                     c_hg: tuple[float, float, float]) -> None:  # fmt: skip
    """Frame, B, area, strain rates of slots 0..n-1; advances their shear forces and hourglass
    stresses (SIMD across the slots: straight-line, every value computed before the first store).

    Args:
        w: the block scratch.
        n: slots in use.
        dt: time step [s].
        shear: the block's laminate's H (H11, H12, H21, H22) [N/m].
        c_hg: r A_max [N/m], r D_max [N m], r H_max t^2 [N m] of the hourglass constants.
    """
    for e in range(n):
        frame, p, q, area, b1, b2 = local_geometry(
            load3(w, R_X, e), load3(w, R_X + 3, e), load3(w, R_X + 6, e), load3(w, R_X + 9, e)
        )
        e1, e2, e3 = frame
        u0 = local_velocity(e1, e2, e3, w, R_V, e)
        u1 = local_velocity(e1, e2, e3, w, R_V + 6, e)
        u2 = local_velocity(e1, e2, e3, w, R_V + 12, e)
        u3 = local_velocity(e1, e2, e3, w, R_V + 18, e)
        d, k, g = strain_rates(b1, b2, u0, u1, u2, u3)
        sx = w[at(R_SHEAR, e)] + (shear[0] * g[0] + shear[1] * g[1]) * dt
        sy = w[at(R_SHEAR + 1, e)] + (shear[2] * g[0] + shear[3] * g[1]) * dt
        h, bb = hourglass_vector(p, q, b1, b2)
        c_m = c_hg[0] * area * bb / 8.0
        c_b = c_hg[1] * area * bb / 16.0
        c_w = c_hg[2] * bb / 12.0
        t = (h[0] * dt, h[1] * dt, h[2] * dt, h[3] * dt)
        hg0 = hourglass_increment(w[at(R_HOURGLASS + 0, e)], c_m, t, u0, u1, u2, u3, 0)
        hg1 = hourglass_increment(w[at(R_HOURGLASS + 1, e)], c_m, t, u0, u1, u2, u3, 1)
        hg2 = hourglass_increment(w[at(R_HOURGLASS + 2, e)], c_b, t, u0, u1, u2, u3, 3)
        hg3 = hourglass_increment(w[at(R_HOURGLASS + 3, e)], c_b, t, u0, u1, u2, u3, 4)
        hg4 = hourglass_increment(w[at(R_HOURGLASS + 4, e)], c_w, t, u0, u1, u2, u3, 2)
        store3(w, R_FRAME, e, e1)
        store3(w, R_FRAME + 3, e, e2)
        store3(w, R_FRAME + 6, e, e3)
        store3(w, R_B, e, (b1[0], b1[1], b1[2]))
        store3(w, R_B + 3, e, (b1[3], b2[0], b2[1]))
        w[at(R_B + 6, e)] = b2[2]
        w[at(R_B + 7, e)] = b2[3]
        w[at(R_AREA, e)] = area
        store3(w, R_GAMMA, e, (h[0], h[1], h[2]))
        w[at(R_GAMMA + 3, e)] = h[3]
        store3(w, R_RATE, e, d)
        store3(w, R_RATE + 3, e, k)
        w[at(R_SHEAR, e)] = sx
        w[at(R_SHEAR + 1, e)] = sy
        store3(w, R_HOURGLASS, e, (hg0, hg1, hg2))
        w[at(R_HOURGLASS + 3, e)] = hg3
        w[at(R_HOURGLASS + 4, e)] = hg4
        store3(w, R_RES, e, (0.0, 0.0, 0.0))  # for the layer groups' sums
        store3(w, R_RES + 3, e, (0.0, 0.0, 0.0))


Layer = tuple[float, float, float, float, float, float, float, float, float]


@nb.njit(inline="always", fastmath=FASTMATH)
def layer_stiffness_of(stiffness: np.ndarray, k: int) -> Layer:
    """Qbar of layer k, row-major, as a 9-tuple [Pa]."""
    q = stiffness[k]
    return (q[0, 0], q[0, 1], q[0, 2], q[1, 0], q[1, 1], q[1, 2], q[2, 0], q[2, 1], q[2, 2])


@nb.njit(inline="always", fastmath=FASTMATH)
def add_layer(s: np.ndarray, row: int, e: int, r: tuple, q: Layer, z: float, t: float,
              dt: float, f: Vec3, m: Vec3) -> tuple[Vec3, Vec3, Vec3]:  # fmt: skip
    """One layer of slot e: its stress (rows row..row+2 of ``s``) advanced by
    Qbar (d + z kappa) dt, and the resultants ``f`` (N) and ``m`` (M) with its share added.

    Args:
        r: the membrane and curvature rates (6).
        q: Qbar [Pa]; z: the layer's height [m]; t: its thickness [m].

    Returns:
        The new stress, N [N/m] and M [N].
    """
    d0, d1, d2 = r[0] + z * r[3], r[1] + z * r[4], r[2] + z * r[5]
    s0 = s[at(row, e)] + (q[0] * d0 + q[1] * d1 + q[2] * d2) * dt
    s1 = s[at(row + 1, e)] + (q[3] * d0 + q[4] * d1 + q[5] * d2) * dt
    s2 = s[at(row + 2, e)] + (q[6] * d0 + q[7] * d1 + q[8] * d2) * dt
    zt = z * t
    return ((s0, s1, s2), (f[0] + t * s0, f[1] + t * s1, f[2] + t * s2),
            (m[0] + zt * s0, m[1] + zt * s1, m[2] + zt * s2))  # fmt: skip


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def block_layer_group(w: np.ndarray, s: np.ndarray, dt: float, stiffness: np.ndarray,
                      z: np.ndarray, thickness: np.ndarray, first: int) -> None:  # fmt: skip
    """Advance layers first..first+GROUP-1 of all BLOCK slots (their stresses in ``s``) and add
    their shares t_k sigma_k and z_k t_k sigma_k to the resultants N [N/m], M [N] (rows R_RES),
    SIMD across the slots (straight-line, every value computed before the first store).

    Args:
        w: the block scratch; s: the group's stress scratch.
        dt: time step [s].
        stiffness, z, thickness: the block's laminate's Qbar_k (n, 3, 3) [Pa], z_k [m] and
            t_k [m], padded with zero layers to whole groups.
        first: the group's first layer.
    """
    q0, q1 = layer_stiffness_of(stiffness, first), layer_stiffness_of(stiffness, first + 1)
    q2, q3 = layer_stiffness_of(stiffness, first + 2), layer_stiffness_of(stiffness, first + 3)
    q4 = layer_stiffness_of(stiffness, first + 4)
    z0, z1, z2, z3, z4 = z[first], z[first + 1], z[first + 2], z[first + 3], z[first + 4]
    t0, t1, t2 = thickness[first], thickness[first + 1], thickness[first + 2]
    t3, t4 = thickness[first + 3], thickness[first + 4]
    for e in range(BLOCK):
        rm, rk = load3(w, R_RATE, e), load3(w, R_RATE + 3, e)
        r = (rm[0], rm[1], rm[2], rk[0], rk[1], rk[2])
        f, m = load3(w, R_RES, e), load3(w, R_RES + 3, e)
        a0, f, m = add_layer(s, 0, e, r, q0, z0, t0, dt, f, m)
        a1, f, m = add_layer(s, 3, e, r, q1, z1, t1, dt, f, m)
        a2, f, m = add_layer(s, 6, e, r, q2, z2, t2, dt, f, m)
        a3, f, m = add_layer(s, 9, e, r, q3, z3, t3, dt, f, m)
        a4, f, m = add_layer(s, 12, e, r, q4, z4, t4, dt, f, m)
        store3(s, 0, e, a0)
        store3(s, 3, e, a1)
        store3(s, 6, e, a2)
        store3(s, 9, e, a3)
        store3(s, 12, e, a4)
        store3(w, R_RES, e, f)
        store3(w, R_RES + 3, e, m)


@nb.njit(inline="always", fastmath=FASTMATH)
def node_forces(b1: float, b2: float, g: float, area: float, res: tuple, q: tuple[float, float],
                hg: tuple, frame: tuple[Vec3, Vec3, Vec3]) -> tuple[Vec3, Vec3]:  # fmt: skip
    """One node's force [N] and moment [N m] in global axes from its B1, B2 [1/m] and hourglass
    shape g, the resultants ``res`` (N, M), shear forces Q and hourglass stresses ``hg``."""
    f0 = area * (b1 * res[0] + b2 * res[2]) + g * hg[0]
    f1 = area * (b2 * res[1] + b1 * res[2]) + g * hg[1]
    f2 = area * (b1 * q[0] + b2 * q[1]) + g * hg[4]
    f3 = area * (-b2 * res[4] - b1 * res[5] - 0.25 * q[1]) + g * hg[2]
    f4 = area * (b1 * res[3] + b2 * res[5] + 0.25 * q[0]) + g * hg[3]
    e1, e2, e3 = frame
    return to_global(e1, e2, e3, f0, f1, f2), moment_to_global(e1, e2, f3, f4)


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def block_forces(w: np.ndarray, n: int) -> None:
    """Nodal forces and moments (global) of slots 0..n-1 into rows R_V + 6 a + i (SIMD across
    the slots), by virtual work on the area: N . eps + M . kappa + Q . gamma, plus hourglass."""
    for e in range(n):
        frame = (load3(w, R_FRAME, e), load3(w, R_FRAME + 3, e), load3(w, R_FRAME + 6, e))
        lo, mid = load3(w, R_B, e), load3(w, R_B + 3, e)
        b1 = (lo[0], lo[1], lo[2], mid[0])
        b2 = (mid[1], mid[2], w[at(R_B + 6, e)], w[at(R_B + 7, e)])
        area = w[at(R_AREA, e)]
        g = (w[at(R_GAMMA, e)], w[at(R_GAMMA + 1, e)], w[at(R_GAMMA + 2, e)],
             w[at(R_GAMMA + 3, e)])  # fmt: skip
        n_, m_ = load3(w, R_RES, e), load3(w, R_RES + 3, e)
        res = (n_[0], n_[1], n_[2], m_[0], m_[1], m_[2])
        q = (w[at(R_SHEAR, e)], w[at(R_SHEAR + 1, e)])
        h = load3(w, R_HOURGLASS, e)
        hg = (h[0], h[1], h[2], w[at(R_HOURGLASS + 3, e)], w[at(R_HOURGLASS + 4, e)])
        f0, m0 = node_forces(b1[0], b2[0], g[0], area, res, q, hg, frame)
        f1, m1 = node_forces(b1[1], b2[1], g[1], area, res, q, hg, frame)
        f2, m2 = node_forces(b1[2], b2[2], g[2], area, res, q, hg, frame)
        f3, m3 = node_forces(b1[3], b2[3], g[3], area, res, q, hg, frame)
        store3(w, R_V, e, f0)
        store3(w, R_V + 3, e, m0)
        store3(w, R_V + 6, e, f1)
        store3(w, R_V + 9, e, m1)
        store3(w, R_V + 12, e, f2)
        store3(w, R_V + 15, e, m2)
        store3(w, R_V + 18, e, f3)
        store3(w, R_V + 21, e, m3)


@nb.njit
def gather_nodes(w: np.ndarray, start: int, n: int, points: np.ndarray, velocity: np.ndarray,
                 cells: np.ndarray) -> None:  # fmt: skip
    """The node coordinates and velocities of cells start..start+n-1."""
    for e in range(n):
        for a in range(4):
            node = cells[start + e, a]
            for i in range(3):
                w[at(R_X + 3 * a + i, e)] = points[node, i]
            for i in range(6):
                w[at(R_V + 6 * a + i, e)] = velocity[node, i]


@nb.njit
def clear_unused_rates(w: np.ndarray, n: int) -> None:
    """Zero rates for the slots n..BLOCK-1 that a short block leaves unused (the layer loop runs
    them too), so that their history stays zero."""
    for r in range(R_RATE, R_RATE + 6):
        for e in range(n, BLOCK):
            w[at(r, e)] = 0.0


@nb.njit
def store_cell_forces(w: np.ndarray, start: int, n: int, forces: np.ndarray) -> None:
    """The nodal forces of cells start..start+n-1 into ``forces`` (n_cells, 4, 6)."""
    for e in range(n):
        for a in range(4):
            for i in range(6):
                forces[start + e, a, i] = w[at(R_V + 6 * a + i, e)]


@nb.njit
def add_nodal_forces(w: np.ndarray, start: int, n: int, cells: np.ndarray,
                     nodal: np.ndarray) -> None:  # fmt: skip
    """Add the nodal forces of cells start..start+n-1 into ``nodal`` (n_points, 6), cell by cell
    and node by node (the order of a serial sum over (n_cells, 4, 6) cell forces)."""
    for e in range(n):
        for a in range(4):
            node = cells[start + e, a]
            for i in range(6):
                nodal[node, i] += w[at(R_V + 6 * a + i, e)]


@nb.njit
def active_layers(layer_stiffness: np.ndarray, layer_thickness: np.ndarray) -> np.ndarray:
    """Per laminate, the number of layers up to the last one of non-zero thickness or stiffness
    (the rest is the padding of :func:`batball.elements.shell_bt_section.layered_section`)."""
    n_laminates, n_layers = layer_thickness.shape
    active = np.zeros(n_laminates, dtype=np.int64)
    for lam in range(n_laminates):
        for k in range(n_layers):
            if layer_thickness[lam, k] != 0.0 or np.any(layer_stiffness[lam, k] != 0.0):
                active[lam] = k + 1
    return active


@nb.njit
def padded_layers(
    layer_stiffness: np.ndarray, layer_z: np.ndarray, layer_thickness: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Qbar_k, z_k and t_k of every laminate padded with zero layers to whole groups."""
    n_laminates, n_layers = layer_z.shape
    n_padded = padded_layer_count(n_layers)
    stiffness = np.zeros((n_laminates, n_padded, 3, 3))
    z, thickness = np.zeros((n_laminates, n_padded)), np.zeros((n_laminates, n_padded))
    stiffness[:, :n_layers] = layer_stiffness
    z[:, :n_layers] = layer_z
    thickness[:, :n_layers] = layer_thickness
    return stiffness, z, thickness


@nb.njit(inline="always")
def advance_blocks(first, last, points, cells, velocity, dt, cell_laminate, section, ratio,
                   block_start, history, forces, fused):  # fmt: skip
    """Blocks first..last-1: their stresses advanced in ``history``, their nodal forces written
    to ``forces`` (n_cells, 4, 6) or, with ``fused`` (a compile-time constant), added into it
    (n_points, 6)."""
    stiffness, z, thickness, active, shear, moduli = section
    group_size = 3 * GROUP * BLOCK
    state = N_STATE_ROWS * BLOCK
    w = np.zeros(N_ROWS * BLOCK)
    for b in range(first, last):
        start, stop = block_start[b], block_start[b + 1]
        n, lam = stop - start, cell_laminate[start]
        h, m, rows = shear[lam], moduli[lam], history[b]
        gather_nodes(w, start, n, points, velocity, cells)
        w[R_SHEAR * BLOCK : R_SHEAR * BLOCK + state] = rows[:state]
        block_kinematics(w, n, dt, (h[0, 0], h[0, 1], h[1, 0], h[1, 1]),
                         (ratio * m[0], ratio * m[1], ratio * m[2] * m[3] ** 2))  # fmt: skip
        clear_unused_rates(w, n)
        for group in range(-(-active[lam] // GROUP)):
            first_row = S_LAYERS * BLOCK + group * group_size
            block_layer_group(w, rows[first_row : first_row + group_size], dt, stiffness[lam],
                              z[lam], thickness[lam], group * GROUP)  # fmt: skip
        block_forces(w, n)
        rows[:state] = w[R_SHEAR * BLOCK : R_SHEAR * BLOCK + state]
        if fused:
            add_nodal_forces(w, start, n, cells, forces)
        else:
            store_cell_forces(w, start, n, forces)


@nb.njit
def kernel_section(layer_stiffness: np.ndarray, layer_z: np.ndarray,
                   layer_thickness: np.ndarray, shear: np.ndarray, moduli: np.ndarray,
                   history: np.ndarray) -> tuple:  # fmt: skip
    """The section arrays as the block loop takes them (layers padded to whole groups, the
    active layer counts); checks that ``history`` has the rows of this section."""
    stiffness, z, thickness = padded_layers(layer_stiffness, layer_z, layer_thickness)
    if history.shape[1] != (N_STATE_ROWS + 3 * stiffness.shape[1]) * BLOCK:
        raise ValueError("the shell state's history does not fit the section's layers")
    return (stiffness, z, thickness, active_layers(layer_stiffness, layer_thickness), shear,
            moduli)  # fmt: skip


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def bt_force_kernel(points: np.ndarray, cells: np.ndarray, velocity: np.ndarray, dt: float,
                    cell_laminate: np.ndarray, layer_stiffness: np.ndarray,
                    layer_z: np.ndarray, layer_thickness: np.ndarray, shear: np.ndarray,
                    moduli: np.ndarray, ratio: float, block_start: np.ndarray,
                    history: np.ndarray, forces: np.ndarray) -> None:  # fmt: skip
    """Advance every cell's stresses by dt and write its nodal forces (n_cells, 4, 6), global.

    Args:
        points: current node coordinates, (n_points, 3), m.
        cells: (n_cells, 4) node indices.
        velocity: (n_points, 6) mid-step velocities and rotation rates, m/s and rad/s.
        dt: time step, s.
        cell_laminate, layer_stiffness, layer_z, layer_thickness, shear, moduli: the
            :class:`~batball.elements.shell_bt_section.LayeredSection` arrays.
        ratio: r of the hourglass constants.
        block_start, history: the :class:`ShellForceState` arrays; history in/out.
        forces: (n_cells, 4, 6) out: forces [N] and moments [N m] on each cell's nodes (f_int).

    The blocks run in a fixed number of contiguous parallel chunks; a cell writes only its own
    rows and its arithmetic does not depend on the chunks, so the result does not depend on the
    number of threads.
    """
    section = kernel_section(layer_stiffness, layer_z, layer_thickness, shear, moduli, history)
    n_blocks = block_start.size - 1
    n_chunks = max(1, min(n_blocks, 64))  # enough for the threads' load balance
    for chunk in nb.prange(n_chunks):
        advance_blocks(chunk * n_blocks // n_chunks, (chunk + 1) * n_blocks // n_chunks, points,
                       cells, velocity, dt, cell_laminate, section, ratio, block_start, history,
                       forces, False)  # fmt: skip


@nb.njit(cache=True, fastmath=FASTMATH)
def bt_nodal_force_kernel(points: np.ndarray, cells: np.ndarray, velocity: np.ndarray,
                          dt: float, cell_laminate: np.ndarray, layer_stiffness: np.ndarray,
                          layer_z: np.ndarray, layer_thickness: np.ndarray, shear: np.ndarray,
                          moduli: np.ndarray, ratio: float, block_start: np.ndarray,
                          history: np.ndarray, nodal: np.ndarray) -> None:  # fmt: skip
    """:func:`bt_force_kernel` with the assembly fused in, on one thread: ``nodal`` (n_points,
    >= 6) gets f_int in its first 6 columns (overwritten), summed cell by cell, node by node:
    the same bits as a serial sum of :func:`bt_force_kernel`'s cell forces (no (n_cells, 4, 6)
    array written and read back)."""
    nodal[:, :6] = 0.0
    section = kernel_section(layer_stiffness, layer_z, layer_thickness, shear, moduli, history)
    advance_blocks(0, block_start.size - 1, points, cells, velocity, dt, cell_laminate, section,
                   ratio, block_start, history, nodal, True)  # fmt: skip


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def bt_slot_force_kernel(points: np.ndarray, cells: np.ndarray, velocity: np.ndarray,
                         dt: float, cell_laminate: np.ndarray, layer_stiffness: np.ndarray,
                         layer_z: np.ndarray, layer_thickness: np.ndarray, shear: np.ndarray,
                         moduli: np.ndarray, ratio: float, block_start: np.ndarray,
                         history: np.ndarray, slots: np.ndarray,
                         slot_nodes: np.ndarray) -> None:  # fmt: skip
    """:func:`bt_nodal_force_kernel` on several threads: the blocks split into
    ``slots.shape[0]`` equal contiguous runs, run k adding f_int into ``slots[k]`` (n_slots,
    n_points, 6), cleared first inside its node range ``slot_nodes[k]`` (:func:`slot_node_ranges`),
    so that each nodal array has one writer and no per-cell force array is written and read back.
    :func:`sum_slots` adds the slots up. The sums depend on the number of slots (a node shared by
    two runs is summed in two parts), not on the threads' scheduling."""
    section = kernel_section(layer_stiffness, layer_z, layer_thickness, shear, moduli, history)
    n_blocks = block_start.size - 1
    n_slots = slots.shape[0]
    for k in nb.prange(n_slots):
        slots[k, slot_nodes[k, 0] : slot_nodes[k, 1], :6] = 0.0
        advance_blocks(k * n_blocks // n_slots, (k + 1) * n_blocks // n_slots, points, cells,
                       velocity, dt, cell_laminate, section, ratio, block_start, history,
                       slots[k], True)  # fmt: skip


def slot_node_ranges(cells: np.ndarray, block_start: np.ndarray, n_slots: int) -> np.ndarray:
    """The node ids each run of :func:`bt_slot_force_kernel` can write, (n_slots, 2) as
    [lowest, highest + 1] over the run's cells (empty runs get [0, 0])."""
    n_blocks = block_start.size - 1
    ranges = np.zeros((n_slots, 2), dtype=np.int64)
    for k in range(n_slots):
        first = block_start[k * n_blocks // n_slots]
        last = block_start[(k + 1) * n_blocks // n_slots]
        if last > first:
            ranges[k] = cells[first:last].min(), cells[first:last].max() + 1
    return ranges


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def sum_slots(slots: np.ndarray, slot_nodes: np.ndarray, scale: float, out: np.ndarray) -> None:
    """out[:, :6] = scale times the sum of the slots holding each node (slot order)."""
    for n in nb.prange(out.shape[0]):
        for i in range(6):
            total = 0.0
            for k in range(slots.shape[0]):
                if slot_nodes[k, 0] <= n < slot_nodes[k, 1]:
                    total += slots[k, n, i]
            out[n, i] = scale * total


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
    nodal = np.empty((points.shape[0], 6))
    bt_nodal_force_kernel(np.ascontiguousarray(points, dtype=np.float64), cells.astype(np.int64),
                          np.ascontiguousarray(velocity, dtype=np.float64), float(dt),
                          section.cell_laminate, section.layer_stiffness, section.layer_z,
                          section.layer_thickness, section.shear, section.hourglass_moduli,
                          float(hourglass_ratio), state.block_start, state.history,
                          nodal)  # fmt: skip
    return nodal


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
