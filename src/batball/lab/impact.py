"""The virtual ball-impact lab: CCOR and dynamic stiffness (ASTM F2845) and COR (ASTM F1887).

The ball (an O-grid hex sphere of its spec's size, mass and material) is fired without spin at a
fixed rigid target: the 2.63-in diameter half-cylinder of F2845, axis across the flight path, or
the flat wall of F1887. The target's reaction is the load cell. The run stops a little after the
ball separates, then the measurements of :mod:`batball.lab.measures` are taken.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from batball.contact.rigid import (
    RigidCylinder,
    RigidPlane,
    nodal_stiffness,
    segment_stiffness,
)
from batball.elements.hex8_block import check_precision
from batball.errors import SimulationError, SpecError
from batball.lab.measures import ImpactMeasures, measure_impact
from batball.materials.base import BULK, G0
from batball.materials.foam import FoamTable
from batball.mesh import Mesh, boundary_faces, hex_volumes, make_ball_mesh
from batball.solvers.explicit import (
    BulkViscosity,
    ExplicitControls,
    ExplicitResult,
    HourglassControl,
    Model,
    RigidContact,
    run_explicit,
)
from batball.specs import BallSpec
from batball.units import IN, MPH

#: The ball tests, keyed by the names users type.
IMPACT_TARGETS = {"ccor": "cylinder", "cor": "wall"}


@dataclass(frozen=True)
class ContactOptions:
    """Penalty contact settings (LS-DYNA names): SOFT (0 or 1), SLSFAC, SFS and SOFSCL."""

    soft: int = 0
    slsfac: float = 0.1
    sfs: float = 1.0
    sofscl: float = 0.1

    def __post_init__(self) -> None:
        if self.soft not in (0, 1):
            raise SpecError("contact.soft", self.soft, "0 (bulk-modulus penalty) or 1 (stability)")
        for name in ("slsfac", "sfs", "sofscl"):
            if not getattr(self, name) > 0:
                raise SpecError(f"contact.{name}", getattr(self, name), "a positive factor")


@dataclass(frozen=True)
class ImpactSetup:
    """One ball-impact test.

    Attributes:
        test: "ccor" (2.63-in half-cylinder, F2845) or "cor" (flat wall, F1887).
        speed: inbound speed [m/s].
        divisions: ball mesh size (12 gives the seed's 12,096 hexes).
        cylinder_diameter, cylinder_length: F2845 target [m] (2.63 in; length not stated in the
            seed, 6 in is longer than any contact patch).
        gap: initial clearance between ball and target [m].
        end_time: longest run [s]; separation_time: run on this long after contact ends [s].
        contact_threshold: contact-time threshold, fraction of the peak force.
        precision: the hex kernel's element arithmetic, "single" (the default, as LS-DYNA's
            default executable) or "double" (``ExplicitControls.precision``; the two agree to
            about 1e-6 in CCOR, docs/precision.md).
    """

    test: str
    speed: float
    divisions: int = 12
    hourglass: HourglassControl = field(default_factory=HourglassControl)
    bulk_viscosity: BulkViscosity = field(default_factory=BulkViscosity)
    contact: ContactOptions = field(default_factory=ContactOptions)
    time_step_scale: float = 0.9
    cylinder_diameter: float = 2.63 * IN
    cylinder_length: float = 6.0 * IN
    gap: float = 0.002 * IN
    end_time: float = 4e-3
    separation_time: float = 0.1e-3
    contact_threshold: float = 0.01
    precision: str = "single"

    def __post_init__(self) -> None:
        if self.test not in IMPACT_TARGETS:
            raise SpecError("test", self.test, f"one of {sorted(IMPACT_TARGETS)}")
        if not (np.isfinite(self.speed) and 0 < self.speed <= 100.0):
            raise SpecError("speed", f"{self.speed / MPH:.4g} mph", "0 mph < speed <= 223 mph")
        if not 2 <= self.divisions <= 40:
            raise SpecError("divisions", self.divisions, "an integer 2..40 (12 = seed mesh)")
        check_precision(self.precision)


@dataclass(frozen=True)
class ImpactResult:
    """An impact run: its setup, the measurements and the raw histories."""

    ball: BallSpec
    setup: ImpactSetup
    measures: ImpactMeasures
    run: ExplicitResult
    mesh: Mesh
    load_cell: np.ndarray  # (n_steps,) force along the flight path [N]


def make_target(setup: ImpactSetup, radius: float) -> RigidPlane | RigidCylinder:
    """The fixture below a ball of ``radius`` centred at the origin and moving along -z."""
    face_z = -(radius + setup.gap)
    if IMPACT_TARGETS[setup.test] == "wall":
        return RigidPlane(point=np.array([0.0, 0.0, face_z]), normal=np.array([0.0, 0.0, 1.0]))
    r_cyl = 0.5 * setup.cylinder_diameter
    return RigidCylinder(
        axis_point=np.array([0.0, 0.0, face_z - r_cyl]),
        axis=np.array([1.0, 0.0, 0.0]),
        front=np.array([0.0, 0.0, 1.0]),
        radius=r_cyl,
        length=setup.cylinder_length,
    )


def ball_contact_stiffness(
    mesh: Mesh, bulk_modulus: float, density: float, options: ContactOptions, first_dt: float
) -> tuple[np.ndarray, np.ndarray]:
    """Surface node ids and their penalty stiffness [N/m] (SOFT = 0 or 1, see contact.rigid)."""
    faces, owner = boundary_faces(mesh.cells)
    volumes = hex_volumes(mesh.points, mesh.cells)[owner]
    k_faces = segment_stiffness(
        mesh.points,
        faces,
        volumes,
        np.full(len(faces), bulk_modulus),
        scale=options.slsfac * options.sfs,
    )
    nodes = np.unique(faces)
    k0 = nodal_stiffness(faces, k_faces, nodes, mesh.n_points)
    if options.soft == 0:
        return nodes, k0
    from batball.solvers.explicit_kernels import lumped_masses

    node_mass = lumped_masses(
        mesh.cells, density * hex_volumes(mesh.points, mesh.cells), mesh.n_points
    )[nodes]
    k1 = 0.5 * node_mass / first_dt**2
    return nodes, np.maximum(k0, options.sofscl * k1)


@dataclass(frozen=True)
class BallBody:
    """The meshed ball every ball test starts from: mesh, kernel constants, density and the
    penalty stiffness of its surface nodes [N/m]."""

    mesh: Mesh
    constants: np.ndarray
    density: float
    nodes: np.ndarray
    stiffness: np.ndarray
    foam: FoamTable | None = None  # a foam ball's packed material


def ball_body(
    ball: BallSpec,
    divisions: int,
    contact: ContactOptions,
    time_step_scale: float,
    mass_scale: float = 1.0,
) -> BallBody:
    """Mesh the ball, take its material constants, and size its contact penalty.

    ``mass_scale`` multiplies the density the SOFT = 1 stiffness sees (quasi-static tests).
    """
    mesh = make_ball_mesh(ball.radius, divisions=divisions)
    constants = ball.material.kernel_constants()
    # the FE ball weighs exactly the spec mass: density on the faceted mesh volume
    density = ball.mass / float(hex_volumes(mesh.points, mesh.cells).sum())
    scaled = density * mass_scale
    first_dt = estimate_first_step(mesh, constants, scaled) * time_step_scale
    bulk = float(constants[BULK])
    nodes, stiffness = ball_contact_stiffness(mesh, bulk, scaled, contact, first_dt)
    return BallBody(mesh, constants, density, nodes, stiffness, ball.material.foam_table())


def build_impact_model(ball: BallSpec, setup: ImpactSetup) -> Model:
    """The ball mesh, material, initial velocity and target of an impact test."""
    body = ball_body(ball, setup.divisions, setup.contact, setup.time_step_scale)
    mesh = body.mesh
    velocity = np.zeros((mesh.n_points, 3))
    velocity[:, 2] = -setup.speed
    target = make_target(setup, ball.radius)
    return Model(
        mesh=mesh,
        cell_material=np.zeros(mesh.n_cells, dtype=np.int64),
        material_constants=body.constants[None, :],
        densities=np.array([body.density]),
        contacts=(RigidContact(setup.test, target, body.nodes, body.stiffness),),
        initial_velocity=velocity,
        foam=body.foam,
    )


def estimate_first_step(mesh: Mesh, constants: np.ndarray, density: float) -> float:
    """Stable element step of the undeformed mesh, min L_e / c [s] (before TSSFAC)."""
    from batball.mesh import characteristic_lengths

    c = np.sqrt((constants[BULK] + 4.0 / 3.0 * constants[G0]) / density)
    return float(characteristic_lengths(mesh.points, mesh.cells).min() / c)


def run_impact(
    ball: BallSpec, setup: ImpactSetup, *, progress: Callable[[float], None] | None = None
) -> ImpactResult:
    """Build, run and measure one impact test."""
    model = build_impact_model(ball, setup)
    controls = ExplicitControls(
        end_time=setup.end_time,
        time_step_scale=setup.time_step_scale,
        hourglass=setup.hourglass,
        bulk_viscosity=setup.bulk_viscosity,
        separation_time=setup.separation_time,
        precision=setup.precision,
    )
    run, load_cell, measures = run_impact_model(
        model, controls, setup.contact_threshold, progress=progress
    )
    return ImpactResult(
        ball=ball, setup=setup, measures=measures, run=run, mesh=model.mesh, load_cell=load_cell
    )


def run_impact_model(
    model: Model,
    controls: ExplicitControls,
    threshold: float,
    *,
    progress: Callable[[float], None] | None = None,
) -> tuple[ExplicitResult, np.ndarray, ImpactMeasures]:
    """Run an impact model (body fired at its first contact's target) and measure it.

    Returns the run, the load cell (the first target's reaction along the flight path [N]) and
    the measurements. Shared by :func:`run_impact` and the keyword-deck runner.
    """
    run = run_explicit(model, controls, progress=progress)
    if run.contact_nodes[-1] > 0 or not run.contact_nodes.any():
        state = "is still in contact with" if run.contact_nodes.any() else "never reached"
        raise SimulationError(
            f"the ball {state} the target at the end time {controls.end_time * 1e3:.2f} ms, so "
            f"no rebound can be measured; raise end_time or check the material"
        )
    speed = float(np.linalg.norm(model.initial_velocity[0]))
    direction = model.initial_velocity[0] / speed
    load_cell = run.reaction[:, 0, :] @ direction
    measures = measure_impact(
        run.time,
        load_cell,
        run.com_velocity,
        inbound=model.initial_velocity[0],
        mass=run.mass,
        threshold=threshold,
    )
    return run, load_cell, measures
