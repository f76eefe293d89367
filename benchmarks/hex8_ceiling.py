"""How fast the full-size CCOR solver could run on this machine: the hex kernel's parts and a bound.

The CCOR goal is a rate (hex element-cycles per second per GFLOP/s of SGEMM). This script
measures where a cycle's time goes on one thread, and what the hex kernel's vector loop would
take if each of its vector floating-point instructions issued at the machine's vector-FMA rate.
From these it prints the solver's rate as measured, with the data movement of the kernel free,
with its element loop at that rate, and with both:

* the cycle, timed by part on the 95 mph CCOR solver of ball type 1 (12,096 hexes, single
  precision, IHQ 1, after ``--cycles`` cycles): the whole hex kernel (``compute_hex8_forces``),
  its node gather (``hex8_block.gather_nodes``), its force scatter (``scatter_forces``), the
  material factors and the volumes and steps copied (``gather_material``, ``scatter_outputs``),
  each alone over all blocks; the element loop (``element_block``) is the kernel less those;
  the whole cycle from full cycles of a second solver in the solvers' own compiled loop
  (``explicit_kernels.run_cycles``, as a run takes them), and the rest of the cycle (contact,
  step, update, records) as the cycle less the kernel. The parts alternate in rounds; each
  figure is the median. The kernel and the parts, too, run in compiled loops: called from
  Python with its arrays the kernel took 18 us a call more, and the rest of the cycle, timed
  by the solver's own phase clock (called from Python with its two dozen arrays), 68 us where
  the loops give 31-38 (the Intel Xeon of 2026-12-07);
* the element loop's instructions, read from its assembly (compiled alone here; the kernel
  inlines the same function): the one-block loop with the most instructions on the widest
  vector register, split into vector floating-point instructions (arithmetic, FMA, division,
  square root, compares, selects, logic, conversions, shuffles), vector moves, and moves that
  address the stack (spills and reloads);
* the yardstick: NumPy SGEMM on one thread (``yardstick.py``), measured in every round (a
  shared host's speed drifts within seconds) and taken as 2 x lanes flops per vector FMA
  instruction: the rate at which this machine issues vector FMAs on dense work.

The bound is optimistic: every vector floating-point instruction at the FMA rate (divisions and
square roots are slower) and every move free. Each part is timed over ``--calls`` calls after
the round's SGEMM: on an AMD Zen 5 the first few dozen calls after it ran up to half as long
again (20 calls gave the kernel 522 us a cycle, 100 calls 357 us, as in whole runs), so the
default is 100. Usage:

    python benchmarks/hex8_ceiling.py [--cycles 40] [--calls 100] [--rounds 5]
"""

from __future__ import annotations

import argparse
import re
import statistics
import time
from collections.abc import Callable

import numba as nb
import numpy as np
from bench_hex8_kernel import kernel_loop, loaded_solver, one_thread_arguments, seconds_per_call
from yardstick import gemm_gflops

from batball.elements import hex8_block as hb
from batball.elements.hex8 import kernel_ids
from batball.numerics import wide_vectors
from batball.solvers import explicit_kernels as kern
from batball.solvers.explicit import ExplicitSolver

#: The goal of the CCOR solver: hex element-cycles per second per GFLOP/s of SGEMM.
GOAL = 2e5

#: Mnemonic prefixes of vector floating-point work (the vector ALU ports: arithmetic, logic,
#: conversions and shuffles), as opposed to moves.
_FP = ("vadd", "vsub", "vmul", "vfmadd", "vfmsub", "vfnmadd", "vfnmsub", "vdiv", "vsqrt",
       "vmax", "vmin", "vrcp", "vrsqrt", "vrndscale", "vcvt", "vand", "vor", "vxor", "vcmp",
       "vblend", "vpternlog", "vpadd", "vpsub", "vpsll", "vpsrl", "vpand", "vpor", "vpxor",
       "vpcmp", "vpmul", "vperm", "vshuf", "vunpck")  # fmt: skip


# Each part over all blocks, ``calls`` times in its compiled loop (as the kernel is timed):
# called from Python, a call would add the typing of its arrays.


@nb.njit
def _gather_all(w, xs, vs, cells, n_cells, calls):  # noqa: ANN001, ANN202
    for _ in range(calls):
        for start in range(0, n_cells, hb.BLOCK):
            hb.gather_nodes(w, start, min(hb.BLOCK, n_cells - start), xs, vs, cells)


@nb.njit
def _scatter_all(w, cells, forces, n_cells, calls):  # noqa: ANN001, ANN202
    for _ in range(calls):
        for start in range(0, n_cells, hb.BLOCK):
            hb.scatter_forces(w, start, min(hb.BLOCK, n_cells - start), cells, forces)


@nb.njit
def _copies_all(w, cell_material, factors, volume, dt, n_cells, calls):  # noqa: ANN001, ANN202
    for _ in range(calls):
        held = -1  # as the kernel calls them: a block of the material w holds is not copied
        for start in range(0, n_cells, hb.BLOCK):
            n = min(hb.BLOCK, n_cells - start)
            held = hb.gather_material(w, start, n, cell_material, factors, held)
            hb.scatter_outputs(w, start, n, volume, dt)


def vector_loop(asm: str, register: str) -> list[list[str]]:
    """The instructions (mnemonic and operands) of the loop of one basic block, jumping back to
    its own label, that holds the most instructions on ``register`` (``zmm`` or ``ymm``)."""
    best: list[list[str]] = []
    label, body = None, []
    for line in asm.splitlines():
        if re.match(r"^\.LBB\w+:", line):
            label, body = line.split(":")[0], []
        elif line.startswith("\t") and not line.startswith("\t.") and label is not None:
            parts = line.split(None, 1)
            body.append([parts[0], parts[1] if len(parts) > 1 else ""])
            if parts[0].startswith("j") and parts[-1].strip() == label:
                count = sum(register in b[1] for b in body)
                if count > sum(register in b[1] for b in best):
                    best = list(body)
    return best


def instruction_mix(loop: list[list[str]], register: str) -> dict[str, int]:
    """Counts of the loop's vector floating-point instructions, vector memory moves, and moves
    that address the stack (``rsp``: spills and reloads)."""
    vector = [b for b in loop if register in b[1]]
    fp = [b for b in vector if b[0].startswith(_FP)]
    moves = [b for b in vector if b[0].startswith(("vmov", "vbroadcast"))]
    return {
        "instructions": len(loop),
        "vector": len(vector),
        "vector floating point": len(fp),
        "divisions and square roots": sum(b[0].startswith(("vdiv", "vsqrt")) for b in fp),
        "vector moves": len(moves),
        "stack moves": sum("rsp" in b[1] for b in moves),
    }


def seconds_per_cycle(solver: ExplicitSolver, cycles: int) -> float:
    """Wall seconds a cycle of ``solver`` over ``cycles`` cycles in the solvers' compiled loop
    (:func:`batball.solvers.explicit_kernels.run_cycles`: the kernel, then contact, step,
    update and the history row), as :meth:`ExplicitSolver.run` takes them."""
    kernel, arguments, controls = solver.kernel_call()
    table = np.zeros((cycles, solver.work.row_width))
    start = time.perf_counter()
    status, rows = kern.run_cycles(kernel, arguments, controls, solver.finish_arguments(), table,
                                   0, np.inf, np.inf, 0)  # fmt: skip
    seconds = time.perf_counter() - start
    if status < 0 or rows != cycles:
        raise SystemExit(f"the solver stopped after {rows} of {cycles} cycles (status {status}): "
                         "fewer --cycles before, or fewer --calls")  # fmt: skip
    return seconds / cycles


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    args = one_thread_arguments(parser, 40, 100, 5)
    solver = loaded_solver(1, args.cycles)  # the parts called alone (their sums pile up)
    cycling = loaded_solver(1, args.cycles)  # full cycles, for the rest of the cycle
    state, work, model = solver.state, solver.work, solver.model
    cells, n_cells = kernel_ids(work.cells), model.mesh.n_cells
    xs, vs = state.points.reshape(-1), state.velocities.reshape(-1)
    w = np.zeros(hb.N_ROWS * hb.BLOCK, dtype=state.history.dtype)
    factors = hb.material_factors(model.material_constants, model.densities, float(state.dt))
    forces = np.zeros_like(xs)
    volume, step = np.empty(n_cells), np.empty(n_cells)
    material = kernel_ids(work.cell_material)
    parts: dict[str, Callable[[int], object]] = {
        "kernel": kernel_loop(solver),
        "gather": lambda calls: _gather_all(w, xs, vs, cells, n_cells, calls),
        "scatter": lambda calls: _scatter_all(w, cells, forces, n_cells, calls),
        "copies": lambda calls: _copies_all(w, material, factors, volume, step, n_cells, calls),
    }
    times: dict[str, list[float]] = {name: [] for name in [*parts, "cycle"]}
    sgemms = []
    seconds_per_cycle(cycling, 2)  # the loop typed (or compiled) once
    for _ in range(args.rounds):
        sgemms.append(gemm_gflops(1)["sgemm"])
        for name, call in parts.items():
            times[name].extend(seconds_per_call(call, args.calls, 1))
        times["cycle"].append(seconds_per_cycle(cycling, args.calls))
    t = {name: statistics.median(values) for name, values in times.items()}
    t["rest of cycle"] = t["cycle"] - t["kernel"]
    if t["rest of cycle"] <= 0.0:
        raise SystemExit("the whole cycle took less than the kernel alone: the host's load "
                         "changed within a round; run again")  # fmt: skip
    t["element loop"] = t["kernel"] - t["gather"] - t["scatter"] - t["copies"]
    if t["element loop"] <= 0.0:
        raise SystemExit("the kernel took less than its gather, scatter and copies alone: the "
                         "host's load changed within a round; run again")  # fmt: skip
    sgemm = statistics.median(sgemms)

    wide = wide_vectors()
    register, lanes = ("zmm", 16) if wide else ("ymm", 8)
    block = hb.element_block_viscous  # compiled alone here (the kernel inlines it)
    signature = hb.element_block_types(np.float32)
    block.compile(signature)
    loop = vector_loop(block.inspect_asm(signature), register)
    if not loop:
        raise SystemExit(f"no one-block loop on {register} registers in the element loop's "
                         "assembly: a vector width this bound does not know")  # fmt: skip
    mix = instruction_mix(loop, register)
    fma_rate = sgemm * 1e9 / (2 * lanes)  # vector FMA instructions per second
    bound = mix["vector floating point"] * n_cells / lanes / fma_rate

    print(f"SGEMM {sgemm:.1f} GFLOP/s on 1 thread (rounds {min(sgemms):.0f}-{max(sgemms):.0f}): "
          f"{fma_rate / 1e9:.2f} G {lanes}-lane FMA instructions/s; {n_cells} hexes, medians of "
          f"{args.rounds} rounds")  # fmt: skip
    for name in ("kernel", "gather", "element loop", "scatter", "copies", "rest of cycle"):
        print(f"  {name:>14}: {t[name] * 1e6:8.1f} us a cycle")
    counts = ", ".join(f"{value} {key}" for key, value in mix.items())
    print(f"  element loop, {lanes} cells an iteration: {counts}")
    print(f"  element loop at the FMA rate: {bound * 1e6:.1f} us a cycle "
          f"({bound / t['element loop']:.0%} of its measured time)")  # fmt: skip
    cycle = t["cycle"]
    moves = t["gather"] + t["scatter"] + t["copies"]
    at_peak = cycle - t["element loop"] + bound
    for label, seconds in (
        ("as measured", cycle),
        ("gather, scatter and copies free", cycle - moves),
        ("element loop at the FMA rate", at_peak),
        ("both", at_peak - moves),
    ):
        rate = n_cells / seconds
        print(f"  solver, {label}: {rate / 1e6:.1f} M element-cycles/s, {rate / sgemm:.3g} per "
              f"GFLOP/s of SGEMM (goal {GOAL:.0e})")  # fmt: skip


if __name__ == "__main__":
    main()
