"""The optimiser recovers known parameters from a synthetic target made with other values."""

from __future__ import annotations

import dataclasses

import pytest

from batball.calibrate import (
    CalibrationProblem,
    Evaluator,
    OptimiserOptions,
    StudyStore,
    Target,
    calibrate,
    make_parameter_space,
    open_executor,
)
from batball.calibrate.study import INFEASIBLE_RESIDUAL
from batball.lab.impact import run_impact
from batball.models.impact import ImpactSetup
from batball.specs import MaterialSpec, load_ball_spec

PSI = 6894.757293168361
MPH = 0.44704
DIVISIONS = 4  # 448 hexes, 0.2 s a run on one thread


def synthetic_targets(ball, values: dict, speeds: tuple[float, ...]) -> tuple[Target, ...]:
    """CCOR, DS, peak force and contact time of ``ball`` with ``values``, as measurements."""
    truth = dataclasses.replace(ball, material=MaterialSpec(law="mat006", values=values))
    targets = []
    for speed in speeds:
        m = run_impact(truth, ImpactSetup(test="ccor", speed=speed, divisions=DIVISIONS)).measures
        targets += [
            Target("ccor", speed, m.restitution),
            Target("dynamic_stiffness", speed, m.dynamic_stiffness),
            Target("peak_force", speed, m.peak_force),
            Target("contact_time", speed, m.contact_time),
        ]
    return tuple(targets)


def test_least_squares_recovers_g0_and_beta_of_a_synthetic_ball() -> None:
    """Truth g0 = 30000 psi, beta = 50000/s; start at the seed's 22500 psi, 75000/s.

    Same mesh for truth and fit, so a zero-residual optimum exists; what limits the recovery is
    the noise of the FE outputs under a 2 %-of-box finite-difference step and the optimiser's
    stopping tolerances (xtol 1e-3 of the box = 0.5 % in a log box of two decades): 2 % allowed.
    """
    ball = load_ball_spec("type1")
    truth = dict(ball.material.values, g0=30000 * PSI, beta=50000.0)
    targets = synthetic_targets(ball, truth, (95 * MPH,))
    space = make_parameter_space(ball.material.material_law, ball.material.values, ["g0", "beta"])
    problem = CalibrationProblem(ball, space, targets, divisions=DIVISIONS)
    options = OptimiserOptions(
        global_points=4, coarse_divisions=DIVISIONS, coarse_evaluations=20, fine_divisions=None
    )
    with open_executor(workers=0) as executor:
        result = calibrate(problem, Evaluator(StudyStore(":memory:"), executor), options)
    assert result.best.values["g0"] == pytest.approx(truth["g0"], rel=0.02)
    assert result.best.values["beta"] == pytest.approx(truth["beta"], rel=0.02)


def test_candidate_breaking_g_inf_below_g0_is_infeasible_not_an_error() -> None:
    ball = load_ball_spec("type1")
    space = make_parameter_space(ball.material.material_law, ball.material.values, ["g_inf"])
    targets = (Target("ccor", 95 * MPH, 0.38),)
    problem = CalibrationProblem(ball, space, targets, divisions=DIVISIONS)
    values = dict(ball.material.values, g_inf=2 * ball.material.values["g0"])
    with open_executor(workers=0) as executor:
        (evaluation,) = problem.evaluate_values(
            [values], Evaluator(StudyStore(":memory:"), executor)
        )
    assert evaluation.residuals.tolist() == [INFEASIBLE_RESIDUAL]
