"""The impact solver's compiled loop over cycles (``explicit_kernels.run_cycles``) takes the
element kernel as a first-class function of the kernel's signature and calls it through its
address. Typed on the kernel itself (a Numba dispatcher), the loop linked the kernel's code in,
optimised it again in every process (1.3-1.7 s at full size) and could not be loaded from
Numba's on-disk cache, whose key would hold the dispatcher object.

The check: the same small CCOR run in two new interpreters. The second must load the loop from
the cache (one hit, no miss), every signature the loop was compiled for must take a function
type, and both processes must give the same answer, to the bit.
"""

from __future__ import annotations

import json
import subprocess
import sys

SCRIPT = """
import json
from batball.lab.impact import ImpactSetup, run_impact
from batball.solvers import explicit_kernels as kern
from batball.specs import load_ball_spec
result = run_impact(load_ball_spec("type1"), ImpactSetup(test="ccor", speed=42.0, divisions=3))
loop = kern._cycles
print(json.dumps({
    "ccor": result.measures.restitution.hex(),
    "steps": result.run.n_steps,
    "hits": sum(loop.stats.cache_hits.values()),
    "misses": sum(loop.stats.cache_misses.values()),
    "kernel types": [type(signature[0]).__name__ for signature in loop.signatures],
}))
"""


def run_in_new_process() -> dict:
    """The script's output in a new interpreter (Numba's cache where the package keeps it)."""
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                          check=True, timeout=600)  # fmt: skip
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_the_cycle_loop_is_loaded_from_the_cache_by_a_later_process() -> None:
    first = run_in_new_process()  # compiles the loop, or loads it if a run before did
    later = run_in_new_process()
    assert later["hits"] == 1 and later["misses"] == 0
    assert first["kernel types"] == later["kernel types"] == ["FunctionType"]
    assert (later["ccor"], later["steps"]) == (first["ccor"], first["steps"])
