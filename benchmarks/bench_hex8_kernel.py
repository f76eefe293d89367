"""Hex8 force kernel alone: element-cycles per second on the 12,096-hex ball.

Builds the 95 mph CCOR model of a ball (type 1, MAT_006, by default), runs a few dozen explicit
cycles so that the stresses and hourglass forces are non-trivial, then times the ball's element
kernel alone (in a compiled loop, as the solvers call it, after a warm-up call; the median and
the best of several repeats) with 1 thread and with 2 (or every) threads:
``compute_hex8_forces``, or for a foam ball (``--ball type1-fit``, the model of record's) the
foam kernel (``hex8_foam``, always double precision). Usage:

    python benchmarks/bench_hex8_kernel.py [--ball type1] [--precision single] [--hourglass 1]
        [--cycles 50] [--calls 50] [--repeats 11]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numba
from numba import types
from yardstick import cpu_description

from batball.models.impact import ImpactSetup, build_impact_model
from batball.solvers.explicit import ExplicitControls, ExplicitSolver, HourglassControl
from batball.specs import load_ball_spec
from batball.units import MPH


def loaded_solver(
    hourglass: int, cycles: int, precision: str = "single", ball: str = "type1"
) -> ExplicitSolver:
    """The 95 mph CCOR solver of ``ball`` after ``cycles`` explicit cycles, its element
    arithmetic in ``precision`` (single, as the CCOR test runs by default; a foam's is double)."""
    setup = ImpactSetup(test="ccor", speed=95 * MPH, divisions=12)  # 12,096 hexes
    model = build_impact_model(load_ball_spec(ball), setup)
    controls = ExplicitControls(
        end_time=1e-3, hourglass=HourglassControl(type=hourglass), precision=precision
    )
    solver = ExplicitSolver(model, controls)
    for _ in range(cycles):
        solver.cycle()
    return solver


@numba.njit
def _kernel_calls(kernel: Callable, arguments: tuple, controls: tuple, dt: float,
                  calls: int) -> None:  # fmt: skip
    """``calls`` calls of the element kernel as the solvers' compiled loop makes them."""
    for _ in range(calls):
        kernel(*arguments, (dt, *controls))


def kernel_loop(solver: ExplicitSolver) -> Callable[[int], None]:
    """A call that runs the solver's element kernel (the hex kernel, or a foam ball's) a given
    number of times in a compiled loop, through the kernel's address as
    ``explicit_kernels.run_cycles`` calls it: called from Python, each call would add the
    typing of its arguments (18 us a call on an Intel Xeon)."""
    kernel, arguments, controls = solver.kernel_call()
    dt = float(solver.state.dt)
    signature = types.none(*(numba.typeof(a) for a in arguments), numba.typeof((dt, *controls)))
    kernel.compile(signature.args)  # type: ignore[attr-defined]
    loop = _kernel_calls.compile((types.FunctionType(signature), numba.typeof(arguments),
                                  numba.typeof(controls), types.float64, types.int64))  # fmt: skip
    return lambda calls: loop(kernel, arguments, controls, dt, calls)


def seconds_per_call(loop: Callable[[int], object], calls: int, repeats: int) -> list[float]:
    """Mean wall time a call of ``calls`` back-to-back calls, ``repeats`` times [s]: ``loop(n)``
    makes n calls in a compiled loop (:func:`kernel_loop`), so that the time is the calls'
    own, not that of Python typing their arguments."""
    loop(1)  # warm-up (and compilation)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        loop(calls)
        times.append((time.perf_counter() - start) / calls)
    return times


def one_thread_arguments(
    parser: argparse.ArgumentParser, cycles: int, calls: int, rounds: int
) -> argparse.Namespace:
    """Parse ``--cycles``, ``--calls`` and ``--rounds`` (with these defaults) and the parser's own
    options, refuse a count below 1, print the CPU line and set Numba to one thread: the common
    start of the one-thread part timings (``hex8_ceiling.py``, ``foam_stages.py``)."""
    parser.add_argument("--cycles", type=int, default=cycles)
    parser.add_argument("--calls", type=int, default=calls)
    parser.add_argument("--rounds", type=int, default=rounds)
    args = parser.parse_args()
    for name in ("cycles", "calls", "rounds"):
        if getattr(args, name) < 1:
            parser.error(f"--{name}: {getattr(args, name)} is not allowed; expected 1 or more")
    cpu = cpu_description()
    print(f"{cpu['model']}, {cpu['vector_bits']}-bit vectors, {cpu['logical_cpus']} logical CPUs")
    numba.set_num_threads(1)
    return args


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ball", default="type1", help="a ball spec (type1-fit: a foam)")
    parser.add_argument("--hourglass", type=int, default=1, help="LS-DYNA IHQ (1, 2 or 4)")
    parser.add_argument("--cycles", type=int, default=50)
    parser.add_argument("--calls", type=int, default=50)
    parser.add_argument("--repeats", type=int, default=11)
    parser.add_argument("--precision", choices=("single", "double"), default="single")
    args = parser.parse_args()
    solver = loaded_solver(args.hourglass, args.cycles, args.precision, args.ball)
    label = f"{args.ball}, " + ("foam" if solver.model.foam is not None else args.precision)
    n_cells = solver.model.mesh.n_cells
    loop = kernel_loop(solver)
    for threads in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS), numba.get_num_threads()}):
        numba.set_num_threads(threads)
        times = seconds_per_call(loop, args.calls, args.repeats)
        median, best = statistics.median(times), min(times)
        print(f"{label}, IHQ {args.hourglass}, threads {threads}: {n_cells} hexes, "
              f"{median * 1e3:.3f} ms per call (median of {args.repeats} x {args.calls} calls): "
              f"{n_cells / median / 1e6:.2f} M element-cycles/s "
              f"(best {n_cells / best / 1e6:.2f})")  # fmt: skip


if __name__ == "__main__":
    main()
