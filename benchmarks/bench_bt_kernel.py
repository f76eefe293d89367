"""Cost of the layered Belytschko-Tsay shell kernel alone on the batted-ball-speed bat mesh.

Builds the BBS model's bat (default bat spec, ``--circumferential`` x ``--axial-size-in`` shells),
gives its nodes random velocities and rotation rates (fixed seed; small enough that nothing
distorts), and times ``--calls`` calls of ``shell_bt.bt_force_kernel`` (the stress state evolves
from call to call, the mesh stays put) after one warm-up call; prints the median and best
seconds per call and the microseconds per shell and cycle. The kernel's signature has not changed
across issue 9, so the same script times an older checkout (``PYTHONPATH=<that>/src``). Usage:

    NUMBA_NUM_THREADS=1 PYTHONPATH=src python benchmarks/bench_bt_kernel.py --calls 200
"""

from __future__ import annotations

import argparse
import json
import time

import numba as nb
import numpy as np

from batball.elements.shell_bt import HOURGLASS_RATIO, bt_force_kernel, initial_force_state
from batball.lab.bbs import IN
from batball.models.bbs import BbsSetup, build_bbs_model
from batball.specs import load_ball_spec, load_bat_spec


@nb.njit
def gather_cell_forces(cell_forces: np.ndarray, cells: np.ndarray, forces: np.ndarray) -> None:
    """forces[cells[c, a]] = sum of cell_forces[c, a] (serial: no race); (n_cells, k, m) into
    (n_points, >= m), the first m columns overwritten."""
    m = cell_forces.shape[2]
    forces[:, :m] = 0.0
    for c in range(cells.shape[0]):
        for a in range(cells.shape[1]):
            node = cells[c, a]
            for k in range(m):
                forces[node, k] += cell_forces[c, a, k]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--circumferential", type=int, default=48)
    parser.add_argument("--axial-size-in", type=float, default=0.1)
    parser.add_argument("--calls", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=5, help="timed runs of --calls calls")
    parser.add_argument("--fused", action="store_true", help="bt_nodal_force_kernel")
    args = parser.parse_args()
    setup = BbsSetup(ball_divisions=4, circumferential=args.circumferential,
                     axial_size=args.axial_size_in * IN, gap=0.0)  # fmt: skip
    model = build_bbs_model(load_bat_spec("default"), load_ball_spec("type1"), setup).coupled
    bat, section = model.bat, model.bat.section
    points = np.ascontiguousarray(model.points[: model.n_bat])
    rng = np.random.default_rng(1)
    velocity = rng.normal(0.0, 1.0, (points.shape[0], 6)) * [1.0, 1.0, 1.0, 20.0, 20.0, 20.0]
    state = initial_force_state(section)
    cell_forces = np.zeros((bat.cells.shape[0], 4, 6))
    forces = np.zeros((points.shape[0], 6))
    dt = 2e-7
    # the state arrays: the block layout since issue 9, element-wise before
    state_arrays = ((state.block_start, state.history) if hasattr(state, "history")
                    else (state.layer_stress, state.shear_force, state.hourglass))  # fmt: skip
    arguments = (points, bat.cells, velocity, dt, section.cell_laminate, section.layer_stiffness,
                 section.layer_z, section.layer_thickness, section.shear,
                 section.hourglass_moduli, HOURGLASS_RATIO, *state_arrays)  # fmt: skip

    def call() -> None:
        if args.fused:
            from batball.elements.shell_bt import bt_nodal_force_kernel

            bt_nodal_force_kernel(*arguments, forces)
        else:
            bt_force_kernel(*arguments, cell_forces)
            gather_cell_forces(cell_forces, bat.cells, forces)

    call()  # compile / load
    seconds = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        for _ in range(args.calls):
            call()
        seconds.append((time.perf_counter() - start) / args.calls)
    n_cells = bat.cells.shape[0]
    print(json.dumps({
        "n_shells": n_cells, "n_layers": section.layer_z.shape[1],
        "seconds_per_call": {"median": float(np.median(seconds)), "best": min(seconds)},
        "us_per_shell_cycle": {"median": 1e6 * float(np.median(seconds)) / n_cells,
                               "best": 1e6 * min(seconds) / n_cells},
        "checksum": float(np.abs(forces).sum()),
    }, indent=2))  # fmt: skip


if __name__ == "__main__":
    main()
