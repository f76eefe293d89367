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


def checked_revision(option: str, revision: str) -> str:
    """``revision`` as a commit id, or a one-line error naming the option."""
    found = subprocess.run(["git", "-C", str(REPOSITORY), "rev-parse", "--verify", "-q",
                            f"{revision}^{{commit}}"], capture_output=True, text=True)  # fmt: skip
    if found.returncode != 0:
        raise SystemExit(f"{option} {revision!r}: not a commit of {REPOSITORY}")
    return found.stdout.strip()


def checkout(revision: str, folder: Path) -> Path:
    """A worktree of ``revision`` in ``folder``; its ``src``."""
    subprocess.run(["git", "-C", str(REPOSITORY), "worktree", "add", "--detach", "-f", "-q",
                    str(folder), revision], check=True)  # fmt: skip
    return folder / "src"


def environment(source: Path, cache: Path, threads: int) -> dict[str, str]:
    """The environment of a run of the code in ``source``, checked to import it from there (an
    installed batball must not take its place)."""
    variables = dict(os.environ, PYTHONPATH=str(source), NUMBA_CACHE_DIR=str(cache),
                     NUMBA_NUM_THREADS=str(threads))  # fmt: skip
    where = subprocess.run([sys.executable, "-c", "import batball; print(batball.__file__)"],
                           env=variables, capture_output=True, text=True)  # fmt: skip
    if not where.stdout.strip().startswith(str(source)):
        raise SystemExit(f"batball imports from {where.stdout.strip() or where.stderr[-500:]}, "
                         f"not from {source}")  # fmt: skip
    return variables


def run_once(variables: dict[str, str], command: list[str], field: str | None
             ) -> tuple[float, str]:  # fmt: skip
    """Process wall seconds of ``batball COMMAND --runs-dir NEW`` in the environment
    ``variables`` (:func:`environment`), and ``field=value`` of its JSON output ("" without
    ``field``)."""
    source = variables["PYTHONPATH"]
    with tempfile.TemporaryDirectory(prefix="ab-runs-") as runs:
        start = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-c", "from batball.cli import main; main()", *command,
             "--runs-dir", runs],
            env=variables, capture_output=True, text=True,
        )  # fmt: skip
        seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{source}: the command failed ({done.returncode}): {done.stderr[-2000:]}")
    if field is None:
        return seconds, ""
    try:
        return seconds, f"{field}={json.loads(done.stdout)[field]!r}"
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
    if any(word.startswith("--runs-dir") for word in args.command):
        raise SystemExit("the command's --runs-dir: leave it out (each run gets a new empty one)")
    revisions = {"before": checked_revision("--before", args.before)}
    if args.after is not None:
        revisions["after"] = checked_revision("--after", args.after)
    print(json.dumps(cpu_description()), f"threads {args.threads}", flush=True)
    with tempfile.TemporaryDirectory(prefix="ab-command-") as scratch:
        root = Path(scratch)
        trees: list[Path] = []
        try:
            sources = {"after": REPOSITORY / "src"}
            for code, revision in revisions.items():
                trees.append(root / code)
                sources[code] = checkout(revision, root / code)
            runs = {code: environment(sources[code], root / f"cache-{code}", args.threads)
                    for code in ("before", "after")}  # fmt: skip
            for code, variables in runs.items():  # compile into each code's own cache
                seconds, value = run_once(variables, args.command, args.field)
                print(f"warm-up {code}: {seconds:.1f} s {value}", flush=True)
            ratios = []
            for r in range(1, args.rounds + 1):
                times = {}
                for code, variables in runs.items():
                    times[code], value = run_once(variables, args.command, args.field)
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
