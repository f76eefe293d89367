"""Shared by the integration tests: headless Chromium, for the tests that open a page batball
wrote (Debian's ``chromium``; ``.ci/run`` installs it, and a test without it is skipped)."""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable

import pytest


@pytest.fixture
def run_chromium() -> Callable[..., str]:
    """A function running headless Chromium (no sandbox: CI runs as root) with the arguments
    given, returning its stdout; the test is skipped where no Chromium is installed."""
    found = next(filter(None, (shutil.which(n) for n in ("chromium", "chromium-browser"))), None)
    if found is None:
        pytest.skip("chromium is not installed (apt-get install -y chromium; .ci/run does it)")

    def run(*args: str) -> str:
        command = [found, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                   "--virtual-time-budget=10000", *args]  # fmt: skip
        done = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
        assert done.returncode == 0, done.stderr[-2000:]
        return done.stdout

    return run
