"""The MITC4 shell force call of another revision against the working tree's, call by call.

On a noisy shared host, rounds of tens of calls per version gave medians 10 % apart for the same
code. This script loads ``elements/shell_corotational.py`` as it was at ``--before`` (a git
revision) beside the working tree's, builds both force objects on the full-size BBS bat (default
spec), checks that they give the same forces bit for bit after three calls, then alternates
single calls (old, new, new, old, ...) and prints the median of the per-pair time ratio with its
quartiles. Run it with an empty Numba cache and the threads wanted, e.g.:

    NUMBA_CACHE_DIR=$(mktemp -d) NUMBA_NUM_THREADS=1 python benchmarks/mitc4_call_ab.py \
        --before HEAD --pairs 500
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba as nb
import numpy as np

import batball.elements.shell_corotational as new
from batball.elements.shell_stiffness import shell_section
from batball.models.bat import bat_laminates
from batball.models.bbs import BbsSetup, bat_part
from batball.specs import load_bat_spec
from batball.units import IN

MODULE = "src/batball/elements/shell_corotational.py"


def module_at(revision: str, folder: str):  # noqa: ANN201
    """The MITC4 module as it was at ``revision``, imported under another name."""
    shown = subprocess.run(["git", "show", f"{revision}:{MODULE}"], capture_output=True,
                           text=True)  # fmt: skip
    if shown.returncode != 0:
        raise SystemExit(f"--before: {revision!r}: {shown.stderr.strip()}")
    path = Path(folder) / "shell_corotational_before.py"
    path.write_text(shown.stdout)
    spec = importlib.util.spec_from_file_location("batball.elements._mitc4_before", path)
    module = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
    sys.modules[spec.name] = module  # type: ignore[union-attr]
    spec.loader.exec_module(module)  # type: ignore[union-attr]
    return module


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, help="git revision of the code before")
    parser.add_argument("--pairs", type=int, default=500)
    args = parser.parse_args()
    if args.pairs < 1:
        parser.error(f"--pairs: {args.pairs} is not allowed; expected 1 or more")
    with tempfile.TemporaryDirectory() as folder:
        old = module_at(args.before, folder)
        spec = load_bat_spec("default")
        bat, mesh, _ = bat_part(spec, BbsSetup(circumferential=48, axial_size=0.1 * IN))
        section = shell_section(*bat_laminates(spec, mesh))
        rng = np.random.default_rng(7)
        velocity = np.hstack([1e-3 * rng.standard_normal((mesh.n_points, 3)),
                              1e-1 * rng.standard_normal((mesh.n_points, 3))])  # fmt: skip
        calls, outs = [], []
        for module in (old, new):
            forces, out = module.CorotationalShellForces(mesh.points, mesh.cells, section), \
                np.zeros((mesh.n_points, 6))
            for _ in range(3):
                forces(mesh.points, velocity, bat.stable_step, out)
            calls.append(lambda f=forces, o=out: f(mesh.points, velocity, bat.stable_step, o))
            outs.append(out)
        seconds = np.zeros((args.pairs, 2))
        for pair in range(args.pairs):
            for k in (0, 1) if pair % 2 == 0 else (1, 0):
                start = time.perf_counter()
                calls[k]()
                seconds[pair, k] = time.perf_counter() - start
    ratio = seconds[:, 1] / seconds[:, 0]
    q25, median, q75 = np.quantile(ratio, [0.25, 0.5, 0.75])
    print(f"{mesh.n_cells} shells, {nb.get_num_threads()} thread(s), {args.pairs} pairs; "
          f"forces the same bits: {np.array_equal(outs[0], outs[1])}")
    print(f"before {np.median(seconds[:, 0]) * 1e3:.3f} ms a call, after "
          f"{np.median(seconds[:, 1]) * 1e3:.3f} ms (medians); after over before, per pair: "
          f"median {median:.3f}, quartiles {q25:.3f}-{q75:.3f}")  # fmt: skip


if __name__ == "__main__":
    main()
