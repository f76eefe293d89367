"""The bat commands as a user meets them: props JSON keys and run folder, fit-bat, errors."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import tomli_w

from batball.cli import main
from batball.specs import bat_spec_to_toml_dict, load_bat_spec

COARSE = ["--circumferential", "12", "--axial-size", "0.5 in"]
PROPS_KEYS = {"weight_oz", "balance_point_in", "moi_pivot_oz_in2", "moi_cm_oz_in2", "n_shells",
              "wall_seconds"}  # fmt: skip


def run_cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_props_json_has_the_keys_and_writes_the_run_folder(tmp_path: Path, capsys) -> None:
    args = ["props", "--bat", "default", "--json", "--runs-dir", str(tmp_path), *COARSE]
    code, out, _ = run_cli(args, capsys)
    assert code == 0
    summary = json.loads(out)
    assert summary.keys() >= PROPS_KEYS
    assert 21.5 < summary["weight_oz"] < 22.7  # coarse mesh, near Table 1's 22.1 oz
    folder = Path(summary["run_folder"])
    assert folder.name.startswith("props-")
    for name in ("summary.json", "bat.png", "bat.toml"):
        assert (folder / name).is_file(), name
    again = json.loads(run_cli(args, capsys)[1])  # same inputs: reused
    assert again["wall_seconds"] == summary["wall_seconds"]


def test_props_text_report_names_units(tmp_path: Path, capsys) -> None:
    code, out, _ = run_cli(["props", "--runs-dir", str(tmp_path), *COARSE], capsys)
    assert code == 0
    assert "oz*in^2" in out and "balance point" in out


def test_props_axial_size_without_unit_names_the_field(tmp_path: Path, capsys) -> None:
    code, _, err = run_cli(["props", "--axial-size", "0.1", "--runs-dir", str(tmp_path)], capsys)
    assert code == 2
    assert err.startswith("batball: error: axial-size:") and len(err.strip().splitlines()) == 1


def test_props_bad_bat_file_names_the_field(tmp_path: Path, capsys) -> None:
    document = bat_spec_to_toml_dict(load_bat_spec("default"))
    document["parts"][4]["layup"][2]["thickness"] = "-0.01 in"
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(document))
    code, _, err = run_cli(["props", "--bat", str(path), "--runs-dir", str(tmp_path)], capsys)
    assert code == 2
    assert "parts[4].layup[2].thickness" in err


def test_fit_bat_matches_the_targets_and_writes_a_bat(tmp_path: Path, capsys) -> None:
    output = tmp_path / "fitted.toml"
    args = ["fit-bat", "--weight", "22.5 oz", "--json", "--output", str(output), *COARSE]
    code, out, _ = run_cli(args, capsys)
    assert code == 0
    summary = json.loads(out)
    assert summary["matched"] is True
    assert summary["properties"]["weight_oz"] == pytest.approx(22.5, rel=1e-6)
    assert summary["properties"]["balance_point_in"] == pytest.approx(21.0, rel=1e-6)
    assert set(summary["parameters"]) == {
        "lumped_mass:endcap", "thickness:handle-glass", "thickness:barrel-carbon"
    }  # fmt: skip
    assert load_bat_spec(output).part("endcap").lumped_mass > 0.0


def test_fit_bat_unknown_parameter_names_the_field(capsys) -> None:
    code, _, err = run_cli(["fit-bat", "--free", "thickness:nothing", *COARSE], capsys)
    assert code == 2
    assert "free" in err


def test_fit_bat_out_of_reach_says_so_and_exits_1(capsys) -> None:
    # 23 oz at the same BP and MOI needs a negative end-cap mass
    code, out, _ = run_cli(["fit-bat", "--weight", "23 oz", *COARSE], capsys)
    assert code == 1
    assert "NOT met" in out and "lumped_mass:endcap" in out


def test_fit_bat_hoop_targets_must_be_positive_and_ascending(capsys) -> None:
    code, _, err = run_cli(["fit-bat", "--to", "hoop", "--hoop", "1950 Hz", "1450 Hz", *COARSE],
                           capsys)  # fmt: skip
    assert code == 2
    assert "hoop" in err and "lowest first" in err


def test_fit_bat_to_hoop_recovers_a_braid_and_stores_its_evaluations(tmp_path: Path,
                                                                     capsys) -> None:  # fmt: skip
    """`--to hoop` end to end on a coarse bat (16 x 0.5 in, ~30 s): given the hoop frequencies of
    a bat built with a 40-deg barrel braid, the default fit frees that braid, finds 40 deg (the
    fit stops at 0.003-deg steps, so 0.01 deg), writes it to the output bat and keeps one stored
    evaluation per modal analysis."""
    import math

    from batball.calibrate.bat_fit import (
        DEFAULT_HOOP_FREE,
        FreeParameter,
        MeshOptions,
        ModalTargets,
    )

    braid = FreeParameter.parse(DEFAULT_HOOP_FREE[0])
    truth = braid.apply(load_bat_spec("default"), math.radians(40.0))
    hoop = ModalTargets().achieved(truth, MeshOptions(16, 0.5 * 0.0254))
    output = tmp_path / "fitted.toml"
    args = ["fit-bat", "--to", "hoop", "--hoop", *(f"{f!r} Hz" for f in hoop), "--json",
            "--output", str(output), "--runs-dir", str(tmp_path / "runs"),
            "--circumferential", "16", "--axial-size", "0.5 in"]  # fmt: skip
    code, out, _ = run_cli(args, capsys)
    assert code == 0
    summary = json.loads(out)
    assert summary["matched"] is True and summary["least_squares"] is True
    fitted = summary["parameters"][DEFAULT_HOOP_FREE[0]]["fitted"]
    assert fitted.endswith(" deg") and float(fitted.split()[0]) == pytest.approx(40.0, abs=0.01)
    assert math.degrees(braid.value(load_bat_spec(output))) == pytest.approx(40.0, abs=0.01)
    stored = list((tmp_path / "runs").glob("fit-hoop-*/summary.json"))
    assert len(stored) == summary["n_evaluations"]


def test_fit_bat_sensitivity_reports_what_the_joint_targets_pin(tmp_path: Path, capsys) -> None:
    """`--to joint --sensitivity` on a coarse bat (three modal analyses, ~10 s): the weight's
    entry for the end cap is the closed form, the spread over the resolution (1 oz of spread
    against Table 1's 0.1-oz resolution: 10 resolutions per spread), a braid angle moves no
    mass, and the report names every combination and posterior ratio. Bad spreads exit 2."""
    base = ["fit-bat", "--to", "joint", "--sensitivity", "--free", "lumped_mass:endcap",
            "--free", "angle:barrel-carbon", "--circumferential", "16", "--axial-size", "0.5 in",
            "--runs-dir", str(tmp_path / "runs")]  # fmt: skip
    code, out, _ = run_cli([*base, "--spread", "lumped_mass:endcap=1 oz", "--json"], capsys)
    assert code == 0
    report = json.loads(out)
    weight = report["jacobian"]["weight_oz"]
    assert weight["lumped_mass:endcap"] == pytest.approx(10.0, rel=1e-3)
    assert weight["angle:barrel-carbon"] == 0.0
    assert report["spread"] == {"lumped_mass:endcap": "1 oz", "angle:barrel-carbon": "5 deg"}
    assert len(report["combinations"]) == 2
    assert all(0.0 < r < 1.0 for r in report["posterior_ratio"].values())
    assert run_cli([*base[:-2], "--runs-dir", str(tmp_path / "runs")], capsys)[0] == 0  # text
    for bad in ("lumped_mass:knob=1 oz", "lumped_mass:endcap=-1 oz", "angle:barrel-carbon=5"):
        code, _, err = run_cli([*base, "--spread", bad], capsys)
        assert code == 2 and "spread" in err
    code, _, err = run_cli(["fit-bat", "--to", "hoop", "--sensitivity"], capsys)
    assert code == 2 and "sensitivity" in err
    code, _, err = run_cli([*base, "--output", str(tmp_path / "bat.toml")], capsys)
    assert code == 2 and "output" in err and not (tmp_path / "bat.toml").exists()
    code, _, err = run_cli(["fit-bat", "--spread", "lumped_mass:endcap=1 oz"], capsys)
    assert code == 2 and "spread" in err and "--to joint" in err
    code, _, err = run_cli([*base, "--bending", "555 Hz", "146 Hz"], capsys)
    assert code == 2 and "bending" in err and "lowest first" in err


def test_fit_bat_joint_takes_any_number_of_measured_frequencies(tmp_path: Path, capsys) -> None:
    """A lab's own bat measured for one bending frequency: each frequency weighed at 1 % (the
    frequency resolution), so the report lists six targets with their resolutions."""
    code, out, _ = run_cli(["fit-bat", "--to", "joint", "--sensitivity", "--free",
                            "lumped_mass:endcap", "--bending", "150 Hz", "--hoop", "1400 Hz",
                            "1900 Hz", "--circumferential", "16", "--axial-size",
                            "0.5 in", "--runs-dir", str(tmp_path / "runs"), "--json"],
                           capsys)  # fmt: skip
    assert code == 0
    report = json.loads(out)
    assert report["resolution_percent"] == pytest.approx({
        "weight_oz": 100 * 0.1 / 22.1, "balance_point_in": 100 * 0.1 / 21.0,
        "moi_pivot_oz_in2": 1.0, "bending_1_hz": 1.0, "hoop_1_hz": 1.0, "hoop_2_hz": 1.0},
        rel=1e-9)  # fmt: skip
