"""The user documentation builds with MkDocs in strict mode: a broken link, a missing page in the
navigation, an unknown API reference or a failing generated part fails the test."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_docs_build_strict(tmp_path: Path) -> None:
    site = tmp_path / "site"
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-4000:]
    start = (site / "index.html").read_text(encoding="utf-8")
    assert "batball ccor" in start
    # the generated parts were filled: the options tables and the command-line reference
    ccor = (site / "tests" / "ccor" / "index.html").read_text(encoding="utf-8")
    assert "--hourglass-type" in ccor and "{{" not in ccor
    cli = (site / "cli" / "index.html").read_text(encoding="utf-8")
    assert "batball bbs" in cli and "--penalty-scale" in cli
    api = (site / "api" / "index.html").read_text(encoding="utf-8")
    assert "run_test" in api
