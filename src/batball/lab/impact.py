"""The virtual ball-impact lab: CCOR and dynamic stiffness (ASTM F2845) and COR (ASTM F1887).

The ball (an O-grid hex sphere of its spec's size, mass and material) is fired without spin at a
fixed rigid target: the 2.63-in diameter half-cylinder of F2845, axis across the flight path, or
the flat wall of F1887. The target's reaction is the load cell. The run stops a little after the
ball separates, then the measurements of :mod:`batball.lab.measures` are taken.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.errors import SimulationError
from batball.lab.measures import ImpactMeasures, max_approach, measure_impact
from batball.mesh import Mesh
from batball.models.ball import ball_hourglass, with_ball_hourglass
from batball.models.impact import ImpactSetup, build_impact_model
from batball.solvers.explicit import (
    ExplicitControls,
    ExplicitResult,
    Model,
    run_explicit,
)
from batball.specs import BallSpec


@dataclass(frozen=True)
class ImpactResult:
    """An impact run: its setup, the measurements and the raw histories.

    Attributes:
        load_cell: (n_steps,) the target's reaction along the flight path [N].
        targets: the run's rigid targets (for the field output).
    """

    ball: BallSpec
    setup: ImpactSetup
    measures: ImpactMeasures
    run: ExplicitResult
    mesh: Mesh
    load_cell: np.ndarray
    targets: tuple[RigidPlane | RigidCylinder, ...] = ()

    @property
    def max_deflection(self) -> float:
        """The ball's deflection: the largest approach of its centre of mass toward the target
        after the first contact [m] (:func:`batball.lab.measures.max_approach`)."""
        run = self.run
        direction = run.com_velocity[0] / np.linalg.norm(run.com_velocity[0])
        return max_approach(run.time, run.com_velocity @ direction, run.contact_nodes > 0)


def run_impact(
    ball: BallSpec, setup: ImpactSetup, *, progress: Callable[[float], None] | None = None
) -> ImpactResult:
    """Build, run and measure one impact test (the setup's hourglass control, else the ball's)."""
    setup = with_ball_hourglass(setup, ball)
    model = build_impact_model(ball, setup)
    controls = ExplicitControls(
        end_time=setup.end_time,
        time_step_scale=setup.time_step_scale,
        hourglass=ball_hourglass(setup.hourglass, ball),
        bulk_viscosity=setup.bulk_viscosity,
        separation_time=setup.separation_time,
        precision=setup.precision,
    )
    run, load_cell, measures = run_impact_model(
        model, controls, setup.contact_threshold, progress=progress
    )
    return ImpactResult(
        ball=ball, setup=setup, measures=measures, run=run, mesh=model.mesh, load_cell=load_cell,
        targets=tuple(contact.target for contact in model.contacts),
    )  # fmt: skip


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
    speed = float(np.linalg.norm(model.initial_velocity[0]))
    direction = model.initial_velocity[0] / speed
    if not run.contact_nodes.any():
        # how far the ball's centre went along the flight line: beyond its own size, it went
        # through the target rather than not reaching it
        travelled = float(np.trapezoid(run.com_velocity @ direction, run.time))
        size = float(np.ptp(model.mesh.points @ direction))
        if travelled > size:
            raise SimulationError(
                f"the ball went through the target without touching it ({travelled * 1e3:.1f} mm "
                f"in {controls.end_time * 1e3:.2f} ms, more than its {size * 1e3:.1f} mm): the "
                "contact missed it; lower the speed or the time-step scale, or check the mesh"
            )
        raise SimulationError(
            f"the ball never reached the target in the end time {controls.end_time * 1e3:.2f} ms "
            f"({travelled * 1e3:.1f} mm travelled), so no rebound can be measured; raise end_time"
        )
    if run.contact_nodes[-1] > 0:
        raise SimulationError(
            f"the ball is still in contact with the target at the end time "
            f"{controls.end_time * 1e3:.2f} ms, so no rebound can be measured; raise end_time or "
            "check the material"
        )
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
