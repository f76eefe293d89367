"""Cost of the coupled ball-bat cycle at a given mesh size, measured over a fixed number of cycles.

Builds the batted-ball-speed model (ball fired at the pivoting bat), skips the pre-stress, runs
``--cycles`` cycles from the start (the ball in flight then in contact) and prints the stable
step, the seconds per cycle by phase and the element-cycles per second, plus the projection of a
whole run: the cycles a run needs (the pre-stress's, lab.bbs.relaxation_cycles, + the impact's
simulated time over the step) times the measured cost (a pre-stress cycle, bat only, is counted
as a whole cycle: an upper bound). ``--mass-scaling off`` measures without selective mass
scaling; ``--shell`` picks the bat's shell element (default the co-rotational MITC4 of the
batted-ball-speed test, ``bt`` the Belytschko-Tsay shells). The machine's SGEMM GFLOP/s on
the Numba thread count, measured in the same run (``yardstick.py``), gives the element-cycles
per second per GFLOP/s, comparable between hosts; with the flops the element kernels do per
element-cycle (counted from the code, ``flop_counts.py``), the shells' and the hexes' GFLOP/s
(each over its own phase's time) and the cycle's, as fractions of the yardstick.
Usage:

    NUMBA_NUM_THREADS=1 PYTHONPATH=src python benchmarks/bench_bbs_cycles.py \
        --ball-divisions 12 --circumferential 48 --axial-size-in 0.1 --cycles 300
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from batball.elements.shell_corotational import SHELLS
from batball.lab.bbs import coupled_controls
from batball.models.bbs import BbsSetup, build_bbs_model, relaxation_cycles
from batball.solvers.ball_bat import HISTORY_COLUMNS, CoupledSolver
from batball.specs import load_ball_spec, load_bat_spec
from batball.units import IN


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ball-divisions", type=int, default=12)
    parser.add_argument("--circumferential", type=int, default=48)
    parser.add_argument("--axial-size-in", type=float, default=0.1)
    parser.add_argument("--cycles", type=int, default=300)
    parser.add_argument("--mass-scaling", choices=("barrel", "off"), default="barrel")
    parser.add_argument(
        "--shell",
        choices=SHELLS,
        default="mitc4",
        help="the bat's shell element (mitc4: the model of record's)",
    )
    parser.add_argument(
        "--simulated-ms",
        type=float,
        default=1.25,
        help="impact run length to project to (1.25 ms: contact + 0.2 ms)",
    )
    args = parser.parse_args()
    setup = BbsSetup(ball_divisions=args.ball_divisions, circumferential=args.circumferential,
                     axial_size=args.axial_size_in * IN, gap=0.0,
                     mass_scaling=None if args.mass_scaling == "off" else "barrel",
                     bat_shell=args.shell)  # fmt: skip
    start = time.perf_counter()
    model = build_bbs_model(load_bat_spec("default"), load_ball_spec("type1"), setup)
    build = time.perf_counter() - start
    solver = CoupledSolver(model.coupled, coupled_controls(setup))  # as a BBS run's
    row = np.zeros(len(HISTORY_COLUMNS))
    for _ in range(5):  # compile / warm up
        solver.cycle(row)
    solver.phase_seconds = dict.fromkeys(solver.phase_seconds, 0.0)
    start = time.perf_counter()
    for _ in range(args.cycles):
        solver.cycle(row)
    seconds = (time.perf_counter() - start) / args.cycles
    n_shells, n_hexes = model.bat_mesh.n_cells, model.ball_cells.shape[0]
    import numba
    from flop_counts import bt_default_bat_mean_flops, hex8_flops, mitc4_flops
    from yardstick import cpu_description, gemm_gflops, yardstick_label

    sgemm = gemm_gflops(numba.get_num_threads())["sgemm"]
    cycles = sum(relaxation_cycles(setup, solver.dt)) + args.simulated_ms * 1e-3 / solver.dt
    phases = {k: v / args.cycles for k, v in solver.phase_seconds.items()}
    shell_flops = (mitc4_flops(model.bat_mesh.n_points / n_shells) if args.shell == "mitc4"
                   else bt_default_bat_mean_flops())  # fmt: skip
    hex_flops = hex8_flops(single=setup.precision == "single")
    gflops = {
        "bat_shells": n_shells * shell_flops / phases["bat_forces"] / 1e9,
        "ball_hexes": n_hexes * hex_flops / phases["ball_forces"] / 1e9,
        "cycle": (n_shells * shell_flops + n_hexes * hex_flops) / seconds / 1e9,
    }
    print(json.dumps({
        "bat_shell": args.shell, "n_shells": n_shells, "n_hexes": n_hexes,
        "stable_step_s": solver.dt, "ball_precision": setup.precision,
        "added_mass_g": float(model.added_mass.sum() * 1e3),
        "build_seconds": build, "seconds_per_cycle": seconds,
        "phase_seconds_per_cycle": phases,
        "element_cycles_per_second": (n_shells + n_hexes) / seconds,
        "cpu": cpu_description(), "threads": numba.get_num_threads(),
        "sgemm_gflops": sgemm, "yardstick": yardstick_label(),
        "element_cycles_per_second_per_sgemm_gflops": (n_shells + n_hexes) / seconds / sgemm,
        "flops_per_element_cycle": {"bat_shell": shell_flops, "ball_hex": hex_flops},
        "gflops": gflops, "fraction_of_sgemm": {k: v / sgemm for k, v in gflops.items()},
        "projected_cycles": cycles, "projected_run_seconds": cycles * seconds,
    }, indent=2))  # fmt: skip


if __name__ == "__main__":
    main()
