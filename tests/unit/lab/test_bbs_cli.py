"""``batball bbs`` as a user meets it: JSON keys, the run folder, reuse, bad input."""

import json
from pathlib import Path

import pytest

from batball.cli import main
from batball.errors import SpecError
from batball.models.bbs import BbsSetup

COARSE = ["--ball-divisions", "4", "--circumferential", "8", "--axial-size", "1 in"]


def run_cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_bbs_json_has_the_keys_and_writes_the_run_folder(tmp_path: Path, capsys) -> None:
    # a coarse ball and bat: checks the plumbing and the definitions, not the seed's number
    args = ["bbs", "--ball", "type2", "--speed", "95 mph", *COARSE, "--json",
            "--runs-dir", str(tmp_path)]  # fmt: skip
    code, out, _ = run_cli(args, capsys)
    assert code == 0
    s = json.loads(out)
    assert s.keys() >= {"bbs_mph", "collision_efficiency", "bbcor", "rebound_mph",
                        "peak_force_lbf", "energy_balance_error", "wall_seconds"}  # fmt: skip
    assert s["inbound_mph"] == pytest.approx(95.0)
    e_a = s["collision_efficiency"]
    assert e_a == pytest.approx(s["rebound_mph"] / 95.0, rel=1e-9)
    assert s["bbs_mph"] == pytest.approx(85.0 + 110.0 * e_a, rel=1e-9)  # ASA: docs/physics.md 4.2
    assert s["bbcor"] == pytest.approx(e_a * (1 + s["k"]) + s["k"], rel=1e-9)
    assert s["energy_balance_error"] < 0.01
    folder = Path(s["run_folder"])
    for name in ("summary.json", "history.csv", "force_time.png", "barrel_deformation.png"):
        assert (folder / name).is_file(), name
    again = json.loads(run_cli(args, capsys)[1])
    assert again["wall_seconds"] == s["wall_seconds"]


@pytest.mark.parametrize(
    ("option", "value", "field"),
    [("--speed", "300 mph", "speed"), ("--pivot-band", "0 in", "pivot_band"),
     ("--speed", "95 lbf", "speed"), ("--insert-friction", "-0.2", "insert_friction"),
     ("--bat-damping", "1000 mph", "bat-damping"), ("--bat-damping", "-5 1/s", "bat_damping"),
     ("--hourglass-ratio", "0.5", "hourglass-ratio: 0.5 is not allowed; expected only with "
      "--shell bt")],
)  # fmt: skip
def test_bad_input_names_the_field(tmp_path: Path, capsys, option: str, value: str,
                                   field: str) -> None:  # fmt: skip
    code, _, err = run_cli(["bbs", option, value, *COARSE, "--runs-dir", str(tmp_path)], capsys)
    assert code == 2
    assert field in err


def test_setup_rejects_a_coarse_ball_mesh() -> None:
    with pytest.raises(SpecError, match="ball_divisions"):
        BbsSetup(ball_divisions=1)


def test_rigid_bat_summary_is_valid_json_without_a_prestress(tmp_path: Path, capsys) -> None:
    # a rigid bat has no insert contact, so no fit pressure: None in the JSON, not NaN
    args = ["bbs", "--rigid-bat", *COARSE, "--json", "--runs-dir", str(tmp_path)]
    code, out, _ = run_cli(args, capsys)
    assert code == 0
    s = json.loads(out)
    assert s["interference_pressure_psi"] is None
    assert s["added_mass_g"] == 0.0  # a rigid bat is not mass-scaled
    assert s["model_pivot_moi_oz_in2"] == pytest.approx(s["pivot_moi_oz_in2"], rel=1e-12)


@pytest.mark.parametrize("value", ["all", 0.0, 1.0])
def test_setup_rejects_a_bad_mass_scaling(value: object) -> None:
    with pytest.raises(SpecError, match="mass_scaling"):
        BbsSetup(mass_scaling=value)  # type: ignore[arg-type]


@pytest.mark.parametrize("ratio", [0.0, -0.01, 10.0, float("nan")])
def test_setup_rejects_a_bad_shell_hourglass_ratio(ratio: float) -> None:
    with pytest.raises(SpecError, match="shell_hourglass_ratio"):
        BbsSetup(shell_hourglass_ratio=ratio)


def test_a_second_speed_restores_the_stored_fit(tmp_path: Path, capsys) -> None:
    base = ["bbs", "--ball", "type2", *COARSE, "--runs-dir", str(tmp_path)]
    first = json.loads(run_cli([*base, "--speed", "95 mph", "--json"], capsys)[1])
    assert first["prestress_reused"] is False
    assert len(list(tmp_path.glob("fit-*"))) == 1
    code, out, _ = run_cli([*base, "--speed", "110 mph"], capsys)
    assert code == 0
    assert "restored from the store" in out
    # the one-point BT shells are another bat model: their own fit, relaxed anew
    code, out, _ = run_cli([*base, "--speed", "110 mph", "--shell", "bt"], capsys)
    assert code == 0
    assert "relaxed in this run" in out and "BT shells" in out
    assert len(list(tmp_path.glob("fit-*"))) == 2


def test_a_bad_hourglass_ratio_of_the_bt_shells_names_the_field(tmp_path: Path, capsys) -> None:
    args = ["bbs", "--shell", "bt", "--hourglass-ratio", "2", *COARSE, "--runs-dir", str(tmp_path)]
    code, _, err = run_cli(args, capsys)
    assert code == 2 and "shell_hourglass_ratio" in err


def test_setup_rejects_an_unknown_shell() -> None:
    with pytest.raises(SpecError, match="bat_shell"):
        BbsSetup(bat_shell="hughes-liu")
