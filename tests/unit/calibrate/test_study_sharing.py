"""Two ``batball calibrate`` processes on one study file share the work: every evaluation is
computed once (the other process waits on its claim and reads it back), and both finish with
the same fit."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from batball.calibrate.store import StudyStore


def test_two_calibrations_on_one_study_compute_each_run_once(tmp_path: Path) -> None:
    study = tmp_path / "study.db"
    args = [sys.executable, "-m", "batball.cli", "calibrate", "--ball", "type1", "--quick",
            "--coarse-divisions", "3", "--global-points", "4", "--max-evaluations", "6",
            "--workers", "0", "--study", str(study), "--json", "--no-progress"]  # fmt: skip
    processes = [subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                 for _ in range(2)]  # fmt: skip
    outputs = [p.communicate(timeout=600) for p in processes]
    assert all(p.returncode == 0 for p in processes), [err[-2000:] for _, err in outputs]
    fits = [json.loads(out)["parameters_si"] for out, _ in outputs]
    assert fits[0] == fits[1]
    store = StudyStore(study)
    counts = store.computation_counts()
    store.close()
    assert counts and set(counts.values()) == {1}, counts
