"""A ball's hourglass control as part of its model: the ball file's ``[hourglass]`` runs as the
test's ``--hourglass-type``/``--hourglass-coefficient`` would, a test's option replaces it, and
a ball that names none keeps its run keys."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest
import tomli_w

from batball.cli import main
from batball.lab.bbs_run import bbs_inputs
from batball.lab.impact import run_impact
from batball.lab.impact_run import ball_test_inputs
from batball.models.bbs import BbsSetup, build_bbs_model
from batball.models.impact import ImpactSetup
from batball.solvers.explicit import HourglassControl
from batball.specs import BallHourglass, ball_spec_to_toml_dict, load_ball_spec, load_bat_spec
from batball.units import MPH

SEED = HourglassControl(type=4, coefficient=0.01)  # the seed-check's stiffness form


def _stiff_ball() -> object:
    return dataclasses.replace(load_ball_spec("type1"), hourglass=BallHourglass(4, 0.01))


def test_the_balls_own_hourglass_runs_as_the_tests_option_and_the_option_wins() -> None:
    """Three coarse CCOR runs: the ball naming IHQ 4 with no option equals the plain ball with
    the option (to the bit: the same arithmetic); the option IHQ 1 on that ball equals the plain
    ball's default; and IHQ 4 is not IHQ 1 here (the form is in effect)."""
    plain, stiff = load_ball_spec("type1"), _stiff_ball()
    setup = ImpactSetup(test="ccor", speed=95 * MPH, divisions=3)
    own = run_impact(stiff, setup)
    option = run_impact(plain, dataclasses.replace(setup, hourglass=SEED))
    assert own.measures.restitution == option.measures.restitution
    assert own.setup.hourglass == SEED  # the result names the control it ran with
    replaced = run_impact(stiff, dataclasses.replace(setup, hourglass=HourglassControl()))
    default = run_impact(plain, setup)
    assert replaced.measures.restitution == default.measures.restitution
    assert abs(own.measures.restitution - default.measures.restitution) > 1e-4


def test_a_ball_without_one_keeps_its_run_keys() -> None:
    """The stores made before balls could name a control stay valid: a plain ball's key with
    the test's default (None) is the key of the solver default written out."""
    plain = load_ball_spec("type2")
    setup = ImpactSetup(test="ccor", speed=95 * MPH, divisions=3)
    written = dataclasses.replace(setup, hourglass=HourglassControl())
    assert ball_test_inputs(plain, setup) == ball_test_inputs(plain, written)
    bat = load_bat_spec("default")
    assert bbs_inputs(bat, plain, BbsSetup()) == bbs_inputs(
        bat, plain, BbsSetup(hourglass=HourglassControl())
    )
    # and a ball that names one is another run than the plain ball with the same option
    assert ball_test_inputs(_stiff_ball(), setup) != ball_test_inputs(
        load_ball_spec("type1"), dataclasses.replace(setup, hourglass=SEED)
    )


def test_the_bat_collision_takes_the_balls_hourglass() -> None:
    bat = load_bat_spec("default")
    setup = BbsSetup(ball_divisions=3, circumferential=8, axial_size=0.0254)
    ball = build_bbs_model(bat, _stiff_ball(), setup).coupled.ball
    assert (ball.hourglass_type, ball.hourglass_coefficient) == (4, 0.01)
    ball = build_bbs_model(
        bat, _stiff_ball(), dataclasses.replace(setup, hourglass=HourglassControl())
    ).coupled.ball
    assert (ball.hourglass_type, ball.hourglass_coefficient) == (1, 0.1)


def test_the_command_reports_the_control_it_ran_with(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "stiff.toml"
    path.write_text(tomli_w.dumps(ball_spec_to_toml_dict(_stiff_ball())))
    base = ["cor", "--ball", str(path), "--divisions", "3", "--json", "--runs-dir", str(tmp_path)]
    assert main(base) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["hourglass_type"], summary["hourglass_coefficient"]) == (4, 0.01)
    assert main([*base, "--hourglass-type", "2"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["hourglass_type"], summary["hourglass_coefficient"]) == (2, 0.1)


def test_the_ball_file_allows_exactly_the_types_the_hex_kernel_has() -> None:
    """The spec layer cannot import the element layer, so the two lists are kept apart: a type
    the ball file accepts must be one the kernel runs, and the other way round."""
    from batball.elements.hex8 import HOURGLASS_TYPES
    from batball.specs.ball import BALL_HOURGLASS_TYPES

    assert set(BALL_HOURGLASS_TYPES) == set(HOURGLASS_TYPES)
