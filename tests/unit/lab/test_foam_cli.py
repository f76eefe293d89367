"""The ball-test commands with the example foam balls: compression (with --sfs) and CCOR write
their run folders, and the saved ball.toml reads back as the same foam."""

import json
from pathlib import Path

from batball.cli import main
from batball.specs import load_ball_spec


def test_foam_compression_and_ccor_from_the_cli(tmp_path: Path, capsys) -> None:
    args = ["compression", "--ball", "foam083", "--divisions", "3", "--rate", "10 in/s",
            "--quasi-static-ratio", "20", "--sfs", "5", "--json",
            "--runs-dir", str(tmp_path)]  # fmt: skip
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["compression_lbf"] > 0
    saved = load_ball_spec(Path(summary["run_folder"]) / "ball.toml")
    assert saved.material == load_ball_spec("foam083").material
    args = ["ccor", "--ball", "foam057", "--divisions", "3", "--json", "--runs-dir", str(tmp_path)]
    assert main(args) == 0
    assert 0.0 < json.loads(capsys.readouterr().out)["ccor"] < 1.0
