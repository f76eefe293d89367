"""Where the foam kernel's time goes: its passes over a block, timed on the full-size foam ball.

The foam kernel (``hex8_foam``) runs five passes over each block of ``EIGEN_LANES`` cells:
the kinematics (node gather, modal sums, L, b = F F^T), the eigen-decompositions of b, the law,
the element response and the store (history, hourglass forces, nodal forces, volumes, steps).
This script times the passes on one thread on the 95 mph CCOR solver of a foam ball (the model
of record's ``type1-fit``, 12,096 hexes, after ``--cycles`` cycles): it runs the block loop
over all cells with the first 1, 2, ..., 5 passes, alternated in rounds with the whole kernel,
and gives each pass as the difference of two medians. The yardstick is NumPy DGEMM on one
thread (the foam kernel computes in double), measured in every round. Usage:

    python benchmarks/foam_stages.py [--ball type1-fit] [--cycles 50] [--calls 10] [--rounds 5]
"""

from __future__ import annotations

import argparse
import statistics

import numba as nb
import numpy as np
from bench_hex8_kernel import kernel_loop, loaded_solver, one_thread_arguments, seconds_per_call
from yardstick import gemm_gflops

from batball.elements import hex8_foam as hf
from batball.elements.hex8 import kernel_ids
from batball.materials import foam_update as fu
from batball.materials.foam import P_BETA1, P_DAMP, P_ED, P_RATE_FILTER
from batball.materials.viscoelastic import viscoelastic_step_factors

PASSES = ("kinematics", "eigen", "law", "response", "store")


@nb.njit
def _first_passes(passes, mesh, material, state, outputs, controls, calls):  # noqa: ANN001, ANN202
    """``calls`` times the foam kernel's block loop over all cells (one slot) with its first
    ``passes`` passes (in a compiled loop, as the kernel is timed: called from Python, a call
    would add the typing of its arguments)."""
    sums = (0.0, 0.0, 0.0)
    for _ in range(calls):
        sums = _passes_once(passes, mesh, material, state, outputs, controls)
    return sums


@nb.njit
def _passes_once(passes, mesh, material, state, outputs, controls):  # noqa: ANN001, ANN202
    """The foam kernel's block loop over all cells (one slot) with its first ``passes`` passes."""
    n_cells = mesh[2].shape[0]
    lanes = fu.EIGEN_LANES
    work_space = (fu.law_block(), np.empty(fu.N_HISTORY * lanes), np.empty(hf.N_KEEP * lanes),
                  fu.eigen_block(), np.empty(hf.N_GATHER * lanes),
                  np.empty(hf.N_RESPONSE * lanes))  # fmt: skip
    params, dt = material[2][0], controls[0]
    decay, scale = viscoelastic_step_factors(0.5 * params[P_ED], 0.0, params[P_BETA1], dt)
    weight = fu.rate_filter_weight(params[P_RATE_FILTER], dt)
    sums = (0.0, 0.0, 0.0)
    for start in range(0, n_cells, lanes):
        n = min(lanes, n_cells - start)
        hf.foam_kinematics(start, n, mesh, dt, work_space[2], work_space[3], work_space[4])
        if passes >= 2:
            fu.block_symmetric_eigen(work_space[3], n)
        if passes >= 3:
            hf.foam_law(start, n, material[2], state, material[1], work_space, weight)
        if passes >= 4:
            hf.foam_response(n, work_space[2], work_space[1], work_space[5], material[0],
                             params[P_DAMP], controls, (decay, scale))  # fmt: skip
        if passes >= 5:
            sums = hf.foam_store(start, n, mesh[2], state, outputs, work_space, sums)
    return sums


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ball", default="type1-fit", help="a foam ball spec")
    args = one_thread_arguments(parser, 50, 10, 5)
    solver = loaded_solver(1, args.cycles, ball=args.ball)
    if solver.model.foam is None:
        parser.error(f"--ball: {args.ball!r} is not a foam ball; expected one (type1-fit)")
    s, w, m = solver.state, solver.work, solver.model
    hourglass = solver.controls.hourglass
    n_cells = len(w.cells)
    mesh = (s.points.reshape(-1), s.velocities.reshape(-1), kernel_ids(w.cells), w.foam_reference)
    material = (float(m.densities[0]), w.volume0, m.foam.arrays())
    # the passes run on copies of the history (the law and the store write it)
    state = (s.foam_history.copy(), s.hg_state.copy())
    outputs = (np.zeros(s.points.size), np.empty(n_cells), np.empty(n_cells))
    controls = (float(s.dt), float(w.q1), float(w.q2), float(hourglass.coefficient),
                hourglass.type >= 2, hourglass.type >= 4)  # fmt: skip

    def first(passes: int):  # noqa: ANN202
        return lambda n: _first_passes(passes, mesh, material, state, outputs, controls, n)

    calls = {f"first {k}": first(k) for k in range(1, len(PASSES) + 1)}
    calls["kernel"] = kernel_loop(solver)
    times: dict[str, list[float]] = {name: [] for name in calls}
    dgemms = []
    for _ in range(args.rounds):
        dgemms.append(gemm_gflops(1)["dgemm"])
        for name, call in calls.items():
            times[name].extend(seconds_per_call(call, args.calls, 1))
    t = {name: statistics.median(values) for name, values in times.items()}
    dgemm = statistics.median(dgemms)
    print(f"{args.ball}: {n_cells} hexes, one thread, medians of {args.rounds} rounds of "
          f"{args.calls} calls; DGEMM {dgemm:.1f} GFLOP/s (rounds {min(dgemms):.0f}-"
          f"{max(dgemms):.0f})")  # fmt: skip
    before = 0.0
    for k, name in enumerate(PASSES, start=1):
        now = t[f"first {k}"]
        print(f"  {name:>10}: {(now - before) * 1e6:8.1f} us a call, "
              f"{(now - before) / n_cells * 1e9:6.1f} ns a cell")  # fmt: skip
        before = now
    kernel = t["kernel"]
    rate = n_cells / kernel
    print(f"  the passes together: {before * 1e6:.1f} us; the kernel: {kernel * 1e6:.1f} us a "
          f"call, {rate / 1e6:.2f} M element-cycles/s, {rate / dgemm:.3g} per GFLOP/s of "
          f"DGEMM")  # fmt: skip


if __name__ == "__main__":
    main()
