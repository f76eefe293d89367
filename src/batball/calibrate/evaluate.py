"""One evaluation = one virtual test run of a candidate ball, keyed by the hash of its inputs.

A :class:`RunRequest` is everything that decides a run's outcome (the ball, the test, the speed,
the mesh); :func:`run_request` runs it with :func:`batball.lab.impact.run_impact` (or, for the
ASTM F1888 compression test, :func:`batball.lab.compression.run_compression`) and returns plain
data, so that it can travel to a process-pool or Dask worker and into the study store.

Compression in a calibration (docs/calibration.md, "Compression targets"): one run per candidate
ball, on at most :data:`COMPRESSION_DIVISIONS` divisions and at the solver loading rate
:data:`COMPRESSION_RATIO`, read as the power-law value at 0.25 in. Those are the coarsest
settings whose number means something (docs/notes/compression.md): 6 divisions reads 25 % low, the
8- and 10-division power-law values agree within 1.2 %, and ratio 30 moves the force by 0.9 %
against the default 60 at half the steps.
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

#: Finest ball mesh of a compression run in a calibration (a type-1 run on the 12-division mesh
#: costs 2 min on the idle machine, 6-30 min on the loaded one; 8 divisions is the coarsest that
#: reads within about 5 % of it, docs/notes/compression.md).
COMPRESSION_DIVISIONS = 8
#: Solver loading rate of a compression run in a calibration (the test's own default is 60).
COMPRESSION_RATIO = 30.0


@dataclass(frozen=True)
class RunRequest:
    """The inputs of one run (an impact or a compression test).

    Attributes:
        ball: the candidate ball; test: ``"ccor"``, ``"cor"`` or ``"compression"``;
        speed: inbound [m/s] (0 for compression); divisions: ball mesh size
        (:func:`batball.mesh.make_ball_mesh`).
    """

    ball: BallSpec
    test: str
    speed: float
    divisions: int

    def inputs(self) -> dict[str, Any]:
        """The inputs as JSON-able data, floats written exactly (hex)."""
        inputs: dict[str, Any] = {
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
        if self.ball.hourglass is not None:  # the balls without one keep their keys
            inputs["hourglass"] = [self.ball.hourglass.type,
                                   float(self.ball.hourglass.coefficient).hex()]  # fmt: skip
        if self.test == "compression":  # the impact runs' keys stay as they were
            inputs["quasi_static_ratio"] = float(COMPRESSION_RATIO).hex()
        return inputs

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
    from batball.lab.impact import run_impact
    from batball.lab.registry import LAB_TESTS
    from batball.units import unit_registry

    start = time.perf_counter()
    try:
        if request.test == "compression":
            measures = compression_measures(request.ball, request.divisions)
        else:
            speed = unit_registry().Quantity(request.speed, "m/s")
            setup = LAB_TESTS[request.test].setup(speed=speed, divisions=request.divisions)
            measures = asdict(run_impact(request.ball, setup).measures)
    except (SimulationError, SpecError, FloatingPointError) as exc:
        return {"error": str(exc), "seconds": time.perf_counter() - start}
    return {"measures": measures, "seconds": time.perf_counter() - start}


def compression_measures(ball: BallSpec, divisions: int) -> dict[str, float]:
    """The ASTM F1888 compression test of ``ball`` at the calibration's settings, SI.

    ``compression_fit``: the power law F = C d^(3/2) fitted over 0.15-0.25 in, at 0.25 in [N]
    (the calibration's reading: the single reading at 0.25 in steps by up to 5 % as rings of
    surface nodes reach the plates, noise a least-squares fit should not chase);
    ``compression``: that single reading [N]; the quasi-static checks beside them.
    """
    from batball.lab.compression import run_compression
    from batball.lab.registry import LAB_TESTS

    setup = LAB_TESTS["compression"].setup(divisions=divisions,
                                           quasi_static_ratio=COMPRESSION_RATIO)  # fmt: skip
    result = run_compression(ball, setup)
    return {
        "compression_fit": result.compression_fit,
        "compression": result.compression,
        "kinetic_to_internal": result.kinetic_to_internal,
        "plate_force_difference": float(abs(result.force_difference[-1])),
        "penetration": result.penetration,
    }


def limit_threads(threads: int) -> None:
    """Worker initialiser: use ``threads`` Numba threads (the machine is shared by the pool)."""
    import numba
    from numba.np.ufunc.parallel import get_thread_count

    numba.set_num_threads(max(1, min(threads, get_thread_count())))
