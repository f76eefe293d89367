"""A kernel loaded from Numba's on-disk cache gives the bits of the process that compiled it.

Numba links a copy of every non-inlined callee (a helper, a parallel loop's body) into each
cached kernel and optimises it again there. A process that compiles the kernel calls the callee's
first copy; a process that loads the kernel from the cache runs the kernel's own copy. With
fast-math reassociation the two copies rounded differently (docs/notes/precision.md, "Same input,
same bits, compiled or cached"): the fast-math flags (``batball.numerics.FASTMATH``) now leave
``reassoc`` out, so that a second optimisation may not regroup a sum.

The check: the BT shell kernels (a serial one whose element helpers are linked copies, and the
parallel one whose loop body is a gufunc) stepped three times on the same random input in a
process that compiles them into an empty cache folder, then in one that loads them from it, and
likewise the co-rotational MITC4 kernel (a parallel loop calling the non-inlined chunk kernel,
which adds into the nodes) on the bat's coarse mesh: its nodal forces and rotations. The two
processes must give the same bits. Before the change they did not for the BT kernels (measured
on this script's input: the nodal forces' hashes differed in both, by up to 2.8e-14 N of 413 N).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).parent

SCRIPT = f"""
import hashlib, json, sys
import numpy as np
sys.path.insert(0, {str(HERE)!r})
import test_shell_bt_kernel as T
from batball.elements.shell_bt import bt_force_kernel, bt_nodal_force_kernel
from batball.elements.shell_corotational import CorotationalShellForces, cell_and_node_forces
from batball.elements.shell_stiffness import shell_section
from batball.mesh.bat import make_bat_mesh
from batball.models.bat import bat_laminates
from batball.specs import load_bat_spec

def digest(a):
    return hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()

rng = np.random.default_rng(7)
points, cells, section = T.curved_mesh(rng)
state = T.random_state(rng, section)
velocities = [rng.normal(0.0, 1.0, (points.shape[0], 6)) for _ in range(3)]
cell_forces, cell_state = T.run(bt_force_kernel, points, cells, section, velocities, 1e-7, state)
nodal, nodal_state = T.run(bt_nodal_force_kernel, points, cells, section, velocities, 1e-7, state,
                           (points.shape[0], 6))
spec = load_bat_spec("default")
mesh = make_bat_mesh(spec, circumferential=8, axial_size=0.0254)
shells = CorotationalShellForces(mesh.points, mesh.cells,
                                 shell_section(*bat_laminates(spec, mesh)))
moved = mesh.points + rng.normal(0.0, 1e-5, mesh.points.shape)
mitc4 = np.zeros((mesh.n_points, 6))
for _ in range(3):
    shells(moved, rng.normal(0.0, 10.0, (mesh.n_points, 6)), 1e-7, mitc4)
kernels = (bt_force_kernel, bt_nodal_force_kernel, cell_and_node_forces)
print(json.dumps({{
    "bt_force_kernel": [digest(cell_forces)] + [digest(a) for a in cell_state],
    "bt_nodal_force_kernel": [digest(nodal)] + [digest(a) for a in nodal_state],
    "mitc4": [digest(mitc4), digest(shells.state.history)],
    "cache_hits": [sum(k.stats.cache_hits.values()) for k in kernels],
}}))
"""


def run_in_fresh_process(cache: Path) -> dict:
    """The script's output in a new interpreter with Numba's cache in ``cache``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    done = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True,
                          text=True, check=True, timeout=600)  # fmt: skip
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_a_cached_kernel_gives_the_bits_of_the_compiling_process(tmp_path: Path) -> None:
    compiled = run_in_fresh_process(tmp_path)
    cached = run_in_fresh_process(tmp_path)
    assert compiled["cache_hits"] == [0, 0, 0]  # the first process compiled the kernels
    assert cached["cache_hits"] == [1, 1, 1]  # the second loaded them from the cache
    for kernel in ("bt_force_kernel", "bt_nodal_force_kernel", "mitc4"):
        assert cached[kernel] == compiled[kernel], kernel
