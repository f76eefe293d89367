"""Penalty contact between a deformable body's surface nodes and rigid analytic targets.

The targets are the fixtures of the ball tests: the flat wall of ASTM F1887 (COR) and the 2.63-in
half-cylinder of ASTM F2845 (CCOR, dynamic stiffness). Each slave node that penetrates the target
by g > 0 gets the force k g n along the target's outward normal n; the target's reaction, the sum
of the opposite forces, is what the load cells measure.

Penalty stiffness (LS-DYNA conventions, docs/physics.md section 6.6):

* SOFT = 0: a body segment of area A on an element of volume V has k = SLSFAC * SFS * K A^2 / V,
  with K the body's bulk modulus and SLSFAC = 0.1 by default (*CONTROL_CONTACT). A slave node takes
  the mean stiffness of the surface segments around it. The rigid side is the stiffer one, so the
  body's segments set the stiffness, as LS-DYNA's two-way contact does when a soft part meets a
  stiff one.
* SOFT = 1: k = max(SLSFAC * SFS * k0, SOFSCL * k1) with k1 = m / (2 dt^2), m the node's mass and
  dt the initial stable step (LS-DYNA FAQ "contact.soft1", SOFSCL = 0.1 by default). This is the
  stability-based stiffness that LS-DYNA recommends for soft materials against stiff ones.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

from batball.contact.columns import coulomb_update
from batball.errors import SpecError
from batball.numerics import FASTMATH

TARGET_PLANE = 0
TARGET_CYLINDER = 1


#: Length of a packed target's parameter row (see ``RigidPlane.packed``).
N_TARGET_PARAMS = 14

#: A point whose squared distance from a cylinder's axis exceeds this times R^2 is outside it
#: whatever the rounding of the root (a margin far above it), so its depth is not computed.
OUTSIDE = 1.0 + 1e-9


@dataclass(frozen=True)
class RigidPlane:
    """An infinite flat wall, fixed or translating at a constant velocity.

    Attributes:
        point: (3,) a point on the wall face at t = 0 [m].
        normal: (3,) unit normal pointing out of the wall, toward the ball.
        velocity: (3,) the wall's prescribed velocity [m/s] (a moving platen); None = fixed.
    """

    point: np.ndarray
    normal: np.ndarray
    velocity: np.ndarray | None = None

    def packed(self) -> tuple[int, np.ndarray]:
        """Kernel form: (TARGET_PLANE, [point, normal, 5 zeros, velocity])."""
        params = np.zeros(N_TARGET_PARAMS)
        params[0:3] = self.point
        params[3:6] = unit(self.normal, "target.normal")
        params[11:14] = packed_velocity(self.velocity)
        return TARGET_PLANE, params

    def surface(self, *, center: np.ndarray, size: float) -> tuple[np.ndarray, np.ndarray]:
        """The wall drawn for ParaView at t = 0: a square of side ``size`` [m] on the wall,
        centred at the foot of ``center`` (3,) [m]; (points (4, 3) [m], quads (1, 4)), the
        quad's right-hand normal out of the wall."""
        n = unit(self.normal, "target.normal")
        e1, e2 = plane_axes(n)
        foot = center - ((center - self.point) @ n) * n
        corners = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
        points = foot + 0.5 * size * (corners[:, :1] * e1 + corners[:, 1:] * e2)
        return points, np.array([[0, 1, 2, 3]])


@dataclass(frozen=True)
class RigidCylinder:
    """A half-cylinder, fixed or translating, whose curved face meets the body.

    Attributes:
        axis_point: (3,) a point on the axis, at mid-length [m].
        axis: (3,) unit axis direction.
        front: (3,) unit vector normal to the axis toward the ball: only the half with
            (x - axis_point) . front >= 0 is the impact face.
        radius: [m]; length: the cylinder's length along the axis [m].
        velocity: (3,) prescribed velocity [m/s]; None = fixed.
    """

    axis_point: np.ndarray
    axis: np.ndarray
    front: np.ndarray
    radius: float
    length: float
    velocity: np.ndarray | None = None

    def packed(self) -> tuple[int, np.ndarray]:
        """Kernel form: (TARGET_CYLINDER, [axis point, axis, front, radius, half length,
        velocity])."""
        if not (self.radius > 0 and self.length > 0):
            raise SpecError("target.radius", self.radius, "a positive radius and length")
        params = np.zeros(N_TARGET_PARAMS)
        params[0:3] = self.axis_point
        params[3:6] = unit(self.axis, "target.axis")
        params[6:9] = unit(self.front, "target.front")
        params[9] = self.radius
        params[10] = 0.5 * self.length
        params[11:14] = packed_velocity(self.velocity)
        return TARGET_CYLINDER, params

    def surface(self, *, center: np.ndarray | None = None, size: float = 0.0,
                n_around: int = 24, n_along: int = 8) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """The impact face drawn for ParaView at t = 0: the half-cylinder's curved face, whole
        (``center`` and ``size`` are a wall's and not used), ``n_around`` by ``n_along`` quads;
        (points (n_points, 3) [m], quads (n_quads, 4)), right-hand normals outward."""
        axis = unit(self.axis, "target.axis")
        front = unit(self.front - (self.front @ axis) * axis, "target.front")
        side = np.cross(axis, front)
        angle = np.linspace(-0.5 * np.pi, 0.5 * np.pi, n_around + 1)
        along = np.linspace(-0.5 * self.length, 0.5 * self.length, n_along + 1)
        radial = np.cos(angle)[:, None] * front + np.sin(angle)[:, None] * side
        points = (self.axis_point + self.radius * radial[:, None, :]
                  + along[None, :, None] * axis).reshape(-1, 3)  # fmt: skip
        i, j = np.meshgrid(np.arange(n_around), np.arange(n_along), indexing="ij")
        first = (i * (n_along + 1) + j).ravel()
        quads = np.stack([first, first + n_along + 1, first + n_along + 2, first + 1], axis=1)
        return points, quads


def plane_axes(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors e1, e2 in the plane of unit ``normal`` (3,) with e1 x e2 = normal."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(normal, helper)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(normal, e1)


def packed_velocity(velocity: np.ndarray | None) -> np.ndarray:
    """A target's velocity as three finite floats [m/s] (zero when fixed)."""
    if velocity is None:
        return np.zeros(3)
    v = np.asarray(velocity, dtype=np.float64)
    if v.shape != (3,) or not np.isfinite(v).all():
        raise SpecError("target.velocity", np.asarray(velocity).tolist(), "three finite m/s values")
    return v


def unit(vector: np.ndarray, field: str) -> np.ndarray:
    """``vector`` scaled to unit length; a zero vector is a :class:`SpecError`."""
    v = np.asarray(vector, dtype=np.float64)
    norm = float(np.linalg.norm(v))
    if not norm > 0:
        raise SpecError(field, vector.tolist(), "a non-zero direction")
    return v / norm


@nb.njit(inline="always", fastmath=FASTMATH)
def _penetration(
    kind: int, params: np.ndarray, x0: float, x1: float, x2: float, normal: np.ndarray
) -> float:
    """Penetration depth g (> 0 inside) of a point and the target's outward normal there.

    ``x0, x1, x2`` are relative to the target's motion (the point minus velocity * time).
    """
    if kind == TARGET_PLANE:
        for i in range(3):
            normal[i] = params[3 + i]
        return -(
            (x0 - params[0]) * params[3]
            + (x1 - params[1]) * params[4]
            + (x2 - params[2]) * params[5]
        )
    d0 = x0 - params[0]
    d1 = x1 - params[1]
    d2 = x2 - params[2]
    axial = d0 * params[3] + d1 * params[4] + d2 * params[5]
    if abs(axial) > params[10]:
        return -1.0
    r0 = d0 - axial * params[3]
    r1 = d1 - axial * params[4]
    r2 = d2 - axial * params[5]
    if r0 * params[6] + r1 * params[7] + r2 * params[8] < 0.0:
        return -1.0
    squared = r0 * r0 + r1 * r1 + r2 * r2
    if squared > OUTSIDE * params[9] * params[9]:
        return -1.0  # r > R for certain: the root and the normal only for nodes that may touch
    r = np.sqrt(squared)
    if r == 0.0:
        return -1.0
    normal[0] = r0 / r
    normal[1] = r1 / r
    normal[2] = r2 / r
    return params[9] - r


@nb.njit(fastmath=FASTMATH, cache=True)
def add_rigid_contact_forces(
    points: np.ndarray,
    time: float,
    node_ids: np.ndarray,
    stiffness: np.ndarray,
    offsets: np.ndarray,
    kinds: np.ndarray,
    params: np.ndarray,
    forces: np.ndarray,
    reaction: np.ndarray,
    penetration: np.ndarray,
) -> int:
    """Add the penalty forces of every target on its slave nodes to ``forces``.

    Args:
        points: (n_points, 3) current coordinates [m]; time: the current time [s] (moves the
            translating targets).
        node_ids, stiffness: (n_slaves,) slave node ids and penalty stiffness [N/m] of all
            targets, target k's slaves at ``offsets[k]:offsets[k + 1]``.
        kinds, params: (n_targets,) and (n_targets, N_TARGET_PARAMS), the packed targets (see
            ``RigidPlane.packed``, ``RigidCylinder.packed``).
        forces: (n_points, 3) nodal forces [N], added to in place.
        reaction: (n_targets, 3) out: the force the body exerts on each target [N].
        penetration: (n_targets,) out: the deepest penetration into each target [m] (0 when
            apart): the penalty's own compliance, which a displacement reading must remove.

    Returns:
        The number of slave nodes in contact.
    """
    normal = np.empty(3)
    reaction[:] = 0.0
    penetration[:] = 0.0
    n_active = 0
    for k in range(kinds.shape[0]):
        p = params[k]
        shift0 = p[11] * time
        shift1 = p[12] * time
        shift2 = p[13] * time
        for s in range(offsets[k], offsets[k + 1]):
            n = node_ids[s]
            g = _penetration(
                kinds[k],
                p,
                points[n, 0] - shift0,
                points[n, 1] - shift1,
                points[n, 2] - shift2,
                normal,
            )
            if g > 0.0:
                n_active += 1
                if g > penetration[k]:
                    penetration[k] = g
                for i in range(3):
                    fi = stiffness[s] * g * normal[i]
                    forces[n, i] += fi
                    reaction[k, i] -= fi
    return n_active


@nb.njit(cache=True, fastmath=FASTMATH)
def add_rigid_friction_forces(normal_force: np.ndarray, slip: np.ndarray, mu: float,
                              stiffness: np.ndarray, friction: np.ndarray,
                              out: np.ndarray) -> None:  # fmt: skip
    """Coulomb friction of rigid targets on their slaves, per slave row, added to ``out``
    (n_slaves, 3) [N]: the friction force ``friction`` (n_slaves, 3) [N] grows by ``stiffness``
    (n_slaves,) [N/m] times the tangential part of ``slip`` (n_slaves, 3) [m], the target's
    motion minus the slave's contact surface's over the step, and is capped at ``mu`` times
    the normal force ``normal_force`` (n_slaves, 3) [N] of :func:`add_rigid_contact_forces`
    (:func:`batball.contact.columns.coulomb_update`). A slave out of contact carries none."""
    for s in range(normal_force.shape[0]):
        size = np.sqrt(normal_force[s, 0] ** 2 + normal_force[s, 1] ** 2
                       + normal_force[s, 2] ** 2)  # fmt: skip
        if size == 0.0:
            friction[s, :] = 0.0
            continue
        coulomb_update(friction[s], normal_force[s, 0] / size, normal_force[s, 1] / size,
                       normal_force[s, 2] / size, slip[s, 0], slip[s, 1], slip[s, 2],
                       stiffness[s], mu * size)  # fmt: skip
        for k in range(3):
            out[s, k] += friction[s, k]


def segment_stiffness(
    points: np.ndarray,
    faces: np.ndarray,
    owner_volume: np.ndarray,
    bulk_modulus: np.ndarray,
    *,
    scale: float,
) -> np.ndarray:
    """SOFT = 0 segment stiffness k = scale * K A^2 / V, shape (n_faces,) [N/m].

    Args:
        points: (n_points, 3) [m]; faces: (n_faces, 4) boundary quads.
        owner_volume: (n_faces,) volume of each face's element [m^3].
        bulk_modulus: (n_faces,) bulk modulus of each face's element [Pa].
        scale: SLSFAC * SFS.
    """
    p = points[faces]
    area_vec = 0.5 * np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    area = np.linalg.norm(area_vec, axis=1)
    return scale * bulk_modulus * area**2 / owner_volume


def nodal_stiffness(
    faces: np.ndarray, face_stiffness: np.ndarray, node_ids: np.ndarray, n_points: int
) -> np.ndarray:
    """Mean stiffness of the segments around each node of ``node_ids``, shape (n_nodes,) [N/m]."""
    total = np.zeros(n_points)
    count = np.zeros(n_points)
    np.add.at(total, faces.ravel(), np.repeat(face_stiffness, 4))
    np.add.at(count, faces.ravel(), 1.0)
    return total[node_ids] / np.maximum(count[node_ids], 1.0)
