"""The study file: every finished evaluation in SQLite, keyed by the hash of its inputs.

Each outcome is written in its own transaction (SQLite's rollback journal makes it atomic), so a
study killed at any instant leaves a valid file holding every run that finished before the kill;
a restarted study reads them back instead of running them again. The ``computations`` table logs
each run actually computed, with the session that computed it, so tests can check that nothing
was computed twice.

Two processes on one study share the work: before computing a run a process claims its key (an
``flock`` on ``STUDY.locks/KEY.lock``, which the operating system releases if the process dies);
a key another process holds is waited for and then read back, or computed here if that process
died before storing it.
"""

from __future__ import annotations

import json
import os
import sqlite3
import time
import uuid
from pathlib import Path
from typing import IO, Any

_SCHEMA = """
CREATE TABLE IF NOT EXISTS runs (
    key TEXT PRIMARY KEY,
    inputs TEXT NOT NULL,
    outcome TEXT NOT NULL,
    created REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS computations (
    key TEXT NOT NULL,
    session TEXT NOT NULL,
    seconds REAL NOT NULL,
    created REAL NOT NULL
);
"""


class StudyStore:
    """An SQLite study file (``":memory:"`` for a throw-away study).

    Args:
        path: the file; created with its tables if missing.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = str(path)
        self.session = uuid.uuid4().hex
        self._connection = sqlite3.connect(self.path)
        with self._connection:
            self._connection.executescript(_SCHEMA)

    def get(self, key: str) -> dict[str, Any] | None:
        """The stored outcome of ``key``, or None."""
        row = self._connection.execute("SELECT outcome FROM runs WHERE key = ?", (key,)).fetchone()
        return None if row is None else json.loads(row[0])

    def put(self, key: str, inputs: dict[str, Any], outcome: dict[str, Any]) -> None:
        """Store one computed outcome and log the computation, in one transaction."""
        now = time.time()
        with self._connection:
            self._connection.execute(
                "INSERT OR IGNORE INTO runs VALUES (?, ?, ?, ?)",
                (key, json.dumps(inputs, sort_keys=True), json.dumps(outcome), now),
            )
            self._connection.execute(
                "INSERT INTO computations VALUES (?, ?, ?, ?)",
                (key, self.session, float(outcome.get("seconds", 0.0)), now),
            )

    def claim(self, key: str, *, wait: bool = False) -> IO[str] | None:
        """Claim ``key`` for this process: the open lock file (close it, after :meth:`put`, to
        release the claim), or None when another process holds it (``wait``: block until it is
        released, then claim it). A throw-away ``":memory:"`` study always succeeds."""
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX: no sharing between processes
            return open(os.devnull)  # noqa: SIM115
        if self.path == ":memory:":
            return open(os.devnull)  # noqa: SIM115
        folder = Path(f"{self.path}.locks")
        folder.mkdir(exist_ok=True)
        lock = open(folder / f"{key}.lock", "a")  # noqa: SIM115 - held until the caller closes it
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            lock.close()
            return None
        return lock

    def __len__(self) -> int:
        return int(self._connection.execute("SELECT COUNT(*) FROM runs").fetchone()[0])

    def computation_counts(self) -> dict[str, int]:
        """``{key: times computed}`` over every session that used this file."""
        rows = self._connection.execute("SELECT key, COUNT(*) FROM computations GROUP BY key")
        return {key: int(count) for key, count in rows}

    def computed_seconds(self) -> float:
        """Total wall time of the runs computed for this file, all sessions [s]."""
        row = self._connection.execute("SELECT COALESCE(SUM(seconds), 0) FROM computations")
        return float(row.fetchone()[0])

    def close(self) -> None:
        """Close the connection."""
        self._connection.close()
