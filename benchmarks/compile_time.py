"""Seconds to compile the kernels from an empty Numba cache, with batball's one-graph inlining
copy (``batball.numerics.share_inline_copies``) and with Numba's own
(``BATBALL_INLINE_COPY=numba``).

Each compile runs in a fresh interpreter with an empty cache folder and one Numba thread, the two
ways alternated (shared-host drift falls on both alike). The kernels: the hex element loop
(single precision, LS-DYNA IHQ 1: the loop every ball run compiles) and the MITC4 shell forces
on a coarse bat (the bat's kernel in the BBS test). Usage:

    python benchmarks/compile_time.py [--rounds 3]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

from yardstick import cpu_description

from batball.numerics import INLINE_COPY_VARIABLE

KERNELS = {
    "hex element loop (float32, IHQ 1)": """
import numpy as np
from batball.elements.hex8_block import BLOCK, N_ROWS, element_block_viscous, history_rows
w = np.ones(N_ROWS * BLOCK, dtype=np.float32)
history = np.ones(history_rows(1) * BLOCK, dtype=np.float32)
element_block_viscous(w, history, BLOCK, 1e-7, 1.5, 0.06, 0.1)
""",
    "MITC4 shell forces": """
import numpy as np
from batball.elements.shell_corotational import CorotationalShellForces
from batball.elements.shell_stiffness import shell_section
from batball.mesh.bat import make_bat_mesh
from batball.models.bat import bat_laminates
from batball.specs import load_bat_spec
spec = load_bat_spec("default")
mesh = make_bat_mesh(spec, circumferential=8, axial_size=0.0254)
shells = CorotationalShellForces(mesh.points, mesh.cells, shell_section(*bat_laminates(spec, mesh)))
shells(mesh.points, np.zeros((mesh.n_points, 6)), 1e-7, np.zeros((mesh.n_points, 6)))
""",
}

TIMED = """
import json, time
import batball.numerics
imported = time.perf_counter()
exec(compile({code!r}, "kernel", "exec"))
print(json.dumps({{"seconds": time.perf_counter() - imported,
                  "shared": batball.numerics.INLINE_COPIES_SHARED}}))
"""


def compile_seconds(code: str, numba_copy: bool) -> tuple[float, bool]:
    """(seconds, whether the one-graph copy was on) of one compile in a fresh interpreter."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "NUMBA_NUM_THREADS": "1"}
        env.pop(INLINE_COPY_VARIABLE, None)
        if numba_copy:
            env[INLINE_COPY_VARIABLE] = "numba"
        done = subprocess.run([sys.executable, "-c", TIMED.format(code=code)], env=env,
                              capture_output=True, text=True, check=True)  # fmt: skip
    out = json.loads(done.stdout.strip().splitlines()[-1])
    return out["seconds"], out["shared"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    if args.rounds < 1:
        parser.error(f"--rounds: {args.rounds} is not allowed; expected 1 or more")
    print(f"CPU: {cpu_description()}; one Numba thread; empty cache each compile")
    for name, code in KERNELS.items():
        shared, numba = [], []
        for _ in range(args.rounds):
            seconds, on = compile_seconds(code, numba_copy=False)
            if not on:
                raise SystemExit("the one-graph inlining copy was not applied on this Numba")
            shared.append(seconds)
            numba.append(compile_seconds(code, numba_copy=True)[0])
        ratio = statistics.median(s / n for s, n in zip(shared, numba, strict=True))
        print(f"{name}: one-graph copy {statistics.median(shared):.1f} s, Numba's own "
              f"{statistics.median(numba):.1f} s (medians of {args.rounds}); "
              f"median ratio {ratio:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
