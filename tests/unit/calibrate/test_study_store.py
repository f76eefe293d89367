"""The SQLite study file: outcomes survive reopening; computations are logged per session."""

from __future__ import annotations

from pathlib import Path

from batball.calibrate import StudyStore


def test_outcomes_survive_reopening_and_computations_are_counted(tmp_path: Path) -> None:
    path = tmp_path / "study.db"
    first = StudyStore(path)
    first.put("k1", {"a": 1}, {"measures": {"restitution": 0.3}, "seconds": 2.0})
    first.close()
    second = StudyStore(path)
    assert second.get("k1") == {"measures": {"restitution": 0.3}, "seconds": 2.0}
    assert second.get("k2") is None
    second.put("k2", {"a": 2}, {"error": "no rebound", "seconds": 1.0})
    assert len(second) == 2
    assert second.computation_counts() == {"k1": 1, "k2": 1}
    assert second.computed_seconds() == 3.0
