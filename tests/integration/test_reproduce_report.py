"""``batball reproduce --quick`` end to end on the smallest meshes, opened in headless Chromium.

The real runners run (props, modal, barrel, compression, the CCOR and batted-ball-speed cases of
the model of record and of the solver check, the refit of both seed balls); only the quick mesh
sizes and the calibration's budget are shrunk so the whole report takes a minute or so once
Numba's cache is warm. The browser check needs Debian's
``chromium`` (``.ci/run`` installs it) and is skipped, saying so, without it.
"""

from __future__ import annotations

import json
import re
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

import batball.report.reproduce_runs as runs_module
import batball.report.reproduce_setup as repro_setup
from batball.calibrate import OptimiserOptions
from batball.cli import main

TINY = repro_setup.MeshSizes(ball_divisions=2, bat_circumferential=8, bat_axial_size=0.0254,
                               bbs=(3, 16, 0.0254))  # fmt: skip
#: The calibration's smallest budget: the start and 1 Latin-hypercube point, 2 least-squares steps.
TINY_CALIBRATION = OptimiserOptions(
    global_points=1, coarse_divisions=2, coarse_evaluations=2, fine_divisions=None
)
SEED_TABLE_IDS = [f"table{n}" for n in range(1, 10)] + ["compression"]
TABLE_IDS = [*SEED_TABLE_IDS, "check_impact", "check_table9", "calibrated_type1",
             "calibrated_type2"]  # fmt: skip


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A --quick --calibrate report (tiny meshes, tiny calibration budget), run twice: the second
    run reuses every stored run and every calibration evaluation."""
    root = tmp_path_factory.mktemp("reproduce")
    args = ["reproduce", "--quick", "--calibrate", "--out", str(root / "report"),
            "--runs-dir", str(root / "runs")]  # fmt: skip
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(repro_setup, "QUICK_MESHES", TINY)
        patch.setattr(runs_module, "calibration_options", lambda _: TINY_CALIBRATION)
        assert main(args) == 0
        shutil.copyfile(root / "report" / "summary.json", root / "first_summary.json")
        assert main(args) == 0
    return root


def test_report_files_and_measured_values(report: Path) -> None:
    out = report / "report"
    for name in ("index.html", "summary.json", *(f"{t}.csv" for t in TABLE_IDS)):
        assert (out / name).is_file(), name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["meshes"]["ball_divisions"] == TINY.ball_divisions
    for name in ("props", "modal", "ccor", "bbs", "ccor-check", "bbs-check", "calibrate"):
        assert summary["tests"][name]["available"], name
    for name in ("ccor", "bbs", "ccor-check", "bbs-check"):
        assert len(summary["tests"][name]["runs"]) == 4, name
    assert summary["model_of_record"] == {"balls": ["type1-fit", "type2-fit"], "bat": "fitted"}
    assert summary["meshes"]["converged"] is False
    assert summary["warnings"][0].startswith("coarse meshes (--quick)")  # indicative numbers
    rows = {r["key"]: r for t in summary["tables"].values() for r in t["rows"]}
    # every row has its role; nothing on these meshes is given a verdict
    assert {r["role"] for r in rows.values()} == {"fitted", "predicted", "check"}
    assert all(r["indicative"] and r["verdict"] is None for r in rows.values())
    assert {rows[f"bbs/{b}/{s}mph"]["role"] for b in ("type1", "type2") for s in (95, 110)} == {
        "predicted"
    }
    assert {r["role"] for r in summary["tables"]["table1"]["rows"]} == {"fitted"}
    for key in ("bbs/type1/95mph", "check/bbs/type2/110mph"):
        assert 40.0 < rows[key]["batball"] < 130.0, key  # mph, a batted ball off a coarse bat
    assert rows["check/material/type1/g_inf"]["batball"] == pytest.approx(750.0)  # as Table 4
    calibrations = {r["label"]: r for r in summary["tests"]["calibrate"]["runs"]}
    assert set(calibrations) == {"type1", "type2"}
    for ball, run in calibrations.items():
        assert Path(run["run_folder"]) == report / "runs" / f"calibrate-{ball}-mat006.db"
        fitted = run["summary"]["parameters_si"]
        assert rows[f"calibrated/material/{ball}/beta"]["batball"] == pytest.approx(
            fitted["beta"]
        )
        assert rows[f"calibrated/material/{ball}/g0"]["batball"] == pytest.approx(
            fitted["g0"] / 6894.757293168361
        )
        for target in run["summary"]["targets"]:  # the calibrate --json rows, one table cell each
            quantity = runs_module.CALIBRATION_QUANTITIES[target["quantity"]]
            row = rows[f"calibrated/{quantity}/{ball}/{round(target['speed_mph'])}mph"]
            assert row["batball"] == pytest.approx(target["fitted"])
            assert row["experiment"] == pytest.approx(target["measured"])
            assert row["seed_lsdyna"] == pytest.approx(target["seed_fe"])
            assert row["role"] == "fitted"
    assert 0.0 < rows["ccor/type1/95mph"]["batball"] < 1.0
    assert 18.0 < rows["props/weight"]["batball"] < 26.0  # ounces, a coarse 22-oz bat
    first = json.loads((report / "first_summary.json").read_text())
    assert not any(r["reused"] for t in first["tests"].values() for r in t["runs"])
    assert all(r["reused"] for t in summary["tests"].values() for r in t["runs"])
    figures = sorted(p.name for p in (out / "figures").glob("*.png"))
    assert {"figure15_type1.png", "energies_ccor.png", "bat_modes.png"} <= set(figures)


def test_report_renders_in_headless_chromium(
    report: Path, run_chromium: Callable[..., str]
) -> None:
    page = (report / "report" / "index.html").resolve().as_uri()
    dom = run_chromium("--dump-dom", page)
    body = re.search(r"<body([^>]*)>", dom)
    assert body is not None
    n_figures = len(list((report / "report" / "figures").glob("*.png")))
    assert 'data-images-loaded="all"' in body.group(1), body.group(1)  # every <img> decoded
    assert f'data-image-count="{n_figures}"' in body.group(1)
    for table_id in TABLE_IDS:
        assert f'data-table="{table_id}"' in dom, table_id
    table4 = dom[dom.index('data-table="table4"') :].split("</table>")[0]
    assert "not yet available" not in table4 and "skipped" not in table4
    assert dom.count("<img") == n_figures
    screenshot = report / "report.png"
    run_chromium("--window-size=1280,6000", f"--screenshot={screenshot}", page)
    assert screenshot.stat().st_size > 50_000  # a page of tables and plots, not a blank one


def test_report_shows_an_ensembles_table_9_intervals(
    report: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--ensemble DIR``: the report gains a "Table 9 with intervals" section whose cells are
    the ensemble's (its summary.json, to the page's two decimals) and links to its page; a
    folder without an ensemble's summary is refused by name before anything runs."""
    study = report / "ensemble.toml"
    study.write_text(
        'name = "tiny"\nspeeds = ["95 mph", "110 mph"]\nballs = ["type1", "type2"]\n'
        '[bat]\nspec = "default"\nsamples = 1\nfree = ["lumped_mass:endcap"]\n'
        '[bat.mesh]\ncircumferential = 8\naxial_size = "1 in"\n'
        '[mesh]\ndivisions = 3\ncircumferential = 8\naxial_size = "1 in"\n', encoding="utf-8")
    folder = report / "ensemble"
    assert main(["ensemble", str(study), "--out", str(folder), "--runs-dir",
                 str(report / "runs"), "--workers", "0", "--json"]) == 0  # fmt: skip
    cells = json.loads(capsys.readouterr().out)["cells"]
    args = ["reproduce", "--quick", "--out", str(report / "with-intervals"),
            "--runs-dir", str(report / "runs")]  # fmt: skip
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(repro_setup, "QUICK_MESHES", TINY)
        assert main([*args, "--ensemble", str(folder)]) == 0
        assert main([*args, "--ensemble", str(report / "runs")]) == 2
    assert "ensemble: " in capsys.readouterr().err  # the refusal names the field
    page = (report / "with-intervals" / "index.html").read_text(encoding="utf-8")
    assert "id='intervals'" in page and "../ensemble/index.html" in page
    for cell in cells:
        st = cell["stats"]
        assert f"{st['low']:.2f} to {st['high']:.2f}" in page
