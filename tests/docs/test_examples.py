"""Every script in examples/ runs on coarse meshes (``BATBALL_EXAMPLE_TINY=1``), as a user would
run it from an empty folder, and writes what its docstring says it writes."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: Each example and the files it promises.
WRITES = {
    "ccor_and_plot.py": ["ccor_force_time.png"],
    "calibrate_from_measurements.py": ["my_ball.toml", "my_measurements.csv"],
    "bbs_custom_layup.py": ["stiff_barrel.toml"],
    "read_fields.py": ["ball_stress.png"],
    "design_study.py": ["designs/barrel-layup/designs.csv", "designs/barrel-layup/index.html"],
}


def test_every_example_is_listed() -> None:
    assert sorted(p.name for p in EXAMPLES.glob("*.py")) == sorted(WRITES)
    assert (EXAMPLES / "barrel_layup_study.toml").is_file()  # design_study.py's study


@pytest.mark.parametrize("name", sorted(WRITES))
def test_example_runs(name: str, tmp_path: Path) -> None:
    env = {**os.environ, "BATBALL_EXAMPLE_TINY": "1", "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, str(EXAMPLES / name)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=900)  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    for written in WRITES[name]:
        assert (tmp_path / written).is_file(), f"{name} did not write {written}"
