"""The explicit bat shells' force evaluation: co-rotational MITC4 against Belytschko-Tsay.

Builds the BBS test's bat (default spec, ``--circumferential`` x ``--axial-size-in`` shells),
and times, in one process and interleaved (so that a loaded machine slows both alike), calls of
the two shells' force objects as the explicit solvers make them: ``solvers.ball_bat.
ShellForces`` (the BT kernel, threaded) and ``elements.shell_corotational.
CorotationalShellForces`` (nodal rotations, deformations, K0 d, balance, scatter). The nodes
carry small random velocities and rotation rates (fixed seed), so both do their full work.
Prints the best of ``--repeats`` rounds of ``--calls`` calls each, in ms a call, and the ratio.
Usage:

    PYTHONPATH=src python benchmarks/bench_shell_kernels.py --circumferential 48 --axial-size-in 0.1
"""

from __future__ import annotations

import argparse
import json
import time

import numba as nb
import numpy as np

from batball.elements.shell_bt import initial_force_state
from batball.elements.shell_corotational import CorotationalShellForces
from batball.elements.shell_stiffness import shell_section
from batball.models.bat import bat_laminates
from batball.models.bbs import BbsSetup, bat_part
from batball.solvers.ball_bat import ShellForces
from batball.specs import load_bat_spec
from batball.units import IN


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--circumferential", type=int, default=48)
    parser.add_argument("--axial-size-in", type=float, default=0.1)
    parser.add_argument("--calls", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args()
    spec = load_bat_spec("default")
    setup = BbsSetup(circumferential=args.circumferential, axial_size=args.axial_size_in * IN)
    bat, mesh, _ = bat_part(spec, setup)
    shells = {
        "bt": ShellForces(bat, initial_force_state(bat.section)),
        "mitc4": CorotationalShellForces(mesh.points, mesh.cells,
                                         shell_section(*bat_laminates(spec, mesh))),
    }  # fmt: skip
    rng = np.random.default_rng(7)
    velocity = np.hstack([1e-3 * rng.standard_normal((mesh.n_points, 3)),
                          1e-1 * rng.standard_normal((mesh.n_points, 3))])  # fmt: skip
    points, out, dt = mesh.points.copy(), np.zeros((mesh.n_points, 6)), bat.stable_step
    best = dict.fromkeys(shells, np.inf)
    for forces in shells.values():
        forces(points, velocity, dt, out)  # compile and warm up
    for _ in range(args.repeats):
        for name, forces in shells.items():
            start = time.perf_counter()
            for _ in range(args.calls):
                forces(points, velocity, dt, out)
            best[name] = min(best[name], (time.perf_counter() - start) / args.calls)
    print(json.dumps({
        "shells": mesh.n_cells, "threads": nb.get_num_threads(),
        "bt_ms": 1e3 * best["bt"], "mitc4_ms": 1e3 * best["mitc4"],
        "mitc4_over_bt": best["mitc4"] / best["bt"],
    }, indent=1))  # fmt: skip


if __name__ == "__main__":
    main()
