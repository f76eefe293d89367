"""The reproduction registry: every table has its test, and a missing test never shows a number."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from batball.report.reproduce import (
    REPRODUCTION_TESTS,
    MeshSizes,
    ReproduceOptions,
    reproduce,
    run_compression,
)
from batball.report.seed_comparison import comparison_tables
from batball.specs import load_seed_tables

TINY = MeshSizes(ball_divisions=2, bat_circumferential=8, bat_axial_size=0.0254)


def test_every_table_is_filled_by_a_registered_test_and_back() -> None:
    tables = {t.id: t.test for t in comparison_tables(load_seed_tables())}
    for table_id, test in tables.items():
        assert table_id in REPRODUCTION_TESTS[test].tables
    for name, test in REPRODUCTION_TESTS.items():
        assert test.name == name
        assert all(tables[t] == name for t in test.tables)


def test_tests_not_built_yet_have_a_reason() -> None:
    for name in ("barrel", "calibrate", "bbs"):
        assert REPRODUCTION_TESTS[name].run is None
        assert REPRODUCTION_TESTS[name].missing


def quiet_options(tmp_path: Path) -> ReproduceOptions:
    return ReproduceOptions(out_dir=tmp_path / "report", runs_dir=tmp_path / "runs", meshes=TINY,
                            log=lambda _: None)  # fmt: skip


def test_missing_tests_show_not_yet_available_and_no_numbers(tmp_path: Path) -> None:
    missing = {k: v for k, v in REPRODUCTION_TESTS.items() if v.run is None}
    reproduce(quiet_options(tmp_path), tests=missing)
    summary = json.loads((tmp_path / "report" / "summary.json").read_text())
    for name in missing:
        assert summary["tests"][name]["available"] is False
        assert summary["tests"][name]["runs"] == []
    for table in summary["tables"].values():
        assert all(row["batball"] is None for row in table["rows"])
    page = (tmp_path / "report" / "index.html").read_text()
    assert page.count("not yet available") >= 2 + 4 + 16  # Table 2, Table 9, Tables 5-8 cells
    csv_lines = (tmp_path / "report" / "table9.csv").read_text().splitlines()
    assert csv_lines[0].startswith("key,quantity,unit,experiment,seed_lsdyna,batball,")
    assert all(line.split(",")[5] == "" for line in csv_lines[1:])  # batball column empty


def test_compression_without_its_module_is_not_yet_available(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "batball.lab.compression_run", None)  # import fails
    tests = {"compression": REPRODUCTION_TESTS["compression"]}
    result = reproduce(quiet_options(tmp_path), tests=tests)
    (outcome,) = result.outcomes
    assert not outcome.available
    assert "compression" in outcome.missing
    assert run_compression is REPRODUCTION_TESTS["compression"].run
