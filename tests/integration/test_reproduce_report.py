"""``batball reproduce --quick`` end to end on the smallest meshes, opened in headless Chromium.

The real runners run (props, modal, the four CCOR cases); only the quick mesh sizes are shrunk so
the whole report takes seconds once Numba's cache is warm. The browser check needs Debian's
``chromium`` (``.ci/run`` installs it) and is skipped, saying so, without it.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

import batball.report.reproduce as reproduce_module
from batball.cli import main

TINY = reproduce_module.MeshSizes(ball_divisions=2, bat_circumferential=8, bat_axial_size=0.0254)
SEED_TABLE_IDS = [f"table{n}" for n in range(1, 10)] + ["compression"]


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A --quick report (tiny meshes), run twice: the second run reuses every stored run."""
    root = tmp_path_factory.mktemp("reproduce")
    args = ["reproduce", "--quick", "--out", str(root / "report"), "--runs-dir", str(root / "runs")]
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(reproduce_module, "QUICK_MESHES", TINY)
        assert main(args) == 0
        shutil.copyfile(root / "report" / "summary.json", root / "first_summary.json")
        assert main(args) == 0
    return root


def test_report_files_and_measured_values(report: Path) -> None:
    out = report / "report"
    for name in ("index.html", "summary.json", *(f"{t}.csv" for t in SEED_TABLE_IDS)):
        assert (out / name).is_file(), name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["meshes"]["ball_divisions"] == TINY.ball_divisions
    for name in ("props", "modal", "ccor"):
        assert summary["tests"][name]["available"], name
    assert len(summary["tests"]["ccor"]["runs"]) == 4
    rows = {r["key"]: r for t in summary["tables"].values() for r in t["rows"]}
    assert 0.0 < rows["ccor/type1/95mph"]["batball"] < 1.0
    assert 18.0 < rows["props/weight"]["batball"] < 26.0  # ounces, a coarse 22-oz bat
    assert rows["bbs/type1/95mph"]["batball"] is None  # no batted-ball-speed test yet
    first = json.loads((report / "first_summary.json").read_text())
    assert not any(r["reused"] for t in first["tests"].values() for r in t["runs"])
    assert all(r["reused"] for t in summary["tests"].values() for r in t["runs"])
    figures = sorted(p.name for p in (out / "figures").glob("*.png"))
    assert {"figure15_type1.png", "energies_ccor.png", "bat_modes.png"} <= set(figures)


def chromium() -> str:
    for name in ("chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    pytest.skip("chromium is not installed (apt-get install -y chromium; .ci/run does it)")


def run_chromium(*args: str) -> str:
    """Headless Chromium (no sandbox: CI runs as root); returns stdout."""
    command = [chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
               "--virtual-time-budget=10000", *args]  # fmt: skip
    done = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


def test_report_renders_in_headless_chromium(report: Path) -> None:
    page = (report / "report" / "index.html").resolve().as_uri()
    dom = run_chromium("--dump-dom", page)
    body = re.search(r"<body([^>]*)>", dom)
    assert body is not None
    n_figures = len(list((report / "report" / "figures").glob("*.png")))
    assert 'data-images-loaded="all"' in body.group(1), body.group(1)  # every <img> decoded
    assert f'data-image-count="{n_figures}"' in body.group(1)
    for table_id in SEED_TABLE_IDS:
        assert f'data-table="{table_id}"' in dom, table_id
    assert dom.count("<img") == n_figures
    screenshot = report / "report.png"
    run_chromium("--window-size=1280,6000", f"--screenshot={screenshot}", page)
    assert screenshot.stat().st_size > 50_000  # a page of tables and plots, not a blank one
