"""Node-level Numba kernels of the explicit cycle: contact, time step, assembly, update, checks.

:func:`finish_cycle` does everything of a cycle after the element forces in one compiled call, so
the Python step loop makes two calls per cycle. Numba's cache of this module does not see edits of
``contact/rigid.py``, whose kernel it compiles in: touch this file after editing that one.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import Any, cast

import numba as nb
import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from batball.contact.rigid import add_rigid_contact_forces
from batball.elements.hex8 import slot_cells
from batball.elements.vector_math import bits_float, component_rows
from batball.numerics import FASTMATH

#: :func:`finish_cycle` outcomes: go on, or stop (separation), or fail (negative).
CYCLE_OK, CYCLE_SEPARATED = 0, 1
FAIL_INVERTED, FAIL_STEP_COLLAPSE, FAIL_NON_FINITE, FAIL_ENERGY = -1, -2, -3, -4

#: Slots of the ``clock`` array: time [s], last step [s], first step [s], contact start and last
#: contact time [s] (-1 before any contact).
TIME, DT, FIRST_DT, CONTACT_BEGAN, LAST_CONTACT = range(5)
#: Slots of the ``counters`` array: steps taken, element named by a failure.
STEP, ELEMENT = range(2)
#: Slots of the ``limits`` array.
(
    TSSFAC,
    MIN_STEP_RATIO,
    DAMPING,
    SEPARATION_TIME,
    KINETIC0,
    MAX_ENERGY_ERROR,
    TOTAL_MASS,
    ENERGY_FLOOR,
) = range(8)
#: Slots of the ``energies`` array [J]: accumulated internal, hourglass, bulk-viscosity, contact
#: (minus the work of the contact forces on the body) and damping (dissipated) energy.
CONTACT_ENERGY, DAMPING_ENERGY, N_ENERGIES = 3, 4, 5


def slot_node_ranges(cells: np.ndarray, n_slots: int) -> np.ndarray:
    """The node ids each slot of the element kernel can write: (n_slots, 2) [lowest, highest + 1]
    over the slot's cells (:func:`batball.elements.hex8.slot_cells`, as the element kernel
    splits them). The update takes a slot's forces only inside its range (they are zero outside
    it), and at a node that one slot's range holds, only that slot's."""
    ranges = np.zeros((n_slots, 2), dtype=np.int64)
    for slot in range(n_slots):
        first, end = slot_cells(slot, n_slots, cells.shape[0])
        part = cells[first:end]
        if part.size:
            ranges[slot] = part.min(), part.max() + 1
    return ranges


#: Nodes per block of the update's kinetic-energy, momentum and dissipation sums.
SUM_BLOCK = 256
#: Partial sums a block keeps of each quantity: lane j sums the block's nodes j, j + LANES,
#: j + 2 LANES, ..., so that a block's sums are vector additions in a fixed order.
LANES = 8


def sum_blocks(n_points: int) -> np.ndarray:
    """Scratch for :func:`assemble_and_update`'s sums of ``n_points`` nodes: (n_blocks, 5,
    LANES), each block's lanes of its five sums (:func:`motion_sums`)."""
    return np.zeros((max(1, -(-n_points // SUM_BLOCK)), 5, LANES))


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def assemble_and_update(
    nodal_forces: np.ndarray,
    slot_nodes: np.ndarray,
    mass: np.ndarray,
    damping: float,
    dt_old: float,
    dt_new: float,
    points: np.ndarray,
    velocities: np.ndarray,
    sums: np.ndarray,
    scratch: tuple,
) -> None:
    """Sum the slots of nodal forces (element and contact forces; cleared for the next cycle) and
    take one central-difference step, in place:
    m (v^(n+1/2) - v^(n-1/2)) / h = f^n - c m (v^(n+1/2) + v^(n-1/2)) / 2, h = (dt_old + dt_new)/2,
    x^(n+1) = x^n + dt_new v^(n+1/2), with mass-proportional damping c (0 = undamped).

    Args:
        nodal_forces: (n_slots, n_points, 3) the forces [N] of each slot (zeroed here).
        slot_nodes: (n_slots, 2) the node range of each slot (:func:`slot_node_ranges`).
        mass: (n_points,) lumped masses [kg]; damping: c [1/s].
        points, velocities: (n_points, 3) x^n and v^(n-1/2), advanced in place [m, m/s].
        sums: (6,) out: kinetic energy at n+1/2 [J], (slot 1 is left to the caller: the contact
            work), energy dissipated by the damping [J], and the total momentum [kg m/s].
        scratch: (node_sums, block_sums): each node's damping dissipation, (n_points,), and
            each block's sums (:func:`sum_blocks`).

    The nodes run in one parallel loop, each thread a run of whole SUM_BLOCK-node blocks
    (:func:`update_run`): one fork and join a cycle, where a thread waking the other costs most
    on a virtual machine, and each thread then reads back only what it has just written. The
    sums do not depend on the number of threads: each block is summed in node order, the blocks
    in block order.
    """
    node_sums, block_sums = scratch
    n_slots = nodal_forces.shape[0]
    n_blocks = block_sums.shape[0]
    half = 0.5 * (dt_old + dt_new)
    force, x, v = nodal_forces.reshape(-1), points.reshape(-1), velocities.reshape(-1)
    for run in nb.prange(n_slots):
        update_run(force, slot_nodes, mass, damping, half, dt_new, x, v, node_sums, block_sums,
                   run * n_blocks // n_slots, (run + 1) * n_blocks // n_slots)  # fmt: skip
    kinetic = 0.0
    dissipated = 0.0
    p0 = 0.0
    p1 = 0.0
    p2 = 0.0
    for block in range(n_blocks):
        for j in range(LANES):
            kinetic += block_sums[block, 0, j]
            dissipated += block_sums[block, 1, j]
            p0 += block_sums[block, 2, j]
            p1 += block_sums[block, 3, j]
            p2 += block_sums[block, 4, j]
    sums[0] = kinetic
    sums[2] = dissipated
    sums[3] = p0
    sums[4] = p1
    sums[5] = p2


@nb.njit(fastmath=FASTMATH, inline="always")
def _take_force(force, o):  # noqa: ANN001, ANN202
    """The force (3-tuple) at flat offset o, its entries cleared."""
    one, two = np.uint64(1), np.uint64(2)
    f = (force[o], force[o + one], force[o + two])
    force[o] = 0.0
    force[o + one] = 0.0
    force[o + two] = 0.0
    return f


@nb.njit(fastmath=FASTMATH, inline="always", error_model="numpy")
def _step_node(n, o, f, mass, x, v, node_sums, step):  # noqa: ANN001, ANN202
    """The central-difference step of node n (flat offset o) under the force f (3-tuple);
    ``step`` = (keep, scale, half, dt_new, damping, damped) of :func:`update_run`."""
    keep, scale, half, dt_new, damping, damped = step
    one, two = np.uint64(1), np.uint64(2)
    m = mass[n]
    h_m = half / m
    v0, v1, v2 = v[o], v[o + one], v[o + two]
    w0 = (keep * v0 + f[0] * h_m) * scale
    w1 = (keep * v1 + f[1] * h_m) * scale
    w2 = (keep * v2 + f[2] * h_m) * scale
    v[o] = w0
    v[o + one] = w1
    v[o + two] = w2
    x[o] += dt_new * w0
    x[o + one] += dt_new * w1
    x[o + two] += dt_new * w2
    if damped:
        a0 = 0.5 * (v0 + w0)
        a1 = 0.5 * (v1 + w1)
        a2 = 0.5 * (v2 + w2)
        node_sums[n] = damping * m * half * (a0 * a0 + a1 * a1 + a2 * a2)


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def _step_nodes(force, first, end, mass, x, v, node_sums, step):  # noqa: ANN001, ANN202
    """:func:`_step_node` on nodes first..end - 1 (unsigned) under one slot's forces ``force``
    (flat, n_points * 3), cleared."""
    three = np.uint64(3)
    for n in range(first, end):
        o = three * n
        _step_node(n, o, _take_force(force, o), mass, x, v, node_sums, step)


@nb.njit(inline="always")
def _segment(slot_nodes, n, end):  # noqa: ANN001, ANN202
    """From node n (unsigned), the end of the run of nodes (at most ``end``) that the same slots'
    node ranges hold, how many slots hold it and the last of them."""
    stop = end
    n_holding = 0
    only = 0
    for slot in range(slot_nodes.shape[0]):
        lo, hi = np.uint64(slot_nodes[slot, 0]), np.uint64(slot_nodes[slot, 1])
        if lo <= n < hi:
            n_holding += 1
            only = slot
            stop = min(stop, hi)
        elif n < lo:
            stop = min(stop, lo)
    return stop, n_holding, only


@nb.njit(fastmath=FASTMATH, error_model="numpy")
def update_run(
    force: np.ndarray,
    slot_nodes: np.ndarray,
    mass: np.ndarray,
    damping: float,
    half: float,
    dt_new: float,
    x: np.ndarray,
    v: np.ndarray,
    node_sums: np.ndarray,
    block_sums: np.ndarray,
    first_block: int,
    end_block: int,
) -> None:
    """:func:`assemble_and_update` on the nodes of blocks first_block..end_block - 1, with the
    forces, points and velocities flat (n_slots * n_points * 3 and n_points * 3).

    Each node's force is its slots' forces summed in slot order, each slot within its own node
    range (a slot's forces are zero outside it), in the same pass over the nodes as the step,
    and cleared: one pass over the forces instead of a pass that adds the slots into slot 0
    and a second one that reads it (on two threads of a 2-core Sapphire Rapids Xeon about a
    tenth off the update). The nodes go in runs that the same slots' ranges hold
    (:func:`_segment`): a run that one slot holds takes that slot's forces with no range checks
    (on that Xeon, two threads with slots that overlap only in a few nodes took 28 us where the
    check at every node took 39 us, one thread with one slot 47-51 us), through the same
    compiled loop as a single slot, on a view of that slot (:func:`_step_nodes`; indexed from
    the slot's offset in the whole array, that loop took 26.5 us against 15 on a Zen 5 core).
    Then each block's sums from the new velocities, as vector partial sums
    (:func:`motion_sums`; as plain sums in node order they took half the update, 12 of 25 us
    a cycle on the 12,096-hex ball, one thread of an AMD Zen 5 core).

    Compiled with NumPy's error model: Python's tests every division (half / m) for zero, a
    branch that kept LLVM from vectorising the node loops (the masses are positive,
    :func:`lumped_masses`; alone on one thread the update took about a fifth less, the same
    bits). The offsets are unsigned, for which Numba adds no negative-index wraparound: with
    signed ones from a runtime range the step ran 40 % slower. (The coupled test's
    ball_bat.take_slot_forces sums every slot into a separate array: the same sums, but 60 %
    more time here on one thread.)
    """
    n_points = mass.shape[0]
    first = first_block * SUM_BLOCK
    end = min(end_block * SUM_BLOCK, n_points)
    three = np.uint64(3)
    stride = three * np.uint64(n_points)
    keep = 1.0 - 0.5 * damping * half
    scale = 1.0 / (1.0 + 0.5 * damping * half)
    damped = damping != 0.0
    step = (keep, scale, half, dt_new, damping, damped)
    if slot_nodes.shape[0] == 1:
        _step_nodes(force, np.uint64(first), np.uint64(end), mass, x, v, node_sums, step)
    else:
        segment = np.uint64(first)
        while segment < np.uint64(end):
            stop, n_holding, only = _segment(slot_nodes, segment, np.uint64(end))
            if n_holding == 1:
                base = np.uint64(only) * stride
                _step_nodes(force[base : base + stride], segment, stop, mass, x, v, node_sums,
                            step)  # fmt: skip
            else:
                for n in range(segment, stop):
                    o = three * n
                    f = (0.0, 0.0, 0.0)
                    for slot in range(slot_nodes.shape[0]):
                        if np.uint64(slot_nodes[slot, 0]) <= n < np.uint64(slot_nodes[slot, 1]):
                            g = _take_force(force, np.uint64(slot) * stride + o)
                            f = (f[0] + g[0], f[1] + g[1], f[2] + g[2])
                    _step_node(n, o, f, mass, x, v, node_sums, step)
            segment = stop
    for block in range(first_block, end_block):
        lo = block * SUM_BLOCK
        motion_sums(mass, v, node_sums, lo, min(lo + SUM_BLOCK, n_points), damped,
                    block_sums[block])  # fmt: skip


def _motion_lanes(builder: ir.IRBuilder, mass: ir.Value, v: ir.Value, n0: ir.Value) -> list:
    """LLVM IR: the kinetic energy 0.5 m |v|^2 and momentum m v_i (i = 0, 1, 2) of the LANES
    nodes from node ``n0`` (<LANES x double> each)."""
    row = ir.VectorType(ir.DoubleType(), LANES)
    m = builder.load(builder.bitcast(builder.gep(mass, [n0]), row.as_pointer()), align=8)
    w = component_rows(builder, v, builder.mul(n0, ir.IntType(64)(3)), LANES)
    squares = builder.fadd(builder.fadd(builder.fmul(w[0], w[0]), builder.fmul(w[1], w[1])),
                           builder.fmul(w[2], w[2]))  # fmt: skip
    half_m = builder.fmul(ir.Constant(row, [0.5] * LANES), m)
    return [builder.fmul(half_m, squares)] + [builder.fmul(m, wi) for wi in w]


@intrinsic
def _lane_motion_sums(typingctx, out, mass, v, first, count):  # noqa: ANN001, ANN202
    """``out[r, j]`` (rows 0, 2, 3, 4; row 1 untouched) = the sum over k < ``count``, in order,
    of node ``first + LANES k + j``'s kinetic energy 0.5 m |v|^2 (row 0) and momentum m v_i
    (rows 2..4), for masses ``mass`` (n,) and flat velocities ``v`` (3 n,): four vector
    accumulators, so the sums are vector additions (LLVM vectorises no floating-point sum
    without reassociation, which the kernels leave out; see ``numerics.FASTMATH``)."""
    double = types.Array(types.float64, 1, "C")
    if (
        out != types.Array(types.float64, 2, "C")
        or mass != double
        or v != double
        or first != types.int64
        or count != types.int64
    ):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        target, masses, velocities = (
            context.make_array(signature.args[k])(context, builder, value=args[k]).data
            for k in range(3)
        )
        zero = ir.Constant(ir.VectorType(ir.DoubleType(), LANES), [0.0] * LANES)
        sums = [cgutils.alloca_once_value(builder, zero) for _ in range(4)]
        with cgutils.for_range(builder, args[4]) as loop:
            n0 = builder.add(args[3], builder.mul(loop.index, ir.IntType(64)(LANES)))
            for total, term in zip(sums, _motion_lanes(builder, masses, velocities, n0),
                                   strict=True):  # fmt: skip
                builder.store(builder.fadd(builder.load(total), term), total)
        for total, row in zip(sums, (0, 2, 3, 4), strict=True):
            at = builder.gep(target, [ir.IntType(64)(row * LANES)])
            builder.store(builder.load(total), builder.bitcast(at, zero.type.as_pointer()),
                          align=8)  # fmt: skip
        return context.get_dummy_value()

    return types.none(out, mass, v, first, count), codegen


#: Typed view of the intrinsic for mypy (the same object for Numba).
lane_motion_sums = cast(
    "Callable[[np.ndarray, np.ndarray, np.ndarray, int, int], None]", _lane_motion_sums
)


@nb.njit(fastmath=FASTMATH, inline="always")
def motion_sums(
    mass: np.ndarray,
    velocities: np.ndarray,
    dissipation: np.ndarray,
    first: int,
    end: int,
    dissipates: bool,
    out: np.ndarray,
) -> None:
    """The kinetic energy [J], the sum of ``dissipation`` [J] (when ``dissipates``) and the
    momentum [kg m/s] of nodes first..end - 1 of ``mass`` moving at ``velocities`` (flat, 3
    n_points), as LANES partial sums each: out[0], out[1] and out[2:5] (``out`` (5, LANES)),
    lane j the nodes first + j, first + j + LANES, ... in order (the dissipation in lane 0)."""
    whole = (end - first) // LANES
    lane_motion_sums(out, mass, velocities, first, whole)
    tail = first + whole * LANES
    for n in range(tail, end):
        j = n - tail
        m = mass[n]
        w0 = velocities[3 * n]
        w1 = velocities[3 * n + 1]
        w2 = velocities[3 * n + 2]
        out[0, j] += 0.5 * m * (w0 * w0 + w1 * w1 + w2 * w2)
        out[2, j] += m * w0
        out[3, j] += m * w1
        out[4, j] += m * w2
    dissipated = 0.0
    if dissipates:
        for n in range(first, end):
            dissipated += dissipation[n]
    out[1, 0] = dissipated
    for j in range(1, LANES):
        out[1, j] = 0.0


def contact_node_slots(
    node_ids: np.ndarray, slot_nodes: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The distinct nodes that may touch a target, and for each the first slot whose node range
    holds it (where :func:`finish_cycle` adds its contact force)."""
    nodes = np.unique(node_ids).astype(np.int64)
    slots = np.zeros(nodes.size, dtype=np.int64)
    for j, n in enumerate(nodes):
        holding = np.flatnonzero((slot_nodes[:, 0] <= n) & (n < slot_nodes[:, 1]))
        slots[j] = holding[0] if holding.size else 0
    return nodes, slots


@nb.njit(inline="always")
def contact_power(nodes: np.ndarray, contact_forces: np.ndarray, velocities: np.ndarray) -> float:
    """sum f . v over the contact nodes [W]: over those with a force, in the order of
    ``nodes`` (a zero force adds nothing, and most contact nodes are apart at any step)."""
    power = 0.0
    for n in nodes:
        f0, f1, f2 = contact_forces[n, 0], contact_forces[n, 1], contact_forces[n, 2]
        if f0 != 0.0 or f1 != 0.0 or f2 != 0.0:
            power += f0 * velocities[n, 0]
            power += f1 * velocities[n, 1]
            power += f2 * velocities[n, 2]
    return power


@nb.njit(inline="always")
def move_contact_forces(
    nodes: np.ndarray, slots: np.ndarray, contact_forces: np.ndarray, nodal_forces: np.ndarray
) -> None:
    """Add the contact nodes' forces into their slots of ``nodal_forces`` (those with a
    force: adding zero changes nothing)."""
    for j in range(nodes.shape[0]):
        n = nodes[j]
        f0, f1, f2 = contact_forces[n, 0], contact_forces[n, 1], contact_forces[n, 2]
        if f0 != 0.0 or f1 != 0.0 or f2 != 0.0:
            nodal_forces[slots[j], n, 0] += f0
            nodal_forces[slots[j], n, 1] += f1
            nodal_forces[slots[j], n, 2] += f2


def lumped_masses(cells: np.ndarray, cell_mass: np.ndarray, n_points: int) -> np.ndarray:
    """Row-sum lumped masses: each hex gives 1/8 of its mass to each node, (n_points,) [kg]."""
    mass = np.zeros(n_points)
    np.add.at(mass, cells.ravel(), np.repeat(cell_mass / 8.0, 8))
    return mass


#: The bits of +infinity as an int64: a float64 whose bits (as an int64) are larger is a NaN.
_INFINITY_BITS = np.int64(0x7FF0000000000000)


@nb.njit(inline="always")
def _first_at(bits: np.ndarray, value: np.int64) -> int:
    """The first index of ``value`` in ``bits`` (which holds it)."""
    e = 0
    while bits[e] != value:
        e += 1
    return e


@nb.njit(inline="always")
def _first_nan(values: np.ndarray) -> int:
    """The first index of a NaN in ``values`` (which holds one)."""
    e = 0
    while values[e] == values[e]:
        e += 1
    return e


@nb.njit(inline="always")
def next_step(
    cell_dt: np.ndarray, clock: np.ndarray, counters: np.ndarray, limits: np.ndarray
) -> float:
    """TSSFAC times the smallest element step [s], or a FAIL_* code (negative) when an element
    has no positive volume (FAIL_INVERTED), a NaN step (FAIL_NON_FINITE), or the step fell
    below MIN_STEP_RATIO of the first one (FAIL_STEP_COLLAPSE); ``counters[ELEMENT]`` is then
    the element (the first with the smallest step, or the first NaN).

    The steps are compared as their bits (int64): for floats of positive sign that is their
    order, and integer minima and maxima vectorise where floating-point ones would need
    fast-math flags that would also drop NaN checks. A step of 0 or of negative sign is the
    smallest; a NaN of positive sign is larger than infinity, so the largest tells it."""
    bits = cell_dt.view(np.int64)
    lowest = bits[0]
    highest = bits[0]
    for e in range(1, bits.shape[0]):
        b = bits[e]
        lowest = min(lowest, b)
        highest = max(highest, b)
    smallest = bits_float(np.uint64(lowest))
    if highest > _INFINITY_BITS or smallest != smallest:
        counters[ELEMENT] = _first_nan(cell_dt)
        return float(FAIL_NON_FINITE)
    if not smallest > 0.0:
        counters[ELEMENT] = _first_at(bits, lowest)
        return float(FAIL_INVERTED)
    dt_new = limits[TSSFAC] * smallest
    if clock[FIRST_DT] == 0.0:
        clock[FIRST_DT] = dt_new
    elif dt_new < limits[MIN_STEP_RATIO] * clock[FIRST_DT]:
        counters[ELEMENT] = _first_at(bits, lowest)
        clock[DT] = dt_new
        return float(FAIL_STEP_COLLAPSE)
    return dt_new


@nb.njit(inline="always")
def record_row(
    row: np.ndarray,
    time: float,
    reaction: np.ndarray,
    penetration: np.ndarray,
    sums: np.ndarray,
    total_mass: float,
    energies: np.ndarray,
    balance: float,
    n_active: int,
) -> None:
    """The history row (layout in :func:`finish_cycle`)."""
    n_targets = reaction.shape[0]
    row[0] = time
    for k in range(n_targets):
        for i in range(3):
            row[1 + 3 * k + i] = reaction[k, i]
    base = 1 + 3 * n_targets
    for i in range(3):
        row[base + i] = sums[3 + i] / total_mass
    row[base + 3] = sums[0]
    for c in range(N_ENERGIES):
        row[base + 4 + c] = energies[c]
    row[base + 4 + N_ENERGIES] = balance
    row[base + 5 + N_ENERGIES] = n_active
    for k in range(n_targets):
        row[base + 6 + N_ENERGIES + k] = penetration[k]


@nb.njit(inline="always")
def rigid_contact_forces(
    points: np.ndarray, time: float, contact_nodes: np.ndarray, contact_forces: np.ndarray,
    contacts: tuple,
) -> int:
    """Clear the contact nodes' rows of ``contact_forces`` and add every target's penalty forces
    (``contacts`` as in :func:`finish_cycle`); returns the number of nodes in contact."""
    node_ids, stiffness, c_offsets, kinds, params, reaction, penetration = contacts
    for n in contact_nodes:
        contact_forces[n, 0] = 0.0
        contact_forces[n, 1] = 0.0
        contact_forces[n, 2] = 0.0
    return add_rigid_contact_forces(
        points, time, node_ids, stiffness, c_offsets, kinds, params, contact_forces, reaction,
        penetration,
    )


@nb.njit(fastmath=FASTMATH, cache=True)
def finish_cycle(
    energy_increments: np.ndarray,
    cell_dt: np.ndarray,
    nodal_forces: np.ndarray,
    nodes: tuple,
    contacts: tuple,
    points: np.ndarray,
    velocities: np.ndarray,
    clock: np.ndarray,
    counters: np.ndarray,
    energies: np.ndarray,
    limits: np.ndarray,
    row: np.ndarray,
) -> int:
    """The rest of a cycle once the element kernel has run: contact, step, update, checks, record.

    Args:
        energy_increments: (n_slots, 3) the element kernel's internal, hourglass, bulk work [J].
        cell_dt: (n_cells,) element stable steps [s]; nodal_forces: (n_slots, n_points, 3) [N].
        nodes: (slot_nodes, mass, contact_forces, sums, contact_nodes, contact_slots,
            scratch): as in :func:`assemble_and_update`, the (n_points, 3) contact forces
            (only the contact nodes' rows are used) and :func:`contact_node_slots`.
        contacts: (node_ids, stiffness, offsets, kinds, params, reaction, penetration) of
            ``add_rigid_contact_forces``.
        points, velocities: x^n and v^(n-1/2), advanced in place.
        clock, counters, energies, limits: see the slot names of this module (in place).
        row: out, the history row: time, reactions (n_targets x 3), centre-of-mass velocity (3),
            kinetic, the N_ENERGIES energies, balance error [J], nodes in contact, deepest
            penetration into each target (n_targets) [m].

    Returns:
        CYCLE_OK, CYCLE_SEPARATED or a FAIL_* code: from the element steps (:func:`next_step`,
        which names the element in ``counters[ELEMENT]``) the step is not taken; from the
        energies (FAIL_NON_FINITE, FAIL_ENERGY) it is taken and recorded.
    """
    slot_nodes, mass, contact_forces, sums, contact_nodes, contact_slots, scratch = nodes
    reaction, penetration = contacts[5], contacts[6]
    for c in range(3):
        energies[c] += energy_increments[:, c].sum()
    n_active = rigid_contact_forces(points, clock[TIME], contact_nodes, contact_forces, contacts)
    dt_new = next_step(cell_dt, clock, counters, limits)
    if dt_new < 0.0:
        return int(dt_new)
    # contact work over the step with the mean displacement (dx^(n-1/2) + dx^(n+1/2)) / 2, which
    # is consistent with the kinetic-energy change of the scheme
    work = 0.5 * clock[DT] * contact_power(contact_nodes, contact_forces, velocities)
    move_contact_forces(contact_nodes, contact_slots, contact_forces, nodal_forces)
    assemble_and_update(
        nodal_forces, slot_nodes, mass, limits[DAMPING], clock[DT], dt_new, points, velocities,
        sums, scratch,
    )
    sums[1] = work + 0.5 * dt_new * contact_power(contact_nodes, contact_forces, velocities)
    energies[CONTACT_ENERGY] -= sums[1]
    energies[DAMPING_ENERGY] += sums[2]
    clock[TIME] += dt_new
    clock[DT] = dt_new
    counters[STEP] += 1
    kinetic = sums[0]
    balance = kinetic - limits[KINETIC0]
    for c in range(N_ENERGIES):
        balance += energies[c]
    record_row(row, clock[TIME], reaction, penetration, sums, limits[TOTAL_MASS], energies,
               balance, n_active)  # fmt: skip
    if not (np.isfinite(kinetic) and np.isfinite(balance)):
        return FAIL_NON_FINITE
    reference = max(limits[KINETIC0], abs(energies[CONTACT_ENERGY]), limits[ENERGY_FLOOR])
    if abs(balance) > limits[MAX_ENERGY_ERROR] * reference:
        return FAIL_ENERGY
    if n_active:
        if clock[CONTACT_BEGAN] < 0.0:
            clock[CONTACT_BEGAN] = clock[TIME]
        clock[LAST_CONTACT] = clock[TIME]
    if (
        limits[SEPARATION_TIME] >= 0.0
        and clock[CONTACT_BEGAN] >= 0.0
        and clock[TIME] - clock[LAST_CONTACT] > limits[SEPARATION_TIME]
    ):
        return CYCLE_SEPARATED
    return CYCLE_OK


def run_cycles(
    kernel: Callable,
    kernel_arguments: tuple,
    kernel_controls: tuple,
    finish_arguments: tuple,
    table: np.ndarray,
    first_row: int,
    end_time: float,
    frame_time: float,
    progress_every: int,
) -> tuple[int, int]:
    """Cycles of the impact solver in one compiled loop: each the element kernel
    (``kernel(*kernel_arguments, (dt, *kernel_controls))``, dt the step that led to x^n,
    :func:`batball.elements.hex8.hex8_kernel_call`) then :func:`finish_cycle`
    (``finish_arguments``: its arguments but the row), writing rows ``first_row``, ... of
    ``table``. Stops after a cycle that fails (its row not counted), separates, reaches
    ``end_time`` or ``frame_time`` [s], fills the table, or takes the step count to a multiple
    of ``progress_every`` (0: never); returns (the last status, the next free row).

    The caller does between calls what needs Python (frames, progress, a bigger table, the
    failure's message): the per-cycle call and dispatch from Python cost a few microseconds a
    cycle, and on two threads more than a tenth of a full-size CCOR cycle.

    The loop (:func:`_cycles`) takes the kernel as a first-class function of the kernel's
    signature, which it calls through its address: a loop typed on the kernel itself (a
    dispatcher) linked the kernel's code in and optimised it again, 1.3-1.7 s in every process,
    and could not be cached (the dispatcher is part of the type). Typed on the signature, it is
    compiled once per signature and cached like the other kernels."""
    typed = (kernel_arguments, kernel_controls, finish_arguments, table)
    loop = _typed_loop(kernel, typed)
    status, row = loop(kernel, typed, first_row, end_time, frame_time, progress_every)
    return status, row


#: Per element kernel, the loop last typed for it and what it was typed from (:func:`_typed_loop`).
_LOOPS: dict[Callable, tuple[object, list[weakref.ref], Callable]] = {}


def _identity(value: object, arrays: list[weakref.ref]) -> object:
    """What fixes the Numba type of ``value``: an array by its identity (a weak reference to it
    goes to ``arrays``; its dtype, rank, layout and writeability, which its type holds, stay as
    they are unless set on the array itself, which the solvers never do), a tuple element by
    element, anything else by its Python type."""
    if isinstance(value, tuple):
        return tuple(_identity(v, arrays) for v in value)
    if isinstance(value, np.ndarray):
        arrays.append(weakref.ref(value))
        return id(value)
    return type(value)


def _typed_loop(kernel: Callable, typed: tuple) -> Callable:
    """:func:`_cycles` compiled (or loaded) for ``kernel``'s signature and the types of ``typed``
    (the kernel's arguments and controls, ``finish_cycle``'s arguments, the table). Typing them
    took about 0.5 ms a stretch at full size (2 % of a CCOR run), so the loop is kept for the
    same arrays, which a solver passes stretch after stretch."""
    arrays: list[weakref.ref] = []
    key = _identity(typed, arrays)
    last = _LOOPS.get(kernel)
    if last is not None and last[0] == key and all(ref() is not None for ref in last[1]):
        return last[2]
    kernel_arguments, kernel_controls = typed[0], typed[1]
    signature = types.none(*(nb.typeof(a) for a in kernel_arguments),
                           nb.typeof((0.0, *kernel_controls)))  # fmt: skip
    cast("Any", kernel).compile(signature.args)  # the overload the loop takes the address of
    loop = _cycles.compile((types.FunctionType(signature), nb.typeof(typed), types.int64,
                            types.float64, types.float64, types.int64))  # fmt: skip
    _LOOPS[kernel] = (key, arrays, loop)
    return loop


@nb.njit(cache=True)
def _cycles(
    kernel: Callable, typed: tuple, first_row: int, end_time: float, frame_time: float,
    progress_every: int,
) -> tuple[int, int]:  # fmt: skip
    """The loop of :func:`run_cycles`; ``typed`` holds its kernel arguments, kernel controls,
    finish arguments and table."""
    kernel_arguments, kernel_controls, finish_arguments, table = typed
    clock, counters = finish_arguments[7], finish_arguments[8]
    row = first_row
    status = CYCLE_OK
    while row < table.shape[0]:
        kernel(*kernel_arguments, (clock[DT], *kernel_controls))
        status = finish_cycle(*finish_arguments, table[row])  # type: ignore[call-arg]
        if status < 0:
            return status, row
        row += 1
        if status == CYCLE_SEPARATED or clock[TIME] >= end_time or clock[TIME] >= frame_time:
            break
        if progress_every > 0 and counters[STEP] % progress_every == 0:
            break
    return status, row
