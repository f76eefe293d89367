"""The hex element loop alone, its present source against variants, in one process.

Whole runs and even the kernel alone drift by a tenth within minutes on a shared host, more than
a change of the element loop's source order makes (benchmarks/RESULTS.md, 2026-12-07). This
script compiles the present loop (``hex8_block.element_block_viscous``: MAT_006, IHQ 1, the
95 mph CCOR's) and each variant given side by side, and times them in alternating rounds on
the same data: every ``--every``-th block of the 12,096-hex ball after ``--cycles`` cycles,
gathered once. Each call first copies the block's scratch and history row back in (the loop
overwrites them), so the script also times that copy alone and prints each loop's time less
it. Before timing it checks that every variant gives the present loop's bits on one block.

The loop is compiled here inside the timing loop, not inside the kernel, and LLVM may allocate
its registers differently in the two: confirm a gain on the kernel (``bench_hex8_kernel.py``,
or ``kernel_llvm_options_ab.py`` for compiler options), as a scheduler that made this loop
10-14 % faster made the kernel slower (benchmarks/RESULTS.md, 2026-12-07).

A variant is ``path/to/file.py:name``: a Numba function with ``element_block``'s signature
``(w, history, n, dt, q1, q2, hg_coefficient) -> (internal, hourglass, bulk)``, typically a
copy of ``hex8_block._make_element_block``'s loop with its statements reordered. Usage:

    python benchmarks/element_loop_ab.py [VARIANT ...] [--rounds 15] [--every 7] [--calls 200]
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import time
from collections.abc import Callable

import numba as nb
import numpy as np
from bench_hex8_kernel import loaded_solver

from batball.elements import hex8_block as hb
from batball.elements.hex8 import kernel_ids

#: The controls the timed calls pass (Q1, Q2 and QH of the CCOR runs).
Q1, Q2, QH = 1.5, 0.06, 0.1


@nb.njit
def _copy_only(w, history, n, dt, q1, q2, hg_coefficient):  # noqa: ANN001, ANN202
    """The copy-in's yardstick: takes the loop's arguments and does nothing."""
    return 0.0, 0.0, 0.0


@nb.njit
def _run(loop, scratches, histories, w, history, calls, dt):  # noqa: ANN001, ANN202
    """``calls`` times over the blocks: copy block i's scratch and history in, run ``loop``."""
    total = 0.0
    for _ in range(calls):
        for i in range(scratches.shape[0]):
            w[:] = scratches[i]
            history[:] = histories[i]
            total += loop(w, history, hb.BLOCK, dt, Q1, Q2, QH)[0]
    return total


def load_variant(spec: str) -> Callable:
    """The function ``name`` of the Python file ``path`` in ``path:name``."""
    path, _, name = spec.rpartition(":")
    if not path or not name:
        raise SystemExit(f"variant {spec!r}: expected path/to/file.py:name")
    module_spec = importlib.util.spec_from_file_location("element_loop_variant", path)
    if module_spec is None or module_spec.loader is None:
        raise SystemExit(f"variant {spec!r}: {path} is not a Python file")
    module = importlib.util.module_from_spec(module_spec)
    module_spec.loader.exec_module(module)
    if not hasattr(module, name):
        raise SystemExit(f"variant {spec!r}: {path} has no {name}")
    return getattr(module, name)


def gathered_blocks(cycles: int, every: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Every ``every``-th block's scratch (gathered nodes and material factors) and history row
    of the CCOR solver after ``cycles`` cycles, and its step [s]."""
    solver = loaded_solver(1, cycles)
    state, work, model = solver.state, solver.work, solver.model
    dt = float(state.dt)
    factors = hb.material_factors(model.material_constants, model.densities, dt)
    cells, material = kernel_ids(work.cells), kernel_ids(work.cell_material)
    xs, vs = state.points.reshape(-1), state.velocities.reshape(-1)
    n_full = model.mesh.n_cells // hb.BLOCK  # whole blocks only
    scratches, histories = [], []
    for block in range(0, n_full, every):
        w = np.zeros((hb.R_MAT + factors.shape[1]) * hb.BLOCK, dtype=state.history.dtype)
        hb.gather_nodes(w, block * hb.BLOCK, hb.BLOCK, xs, vs, cells)
        hb.gather_material(w, block * hb.BLOCK, hb.BLOCK, material, factors, -1)
        scratches.append(w)
        histories.append(state.history[block].copy())
    return np.stack(scratches), np.stack(histories), dt


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("variants", nargs="*", help="path/to/file.py:name")
    parser.add_argument("--cycles", type=int, default=50)
    parser.add_argument("--every", type=int, default=7, help="time every N-th block")
    parser.add_argument("--calls", type=int, default=200, help="passes over the blocks a round")
    parser.add_argument("--rounds", type=int, default=15)
    args = parser.parse_args()
    for name in ("cycles", "every", "calls", "rounds"):
        if getattr(args, name) < 1:
            parser.error(f"--{name}: {getattr(args, name)} is not allowed; expected 1 or more")
    nb.set_num_threads(1)
    loops = {"present": hb.element_block_viscous, "copy-in alone": _copy_only}
    loops.update({spec: load_variant(spec) for spec in args.variants})
    scratches, histories, dt = gathered_blocks(args.cycles, args.every)
    w, history = scratches[0].copy(), histories[0].copy()
    outputs = {}
    for name, loop in loops.items():
        _run(loop, scratches, histories, w, history, 1, dt)  # compiles
        w[:], history[:] = scratches[0], histories[0]
        loop(w, history, hb.BLOCK, dt, Q1, Q2, QH)
        outputs[name] = (w.copy(), history.copy())
    present = outputs["present"]
    for name in args.variants:
        same = all(np.array_equal(a, b) for a, b in zip(outputs[name], present, strict=True))
        print(f"{name}: {'the same bits as' if same else 'NOT the same bits as'} the present loop")
    times: dict[str, list[float]] = {name: [] for name in loops}
    per_call = args.calls * len(scratches)
    for _ in range(args.rounds):
        for name, loop in loops.items():
            start = time.perf_counter()
            _run(loop, scratches, histories, w, history, args.calls, dt)
            times[name].append((time.perf_counter() - start) / per_call * 1e6)
    copy_in = statistics.median(times["copy-in alone"])
    print(f"{len(scratches)} blocks of {hb.BLOCK} cells, {args.rounds} alternated rounds of "
          f"{args.calls} passes; us a block (the copy-in alone: median {copy_in:.3f})")  # fmt: skip
    for name in loops:
        if name == "copy-in alone":
            continue
        values = times[name]
        print(f"  {name}: min {min(values):.3f}, median {statistics.median(values):.3f}; "
              f"less the copy-in {statistics.median(values) - copy_in:.3f}")  # fmt: skip


if __name__ == "__main__":
    main()
