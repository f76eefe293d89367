"""Penalty contact of nodes against deformable quad segments (shells or solid faces), with a
bucket search.

The ball-bat contact of the batted-ball-speed test (LS-DYNA ``*CONTACT_AUTOMATIC_SURFACE_TO_
SURFACE`` run both ways: the ball's surface nodes against the bat's shells, and the bat's nodes
against the ball's surface quads) and the insert-barrel contact of the double-wall bat use it.
docs/physics.md section 6.6.

* Search: every master segment's bounding box, grown by the contact thickness and a margin, is
  binned into a uniform grid of buckets (cell size about the largest box); each slave node looks
  in its own bucket and keeps the segments whose box holds it (a node outside the hull of all
  the boxes is not looked up). The search costs O(n_slaves + n_segments), runs as one compiled
  pass and is repeated every few cycles; the margin covers the travel in between.
* Projection: a slave node x is projected on a segment's plane (centroid c, unit normal n from
  the diagonals); its bilinear coordinates (xi, eta) come from two Newton steps in the plane. It
  touches the segment when |xi|, |eta| <= 1 + a small tolerance (neighbouring segments overlap a
  little, so no node falls between two).
* Gap: d = (x - c) . n. A shell segment is two-sided: the penetration is t_s + t_m - |d|, pushing
  along sign(d) n (t_s, t_m the slave and master contact thicknesses, the shells' half
  thicknesses). A solid face is one-sided: penetration t_s + t_m - d for -depth < d, along n
  (outward). Each slave takes the segment with the deepest penetration; the penetration needs
  only d, so a candidate that cannot beat the deepest so far is never projected, and a
  projection whose first Newton step lands plainly off the quad stops there (the contact cost
  of the full-size BBS run was dominated by projections of candidates that were then dropped).
* Smoothing (optional, the insert-barrel pair): the push is along the master's nodal normals
  interpolated at the contact point; the penetration is still the segment's. The segment's
  share is put where the line through the slave along that normal meets the segment, so the
  pair still has no moment.
* Force: f = k p on the slave node, -f N_a(xi, eta) on the segment's four nodes (equal and
  opposite, so the pair conserves momentum; the weights are not clipped at the edge tolerance,
  so sum N_a x_a is the projected point and the pair, acting along n, has no moment: angular
  momentum is conserved too). The slave loop runs in parallel and writes its own
  rows only; the master forces are added afterwards in one serial pass over the touching slaves:
  no data race.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numba as nb
import numpy as np

from batball.numerics import FASTMATH

#: Tolerance on |xi|, |eta| beyond 1 when a node is taken as over a segment.
EDGE_TOLERANCE = 0.02
#: Most candidate segments kept per slave node.
MAX_CANDIDATES = 24
#: Candidate checks of one force pass below which it runs on one thread
#: (:func:`slave_penalties`; the search is one serial pass).
PARALLEL_MIN_WORK = 200_000
#: Slaves a task of :func:`slave_penalty_forces`' parallel loop.
PENALTY_BLOCK = 64


@nb.njit(cache=True, fastmath=FASTMATH)
def segment_boxes(points: np.ndarray, segments: np.ndarray, grow: np.ndarray) -> np.ndarray:
    """Bounding boxes (lo xyz, hi xyz) of each segment grown by ``grow``, (n_segments, 6) [m]."""
    boxes = np.empty((segments.shape[0], 6))
    for s in range(segments.shape[0]):
        for k in range(3):
            lo = points[segments[s, 0], k]
            hi = lo
            for a in range(1, 4):
                value = points[segments[s, a], k]
                lo = min(lo, value)
                hi = max(hi, value)
            boxes[s, k] = lo - grow[s]
            boxes[s, 3 + k] = hi + grow[s]
    return boxes


@nb.njit(cache=True)
def bucket_grid(boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
    """The grid of buckets over the boxes (n_boxes >= 1, (lo xyz, hi xyz) rows): the lowest
    corner of the boxes, their highest, the buckets' side (the largest box side, enlarged to
    cover the boxes in at most 256 buckets an axis) and the buckets along each axis."""
    origin, top = boxes[0, :3].copy(), boxes[0, 3:].copy()
    size = boxes[0, 3] - boxes[0, 0]
    for s in range(boxes.shape[0]):
        for k in range(3):
            origin[k] = min(origin[k], boxes[s, k])
            top[k] = max(top[k], boxes[s, 3 + k])
            size = max(size, boxes[s, 3 + k] - boxes[s, k])
    dims = np.empty(3, dtype=np.int64)
    for k in range(3):
        dims[k] = max(1, min(int(np.ceil((top[k] - origin[k]) / size)), 256))
    widest = size
    for k in range(3):
        widest = max(widest, (top[k] - origin[k]) / dims[k])
    return origin, top, widest, dims


@nb.njit(inline="always")
def bucket_at(value: float, origin: float, size: float, dim: int) -> int:
    """The bucket along one axis that holds ``value`` (clamped to the grid)."""
    return min(max(int(np.floor((value - origin) / size)), 0), dim - 1)


@nb.njit(cache=True)
def fill_buckets(boxes: np.ndarray, origin: np.ndarray, size: float,
                 dims: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """CSR map bucket -> segments whose box overlaps it, each bucket's in segment order (a
    count, then a fill; each box's range of buckets found once)."""
    n_buckets = dims[0] * dims[1] * dims[2]
    ranges = np.empty((boxes.shape[0], 6), dtype=np.int64)
    counts = np.zeros(n_buckets + 1, dtype=np.int64)
    for s in range(boxes.shape[0]):
        for k in range(3):
            ranges[s, k] = bucket_at(boxes[s, k], origin[k], size, dims[k])
            ranges[s, 3 + k] = bucket_at(boxes[s, 3 + k], origin[k], size, dims[k])
        for i in range(ranges[s, 0], ranges[s, 3] + 1):
            for j in range(ranges[s, 1], ranges[s, 4] + 1):
                for m in range(ranges[s, 2], ranges[s, 5] + 1):
                    counts[(i * dims[1] + j) * dims[2] + m + 1] += 1
    for b in range(n_buckets):
        counts[b + 1] += counts[b]
    entries = np.empty(counts[n_buckets], dtype=np.int64)
    cursor = counts[:-1].copy()
    for s in range(boxes.shape[0]):
        for i in range(ranges[s, 0], ranges[s, 3] + 1):
            for j in range(ranges[s, 1], ranges[s, 4] + 1):
                for m in range(ranges[s, 2], ranges[s, 5] + 1):
                    b = (i * dims[1] + j) * dims[2] + m
                    entries[cursor[b]] = s
                    cursor[b] += 1
    return counts, entries


@nb.njit(cache=True)
def search_candidates(points: np.ndarray, slave_nodes: np.ndarray, segments: np.ndarray,
                      grow: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """Candidate segments of every slave node by the bucket search (module docs), in one
    compiled pass (the search's NumPy steps between compiled ones had cost more than the
    search itself).

    Args:
        points: (n_points, 3) current coordinates of every node [m].
        slave_nodes: (n_slaves,) node ids; segments: (n_segments, 4) node ids.
        grow: (n_segments,) growth of each box: contact thicknesses plus the search margin [m].

    Returns:
        candidates (n_slaves, MAX_CANDIDATES) segment ids (each slave's first n_candidates, in
        segment order), n_candidates (n_slaves,), and the segments that are some slave's
        candidate (sorted).
    """
    candidates = np.zeros((slave_nodes.size, MAX_CANDIDATES), dtype=np.int64)
    n_candidates = np.zeros(slave_nodes.size, dtype=np.int64)
    taken = np.zeros(segments.shape[0], dtype=np.bool_)
    if segments.shape[0] == 0:
        return candidates, n_candidates, np.flatnonzero(taken)
    boxes = segment_boxes(points, segments, grow)
    origin, top, size, dims = bucket_grid(boxes)
    offsets, entries = fill_buckets(boxes, origin, size, dims)
    for n in range(slave_nodes.size):
        x = points[slave_nodes[n]]
        # outside the boxes' hull no box holds the node (a NaN goes on, as before)
        if (x[0] < origin[0] or x[1] < origin[1] or x[2] < origin[2]
                or x[0] > top[0] or x[1] > top[1] or x[2] > top[2]):  # fmt: skip
            continue
        b = 0
        for k in range(3):
            b = b * dims[k] + bucket_at(x[k], origin[k], size, dims[k])
        count = 0
        for e in range(offsets[b], offsets[b + 1]):
            s = entries[e]
            inside = True
            for k in range(3):
                if x[k] < boxes[s, k] or x[k] > boxes[s, 3 + k]:
                    inside = False
            if inside and count < MAX_CANDIDATES:
                candidates[n, count] = s
                taken[s] = True
                count += 1
        n_candidates[n] = count
    return candidates, n_candidates, np.flatnonzero(taken)


@nb.njit(cache=True, fastmath=FASTMATH)
def segment_planes(points: np.ndarray, segments: np.ndarray, active: np.ndarray,
                   planes: np.ndarray) -> None:  # fmt: skip
    """Centroid and unit normal (from the diagonals, right-hand rule) of each ``active`` segment
    into ``planes`` (n_segments, 6) [m, -]; computed once per segment and cycle rather than once
    per candidate (a node has about 9 candidates on the insert-barrel contact)."""
    for i in range(active.shape[0]):
        s = active[i]
        c0, c1, c2, c3 = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3]
        a0, a1, a2 = (points[c2, 0] - points[c0, 0], points[c2, 1] - points[c0, 1],
                      points[c2, 2] - points[c0, 2])  # fmt: skip
        b0, b1, b2 = (points[c3, 0] - points[c1, 0], points[c3, 1] - points[c1, 1],
                      points[c3, 2] - points[c1, 2])  # fmt: skip
        n0, n1, n2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
        norm = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        for k in range(3):
            planes[s, k] = 0.25 * (points[c0, k] + points[c1, k] + points[c2, k] + points[c3, k])
        planes[s, 3], planes[s, 4], planes[s, 5] = n0 / norm, n1 / norm, n2 / norm


@nb.njit(cache=True, fastmath=FASTMATH)
def nodal_normals(segments: np.ndarray, nodes: np.ndarray, planes: np.ndarray,
                  normals: np.ndarray) -> None:  # fmt: skip
    """Unit normal at each of ``nodes`` (the distinct nodes of ``segments``), the normalised sum
    of the normals of its segments (``planes`` of every segment), into ``normals`` (n_points,
    3). The segments must be oriented alike (a shell mesh's cells are)."""
    for n in nodes:
        normals[n, 0] = 0.0
        normals[n, 1] = 0.0
        normals[n, 2] = 0.0
    for s in range(segments.shape[0]):
        for a in range(4):
            for k in range(3):
                normals[segments[s, a], k] += planes[s, 3 + k]
    for n in nodes:
        norm = np.sqrt(normals[n, 0] ** 2 + normals[n, 1] ** 2 + normals[n, 2] ** 2)
        for k in range(3):
            normals[n, k] /= norm


#: |xi| or |eta| after the first Newton step beyond which a node is plainly off the segment
#: (that step is exact on a parallelogram), so the last two steps are skipped.
PLAINLY_OFF = 3.0


@nb.njit(inline="always", fastmath=FASTMATH)
def segment_coordinates(
    x: tuple[float, float, float], c: np.ndarray, d: float, n0: float, n1: float, n2: float,
    scratch: np.ndarray,
) -> tuple[float, float]:  # fmt: skip
    """(xi, eta): bilinear coordinates of the projection x - d n of x (a 3-tuple) on the quad
    ``c`` (4, 3), by three Newton steps in the tangent plane (one when the first lands plainly
    off the quad). ``scratch`` (3, 3) is work space, so the contact loop allocates nothing."""
    xi, eta = 0.0, 0.0
    g_xi, g_eta, res = scratch[0], scratch[1], scratch[2]
    for it in range(3):  # Newton on x - d n = sum N_a(xi, eta) x_a in the tangent plane
        for k in range(3):
            g_xi[k] = 0.25 * ((c[1, k] - c[0, k]) * (1 - eta) + (c[2, k] - c[3, k]) * (1 + eta))
            g_eta[k] = 0.25 * ((c[3, k] - c[0, k]) * (1 - xi) + (c[2, k] - c[1, k]) * (1 + xi))
            mapped = 0.25 * (
                c[0, k] * (1 - xi) * (1 - eta)
                + c[1, k] * (1 + xi) * (1 - eta)
                + c[2, k] * (1 + xi) * (1 + eta)
                + c[3, k] * (1 - xi) * (1 + eta)
            )
            res[k] = x[k] - mapped
        res[0] -= d * n0
        res[1] -= d * n1
        res[2] -= d * n2
        a11 = g_xi[0] * g_xi[0] + g_xi[1] * g_xi[1] + g_xi[2] * g_xi[2]
        a12 = g_xi[0] * g_eta[0] + g_xi[1] * g_eta[1] + g_xi[2] * g_eta[2]
        a22 = g_eta[0] * g_eta[0] + g_eta[1] * g_eta[1] + g_eta[2] * g_eta[2]
        q1 = g_xi[0] * res[0] + g_xi[1] * res[1] + g_xi[2] * res[2]
        q2 = g_eta[0] * res[0] + g_eta[1] * res[1] + g_eta[2] * res[2]
        det = a11 * a22 - a12 * a12
        xi += (a22 * q1 - a12 * q2) / det
        eta += (a11 * q2 - a12 * q1) / det
        if it == 0 and (abs(xi) > PLAINLY_OFF or abs(eta) > PLAINLY_OFF):
            break
    return xi, eta


@nb.njit(inline="always", fastmath=FASTMATH)
def bilinear_weights(xi: float, eta: float) -> tuple[float, float, float, float]:
    """The quad's shape functions N_1..N_4 at (xi, eta)."""
    return (0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta),
            0.25 * (1 + xi) * (1 + eta), 0.25 * (1 - xi) * (1 + eta))  # fmt: skip


@nb.njit(inline="always", fastmath=FASTMATH)
def smoothed_normal(node_normals: np.ndarray, corners: np.ndarray, xi: float, eta: float,
                    facet: np.ndarray) -> tuple[float, float, float]:  # fmt: skip
    """The nodal normals of a segment's ``corners`` interpolated at (xi, eta), normalised and
    turned to the side of ``facet`` (the segment's normal, signed towards the slave)."""
    w = bilinear_weights(xi, eta)
    o0, o1, o2 = 0.0, 0.0, 0.0
    for a in range(4):
        o0 += w[a] * node_normals[corners[a], 0]
        o1 += w[a] * node_normals[corners[a], 1]
        o2 += w[a] * node_normals[corners[a], 2]
    norm = np.sqrt(o0 * o0 + o1 * o1 + o2 * o2)
    side = 1.0 if o0 * facet[0] + o1 * facet[1] + o2 * facet[2] >= 0.0 else -1.0
    return o0 * (side / norm), o1 * (side / norm), o2 * (side / norm)


@nb.njit(cache=True, fastmath=FASTMATH)
def slave_penalties(first: int, stop: int, points: np.ndarray, slave_nodes: np.ndarray,
                     slave_thickness: np.ndarray, slave_stiffness: np.ndarray,
                     segments: np.ndarray, segment_thickness: np.ndarray, two_sided: bool,
                     depth: float, gap_offset: np.ndarray, candidates: np.ndarray,
                     n_candidates: np.ndarray, planes: np.ndarray, node_normals: np.ndarray,
                     slave_force: np.ndarray, contact_segment: np.ndarray, weights: np.ndarray,
                     penetration: np.ndarray) -> None:  # fmt: skip
    """Slaves ``first`` to ``stop`` - 1 of :func:`slave_penalty_forces`, one after the other on
    this thread, their scratch made once: the parallel kernel's tasks, and the whole pass where
    it is too small to wake the other threads for (``PARALLEL_MIN_WORK``; setting Numba's
    thread count to one and back around the parallel kernel instead cost 40-45 us a cycle of
    the full-size BBS test on two threads). A call, not inlined: inlined into a loop over the
    slaves, its array arguments were reference-counted once a slave (190 ns a slave of that
    test's bat contact, most of which have no candidate)."""
    corners, scratch, bn = np.empty((4, 3)), np.empty((3, 3)), np.empty(3)
    for n in range(first, stop):
        node = slave_nodes[n]
        x = (points[node, 0], points[node, 1], points[node, 2])  # a view would be refcounted
        best, best_p, bxi, beta, bd = -1, 0.0, 0.0, 0.0, 0.0
        bn[0] = bn[1] = bn[2] = 0.0
        for c in range(n_candidates[n]):
            s = candidates[n, c]
            n0, n1, n2 = planes[s, 3], planes[s, 4], planes[s, 5]
            d = (x[0] - planes[s, 0]) * n0 + (x[1] - planes[s, 1]) * n1 + (x[2] - planes[s, 2]) * n2
            reach = slave_thickness[n] + segment_thickness[s]
            if two_sided:
                sign = 1.0 if d >= 0.0 else -1.0
                p = reach - abs(d) - gap_offset[n]
            else:
                if d < -depth:
                    continue
                sign = 1.0
                p = reach - d - gap_offset[n]
            if p <= best_p:  # cannot be taken, wherever x projects: skip the projection
                continue
            for a in range(4):
                corners[a] = points[segments[s, a]]
            xi, eta = segment_coordinates(x, corners, d, n0, n1, n2, scratch)
            if abs(xi) > 1.0 + EDGE_TOLERANCE or abs(eta) > 1.0 + EDGE_TOLERANCE:
                continue
            best, best_p, bxi, beta, bd = s, p, xi, eta, sign * d
            bn[0], bn[1], bn[2] = sign * n0, sign * n1, sign * n2
        if best >= 0 and node_normals.shape[0] > 0:
            # push along the smoothed normal, and put the segment's share on the point where
            # that line meets the segment (x - t n_s), so that the pair has no moment
            s0, s1, s2 = smoothed_normal(node_normals, segments[best], bxi, beta, bn)
            t = bd / (s0 * bn[0] + s1 * bn[1] + s2 * bn[2])
            for a in range(4):
                corners[a] = points[segments[best, a]]
            bxi, beta = segment_coordinates(x, corners, t, s0, s1, s2, scratch)
            bn[0], bn[1], bn[2] = s0, s1, s2
        contact_segment[n] = best
        penetration[n] = best_p
        f = slave_stiffness[n] * best_p
        for k in range(3):
            slave_force[n, k] = f * bn[k] if best >= 0 else 0.0
        xi, eta = bxi, beta  # unclipped: sum N_a x_a is the contact point, so no spurious torque
        w = bilinear_weights(xi, eta)
        for a in range(4):
            weights[n, a] = w[a]


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def slave_penalty_forces(points: np.ndarray, slave_nodes: np.ndarray, slave_thickness: np.ndarray,
                         slave_stiffness: np.ndarray, segments: np.ndarray,
                         segment_thickness: np.ndarray, two_sided: bool, depth: float,
                         gap_offset: np.ndarray, candidates: np.ndarray,
                         n_candidates: np.ndarray, planes: np.ndarray, node_normals: np.ndarray,
                         slave_force: np.ndarray, contact_segment: np.ndarray,
                         weights: np.ndarray, penetration: np.ndarray) -> None:  # fmt: skip
    """Penalty force on each slave node from its deepest-penetrated candidate (module docs).

    Args:
        points: (n_points, 3) [m]; slave_nodes, slave_thickness [m], slave_stiffness [N/m]:
            (n_slaves,); segments (n_segments, 4), segment_thickness (n_segments,) [m].
        two_sided: shells (True) or outward-facing solid faces (False); depth: deepest d below
            a solid face still taken as contact [m].
        gap_offset: (n_slaves,) penetration subtracted from each slave's (initial overlaps) [m].
        candidates, n_candidates: from :func:`search_candidates`.
        planes: (n_segments, 6) centroid and unit normal of every candidate segment
            (:func:`segment_planes`).
        node_normals: (n_points, 3) the master's nodal normals (:func:`nodal_normals`) to push
            along, interpolated at the contact point, instead of the segment's normal; (0, 3)
            for the segment's normal.
        slave_force: (n_slaves, 3) out [N]; contact_segment: (n_slaves,) out, -1 where free;
            weights: (n_slaves, 4) out, N_a at the contact point; penetration: (n_slaves,) out [m].
    """
    n_slaves = slave_nodes.shape[0]
    for block in nb.prange(-(-n_slaves // PENALTY_BLOCK)):
        first = block * PENALTY_BLOCK
        slave_penalties(first, min(first + PENALTY_BLOCK, n_slaves), points, slave_nodes,
                         slave_thickness, slave_stiffness, segments, segment_thickness,
                         two_sided, depth, gap_offset, candidates, n_candidates, planes,
                         node_normals, slave_force, contact_segment, weights,
                         penetration)  # fmt: skip


@nb.njit(cache=True)
def scatter_pair_forces(slave_nodes: np.ndarray, segments: np.ndarray, slave_force: np.ndarray,
                        contact_segment: np.ndarray, weights: np.ndarray,
                        forces: np.ndarray) -> int:  # fmt: skip
    """Add the slave forces and their opposite shares on the segments' nodes to ``forces``
    (n_points, 3) in one serial pass; returns the number of slaves in contact."""
    touching = 0
    for n in range(slave_nodes.shape[0]):
        s = contact_segment[n]
        if s < 0:
            continue
        touching += 1
        for k in range(3):
            forces[slave_nodes[n], k] += slave_force[n, k]
            for a in range(4):
                forces[segments[s, a], k] -= weights[n, a] * slave_force[n, k]
    return touching


@dataclass
class SegmentContact:
    """One direction of a penalty contact: slave nodes against master quad segments.

    Attributes:
        name: label for histories and messages.
        slave_nodes: (n_slaves,) node ids; slave_thickness: (n_slaves,) contact thickness of
            each (half the shell's thickness, 0 for a solid) [m]; slave_stiffness: (n_slaves,)
            penalty [N/m].
        segments: (n_segments, 4) master node ids (solid faces oriented outward);
            segment_thickness: (n_segments,) [m].
        two_sided: shells (True) or solid faces (False); depth: see
            :func:`slave_penalty_forces` [m].
        margin: search margin [m]; gap_offset: (n_slaves,) initial overlap ignored [m].
        smooth: push along the master's nodal normals (each the mean of its segments' normals)
            interpolated at the contact point, not along the segment's own normal: the push then
            turns smoothly where a node crosses from one segment to the next (segments oriented
            alike; :func:`nodal_normals`).
    """

    name: str
    slave_nodes: np.ndarray
    slave_thickness: np.ndarray
    slave_stiffness: np.ndarray
    segments: np.ndarray
    segment_thickness: np.ndarray
    two_sided: bool
    depth: float
    margin: float
    gap_offset: np.ndarray = field(default_factory=lambda: np.zeros(0))
    smooth: bool = False
    candidates: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), dtype=np.int64))
    n_candidates: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))

    def __post_init__(self) -> None:
        n = self.slave_nodes.size
        if self.gap_offset.size != n:
            self.gap_offset = np.zeros(n)
        self.slave_force = np.zeros((n, 3))
        self.contact_segment = np.full(n, -1, dtype=np.int64)
        self.weights = np.zeros((n, 4))
        self.penetration = np.zeros(n)
        self.planes = np.zeros((len(self.segments), 6))
        self.active_segments = np.zeros(0, dtype=np.int64)
        self.all_segments = np.arange(len(self.segments))
        self.master_nodes = np.unique(self.segments)
        self.node_normals = np.zeros((0, 3))

    def search(self, points: np.ndarray) -> None:
        """Refresh every slave's candidate segments (bucket search)."""
        grow = self.segment_thickness + self.slave_thickness.max(initial=0.0) + self.margin
        self.candidates, self.n_candidates, self.active_segments = search_candidates(
            points, self.slave_nodes, self.segments, grow
        )

    def add_forces(self, points: np.ndarray, forces: np.ndarray) -> int:
        """Add this contact's forces to ``forces`` (n_points, 3) [N]; returns slaves touching."""
        if self.smooth:
            segment_planes(points, self.segments, self.all_segments, self.planes)
            if self.node_normals.shape[0] != points.shape[0]:
                self.node_normals = np.zeros_like(points)
            nodal_normals(self.segments, self.master_nodes, self.planes, self.node_normals)
        else:
            segment_planes(points, self.segments, self.active_segments, self.planes)
        arguments = (points, self.slave_nodes, self.slave_thickness, self.slave_stiffness,
                     self.segments, self.segment_thickness, self.two_sided, self.depth,
                     self.gap_offset, self.candidates, self.n_candidates, self.planes,
                     self.node_normals, self.slave_force, self.contact_segment, self.weights,
                     self.penetration)  # fmt: skip
        if int(self.n_candidates.sum()) < PARALLEL_MIN_WORK:  # not worth the threads
            slave_penalties(0, self.slave_nodes.shape[0], *arguments)
        else:
            slave_penalty_forces(*arguments)
        return int(scatter_pair_forces(self.slave_nodes, self.segments, self.slave_force,
                                       self.contact_segment, self.weights, forces))  # fmt: skip

    def initial_overlap(self, points: np.ndarray) -> np.ndarray:
        """Each slave's penetration in ``points`` with no offset, (n_slaves,) [m]."""
        saved = self.gap_offset
        self.gap_offset = np.zeros_like(saved)
        self.search(points)
        self.add_forces(points, np.zeros_like(points))
        self.gap_offset = saved
        return self.penetration.copy()
