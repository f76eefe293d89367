"""The insert's interface as a property of the bat: read from the bat file, used by the tests
that load the insert unless their option overrides it, and free in ``batball fit-bat``; and
Table 2 as a fit target."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from batball.calibrate.bat_fit import BarrelTargets, FreeParameter, joint_resolution
from batball.calibrate.bat_sensitivity import default_spread
from batball.cli import main
from batball.errors import SimulationError, SpecError
from batball.lab.bbs_run import bbs_inputs
from batball.models.barrel import BarrelTestOptions
from batball.models.bbs import BbsSetup
from batball.solvers.ball_bat import relax_fit
from batball.specs import load_ball_spec, load_bat_spec
from batball.specs.bat import bat_spec_from_dict, bat_spec_to_toml_dict


def with_friction(mu: float):  # noqa: ANN201
    spec = load_bat_spec("fitted")
    return dataclasses.replace(spec, insert=dataclasses.replace(spec.insert, friction=mu))


def test_the_bat_file_carries_the_insert_friction() -> None:
    document = bat_spec_to_toml_dict(with_friction(0.35))
    assert bat_spec_from_dict(document, source="x").insert.friction == 0.35
    # a frictionless insert writes no key, so the run keys of every stored bat stay as they were
    assert "friction" not in bat_spec_to_toml_dict(load_bat_spec("fitted"))["insert"]
    for bad, allowed in (("0.3", "without a unit"), (-0.1, "0 .. 10"), (11.0, "0 .. 10")):
        document["insert"]["friction"] = bad
        with pytest.raises(SpecError, match=f"insert.friction.*{allowed}"):
            bat_spec_from_dict(document, source="x")


def test_friction_is_a_free_parameter_of_the_insert_only() -> None:
    spec = load_bat_spec("fitted")
    parameter = FreeParameter.parse("friction:insert")
    assert parameter.value(spec) == 0.0
    assert parameter.apply(spec, 0.4).insert.friction == 0.4
    assert default_spread(parameter, spec) == 0.3
    for text in ("friction:endcap", "friction:insert@barrel-1"):
        with pytest.raises(SpecError, match="friction:insert"):
            FreeParameter.parse(text)
    with pytest.raises(SpecError, match="no insert"):
        parameter.value(dataclasses.replace(spec, insert=None))


def test_the_tests_take_the_bats_friction_unless_given_one() -> None:
    rubbing = with_friction(0.25)
    assert BarrelTestOptions().for_bat(rubbing).insert_friction == 0.25
    assert BarrelTestOptions(friction=0.0).for_bat(rubbing).insert_friction == 0.0
    with pytest.raises(SimulationError, match="for_bat"):
        _ = BarrelTestOptions().frictional
    ball = load_ball_spec("type1-fit")
    assert bbs_inputs(rubbing, ball, BbsSetup())["setup"]["insert_friction"] == 0.25
    assert bbs_inputs(rubbing, ball, BbsSetup(insert_friction=0.0))["setup"][
        "insert_friction"] == 0.0  # fmt: skip
    assert bbs_inputs(load_bat_spec("fitted"), ball, BbsSetup())["setup"]["insert_friction"] == 0


def test_a_diverging_fit_relaxation_stops_with_where() -> None:
    mass = np.ones((2, 6))
    velocity = np.zeros((2, 6))
    with pytest.raises(SimulationError, match="cycle 1 of 4"):
        relax_fit([], interference=0.0, ramp_steps=2, settle_steps=2, search_interval=1,
                  points=np.zeros((2, 3)), forces=lambda: np.full((2, 6), np.nan), mass=mass,
                  velocity=velocity, moving=np.ones(2, bool), dt=1e-7)  # fmt: skip


def test_table2_targets_are_the_seeds_with_assumed_resolutions() -> None:
    targets = BarrelTargets()
    assert targets.names == ("preload_lbf", "final_load_lbf")
    assert targets.wanted == pytest.approx((186.0, 368.0))  # seed Table 2, experiment
    assert BarrelTargets(loads=("final_load",)).wanted == pytest.approx((368.0,))
    assert joint_resolution("preload_lbf", 186.0) == 0.05
    assert joint_resolution("final_load_lbf", 368.0) == 0.03
    with pytest.raises(SpecError, match="barrel loads"):
        BarrelTargets(loads=("peak",))
    with pytest.raises(SpecError, match="barrel correction"):
        BarrelTargets(correction=(1.0,))


def test_fit_bat_barrel_options_are_checked_before_anything_runs(capsys) -> None:  # noqa: ANN001
    assert main(["fit-bat", "--to", "mass", "--barrel"]) == 2
    assert "--to joint" in capsys.readouterr().err
    assert main(["fit-bat", "--to", "joint", "--barrel", "--preload", "0 lbf"]) == 2
    assert "preload" in capsys.readouterr().err
    assert main(["fit-bat", "--to", "joint", "--barrel", "--free", "friction:insert", "--spread",
                 "friction:insert=0.2 mph"]) == 2  # fmt: skip
    assert "without a unit" in capsys.readouterr().err
    # options that only Table 2 uses, and the parameter only Table 2 sees, need --barrel
    assert main(["fit-bat", "--to", "joint", "--preload", "190 lbf"]) == 2
    assert "only with --barrel" in capsys.readouterr().err
    assert main(["fit-bat", "--to", "joint", "--free", "friction:insert"]) == 2
    assert "only with --barrel" in capsys.readouterr().err


def test_a_deck_refuses_a_bat_whose_insert_rubs(tmp_path, capsys) -> None:  # noqa: ANN001
    path = tmp_path / "rubbing.toml"
    import tomli_w

    path.write_text(tomli_w.dumps(bat_spec_to_toml_dict(with_friction(0.3))), encoding="utf-8")
    assert main(["export", "barrel", "--bat", str(path), "-o", str(tmp_path / "b.k")]) == 2
    assert "insert.friction" in capsys.readouterr().err
    # the test's own option set to 0 is what the deck carries
    assert main(["export", "barrel", "--bat", str(path), "--friction", "0", "--circumferential",
                 "16", "--axial-size", "0.5 in", "-o", str(tmp_path / "b.k")]) == 0  # fmt: skip
