"""docs/summary.md lists every key that each test's summary.json holds: each test is run on
its coarsest mesh and its keys are looked up in the page's table for that test and in the table
of keys every test shares."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

import batball

PAGE = Path(__file__).resolve().parents[2] / "docs" / "summary.md"

#: The page's section for each test, and the smallest run of it.
COARSE: dict[str, tuple[str, dict[str, Any]]] = {
    "ccor": ("Ball tests: ccor and cor", {"ball": "type1", "divisions": 2}),
    "cor": ("Ball tests: ccor and cor", {"ball": "type1", "divisions": 2}),
    "compression": ("compression", {"ball": "type1", "divisions": 2}),
    "props": ("props", {"bat": "default", "circumferential": 8, "axial_size": "1 in"}),
    "modal": ("modal", {"bat": "default", "circumferential": 16, "axial_size": "1 in"}),
    "barrel": ("barrel", {"bat": "default", "circumferential": 16, "axial_size": "1 in"}),
    "bbs": ("bbs", {"bat": "default", "ball": "type1", "divisions": 2, "circumferential": 8,
                    "axial_size": "1 in"}),
}


def documented(section: str) -> set[str]:
    """The `key` names in the first column of the page's table under ``## section``."""
    text = PAGE.read_text(encoding="utf-8")
    body = text.split(f"\n## {section}\n", 1)[1].split("\n## ", 1)[0]
    keys: set[str] = set()
    for line in body.splitlines():
        if line.startswith("| `"):
            keys.update(re.findall(r"`([a-z0-9_]+)`", line.split("|")[1]))
    return keys


@pytest.mark.parametrize("test", list(COARSE))
def test_every_summary_key_is_documented(test: str, tmp_path: Path) -> None:
    section, arguments = COARSE[test]
    result = batball.run_test(test, runs_dir=tmp_path, **arguments)
    keys = set(result.summary)
    missing = keys - documented(section) - documented("Every test") - {test}
    assert not missing, f"docs/summary.md does not list {sorted(missing)} of {test}"
