"""Wall time of one batball command under two versions of the code, alternated in one run.

A shared host's speed drifts by a fifth within minutes, so a before/after comparison means
something only when the two codes run turn about, in the same run. This script checks the
``--before`` revision (and ``--after``, default the working tree) out into temporary git
worktrees, gives each code its own empty Numba cache (a cache filled by the other code, or by
another command first, can change a kernel's last bits: docs/notes/precision.md), runs the
command once under each to compile, then ``--rounds`` rounds of before and after, each run a new
process on ``--threads`` Numba threads with a new empty ``--runs-dir`` (so nothing is reused),
and prints the process wall seconds, the ratio before/after round by round and, with
``--field``, that field of each run's JSON output (the command must print JSON: pass
``--json``), so that the answers can be compared too. Usage:

    python benchmarks/ab_command.py --before 435064d --threads 1 --rounds 2 \\
        --field bbs_mph -- bbs --no-reuse --json

The command is what follows ``--``, without ``batball`` and without ``--runs-dir``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from yardstick import cpu_description

REPOSITORY = Path(__file__).resolve().parent.parent


def checkout(revision: str, folder: Path) -> Path:
    """A worktree of ``revision`` in ``folder``; its ``src``."""
    subprocess.run(["git", "-C", str(REPOSITORY), "worktree", "add", "--detach", "-f", "-q",
                    str(folder), revision], check=True)  # fmt: skip
    return folder / "src"


def run_once(source: Path, cache: Path, threads: int, command: list[str], field: str | None
             ) -> tuple[float, str]:  # fmt: skip
    """Process wall seconds of ``batball COMMAND --runs-dir NEW`` on the code in ``source``, and
    ``field`` of its JSON output ("" without one)."""
    environment = dict(os.environ, PYTHONPATH=str(source), NUMBA_CACHE_DIR=str(cache),
                       NUMBA_NUM_THREADS=str(threads))  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="ab-runs-") as runs:
        start = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-c", "from batball.cli import main; main()", *command,
             "--runs-dir", runs],
            env=environment, capture_output=True, text=True,
        )  # fmt: skip
        seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{source}: the command failed ({done.returncode}): {done.stderr[-2000:]}")
    if field is None:
        return seconds, ""
    try:
        return seconds, repr(json.loads(done.stdout)[field])
    except (json.JSONDecodeError, KeyError) as error:
        raise SystemExit(f"{source}: no JSON field {field!r} in the output ({error})") from error


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, help="git revision of the code before")
    parser.add_argument("--after", help="git revision of the code after (default: working tree)")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--threads", type=int, default=1, help="Numba threads of every run")
    parser.add_argument("--field", help="a field of the command's JSON output to print")
    parser.add_argument("command", nargs="+", help="the batball command, after --")
    args = parser.parse_args()
    if args.rounds < 1 or args.threads < 1:
        raise SystemExit(f"--rounds {args.rounds} and --threads {args.threads}: each at least 1")
    print(json.dumps(cpu_description()), f"threads {args.threads}", flush=True)
    with tempfile.TemporaryDirectory(prefix="ab-command-") as scratch:
        root = Path(scratch)
        trees: list[Path] = []
        try:
            sources = {"before": checkout(args.before, root / "before")}
            trees.append(root / "before")
            if args.after is None:
                sources["after"] = REPOSITORY / "src"
            else:
                sources["after"] = checkout(args.after, root / "after")
                trees.append(root / "after")
            caches = {code: root / f"cache-{code}" for code in sources}
            for code, source in sources.items():  # compile into each code's own cache
                seconds, value = run_once(source, caches[code], args.threads, args.command,
                                          args.field)  # fmt: skip
                print(f"warm-up {code}: {seconds:.1f} s {value}", flush=True)
            ratios = []
            for r in range(1, args.rounds + 1):
                times = {}
                for code, source in sources.items():
                    times[code], value = run_once(source, caches[code], args.threads,
                                                  args.command, args.field)  # fmt: skip
                    print(f"round {r} {code}: {times[code]:.1f} s {value}", flush=True)
                ratios.append(times["before"] / times["after"])
                print(f"round {r} before/after: {ratios[-1]:.2f}", flush=True)
            print(f"before/after: {', '.join(f'{x:.2f}' for x in ratios)} "
                  f"(median {statistics.median(ratios):.2f})")  # fmt: skip
        finally:
            for tree in trees:
                subprocess.run(["git", "-C", str(REPOSITORY), "worktree", "remove", "--force",
                                str(tree)], check=False)  # fmt: skip


if __name__ == "__main__":
    main()
