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
``--mca`` also runs LLVM's machine-code analyser (``llvm-mca``, from the system's LLVM, not
installed by batball) on each loop for ``--mca-cpu`` (default ``--cpu``; an older llvm-mca may
not know the newest names, and models some, as ``sapphirerapids``, on an older core's ports): the
cycles an iteration it predicts in a steady state, the bound from its ports' throughput alone,
the share of the predicted cycles it puts on port pressure and on chains of dependent
instructions, and the busiest resources (ports and units). A model, not a measurement: it
knows no cache misses and a simplified out-of-order engine. A variant is
``path/to/file.py:name``, as for ``element_loop_ab.py``. Usage:

    python benchmarks/loop_asm.py [--cpu znver3] [--vector-bits 256] [--mca] [VARIANT ...]
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import NamedTuple

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
    print(json.dumps({{"loop": name, "mix": mix, "body": body}}))
"""

#: Iterations of the loop llvm-mca simulates.
MCA_ITERATIONS = 100


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


def mca_tool(cpu: str) -> str:
    """The path of llvm-mca, if it is on PATH and knows ``cpu``; else a one-line refusal
    (checked before anything compiles)."""
    tool = shutil.which("llvm-mca")
    if tool is None:
        raise SystemExit("--mca: llvm-mca is not on PATH (it comes with LLVM, as Debian's "
                         "llvm package); run without --mca")  # fmt: skip
    out = subprocess.run([tool, f"-mcpu={cpu}"], input="\tnop\n", capture_output=True,
                         text=True, check=False)  # fmt: skip
    if out.returncode != 0 or "not a recognized processor" in out.stderr:
        raise SystemExit(f"--mca-cpu {cpu}: not a CPU this llvm-mca knows (`llvm-mca "
                         "-mcpu=help`); name an older one of its family, as znver3 or "
                         "skylake-avx512")  # fmt: skip
    return tool


class McaView(NamedTuple):
    """What llvm-mca predicts for a loop: cycles an iteration, the bound from its ports alone,
    the shares of the cycles it puts on port pressure and on dependency chains [%], and the
    busiest resources (cycles an iteration, name)."""

    cycles: float
    bound: float
    pressure: float
    dependencies: float
    busiest: list[tuple[float, str]]


def mca(tool: str, body: list[list[str]], cpu: str) -> McaView:
    """llvm-mca's view (``tool``, from :func:`mca_tool`) of the loop ``body`` (instructions as
    ``vector_loop`` gives them) on ``cpu`` (:class:`McaView`)."""
    text = "".join(f"\t{op}\t{' '.join(rest)}\n" for op, *rest in body)
    out = subprocess.run([tool, f"-mcpu={cpu}", f"-iterations={MCA_ITERATIONS}",
                          "-bottleneck-analysis"], input=text, capture_output=True, text=True,
                         check=False)  # fmt: skip
    if out.returncode != 0:
        raise SystemExit(f"--mca: llvm-mca failed on the loop for {cpu} "
                         f"({(out.stderr.strip().splitlines() or ['no message'])[0]})")  # fmt: skip
    report = out.stdout

    def number(label: str) -> float:
        found = re.search(rf"{label}:?\s*\[?\s*([0-9.]+)", report)
        if found is None:
            raise SystemExit(f"--mca: no '{label}' in llvm-mca's report")
        return float(found.group(1))

    names = re.findall(r"^\[([0-9.]+)\]\s+-\s+(\S+)", report, flags=re.MULTILINE)
    pressure = report.split("Resource pressure per iteration:", 1)[1].splitlines()[2].split()
    # a unit of several (as "[12.0] - Zn3FPP45") is named with its index
    loads = sorted(((float(value), f"{name}[{index}]" if "." in index else name)
                    for (index, name), value in zip(names, pressure, strict=True)
                    if value != "-"), reverse=True)  # fmt: skip
    return McaView(
        number("Total Cycles") / MCA_ITERATIONS,
        number("Block RThroughput"),
        number("Resource Pressure"),
        number("Data Dependencies"),
        loads[:4],
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("variants", nargs="*", help="path/to/file.py:name")
    parser.add_argument("--cpu", default="znver3", help="an LLVM CPU name (llc -mcpu=help)")
    parser.add_argument("--vector-bits", type=int, choices=(256, 512), default=256)
    parser.add_argument("--mca", action="store_true", help="llvm-mca's view of each loop")
    parser.add_argument("--mca-cpu", help="the CPU model llvm-mca takes (default --cpu)")
    args = parser.parse_args()
    mca_cpu = args.mca_cpu or args.cpu
    tool = mca_tool(mca_cpu) if args.mca else None
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
        if tool is not None:
            view = mca(tool, loop["body"], mca_cpu)
            busiest = ", ".join(f"{name} {value:.0f}" for value, name in view.busiest)
            print(f"    llvm-mca ({mca_cpu}): {view.cycles:.1f} cycles an "
                  f"iteration ({view.cycles / lanes:.1f} a cell), the ports' bound "
                  f"{view.bound:.1f} cycles; cycles it puts on port pressure "
                  f"{view.pressure:.0f} %, on dependency chains {view.dependencies:.0f} % "
                  f"(they overlap); busiest resources, cycles an iteration: {busiest}")  # fmt: skip


if __name__ == "__main__":
    main()
