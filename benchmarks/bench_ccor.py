"""Full-size CCOR benchmark: ball type 1 at 95 mph on the 12,096-hex ball.

Runs the whole test (mesh, model, explicit run to separation, measurements) once to compile the
Numba kernels, then times it with 1 thread (the baseline in the same run) and with every thread,
and prints wall time and hex element-cycles per second for each, also per GFLOP/s of the
machine's SGEMM on the same threads, measured in the same run (``yardstick.py``), with the CPU's
model and vector width, and the hex kernel's GFLOP/s from the flops it does per element-cycle
(counted from the code, ``flop_counts.py``) as a fraction of that yardstick. Usage:

    python benchmarks/bench_ccor.py [--divisions 12] [--repeats 3] [--precision single]
        [--rounds 1]

``--precision both`` alternates single and double element arithmetic (the A/B of
docs/notes/precision.md). ``--rounds R`` runs the thread counts R times in turn, each round a
new process per thread count, and ends with each round's solver time on one thread over that
on the others: a shared host's speed drifts by a tenth within minutes, so the ratio of two
runs minutes apart says little; the ratios of runs seconds apart, over rounds, say more.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys

CHILD = """
import json, time, numba
from batball.lab.impact import ImpactSetup, run_impact
from batball.specs import load_ball_spec
numba.set_num_threads({threads})
ball = load_ball_spec("type1")
setup = ImpactSetup(test="ccor", speed=95 * 0.44704, divisions={divisions}, precision="{precision}")
run_impact(ball, ImpactSetup(test="ccor", speed=95 * 0.44704, divisions=3, precision="{precision}"))
walls, solver = [], []
for _ in range({repeats}):
    start = time.perf_counter()
    result = run_impact(ball, setup)
    walls.append(time.perf_counter() - start)
    solver.append(result.run.wall_seconds)
print(json.dumps(dict(walls=walls, solver=solver, n_cells=result.mesh.n_cells,
                      n_steps=result.run.n_steps, phases=result.run.phase_seconds,
                      ccor=result.measures.restitution)))
"""


def measure(threads: int, divisions: int, repeats: int, precision: str) -> dict:
    code = CHILD.format(threads=threads, divisions=divisions, repeats=repeats, precision=precision)
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--divisions", type=int, default=12)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--precision", choices=("single", "double", "both"), default="single")
    parser.add_argument("--threads", type=int, nargs="*", help="thread counts (default 1 and all)")
    parser.add_argument("--rounds", type=int, default=1, help="times to run the thread counts in "
                        "turn (default 1)")  # fmt: skip
    args = parser.parse_args()
    import numba
    from yardstick import cpu_description, yardstick_label

    cpu = cpu_description()
    print(f"{cpu['model']}, {cpu['vector_bits']}-bit vectors, {cpu['logical_cpus']} logical "
          f"CPUs; GEMM by {yardstick_label()}")  # fmt: skip
    precisions = ("single", "double") if args.precision == "both" else (args.precision,)
    runs = [(t, p) for t in args.threads or sorted({1, numba.config.NUMBA_NUM_THREADS})
            for p in precisions]  # fmt: skip
    solver_seconds: dict[tuple[int, str], list[float]] = {run: [] for run in runs}
    for round_ in range(args.rounds):
        for threads, precision in runs:
            if args.rounds > 1:
                print(f"round {round_ + 1} of {args.rounds}:", end=" ")
            solver = report(threads, precision, args.divisions, args.repeats)
            solver_seconds[threads, precision].append(solver)
    for precision in precisions:
        counts = [t for t, p in runs if p == precision and t != 1]
        if args.rounds < 2 or (1, precision) not in solver_seconds:
            continue
        one = solver_seconds[1, precision]
        for threads in counts:
            ratios = [a / b for a, b in zip(one, solver_seconds[threads, precision], strict=True)]
            print(f"{precision}: one thread's solver time over {threads} threads', round by "
                  f"round: {', '.join(f'{r:.2f}' for r in ratios)}; median "
                  f"{statistics.median(ratios):.2f}")  # fmt: skip


def report(threads: int, precision: str, divisions: int, repeats: int) -> float:
    """Run the test on ``threads`` threads in a new process and print its figures; returns the
    solver's median seconds."""
    from flop_counts import hex8_flops
    from yardstick import gemm_gflops

    r = measure(threads, divisions, repeats, precision)
    wall, solver = statistics.median(r["walls"]), statistics.median(r["solver"])
    rate = r["n_cells"] * r["n_steps"] / solver
    gemm = gemm_gflops(threads)["sgemm" if precision == "single" else "dgemm"]
    print(f"{precision}, threads {threads}: {r['n_cells']} hexes x {r['n_steps']} cycles; "
          f"wall {wall:.2f} s (median of {repeats}), solver {solver:.2f} s, "
          f"{rate / 1e6:.2f} M element-cycles/s; CCOR {r['ccor']:.4f}")  # fmt: skip
    name = "SGEMM" if precision == "single" else "DGEMM"
    flops = hex8_flops(single=precision == "single")  # type 1: MAT_006, one Prony term
    achieved = rate * flops / 1e9  # the solver's time: the hexes and everything else
    print(f"  yardstick: {name} {gemm:.1f} GFLOP/s on {threads} thread(s); "
          f"{rate / gemm:.3g} element-cycles/s per GFLOP/s; {flops} flops an element-cycle "
          f"-> {achieved:.1f} GFLOP/s, {achieved / gemm:.1%} of {name}")  # fmt: skip
    print("  phases (s, last run):", {k: round(v, 2) for k, v in r["phases"].items()})
    return solver


if __name__ == "__main__":
    main()
