"""One evaluation = one virtual impact run of a candidate ball, keyed by the hash of its inputs.

A :class:`RunRequest` is everything that decides a run's outcome (the ball, the test, the speed,
the mesh); :func:`run_request` runs it with :func:`batball.lab.impact.run_impact` and returns
plain data, so that it can travel to a process-pool or Dask worker and into the study store.
"""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import asdict, dataclass
from typing import Any

from batball.errors import SimulationError, SpecError
from batball.specs import BallSpec

#: Bump when a change to the solver or the measures changes the outcome of the same inputs, so
#: that a study file does not mix outcomes of two code versions.
EVALUATION_VERSION = 1


@dataclass(frozen=True)
class RunRequest:
    """The inputs of one impact run.

    Attributes:
        ball: the candidate ball; test: ``"ccor"`` or ``"cor"``; speed: inbound [m/s];
        divisions: ball mesh size (:func:`batball.mesh.make_ball_mesh`).
    """

    ball: BallSpec
    test: str
    speed: float
    divisions: int

    def inputs(self) -> dict[str, Any]:
        """The inputs as JSON-able data, floats written exactly (hex)."""
        return {
            "version": EVALUATION_VERSION,
            "test": self.test,
            "speed": float(self.speed).hex(),
            "divisions": self.divisions,
            "circumference": float(self.ball.circumference).hex(),
            "mass": float(self.ball.mass).hex(),
            "law": self.ball.material.law,
            "values": {k: float(v).hex() for k, v in self.ball.material.values.items()},
            **({"curves": _curves_inputs(self.ball)} if self.ball.material.curves else {}),
        }

    @property
    def key(self) -> str:
        """SHA-256 of :meth:`inputs` (the ball's name and description do not count)."""
        text = json.dumps(self.inputs(), sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()


def _curves_inputs(ball: BallSpec) -> list[dict[str, Any]]:
    """A foam ball's loading curves as exact (hex) floats, for the run key."""
    return [
        {
            "strain_rate": float(c.strain_rate).hex(),
            "strain": [float(x).hex() for x in c.strain],
            "stress": [float(x).hex() for x in c.stress],
        }
        for c in ball.material.curves
    ]


def run_request(request: RunRequest) -> dict[str, Any]:
    """Run one request; ``{"measures": {...SI...}, "seconds": wall}`` or ``{"error": text}``.

    A ball that never rebounds or a solver failure is an outcome (the candidate is infeasible),
    not an exception, so that it is stored like any other and never run again.
    """
    from batball.lab.impact import ImpactSetup, run_impact

    start = time.perf_counter()
    setup = ImpactSetup(test=request.test, speed=request.speed, divisions=request.divisions)
    try:
        result = run_impact(request.ball, setup)
    except (SimulationError, SpecError, FloatingPointError) as exc:
        return {"error": str(exc), "seconds": time.perf_counter() - start}
    return {"measures": asdict(result.measures), "seconds": time.perf_counter() - start}


def limit_threads(threads: int) -> None:
    """Worker initialiser: use ``threads`` Numba threads (the machine is shared by the pool)."""
    import numba
    from numba.np.ufunc.parallel import get_thread_count

    numba.set_num_threads(max(1, min(threads, get_thread_count())))
