"""``batball calibrate``: JSON report, the saved ball used by another test, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from batball.cli import main
from batball.specs import load_ball_spec

PSI = 6894.757293168361
TINY = ["--quick", "--coarse-divisions", "4", "--global-points", "2", "--max-evaluations", "3",
        "--workers", "0", "--no-progress", "--json"]  # fmt: skip


def test_calibrate_reports_every_seed_target_and_saves_a_ball_ccor_can_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    saved = tmp_path / "fitted.toml"
    args = ["calibrate", "--ball", "type2", "--free", "g0", "--study", str(tmp_path / "s.db")]
    assert main([*args, *TINY, "--save", str(saved)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert [r["target"] for r in report["targets"]][:4] == [
        "ccor @ 95 mph", "dynamic_stiffness @ 95 mph", "peak_force @ 95 mph",
        "contact_time @ 95 mph",
    ]  # fmt: skip
    ds = report["targets"][1]
    assert (ds["measured"], ds["seed_fe"], ds["unit"]) == pytest.approx((5760, 4610, "lbf/in"))
    assert ds["seed_fe_pct"] == pytest.approx(100 * (4610 - 5760) / 5760)
    assert list(report["parameters"]) == ["g0"] and report["parameters"]["g0"].endswith("psi")
    fitted = load_ball_spec(saved)
    assert fitted.material.values["g0"] == pytest.approx(report["parameters_si"]["g0"], rel=1e-11)
    assert fitted.material.values["beta"] == 60000.0  # not freed: the seed's value kept
    assert main(["ccor", "--ball", str(saved), "--divisions", "4", "--json",
                 "--runs-dir", str(tmp_path / "runs")]) == 0  # fmt: skip
    assert 0.0 < json.loads(capsys.readouterr().out)["ccor"] < 1.0


def test_prony3_model_starts_from_the_mat006_ball(tmp_path: Path, capsys) -> None:
    args = ["calibrate", "--ball", "type1", "--model", "prony3", "--free", "g1", "--fit-speeds",
            "95 mph", "--study", str(tmp_path / "s.db"), *TINY]  # fmt: skip
    assert main(args) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["model"] == "prony3"
    used = {r["target"]: r["used_in_fit"] for r in report["targets"]}
    assert used["ccor @ 95 mph"] and not used["ccor @ 110 mph"]  # 110 mph predicted


@pytest.mark.parametrize(
    ("extra", "field"),
    [
        (["--free", "gamma"], "free: 'gamma'"),
        (["--free", "g0", "--bound", "g0=1 psi:1e15 psi"], "bounds.g0"),
        (["--model", "mat006", "--ball", "nowhere.toml"], "ball"),
    ],
)
def test_bad_input_exits_2_naming_the_field(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], field: str
) -> None:
    assert main(["calibrate", *extra, "--study", str(tmp_path / "s.db"), *TINY]) == 2
    assert field in capsys.readouterr().err


def test_the_hourglass_form_is_calibrated_as_part_of_the_ball(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--hourglass-type 4 --hourglass-coefficient 0.01``: every run of the fit uses the
    stiffness form (its own run keys), the report names it, and the saved ball carries it, so a
    later test runs the model that was fitted."""
    import dataclasses

    from batball.calibrate.evaluate import RunRequest
    from batball.specs import BallHourglass

    saved = tmp_path / "fitted.toml"
    args = ["calibrate", "--ball", "type2", "--free", "g0", "--study", str(tmp_path / "s.db"),
            "--hourglass-type", "4", "--hourglass-coefficient", "0.01"]  # fmt: skip
    assert main([*args, *TINY, "--save", str(saved)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["hourglass"] == {"type": 4, "coefficient": 0.01}
    fitted = load_ball_spec(saved)
    assert fitted.hourglass == BallHourglass(4, 0.01)
    assert main(["ccor", "--ball", str(saved), "--divisions", "4", "--json",
                 "--runs-dir", str(tmp_path / "runs")]) == 0  # fmt: skip
    assert json.loads(capsys.readouterr().out)["hourglass_type"] == 4
    plain = load_ball_spec("type2")
    request = RunRequest(plain, "ccor", 42.5, 4)
    assert "hourglass" not in request.inputs()  # the stores of plain balls keep their keys
    stiff = RunRequest(
        dataclasses.replace(plain, hourglass=BallHourglass(4, 0.01)), "ccor", 42.5, 4
    )
    assert stiff.key != request.key


def test_one_hourglass_option_keeps_the_other_value_of_the_balls_own() -> None:
    """A ball whose model names IHQ 4, QM 0.01: ``--hourglass-coefficient 0.02`` alone keeps
    IHQ 4 (it does not fall back to the viscous default), ``--hourglass-type 5`` alone keeps
    QM 0.01; on a plain ball the value not given is the solver default (IHQ 1, 0.1)."""
    import argparse
    import dataclasses

    from batball.calibrate.command import with_hourglass_options
    from batball.specs import BallHourglass

    stiff = dataclasses.replace(load_ball_spec("type2"), hourglass=BallHourglass(4, 0.01))

    def given(kind: int | None, coefficient: float | None) -> argparse.Namespace:
        return argparse.Namespace(hourglass_type=kind, hourglass_coefficient=coefficient)

    assert with_hourglass_options(stiff, given(None, 0.02)).hourglass == BallHourglass(4, 0.02)
    assert with_hourglass_options(stiff, given(5, None)).hourglass == BallHourglass(5, 0.01)
    assert with_hourglass_options(stiff, given(None, None)) is stiff
    plain = load_ball_spec("type2")
    assert with_hourglass_options(plain, given(None, 0.05)).hourglass == BallHourglass(1, 0.05)
