"""The virtual ball-compression test (ASTM F1888; docs/physics.md section 3.2; the seed's "Ball
Compression").

The ball sits between two rigid flat plates; the bottom plate is fixed and the top plate moves
down at the test's rate (1 in/min) until it has travelled 0.25 in; the force at 0.25 in is the
ball's compression. The ball is an isotropic sphere here (no seams are modelled), compressed along
the mesh's z axis.

How it is solved, and why it is quasi-static. The seed solved this implicitly. Here the explicit
solver runs it in *real time* with mass scaling and light damping (a dynamic relaxation that keeps
the true time axis):

* The plate moves at the real 1 in/min, so the loading lasts the real 15 s and the viscoelastic
  law sees the real strain rates; MAT_006 relaxes to G_inf within a few 1/beta (about 13 us for
  the seed's balls), which is what governs the compression force.
* The density is multiplied by s, which slows every vibration of the ball by sqrt(s) and lengthens
  the stable step by sqrt(s) without changing any static answer. s is chosen so that the loading
  time is ``quasi_static_ratio`` radians of the ball's lowest "squash" mode (the ball's mass on
  the two Hertz contacts at full travel); the run then takes about ratio / (omega dt) steps.
* The plates push through penalty contact, whose springs let the ball sink a little into each
  plate. The test's displacement is the ball's own deformation (rigid plates in the lab), so it
  is read as the plate travel minus the deepest penetration into each plate, and the run goes on
  past 0.25 in of travel until the deformation has reached 0.25 in.
* Mass-proportional damping at ``damping_ratio`` of that mode's critical damping removes the
  start-up ring. Its drag on the ball's rigid drift (the centre moves at half the plate speed)
  loads the two plates unequally by the same amount, so the reported force is the mean of the
  top and bottom plate forces, and their difference is reported as a check.

Quasi-static checks reported with every run: kinetic over internal energy at the end, the
top-bottom force difference, and the energy balance against the plates' work. That the answer
does not depend on the solver's loading rate is shown by running two ratios
(``tests/verification/test_compression.py``, ``docs/notes/compression.md``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.errors import SimulationError
from batball.mesh import Mesh
from batball.models.ball import ball_hourglass, with_ball_hourglass
from batball.models.compression import (
    TRAVEL_MARGIN,
    CompressionSetup,
    build_compression_model,
    relaxed_hertz,
)
from batball.solvers.explicit import (
    BALANCE,
    ENERGY_COLUMNS,
    ExplicitControls,
    ExplicitResult,
    Model,
    run_explicit,
)
from batball.specs import BallSpec
from batball.units import IN


@dataclass(frozen=True)
class CompressionResult:
    """A compression run: the curve, the reading at full travel and the quasi-static checks.

    Attributes:
        displacement, force: (samples,) the ball's deformation (plate travel minus the contact
            penetrations) [m] and the mean plate force [N].
        force_difference: (samples,) top minus bottom plate force [N].
        penetration: the contact penetration (both plates) at full deformation [m].
        compression: the force at ``setup.displacement`` [N], read off the curve (the test's
            definition).
        compression_fit: the same force from the least-squares power law F = C d^(3/2) over
            the last 40 % of the travel [N]: it averages the steps the curve takes as each ring
            of surface nodes reaches a plate (docs/notes/compression.md), so it varies less with
            the mesh.
        compression: the force at ``setup.displacement`` [N].
        kinetic_to_internal: kinetic over internal energy at the end.
        mass_scale: the density factor s; damping: the damping coefficient [1/s].
        targets: the run's plates, top then bottom (for the field output).
    """

    ball: BallSpec
    setup: CompressionSetup
    mesh: Mesh
    run: ExplicitResult
    displacement: np.ndarray
    force: np.ndarray
    force_difference: np.ndarray
    penetration: float
    compression: float
    compression_fit: float
    kinetic_to_internal: float
    energy_balance_error: float
    mass_scale: float
    damping: float
    targets: tuple[RigidPlane | RigidCylinder, ...] = ()

    @property
    def max_deflection(self) -> float:
        """The ball's largest deformation between the plates over the run, plate travel minus
        the penetration into both plates [m] (the displacement the test reads its force at)."""
        run = self.run
        return float(np.max(self.setup.rate * run.time - run.penetration.sum(axis=1)))


def power_law_reading(displacement: np.ndarray, force: np.ndarray, at: float) -> float:
    """C at^(3/2) with C the least-squares fit of F = C d^(3/2) over 0.6 at <= d <= at [N]."""
    span = (displacement >= 0.6 * at) & (displacement <= at)
    basis = displacement[span] ** 1.5
    return float(force[span] @ basis / (basis @ basis) * at**1.5)


def run_compression(
    ball: BallSpec, setup: CompressionSetup, *, progress: Callable[[float], None] | None = None
) -> CompressionResult:
    """Build, run and measure one compression test (the setup's hourglass control, else the
    ball's)."""
    setup = with_ball_hourglass(setup, ball)
    model, scale, damping = build_compression_model(ball, setup)
    loading_time = setup.displacement / setup.rate
    hertz_force = relaxed_hertz(model.material_constants[0], ball.radius, setup.displacement)[0]
    controls = ExplicitControls(
        end_time=TRAVEL_MARGIN * loading_time,
        time_step_scale=setup.time_step_scale,
        hourglass=ball_hourglass(setup.hourglass, ball),
        bulk_viscosity=setup.bulk_viscosity,
        mass_damping=damping,
        frame_count=20,
        # 1 % of the Hertz estimate of the plates' work, the integral of F ~ d^1.5: 0.4 F d
        energy_floor=0.01 * 0.4 * hertz_force * setup.displacement,
    )
    run, grid, force, difference, sunk_at_end, ratio, error = run_compression_model(
        model, controls, setup.rate, setup.displacement, setup.samples, progress=progress
    )
    return CompressionResult(
        ball=ball,
        setup=setup,
        mesh=model.mesh,
        run=run,
        displacement=grid,
        force=force,
        force_difference=difference,
        penetration=sunk_at_end,
        compression=float(force[-1]),
        compression_fit=power_law_reading(grid, force, setup.displacement),
        kinetic_to_internal=ratio,
        energy_balance_error=error,
        mass_scale=scale,
        damping=damping,
        targets=tuple(contact.target for contact in model.contacts),
    )


def run_compression_model(
    model: Model,
    controls: ExplicitControls,
    rate: float,
    displacement: float,
    samples: int,
    *,
    progress: Callable[[float], None] | None = None,
) -> tuple[ExplicitResult, np.ndarray, np.ndarray, np.ndarray, float, float, float]:
    """Run a ball between a top plate (contact 0) moving at ``rate`` and a fixed bottom plate
    (contact 1) and read the curve: shared by :func:`run_compression` and the keyword-deck runner.

    Returns the run, the deformation grid [m], the mean plate force and the top-bottom difference
    on it [N], the penetration at full deformation [m], kinetic over internal energy at the end,
    and the energy balance error over the plates' work.
    """
    run = run_explicit(model, controls, progress=progress)
    sunk = run.penetration.sum(axis=1)
    deformation = np.maximum.accumulate(rate * run.time - sunk)
    if deformation[-1] < displacement:
        raise SimulationError(
            f"the ball deformed only {deformation[-1] / IN:.4f} in after "
            f"{rate * run.time[-1] / IN:.4f} in of plate travel: the contact penalty lets "
            f"it sink {sunk[-1] / IN:.4f} in into the plates; raise the contact scale (SFS)"
        )
    top = run.reaction[:, 0, 2]
    bottom = -run.reaction[:, 1, 2]
    grid = np.linspace(0.0, displacement, samples)
    force = np.interp(grid, deformation, 0.5 * (top + bottom))
    difference = np.interp(grid, deformation, top - bottom)
    at_end = int(np.searchsorted(deformation, displacement))
    energies = run.energies[-1]
    external = abs(energies[ENERGY_COLUMNS.index("contact")])
    internal = energies[ENERGY_COLUMNS.index("internal")]
    ratio = float(energies[ENERGY_COLUMNS.index("kinetic")] / max(internal, 1e-300))
    error = float(np.abs(run.energies[:, BALANCE]).max() / max(external, 1e-300))
    return run, grid, force, difference, float(sunk[at_end]), ratio, error
