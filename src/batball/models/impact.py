"""The ball-impact fixtures: the F2845 half-cylinder (CCOR, dynamic stiffness) and the F1887 wall
(COR), the test's Setup, and the model of the ball fired at them (run by :mod:`batball.lab.impact`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from batball.contact.rigid import (
    RigidCylinder,
    RigidPlane,
)
from batball.elements.hex8_block import check_precision
from batball.errors import SpecError
from batball.models.ball import ContactOptions, ball_body
from batball.solvers.explicit import (
    BulkViscosity,
    HourglassControl,
    Model,
    RigidContact,
)
from batball.specs import BallSpec
from batball.units import IN, MPH

#: The ball tests, keyed by the names users type.
IMPACT_TARGETS = {"ccor": "cylinder", "cor": "wall"}


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
            about 1e-6 in CCOR, docs/notes/precision.md).
    """

    test: str
    speed: float
    divisions: int = 12
    hourglass: HourglassControl | None = None  # None: the ball's own (models.ball)
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
