"""The whole hex kernel as built, against the same source compiled under LLVM options, at once.

LLVM's command-line options (``llvmlite.binding.set_option``) are global to a process and read
when a function is compiled, so an A/B of them in two processes compares two hosts as much as
two codes (a shared host drifts by a fifth within minutes). This script loads the present
kernel (``hex8._forces_viscous``: MAT_006, IHQ 1, single precision, as the 95 mph CCOR runs it),
then sets the options given and compiles a second kernel from the same source (uncached), runs
both once on copies of the same state and says whether they give the same bits, and times them
in alternating rounds on the CCOR solver's arrays after ``--cycles`` cycles, one thread.

The kernel is the context to judge a schedule in: ``element_loop_ab.py`` times the element loop
compiled inside its own timing loop, where LLVM allocates registers differently, and there a
scheduler that made the kernel slower made the loop faster (benchmarks/RESULTS.md,
2026-12-07). Note that llvmlite ignores an option this LLVM does not have, without a word: a
variant whose code does not differ measures nothing but noise. Usage:

    python benchmarks/kernel_llvm_options_ab.py --llvm=-pre-RA-sched=list-ilp [--rounds 9]
"""

from __future__ import annotations

import argparse
import statistics
import time

import llvmlite.binding as llvm
import numba as nb
import numpy as np
from bench_hex8_kernel import loaded_solver, one_thread_arguments

from batball.elements import hex8
from batball.elements import hex8_block as hb
from batball.numerics import FASTMATH


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--llvm",
        action="append",
        required=True,
        dest="options",
        help="an LLVM option (repeatable), as --llvm=-pre-RA-sched=list-ilp",
    )
    args = one_thread_arguments(parser, 40, 100, 9)
    solver = loaded_solver(1, args.cycles)
    present, arguments, controls = solver.kernel_call()
    if present is not hex8._forces_viscous:  # the variant below is compiled from its source
        raise SystemExit("the CCOR solver of ball type 1 no longer runs hex8._forces_viscous")
    arguments = (*arguments, (float(solver.state.dt), *controls))
    present(*arguments)
    for option in args.options:
        llvm.set_option("kernel_llvm_options_ab", option)

    @nb.njit(parallel=True, fastmath=FASTMATH)
    def variant(mesh, material, history, outputs, controls):  # noqa: ANN001, ANN202
        hex8._advance_all(hb.element_block_viscous, mesh, material, history, outputs, controls)

    def fresh() -> tuple:
        """The arguments with copies of what the kernel writes."""
        history = arguments[2].copy()
        outputs = tuple(a.copy() for a in arguments[3])
        return arguments[0], arguments[1], history, outputs, arguments[4]

    ran = {}
    for name, kernel in (("present", present), ("variant", variant)):
        copy = fresh()
        kernel(*copy)
        ran[name] = [copy[2], *copy[3]]
    same = all(np.array_equal(a, b) for a, b in zip(ran["present"], ran["variant"], strict=True))
    print(f"{' '.join(args.options)}: {'the same bits as' if same else 'NOT the same bits as'} "
          f"the present kernel")  # fmt: skip
    times: dict[str, list[float]] = {"present": [], "variant": []}
    for _ in range(args.rounds):
        for name, kernel in (("present", present), ("variant", variant)):
            start = time.perf_counter()
            for _ in range(args.calls):
                kernel(*arguments)
            times[name].append((time.perf_counter() - start) / args.calls * 1e6)
    for name, values in times.items():
        print(f"  {name}: median {statistics.median(values):.1f} us a call, min {min(values):.1f} "
              f"({args.rounds} alternated rounds of {args.calls} calls)")  # fmt: skip


if __name__ == "__main__":
    main()
