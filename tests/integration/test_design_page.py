"""A design study's page end to end: a tiny study run, its page written, opened in headless
Chromium.

The study is real (props and batted-ball-speed runs on an 8 x 1 in bat and a 2-division ball, five
designs over the end cap's mass and the barrel carbon's angle, the ASA 2004 rule, two
objectives); it takes about half a minute once Numba's cache is warm. The browser check needs
Debian's ``chromium`` (``.ci/run`` installs it) and is skipped, saying so, without it.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from batball.design import design_study_from_dict, run_design_study
from batball.report.design_page import write_design_page

STUDY = {
    "name": "page-test",
    "bat": "default",
    "mesh": {"circumferential": 8, "axial_size": "1 in", "ball_divisions": 2},
    "sampling": {"designs": 5, "seed": 3},
    "parameter": [
        {"name": "endcap", "set": "lumped_mass:endcap", "range": ["0.5 oz", "2.5 oz"]},
        {"name": "carbon_angle", "set": "angle:barrel-carbon", "range": ["15 deg", "45 deg"]},
    ],
    "ball": [{"name": "type1", "speeds": ["110 mph"]}],
    "constraint": [{"rule": "asa-2004-bbs"}],
    "objective": [{"maximize": "bbs_type1_110mph"}, {"minimize": "moi_pivot_oz_in2"}],
}
FIGURES = ("scatter_matrix.png", "pareto.png", "influence.png")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The tiny study run and its page written."""
    root = tmp_path_factory.mktemp("design")
    study = design_study_from_dict(STUDY)
    run_design_study(study, out_dir=root / "out", runs_dir=root / "runs", workers=0)
    assert write_design_page(root / "out") == root / "out" / "index.html"
    return root / "out"


def summary(study_dir: Path) -> dict[str, Any]:
    return json.loads((study_dir / "summary.json").read_text())


def test_page_and_figures_are_written(study_dir: Path) -> None:
    for name in FIGURES:
        png = (study_dir / "figures" / name).read_bytes()
        assert png.startswith(PNG_SIGNATURE), name
        assert len(png) > 10_000, name  # axes, markers and labels, not an empty canvas
    assert not list(study_dir.glob("**/.*.tmp*"))  # every file moved into place
    page = (study_dir / "index.html").read_text()
    assert page.count("<img ") == len(FIGURES)
    for name in FIGURES:
        assert f"src='figures/{name}'" in page
    assert "href='designs.csv'" in page


def test_page_shows_the_study_as_given(study_dir: Path) -> None:
    page = (study_dir / "index.html").read_text()
    # the ranges, speed and limit as the study and the rule state them
    for text in ("0.50 oz", "2.50 oz", "15.0 deg", "45.0 deg", "110 mph", "98.00 mph"):
        assert text in page, text
    assert "ASTM F2219" in page  # the rule's source
    assert "lumped_mass:endcap" in page and "angle:barrel-carbon" in page
    assert "maximise" in page and "minimise" in page
    assert "8 x 1 in shells, 2-division ball" in page


def best_table(page: str) -> str:
    start = page.index("data-table='best'")
    return page[start : page.index("</table>", start)]


def test_best_table_holds_each_best_design_and_its_margin(study_dir: Path) -> None:
    best = summary(study_dir)["best"]
    assert best, "the tiny bat meets the ASA limit (its BBS is far under 98 mph)"
    table = best_table((study_dir / "index.html").read_text())
    for rank, design in enumerate(best, start=1):
        assert f"#{rank} {design['design']}" in table
        bbs = design["responses"]["bbs_type1_110mph"]
        assert f"<td>{bbs:,.2f}</td>" in table
        assert f"<td>{98.0 - bbs:,.2f}</td>" in table  # the margin: the ASA limit minus BBS
    for row in ("endcap", "carbon_angle", "weight", "MOI about the 6-in pivot", "feasible"):
        assert f"<td class='label'>{row}</td>" in table, row
    assert "oz·in²" in table and "mph" in table


def test_page_renders_in_headless_chromium(
    study_dir: Path, run_chromium: Callable[..., str]
) -> None:
    page = (study_dir / "index.html").resolve().as_uri()
    dom = run_chromium("--dump-dom", page)
    body = re.search(r"<body([^>]*)>", dom)
    assert body is not None
    assert 'data-images-loaded="all"' in body.group(1), body.group(1)  # every <img> decoded
    assert f'data-image-count="{len(FIGURES)}"' in body.group(1)
    assert 'data-table="best"' in dom
    screenshot = study_dir.parent / "page.png"
    run_chromium("--window-size=1280,3600", f"--screenshot={screenshot}", page)
    assert screenshot.read_bytes().startswith(PNG_SIGNATURE)
    assert screenshot.stat().st_size > 50_000  # tables and plots, not a blank page
