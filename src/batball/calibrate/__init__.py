"""Calibration of ball material models against measured impact data.

Targets (measured CCOR, DS, peak force, contact time at given speeds) -> free parameters of a
material law -> virtual impact runs in parallel, stored in a resumable SQLite study -> a
Latin-hypercube plus least-squares fit, coarse mesh first. See ``docs/calibration.md``.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
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

#: Where each public name lives. The names are imported when first asked for (PEP 562), not
#: with the package: the command line builds its parser from ``batball.calibrate.command``,
#: whose package would otherwise import the optimiser and SciPy's (about 0.4 s) for every
#: command, calibration or not.
_SOURCES = {
    "RunRequest": "evaluate", "run_request": "evaluate", "open_executor": "executors",
    "CalibrationResult": "optimise", "OptimiserOptions": "optimise", "StageResult": "optimise",
    "calibrate": "optimise", "predict": "optimise", "FreeParameter": "parameters",
    "ParameterSpace": "parameters", "make_parameter_space": "parameters",
    "parse_bounds": "parameters", "StudyStore": "store", "CalibrationProblem": "study",
    "Evaluation": "study", "Evaluator": "study", "QUANTITIES": "targets", "Target": "targets",
    "load_targets": "targets", "seed_targets": "targets",
}  # fmt: skip


def __getattr__(name: str) -> Any:
    """A public name, imported from its module on first use."""
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_SOURCES[name]}"), name)
    globals()[name] = value
    return value


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
