"""Coupled explicit dynamics of a hex-meshed ball and a shell-meshed bat on a pivot.

One central-difference scheme for both bodies (docs/physics.md section 6.1): lumped masses, one
stable step for both (the smaller of the hexes' and the shells' steps, times TSSFAC), the ball's
internal forces from the one-point hex kernel (:func:`ball_internal_forces`, the only call into
:mod:`batball.elements.hex8`), the bat's from the layered Belytschko-Tsay kernel, and penalty
contact (:mod:`batball.contact.segments`) both ways between them, and between the bat's insert
and its barrel (:mod:`batball.contact.columns`). The cycle reads as the named phases of the
design: contact search (every ``search_interval`` cycles), element forces, contact forces,
accelerations, constraints, update.

The pivot (ASTM F2219; the seed's aluminium pivot block): the bat nodes within a band around
the pivot station form a rigid body that may only turn about the fixed pivot axis (z, through
(x_pivot, 0, 0)); a revolute joint. Each cycle the band's nodal forces and moments give the
torque T about the axis, the band's angular velocity advances by h T / I_band, and every band
node then moves with it (v = omega e_z x r, rotation rate omega e_z). The joint's reactions pass
through the axis, so they change neither the angular momentum about it nor the energy. With
the band covering the whole bat, the bat is a rigid body on the pivot (the verification case).

Energies: kinetic (at the half steps), the ball's internal, hourglass and bulk-viscosity work
from the hex kernel's stress power, the bat's internal work (its nodal internal forces times the
displacement increments), and the contact energy (minus the work of the contact forces on both
bodies, back to about zero when the penalty springs unload). Their sum against the initial
kinetic energy is the balance error.

One module (about 760 lines) because it is one time loop: the coupled model, its state, the
phases of a cycle and the pre-stress relaxation share the solver's arrays, and splitting them
would pass those arrays across module boundaries for no reader's gain.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numba as nb
import numpy as np

from batball.contact.columns import ColumnContact
from batball.contact.segments import SegmentContact
from batball.elements.hex8 import compute_hex8_forces, kernel_ids
from batball.elements.hex8_block import PRECISIONS, check_precision, constants_terms, pack_history
from batball.elements.hex8_foam import N_FOAM_HISTORY, compute_foam_forces
from batball.elements.shell_bt import (
    HOURGLASS_RATIO,
    ShellForceState,
    bt_nodal_force_kernel,
    bt_slot_force_kernel,
    slot_node_ranges,
    sum_slots,
)
from batball.elements.shell_bt_section import LayeredSection
from batball.elements.shell_corotational import (
    CorotationalShellForces,
    CorotationalState,
    checked_shells,
)
from batball.elements.shell_stiffness import ShellSection
from batball.errors import SimulationError
from batball.materials.foam import FoamTable
from batball.numerics import FASTMATH
from batball.solvers.frames import (
    Frame,
    FrameRecorder,
    ball_frame,
    bat_frame,
    foam_cell_stress,
    hex_cell_stress,
    ply_von_mises,
    surface_node_areas,
)

#: The fit's dynamic relaxation scales velocities by this each cycle (LS-DYNA's DRFCTR default).
RELAX_FACTOR = 0.995


@dataclass(frozen=True)
class BallPart:
    """The ball's share of the coupled model (its nodes follow the bat's in the global arrays).

    Attributes:
        cells: (n_cells, 8) node ids local to the ball; first_node: global id of its node 0.
        material_constants: (1, 2 N + 2) kernel constants; density: [kg/m^3].
        volume0: (n_cells,) [m^3]; mass: (n_ball_points,) lumped [kg].
        hourglass_type, hourglass_coefficient, q1, q2: element controls.
        foam: a foam ball's packed material (MAT_057/083) and reference: its cells' reference
            gradients and volumes (``hex8_foam.foam_reference_gradients`` of its undeformed
            coordinates); None for a viscoelastic ball (``material_constants``
            are then the hex kernel's; for a foam they are only the contact stand-ins).
    """

    cells: np.ndarray
    first_node: int
    material_constants: np.ndarray
    density: float
    volume0: np.ndarray
    mass: np.ndarray
    hourglass_type: int
    hourglass_coefficient: float
    q1: float
    q2: float
    foam: FoamTable | None = None
    reference: np.ndarray | None = None


@dataclass(frozen=True)
class BatPart:
    """The bat's share: shells, their layered section and lumped mass, and the pivot.

    Attributes:
        cells: (n_cells, 4) node ids (global = local: the bat's nodes come first).
        section: layer data; mass: (n_bat_points, 6) [kg, kg m^2]; stable_step: [s] (TSSFAC
            applied).
        band: (n_band,) nodes of the rigid pivot band; pivot: (3,) a point of the axis [m]; the
            axis is z.
        rigid: the whole bat is the band (no shell forces); fixed: the band cannot turn.
    """

    cells: np.ndarray
    section: LayeredSection
    mass: np.ndarray
    stable_step: float
    band: np.ndarray
    pivot: np.ndarray
    rigid: bool = False
    fixed: bool = False


class ShellForces:
    """The bat shells' nodal forces (minus the internal forces), threaded when numba has more
    than one thread: the Belytschko-Tsay kernel of :mod:`batball.elements.shell_bt` with the
    rate-form stresses of ``state`` updated in place (one call per cycle) and the hourglass
    ratio r of its constants (LS-DYNA's default, 0.01, unless given)."""

    def __init__(self, bat: BatPart, state: ShellForceState, *,
                 hourglass_ratio: float = HOURGLASS_RATIO) -> None:  # fmt: skip
        self.bat, self.state, self.hourglass_ratio = bat, state, hourglass_ratio
        n_bat = bat.mass.shape[0]
        n_slots = max(1, min(nb.get_num_threads(), len(state.block_start) - 1))
        self.slots = np.zeros((n_slots, n_bat, 6))  # bt_slot_force_kernel's nodal arrays
        self.slot_nodes = slot_node_ranges(bat.cells, state.block_start, n_slots)

    def __call__(self, points: np.ndarray, velocity: np.ndarray, dt: float,
                 out: np.ndarray) -> None:  # fmt: skip
        """Forces on the nodes, (n_bat, 6), into ``out`` from x^n (n_bat, 3), v^(n-1/2) (n_bat,
        6) and the last step ``dt`` [s]."""
        s, sec = self.state, self.bat.section
        args = (points, self.bat.cells, velocity, dt, sec.cell_laminate, sec.layer_stiffness,
                sec.layer_z, sec.layer_thickness, sec.shear, sec.hourglass_moduli,
                self.hourglass_ratio, s.block_start, s.history)  # fmt: skip
        if self.slots.shape[0] == 1:  # assembled in the kernel: one serial pass
            bt_nodal_force_kernel(*args, out)
            out *= -1.0  # f_int -> force on the nodes
        else:  # one nodal array per thread, summed (and negated) in parallel
            bt_slot_force_kernel(*args, self.slots, self.slot_nodes)
            sum_slots(self.slots, self.slot_nodes, -1.0, out)


@dataclass(frozen=True)
class CoupledModel:
    """Ball, bat, their contacts and the initial state (static during a run).

    Attributes:
        points: (n_points, 3) initial coordinates, bat nodes first [m].
        velocity: (n_points, 3) initial translational velocity [m/s].
        ball, bat: the parts; contacts: ball-bat (both ways) and insert-barrel contacts.
        ball_contacts: how many of ``contacts`` (the first ones) act between ball and bat.
        shell_state: initial state of the shells (pre-stress), updated in place by a run: the
            BT shells' stresses, or with ``shell_section`` the nodes' rotations.
        shell_section: the statics' MITC4 section when the bat's shells are the co-rotational
            MITC4 (:mod:`batball.elements.shell_corotational`); None: Belytschko-Tsay.
    """

    points: np.ndarray
    velocity: np.ndarray
    ball: BallPart
    bat: BatPart
    contacts: tuple[SegmentContact | ColumnContact, ...]
    ball_contacts: int
    shell_state: ShellForceState | CorotationalState
    shell_section: ShellSection | None = None

    @property
    def n_bat(self) -> int:
        """Bat nodes (the first rows of the global arrays)."""
        return int(self.bat.mass.shape[0])


@dataclass(frozen=True)
class CoupledControls:
    """Run controls: end time [s], TSSFAC, search interval [cycles], separation time [s] (stop
    once the ball-bat contact has been open this long), the energy run-away limit, the
    precision of the ball's hex kernel ("double" or "single"; ``ExplicitControls.precision``),
    the hourglass ratio r of the bat's shells (LS-DYNA's default 0.01) and the damping of the
    bat's deformation relative to its own rigid turn about the pivot, c [1/s] (the form of
    ``*DAMPING_RELATIVE``, :func:`advance_bat`; 0: none, as the seed) and about how many
    field frames of ball and bat to keep over the end time (:mod:`batball.solvers.frames`;
    0: only the first and the last)."""

    end_time: float = 2e-3
    time_step_scale: float = 0.9
    search_interval: int = 10
    separation_time: float | None = 0.2e-3
    max_energy_error: float = 0.2
    precision: str = "double"
    shell_hourglass_ratio: float = HOURGLASS_RATIO
    bat_damping: float = 0.0
    frame_count: int = 60

    def __post_init__(self) -> None:
        check_precision(self.precision)


#: Time constant of the contact-force average that picks the peak-force picture [s].
PEAK_SMOOTHING = 0.01e-3

#: History columns, one row per cycle.
HISTORY_COLUMNS = (
    "time_s", "contact_force_n", "ball_vx", "ball_vy", "ball_vz", "bat_omega_rad_s",
    "angular_momentum", "kinetic_j", "ball_internal_j", "ball_hourglass_j",
    "ball_bulk_viscosity_j", "bat_internal_j", "contact_j", "bat_damping_j", "balance_error_j",
    "ball_nodes_in_contact", "insert_nodes_in_contact",
)  # fmt: skip


def ball_internal_forces(
    part: BallPart,
    state: BallState,
    points: np.ndarray,
    velocities: np.ndarray,
    dt: float,
    forces: np.ndarray,
) -> None:
    """The ball's element forces (hex8 kernel, or the foam kernel for a foam ball) summed to its
    nodes: ``forces`` (n_ball, 3) [N] (the force on the nodes, m a = f); also fills ``state``'s
    stable steps and energy slots."""
    if part.foam is not None and part.reference is not None:
        compute_foam_forces(points, velocities, part.cells, part.reference, dt, part.density,
                            part.volume0, part.foam.arrays(), state.foam_history, state.hg_state,
                            part.hourglass_type, part.hourglass_coefficient, part.q1, part.q2,
                            state.nodal_forces, state.cell_volume, state.cell_dt,
                            state.energy_increments)  # fmt: skip
    else:
        compute_hex8_forces(points, velocities, part.cells, dt, state.cell_material,
                            part.material_constants, np.array([part.density]), state.history,
                            part.hourglass_type, part.hourglass_coefficient, part.q1, part.q2,
                            state.nodal_forces, state.cell_volume, state.cell_dt,
                            state.energy_increments)  # fmt: skip
    take_slot_forces(state.nodal_forces, forces)


@nb.njit(parallel=True, cache=True, fastmath=FASTMATH)
def take_slot_forces(nodal_forces: np.ndarray, forces: np.ndarray) -> None:
    """forces = the sum of the kernel's slots (n_slots, n_points, 3), which are cleared; over
    the threads (each node's sum in slot order, the same on any number of threads): half the
    slots were written by the other threads, and reading them from one thread cost 0.39 ms a
    cycle of the full-size BBS test on two threads, against 0.05 ms with the data in cache."""
    for n in nb.prange(forces.shape[0]):
        for i in range(3):
            total = 0.0
            for slot in range(nodal_forces.shape[0]):
                total += nodal_forces[slot, n, i]
                nodal_forces[slot, n, i] = 0.0
            forces[n, i] = total


@nb.njit(cache=True)
def smallest_step(cell_dt: np.ndarray) -> tuple[float, int]:
    """The smallest of the cells' stable steps [s] and -1, or a step that is not positive (or
    NaN) and the first cell that has one, in one pass over the steps: on two threads the other
    thread's half of the hex kernel has just written half of them, and a NumPy test and minimum
    would read them twice (about 25 us each in a full-size BBS cycle)."""
    smallest = np.inf
    for e in range(cell_dt.shape[0]):
        step = cell_dt[e]
        if not step > 0.0:
            return step, e
        smallest = min(smallest, step)
    return smallest, -1


@dataclass
class BallState:
    """The ball's element histories and per-cycle work arrays."""

    cell_material: np.ndarray
    history: np.ndarray  # the hex kernel's block layout (hex8_block.pack_history)
    nodal_forces: np.ndarray  # (n_slots, n_points, 3): compute_hex8_forces' per-thread slots
    cell_volume: np.ndarray
    cell_dt: np.ndarray
    energy_increments: np.ndarray
    foam_history: np.ndarray  # a foam ball's (n_cells, N_FOAM_HISTORY); (0, ...) otherwise
    hg_state: np.ndarray  # a foam ball's stiffness-form hourglass forces (n_cells, 4, 3) [N]

    @classmethod
    def initial(cls, part: BallPart, precision: str = "double") -> BallState:
        """Unstressed ball (the hex kernel's history in ``precision``)."""
        n = part.cells.shape[0]
        n_slots = max(1, min(n, nb.get_num_threads()))  # one per thread (compute_hex8_forces)
        n_points = len(part.mass)
        n_terms = constants_terms(part.material_constants)
        n_foam = n if part.foam is not None else 0
        history = pack_history(part.volume0, n_terms=n_terms, dtype=PRECISIONS[precision])
        return cls(kernel_ids(np.zeros(n, dtype=int)), history,
                   np.zeros((n_slots, n_points, 3)), np.zeros(n), np.zeros(n),
                   np.zeros((n_slots, 3)), np.zeros((n_foam, N_FOAM_HISTORY)),
                   np.zeros((n_foam, 4, 3)))  # fmt: skip


#: Nodes a task of :func:`central_difference`'s parallel loop.
RELAX_BLOCK = 512


@nb.njit(cache=True, fastmath=FASTMATH, error_model="numpy", parallel=True)
def central_difference(
    forces: np.ndarray,
    mass: np.ndarray,
    velocity: np.ndarray,
    half: float,
    dt_new: float,
    points: np.ndarray,
    moving: np.ndarray,
    factor: float,
    node_kinetic: np.ndarray,
) -> None:
    """v += h f / m on every dof, then x += dt v on the translations of ``moving`` nodes
    (all but the pivot band, held by the relaxation), then v *= ``factor``; (n, 6) C-ordered
    arrays, blocks of RELAX_BLOCK nodes over the threads. The velocities run flat over each
    block's dofs with unsigned offsets and NumPy's error model (no negative-index wraparound,
    no zero-division check), the loops LLVM vectorises: 2.1 times the speed of a loop over the
    nodes, the same bits. ``node_kinetic`` (n,) receives each node's sum m v^2 over its dofs
    in dof order (:func:`kinetic_energy` adds them), taken while the block is in cache."""
    n_nodes, n_dofs = forces.shape
    f, m, v = forces.reshape(-1), mass.reshape(-1), velocity.reshape(-1)
    for block in nb.prange(-(-n_nodes // RELAX_BLOCK)):
        first, stop = block * RELAX_BLOCK, min((block + 1) * RELAX_BLOCK, n_nodes)
        lo, hi = np.uint64(n_dofs * first), np.uint64(n_dofs * stop)
        for j in range(lo, hi):
            v[j] += half * f[j] / m[j]
        for n in range(first, stop):
            if moving[n]:
                for k in range(3):
                    points[n, k] += dt_new * velocity[n, k]
        for j in range(lo, hi):
            v[j] *= factor
        for n in range(first, stop):
            node = 0.0
            for k in range(n_dofs):
                node += mass[n, k] * velocity[n, k] * velocity[n, k]
            node_kinetic[n] = node


@nb.njit(cache=True, fastmath=FASTMATH, parallel=True)
def advance_ball(
    forces: np.ndarray,
    contact: np.ndarray,
    mass: np.ndarray,
    velocity: np.ndarray,
    points: np.ndarray,
    pivot: np.ndarray,
    half: float,
    dt_old: float,
    dt_new: float,
    out: np.ndarray,
) -> None:
    """The ball's central-difference update with its bookkeeping in one pass, (n, 3) arrays:
    v += h (f + f_c) / m, x += dt_new v; ``out`` (7,) receives the contact work on the ball
    (f_c times the increment (v_old dt_old + v_new dt_new) / 2, the displacement over the step
    centred on this cycle), the kinetic energy, the sum of m v (3), the angular momentum about
    the z axis through ``pivot`` (at the new positions) and the contact force along y [N].

    The nodes are split over the threads; the sums are reductions (each thread's part added in
    thread order), so they change at round-off with the thread count, the motion does not."""
    work = kinetic = px = py = pz = spin = pull = 0.0
    for n in nb.prange(forces.shape[0]):
        m = mass[n]
        old0, old1, old2 = velocity[n, 0], velocity[n, 1], velocity[n, 2]
        v0 = old0 + half * (forces[n, 0] + contact[n, 0]) / m
        v1 = old1 + half * (forces[n, 1] + contact[n, 1]) / m
        v2 = old2 + half * (forces[n, 2] + contact[n, 2]) / m
        velocity[n, 0], velocity[n, 1], velocity[n, 2] = v0, v1, v2
        work += (contact[n, 0] * 0.5 * (old0 * dt_old + v0 * dt_new)
                 + contact[n, 1] * 0.5 * (old1 * dt_old + v1 * dt_new)
                 + contact[n, 2] * 0.5 * (old2 * dt_old + v2 * dt_new))  # fmt: skip
        kinetic += 0.5 * m * (v0 * v0 + v1 * v1 + v2 * v2)
        px += m * v0
        py += m * v1
        pz += m * v2
        points[n, 0] += dt_new * v0
        points[n, 1] += dt_new * v1
        points[n, 2] += dt_new * v2
        rx = points[n, 0] - pivot[0]
        ry = points[n, 1] - pivot[1]
        spin += m * (rx * v1 - ry * v0)
        pull += contact[n, 1]
    out[0], out[1], out[2], out[3], out[4], out[5], out[6] = work, kinetic, px, py, pz, spin, pull


@nb.njit(cache=True, fastmath=FASTMATH, parallel=True)
def advance_bat(
    forces: np.ndarray,
    contact: np.ndarray,
    mass: np.ndarray,
    velocity: np.ndarray,
    points: np.ndarray,
    moving: np.ndarray,
    band: np.ndarray,
    pivot: np.ndarray,
    inertia: float,
    omega: np.ndarray,
    damping: float,
    damping_forces: np.ndarray,
    half: float,
    dt_old: float,
    dt_new: float,
    out: np.ndarray,
) -> None:
    """The bat's update (free nodes by central differences, the pivot band as a rigid body
    turning about the axis) with its bookkeeping in one pass: ``forces`` (n, 6) internal forces
    on the nodes, ``contact`` (n, 3), ``moving`` (n,) False on the band; ``out`` (5,) receives
    the work of the internal forces and of the contact forces over the step centred on this
    cycle, the kinetic energy, the angular momentum about the pivot axis (at the new
    positions) and the work of the damping. The band: omega += h T / I_band with T the torque
    of its nodes' forces about the axis, then every band node moves with omega e_z x r (its
    rotation rate omega e_z).

    ``damping`` c [1/s] damps the bat's deformation relative to its rigid turn
    (:func:`add_relative_damping`); the free nodes run over the threads, the sums are
    reductions (:func:`advance_ball`)."""
    torque = 0.0
    for i in range(band.shape[0]):
        n = band[i]
        rx = points[n, 0] - pivot[0]
        ry = points[n, 1] - pivot[1]
        fx, fy = forces[n, 0] + contact[n, 0], forces[n, 1] + contact[n, 1]
        torque += rx * fy - ry * fx + forces[n, 5]
    omega[0] += half * torque / inertia
    w = omega[0]
    if damping > 0.0:
        add_relative_damping(forces, mass, velocity, points, moving, pivot, damping,
                             damping_forces)  # fmt: skip
    internal = external = kinetic = spin = 0.0
    for n in nb.prange(forces.shape[0]):
        rx = points[n, 0] - pivot[0]
        ry = points[n, 1] - pivot[1]
        node_internal = node_external = node_kinetic = 0.0
        for k in range(6):
            v_old = velocity[n, k]
            f_contact = contact[n, k] if k < 3 else 0.0
            if moving[n]:
                v = v_old + half * (forces[n, k] + f_contact) / mass[n, k]
            elif k == 0:
                v = -w * ry
            elif k == 1:
                v = w * rx
            else:
                v = w if k == 5 else 0.0
            velocity[n, k] = v
            increment = 0.5 * (v_old * dt_old + v * dt_new)
            node_internal += forces[n, k] * increment
            node_external += f_contact * increment
            node_kinetic += 0.5 * mass[n, k] * v * v
        internal += node_internal
        external += node_external
        kinetic += node_kinetic
        for k in range(3):  # a band node's z velocity is 0
            points[n, k] += dt_new * velocity[n, k]
        rx = points[n, 0] - pivot[0]
        ry = points[n, 1] - pivot[1]
        spin += (mass[n, 0] * (rx * velocity[n, 1] - ry * velocity[n, 0])
                 + mass[n, 5] * velocity[n, 5])  # fmt: skip
    out[0], out[1], out[2], out[3], out[4] = internal, external, kinetic, spin, 0.0
    if damping > 0.0:
        split_damping_work(forces, contact, mass, velocity, moving, damping_forces, half, dt_old,
                           dt_new, out)  # fmt: skip


@nb.njit(cache=True, fastmath=FASTMATH)
def split_damping_work(
    forces: np.ndarray, contact: np.ndarray, mass: np.ndarray, velocity: np.ndarray,
    moving: np.ndarray, damping_forces: np.ndarray, half: float, dt_old: float, dt_new: float,
    out: np.ndarray,
) -> None:  # fmt: skip
    """Move the damping's work out of the internal forces' (``out[0]``, which the update booked
    with the damping forces inside ``forces``) into ``out[4]``; each free dof's velocity
    before the step is recovered from the new one and the step's forces."""
    for n in range(forces.shape[0]):
        if moving[n]:
            for k in range(6):
                v = velocity[n, k]
                f_contact = contact[n, k] if k < 3 else 0.0
                v_old = v - half * (forces[n, k] + f_contact) / mass[n, k]
                work = damping_forces[n, k] * 0.5 * (v_old * dt_old + v * dt_new)
                out[4] += work
                out[0] -= work


@nb.njit(cache=True, fastmath=FASTMATH)
def add_relative_damping(forces: np.ndarray, mass: np.ndarray, velocity: np.ndarray,
                         points: np.ndarray, moving: np.ndarray, pivot: np.ndarray,
                         damping: float, damping_forces: np.ndarray) -> None:  # fmt: skip
    """-c m (v - v_r) on each free node into ``damping_forces`` and added to ``forces``, v_r
    the free nodes' mean rigid turn about the pivot axis, for :func:`advance_bat`.

    c [1/s] damps the bat's deformation as LS-DYNA's ``*DAMPING_RELATIVE`` does relative to a
    rigid body: v_r is a free node's velocity in the free nodes' mean rigid turn about the axis
    (omega_r e_z x r, rotation rate omega_r e_z, omega_r their angular momentum over their
    MOI), from the velocities at the half step before. The damping forces then have no net
    torque about the pivot (the angular momentum is kept) and take energy out of the
    deformation only, at a fraction of critical c / (2 omega_i) in mode i. (Damping relative to
    the small pivot band instead, with the band taking the reaction, is unstable at the shells'
    step.) The damping forces are added to ``forces`` in place and kept in ``damping_forces``
    (n, 6), so that the undamped update runs the same loop as without."""
    momentum, moi = 0.0, 0.0
    for n in range(forces.shape[0]):
        if moving[n]:
            rx = points[n, 0] - pivot[0]
            ry = points[n, 1] - pivot[1]
            momentum += mass[n, 0] * (rx * velocity[n, 1] - ry * velocity[n, 0]) \
                + mass[n, 5] * velocity[n, 5]
            moi += mass[n, 0] * (rx * rx + ry * ry) + mass[n, 5]
    w_rigid = momentum / moi
    for n in range(forces.shape[0]):
        if moving[n]:
            rx = points[n, 0] - pivot[0]
            ry = points[n, 1] - pivot[1]
            for k in range(6):
                rigid = -w_rigid * ry if k == 0 else w_rigid * rx if k == 1 else \
                    w_rigid if k == 5 else 0.0
                damping_forces[n, k] = -damping * mass[n, k] * (velocity[n, k] - rigid)
                forces[n, k] += damping_forces[n, k]


def band_inertia(model: CoupledModel) -> float:
    """MOI of the band about the pivot axis [kg m^2]."""
    band = model.bat.band
    return moment_of_inertia_z(model.points[band], model.bat.mass[band], model.bat.pivot)


def pivot_inertia(model: CoupledModel) -> float:
    """MOI of the whole (lumped) bat about the pivot axis [kg m^2]."""
    return moment_of_inertia_z(model.points[: model.n_bat], model.bat.mass, model.bat.pivot)


def moment_of_inertia_z(points: np.ndarray, mass: np.ndarray, pivot: np.ndarray) -> float:
    """MOI about the z axis through ``pivot`` (3,) of lumped shell masses (n, 6) [kg, kg m^2] at
    ``points`` (n, 3) [m]: sum m (dx^2 + dy^2) + I_zz [kg m^2]."""
    r = points[:, :2] - pivot[:2]
    return float(np.sum(mass[:, 0] * np.sum(r * r, axis=1)) + np.sum(mass[:, 5]))


@dataclass
class CoupledResult:
    """Histories of a coupled run.

    Attributes:
        history: (n_steps, len(HISTORY_COLUMNS)), columns named in HISTORY_COLUMNS (SI).
        peak_displacement: displacement of every node [m] when the contact force, smoothed
            over about 0.01 ms (an exponential average), peaks (so not at a one-cycle spike),
            (n_points, 3).
        n_steps, wall_seconds, phase_seconds: cost of the run.
        pivot_inertia: the lumped bat's MOI about the pivot [kg m^2]; ball_mass: [kg].
        prestress_kinetic_ratio: the relaxation's final over peak kinetic energy (NaN: none);
        interference_pressure: mean insert-barrel pressure after it [Pa]; prestress_reused:
            the relaxed fit was restored from a store, not relaxed in this run.
        frame_times: (n_frames,) [s]; ball_frames, bat_frames: the fields of ball and bat at
            those times by name, (n_frames, ...) float32 (:mod:`batball.solvers.frames`).
    """

    history: np.ndarray
    peak_displacement: np.ndarray
    n_steps: int
    wall_seconds: float
    phase_seconds: dict[str, float] = field(default_factory=dict)
    pivot_inertia: float = 0.0
    ball_mass: float = 0.0
    prestress_kinetic_ratio: float = float("nan")
    interference_pressure: float = float("nan")
    prestress_reused: bool = False
    frame_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ball_frames: Frame = field(default_factory=dict)
    bat_frames: Frame = field(default_factory=dict)

    def column(self, name: str) -> np.ndarray:
        """One history column by name."""
        return self.history[:, HISTORY_COLUMNS.index(name)]


@nb.njit(cache=True)
def close_cycle(energies: np.ndarray, increments: np.ndarray, ball: np.ndarray, bat: np.ndarray,
                rigid: bool, kinetic0: float, time: float, ball_mass: float, pivot_inertia: float,
                ball_touching: int, insert_touching: int, row: np.ndarray) -> float:  # fmt: skip
    """A coupled cycle's bookkeeping once ball and bat have moved; returns the energy balance
    error [J]. ``energies`` (6,) [J] takes the ball's element work of the cycle (``increments``,
    (n_slots, 3), summed slot by slot), the bat's internal and damping work (``bat``, the sums
    of :func:`advance_bat`; not for a ``rigid`` bat) and the contact work of both sides
    (``ball``, :func:`advance_ball`'s); ``row`` gets the history row (HISTORY_COLUMNS) at
    ``time`` [s]. Each sum runs in index order, as NumPy's reductions over these short arrays
    add, so the row is bit for bit the NumPy form of the same sums (tested)."""
    for c in range(3):
        work = increments[0, c]
        for slot in range(1, increments.shape[0]):
            work += increments[slot, c]
        energies[c] += work
    if not rigid:
        energies[3] -= bat[0]
        energies[5] -= bat[4]
    energies[4] -= ball[0] + bat[1]
    kinetic = ball[1] + bat[2]
    stored = 0.0
    for c in range(energies.shape[0]):
        stored += energies[c]
    balance = kinetic + stored - kinetic0
    row[0], row[1] = time, ball[6]
    for i in range(3):
        row[2 + i] = ball[2 + i] / ball_mass
    row[5], row[6], row[7] = bat[3] / pivot_inertia, bat[3] + ball[5], kinetic
    for c in range(energies.shape[0]):
        row[8 + c] = energies[c]
    row[14], row[15], row[16] = balance, ball_touching, insert_touching
    return balance


@nb.njit(cache=True, fastmath=FASTMATH)
def kinetic_energy(node_kinetic: np.ndarray) -> float:
    """The kinetic energy [J] from each node's sum m v^2 over its dofs (``node_kinetic`` (n,),
    :func:`central_difference`), added in node order: the relaxation's measure of rest, whose
    sum's order does not depend on the threads."""
    total = 0.0
    for n in range(node_kinetic.shape[0]):
        total += node_kinetic[n]
    return 0.5 * total


@nb.njit(cache=True, parallel=True)
def add_and_clear(forces: np.ndarray, contact: np.ndarray, held: np.ndarray) -> None:
    """forces[:, :3] += the first len(forces) rows of ``contact``, which are then zeroed for the
    next cycle; the ``held`` nodes' rows of ``forces`` (n, 6) zeroed. One pass where NumPy made
    three and cleared the whole contact array, in blocks of RELAX_BLOCK nodes over the threads
    (each entry its own sum: the same bits on any number)."""
    n_nodes = forces.shape[0]
    for block in nb.prange(-(-n_nodes // RELAX_BLOCK)):
        for n in range(block * RELAX_BLOCK, min((block + 1) * RELAX_BLOCK, n_nodes)):
            for k in range(3):
                forces[n, k] += contact[n, k]
                contact[n, k] = 0.0
    for i in range(held.shape[0]):
        for k in range(forces.shape[1]):
            forces[held[i], k] = 0.0


def relax_fit(pairs: Sequence[SegmentContact | ColumnContact], *, interference: float,
              ramp_steps: int, settle_steps: int, search_interval: int, points: np.ndarray,
              forces: Callable[[], np.ndarray], mass: np.ndarray, velocity: np.ndarray,
              moving: np.ndarray, dt: float, factor: float = RELAX_FACTOR,
              history: list[float] | None = None) -> float:  # fmt: skip
    """Dynamic relaxation of an insert's fit (LS-DYNA ``*CONTROL_DYNAMIC_RELAXATION``,
    docs/physics.md section 6.7), shared by the BBS test and the explicit barrel test: the
    ``pairs``' ignored initial overlap is reduced by ``interference`` [m] over ``ramp_steps``, then
    ``settle_steps`` more. Each cycle ``forces()`` returns the total force on the bat's nodes,
    (n_bat, 6), at the current state (``points``, (n, 3), the bat's nodes first); then
    v += dt f / m, the ``moving`` nodes move by dt v, and v is scaled by ``factor`` (DRFCTR).
    Velocities (n_bat, 6) are zeroed at the end.

    Returns:
        The bat's kinetic energy at the end over its largest value (LS-DYNA's DRTOL measure);
        ``history`` receives the kinetic energy of every cycle [J].

    Raises:
        SimulationError: the kinetic energy stops being finite (the relaxation diverged).
    """
    overlaps = [pair.gap_offset.copy() for pair in pairs]
    bat_points = points[: mass.shape[0]]
    node_kinetic = np.zeros(mass.shape[0])
    peak = kinetic = 0.0
    for step in range(ramp_steps + settle_steps):
        share = max(0.0, 1.0 - (step + 1) / ramp_steps)
        for pair, overlap in zip(pairs, overlaps, strict=True):
            pair.gap_offset[:] = overlap - (1.0 - share) * interference
            if step % search_interval == 0:
                pair.search(points)
        central_difference(forces(), mass, velocity, dt, dt, bat_points, moving, factor,
                           node_kinetic)  # fmt: skip
        kinetic = kinetic_energy(node_kinetic)
        if not np.isfinite(kinetic):
            raise SimulationError(
                f"insert fit relaxation: the bat's kinetic energy is not finite at cycle "
                f"{step + 1} of {ramp_steps + settle_steps} (step {dt:.3g} s): the relaxation "
                "diverged; a finer bat mesh or a smaller step"
            )
        peak = max(peak, kinetic)
        if history is not None:
            history.append(kinetic)
    velocity[:] = 0.0
    return kinetic / peak if peak > 0 else 0.0


class CoupledSolver:
    """Runs a :class:`CoupledModel` with :class:`CoupledControls` (module docs)."""

    def __init__(self, model: CoupledModel, controls: CoupledControls) -> None:
        self.model, self.controls = model, controls
        n_bat = model.n_bat
        self.points = model.points.copy()
        self.ball_points = self.points[n_bat:]
        self.bat_points = self.points[:n_bat]
        self.ball_velocity = np.ascontiguousarray(model.velocity[n_bat:])
        self.bat_velocity = np.zeros((n_bat, 6))
        self.bat_velocity[:, :3] = model.velocity[:n_bat]
        self.ball_total_mass = float(model.ball.mass.sum())
        self.ball_sums = np.zeros(7)  # advance_ball's bookkeeping
        self.bat_sums = np.zeros(5)  # advance_bat's
        self.ball_state = BallState.initial(model.ball, controls.precision)
        self.shell_state = model.shell_state
        self.ball_forces = np.zeros_like(self.ball_velocity)
        self.bat_forces = np.zeros((n_bat, 6))
        self.damping_forces = np.zeros((n_bat, 6))  # advance_bat's scratch
        self.bat_shells: ShellForces | CorotationalShellForces
        if isinstance(self.shell_state, CorotationalState):
            if model.shell_section is None:
                raise ValueError("co-rotational shell state without a shell section")
            self.bat_shells = checked_shells(model.points[:n_bat], model.bat.cells,
                                             model.shell_section, model.bat.mass,
                                             model.bat.stable_step, state=self.shell_state)
        else:
            ratio = controls.shell_hourglass_ratio
            self.bat_shells = ShellForces(model.bat, self.shell_state, hourglass_ratio=ratio)
        self.contact_forces = np.zeros_like(self.points)
        self.spin = np.zeros_like(self.points)  # rotations over the last step (friction)
        for pair in model.contacts:
            if isinstance(pair, ColumnContact):
                pair.rotation_step = self.spin
        self.ball_surface_area = surface_node_areas(model.points[n_bat:], model.ball.cells)
        self.ball_moving = np.ones(self.ball_points.shape[0], dtype=np.bool_)
        self.bat_moving = np.ones(n_bat, dtype=np.bool_)
        self.bat_moving[model.bat.band] = False
        self.band_inertia = np.inf if model.bat.fixed else band_inertia(model)
        self.omega = np.zeros(1)
        self.relax_history: list[float] = []  # bat kinetic energy per relaxation cycle [J]
        self.energies = np.zeros(6)  # ball internal, hourglass, bulk viscosity; bat; contact;
        # the bat's damping (dissipated)
        self.dt = 0.0
        self.time = 0.0
        self.step = 0
        self.phase_seconds = dict.fromkeys(
            ("contact_search", "ball_forces", "bat_forces", "contact_forces", "update"), 0.0
        )
        total_mass = np.sum(model.ball.mass) + np.sum(model.bat.mass[:, 0])
        self.kinetic0 = 0.5 * float(np.sum(model.ball.mass[:, None] * self.ball_velocity**2)
                                    + np.sum(model.bat.mass * self.bat_velocity**2))  # fmt: skip
        self.total_mass = float(total_mass)

    def timed(self, phase: str, start: float) -> float:
        """Add the time since ``start`` to ``phase``; returns now."""
        now = time.perf_counter()
        self.phase_seconds[phase] += now - start
        return now

    def element_forces(self) -> float:
        """Ball and bat internal forces from x^n, v^(n-1/2); returns the new stable step."""
        m = self.model
        clock = time.perf_counter()
        ball_internal_forces(m.ball, self.ball_state, self.ball_points, self.ball_velocity,
                             self.dt, self.ball_forces)  # fmt: skip
        smallest, bad = smallest_step(self.ball_state.cell_dt)
        if bad >= 0:
            raise SimulationError(f"ball element {bad} inverted at t = {self.time * 1e3:.4f} ms "
                                  f"(step {self.step})")  # fmt: skip
        self.timed("ball_forces", clock)
        self.bat_element_forces()
        ball_dt = self.controls.time_step_scale * smallest
        return min(ball_dt, m.bat.stable_step)

    def bat_element_forces(self) -> None:
        """The bat's internal forces from x^n, v^(n-1/2) into ``bat_forces``."""
        clock = time.perf_counter()
        if self.model.bat.rigid:
            self.bat_forces[:] = 0.0
        else:
            self.bat_shells(self.bat_points, self.bat_velocity, self.dt, self.bat_forces)
        self.timed("bat_forces", clock)

    def relax_bat(self, *, interference: float, ramp_steps: int, settle_steps: int,
                  factor: float = RELAX_FACTOR) -> float:  # fmt: skip
        """Dynamic relaxation of the bat alone before the impact (LS-DYNA
        ``*CONTROL_DYNAMIC_RELAXATION``, docs/physics.md section 6.7): the insert contacts' ignored
        initial overlap is reduced by ``interference`` [m] over ``ramp_steps`` (the fit is pressed
        in: the spec's radial interference, not the mesh's overlap, which the facets of the
        polygonal sections enlarge by (R_barrel - R_insert)(1 - cos(pi / n))), then
        ``settle_steps`` more; velocities are scaled by ``factor`` (DRFCTR) each step, the pivot
        is held, and afterwards velocities are zeroed and the clock reset: the pre-stressed
        shells and the closed contacts are the impact's initial state.

        Returns:
            The bat's kinetic energy at the end over its largest value during the relaxation
            (LS-DYNA's DRTOL measure).
        """
        m = self.model
        inserts = m.contacts[m.ball_contacts :]
        contact = np.zeros((self.points.shape[0], 3))
        self.dt = m.bat.stable_step

        def bat_forces() -> np.ndarray:  # the ball, at rest and apart, is not computed
            self.bat_element_forces()
            for pair in inserts:  # the inserts' nodes are the bat's
                pair.add_forces(self.points, contact)
            add_and_clear(self.bat_forces, contact, m.bat.band)  # the pivot band held still
            return self.bat_forces

        ratio = relax_fit(inserts, interference=interference, ramp_steps=ramp_steps,
                          settle_steps=settle_steps, search_interval=self.controls.search_interval,
                          points=self.points, forces=bat_forces, mass=m.bat.mass,
                          velocity=self.bat_velocity, moving=self.bat_moving, dt=self.dt,
                          factor=factor, history=self.relax_history)  # fmt: skip
        self.ball_state = BallState.initial(m.ball, self.controls.precision)
        self.dt, self.energies[:] = 0.0, 0.0
        return ratio

    def contact(self) -> tuple[int, int]:
        """Contact forces of every pair into ``contact_forces``; (ball-bat, insert) slaves."""
        clock = time.perf_counter()
        if self.step % self.controls.search_interval == 0:
            for pair in self.model.contacts:
                pair.search(self.points)
            clock = self.timed("contact_search", clock)
        self.contact_forces[:] = 0.0
        n_bat = self.model.n_bat
        rubbing = [pair for pair in self.model.contacts
                   if isinstance(pair, ColumnContact) and pair.friction > 0.0]  # fmt: skip
        if rubbing:  # the faces' slip needs the walls' rotations over the last step
            self.spin[:n_bat] = self.dt * self.bat_velocity[:, 3:]
        counts = [pair.add_forces(self.points, self.contact_forces) for pair in self.model.contacts]
        for pair in rubbing:  # the friction's moments at the faces
            self.bat_forces[:, 3:] += pair.moments[:n_bat]
        self.timed("contact_forces", clock)
        k = self.model.ball_contacts
        return sum(counts[:k]), sum(counts[k:])

    def cycle(self, row: np.ndarray) -> bool:
        """One explicit cycle; writes the history row; returns whether the ball touches the bat."""
        m, n_bat, c = self.model, self.model.n_bat, self.controls
        dt_old = self.dt
        dt_new = self.element_forces()
        ball_touching, insert_touching = self.contact()
        clock = time.perf_counter()
        half = 0.5 * (dt_old + dt_new)
        ball, bat = self.ball_sums, self.bat_sums
        advance_ball(self.ball_forces, self.contact_forces[n_bat:], m.ball.mass,
                     self.ball_velocity, self.ball_points, m.bat.pivot, half, dt_old, dt_new,
                     ball)  # fmt: skip
        advance_bat(self.bat_forces, self.contact_forces[:n_bat], m.bat.mass, self.bat_velocity,
                    self.bat_points, self.bat_moving, m.bat.band, m.bat.pivot,
                    self.band_inertia, self.omega, 0.0 if m.bat.rigid else c.bat_damping,
                    self.damping_forces, half, dt_old, dt_new, bat)  # fmt: skip
        self.write_row(row, ball_touching, insert_touching)
        self.time += dt_new
        self.dt = dt_new
        self.step += 1
        self.timed("update", clock)
        return ball_touching > 0

    def write_row(self, row: np.ndarray, ball_touching: int, insert_touching: int) -> None:
        """The energies and the history row of this cycle (HISTORY_COLUMNS) from the sums of
        the update (:func:`close_cycle`); a SimulationError if the balance has run away."""
        balance = close_cycle(self.energies, self.ball_state.energy_increments, self.ball_sums,
                              self.bat_sums, self.model.bat.rigid, self.kinetic0, self.time,
                              self.ball_total_mass, self.pivot_inertia, ball_touching,
                              insert_touching, row)  # fmt: skip
        if (
            not np.isfinite(balance)
            or abs(balance) > self.controls.max_energy_error * self.kinetic0
        ):
            raise SimulationError(
                f"energy balance error {100 * balance / self.kinetic0:+.1f} % of the initial "
                f"kinetic energy at t = {self.time * 1e3:.4f} ms (step {self.step}): the coupled "
                f"run is unstable (time step too large or contact too stiff)"
            )

    @property
    def pivot_inertia(self) -> float:
        """The lumped bat's MOI about the pivot axis [kg m^2]."""
        if not hasattr(self, "_pivot_inertia"):
            self._pivot_inertia = pivot_inertia(self.model)
        return self._pivot_inertia

    def run(self) -> CoupledResult:
        """Advance to the end time, or until the ball has left the bat for ``separation_time``."""
        c = self.controls
        rows = np.zeros((4096, len(HISTORY_COLUMNS)))
        n_rows, contact_began, last_contact, peak, smooth = 0, -1.0, -1.0, -1.0, 0.0
        peak_points = self.points.copy()
        frames = (FrameRecorder(c.end_time / max(c.frame_count, 1)), FrameRecorder(np.inf))
        # the ball's recorder says when; the bat's keeps a frame each time the ball's does
        start = time.perf_counter()
        self.record_frames(frames)
        while self.time < c.end_time:
            if n_rows == len(rows):
                rows = np.concatenate((rows, np.zeros_like(rows)))
            touching = self.cycle(rows[n_rows])
            force = rows[n_rows, 1]
            n_rows += 1
            if touching:
                contact_began = self.time if contact_began < 0 else contact_began
                last_contact = self.time
            if frames[0].due(self.time):
                self.record_frames(frames)
            smooth += min(1.0, self.dt / PEAK_SMOOTHING) * (force - smooth)
            if smooth > peak:
                peak = smooth
                peak_points[:] = self.points
            if (
                c.separation_time is not None
                and last_contact > 0
                and self.time - last_contact > c.separation_time
            ):
                break
        if contact_began < 0:
            raise SimulationError(f"the ball never reached the bat by {c.end_time * 1e3:.2f} ms")
        self.record_frames(frames, last=True)
        (frame_times, ball_frames), (_, bat_frames) = (f.stacked() for f in frames)
        return CoupledResult(rows[:n_rows].copy(), peak_points - self.model.points, self.step,
                             time.perf_counter() - start, dict(self.phase_seconds),
                             self.pivot_inertia, float(self.model.ball.mass.sum()),
                             frame_times=frame_times, ball_frames=ball_frames,
                             bat_frames=bat_frames)  # fmt: skip

    def record_frames(self, frames: tuple[FrameRecorder, FrameRecorder], *,
                      last: bool = False) -> None:  # fmt: skip
        """Keep the ball's and the bat's fields now if a frame is due (``frames[0]`` says), or
        it is the ``last``."""
        ball, bat = frames
        if last:
            ball.add(self.time, self.ball_frame())
        elif not ball.record(self.time, self.ball_frame):
            return
        bat.add(self.time, self.bat_frame())

    def ball_frame(self) -> Frame:
        """The ball's fields now (:func:`batball.solvers.frames.ball_frame`)."""
        m, state, n_bat = self.model, self.ball_state, self.model.n_bat
        if m.ball.foam is not None:
            stress = foam_cell_stress(state.foam_history)
        else:
            stress = hex_cell_stress(state.history, m.ball.cells.shape[0])
        volume = state.cell_volume if self.step else m.ball.volume0
        return ball_frame(self.ball_points - m.points[n_bat:], self.ball_velocity,
                          self.contact_forces[n_bat:], self.ball_surface_area, stress, volume,
                          m.ball.volume0)  # fmt: skip

    def bat_frame(self) -> Frame:
        """The bat's fields now (:func:`batball.solvers.frames.bat_frame`)."""
        m, n_bat = self.model, self.model.n_bat
        von_mises = None
        if isinstance(self.shell_state, ShellForceState):
            if not hasattr(self, "_ply_thickness"):  # (n_cells, n_layers), made at the first frame
                section = m.bat.section
                self._ply_thickness = section.layer_thickness[section.cell_laminate]
            von_mises = ply_von_mises(self.shell_state, self._ply_thickness)
        return bat_frame(self.bat_points - m.points[:n_bat], self.bat_velocity,
                         self.contact_forces[:n_bat], von_mises)  # fmt: skip
