"""The hex element loop's machine code as LLVM compiles it for a named CPU, read on any host.

LLVM compiles for the CPU that Numba names to it (``NUMBA_CPU_NAME``, ``NUMBA_CPU_FEATURES``),
whatever machine runs the compiler. So the loop an AVX2 EPYC runs (Zen 3: sixteen 256-bit
registers) can be read on an AVX-512 host, and the loop an AVX-512 host runs (thirty-two 512-bit
registers) on an AVX2 one. This script compiles, without running, the present element loop
(``hex8_block.element_block_viscous``, single precision: the 95 mph CCOR's) and each variant
given, for ``--cpu``, in a new process (Numba reads its target once, when it starts) with an
empty Numba cache of its own, and prints for each the instructions of its one-block loop (as
``hex8_ceiling.py`` finds it) and, per cell, its vector floating-point instructions, divisions
and square roots, vector moves and the moves that address the stack (spills and reloads).

These counts depend on the code and the target only, not on the host: ``znver3`` read here
gives the loop measured on the AVX2 EPYC itself (benchmarks/RESULTS.md). Times do depend on the
host; to time the AVX2 loop on an AVX-512 host (as a proxy: its ports are not a Zen 3's), run
``element_loop_ab.py`` under the variables this script prints.

``--vector-bits`` is the width batball gives LLVM (``batball.numerics.set_vector_width``): 512
on a CPU with AVX-512 unless ``BATBALL_VECTOR_WIDTH=256``; a CPU without AVX-512 has only 256.
A variant is ``path/to/file.py:name``, as for ``element_loop_ab.py``. Usage:

    python benchmarks/loop_asm.py [--cpu znver3] [--vector-bits 256] [VARIANT ...]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from batball.numerics import WIDTH_FEATURES

#: What the child process prints: one JSON line per loop.
CHILD = """
import json, sys
import numba as nb
import numpy as np
sys.path.insert(0, {benchmarks!r})
from element_loop_ab import load_variant
from hex8_ceiling import instruction_mix, vector_loop
from batball.elements import hex8_block as hb

register, lanes = {register!r}, {lanes}
signature = hb.element_block_types(np.float32)
loops = {{"present": hb.element_block_viscous}}
loops.update({{spec: load_variant(spec) for spec in {variants!r}}})
print(json.dumps({{"cpu": nb.config.CPU_NAME, "features": nb.config.CPU_FEATURES}}))
for name, loop in loops.items():
    loop.compile(signature)
    body = vector_loop(loop.inspect_asm(signature), register)
    mix = instruction_mix(body, register) if body else {{}}
    print(json.dumps({{"loop": name, "mix": mix}}))
"""


def features(vector_bits: int) -> str:
    """The feature string given with the CPU name: the CPU's own features (LLVM's table for the
    name), with batball's choice of width (``numerics.WIDTH_FEATURES``)."""
    return WIDTH_FEATURES[str(vector_bits)]


def child_environment(cpu: str, vector_bits: int, cache: str) -> dict[str, str]:
    """The environment of a process that compiles for ``cpu`` into the Numba cache ``cache``."""
    return os.environ | {
        "NUMBA_CPU_NAME": cpu,
        "NUMBA_CPU_FEATURES": features(vector_bits),
        "NUMBA_CACHE_DIR": cache,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("variants", nargs="*", help="path/to/file.py:name")
    parser.add_argument("--cpu", default="znver3", help="an LLVM CPU name (llc -mcpu=help)")
    parser.add_argument("--vector-bits", type=int, choices=(256, 512), default=256)
    args = parser.parse_args()
    register, lanes = ("zmm", 16) if args.vector_bits == 512 else ("ymm", 8)
    code = CHILD.format(benchmarks=str(Path(__file__).resolve().parent), register=register,
                        lanes=lanes, variants=args.variants)  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="loop-asm-cache-") as cache:
        env = child_environment(args.cpu, args.vector_bits, cache)
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=False)  # fmt: skip
    if "is not a recognized processor" in out.stderr:
        raise SystemExit(f"--cpu {args.cpu}: not a CPU this LLVM knows; expected a name of "
                         "`llc -mcpu=help`, as znver3, znver5 or sapphirerapids")  # fmt: skip
    if out.returncode != 0:
        raise SystemExit(f"compiling for --cpu {args.cpu}: {out.stderr.strip().splitlines()[-1]}")
    lines = [json.loads(line) for line in out.stdout.splitlines() if line.startswith("{")]
    head, loops = lines[0], lines[1:]
    print(f"compiled for {head['cpu']} ({head['features']}), {args.vector_bits}-bit vectors, "
          f"{lanes} single-precision cells an iteration; to time under the same target: "
          f"NUMBA_CPU_NAME={args.cpu} NUMBA_CPU_FEATURES={features(args.vector_bits)}")  # fmt: skip
    for loop in loops:
        mix = loop["mix"]
        if not mix:
            print(f"  {loop['loop']}: no one-block loop on {register} registers (not vectorised "
                  f"{args.vector_bits} bits wide)")  # fmt: skip
            continue
        per_cell = ", ".join(f"{value / lanes:.1f} {key}" for key, value in mix.items()
                             if key not in ("instructions", "vector"))  # fmt: skip
        print(f"  {loop['loop']}: {mix['instructions']} instructions an iteration; a cell: "
              f"{per_cell}")  # fmt: skip


if __name__ == "__main__":
    main()
