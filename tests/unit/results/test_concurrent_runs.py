"""Two ``batball ccor`` processes with the same inputs into one runs folder, started together:
one computes, the other waits on the run key's lock and reuses the stored run (so both print the
same summary, the computing run's wall time included)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path


def test_two_identical_processes_compute_once(tmp_path: Path) -> None:
    args = [sys.executable, "-m", "batball.cli", "ccor", "--ball", "type2", "--divisions", "8",
            "--speed", "95 mph", "--json", "--runs-dir", str(tmp_path / "runs")]  # fmt: skip
    processes = [subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                 for _ in range(2)]  # fmt: skip
    outputs = [p.communicate(timeout=300) for p in processes]
    assert all(p.returncode == 0 for p in processes), [err for _, err in outputs]
    first, second = (json.loads(out) for out, _ in outputs)
    assert first["wall_seconds"] == second["wall_seconds"]  # one run, computed once
    assert len(list((tmp_path / "runs").glob("ccor-*"))) == 1
