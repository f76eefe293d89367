"""``batball compression`` as a user meets it: JSON keys, the run folder, reuse, bad input."""

import json
from pathlib import Path

import pytest

from batball.cli import main
from batball.errors import SpecError
from batball.models.compression import CompressionSetup


def run_cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_compression_json_has_the_keys_and_writes_the_run_folder(tmp_path: Path, capsys) -> None:
    # 3 divisions (189 hexes) and a fast plate: checks the plumbing, not the number
    args = ["compression", "--ball", "type2", "--divisions", "3", "--rate", "10 in/s",
            "--quasi-static-ratio", "20", "--json", "--runs-dir", str(tmp_path)]  # fmt: skip
    code, out, _ = run_cli(args, capsys)
    assert code == 0
    summary = json.loads(out)
    assert summary.keys() >= {"compression_lbf", "displacement_in", "wall_seconds"}
    assert summary["displacement_in"] == pytest.approx(0.25)
    assert summary["compression_lbf"] > 0
    folder = Path(summary["run_folder"])
    for name in ("summary.json", "curve.csv", "history.csv", "force_displacement.png",
                 "fields.pvd", "ball.toml"):  # fmt: skip
        assert (folder / name).is_file(), name
    header = (folder / "curve.csv").read_text().splitlines()[0]
    assert header == "displacement_in,force_lbf,top_minus_bottom_force_lbf"
    again = json.loads(run_cli(args, capsys)[1])
    assert again["wall_seconds"] == summary["wall_seconds"]


@pytest.mark.parametrize(
    ("option", "value", "field"),
    [("--rate", "1 psi", "rate"), ("--displacement", "-0.1 in", "displacement")],
)
def test_bad_compression_input_is_one_line_naming_the_field(
    option: str, value: str, field: str, tmp_path: Path, capsys
) -> None:
    code, _, err = run_cli(["compression", option, value, "--runs-dir", str(tmp_path)], capsys)
    assert code == 2
    assert field in err and len(err.strip().splitlines()) == 1


def test_setup_refuses_a_solver_rate_outside_its_range() -> None:
    with pytest.raises(SpecError, match="quasi_static_ratio"):
        CompressionSetup(quasi_static_ratio=1.0)
