"""Calibration of ball material models against measured impact data.

Targets (measured CCOR, DS, peak force, contact time at given speeds) -> free parameters of a
material law -> virtual impact runs in parallel, stored in a resumable SQLite study -> a
Latin-hypercube plus least-squares fit, coarse mesh first. See ``docs/calibration.md``.
"""

from __future__ import annotations

from batball.calibrate.evaluate import RunRequest, run_request
from batball.calibrate.executors import open_executor
from batball.calibrate.optimise import (
    CalibrationResult,
    OptimiserOptions,
    StageResult,
    calibrate,
    predict,
)
from batball.calibrate.parameters import (
    FreeParameter,
    ParameterSpace,
    make_parameter_space,
    parse_bounds,
)
from batball.calibrate.store import StudyStore
from batball.calibrate.study import CalibrationProblem, Evaluation, Evaluator
from batball.calibrate.targets import QUANTITIES, Target, load_targets, seed_targets

__all__ = [
    "QUANTITIES",
    "CalibrationProblem",
    "CalibrationResult",
    "Evaluation",
    "Evaluator",
    "FreeParameter",
    "OptimiserOptions",
    "ParameterSpace",
    "RunRequest",
    "StageResult",
    "StudyStore",
    "Target",
    "calibrate",
    "load_targets",
    "make_parameter_space",
    "open_executor",
    "parse_bounds",
    "predict",
    "run_request",
    "seed_targets",
]
