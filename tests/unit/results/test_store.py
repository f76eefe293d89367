"""The results store: stable input hashes, run folders, atomic writes that never leave debris."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest

from batball.results.store import (
    atomic_path,
    inputs_hash,
    load_cached_summary,
    run_folder,
    write_csv_atomic,
    write_json_atomic,
    write_summary,
    write_text_atomic,
)

INPUTS = {"ball": {"name": "type1", "mass": "6.93 oz"}, "speed": "95 mph", "mesh_size": 0.004}


def test_hash_is_stable_and_independent_of_key_order() -> None:
    reordered = {
        "speed": "95 mph",
        "mesh_size": 0.004,
        "ball": {"mass": "6.93 oz", "name": "type1"},
    }
    assert inputs_hash(INPUTS) == inputs_hash(reordered)
    assert len(inputs_hash(INPUTS)) == 12
    assert all(c in "0123456789abcdef" for c in inputs_hash(INPUTS))


def test_hash_is_the_sha256_of_canonical_json() -> None:
    # Independent expectation: sha256 of '{"a":1}' begins 015abd7f5cc5.
    assert inputs_hash({"a": 1}) == "015abd7f5cc5"


def test_hash_changes_with_any_input() -> None:
    changed = {**INPUTS, "speed": "110 mph"}
    nested = {**INPUTS, "ball": {"name": "type1", "mass": "6.94 oz"}}
    numeric = {**INPUTS, "mesh_size": 0.0040000001}
    hashes = {inputs_hash(d) for d in (INPUTS, changed, nested, numeric)}
    assert len(hashes) == 4


def test_hash_accepts_numpy_values() -> None:
    assert inputs_hash({"x": np.float64(0.5), "n": np.int64(3)}) == inputs_hash({"x": 0.5, "n": 3})


def test_run_folder_is_test_dash_hash(tmp_path: Path) -> None:
    folder = run_folder(tmp_path, "ccor", INPUTS)
    assert folder == tmp_path / f"ccor-{inputs_hash(INPUTS)}"
    assert not folder.exists()
    with pytest.raises(ValueError):
        run_folder(tmp_path, "../escape", INPUTS)


def test_json_and_text_writers_create_folders(tmp_path: Path) -> None:
    path = tmp_path / "run" / "summary.json"
    write_json_atomic(path, {"ccor": np.float64(0.38), "n": 2})
    assert json.loads(path.read_text()) == {"ccor": 0.38, "n": 2}
    write_text_atomic(tmp_path / "a" / "b.txt", "hello\n")
    assert (tmp_path / "a" / "b.txt").read_text() == "hello\n"


def test_csv_has_named_columns_and_values(tmp_path: Path) -> None:
    path = tmp_path / "history.csv"
    write_csv_atomic(path, {"time_ms": np.array([0.0, 0.5]), "force_lbf": np.array([1.0, 4390.0])})
    lines = path.read_text().splitlines()
    assert lines == ["time_ms,force_lbf", "0,1", "0.5,4390"]


def test_csv_refuses_unequal_columns(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="equal length"):
        write_csv_atomic(tmp_path / "h.csv", {"a": np.zeros(3), "b": np.zeros(2)})
    assert list(tmp_path.iterdir()) == []


def test_failed_write_leaves_target_unchanged_and_no_temp_file(tmp_path: Path) -> None:
    path = tmp_path / "summary.json"
    write_json_atomic(path, {"ccor": 0.38})
    with pytest.raises(ValueError):
        write_json_atomic(path, {"ccor": float("nan")})  # NaN is not JSON
    with pytest.raises(RuntimeError), atomic_path(path) as tmp:
        tmp.write_text('{"ccor": 0.')
        raise RuntimeError("solver died mid-write")
    assert json.loads(path.read_text()) == {"ccor": 0.38}
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]


def test_atomic_path_keeps_suffix_and_replaces_on_success(tmp_path: Path) -> None:
    path = tmp_path / "fields.vtu"
    with atomic_path(path) as tmp:
        assert tmp.parent == tmp_path and tmp.suffix == ".vtu" and tmp != path
        tmp.write_text("new")
    assert path.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["fields.vtu"]


def test_cached_summary_only_when_complete(tmp_path: Path) -> None:
    assert load_cached_summary(tmp_path) is None
    (tmp_path / "summary.json").write_text('{"ccor": 0.3')
    assert load_cached_summary(tmp_path) is None
    write_json_atomic(tmp_path / "summary.json", {"ccor": 0.38})
    assert load_cached_summary(tmp_path) is None
    write_summary(tmp_path, {"ccor": 0.38})
    assert load_cached_summary(tmp_path) == {"ccor": 0.38}  # the marker is the store's own


def test_a_reused_run_must_hold_its_keys_and_its_files(tmp_path: Path) -> None:
    """A summary that parses but lost a key, or a run whose file went missing or changed size,
    is not reused (the run is done again)."""
    write_text_atomic(tmp_path / "history.csv", "t,f\n0,1\n")
    write_summary(tmp_path, {"ccor": 0.38, "ds_lbf_per_in": 7100.0})
    assert load_cached_summary(tmp_path) == {"ccor": 0.38, "ds_lbf_per_in": 7100.0}
    stored = json.loads((tmp_path / "summary.json").read_text())
    assert stored["files"] == {"history.csv": len("t,f\n0,1\n")}
    damaged = {k: v for k, v in stored.items() if k != "ds_lbf_per_in"}
    write_json_atomic(tmp_path / "summary.json", damaged)
    assert load_cached_summary(tmp_path) is None  # a key gone
    write_json_atomic(tmp_path / "summary.json", stored)
    assert load_cached_summary(tmp_path) is not None
    (tmp_path / "history.csv").write_text("t,f\n")
    assert load_cached_summary(tmp_path) is None  # a file changed
    (tmp_path / "history.csv").unlink()
    assert load_cached_summary(tmp_path) is None  # a file gone


def test_two_identical_runs_at_once_compute_once(tmp_path: Path) -> None:
    """Two threads ask for the same run key together: the second waits on the key's lock and
    reuses what the first stored."""
    import threading

    from batball.results.store import run_or_reuse

    computed: list[int] = []

    def compute() -> int:
        computed.append(1)
        time.sleep(0.3)  # long enough for the other thread to arrive while this one computes
        return 42

    def write(result: int, summary: dict) -> None:
        write_summary(folder, summary)

    folder = tmp_path / "ccor-0123456789ab"
    results: list[dict] = []

    def run() -> None:
        summary, _ = run_or_reuse(folder, True, compute, lambda r, s: {"value": r}, write)
        results.append(summary)

    threads = [threading.Thread(target=run) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert computed == [1]
    assert [r["value"] for r in results] == [42, 42]
