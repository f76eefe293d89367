"""Penalty contact of an inner shell of revolution's nodes against the outer shell's columns of
nodes: the explicit form of the insert-barrel gaps of :mod:`batball.contact.shell_contact`.

A double-wall bat's insert and barrel are revolved with the same angles, so each insert node
(slave) lies radially under one column of barrel nodes (master): the barrel's nodes at its angle,
ring after ring. The node touches the polyline through that column:

* Pairing: the column is fixed (the node's angle in the undeformed mesh,
  :func:`column_pairs`); along it the master point is the closest point of the segment between
  two neighbouring rings, x_m = (1 - s) x_a + s x_b, the segment re-found every cycle by
  walking from the last one (a node slides axially over the rings freely).
* Gap: along the master's normal at x_m, n = c x t / |c x t| with t = x_b - x_a (along the
  column) and c the chord between the neighbouring columns (j + 1 minus j - 1), interpolated
  between the two rings like x_m (on a circle that chord is the tangent at the node, so on a
  cylinder or cone n is the exact normal): g = (x_m - x) . n and the penetration
  p = t_s + t_m - g - offset (t the contact thicknesses, half the walls, the master's
  interpolated like x_m).
* Forces: the gradient of the penalty energy k p^2 / 2 over all the nodes that p depends on:
  -k p n on the slave and (1 - s, s) of +k p n on a and b, plus the small forces of the normal's
  turning (on a, b and the four neighbouring-column nodes) and of the closest point's motion
  along the column. The pair is then conservative: it does no net work over a closed cycle,
  and, p being unchanged by a rigid motion, it has no net force or moment (momentum and
  angular momentum about the pivot are kept). The unit tests check the forces against finite
  differences of the energy.
* Why this and not the alternatives tried (docs/notes/bbs.md, "Pre-stress length"): against the
  barrel's facets (:class:`batball.contact.segments.SegmentContact`) the insert's nodes sit
  under the facets' corners, where the penetration has a kink, and the full-size bat's
  pre-stress grew a local mode instead of settling, with the facets' normals or smoothed ones.
  A central spring between x and x_m (push along x_m - x) is conservative too, but it is a
  strut in compression: a sideways slip delta tilts the push by delta / L with the slip's sign,
  a negative stiffness -k p / L along the surface, and the frictionless insert turned away
  about the bat's axis (the relaxation's kinetic energy grew to 0.8 J). Pushing along the
  master's normal n (-k p n on the slave, (1 - s, s) of k p n on the master points, no turning
  forces) has no such stiffness but is not conservative (n follows the neighbours, which get
  no reaction): the full mesh's relaxation then stalled at 7.5e-3 J (kinetic-energy ratio 0.7)
  where the gradient form ends at 5e-5 J (ratio 0.008).
* Friction (optional, off by default; :meth:`ColumnContact.start_friction`): Coulomb, with the
  pair's penalty as the stick spring and the slip measured at the column's material point;
  not conservative, and acting a wall apart it carries a small moment (docs/notes/bbs.md).
"""

from __future__ import annotations

from dataclasses import InitVar, dataclass, field

import numba as nb
import numpy as np

from batball.numerics import FASTMATH

Vec3 = tuple[float, float, float]


def column_pairs(
    points: np.ndarray, slave_nodes: np.ndarray, master_rings: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each slave's master column (its angle's nearest), the ring below it along x and the
    weight of the ring above (the slave's x between the two, clipped to [0, 1]).

    Args:
        points: all nodes, (n_points, 3), m; the shells revolved about the x axis.
        slave_nodes: (n_slaves,).
        master_rings: (n_rings, n_around) master nodes ring by ring, x increasing along axis 0,
            angles 2 pi j / n_around along axis 1.

    Returns:
        column (n_slaves,), ring (n_slaves,) in [0, n_rings - 2], weight_b (n_slaves,).
    """
    n_around = master_rings.shape[1]
    column = np.rint(np.arctan2(points[slave_nodes, 2], points[slave_nodes, 1])
                     / (2.0 * np.pi) * n_around).astype(np.int64) % n_around  # fmt: skip
    ring_x = points[master_rings[:, 0], 0]
    x = points[slave_nodes, 0]
    ring = np.clip(np.searchsorted(ring_x, x, side="right") - 1, 0, ring_x.size - 2)
    weight_b = np.clip((x - ring_x[ring]) / (ring_x[ring + 1] - ring_x[ring]), 0.0, 1.0)
    return column, ring, weight_b


#: Segments a slave may walk along its column in one cycle.
MAX_WALK = 2


@nb.njit(inline="always", fastmath=FASTMATH)
def cross(u: Vec3, v: Vec3) -> Vec3:
    """u x v of two 3-tuples."""
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


@nb.njit(inline="always", fastmath=FASTMATH)
def point(points: np.ndarray, n: int) -> Vec3:
    """Node ``n``'s position as a 3-tuple (an unsigned row: no negative-index check)."""
    row = np.uint64(n)
    return points[row, 0], points[row, 1], points[row, 2]


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def column_penalty_forces(points: np.ndarray, slave_nodes: np.ndarray,
                          slave_thickness: np.ndarray, slave_stiffness: np.ndarray,
                          master_rings: np.ndarray, master_thickness: np.ndarray,
                          column: np.ndarray, ring: np.ndarray, gap_offset: np.ndarray,
                          weight_b: np.ndarray, slave_force: np.ndarray, tilt_force: np.ndarray,
                          penetration: np.ndarray) -> None:  # fmt: skip
    """Penalty forces of each slave's pair (module docs), written to the slave's own rows (no
    data race): ``ring`` (in and out), ``weight_b`` s, ``slave_force`` -k p n (n_slaves, 3) [N],
    ``tilt_force`` (n_slaves, 4, 3) [N]: k p dg/dt and k p dg/dc (the forces of the normal's
    turning: + on b and - on a; + on the right column and - on the left, shared 1 - s, s),
    then k p (dg/ds - dt_m/ds) ds/dx on the slave and ds/dx_b on b (a takes minus their sum:
    the closest point's own motion), ``penetration`` p [m]. ``master_thickness`` is indexed by
    node [m]. The vectors are tuples (an array per slave was a heap allocation)."""
    last, n_around = master_rings.shape[0] - 2, master_rings.shape[1]
    for n in nb.prange(slave_nodes.shape[0]):
        x = point(points, slave_nodes[n])
        j, r, s = column[n], ring[n], 0.0
        for _ in range(MAX_WALK + 1):
            xa, xb = point(points, master_rings[r, j]), point(points, master_rings[r + 1, j])
            t = (xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2])
            d = (x[0] - xa[0], x[1] - xa[1], x[2] - xa[2])
            s = (d[0] * t[0] + d[1] * t[1] + d[2] * t[2]) / (
                t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
            if s < 0.0 and r > 0:
                r -= 1
            elif s > 1.0 and r < last:
                r += 1
            else:
                break
        a, b = master_rings[r, j], master_rings[r + 1, j]
        inside = 0.0 < s < 1.0
        s = min(max(s, 0.0), 1.0)
        left, right = (j - 1) % n_around, (j + 1) % n_around
        xa, xb = point(points, a), point(points, b)
        ar, al = point(points, master_rings[r, right]), point(points, master_rings[r, left])
        br = point(points, master_rings[r + 1, right])
        bl = point(points, master_rings[r + 1, left])
        d = ((1.0 - s) * xa[0] + s * xb[0] - x[0], (1.0 - s) * xa[1] + s * xb[1] - x[1],
             (1.0 - s) * xa[2] + s * xb[2] - x[2])  # fmt: skip
        t = (xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2])
        chord_a = (ar[0] - al[0], ar[1] - al[1], ar[2] - al[2])
        chord_b = (br[0] - bl[0], br[1] - bl[1], br[2] - bl[2])
        c = ((1.0 - s) * chord_a[0] + s * chord_b[0], (1.0 - s) * chord_a[1] + s * chord_b[1],
             (1.0 - s) * chord_a[2] + s * chord_b[2])  # fmt: skip
        m = cross(c, t)  # around x along: outward
        size = np.sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2])
        gap = (d[0] * m[0] + d[1] * m[1] + d[2] * m[2]) / size
        reach = slave_thickness[n] + (1.0 - s) * master_thickness[a] + s * master_thickness[b]
        p = max(reach - gap - gap_offset[n], 0.0)
        ring[n], weight_b[n], penetration[n] = r, s, p
        f = slave_stiffness[n] * p
        # q = dg/dm: d's part across n, over |m|
        q = ((d[0] - gap * m[0] / size) / size, (d[1] - gap * m[1] / size) / size,
             (d[2] - gap * m[2] / size) / size)  # fmt: skip
        for k in range(3):
            slave_force[n, k] = -f * m[k] / size
        along = cross(q, c)
        around = cross(t, q)
        for k in range(3):
            tilt_force[n, 0, k] = f * along[k]
            tilt_force[n, 1, k] = f * around[k]
        # s moves with the nodes (the closest point): d(x_m)/ds = t is across n, but the
        # chord and the master's thickness interpolate in s, so dp/ds = dt_m - (t x q).dc/ds
        slide = 0.0
        if inside:
            slide = f * (around[0] * (chord_b[0] - chord_a[0])
                         + around[1] * (chord_b[1] - chord_a[1])
                         + around[2] * (chord_b[2] - chord_a[2])
                         - (master_thickness[b] - master_thickness[a]))  # fmt: skip
        length2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2]
        for k in range(3):  # ds/dx = t / |t|^2, ds/dx_b = (x - x_a - 2 s t) / |t|^2
            tilt_force[n, 2, k] = slide * t[k] / length2
            tilt_force[n, 3, k] = slide * (x[k] - xa[k] - 2.0 * s * t[k]) / length2


@nb.njit(inline="always")
def pushes(force: np.ndarray, n: int) -> bool:
    """Whether slave n's force (a row of ``force``, (n_slaves, 3)) is not exactly zero (a NaN
    is not): only then has its pair forces to add. A slave without one (its pair open: the
    penalty, hence every force of :func:`column_penalty_forces`, is zero) would add only zeros,
    which change no sum (at most a -0 to +0; the coupled solver's sums start at +0 and never
    reach -0), so the scatters skip it."""
    return force[n, 0] != 0.0 or force[n, 1] != 0.0 or force[n, 2] != 0.0


@nb.njit(cache=True)
def scatter_turning_forces(master_rings: np.ndarray, column: np.ndarray, ring: np.ndarray,
                           weight_b: np.ndarray, slave_nodes: np.ndarray, slave_force: np.ndarray,
                           tilt_force: np.ndarray, forces: np.ndarray) -> None:  # fmt: skip
    """Add the forces of the normal's turning and of the closest point's motion
    (``tilt_force``, :func:`column_penalty_forces`) to ``forces`` (n_points, 3) in one serial
    pass, for the slaves that push (``slave_force``, :func:`pushes`); the push itself is added
    by :func:`scatter_column_shares`."""
    n_around = master_rings.shape[1]
    for n in range(slave_nodes.shape[0]):
        if not pushes(slave_force, n):
            continue
        r, j, s = ring[n], column[n], weight_b[n]
        left, right = (j - 1) % n_around, (j + 1) % n_around
        # the nodes as unsigned rows: no negative-index check on each access
        slave = np.uint64(slave_nodes[n])
        a, b = np.uint64(master_rings[r, j]), np.uint64(master_rings[r + 1, j])
        a_right, a_left = np.uint64(master_rings[r, right]), np.uint64(master_rings[r, left])
        b_right = np.uint64(master_rings[r + 1, right])
        b_left = np.uint64(master_rings[r + 1, left])
        for k in range(3):
            along, around = tilt_force[n, 0, k], tilt_force[n, 1, k]
            on_slave, on_b = tilt_force[n, 2, k], tilt_force[n, 3, k]
            forces[slave, k] += on_slave
            forces[a, k] += -along - on_slave - on_b
            forces[b, k] += along + on_b
            forces[a_right, k] += (1.0 - s) * around
            forces[a_left, k] -= (1.0 - s) * around
            forces[b_right, k] += s * around
            forces[b_left, k] -= s * around


@nb.njit(cache=True, fastmath=FASTMATH)
def coulomb_update(force: np.ndarray, m0: float, m1: float, m2: float, d0: float, d1: float,
                   d2: float, stiffness: float, limit: float) -> None:  # fmt: skip
    """One step of penalty Coulomb friction, in place on a pair's friction force (3,) [N]: the
    old force turned into the tangent plane of the unit normal m, plus ``stiffness`` [N/m]
    times the tangential part of the slip d [m] over the step, capped at ``limit`` [N]
    (mu times the normal force): a radial return."""
    along = d0 * m0 + d1 * m1 + d2 * m2
    old = force[0] * m0 + force[1] * m1 + force[2] * m2
    f0 = force[0] - old * m0 + stiffness * (d0 - along * m0)
    f1 = force[1] - old * m1 + stiffness * (d1 - along * m1)
    f2 = force[2] - old * m2 + stiffness * (d2 - along * m2)
    size = np.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
    scale = min(1.0, limit / size) if size > 0.0 else 1.0
    force[0], force[1], force[2] = f0 * scale, f1 * scale, f2 * scale


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def column_friction_forces(points: np.ndarray, slave_nodes: np.ndarray, master_rings: np.ndarray,
                           column: np.ndarray, ring: np.ndarray, weight_b: np.ndarray,
                           slave_force: np.ndarray, penetration: np.ndarray, mu: float,
                           stiffness: np.ndarray, last_relative: np.ndarray,
                           last_pair: np.ndarray, friction_force: np.ndarray,
                           rotation_step: np.ndarray, slave_thickness: np.ndarray,
                           master_thickness: np.ndarray, arms: np.ndarray) -> None:  # fmt: skip
    """Coulomb friction on each touching pair (:class:`ColumnContact`), per slave row: the
    friction force on the slave, (n_slaves, 3) [N], grows by ``stiffness`` times the tangential
    part of the slip of the two contact surfaces since the last call (the old force turned into
    the new tangent plane), capped at ``mu`` times the normal force. The slip is the change of
    x_m - x at the column's material point of the last call (``last_pair``: its ring and s,
    (n_slaves, 2)), not at the closest point, which follows the slave along the column, plus
    the nodes' rotations over the step (``rotation_step``, (n_points, 3) [rad]) times the
    faces' offsets from the mid-surfaces: -(t_m dtheta_m + t_s dtheta_s) x m, with m the unit
    normal towards the master and t_s, t_m the contact thicknesses scaled to share the
    mid-surfaces' distance (x_m - x) . m, the penalty's overlap split in the walls' proportion
    (a wall bending under the other slides its face over it even where the mid-surfaces keep
    step; a rigid turn of both slides nothing). ``last_relative``
    (n_slaves, 3) [m] and ``last_pair`` then take the new closest point; ``arms`` (n_slaves, 2)
    receives t_s and t_m (the friction's lever arms about the slave and the column point). A
    free pair carries none."""
    for n in nb.prange(slave_nodes.shape[0]):
        a = master_rings[ring[n], column[n]]
        b = master_rings[ring[n] + 1, column[n]]
        s = weight_b[n]
        x = point(points, slave_nodes[n])
        old_ring, old_s = int(last_pair[n, 0]), last_pair[n, 1]
        a_then = master_rings[old_ring, column[n]]
        b_then = master_rings[old_ring + 1, column[n]]
        xa, xb = point(points, a), point(points, b)
        ya, yb = point(points, a_then), point(points, b_then)
        rel = ((1.0 - s) * xa[0] + s * xb[0] - x[0], (1.0 - s) * xa[1] + s * xb[1] - x[1],
               (1.0 - s) * xa[2] + s * xb[2] - x[2])  # fmt: skip
        then = ((1.0 - old_s) * ya[0] + old_s * yb[0] - x[0],
                (1.0 - old_s) * ya[1] + old_s * yb[1] - x[1],
                (1.0 - old_s) * ya[2] + old_s * yb[2] - x[2])  # fmt: skip
        last_pair[n, 0], last_pair[n, 1] = ring[n], s
        normal_force = np.sqrt(slave_force[n, 0] ** 2 + slave_force[n, 1] ** 2
                               + slave_force[n, 2] ** 2)  # fmt: skip
        if penetration[n] <= 0.0 or normal_force == 0.0:
            for k in range(3):
                friction_force[n, k] = 0.0
                last_relative[n, k] = rel[k]
            continue
        m0 = -slave_force[n, 0] / normal_force  # towards the master
        m1 = -slave_force[n, 1] / normal_force
        m2 = -slave_force[n, 2] / normal_force
        # the faces meet inside the penalty's overlap: the arms share the mid-surfaces'
        # distance along m in the walls' proportion (a rigid turn then slides nothing)
        t_s = slave_thickness[n]
        t_m = (1.0 - s) * master_thickness[a] + s * master_thickness[b]
        share = (rel[0] * m0 + rel[1] * m1 + rel[2] * m2) / (t_s + t_m)
        t_s, t_m = share * t_s, share * t_m
        arms[n, 0], arms[n, 1] = t_s, t_m
        ta, tb = point(rotation_step, a), point(rotation_step, b)
        tn = point(rotation_step, slave_nodes[n])
        w = (t_m * ((1.0 - s) * ta[0] + s * tb[0]) + t_s * tn[0],
             t_m * ((1.0 - s) * ta[1] + s * tb[1]) + t_s * tn[1],
             t_m * ((1.0 - s) * ta[2] + s * tb[2]) + t_s * tn[2])  # t_m dtheta_m + t_s dtheta_s
        d0 = then[0] - last_relative[n, 0] - (w[1] * m2 - w[2] * m1)
        d1 = then[1] - last_relative[n, 1] - (w[2] * m0 - w[0] * m2)
        d2 = then[2] - last_relative[n, 2] - (w[0] * m1 - w[1] * m0)
        coulomb_update(friction_force[n], m0, m1, m2, d0, d1, d2, stiffness[n],
                       mu * normal_force)  # fmt: skip
        for k in range(3):
            last_relative[n, k] = rel[k]


@nb.njit(cache=True)
def scatter_friction_moments(slave_nodes: np.ndarray, master_rings: np.ndarray,
                             column: np.ndarray, ring: np.ndarray, weight_b: np.ndarray,
                             slave_force: np.ndarray, friction_force: np.ndarray,
                             arms: np.ndarray, moments: np.ndarray) -> None:  # fmt: skip
    """Add the friction's moments about the nodes, (n_points, 3) [N m]: the force f on the
    slave acts at its face t_s m off the mid-surface, (t_s m) x f; its opposite acts on the
    master's face -t_m m off the column point, (t_m m) x f shared (1 - s, s) on a and b."""
    for n in range(slave_nodes.shape[0]):
        size = np.sqrt(slave_force[n, 0] ** 2 + slave_force[n, 1] ** 2 + slave_force[n, 2] ** 2)
        if size == 0.0:
            continue
        m = (-slave_force[n, 0] / size, -slave_force[n, 1] / size, -slave_force[n, 2] / size)
        torque = cross(m, point(friction_force, n))
        a, b = master_rings[ring[n], column[n]], master_rings[ring[n] + 1, column[n]]
        for k in range(3):
            moments[slave_nodes[n], k] += arms[n, 0] * torque[k]
            moments[a, k] += (1.0 - weight_b[n]) * arms[n, 1] * torque[k]
            moments[b, k] += weight_b[n] * arms[n, 1] * torque[k]


@nb.njit(cache=True)
def scatter_column_shares(slave_nodes: np.ndarray, master_rings: np.ndarray, column: np.ndarray,
                          ring: np.ndarray, weight_b: np.ndarray, slave_force: np.ndarray,
                          forces: np.ndarray) -> None:  # fmt: skip
    """Add a force on each slave and its opposite, shared (1 - s, s), on its column's point
    (the slaves with none skipped: :func:`pushes`)."""
    for n in range(slave_nodes.shape[0]):
        if not pushes(slave_force, n):
            continue
        slave = np.uint64(slave_nodes[n])  # unsigned rows: no negative-index checks
        a = np.uint64(master_rings[ring[n], column[n]])
        b = np.uint64(master_rings[ring[n] + 1, column[n]])
        for k in range(3):
            forces[slave, k] += slave_force[n, k]
            forces[a, k] -= (1.0 - weight_b[n]) * slave_force[n, k]
            forces[b, k] -= weight_b[n] * slave_force[n, k]


@dataclass
class ColumnContact:
    """Inner shell's nodes (slaves) against the outer shell's node columns (module docs); the
    same calls as :class:`batball.contact.segments.SegmentContact` in the coupled solver.

    Attributes:
        name: label for histories and messages.
        slave_nodes: (n_slaves,); slave_thickness: (n_slaves,) [m]; slave_stiffness:
            (n_slaves,) [N/m].
        master_rings: (n_rings, n_around) the master's nodes ring by ring (x increasing, angle
            2 pi j / n_around); master_thickness: (n_points,) contact thickness by node [m].
        gap_offset: (n_slaves,) initial overlap ignored [m].
        points: (n_points, 3) the undeformed nodes [m], which pair each slave with its column.
        friction: Coulomb coefficient (0: frictionless); the stick spring is each pair's
            normal penalty. Friction is not conservative; it is off unless set
            (:meth:`start_friction`). It acts at the two contact faces: set ``rotation_step``
            (n_points, 3), the nodes' rotations over the last step [rad], before each
            :meth:`add_forces` so that the faces' slip includes the walls' rotations, and add
            ``moments`` (n_points, 3) [N m], the friction's moments about the nodes that
            :meth:`add_forces` leaves there, to the nodes' rotational forces. Without
            rotations the slip is the mid-surfaces' (the friction then misses the faces'
            sliding in bending).
    """

    name: str
    slave_nodes: np.ndarray
    slave_thickness: np.ndarray
    slave_stiffness: np.ndarray
    master_rings: np.ndarray
    master_thickness: np.ndarray
    points: InitVar[np.ndarray]
    gap_offset: np.ndarray = field(default_factory=lambda: np.zeros(0))
    friction: float = 0.0

    def __post_init__(self, points: np.ndarray) -> None:
        n = self.slave_nodes.size
        if self.gap_offset.size != n:
            self.gap_offset = np.zeros(n)
        self.column, self.ring, self.weight_b = column_pairs(points, self.slave_nodes,
                                                             self.master_rings)  # fmt: skip
        self.slave_force = np.zeros((n, 3))
        self.tilt_force = np.zeros((n, 4, 3))
        self.penetration = np.zeros(n)
        self.friction_force = np.zeros((n, 3))
        self.last_relative = np.zeros((n, 3))
        self.last_pair = np.column_stack([self.ring, self.weight_b]).astype(float)
        self.arms = np.zeros((n, 2))
        n_points = points.shape[0]
        self.no_rotation = np.zeros((n_points, 3))
        self.rotation_step: np.ndarray | None = None
        self.moments = np.zeros((n_points, 3))

    def search(self, points: np.ndarray) -> None:
        """Nothing to search: each slave walks along its column in :meth:`add_forces`."""

    def add_forces(self, points: np.ndarray, forces: np.ndarray) -> int:
        """Add this contact's forces to ``forces`` (n_points, 3) [N]; returns slaves touching."""
        column_penalty_forces(points, self.slave_nodes, self.slave_thickness,
                              self.slave_stiffness, self.master_rings, self.master_thickness,
                              self.column, self.ring, self.gap_offset, self.weight_b,
                              self.slave_force, self.tilt_force, self.penetration)  # fmt: skip
        scatter_column_shares(self.slave_nodes, self.master_rings, self.column, self.ring,
                              self.weight_b, self.slave_force, forces)  # fmt: skip
        scatter_turning_forces(self.master_rings, self.column, self.ring, self.weight_b,
                               self.slave_nodes, self.slave_force, self.tilt_force,
                               forces)  # fmt: skip
        if self.friction > 0.0:
            spin = self.rotation_step if self.rotation_step is not None else self.no_rotation
            column_friction_forces(points, self.slave_nodes, self.master_rings, self.column,
                                   self.ring, self.weight_b, self.slave_force, self.penetration,
                                   self.friction, self.slave_stiffness, self.last_relative,
                                   self.last_pair, self.friction_force, spin,
                                   self.slave_thickness, self.master_thickness,
                                   self.arms)  # fmt: skip
            scatter_column_shares(self.slave_nodes, self.master_rings, self.column, self.ring,
                                  self.weight_b, self.friction_force, forces)  # fmt: skip
            self.moments[:] = 0.0
            scatter_friction_moments(self.slave_nodes, self.master_rings, self.column,
                                     self.ring, self.weight_b, self.slave_force,
                                     self.friction_force, self.arms, self.moments)  # fmt: skip
        return int(np.count_nonzero(self.penetration > 0.0))

    def start_friction(self, friction: float, points: np.ndarray) -> None:
        """Turn Coulomb friction ``friction`` on from the state ``points`` (no force yet)."""
        self.friction = friction
        self.friction_force[:] = 0.0
        self.add_forces(points, np.zeros_like(points))  # sets the pairs and their x_m - x
        self.friction_force[:] = 0.0

    def initial_overlap(self, points: np.ndarray) -> np.ndarray:
        """Each slave's penetration in ``points`` with no offset, (n_slaves,) [m]."""
        saved = self.gap_offset
        self.gap_offset = np.zeros_like(saved)
        self.add_forces(points, np.zeros_like(points))
        self.gap_offset = saved
        return self.penetration.copy()
