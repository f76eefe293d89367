"""Calibrating a foam ball: the seed ball as a foam, the curves carried through candidates and
run keys, and a tiny end-to-end ``batball calibrate --model mat057`` whose saved ball runs."""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import pytest

from batball.calibrate import CalibrationProblem, make_parameter_space, seed_targets
from batball.calibrate.command import starting_ball
from batball.calibrate.evaluate import RunRequest
from batball.cli import main
from batball.materials.foam import FoamCurve
from batball.specs import load_ball_spec

TINY = ["--quick", "--coarse-divisions", "3", "--global-points", "1", "--max-evaluations", "2",
        "--workers", "0", "--no-progress", "--json"]  # fmt: skip


def test_a_seed_ball_starts_as_the_example_foam_with_its_own_size_and_mass() -> None:
    args = argparse.Namespace(ball="type2", model="mat083")
    ball = starting_ball(args)
    seed, example = load_ball_spec("type2"), load_ball_spec("foam083")
    assert (ball.name, ball.mass, ball.circumference) == (seed.name, seed.mass, seed.circumference)
    assert ball.material == example.material


def test_candidates_keep_the_curves_and_the_run_key_sees_them() -> None:
    ball = load_ball_spec("foam057")
    space = make_parameter_space(ball.material.material_law, ball.material.values, ["hu"])
    problem = CalibrationProblem(ball, space, seed_targets("type1"), divisions=3)
    candidate = problem.candidate(space.values([0.5]))
    assert candidate is not None and candidate.material.curves == ball.material.curves
    # HU in (0, 1]: the default interval starts 1 % in, at 0.01
    assert candidate.material.values["hu"] == pytest.approx(0.01 + 0.5 * 0.99)
    stiffer = FoamCurve(strain=(0.0, 0.5), stress=(0.0, 2e6))
    other = dataclasses.replace(
        ball, material=dataclasses.replace(ball.material, curves=(stiffer,))
    )
    keys = {RunRequest(b, "ccor", 42.0, 3).key for b in (ball, other)}
    assert len(keys) == 2


def test_calibrate_a_foam_and_run_the_saved_ball(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    saved = tmp_path / "fitted.toml"
    args = ["calibrate", "--ball", "type1", "--model", "mat057", "--free", "curve_scale",
            "--study", str(tmp_path / "s.db"), "--save", str(saved)]  # fmt: skip
    assert main([*args, *TINY]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["model"] == "mat057" and list(report["parameters"]) == ["curve_scale"]
    fitted = load_ball_spec(saved)
    assert fitted.material.law == "mat057" and len(fitted.material.curves) == 1
    scale = report["parameters_si"]["curve_scale"]
    assert fitted.material.values["curve_scale"] == pytest.approx(scale, rel=1e-11)
    assert main(["cor", "--ball", str(saved), "--divisions", "3", "--speed", "60 mph",
                 "--json", "--runs-dir", str(tmp_path / "runs")]) == 0  # fmt: skip
    assert 0.0 < json.loads(capsys.readouterr().out)["cor"] < 1.0
