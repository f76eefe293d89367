"""A SIGKILLed ``batball calibrate`` leaves no process behind: its pool workers notice that their
parent is gone (``executors.PARENT_CHECK_SECONDS``) and exit, and with them the last holders of
multiprocessing's resource-tracker pipe."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs /proc")


def children(pid: int) -> list[int]:
    """Processes whose parent is ``pid``."""
    found = []
    for status in Path("/proc").glob("[0-9]*/status"):
        try:
            fields = dict(line.split(":\t", 1) for line in status.read_text().splitlines()
                          if ":\t" in line)  # fmt: skip
        except OSError:
            continue
        if int(fields.get("PPid", "0").strip()) == pid:
            found.append(int(status.parent.name))
    return found


def running(pid: int) -> bool:
    """Alive and not a zombie (a container's init may never reap the dead)."""
    try:
        state = Path(f"/proc/{pid}/status").read_text().split("State:\t", 1)[1][0]
    except (OSError, IndexError):
        return False
    return state not in ("Z", "X")


def command_line(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return ""


def test_pool_workers_exit_when_calibrate_is_killed(tmp_path: Path) -> None:
    args = [sys.executable, "-m", "batball.cli", "calibrate", "--ball", "type1", "--quick",
            "--coarse-divisions", "4", "--global-points", "30", "--max-evaluations", "60",
            "--workers", "2", "--study", str(tmp_path / "study.db"), "--no-progress"]  # fmt: skip
    parent = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    workers: list[int] = []
    try:
        deadline = time.monotonic() + 180
        while time.monotonic() < deadline and parent.poll() is None:
            workers = [p for p in children(parent.pid) if "spawn_main" in command_line(p)]
            if len(workers) >= 2:
                break
            time.sleep(0.2)
        assert len(workers) >= 2, "the pool's workers never started"
        helpers = children(parent.pid)  # the workers and the resource tracker
        os.kill(parent.pid, signal.SIGKILL)
        parent.wait()
        deadline = time.monotonic() + 15
        while any(running(p) for p in helpers) and time.monotonic() < deadline:
            time.sleep(0.1)
        left = [command_line(p) for p in helpers if running(p)]
        assert not left, left
    finally:
        for pid in [*workers, parent.pid]:
            if running(pid):
                os.kill(pid, signal.SIGKILL)
