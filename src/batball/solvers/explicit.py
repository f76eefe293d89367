"""Explicit central-difference dynamics of a hex-meshed body against rigid targets.

A cycle is two compiled calls: the element forces (with the stress update), then
:func:`~batball.solvers.explicit_kernels.finish_cycle` (contact forces, time step, assembly and
central-difference update, energy checks and the history row); the Python loop around them only
keeps frames and progress. Energies (kinetic, internal, hourglass, bulk viscosity, contact,
damping) are kept every step and their balance against the initial kinetic energy plus the
external work is reported. Optional mass-proportional damping turns the run into a dynamic
relaxation (quasi-static tests). A run stops with a :class:`~batball.errors.SimulationError`
that says where and when if an element inverts, the time step collapses, the energy runs away
or a value turns non-finite.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numba as nb
import numpy as np

from batball.contact.rigid import N_TARGET_PARAMS, RigidCylinder, RigidPlane
from batball.elements.hex8 import HOURGLASS_TYPES, hex8_kernel_call, kernel_ids
from batball.elements.hex8_block import PRECISIONS, check_precision, constants_terms, pack_history
from batball.elements.hex8_foam import (
    N_FOAM_HISTORY,
    N_REFERENCE,
    foam_reference_gradients,
    foam_solver_call,
)
from batball.errors import SimulationError, SpecError
from batball.materials.foam import FoamTable
from batball.mesh import Mesh
from batball.solvers import explicit_kernels as kern
from batball.solvers.explicit_kernels import lumped_masses, slot_node_ranges
from batball.solvers.frames import (
    Frame,
    FrameRecorder,
    ball_frame,
    foam_cell_stress,
    hex_cell_stress,
    surface_node_areas,
)
from batball.units import IN

#: A run with a progress callback calls it every this many cycles.
PROGRESS_STEPS = 200


@dataclass(frozen=True)
class HourglassControl:
    """LS-DYNA ``*HOURGLASS``: type IHQ (1, 2/3 viscous; 4/5 stiffness) and coefficient QH/QM.

    The default, IHQ = 1 with QH = 0.1, is LS-DYNA's default for one-point solids, which the seed
    study used (it names no hourglass card).
    """

    type: int = 1
    coefficient: float = 0.1

    def __post_init__(self) -> None:
        if self.type not in HOURGLASS_TYPES:
            raise SpecError("hourglass.type", self.type, f"one of {sorted(HOURGLASS_TYPES)}")
        if not 0.0 <= self.coefficient <= 0.5:
            raise SpecError("hourglass.coefficient", self.coefficient, "0 <= QH <= 0.5")


@dataclass(frozen=True)
class BulkViscosity:
    """LS-DYNA ``*CONTROL_BULK_VISCOSITY``: quadratic Q1 and linear Q2 (defaults 1.5, 0.06)."""

    q1: float = 1.5
    q2: float = 0.06
    enabled: bool = True

    def __post_init__(self) -> None:
        if self.q1 < 0 or self.q2 < 0:
            raise SpecError("bulk_viscosity", (self.q1, self.q2), "q1 >= 0 and q2 >= 0")


@dataclass(frozen=True)
class ExplicitControls:
    """Run controls.

    Attributes:
        end_time: the longest the run goes [s].
        time_step_scale: TSSFAC, the fraction of the stable step used (LS-DYNA default 0.9).
        hourglass, bulk_viscosity: element controls.
        separation_time: stop once every contact force has been zero this long after contact
            began [s]; None runs to ``end_time``.
        frame_count: about how many field frames to keep for ParaView
            (:mod:`batball.solvers.frames`).
        max_energy_error: stop if the energy balance error exceeds this fraction of the initial
            kinetic energy (a run-away).
        min_step_ratio: stop if the step falls below this fraction of the first step.
        mass_damping: mass-proportional damping coefficient c [1/s] (the force -c m v on every
            node; 0 = none). Dynamic relaxation uses about twice the lowest circular frequency.
        precision: "double" or "single", the element arithmetic of the viscoelastic (MAT_006,
            Prony) hex kernel (``hex8_block.PRECISIONS``; LS-DYNA's default executable is
            single). Nodes, contact, time integration and energy sums stay double; foam balls
            run their own kernel in double.
        energy_floor: the smallest energy [J] the balance check compares against, for runs that
            start at rest (the reference is the larger of the initial kinetic energy and the
            external work done by the targets): set it to a small fraction of the work the test
            is expected to do, so that the round-off of the first contact steps, when every
            energy is tiny, is not taken for a run-away.
    """

    end_time: float
    time_step_scale: float = 0.9
    hourglass: HourglassControl = field(default_factory=HourglassControl)
    bulk_viscosity: BulkViscosity = field(default_factory=BulkViscosity)
    separation_time: float | None = None
    frame_count: int = 40
    max_energy_error: float = 0.1
    min_step_ratio: float = 1e-3
    mass_damping: float = 0.0
    energy_floor: float = 1e-9
    precision: str = "double"

    def __post_init__(self) -> None:
        check_precision(self.precision)
        if not self.end_time > 0:
            raise SpecError("end_time", self.end_time, "a positive time")
        if not 0 < self.time_step_scale <= 1:
            raise SpecError("time_step_scale", self.time_step_scale, "0 < TSSFAC <= 1")
        if not (np.isfinite(self.mass_damping) and self.mass_damping >= 0):
            raise SpecError("mass_damping", self.mass_damping, "a damping coefficient >= 0 1/s")


@dataclass(frozen=True)
class RigidContact:
    """A rigid target and the body nodes that may touch it, with their penalty stiffness.

    Attributes:
        target: the fixture surface.
        node_ids: (n_slaves,) body node ids; stiffness: (n_slaves,) [N/m].
    """

    name: str
    target: RigidPlane | RigidCylinder
    node_ids: np.ndarray
    stiffness: np.ndarray


@dataclass(frozen=True)
class Model:
    """What is simulated; it does not change during a run.

    Attributes:
        mesh: the body's hex mesh.
        cell_material: (n_cells,) row into ``material_constants`` and ``densities``.
        material_constants: (n_materials, 2 N + 2) K, G0, G_inf [Pa], beta_1 [1/s], then (G_i [Pa],
            beta_i [1/s]) of Prony terms 2..N (N = 1 for MAT_006; see MaterialLaw).
        densities: (n_materials,) [kg/m^3].
        contacts: the rigid targets.
        initial_velocity: (n_points, 3) [m/s].
        foam: a foam body's packed material (:class:`batball.materials.foam.FoamTable`): every
            cell is then that foam, run by the foam kernel (``material_constants`` holds its
            isotropic stand-ins); None for the viscoelastic/elastic kernel.
    """

    mesh: Mesh
    cell_material: np.ndarray
    material_constants: np.ndarray
    densities: np.ndarray
    contacts: tuple[RigidContact, ...]
    initial_velocity: np.ndarray
    foam: FoamTable | None = None


@dataclass
class State:
    """The evolving state: positions x^n, velocities v^(n-1/2) and the element histories.

    ``clock`` and ``counters`` hold time, step sizes, contact times and the step count in the
    slots named in :mod:`batball.solvers.explicit_kernels`. ``history`` is the viscoelastic
    element history in the hex kernel's block layout (``hex8_block.unpack_history`` gives the
    element-wise stresses); a foam body keeps ``foam_history`` and ``hg_state`` instead.
    """

    clock: np.ndarray
    counters: np.ndarray
    points: np.ndarray
    velocities: np.ndarray
    history: np.ndarray
    hg_state: np.ndarray
    energies: np.ndarray  # internal, hourglass, bulk viscosity, contact, damping [J]
    foam_history: np.ndarray = field(default_factory=lambda: np.zeros((0, N_FOAM_HISTORY)))

    @property
    def time(self) -> float:
        """t^n [s]."""
        return float(self.clock[kern.TIME])

    @property
    def dt(self) -> float:
        """The step dt^(n-1/2) that led to x^n [s]."""
        return float(self.clock[kern.DT])

    @dt.setter
    def dt(self, value: float) -> None:
        self.clock[kern.DT] = value

    @property
    def step(self) -> int:
        """Cycles taken."""
        return int(self.counters[kern.STEP])


@dataclass(frozen=True)
class ExplicitResult:
    """Histories (one row per step) and field frames of a run.

    Attributes:
        time: (n_steps,) [s].
        reaction: (n_steps, n_contacts, 3) force of the body on each target [N].
        com_velocity: (n_steps, 3) body centre-of-mass velocity [m/s].
        energies: (n_steps, 7) kinetic, internal, hourglass, bulk viscosity, contact, damping,
            balance error (all [J], in ``ENERGY_COLUMNS`` order; the error is the total minus the
            initial kinetic energy, the contact energy being minus the work of the targets).
        contact_nodes: (n_steps,) nodes in contact.
        penetration: (n_steps, n_contacts) deepest penetration into each target [m].
        frame_times: (n_frames,) [s]; frames: (n_frames, n_points, 3) displacements [m].
        mass: total mass [kg]; phase_seconds: wall time [s] of the compiled loops over cycles
            (``cycles``: element kernel, contact, step, update and records) and of what the run
            does between them (``frames``: frames, progress); ``ExplicitSolver.cycle`` times its
            two calls apart instead (``element_forces``, ``rest_of_cycle``).
        frame_data: every field of the frames by name, (n_frames, ...) float32, displacement,
            velocity, contact force and pressure, stress and its invariants, volumetric strain
            (:mod:`batball.solvers.frames`; ``frames`` is its displacement).
    """

    time: np.ndarray
    reaction: np.ndarray
    com_velocity: np.ndarray
    energies: np.ndarray
    contact_nodes: np.ndarray
    penetration: np.ndarray
    frame_times: np.ndarray
    frames: np.ndarray
    mass: float
    n_steps: int
    wall_seconds: float
    phase_seconds: dict[str, float]
    frame_data: Frame = field(default_factory=dict)

    @property
    def max_penetration(self) -> float:
        """The deepest any node went into any target over the run [m] (the penalty's own
        compliance; 0 without contact)."""
        return float(self.penetration.max()) if self.penetration.size else 0.0


ENERGY_COLUMNS = (
    "kinetic",
    "internal",
    "hourglass",
    "bulk_viscosity",
    "contact",
    "damping",
    "balance_error",
)
BALANCE = ENERGY_COLUMNS.index("balance_error")


def initial_state(model: Model, volume0: np.ndarray, precision: str = "double") -> State:
    """The state at t = 0: undeformed, unstressed, moving with the initial velocity (element
    volumes ``volume0`` [m^3]; the hex kernel's history in ``precision``)."""
    n_cells = model.mesh.n_cells
    n_terms = constants_terms(model.material_constants)
    clock = np.zeros(5)
    clock[[kern.CONTACT_BEGAN, kern.LAST_CONTACT]] = -1.0
    return State(
        clock=clock,
        counters=np.zeros(2, dtype=np.int64),
        points=model.mesh.points.copy(),
        velocities=model.initial_velocity.copy(),
        history=pack_history(volume0, n_terms=n_terms, dtype=PRECISIONS[precision]),
        hg_state=np.zeros((n_cells if model.foam else 0, 4, 3)),
        energies=np.zeros(kern.N_ENERGIES),
        foam_history=np.zeros((n_cells if model.foam else 0, N_FOAM_HISTORY)),
    )


class _Workspace:
    """Arrays reused every cycle, and the constants derived once from the model."""

    def __init__(self, model: Model, controls: ExplicitControls) -> None:
        mesh = model.mesh
        from batball.mesh import hex_volumes

        self.volume0 = hex_volumes(mesh.points, mesh.cells)
        bad = np.flatnonzero(~(self.volume0 > 0))
        if bad.size:
            raise SpecError(
                f"mesh.cells[{bad[0]}]",
                float(self.volume0[bad[0]]),
                "every element with a positive volume",
            )
        cell_mass = model.densities[model.cell_material] * self.volume0
        self.cells = kernel_ids(mesh.cells)
        self.cell_material = kernel_ids(model.cell_material)
        self.foam_reference = (
            foam_reference_gradients(self.cells, mesh.points)
            if model.foam is not None
            else np.zeros((0, N_REFERENCE))
        )
        self.mass = lumped_masses(mesh.cells, cell_mass, mesh.n_points)
        self.cell_volume = np.zeros(mesh.n_cells)
        self.cell_dt = np.zeros(mesh.n_cells)
        # one slot of element forces per thread (see compute_hex8_forces)
        n_slots = max(1, min(mesh.n_cells, nb.get_num_threads()))
        self.nodal_forces = np.zeros((n_slots, mesh.n_points, 3))
        self.energy_increments = np.zeros((n_slots, 3))
        self.contact_forces = np.zeros((mesh.n_points, 3))
        slot_nodes = slot_node_ranges(mesh.cells, n_slots)
        self.surface_area = surface_node_areas(mesh.points, mesh.cells)  # frames' contact pressure
        self.reaction = np.zeros((len(model.contacts), 3))
        self.contacts = packed_contacts(model.contacts, self.reaction)
        contact_nodes, contact_slots = kern.contact_node_slots(self.contacts[0], slot_nodes)
        n = mesh.n_points
        self.nodes = (slot_nodes, self.mass, self.contact_forces, np.zeros(6), contact_nodes,
                      contact_slots, (np.zeros(n), kern.sum_blocks(n)))  # fmt: skip
        bv = controls.bulk_viscosity
        self.q1, self.q2 = (bv.q1, bv.q2) if bv.enabled else (0.0, 0.0)
        self.row_width = 1 + 4 * len(model.contacts) + 3 + len(ENERGY_COLUMNS) + 1


def packed_contacts(contacts: tuple[RigidContact, ...], reaction: np.ndarray) -> tuple:
    """The kernel form of the targets: (node_ids, stiffness, offsets, kinds, params, reaction,
    penetration)."""
    packed = [c.target.packed() for c in contacts]
    sizes = [len(c.node_ids) for c in contacts]
    offsets = np.zeros(len(contacts) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    node_ids = np.concatenate([c.node_ids for c in contacts] or [np.zeros(0)]).astype(np.int64)
    stiffness = np.concatenate([c.stiffness for c in contacts] or [np.zeros(0)]).astype(float)
    kinds = np.array([k for k, _ in packed], dtype=np.int64)
    params = np.array([p for _, p in packed]).reshape(len(contacts), N_TARGET_PARAMS)
    return node_ids, stiffness, offsets, kinds, params, reaction, np.zeros(len(contacts))


class _Recorder:
    """Per-step history rows in a growing table, and field frames at a fixed interval."""

    def __init__(self, n_contacts: int, width: int, frame_interval: float) -> None:
        self.table = np.zeros((4096, width))
        self.n_rows = 0
        self.n_contacts = n_contacts
        self.frames = FrameRecorder(frame_interval)

    def make_room(self) -> None:
        """At least one free row for the next cycle (the table doubles when full)."""
        if self.n_rows == len(self.table):
            self.table = np.concatenate((self.table, np.zeros_like(self.table)))

    def arrays(self) -> dict[str, np.ndarray]:
        table = self.table[: self.n_rows]
        nc = 3 * self.n_contacts
        n_e = len(ENERGY_COLUMNS)
        return {
            "time": table[:, 0].copy(),
            "reaction": table[:, 1 : 1 + nc].reshape(len(table), self.n_contacts, 3),
            "com_velocity": table[:, 1 + nc : 4 + nc],
            "energies": table[:, 4 + nc : 4 + nc + n_e],
            "contact_nodes": table[:, 4 + nc + n_e].astype(np.int64),
            "penetration": table[:, 5 + nc + n_e :].copy(),
        }


class ExplicitSolver:
    """Runs a :class:`Model` with :class:`ExplicitControls`."""

    def __init__(self, model: Model, controls: ExplicitControls) -> None:
        self.model = model
        self.controls = controls
        self.work = _Workspace(model, controls)
        self.state = initial_state(model, self.work.volume0, controls.precision)
        self.phase_seconds = {"element_forces": 0.0, "rest_of_cycle": 0.0, "cycles": 0.0,
                              "frames": 0.0}  # fmt: skip
        self.kinetic0 = float(0.5 * np.sum(self.work.mass[:, None] * model.initial_velocity**2))
        self.total_mass = float(self.work.mass.sum())
        limits = np.zeros(8)
        limits[kern.TSSFAC] = controls.time_step_scale
        limits[kern.MIN_STEP_RATIO] = controls.min_step_ratio
        limits[kern.DAMPING] = controls.mass_damping
        sep = controls.separation_time
        limits[kern.SEPARATION_TIME] = -1.0 if sep is None else sep
        limits[kern.KINETIC0] = self.kinetic0
        limits[kern.MAX_ENERGY_ERROR] = controls.max_energy_error
        limits[kern.TOTAL_MASS] = self.total_mass
        limits[kern.ENERGY_FLOOR] = controls.energy_floor
        self.limits = limits
        self.scratch_row = np.zeros(self.work.row_width)
        self.separated = False  # set by each cycle: contact ended long enough ago

    def kernel_call(self) -> tuple[Callable, tuple, tuple]:
        """The element kernel on the state's arrays as they are now: (kernel, arguments,
        controls) of :func:`batball.elements.hex8.hex8_kernel_call` (or the foam's)."""
        s, w, m, c = self.state, self.work, self.model, self.controls.hourglass
        if m.foam is not None:  # a foam body has its own element kernel
            return foam_solver_call(m, s.points, s.velocities, w, s.foam_history, s.hg_state, c)
        return hex8_kernel_call(
            s.points, s.velocities, w.cells, w.cell_material, m.material_constants, m.densities,
            s.history, c.type, c.coefficient, w.q1, w.q2, w.nodal_forces, w.cell_volume,
            w.cell_dt, w.energy_increments,
        )  # fmt: skip

    def finish_arguments(self) -> tuple:
        """:func:`kern.finish_cycle`'s arguments but the row, on the state's arrays."""
        s, w = self.state, self.work
        return (w.energy_increments, w.cell_dt, w.nodal_forces, w.nodes, w.contacts, s.points,
                s.velocities, s.clock, s.counters, s.energies, self.limits)  # fmt: skip

    def element_forces(self) -> None:
        """Stress update and element nodal forces from x^n and v^(n-1/2)."""
        kernel, arguments, controls = self.kernel_call()
        kernel(*arguments, (self.state.dt, *controls))

    def finish(self, row: np.ndarray) -> int:
        """Contact, time step, update, checks and the history row (one compiled call)."""
        return int(kern.finish_cycle(*self.finish_arguments(), row))  # type: ignore[call-arg]

    def cycle(self, row: np.ndarray | None = None) -> tuple[float, int]:
        """One explicit cycle; returns (kinetic energy, nodes in contact). Stops on failure."""
        row = self.scratch_row if row is None else row
        clock = time.perf_counter
        t0 = clock()
        self.element_forces()
        t1 = clock()
        status = self.finish(row)
        self.phase_seconds["element_forces"] += t1 - t0
        self.phase_seconds["rest_of_cycle"] += clock() - t1
        if status < 0:
            self.raise_failure(status, row)
        self.separated = status == kern.CYCLE_SEPARATED
        nc = 3 * len(self.model.contacts)
        n_e = len(ENERGY_COLUMNS)
        return float(row[4 + nc]), int(row[4 + nc + n_e])

    def raise_failure(self, status: int, row: np.ndarray) -> None:
        """Stop with a message that says what failed, where and when."""
        s, w = self.state, self.work
        e = int(s.counters[kern.ELEMENT])
        when = f"t = {s.time * 1e3:.4f} ms (step {s.step})"
        if status == kern.FAIL_INVERTED:
            bad = np.flatnonzero(~(w.cell_volume > 0))
            e = int(bad[0]) if bad.size else e
            raise SimulationError(
                f"element {e} inverted at {when}: volume {w.cell_volume[e] / IN**3:.3e} in^3 "
                f"(initial {w.volume0[e] / IN**3:.3e} in^3); {bad.size} element(s) without "
                f"positive volume"
            )
        if status == kern.FAIL_STEP_COLLAPSE:
            first = s.clock[kern.FIRST_DT]
            raise SimulationError(
                f"time step collapsed at {when}: {s.dt:.3e} s, below "
                f"{self.controls.min_step_ratio:g} of the first step {first:.3e} s; smallest in "
                f"element {e}"
            )
        if status == kern.FAIL_NON_FINITE:
            if np.isnan(w.cell_dt[e]):
                raise SimulationError(f"element {e}'s stable time step is NaN at {when}")
            raise SimulationError(f"non-finite kinetic energy or energy balance at {when}")
        balance = row[3 + 3 * len(self.model.contacts) + len(ENERGY_COLUMNS)]
        external = abs(s.energies[kern.CONTACT_ENERGY])
        reference = max(self.kinetic0, external, self.controls.energy_floor)
        raise SimulationError(
            f"energy balance error reached {100 * balance / reference:+.1f} % of the initial "
            f"kinetic energy plus external work at {when}: the run is unstable (time step too "
            f"large or contact too stiff)"
        )

    def run(self, *, progress: Callable[[float], None] | None = None) -> ExplicitResult:
        """Advance to ``end_time`` or separation; record histories every step."""
        c, s = self.controls, self.state
        rec = _Recorder(
            len(self.model.contacts), self.work.row_width, c.end_time / max(c.frame_count, 1)
        )
        start = time.perf_counter()
        frames = rec.frames
        frames.record(0.0, self.frame)
        phases = self.phase_seconds
        while s.clock[kern.TIME] < c.end_time and not self.separated:
            rec.make_room()
            kernel, arguments, controls = self.kernel_call()
            begin = time.perf_counter()
            status, rec.n_rows = kern.run_cycles(
                kernel, arguments, controls, self.finish_arguments(), rec.table, rec.n_rows,
                c.end_time, frames.next_time, 0 if progress is None else PROGRESS_STEPS,
            )  # fmt: skip
            between = time.perf_counter()
            phases["cycles"] += between - begin
            if status < 0:
                self.raise_failure(status, rec.table[rec.n_rows])
            self.separated = status == kern.CYCLE_SEPARATED
            t = s.clock[kern.TIME]
            if frames.due(t):
                frames.record(t, self.frame)
            if progress is not None and s.counters[kern.STEP] % PROGRESS_STEPS == 0:
                progress(t)
            phases["frames"] += time.perf_counter() - between
        frames.add(s.time, self.frame())
        return self.result(rec, time.perf_counter() - start)

    def frame(self) -> Frame:
        """The fields of the current state (:func:`batball.solvers.frames.ball_frame`)."""
        s, w, m = self.state, self.work, self.model
        if m.foam is not None:
            stress = foam_cell_stress(s.foam_history)
        else:
            stress = hex_cell_stress(s.history, m.mesh.n_cells)
        volume = w.cell_volume if s.step else w.volume0  # no cycle yet: the undeformed cells
        return ball_frame(s.points - m.mesh.points, s.velocities, w.contact_forces,
                          w.surface_area, stress, volume, w.volume0)  # fmt: skip

    def result(self, rec: _Recorder, wall: float) -> ExplicitResult:
        """Package the recorded histories."""
        arrays = rec.arrays()
        frame_times, frame_data = rec.frames.stacked()
        return ExplicitResult(
            time=arrays["time"],
            reaction=arrays["reaction"],
            com_velocity=arrays["com_velocity"],
            energies=arrays["energies"],
            contact_nodes=arrays["contact_nodes"],
            penetration=arrays["penetration"],
            frame_times=frame_times,
            frames=frame_data["displacement"],
            mass=self.total_mass,
            n_steps=self.state.step,
            wall_seconds=wall,
            phase_seconds=dict(self.phase_seconds),
            frame_data=frame_data,
        )


def run_explicit(
    model: Model, controls: ExplicitControls, *, progress: Callable[[float], None] | None = None
) -> ExplicitResult:
    """Run ``model`` under ``controls`` (see :class:`ExplicitSolver`)."""
    return ExplicitSolver(model, controls).run(progress=progress)
