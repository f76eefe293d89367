"""The ball-compression fixture (ASTM F1888): the ball between two flat rigid plates, the top one
moving at the test's rate; the test's Setup, the relaxed Hertz estimate that plans the run, and the
mass-scaled, damped model (run and read by :mod:`batball.lab.compression`, whose docstring gives
the loading plan).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from batball.contact.rigid import RigidPlane
from batball.errors import SpecError
from batball.materials.base import BULK, G_INF
from batball.models.ball import ContactOptions, ball_body
from batball.solvers.explicit import (
    BulkViscosity,
    HourglassControl,
    Model,
    RigidContact,
)
from batball.specs import BallSpec
from batball.units import IN

#: Plate travel allowed beyond the test displacement, for the penalty contact's penetration.
TRAVEL_MARGIN = 1.1


@dataclass(frozen=True)
class CompressionSetup:
    """One compression test.

    Attributes:
        displacement: the plate travel at which the force is read [m] (F1888: 0.25 in).
        rate: the plate speed [m/s] (F1888: 1 in/min).
        divisions: ball mesh size (12 = the seed's 12,096 hexes).
        quasi_static_ratio: the loading time in radians of the mass-scaled ball's squash mode,
            omega' T (the solver's loading rate: larger is slower and closer to static, and costs
            proportionally more steps).
        damping_ratio: mass-proportional damping as a fraction of critical for that mode.
        samples: points of the force-displacement curve kept for the CSV and the plot.
    """

    displacement: float = 0.25 * IN
    rate: float = IN / 60.0
    divisions: int = 12
    hourglass: HourglassControl | None = None  # None: the ball's own (models.ball)
    bulk_viscosity: BulkViscosity = field(default_factory=BulkViscosity)
    contact: ContactOptions = field(default_factory=ContactOptions)
    time_step_scale: float = 0.9
    quasi_static_ratio: float = 60.0
    damping_ratio: float = 0.1
    samples: int = 201

    def __post_init__(self) -> None:
        if not (np.isfinite(self.displacement) and 0 < self.displacement <= 1.0 * IN):
            raise SpecError(
                "displacement", f"{self.displacement / IN:.4g} in", "0 in < displacement <= 1 in"
            )
        if not (np.isfinite(self.rate) and 0 < self.rate <= 1.0):
            raise SpecError(
                "rate", f"{self.rate / IN * 60:.4g} in/min", "0 < rate <= 2362 in/min (1 m/s)"
            )
        if not 2 <= self.divisions <= 40:
            raise SpecError("divisions", self.divisions, "an integer 2..40 (12 = seed mesh)")
        if not 10.0 <= self.quasi_static_ratio <= 1e4:
            raise SpecError("quasi_static_ratio", self.quasi_static_ratio, "10 <= ratio <= 10000")
        if not 0.0 <= self.damping_ratio <= 2.0:
            raise SpecError("damping_ratio", self.damping_ratio, "0 <= damping ratio <= 2")
        if not 2 <= self.samples <= 100_000:
            raise SpecError("samples", self.samples, "2..100000 curve points")


def relaxed_hertz(constants: np.ndarray, radius: float, approach: float) -> tuple[float, float]:
    """Hertz force and tangent stiffness [N, N/m] of a sphere of the relaxed (G_inf, K) material
    squeezed by ``approach`` between two rigid plates (each contact takes half).

    F = 4/3 E* sqrt(R) (d/2)^(3/2), E* = E / (1 - nu^2) with E, nu from K and G_inf
    (docs/physics.md section 8, case 3; Johnson, Contact Mechanics, section 4.2).
    """
    bulk, g_inf = float(constants[BULK]), float(constants[G_INF])
    young = 9.0 * bulk * g_inf / (3.0 * bulk + g_inf)
    nu = (3.0 * bulk - 2.0 * g_inf) / (2.0 * (3.0 * bulk + g_inf))
    e_star = young / (1.0 - nu**2)
    delta = 0.5 * approach
    force = 4.0 / 3.0 * e_star * np.sqrt(radius) * delta**1.5
    # dF/d(approach) = dF/d(delta) / 2 = 2 E* sqrt(R delta) / 2
    stiffness = e_star * np.sqrt(radius * delta)
    return force, stiffness


def loading_plan(
    ball: BallSpec, setup: CompressionSetup, constants: np.ndarray, mass: float
) -> tuple[float, float]:
    """The density factor s and the damping coefficient c [1/s] of the run (module docstring).

    The squash mode: the ball's mass on the plates' Hertz tangent stiffness at full travel,
    omega = sqrt(k / (m / 2)) (half the mass moves against each contact). s makes
    omega / sqrt(s) * T equal ``quasi_static_ratio``; never below 1 (no mass scaling).
    """
    _, k = relaxed_hertz(constants, ball.radius, setup.displacement)
    omega = np.sqrt(k / (0.5 * mass))
    loading_time = setup.displacement / setup.rate
    scale = max(1.0, (omega * loading_time / setup.quasi_static_ratio) ** 2)
    omega_scaled = omega / np.sqrt(scale)
    return float(scale), float(2.0 * setup.damping_ratio * omega_scaled)


def build_compression_model(ball: BallSpec, setup: CompressionSetup) -> tuple[Model, float, float]:
    """The mass-scaled ball between its plates; returns (model, mass scale, damping [1/s])."""
    constants = ball.material.kernel_constants()
    scale, damping = loading_plan(ball, setup, constants, ball.mass)
    # SOFT = 1's stability penalty scales with the (scaled) nodal mass
    body = ball_body(ball, setup.divisions, setup.contact, setup.time_step_scale, scale)
    r = ball.radius
    bottom = RigidPlane(point=np.array([0.0, 0.0, -r]), normal=np.array([0.0, 0.0, 1.0]))
    top = RigidPlane(
        point=np.array([0.0, 0.0, r]),
        normal=np.array([0.0, 0.0, -1.0]),
        velocity=np.array([0.0, 0.0, -setup.rate]),
    )
    mesh = body.mesh
    model = Model(
        mesh=mesh,
        cell_material=np.zeros(mesh.n_cells, dtype=np.int64),
        material_constants=body.constants[None, :],
        densities=np.array([body.density * scale]),
        contacts=(
            RigidContact("top", top, body.nodes, body.stiffness),
            RigidContact("bottom", bottom, body.nodes, body.stiffness),
        ),
        initial_velocity=np.zeros((mesh.n_points, 3)),
        foam=body.foam,
    )
    return model, scale, damping
