"""The virtual batted-ball-speed test (ASTM F2219 as the seed ran it, docs/physics.md section 4).

The bat, at rest, may turn about a pivot axis 6 in from the knob (z; the bat's axis is x); the
ball is fired along -y at the barrel 6 in from the end cap. The run goes on until the ball has
left the bat and its speed is steady (the seed ran 2 ms). Measurements (docs/physics.md
sections 4.1-4.2):

* collision efficiency e_A = v_out / v_in, v the ball's centre-of-mass speed along the flight
  line (v_out > 0: rebound);
* BBCOR e = e_A (1 + k) + k with k = m_ball z^2 / I_pivot, z the pivot-to-impact distance and
  I_pivot the lumped bat's MOI about the pivot (without the mass that selective mass scaling
  adds to the model); cross-checked by e = (v_out + omega z) / v_in with
  omega the bat's rigid-body angular velocity after the impact (its angular momentum about the
  pivot over I_pivot);
* BBS = e_A v_pitch + (1 + e_A) v_bat, 25 and 85 mph by default (the ASA slow-pitch constants
  that make the seed's Table 9 consistent, docs/physics.md sections 4.2 and 4.4).

The model: :mod:`batball.solvers.ball_bat` (one explicit scheme, hex ball, Belytschko-Tsay
shells, penalty contact both ways, the pivot as a rigid band turning about the axis). Contact
stiffness, LS-DYNA SOFT = 0 style (docs/physics.md section 6.6): every ball surface node keeps the
stiffness the ball tests give it (SLSFAC K A^2 / V of its faces, the ball being the softer side); a
bat node against the ball gets the ball faces' stiffness per area, SLSFAC K A / V, times its own
tributary area. The insert touches the barrel's bore through a node-to-column contact
(:mod:`batball.contact.columns`; shell thicknesses as offsets, stiffness SLSFAC E A / diagonal
of the barrel's segments).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from batball.contact.columns import ColumnContact
from batball.errors import SimulationError
from batball.lab.fit_store import FitRelaxation, fit_inputs, obtain_fit
from batball.models.ball import with_ball_hourglass
from batball.models.bbs import (
    BbsModel,
    BbsSetup,
    build_bbs_model,
    insert_pressure,
    relaxation_cycles,
    with_bat_friction,
)
from batball.solvers.ball_bat import (
    RELAX_FACTOR,
    CoupledControls,
    CoupledResult,
    CoupledSolver,
)
from batball.specs import BallSpec, BatSpec


def coupled_controls(setup: BbsSetup) -> CoupledControls:
    """The coupled solver's controls of a batted-ball-speed run with ``setup``."""
    return CoupledControls(end_time=setup.end_time, time_step_scale=setup.time_step_scale,
                           search_interval=setup.search_interval,
                           separation_time=setup.separation_time, precision=setup.precision,
                           shell_hourglass_ratio=setup.shell_hourglass_ratio,
                           bat_damping=setup.bat_damping)  # fmt: skip


def run_bbs_model(model: BbsModel, setup: BbsSetup, *, store: Path | None = None,
                  reuse: bool = True) -> CoupledResult:  # fmt: skip
    """Pre-stress the bat (when asked and it has an insert; from the fit stored under
    ``store``, :mod:`batball.lab.fit_store`, when it is there and ``reuse``), then run the
    impact to the end time or separation."""
    solver = CoupledSolver(model.coupled, coupled_controls(setup))
    inserts = model.coupled.contacts[model.coupled.ball_contacts :]
    ratio, pressure, reused = float("nan"), float("nan"), False
    if setup.prestress and inserts:
        bat = model.coupled.bat
        ramp, settle = relaxation_cycles(setup, bat.stable_step)
        relaxation = FitRelaxation(model.interference, ramp, settle, setup.search_interval,
                                   bat.stable_step, RELAX_FACTOR,
                                   setup.shell_hourglass_ratio, setup.bat_shell)  # fmt: skip
        inputs = fit_inputs(bat, model.bat_mesh.points, inserts, solver.bat_moving, relaxation)
        ratio, reused = obtain_fit(
            store, inputs,
            lambda: solver.relax_bat(interference=model.interference, ramp_steps=ramp,
                                     settle_steps=settle, factor=RELAX_FACTOR),
            solver.bat_points, solver.shell_state, inserts, reuse=reuse,
        )  # fmt: skip
        pressure = insert_pressure(model, solver.points)
    if model.insert_friction > 0.0:
        for pair in inserts:
            if isinstance(pair, ColumnContact):
                pair.start_friction(model.insert_friction, solver.points)
    result = solver.run()
    result.prestress_kinetic_ratio, result.interference_pressure = ratio, pressure
    result.prestress_reused = reused
    return result


@dataclass(frozen=True)
class BbsMeasures:
    """The batted-ball-speed numbers (SI; docs/physics.md section 4).

    Attributes:
        inbound_speed, rebound_speed: ball centre-of-mass speed before and after [m/s] (rebound
            > 0 back along the flight line).
        collision_efficiency: e_A = rebound / inbound.
        k: m_ball z^2 / I_pivot; bbcor: e_A (1 + k) + k; bbcor_from_bat: (rebound + omega z) /
            inbound with omega the bat's angular momentum about the pivot over I_pivot.
        bbs: e_A v_pitch + (1 + e_A) v_bat [m/s].
        peak_force: largest ball-bat contact force after a 0.02-ms moving average [N] (a lab load
            cell's bandwidth; the raw history has one-cycle spikes where single ball nodes first
            touch, see docs/notes/bbs.md); peak_force_raw: the unfiltered largest [N];
            contact_time: first to last touch [s].
        energy_balance_error: largest |balance| over the initial kinetic energy.
        angular_momentum_change: |L_end - L_0| / |L_0| about the pivot axis.
        rebound_drift: change of the ball's speed over the last ``separation_time`` [m/s] (0 when
            steady).
        pivot_inertia: the bat's MOI about the pivot [kg m^2]; model_pivot_inertia: the
            model's, with the mass that selective mass scaling added [kg m^2]; z: pivot to
            impact [m]; ball_mass: [kg].
    """

    inbound_speed: float
    rebound_speed: float
    collision_efficiency: float
    k: float
    bbcor: float
    bbcor_from_bat: float
    bbs: float
    peak_force: float
    peak_force_raw: float
    contact_time: float
    energy_balance_error: float
    angular_momentum_change: float
    rebound_drift: float
    pivot_inertia: float
    model_pivot_inertia: float
    z: float
    ball_mass: float


#: Moving-average window of the reported peak force [s].
PEAK_FILTER_WINDOW = 0.02e-3


def filtered_peak(time: np.ndarray, force: np.ndarray, window: float) -> float:
    """Largest value of ``force`` (n,) averaged over ``window`` [s] of the (non-uniform) ``time``
    (n,) [s]: the time integral over each window divided by its length."""
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(time))])
    start = np.interp(time - window, time, integral, left=0.0)
    usable = time >= time[0] + window
    if not usable.any():
        return float(force.max())
    return float(np.max((integral - start)[usable] / window))


def measure_bbs(model: BbsModel, result: CoupledResult, setup: BbsSetup) -> BbsMeasures:
    """The measurements of a finished run (module docs)."""
    t = result.column("time_s")
    vy = result.column("ball_vy")
    touching = np.flatnonzero(result.column("ball_nodes_in_contact") > 0)
    if touching.size == 0 or touching[-1] == len(t) - 1:
        raise SimulationError(
            f"the ball is still touching the bat at the end time "
            f"{setup.end_time * 1e3:.2f} ms: no rebound speed to measure"
        )
    inbound, rebound = -vy[0], vy[-1]
    e_a = rebound / inbound
    k = result.ball_mass * model.z**2 / model.pivot_inertia
    # the bat's angular momentum over the real bat's MOI (the model's carries the added mass)
    omega = result.column("bat_omega_rad_s")[-1] * result.pivot_inertia / model.pivot_inertia
    after = t >= t[-1] - setup.separation_time
    momentum = result.column("angular_momentum")
    kinetic0 = result.column("kinetic_j")[0]
    return BbsMeasures(
        inbound_speed=float(inbound),
        rebound_speed=float(rebound),
        collision_efficiency=float(e_a),
        k=float(k),
        bbcor=float(e_a * (1.0 + k) + k),
        bbcor_from_bat=float((rebound - omega * model.z) / inbound),
        bbs=float(e_a * setup.pitch_speed + (1.0 + e_a) * setup.swing_speed),
        peak_force=filtered_peak(t, result.column("contact_force_n"), PEAK_FILTER_WINDOW),
        peak_force_raw=float(result.column("contact_force_n").max()),
        contact_time=float(t[touching[-1]] - t[touching[0]]),
        energy_balance_error=float(np.abs(result.column("balance_error_j")).max() / kinetic0),
        angular_momentum_change=float(abs(momentum[-1] - momentum[0]) / abs(momentum[0])),
        rebound_drift=float(np.ptp(vy[after])),
        pivot_inertia=model.pivot_inertia,
        model_pivot_inertia=result.pivot_inertia,
        z=model.z,
        ball_mass=result.ball_mass,
    )


@dataclass(frozen=True)
class BbsResult:
    """A batted-ball-speed run: inputs, model, histories and measurements."""

    bat: BatSpec
    ball: BallSpec
    setup: BbsSetup
    model: BbsModel
    run: CoupledResult
    measures: BbsMeasures


def run_bbs(bat: BatSpec, ball: BallSpec, setup: BbsSetup, *, store: Path | None = None,
            reuse: bool = True) -> BbsResult:  # fmt: skip
    """Build, run and measure one batted-ball-speed test (``store``: the runs folder that keeps
    the bat's relaxed fit, :func:`run_bbs_model`)."""
    setup = with_bat_friction(with_ball_hourglass(setup, ball), bat)
    model = build_bbs_model(bat, ball, setup)
    run = run_bbs_model(model, setup, store=store, reuse=reuse)
    return BbsResult(bat, ball, setup, model, run, measure_bbs(model, run, setup))
