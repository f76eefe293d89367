"""Explicit central-difference dynamics of a hex-meshed body against rigid targets.

The cycle runs as named, timed phases (STYLE.md rule 4): element forces (with the stress update),
assembly, contact forces, time step, update. Energies (kinetic, internal, hourglass, bulk
viscosity, contact) are kept every step and their balance against the initial kinetic energy is
reported. A run stops with a :class:`~batball.errors.SimulationError` that says where and when if an
element inverts, the time step collapses, the energy runs away or a value turns non-finite.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numba as nb
import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane, add_rigid_contact_forces
from batball.elements.hex8 import HOURGLASS_TYPES, compute_hex8_forces
from batball.errors import SimulationError, SpecError
from batball.mesh import Mesh
from batball.solvers.explicit_kernels import (
    assemble_nodal_forces,
    central_difference_update,
    lumped_masses,
    node_cell_map,
)

IN = 0.0254  # m, for messages a person reads


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
        frame_count: about how many displacement frames to keep for ParaView.
        max_energy_error: stop if the energy balance error exceeds this fraction of the initial
            kinetic energy (a run-away).
        min_step_ratio: stop if the step falls below this fraction of the first step.
    """

    end_time: float
    time_step_scale: float = 0.9
    hourglass: HourglassControl = field(default_factory=HourglassControl)
    bulk_viscosity: BulkViscosity = field(default_factory=BulkViscosity)
    separation_time: float | None = None
    frame_count: int = 40
    max_energy_error: float = 0.1
    min_step_ratio: float = 1e-3

    def __post_init__(self) -> None:
        if not self.end_time > 0:
            raise SpecError("end_time", self.end_time, "a positive time")
        if not 0 < self.time_step_scale <= 1:
            raise SpecError("time_step_scale", self.time_step_scale, "0 < TSSFAC <= 1")


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
        material_constants: (n_materials, 4) K, G0, G_inf [Pa], beta [1/s].
        densities: (n_materials,) [kg/m^3].
        contacts: the rigid targets.
        initial_velocity: (n_points, 3) [m/s].
    """

    mesh: Mesh
    cell_material: np.ndarray
    material_constants: np.ndarray
    densities: np.ndarray
    contacts: tuple[RigidContact, ...]
    initial_velocity: np.ndarray


@dataclass
class State:
    """The evolving state: positions x^n, velocities v^(n-1/2) and the element histories."""

    time: float
    step: int
    dt: float
    points: np.ndarray
    velocities: np.ndarray
    s_inf: np.ndarray
    h: np.ndarray
    pressure: np.ndarray
    hg_state: np.ndarray
    energies: np.ndarray  # internal, hourglass, bulk viscosity, contact [J]


@dataclass(frozen=True)
class ExplicitResult:
    """Histories (one row per step) and displacement frames of a run.

    Attributes:
        time: (n_steps,) [s].
        reaction: (n_steps, n_contacts, 3) force of the body on each target [N].
        com_velocity: (n_steps, 3) body centre-of-mass velocity [m/s].
        energies: (n_steps, 6) kinetic, internal, hourglass, bulk viscosity, contact, balance
            error (all [J]; the error is total minus initial kinetic energy).
        contact_nodes: (n_steps,) nodes in contact.
        frame_times: (n_frames,) [s]; frames: (n_frames, n_points, 3) displacements [m].
        mass: total mass [kg]; phase_seconds: wall time of each phase [s].
    """

    time: np.ndarray
    reaction: np.ndarray
    com_velocity: np.ndarray
    energies: np.ndarray
    contact_nodes: np.ndarray
    frame_times: np.ndarray
    frames: np.ndarray
    mass: float
    n_steps: int
    wall_seconds: float
    phase_seconds: dict[str, float]


ENERGY_COLUMNS = ("kinetic", "internal", "hourglass", "bulk_viscosity", "contact", "balance_error")


def initial_state(model: Model) -> State:
    """The state at t = 0: undeformed, unstressed, moving with the initial velocity."""
    n_cells = model.mesh.n_cells
    return State(
        time=0.0,
        step=0,
        dt=0.0,
        points=model.mesh.points.copy(),
        velocities=model.initial_velocity.copy(),
        s_inf=np.zeros((n_cells, 6)),
        h=np.zeros((n_cells, 3 * model.material_constants.shape[1] - 6)),  # 6 per Prony term
        pressure=np.zeros(n_cells),
        hg_state=np.zeros((n_cells, 4, 3)),
        energies=np.zeros(4),
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
        self.mass = lumped_masses(mesh.cells, cell_mass, mesh.n_points)
        self.offsets, self.entries = node_cell_map(mesh.cells, mesh.n_points)
        self.cell_forces = np.zeros((mesh.n_cells, 24))
        self.cell_volume = np.zeros(mesh.n_cells)
        self.cell_dt = np.zeros(mesh.n_cells)
        self.n_chunks = max(1, min(mesh.n_cells, 16 * nb.get_num_threads()))
        self.energy_increments = np.zeros((self.n_chunks, 3))
        self.forces = np.zeros((mesh.n_points, 3))
        self.contact_forces = np.zeros((mesh.n_points, 3))
        self.momentum = np.zeros(3)
        self.reaction = np.zeros((len(model.contacts), 3))
        self.packed = [c.target.packed() for c in model.contacts]
        bv = controls.bulk_viscosity
        self.q1, self.q2 = (bv.q1, bv.q2) if bv.enabled else (0.0, 0.0)


class _Recorder:
    """Per-step histories in growing arrays, and displacement frames at a fixed interval."""

    def __init__(self, n_contacts: int, frame_interval: float) -> None:
        self.rows: list[np.ndarray] = []
        self.n_contacts = n_contacts
        self.frame_interval = frame_interval
        self.next_frame = 0.0
        self.frame_times: list[float] = []
        self.frames: list[np.ndarray] = []

    def record(
        self, t: float, reaction: np.ndarray, com_v: np.ndarray, energies: np.ndarray, n_active: int
    ) -> None:
        self.rows.append(np.concatenate(([t], reaction.ravel(), com_v, energies, [n_active])))

    def maybe_frame(self, t: float, displacement: Callable[[], np.ndarray]) -> None:
        if t >= self.next_frame:
            self.frame_times.append(t)
            self.frames.append(displacement().astype(np.float32))
            self.next_frame += self.frame_interval

    def arrays(self) -> dict[str, np.ndarray]:
        table = np.array(self.rows)
        nc = 3 * self.n_contacts
        return {
            "time": table[:, 0],
            "reaction": table[:, 1 : 1 + nc].reshape(-1, self.n_contacts, 3),
            "com_velocity": table[:, 1 + nc : 4 + nc],
            "energies": table[:, 4 + nc : 10 + nc],
            "contact_nodes": table[:, 10 + nc].astype(np.int64),
        }


class ExplicitSolver:
    """Runs a :class:`Model` with :class:`ExplicitControls`; each phase is a method and is timed."""

    def __init__(self, model: Model, controls: ExplicitControls) -> None:
        self.model = model
        self.controls = controls
        self.work = _Workspace(model, controls)
        self.state = initial_state(model)
        self.phase_seconds = {
            p: 0.0 for p in ("element_forces", "assembly", "contact", "time_step", "update")
        }
        self.kinetic0 = float(0.5 * np.sum(self.work.mass[:, None] * model.initial_velocity**2))
        self.first_dt = 0.0
        self.total_mass = float(self.work.mass.sum())  # kg; read every step, so summed once


    def element_forces(self) -> None:
        """Stress update and element nodal forces from x^n and v^(n-1/2)."""
        s, w, m, c = self.state, self.work, self.model, self.controls.hourglass
        compute_hex8_forces(
            s.points,
            s.velocities,
            m.mesh.cells,
            s.dt,
            m.cell_material,
            m.material_constants,
            m.densities,
            w.volume0,
            s.s_inf,
            s.h,
            s.pressure,
            s.hg_state,
            c.type,
            c.coefficient,
            w.q1,
            w.q2,
            w.cell_forces,
            w.cell_volume,
            w.cell_dt,
            w.energy_increments,
        )
        s.energies[:3] += w.energy_increments.sum(axis=0)

    def assembly(self) -> None:
        """Gather element forces to nodes."""
        w = self.work
        assemble_nodal_forces(w.cell_forces, w.offsets, w.entries, w.forces)

    def contact(self) -> int:
        """Penalty forces of every rigid target; returns the number of nodes in contact."""
        w = self.work
        w.contact_forces[:] = 0.0
        n_active = 0
        for k, contact in enumerate(self.model.contacts):
            kind, params = w.packed[k]
            n_active += add_rigid_contact_forces(
                self.state.points,
                contact.node_ids,
                contact.stiffness,
                kind,
                params,
                w.contact_forces,
                w.reaction[k],
            )
        return n_active

    def time_step(self) -> float:
        """The next step: TSSFAC times the smallest element step; stops on failure."""
        w, s = self.work, self.state
        smallest = int(np.argmin(w.cell_dt))
        if not w.cell_dt[smallest] > 0:
            self.raise_inverted()
        dt = self.controls.time_step_scale * float(w.cell_dt[smallest])
        if self.first_dt == 0.0:
            self.first_dt = dt
        elif dt < self.controls.min_step_ratio * self.first_dt:
            raise SimulationError(
                f"time step collapsed at t = {s.time * 1e3:.4f} ms (step {s.step}): "
                f"{dt:.3e} s, below {self.controls.min_step_ratio:g} of the first step "
                f"{self.first_dt:.3e} s; smallest in element {smallest}"
            )
        return dt

    def raise_inverted(self) -> None:
        """Stop with the first inverted element, its volume and the time."""
        w, s = self.work, self.state
        bad = np.flatnonzero(~(w.cell_volume > 0))
        e = int(bad[0]) if bad.size else int(np.argmin(w.cell_dt))
        raise SimulationError(
            f"element {e} inverted at t = {s.time * 1e3:.4f} ms (step {s.step}): volume "
            f"{w.cell_volume[e] / IN**3:.3e} in^3 (initial {w.volume0[e] / IN**3:.3e} in^3); "
            f"{bad.size} element(s) without positive volume"
        )

    def update(self, dt_new: float) -> float:
        """Central-difference update; returns the kinetic energy at n + 1/2."""
        s, w = self.state, self.work
        kinetic, contact_work = central_difference_update(
            s.points, s.velocities, w.forces, w.contact_forces, w.mass, s.dt, dt_new, w.momentum
        )
        s.energies[3] -= contact_work
        s.time += dt_new
        s.step += 1
        s.dt = dt_new
        return kinetic

    def check_energy(self, kinetic: float, balance: float) -> None:
        """Stop on non-finite values or a run-away energy balance."""
        s = self.state
        if not (np.isfinite(kinetic) and np.isfinite(balance)):
            raise SimulationError(
                f"non-finite kinetic energy or energy balance at t = {s.time * 1e3:.4f} ms "
                f"(step {s.step})"
            )
        if abs(balance) > self.controls.max_energy_error * self.kinetic0:
            raise SimulationError(
                f"energy balance error reached {100 * balance / self.kinetic0:+.1f} % of the "
                f"initial kinetic energy at t = {s.time * 1e3:.4f} ms (step {s.step}): the run "
                f"is unstable (time step too large or contact too stiff)"
            )

    def cycle(self) -> tuple[float, int]:
        """One explicit cycle; returns (kinetic energy, nodes in contact)."""
        clock = time.perf_counter
        t0 = clock()
        self.element_forces()
        t1 = clock()
        self.assembly()
        t2 = clock()
        n_active = self.contact()
        t3 = clock()
        dt_new = self.time_step()
        t4 = clock()
        kinetic = self.update(dt_new)
        t5 = clock()
        for name, dt in zip(
            self.phase_seconds, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4), strict=True
        ):
            self.phase_seconds[name] += dt
        return kinetic, n_active

    def run(self, *, progress: Callable[[float], None] | None = None) -> ExplicitResult:
        """Advance to ``end_time`` or separation; record histories every step."""
        c, s = self.controls, self.state
        rec = _Recorder(len(self.model.contacts), c.end_time / max(c.frame_count, 1))
        points0 = self.model.mesh.points
        start = time.perf_counter()
        contact_began: float | None = None
        last_contact = 0.0
        rec.maybe_frame(0.0, lambda: s.points - points0)
        while s.time < c.end_time:
            kinetic, n_active = self.cycle()
            balance = kinetic + s.energies.sum() - self.kinetic0
            self.check_energy(kinetic, balance)
            energies = np.concatenate(([kinetic], s.energies, [balance]))
            rec.record(
                s.time, self.work.reaction, self.work.momentum / self.total_mass, energies, n_active
            )
            rec.maybe_frame(s.time, lambda: s.points - points0)
            if n_active:
                contact_began = s.time if contact_began is None else contact_began
                last_contact = s.time
            if progress is not None and s.step % 200 == 0:
                progress(s.time)
            if (
                c.separation_time is not None
                and contact_began is not None
                and s.time - last_contact > c.separation_time
            ):
                break
        rec.frame_times.append(s.time)
        rec.frames.append((s.points - points0).astype(np.float32))
        return self.result(rec, time.perf_counter() - start)

    def result(self, rec: _Recorder, wall: float) -> ExplicitResult:
        """Package the recorded histories."""
        arrays = rec.arrays()
        return ExplicitResult(
            time=arrays["time"],
            reaction=arrays["reaction"],
            com_velocity=arrays["com_velocity"],
            energies=arrays["energies"],
            contact_nodes=arrays["contact_nodes"],
            frame_times=np.array(rec.frame_times),
            frames=np.stack(rec.frames),
            mass=self.total_mass,
            n_steps=self.state.step,
            wall_seconds=wall,
            phase_seconds=dict(self.phase_seconds),
        )


def run_explicit(
    model: Model, controls: ExplicitControls, *, progress: Callable[[float], None] | None = None
) -> ExplicitResult:
    """Run ``model`` under ``controls`` (see :class:`ExplicitSolver`)."""
    return ExplicitSolver(model, controls).run(progress=progress)
