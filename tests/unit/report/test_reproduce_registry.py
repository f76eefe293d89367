"""The reproduction registry: every table has its test, and a missing test never shows a number."""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

import pytest

from batball.report.reproduce import REPRODUCTION_TESTS, reproduce
from batball.report.reproduce_runs import calibration_options, calibration_values, run_compression
from batball.report.reproduce_setup import FULL_MESHES, QUICK_MESHES, MeshSizes, ReproduceOptions
from batball.report.seed_comparison import comparison_tables
from batball.specs import load_ball_spec, load_seed_tables

TINY = MeshSizes(ball_divisions=2, bat_circumferential=8, bat_axial_size=0.0254)


def test_every_table_is_filled_by_a_registered_test_and_back() -> None:
    tables = {t.id: t.test for t in comparison_tables(load_seed_tables(), refit=True)}
    for table_id, test in tables.items():
        assert table_id in REPRODUCTION_TESTS[test].tables
    for name, test in REPRODUCTION_TESTS.items():
        assert test.name == name
        assert all(tables[t] == name for t in test.tables)


def test_the_model_of_record_and_the_solver_check_are_the_defaults() -> None:
    options = ReproduceOptions(out_dir=Path("report"), runs_dir=Path("runs"))
    assert options.balls == ("type1-fit", "type2-fit") and options.bat == "fitted"
    assert options.check_balls == ("type1", "type2") and options.check_bat == "default"
    assert not options.calibrate  # the fitted balls are embedded: no calibration by default
    for name in options.balls:  # each fitted ball names the seed ball it models
        assert load_ball_spec(name).name == name.removesuffix("-fit")
        assert load_ball_spec(name).material.law == "mat057"
    assert FULL_MESHES.converged and not QUICK_MESHES.converged and not TINY.converged
    assert FULL_MESHES.bbs[0] == 12  # the balls were fitted on the 12,096-hex ball


def quiet_options(tmp_path: Path) -> ReproduceOptions:
    return ReproduceOptions(out_dir=tmp_path / "report", runs_dir=tmp_path / "runs", meshes=TINY,
                            log=lambda _: None)  # fmt: skip


def test_missing_tests_show_not_yet_available_and_no_numbers(tmp_path: Path) -> None:
    # every test is built now: a registry entry without its runner stands in for a missing one
    missing = {name: dataclasses.replace(REPRODUCTION_TESTS[name], run=None, missing="not built")
               for name in ("bbs", "barrel", "ccor")}  # fmt: skip
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
    assert csv_lines[0].startswith("key,quantity,unit,role,indicative,experiment,seed_lsdyna,"
                                   "batball,")  # fmt: skip
    assert all(line.split(",")[7] == "" for line in csv_lines[1:])  # batball column empty
    assert all(line.split(",")[3] == "predicted" for line in csv_lines[1:])


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


def test_calibration_without_the_option_is_skipped_saying_how_to_add_it(tmp_path: Path) -> None:
    options = dataclasses.replace(quiet_options(tmp_path), calibrate=False)
    result = reproduce(options, tests={"calibrate": REPRODUCTION_TESTS["calibrate"]})
    (outcome,) = result.outcomes
    assert outcome.skipped and not outcome.available and not outcome.runs
    assert "--calibrate" in outcome.missing
    assert not any(key.startswith("calibrated/") for key in result.values)
    page = (tmp_path / "report" / "index.html").read_text()
    assert "data-table='calibrated_type1'" not in page and "id='refit'" not in page  # no refit
    summary = json.loads((tmp_path / "report" / "summary.json").read_text())
    assert summary["tests"]["calibrate"]["skipped"] is True
    assert "calibrated_type1" not in summary["tables"]


def test_calibration_values_fill_the_refitted_ball_rows() -> None:
    ball = load_ball_spec("type2")
    rows = [{"quantity": q, "speed_mph": mph, "fitted": 1.5}
            for q in ("ccor", "dynamic_stiffness", "peak_force", "contact_time")
            for mph in (95.0, 110.0)]  # fmt: skip
    rows.append({"quantity": "cor", "speed_mph": 60.0, "fitted": 0.5})  # no table row: left out
    values = calibration_values(ball, {"targets": rows})
    table_keys = {r.key for t in comparison_tables(load_seed_tables(), refit=True) for r in t.rows}
    assert set(values) <= table_keys
    assert values["calibrated/material/type2/beta"] == ball.material.values["beta"]
    assert values["calibrated/material/type2/g0"] == (
        ball.material.values["g0"] / 6894.757293168361
    )
    assert len([k for k in values if k.startswith("calibrated/")]) == 8 + 4
    assert values["calibrated/ds/type2/110mph"] == 1.5


def test_quick_calibration_is_the_calibrate_quick_budget_on_the_quick_mesh() -> None:
    quick = calibration_options(TINY)
    assert (quick.coarse_divisions, quick.fine_divisions, quick.global_points) == (2, None, 6)
    assert calibration_options(MeshSizes(12, 48, 0.00254)).fine_divisions == 12


def test_reproduce_refuses_a_folder_that_is_not_a_finished_ensemble(tmp_path: Path) -> None:
    """``--ensemble``: a folder without summary.json, with one that is not JSON, or with one
    that lacks the cells is refused by its field before anything runs."""
    from batball.errors import SpecError
    from batball.report.reproduce_setup import check_ensemble_folder

    with pytest.raises(SpecError, match="^ensemble: .*summary.json"):
        check_ensemble_folder(tmp_path)
    (tmp_path / "summary.json").write_text("{not json", encoding="utf-8")
    with pytest.raises(SpecError, match="^ensemble: "):
        check_ensemble_folder(tmp_path)
    (tmp_path / "summary.json").write_text('{"study": "x", "trends": []}', encoding="utf-8")
    with pytest.raises(SpecError, match="lacks cells, bats, balls, members"):
        check_ensemble_folder(tmp_path)
