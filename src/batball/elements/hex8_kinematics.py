"""Pointwise kinematics of the one-point hex, as Numba functions on scalars and tuples.

Tensors are tuples so that a loop over a block of elements stays straight-line and vectorises:
3x3 tensors are 9-tuples in row-major order, symmetric ones 6-tuples in Voigt order
(xx, yy, zz, xy, yz, zx), vectors 3-tuples.
"""

from __future__ import annotations

import numba as nb

from batball.elements.hex8_geometry import Vector, modal_volume_gradient
from batball.elements.vector_math import like
from batball.materials.viscoelastic import advance_viscoelastic_component
from batball.numerics import FASTMATH

#: Modal sums or gradients of an element: a tuple of 3-vectors (modes 1..6 or 1..7).
Modes = tuple[Vector, ...]
#: A 3x3 tensor, row-major (9 floats); a symmetric one in Voigt order (6 floats).
Tensor = tuple[float, ...]
Voigt = tuple[float, ...]


@nb.njit(inline="always", fastmath=FASTMATH)
def _contract(v, g, i, j):
    """sum_k v[k][i] g[k][j] over six modal pairs."""
    return (
        v[0][i] * g[0][j]
        + v[1][i] * g[1][j]
        + v[2][i] * g[2][j]
        + v[3][i] * g[3][j]
        + v[4][i] * g[4][j]
        + v[5][i] * g[5][j]
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def velocity_gradient(v: Modes, g: Modes, volume: float) -> Tensor:
    """L_ij = sum_a v_ai B_aj / V = sum_k V_ki G_kj / V [1/s] (9-tuple).

    Args:
        v: six modal velocity sums V_k (3-tuples) [m/s]; g: six G_k = dV/dX_k [m^2];
        volume: V [m^3].
    """
    inv = like(volume, 1.0) / volume
    return (
        _contract(v, g, 0, 0) * inv,
        _contract(v, g, 0, 1) * inv,
        _contract(v, g, 0, 2) * inv,
        _contract(v, g, 1, 0) * inv,
        _contract(v, g, 1, 1) * inv,
        _contract(v, g, 1, 2) * inv,
        _contract(v, g, 2, 0) * inv,
        _contract(v, g, 2, 1) * inv,
        _contract(v, g, 2, 2) * inv,
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def cayley_rotation(w01: float, w12: float, w20: float, dt: float) -> Tensor:
    """Hughes-Winget rotation Q = (I - W dt/2)^-1 (I + W dt/2) (9-tuple) for the spin W.

    With S = W dt / 2 (skew) and theta^2 = |axial(S)|^2 this is Q = I + 2 (S + S^2) / (1 + theta^2).
    """
    one, half = like(dt, 1.0), like(dt, 0.5)
    a = half * dt * w01  # S[0,1]
    b = half * dt * w12  # S[1,2]
    c = half * dt * w20  # S[2,0]
    theta2 = a * a + b * b + c * c
    scale = like(dt, 2.0) / (one + theta2)
    # S = [[0, a, -c], [-a, 0, b], [c, -b, 0]];  S^2 = w w^T - theta2 I with w = (b, c, a)
    return (
        one + scale * (b * b - theta2),
        scale * (a + b * c),
        scale * (-c + a * b),
        scale * (-a + b * c),
        one + scale * (c * c - theta2),
        scale * (b + c * a),
        scale * (c + a * b),
        scale * (-b + c * a),
        one + scale * (a * a - theta2),
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _rotated_row(q, s, i):
    """Row i of Q s for the symmetric Voigt 6-tuple s."""
    qi0, qi1, qi2 = q[3 * i], q[3 * i + 1], q[3 * i + 2]
    return (
        qi0 * s[0] + qi1 * s[3] + qi2 * s[5],
        qi0 * s[3] + qi1 * s[1] + qi2 * s[4],
        qi0 * s[5] + qi1 * s[4] + qi2 * s[2],
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _row_dot(t, q, j):
    """t . (row j of Q)."""
    return t[0] * q[3 * j] + t[1] * q[3 * j + 1] + t[2] * q[3 * j + 2]


@nb.njit(inline="always", fastmath=FASTMATH)
def rotate_voigt(s: Voigt, q: Tensor) -> Voigt:
    """Q s Q^T for a symmetric tensor s (Voigt 6-tuple) and a rotation Q (9-tuple)."""
    t0, t1, t2 = _rotated_row(q, s, 0), _rotated_row(q, s, 1), _rotated_row(q, s, 2)
    return (
        _row_dot(t0, q, 0),
        _row_dot(t1, q, 1),
        _row_dot(t2, q, 2),
        _row_dot(t0, q, 1),
        _row_dot(t1, q, 2),
        _row_dot(t2, q, 0),
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def deviatoric_increment(lg: Tensor, dt: float) -> tuple[Voigt, float]:
    """dev(D) dt (Voigt 6-tuple, tensor shear components) and tr D [1/s] from L (9-tuple)."""
    trd = lg[0] + lg[4] + lg[8]
    third = trd / like(trd, 3.0)
    half = like(dt, 0.5)
    de = (
        (lg[0] - third) * dt,
        (lg[4] - third) * dt,
        (lg[8] - third) * dt,
        half * (lg[1] + lg[3]) * dt,
        half * (lg[5] + lg[7]) * dt,
        half * (lg[6] + lg[2]) * dt,
    )
    return de, trd


@nb.njit(inline="always", fastmath=FASTMATH)
def half_stress_work(s_inf: Voigt, h: Voigt, de: Voigt) -> float:
    """(1/2) (s_inf + h) : de for Voigt 6-tuples (shear counted twice) [Pa]."""
    normal = (s_inf[0] + h[0]) * de[0] + (s_inf[1] + h[1]) * de[1] + (s_inf[2] + h[2]) * de[2]
    shear = (s_inf[3] + h[3]) * de[3] + (s_inf[4] + h[4]) * de[4] + (s_inf[5] + h[5]) * de[5]
    return like(normal, 0.5) * normal + shear


@nb.njit(inline="always", fastmath=FASTMATH)
def advance_deviator(
    s_inf: Voigt, h: Voigt, de: Voigt, two_g_inf: float, decay: float, scale: float
) -> tuple[Voigt, Voigt]:
    """MAT_006 step of both Voigt 6-tuples (see ``advance_viscoelastic_component``)."""
    s0, h0 = advance_viscoelastic_component(s_inf[0], h[0], de[0], two_g_inf, decay, scale)
    s1, h1 = advance_viscoelastic_component(s_inf[1], h[1], de[1], two_g_inf, decay, scale)
    s2, h2 = advance_viscoelastic_component(s_inf[2], h[2], de[2], two_g_inf, decay, scale)
    s3, h3 = advance_viscoelastic_component(s_inf[3], h[3], de[3], two_g_inf, decay, scale)
    s4, h4 = advance_viscoelastic_component(s_inf[4], h[4], de[4], two_g_inf, decay, scale)
    s5, h5 = advance_viscoelastic_component(s_inf[5], h[5], de[5], two_g_inf, decay, scale)
    return (s0, s1, s2, s3, s4, s5), (h0, h1, h2, h3, h4, h5)


@nb.njit(inline="always", fastmath=FASTMATH)
def _step_back(x, v, s):
    """x + s v for 3-tuples."""
    return (x[0] + s * v[0], x[1] + s * v[1], x[2] + s * v[2])


@nb.njit(inline="always", fastmath=FASTMATH)
def midstep_velocity_gradient(x: Modes, v: Modes, dt: float) -> tuple[Tensor, float]:
    """L (9-tuple) [1/s] on x^(n-1/2) = x^n - dt/2 v^(n-1/2), and that geometry's volume [m^3].

    Args:
        x, v: modal sums (3-tuples, modes 1..6 at least) of x^n [m] and v^(n-1/2) [m/s].
    """
    s = like(dt, -0.5) * dt  # the modal sums are linear in the node values
    g1, g2, g3, g4, g5, g6, volume = modal_volume_gradient(
        _step_back(x[0], v[0], s),
        _step_back(x[1], v[1], s),
        _step_back(x[2], v[2], s),
        _step_back(x[3], v[3], s),
        _step_back(x[4], v[4], s),
        _step_back(x[5], v[5], s),
    )
    return velocity_gradient(v, (g1, g2, g3, g4, g5, g6), volume), volume


@nb.njit(inline="always", fastmath=FASTMATH)
def deviator_update(
    lg: Tensor, s_inf: Voigt, h: Voigt, two_g_inf: float, decay: float, scale: float, dt: float
) -> tuple[Voigt, Voigt, float, float, Tensor, Voigt]:
    """Rotate (Hughes-Winget) and advance (MAT_006) the stored deviatoric stresses.

    Args:
        lg: velocity gradient L (9-tuple) [1/s]; s_inf, h: Voigt 6-tuples [Pa];
        two_g_inf, decay, scale: the material's step factors; dt: the step [s].

    Returns:
        The new s_inf and h, tr D [1/s], the midpoint deviatoric stress power per volume
        (s_inf + h) : dev(D) dt [J/m^3], the rotation Q (9-tuple) and dev(D) dt (Voigt), which
        further Prony terms reuse.
    """
    half = like(dt, 0.5)
    q = cayley_rotation(half * (lg[1] - lg[3]), half * (lg[5] - lg[7]), half * (lg[6] - lg[2]), dt)
    s_rotated = rotate_voigt(s_inf, q)
    h_rotated = rotate_voigt(h, q)
    de, trd = deviatoric_increment(lg, dt)
    s_new, h_new = advance_deviator(s_rotated, h_rotated, de, two_g_inf, decay, scale)
    work = half_stress_work(s_rotated, h_rotated, de) + half_stress_work(s_new, h_new, de)
    return s_new, h_new, trd, work, q, de


@nb.njit(inline="always", fastmath=FASTMATH)
def element_kinematics(
    x: Modes, v: Modes, s_inf: Voigt, h: Voigt, factors: tuple[float, float, float], dt: float
) -> tuple[Voigt, Voigt, float, float, float, Modes, float, Tensor, Voigt]:
    """The stress update on the mid-step geometry and the volume gradient on x^n.

    Args:
        x, v: modal sums (3-tuples) of x^n [m] and v^(n-1/2) [m/s].
        s_inf, h: stored deviatoric stresses (Voigt 6-tuples) [Pa].
        factors: the material's (2 G_inf, decay, relaxing modulus) of the step.

    Returns:
        New s_inf and h, tr D [1/s], the deviatoric work per volume [J/m^3], the mid-step
        volume [m^3], G_1..G_6 on x^n [m^2], the volume V [m^3], the step's rotation Q and
        dev(D) dt (for further Prony terms).
    """
    lg, vmid = midstep_velocity_gradient(x, v, dt)
    s_new, h_new, trd, dev_work, q, de = deviator_update(
        lg, s_inf, h, factors[0], factors[1], factors[2], dt
    )
    g1, g2, g3, g4, g5, g6, vol = modal_volume_gradient(x[0], x[1], x[2], x[3], x[4], x[5])
    return s_new, h_new, trd, dev_work, vmid, (g1, g2, g3, g4, g5, g6), vol, q, de


@nb.njit(inline="always", fastmath=FASTMATH)
def advance_prony_term(
    h: Voigt, q: Tensor, de: Voigt, decay: float, scale: float
) -> tuple[Voigt, float]:
    """One further Prony term: h <- decay Q h Q^T + scale de, and its midpoint work per volume
    h : de [J/m^3] (the same recursion as MAT_006's relaxing branch, docs/physics.md 1.3)."""
    r = rotate_voigt(h, q)
    new = (
        decay * r[0] + scale * de[0],
        decay * r[1] + scale * de[1],
        decay * r[2] + scale * de[2],
        decay * r[3] + scale * de[3],
        decay * r[4] + scale * de[4],
        decay * r[5] + scale * de[5],
    )
    z = like(decay, 0.0)
    zero = (z, z, z, z, z, z)
    return new, half_stress_work(zero, r, de) + half_stress_work(zero, new, de)
