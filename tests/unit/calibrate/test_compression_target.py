"""A calibration with a compression target (ASTM F1888) runs end to end on a tiny mesh."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from batball.calibrate import (
    CalibrationProblem,
    Evaluator,
    StudyStore,
    Target,
    make_parameter_space,
    open_executor,
)
from batball.calibrate.evaluate import COMPRESSION_DIVISIONS, COMPRESSION_RATIO
from batball.lab.compression import run_compression
from batball.models.compression import CompressionSetup
from batball.specs import load_ball_spec

LBF = 4.4482216152605  # N
MPH = 0.44704  # m/s
DIVISIONS = 4  # 448 hexes: a compression run takes 1-3 s on one thread


def relaxed_e_star(bulk: float, shear: float) -> float:
    """E* = E / (1 - nu^2) of an isotropic solid from K and G (Johnson, Contact Mechanics 4.2)."""
    young = 9.0 * bulk * shear / (3.0 * bulk + shear)
    nu = (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))
    return young / (1.0 - nu**2)


def test_compression_target_takes_one_compression_run_per_candidate(tmp_path: Path) -> None:
    ball = load_ball_spec("type2")
    targets = (
        Target("ccor", 95 * MPH, 0.46),
        Target("compression", 0.0, 375 * LBF),
    )
    space = make_parameter_space(ball.material.material_law, ball.material.values, ["g_inf"])
    problem = CalibrationProblem(ball, space, targets, divisions=DIVISIONS)
    assert problem.runs() == [("ccor", 95 * MPH), ("compression", 0.0)]
    doubled = dict(ball.material.values, g_inf=2.0 * ball.material.values["g_inf"])
    store = StudyStore(tmp_path / "study.db")
    with open_executor(workers=0) as executor:
        evaluator = Evaluator(store, executor)
        base, stiff = problem.evaluate_values([dict(ball.material.values), doubled], evaluator)
    assert evaluator.computed == 4  # a CCOR and a compression run per candidate
    # the calibration's compression is the lab test's power-law reading at its settings
    lab = run_compression(
        ball, CompressionSetup(divisions=DIVISIONS, quasi_static_ratio=COMPRESSION_RATIO)
    )
    assert base.simulated[1] == pytest.approx(lab.compression_fit, rel=1e-12)
    assert base.residuals[1] == pytest.approx((lab.compression_fit / (375 * LBF) - 1) / 0.05)
    # the relaxed ball is elastic: the force scales with E*(K, G_inf) (Hertz); 5 % on this
    # 448-hex mesh, whose contact patch spans one or two elements (docs/notes/compression.md)
    expected = relaxed_e_star(ball.material.values["bulk_modulus"], doubled["g_inf"]) / (
        relaxed_e_star(ball.material.values["bulk_modulus"], ball.material.values["g_inf"])
    )
    assert stiff.simulated[1] / base.simulated[1] == pytest.approx(expected, rel=0.05)
    assert np.all(np.isfinite(stiff.residuals))
    store.close()


def test_compression_runs_on_the_coarse_mesh_in_every_stage() -> None:
    ball = load_ball_spec("type1")
    space = make_parameter_space(ball.material.material_law, ball.material.values, ["g_inf"])
    problem = CalibrationProblem(ball, space, (Target("compression", 0.0, 1e3),), divisions=12)
    assert problem.run_divisions("compression") == COMPRESSION_DIVISIONS == 8
    assert problem.run_divisions("ccor") == 12
    coarse = dataclasses.replace(problem, divisions=6)
    assert coarse.run_divisions("compression") == 6


def test_report_row_of_a_compression_target_has_lbf_and_no_speed() -> None:
    from batball.calibrate.command import target_rows

    target = Target("compression", 0.0, 375 * LBF)
    (row,) = target_rows([target], [target], np.array([390 * LBF]))
    assert row["target"] == "compression @ 0.25 in" and row["speed_mph"] is None
    assert row["unit"] == "lbf"
    assert (row["measured"], row["fitted"]) == pytest.approx((375, 390), rel=1e-12)
    assert row["fitted_pct"] == pytest.approx(4.0) and row["goal_pct"] == pytest.approx(5.0)
