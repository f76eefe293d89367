"""The barrel compression test run by the explicit shells: geometrically nonlinear.

The static test of :mod:`batball.lab.barrel` is linear: small displacements, contact normals
fixed at first touch. The platens' 0.07 in of travel on a 1.1-in radius is not small (CalculiX's
NLGEOM takes 8.6 % off the final load of a double-wall tube, docs/notes/barrel.md), so this module
runs the same protocol on the bat of the batted-ball-speed test with shells that work in each
element's current co-rotational frame, so that large rotations and the current geometry come
with them, as in the seed's LS-DYNA model: by default the statics' own MITC4 element made
co-rotational (:mod:`batball.elements.shell_corotational`), or the BBS test's one-point
Belytschko-Tsay shells (:mod:`batball.elements.shell_bt`, ``shell="bt"``), whose hourglass
control sets part of the answer under the platens' nearly point load (docs/notes/barrel.md). The
static answer is reached by dynamic relaxation (docs/physics.md section 6.7), the platens moved
slowly and each travel level held until the bat stops moving.

* **Bat and fit:** the shells, layered sections, lumped masses (selective mass scaling to the
  barrel's step: inertia is fictitious in a relaxation) and the insert's column contact of
  :func:`batball.models.bbs.bat_part` and :func:`batball.models.bbs.insert_barrel_contact`; the fit
  is pressed in first, frictionless, by the same ramp-and-settle as the BBS test. Optional
  Coulomb friction at the insert during the squeeze (:meth:`ColumnContact.start_friction`).
  The MITC4 shells take the statics' section of the same laminates and their own step,
  ``step_factor`` (0.8) times their critical step 2 / omega_max (Lanczos on the mass-scaled
  lumped masses, :func:`batball.elements.shell_corotational.shells_and_step`), about 1.45
  times the BT shells' estimate that the BBS test takes. Optional Coulomb friction at the
  platens too (``BarrelTestOptions.platen_friction``, :func:`platen_friction_forces`).
* **Platens:** rigid half-cylinders (:class:`batball.contact.rigid.RigidCylinder`, 3.3 in) across
  the bat ``distance_from_cap`` from the end cap, touching the pre-stressed outer surface (the
  nodes' mid-surface pushed out to the spec's outer radius along their current radial
  direction) at zero travel. They close **symmetrically**, each by half the travel: the relative
  travel is what the test measures, and a fixed bottom platen would make the whole 34-in bat
  translate by half the travel, a rigid motion that relaxation settles only over the handle's
  slow bending (tens of ms). Penalty k = ``contact_scale`` m / dt^2 per node (the stability
  form of LS-DYNA's SOFT = 1), m the node's mass, dt the BT shells' step estimate with either
  shell, so that the MITC4 shells' longer step does not soften it (halving k raised the final
  load by 1.4 % on the full mesh, docs/notes/barrel.md). The penalty's own compliance is removed by
  moving the platens on by the deepest penetrations (low-pass filtered), so the reported travel
  is that of the surface under the platens, as the static test's stiff penalty gives.
* **Supports:** the seed's (Figures 11-12), as the static test: the barrel and insert rings
  nearest the platen centre held axially, their four nodes on the load axis held sideways.
* **Damping:** mass-proportional, c = ``damping`` (1e4 /s, about critical for the barrel's
  ovalling under the platens). Underwood's adaptive c = 2 omega_1 (the Rayleigh quotient of the
  displacement since the squeeze began, as :func:`batball.elements.shell_explicit.
  dynamic_relaxation`) was tried first: the quotient is dominated by the stiff squeezed ring,
  and its holds still drifted by 1 % after 4 ms where c = 1e4 /s settles to 1e-5 in 1 ms
  (docs/notes/barrel.md, "Geometric nonlinearity").
* **Force:** the top platen's reaction along the load axis, averaged over the last
  ``average_fraction`` of each hold. Preload F(0.02 in), final F(0.07 in) - F(0.02 in).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

import numba as nb
import numpy as np

from batball.contact.columns import ColumnContact
from batball.contact.rigid import (
    RigidCylinder,
    add_rigid_contact_forces,
    add_rigid_friction_forces,
)
from batball.elements.shell_bt import initial_force_state
from batball.elements.shell_corotational import (
    SHELLS,
    STEP_FACTOR,
    CorotationalShellForces,
    shells_and_step,
)
from batball.elements.shell_stiffness import shell_section
from batball.errors import SimulationError, SpecError
from batball.lab.barrel import CompressionCurve, halves, radial_cosines
from batball.lab.fit_store import FitRelaxation, capture_fit, fit_inputs, obtain_fit, restore_fit
from batball.mesh.bat import outer_rings
from batball.models.ball import ContactOptions
from batball.models.barrel import BarrelTestOptions, load_axes, support_nodes
from batball.models.bat import bat_laminates
from batball.models.bbs import (
    BbsSetup,
    bat_part,
    check_hourglass_ratio,
    fit_pressure,
    insert_barrel_contact,
    relaxation_cycles,
)
from batball.solvers.ball_bat import RELAX_FACTOR, BatPart, ShellForces, relax_fit
from batball.specs.bat import BatSpec
from batball.units import IN


@dataclass(frozen=True)
class ExplicitBarrelOptions:
    """Controls of the explicit (relaxation) barrel test, SI.

    Attributes:
        circumferential, axial_size: the bat's mesh (as ``batball bbs``).
        travel_rate: platen closing speed while moving [m/s] (both platens together).
        hold_time: how long each travel level is held before it is read [s].
        average_fraction: the last part of a hold whose mean force is the reading.
        contact_scale: platen penalty over m / dt^2, dt the BT shells' step estimate whichever
            shells run (module docs).
        feedback_time: time constant of the penetration filter that moves the platens on [s].
        mass_scaling: as :class:`batball.models.bbs.BbsSetup` ("barrel", a step in s, or None).
        damping: mass-proportional damping of the relaxation [1/s] (module docs).
        fit_slsfac: SLSFAC of the insert's column contact (0.1, as the BBS test).
        hourglass_ratio: r of the BT shells' hourglass constants (module docs).
        shell: the explicit element: "mitc4", the statics' MITC4 shell made co-rotational
            (:mod:`batball.elements.shell_corotational`; no hourglass modes), or "bt", the BBS
            test's Belytschko-Tsay shells with ``hourglass_ratio``.
        step_factor: with the MITC4 shells, the step over their own critical step (Lanczos on
            the lumped masses, mass scaling included; :func:`batball.elements.
            shell_corotational.shells_and_step`); the BT shells take the BBS test's step.
    """

    circumferential: int = 48
    axial_size: float = 0.1 * IN
    travel_rate: float = 0.5
    hold_time: float = 1.0e-3
    average_fraction: float = 0.2
    contact_scale: float = 0.1
    feedback_time: float = 0.05e-3
    mass_scaling: float | str | None = "barrel"
    damping: float = 1.0e4
    fit_slsfac: float = 0.1
    hourglass_ratio: float = 1.0
    shell: str = "mitc4"
    step_factor: float = STEP_FACTOR

    def __post_init__(self) -> None:
        if not (np.isfinite(self.step_factor) and 0.0 < self.step_factor <= 0.9):
            raise SpecError("step_factor", self.step_factor, "0 < factor <= 0.9")
        check_hourglass_ratio("hourglass_ratio", self.hourglass_ratio)
        if self.shell not in SHELLS:
            raise SpecError("shell", self.shell, " or ".join(SHELLS))
        for name in ("travel_rate", "hold_time", "contact_scale", "feedback_time", "damping",
                     "fit_slsfac"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise SpecError(name, value, "a positive finite number")
        if not 0.0 < self.average_fraction <= 1.0:
            raise SpecError("average_fraction", self.average_fraction, "0 < fraction <= 1")
        if self.circumferential % 8:
            raise SpecError("circumferential", self.circumferential,
                            "a multiple of 8 (platens at 0, 45, 90, -45 deg)")  # fmt: skip

    def bbs_setup(self) -> BbsSetup:
        """The BBS test's setup for the same mesh and mass scaling (the bat is built by it)."""
        return BbsSetup(circumferential=self.circumferential, axial_size=self.axial_size,
                        mass_scaling=self.mass_scaling,
                        contact=ContactOptions(slsfac=self.fit_slsfac))  # fmt: skip


@dataclass
class ExplicitBat:
    """The bat's explicit state: nodes (n, 3), velocities (n, 6), shell stresses, the fit."""

    spec: BatSpec
    bat: BatPart
    outer: np.ndarray  # outer-wall node ids, ring by ring
    insert_nodes: np.ndarray
    points: np.ndarray
    velocity: np.ndarray
    shells: ShellForces | CorotationalShellForces
    fit: ColumnContact
    surface_offset: np.ndarray  # spec outer radius minus each node's mid-surface radius [m]
    reference: np.ndarray  # the undeformed nodes [m]
    insert_cells: np.ndarray  # (n, 4) the insert's cells
    prestress_kinetic_ratio: float = float("nan")
    fit_pressure: float = float("nan")  # mean insert-barrel pressure after the fit [Pa]
    fit_pressure_force: float = float("nan")  # the fit's total normal force [N]
    fit_reused: bool = False  # the fit was restored from a store, not relaxed in this run
    penalty_step: float = float("nan")  # the BT shells' step estimate: the platens' penalty [s]

    def __post_init__(self) -> None:
        self.spin = np.zeros_like(self.points)
        self.fit.rotation_step = self.spin

    def forces(self, out: np.ndarray, contact: np.ndarray) -> None:
        """Shell and insert-contact forces on the nodes into ``out`` (n, 6) (with friction, its
        moments at the walls' faces too); ``contact`` (n, 3) is scratch, left holding the
        insert contact's forces."""
        dt = self.bat.stable_step
        self.shells(self.points, self.velocity, dt, out)
        contact[:] = 0.0
        if self.fit.friction > 0.0:
            self.spin[:] = dt * self.velocity[:, 3:]  # the rotations over the last step
        self.fit.add_forces(self.points, contact)
        out[:, :3] += contact
        if self.fit.friction > 0.0:
            out[:, 3:] += self.fit.moments


def build_explicit_bat(spec: BatSpec, options: ExplicitBarrelOptions) -> ExplicitBat:
    """The BBS test's bat (shells, masses, insert contact) for the barrel test, not yet fitted."""
    if spec.insert is None:
        raise SpecError("insert", None, "a double-wall bat with an [insert] table")
    setup = options.bbs_setup()
    bat, mesh, _ = bat_part(spec, setup)
    penalty_step = bat.stable_step
    fit = insert_barrel_contact(spec, bat, mesh, setup)
    radius = np.hypot(mesh.points[:, 1], mesh.points[:, 2])
    offset = np.asarray(spec.outer_radius(mesh.points[:, 0])) - radius
    points = mesh.points.copy()
    velocity = np.zeros((mesh.n_points, 6))
    shells: ShellForces | CorotationalShellForces
    if options.shell == "mitc4":
        shells, step = shells_and_step(mesh.points, mesh.cells,
                                       shell_section(*bat_laminates(spec, mesh)), bat.mass,
                                       factor=options.step_factor)  # fmt: skip
        bat = replace(bat, stable_step=step)
    else:
        shells = ShellForces(bat, initial_force_state(bat.section),
                             hourglass_ratio=options.hourglass_ratio)  # fmt: skip
    return ExplicitBat(spec, bat, outer_rings(mesh).ravel(), mesh.point_sets["insert"], points,
                       velocity, shells, fit, offset, mesh.points,
                       mesh.cells[mesh.cell_sets["insert"]], penalty_step=penalty_step)  # fmt: skip


@nb.njit(cache=True)
def relaxation_step(forces: np.ndarray, mass: np.ndarray, velocity: np.ndarray,
                    points: np.ndarray, damping: float, dt: float, axial: np.ndarray,
                    on_axis: np.ndarray, sideways: np.ndarray) -> float:  # fmt: skip
    """One cycle of central differences with mass-proportional damping c [1/s], in place:
    v <- ((2 - c dt) v + 2 dt f / m) / (2 + c dt) on (n, 6); the ``axial`` nodes' x velocity
    and the ``on_axis`` nodes' velocity along ``sideways`` (3,) set to zero (the supports);
    x += dt v. Returns the kinetic energy [J]."""
    keep = (2.0 - damping * dt) / (2.0 + damping * dt)
    push = 2.0 * dt / (2.0 + damping * dt)
    for n in range(forces.shape[0]):
        for k in range(6):
            velocity[n, k] = keep * velocity[n, k] + push * forces[n, k] / mass[n, k]
    for n in axial:
        velocity[n, 0] = 0.0
    for n in on_axis:
        along = velocity[n, 0] * sideways[0] + velocity[n, 1] * sideways[1] \
            + velocity[n, 2] * sideways[2]
        for k in range(3):
            velocity[n, k] -= along * sideways[k]
    kinetic = 0.0
    for n in range(forces.shape[0]):
        for k in range(6):
            kinetic += 0.5 * mass[n, k] * velocity[n, k] ** 2
        for k in range(3):
            points[n, k] += dt * velocity[n, k]
    return kinetic


def press_fit(state: ExplicitBat, options: ExplicitBarrelOptions, *, store: Path | None = None,
              reuse: bool = True) -> None:  # fmt: skip
    """Press the insert in (the fit's overlap removed over a ramp, then settled) by the BBS
    test's relaxation (:func:`batball.solvers.ball_bat.relax_fit`, its damping factor
    and its physical times, :func:`batball.lab.bbs.relaxation_cycles`), or restore it from
    ``store`` (:mod:`batball.lab.fit_store`) when this bat's fit is there and ``reuse``."""
    setup = options.bbs_setup()
    ramp, settle = relaxation_cycles(setup, state.bat.stable_step)
    forces, contact = np.zeros_like(state.velocity), np.zeros_like(state.points)
    interference = float(state.spec.insert.interference)  # type: ignore[union-attr]
    moving = np.ones(state.points.shape[0], dtype=np.bool_)

    def bat_forces() -> np.ndarray:
        state.forces(forces, contact)
        return forces

    def relax() -> float:
        return relax_fit([state.fit], interference=interference, ramp_steps=ramp,
                         settle_steps=settle, search_interval=setup.search_interval,
                         points=state.points, forces=bat_forces, mass=state.bat.mass,
                         velocity=state.velocity, moving=moving, dt=state.bat.stable_step,
                         factor=RELAX_FACTOR)  # fmt: skip

    relaxation = FitRelaxation(interference, ramp, settle, setup.search_interval,
                               state.bat.stable_step, RELAX_FACTOR, options.hourglass_ratio,
                               options.shell)  # fmt: skip
    inputs = fit_inputs(state.bat, state.reference, [state.fit], moving, relaxation)
    state.prestress_kinetic_ratio, state.fit_reused = obtain_fit(
        store, inputs, relax, state.points, state.shells.state, [state.fit], reuse=reuse)
    state.fit_pressure = fit_pressure(state.fit, state.points, state.reference,
                                      state.insert_cells)  # fmt: skip
    state.fit_pressure_force = float(np.linalg.norm(state.fit.slave_force, axis=1).sum())


@dataclass(frozen=True)
class Platens:
    """The two platens of one orientation: packed targets for the rigid-contact kernel, their
    candidate nodes (outer-wall nodes within the platen radius of its centre, on its side) and
    penalties. The kernel's time argument is the commanded travel (each platen's "velocity" is
    its displacement per unit travel, half the travel each)."""

    nodes: np.ndarray  # global ids of the candidates
    stiffness: np.ndarray
    offsets: np.ndarray
    kinds: np.ndarray
    params: np.ndarray
    load: np.ndarray

    @cached_property
    def motion(self) -> np.ndarray:
        """Each candidate's platen displacement per unit of commanded travel, (n, 3) (built
        once: the friction reads it every cycle)."""
        return np.repeat(self.params[:, 11:14], np.diff(self.offsets), axis=0)


def surface_points(state: ExplicitBat, nodes: np.ndarray) -> np.ndarray:
    """The outer surface over ``nodes``: mid-surface pushed out radially by its offset (m)."""
    p = state.points[nodes]
    radial = np.zeros_like(p)
    radial[:, 1:] = p[:, 1:] / np.hypot(p[:, 1], p[:, 2])[:, None]
    return p + state.surface_offset[nodes, None] * radial


def make_platens(state: ExplicitBat, test: BarrelTestOptions, orientation_deg: float,
                 contact_scale: float) -> Platens:  # fmt: skip
    """Top and bottom platen touching the current (pre-stressed) outer surface (module docs)."""
    load, sideways = load_axes(orientation_deg)
    radius = 0.5 * test.platen_diameter
    centre_x = state.spec.length - test.distance_from_cap
    points = state.points
    near = np.abs(points[state.outer, 0] - centre_x) < radius
    nodes, kinds, params, offsets = [], [], [], [0]
    for side in (1.0, -1.0):
        mine = state.outer[near & (side * (points[state.outer] @ load) > 0.0)]
        surface = surface_points(state, mine)
        # the platen axis at distance d along side * load touches a point where
        # d = side * (p . load) + sqrt(R^2 - (p_x - c_x)^2); first touch is the largest d
        reach = side * (surface @ load) + np.sqrt(radius**2 - (surface[:, 0] - centre_x) ** 2)
        target = RigidCylinder(
            axis_point=np.array([centre_x, 0.0, 0.0]) + side * float(reach.max()) * load,
            axis=sideways, front=-side * load, radius=radius, length=4.0 * radius,
            velocity=-0.5 * side * load,
        )  # fmt: skip
        kind, packed = target.packed()
        nodes.append(mine)
        kinds.append(kind)
        params.append(packed)
        offsets.append(offsets[-1] + mine.size)
    all_nodes = np.concatenate(nodes)
    stiffness = contact_scale * state.bat.mass[all_nodes, 0] / state.penalty_step**2
    return Platens(all_nodes, stiffness, np.array(offsets), np.array(kinds), np.array(params),
                   load)  # fmt: skip


@dataclass(frozen=True)
class ExplicitCurve:
    """One orientation's explicit record: the curve (as the static test's) and its checks.

    Attributes:
        curve: travel levels, platen force, insert contact split.
        kinetic_ratio: (n_levels,) the bat's kinetic energy at the end of each hold over its
            largest value during that level (LS-DYNA's DRTOL measure).
        drift: (n_levels,) change of the platen force over the averaging window of each hold,
            over the force (how settled the reading is).
        travel_error: (n_levels,) surface travel minus the level's travel at the reading [m].
        cycles: explicit cycles of the squeeze; seconds: its wall time.
    """

    curve: CompressionCurve
    kinetic_ratio: np.ndarray
    drift: np.ndarray
    travel_error: np.ndarray
    cycles: int
    seconds: float


def insert_split(state: ExplicitBat, contact: np.ndarray, load: np.ndarray) -> tuple[float, float]:
    """Insert-barrel contact force magnitudes on the insert's top and bottom halves [N]."""
    nodes = state.fit.slave_nodes
    return halves(np.linalg.norm(contact[nodes], axis=1), radial_cosines(state.points[nodes], load))


def platen_friction_forces(state: ExplicitBat, platens: Platens, mu: float, moved: float,
                           friction: np.ndarray, platen_forces: np.ndarray, forces: np.ndarray,
                           reaction: np.ndarray) -> None:  # fmt: skip
    """Coulomb friction ``mu`` between the platens and the barrel's outer surface, added to
    ``forces`` (n, 6): the slip over the last step is the platens' motion (``moved``, the
    commanded travel since the last call [m]) minus the surface's, the node's velocity plus its
    spin about the surface's offset along the current radial direction, times the step; the
    stick spring is the platen's penalty (as the insert contact's); the force acts at the
    surface, so its moment about the node goes to the rotations. ``friction`` (n_candidates, 3)
    [N] is the state; ``platen_forces`` holds the normal forces, and the friction is added to it
    too, and its reaction to the platens' ``reaction`` (2, 3) [N]."""
    nodes, dt = platens.nodes, state.bat.stable_step
    arm = surface_points(state, nodes) - state.points[nodes]  # the surface's offset
    velocity = state.velocity[nodes]
    slip = moved * platens.motion - dt * (velocity[:, :3] + np.cross(velocity[:, 3:], arm))
    before = platen_forces.copy()
    add_rigid_friction_forces(before, slip, mu, platens.stiffness, friction, platen_forces)
    added = platen_forces - before
    forces[nodes, 3:] += np.cross(arm, added)
    for k in range(reaction.shape[0]):
        reaction[k] -= added[platens.offsets[k]:platens.offsets[k + 1]].sum(axis=0)


def squeeze(state: ExplicitBat, test: BarrelTestOptions, options: ExplicitBarrelOptions,
            orientation_deg: float, *, curve: bool) -> ExplicitCurve:  # fmt: skip
    """Close the platens level by level from the pre-stressed state (module docs); the state is
    left squeezed (copy it first to run another orientation)."""
    clock = time.perf_counter()
    platens = make_platens(state, test, orientation_deg, options.contact_scale)
    axial, on_axis = support_nodes(state.reference, state.outer, state.insert_nodes,
                                   state.spec.length - test.distance_from_cap,
                                   platens.load, orientation_deg)  # fmt: skip
    sideways = load_axes(orientation_deg)[1]
    mass, dt = state.bat.mass, state.bat.stable_step
    forces, contact = np.zeros_like(state.velocity), np.zeros_like(state.points)
    platen_forces = np.zeros((platens.nodes.size, 3))
    friction = np.zeros_like(platen_forces)
    reaction, penetration = np.zeros((2, 3)), np.zeros(2)
    travels = test.travels(curve=curve)
    n = travels.size
    force, upper, lower = np.zeros(n), np.zeros(n), np.zeros(n)
    ratio, drift, error = np.zeros(n), np.zeros(n), np.zeros(n)
    filtered, commanded, cycles, last_commanded = 0.0, 0.0, 0, 0.0
    blend = min(1.0, dt / options.feedback_time)
    candidates = np.arange(platens.nodes.size)  # the kernel's node list, into platens.nodes
    previous = 0.0
    for level, target in enumerate(travels):
        move = int(np.ceil((target - previous) / (options.travel_rate * dt)))
        hold = int(np.ceil(options.hold_time / dt))
        window = max(1, int(options.average_fraction * hold))
        peak = kinetic = 0.0
        readings = np.zeros(window)
        for step in range(move + hold):
            travel = previous + (target - previous) * min(1.0, (step + 1) / move)
            if cycles % 10 == 0:
                state.fit.search(state.points)
            state.forces(forces, contact)
            platen_forces[:] = 0.0
            add_rigid_contact_forces(surface_points(state, platens.nodes), commanded,
                                     candidates, platens.stiffness, platens.offsets,
                                     platens.kinds, platens.params, platen_forces, reaction,
                                     penetration)  # fmt: skip
            if test.platen_friction > 0.0:
                platen_friction_forces(state, platens, test.platen_friction,
                                       commanded - last_commanded, friction, platen_forces,
                                       forces, reaction)  # fmt: skip
                last_commanded = commanded
            forces[platens.nodes, :3] += platen_forces
            kinetic = relaxation_step(forces, mass, state.velocity, state.points,
                                      options.damping, dt, axial, on_axis, sideways)  # fmt: skip
            filtered += blend * (penetration.sum() - filtered)
            commanded = travel + filtered
            peak = max(peak, kinetic)
            if step >= move + hold - window:
                readings[step - (move + hold - window)] = reaction[0] @ platens.load
            cycles += 1
        if not np.all(np.isfinite(state.points)):
            raise SimulationError(f"barrel squeeze at {orientation_deg:g} deg went non-finite "
                                  f"at {target / IN:.4f} in (cycle {cycles})")  # fmt: skip
        force[level] = float(readings.mean())
        drift[level] = float(readings[-1] - readings[0]) / max(abs(force[level]), 1e-30)
        ratio[level] = kinetic / peak if peak > 0 else 0.0
        error[level] = commanded - penetration.sum() - target
        upper[level], lower[level] = insert_split(state, contact, platens.load)
        previous = target
    record = CompressionCurve(orientation_deg, travels, force, upper, lower, cycles)
    return ExplicitCurve(record, ratio, drift, error, cycles, time.perf_counter() - clock)


def run_explicit_compression(
    spec: BatSpec, test: BarrelTestOptions, options: ExplicitBarrelOptions, *,
    finished: dict[float, ExplicitCurve] | None = None,
    record: Callable[[ExplicitCurve], None] | None = None,
    store: Path | None = None,
    reuse: bool = True,
) -> tuple[ExplicitBat, list[ExplicitCurve]]:
    """Fit the insert, then squeeze at every orientation of ``test`` from the fitted state.

    ``finished`` holds orientations already run (by angle, deg; an interrupted run resumes
    with them), ``record`` is called with each new one as soon as it is done; ``store``, the
    runs folder that keeps the relaxed fit (:func:`press_fit`)."""
    finished = {} if finished is None else finished
    test = test.for_bat(spec)
    state = build_explicit_bat(spec, options)
    press_fit(state, options, store=store, reuse=reuse)
    fitted = capture_fit(state.points, state.shells.state, [state.fit])
    curves = []
    for k, angle in enumerate(test.orientations_deg):
        if angle in finished:
            curves.append(finished[angle])
            continue
        restore_fit(fitted, state.points, state.shells.state, [state.fit])
        state.velocity[:] = 0.0
        if test.insert_friction > 0.0:
            state.fit.start_friction(test.insert_friction, state.points)
        curves.append(squeeze(state, test, options, angle, curve=k < test.curve_orientations))
        if record is not None:
            record(curves[-1])
    return state, curves

