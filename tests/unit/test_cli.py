"""The command line as a user meets it: JSON keys, run folders, reuse and one-line errors."""

import json
from pathlib import Path

import pytest

from batball.cli import main

REQUIRED_KEYS = {
    "ccor",
    "ds_lbf_per_in",
    "peak_force_lbf",
    "contact_time_ms",
    "inbound_mph",
    "rebound_mph",
    "energy_balance_error",
    "n_cells",
    "n_steps",
    "wall_seconds",
}


def run_cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_ccor_json_has_the_keys_and_writes_the_run_folder(tmp_path: Path, capsys) -> None:
    args = [
        "ccor",
        "--ball",
        "type2",
        "--speed",
        "95 mph",
        "--divisions",
        "3",
        "--json",
        "--runs-dir",
        str(tmp_path),
    ]
    code, out, _ = run_cli(args, capsys)
    assert code == 0
    summary = json.loads(out)
    assert summary.keys() >= REQUIRED_KEYS
    assert summary["inbound_mph"] == pytest.approx(95.0)
    assert summary["n_cells"] == 7 * 27
    folder = Path(summary["run_folder"])
    for name in ("summary.json", "history.csv", "force_time.png", "fields.pvd", "ball.toml"):
        assert (folder / name).is_file(), name
    header = (folder / "history.csv").read_text().splitlines()[0]
    assert "time_ms" in header and "contact_force_lbf" in header and "kinetic_energy_j" in header
    again = json.loads(run_cli(args, capsys)[1])  # same inputs: reused, not rerun
    assert again["wall_seconds"] == summary["wall_seconds"]


def test_cor_accepts_a_ball_file_with_units(tmp_path: Path, capsys) -> None:
    ball = tmp_path / "soft.toml"
    ball.write_text(
        'name = "soft"\ncircumference = "12 in"\nmass = "6.5 oz"\n[material]\n'
        'law = "mat006"\nbulk_modulus = "100000 psi"\ng0 = "11000 psi"\n'
        'g_inf = "640 psi"\nbeta = "60000 1/s"\n'
    )
    code, out, _ = run_cli(
        [
            "cor",
            "--ball",
            str(ball),
            "--speed",
            "60 mph",
            "--divisions",
            "3",
            "--json",
            "--runs-dir",
            str(tmp_path),
        ],
        capsys,
    )
    assert code == 0
    summary = json.loads(out)
    assert 0.0 < summary["cor"] < 1.0
    assert summary["ball_mass_oz"] == pytest.approx(6.5)


@pytest.mark.parametrize(
    ("speed", "field"),
    [("95 psi", "speed"), ("0 mph", "speed"), ("-10 mph", "speed"), ("95", "speed")],
)
def test_bad_speed_is_a_one_line_error_naming_the_field(speed, field, tmp_path, capsys) -> None:
    code, _, err = run_cli(["ccor", "--speed", speed, "--runs-dir", str(tmp_path)], capsys)
    assert code == 2
    assert err.startswith(f"batball: error: {field}:")
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("material_lines", "field"),
    [
        (
            'bulk_modulus = "-5 psi"\ng0 = "11000 psi"\ng_inf = "640 psi"\nbeta = "6e4 1/s"',
            "material.bulk_modulus",
        ),
        (
            'bulk_modulus = "1e5 psi"\ng0 = "1000 psi"\ng_inf = "2000 psi"\nbeta = "6e4 1/s"',
            "material.g_inf",
        ),
        ('bulk_modulus = "1e5 psi"\ng0 = "11000 psi"\nbeta = "6e4 1/s"', "material.g_inf"),
    ],
)
def test_bad_ball_file_names_the_field(material_lines, field, tmp_path, capsys) -> None:
    ball = tmp_path / "bad.toml"
    ball.write_text(
        'name = "bad"\ncircumference = "12 in"\nmass = "6.5 oz"\n[material]\n'
        f'law = "mat006"\n{material_lines}\n'
    )
    code, _, err = run_cli(["ccor", "--ball", str(ball), "--runs-dir", str(tmp_path)], capsys)
    assert code == 2
    assert err.startswith(f"batball: error: {field}:")
    assert len(err.strip().splitlines()) == 1


def test_building_the_parser_leaves_the_optimiser_unimported() -> None:
    """Every command builds the whole parser; the calibration's options must not import its
    optimiser (SciPy's least squares, about 0.4 s of every command's start). In a fresh
    interpreter, as a user's command starts."""
    import subprocess
    import sys

    script = (
        "import sys\n"
        "from batball.cli import build_parser\n"
        "build_parser()\n"
        "print(sorted(m for m in ('scipy.optimize', 'batball.calibrate.optimise') "
        "if m in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          check=False)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"
