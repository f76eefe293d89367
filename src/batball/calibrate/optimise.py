"""The optimiser: a Latin-hypercube global stage, then bounded least squares, coarse mesh first.

1. **Global**: the starting point and ``global_points`` Latin-hypercube points of the unit box
   (fixed seed), evaluated as one parallel batch on the coarse mesh; the best one starts stage 2.
   The residuals of an impact run are smooth in the material constants but the box spans two
   decades per parameter, where a local method alone can stall on a poor basin.
2. **Local, coarse mesh**: ``scipy.optimize.least_squares`` (trust-region reflective, bounds =
   the unit box) on the goal-normalised residuals. Its Jacobian is a forward difference with a
   step of ``diff_step`` of the box (FE outputs carry noise from the discrete time steps and
   contact events, so the step is large), all n_free perturbed runs in one parallel batch.
3. **Local, fine mesh**: the same from stage 2's answer on the full mesh, few evaluations: the
   coarse mesh is a few per cent off in DS and CCOR, which only shifts the optimum a little.

Every stage is deterministic given the outcomes of its runs, so a restarted study (whose runs
come back from the store) retraces the same path to the same answer.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from batball.calibrate.study import CalibrationProblem, Evaluation, Evaluator


@dataclass(frozen=True)
class OptimiserOptions:
    """Options of :func:`calibrate`.

    Attributes:
        global_points: Latin-hypercube points of stage 1 (0: skip it).
        seed: seed of the Latin hypercube.
        coarse_divisions: ball mesh of stages 1 and 2.
        coarse_evaluations: most residual evaluations (``max_nfev``) of stage 2.
        fine_divisions: ball mesh of stage 3, None to skip it.
        fine_evaluations: most residual evaluations of stage 3.
        diff_step: forward-difference step, in unit-box lengths.
    """

    global_points: int = 12
    seed: int = 2024
    coarse_divisions: int = 8
    coarse_evaluations: int = 25
    fine_divisions: int | None = 12
    fine_evaluations: int = 6
    diff_step: float = 0.02

    def __post_init__(self) -> None:
        from batball.errors import SpecError

        if self.global_points < 0:
            raise SpecError("global-points", self.global_points, "an integer >= 0 (0 skips it)")
        for name in ("coarse_evaluations", "fine_evaluations"):
            if getattr(self, name) < 1:
                raise SpecError(name.replace("_", "-"), getattr(self, name), "an integer >= 1")
        for name in ("coarse_divisions", "fine_divisions"):
            value = getattr(self, name)
            if value is not None and not 2 <= value <= 40:
                raise SpecError(name.replace("_", "-"), value, "an integer 2..40 (12 = seed mesh)")
        if not 0.0 < self.diff_step < 1.0:
            raise SpecError("diff-step", self.diff_step, "a step 0 < h < 1 of the unit box")


@dataclass(frozen=True)
class StageResult:
    """The best evaluation of one stage and how many candidates it evaluated."""

    name: str
    divisions: int
    best: Evaluation
    n_candidates: int


@dataclass(frozen=True)
class CalibrationResult:
    """The fitted candidate (on the last stage's mesh) and the stages that led to it."""

    problem: CalibrationProblem
    best: Evaluation
    stages: tuple[StageResult, ...]


class _Memo:
    """Evaluations of one problem keyed by their unit-box point (least_squares asks twice)."""

    def __init__(self, problem: CalibrationProblem, evaluator: Evaluator, label: str) -> None:
        self.problem, self.evaluator, self.label = problem, evaluator, label
        self.seen: dict[tuple[float, ...], Evaluation] = {}

    def batch(self, points: np.ndarray) -> list[Evaluation]:
        """Evaluations of ``points`` (n, n_free), the new ones in one parallel batch."""
        keys = [tuple(float(x) for x in u) for u in points]
        new = [k for k in dict.fromkeys(keys) if k not in self.seen]
        if new:
            found = self.problem.evaluate(np.array(new), self.evaluator, label=self.label)
            self.seen.update(zip(new, found, strict=True))
        return [self.seen[k] for k in keys]

    def best(self) -> Evaluation:
        """The lowest-cost evaluation so far."""
        return min(self.seen.values(), key=lambda e: e.cost)


def global_stage(
    problem: CalibrationProblem, evaluator: Evaluator, options: OptimiserOptions
) -> tuple[np.ndarray, StageResult]:
    """Stage 1: the best of the start and a Latin hypercube; its unit-box point and summary."""
    start = problem.space.start_point()
    memo = _Memo(problem, evaluator, "global")
    points = [start]
    if options.global_points > 0:
        from scipy.stats import qmc  # imported here: scipy.stats takes 0.3 s to import

        sampler = qmc.LatinHypercube(d=start.size, seed=options.seed)
        points.extend(sampler.random(options.global_points))
    found = memo.batch(np.array(points))
    best = int(np.argmin([e.cost for e in found]))
    summary = StageResult("global", problem.divisions, found[best], len(memo.seen))
    return np.array(points[best]), summary


def local_stage(
    problem: CalibrationProblem,
    evaluator: Evaluator,
    start: np.ndarray,
    *,
    max_evaluations: int,
    diff_step: float,
    name: str,
) -> tuple[np.ndarray, StageResult]:
    """Bounded least squares from ``start``; the best point seen and the stage summary."""
    memo = _Memo(problem, evaluator, name)

    def residuals(u: np.ndarray) -> np.ndarray:
        return memo.batch(u[None, :])[0].residuals

    def jacobian(u: np.ndarray) -> np.ndarray:
        steps = np.where(u + diff_step <= 1.0, diff_step, -diff_step)
        points = np.vstack([u, u + np.diag(steps)])
        found = memo.batch(points)
        return np.column_stack(
            [(e.residuals - found[0].residuals) / h for e, h in zip(found[1:], steps, strict=True)]
        )

    least_squares(
        residuals,
        np.clip(start, 0.0, 1.0),
        jac=jacobian,
        bounds=(0.0, 1.0),
        method="trf",
        max_nfev=max_evaluations,
        x_scale=1.0,
        xtol=1e-3,
        ftol=1e-4,
    )
    best = memo.best()
    return _point_of(problem, best), StageResult(name, problem.divisions, best, len(memo.seen))


def _point_of(problem: CalibrationProblem, evaluation: Evaluation) -> np.ndarray:
    """The unit-box point of an evaluation's values."""
    return np.array([p.to_unit(evaluation.values[p.name]) for p in problem.space.free])


def calibrate(
    problem: CalibrationProblem, evaluator: Evaluator, options: OptimiserOptions
) -> CalibrationResult:
    """Fit ``problem`` in the three stages of this module (its ``divisions`` are replaced by
    the options' coarse and fine meshes)."""
    coarse = dataclasses.replace(problem, divisions=options.coarse_divisions)
    point, first = global_stage(coarse, evaluator, options)
    point, second = local_stage(
        coarse, evaluator, point, max_evaluations=options.coarse_evaluations,
        diff_step=options.diff_step, name="local (coarse)",
    )  # fmt: skip
    stages = [first, second]
    last = coarse
    if options.fine_divisions is not None and options.fine_evaluations > 0:
        last = dataclasses.replace(problem, divisions=options.fine_divisions)
        point, third = local_stage(
            last, evaluator, point, max_evaluations=options.fine_evaluations,
            diff_step=options.diff_step, name="local (fine)",
        )  # fmt: skip
        stages.append(third)
    return CalibrationResult(problem=last, best=stages[-1].best, stages=tuple(stages))


def predict(
    problem: CalibrationProblem, evaluator: Evaluator, values: dict[str, float]
) -> Evaluation:
    """``problem``'s targets evaluated at fixed ``values`` (cross-validation, reports)."""
    return problem.evaluate_values([values], evaluator, label="predict")[0]
