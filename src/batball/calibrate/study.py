"""The calibration problem: candidate parameters -> balls -> impact runs -> weighted residuals.

:class:`Evaluator` runs batches of :class:`~batball.calibrate.evaluate.RunRequest` on an
executor, in parallel, reading finished runs from the study store and writing each new one the
moment it completes. :class:`CalibrationProblem` turns points of the unit box into those
requests and their outcomes into residual vectors.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from concurrent.futures import Executor, as_completed
from dataclasses import dataclass
from typing import Any

import numpy as np

from batball.calibrate.evaluate import COMPRESSION_DIVISIONS, RunRequest, run_request
from batball.calibrate.parameters import ParameterSpace
from batball.calibrate.store import StudyStore
from batball.calibrate.targets import Target
from batball.errors import SpecError
from batball.specs import BallSpec, MaterialSpec

#: Residual (in units of a target's goal) given to every target of an infeasible candidate:
#: one whose parameters break a cross-field rule (G_inf > G0) or whose ball never rebounds.
INFEASIBLE_RESIDUAL = 100.0


class Evaluator:
    """Runs requests on ``executor``, reusing and filling ``store``.

    Attributes:
        computed: runs computed by this evaluator (not read from the store).
    """

    def __init__(self, store: StudyStore, executor: Executor, *, progress: bool = False) -> None:
        self.store = store
        self.executor = executor
        self.progress = progress
        self.computed = 0

    def run(self, requests: Sequence[RunRequest], *, label: str = "") -> list[dict[str, Any]]:
        """The outcome of each request (see :func:`run_request`), in order."""
        outcomes: dict[str, dict[str, Any]] = {}
        missing: dict[str, RunRequest] = {}
        for request in requests:
            key = request.key
            stored = outcomes.get(key) or self.store.get(key)
            if stored is not None:
                outcomes[key] = stored
            else:
                missing[key] = request
        if missing:
            outcomes.update(self._claim_and_compute(missing, label=label))
        return [outcomes[request.key] for request in requests]

    def _claim_and_compute(self, missing: dict[str, RunRequest], *,
                           label: str) -> dict[str, dict[str, Any]]:  # fmt: skip
        """Compute the runs this process can claim; wait for the ones another process on the same
        study is computing and read them back (computing any it died before storing)."""
        claims = {key: self.store.claim(key) for key in missing}
        mine = {key: missing[key] for key, lock in claims.items() if lock is not None}
        try:
            done = self._compute(mine, label=label) if mine else {}
        finally:
            for lock in claims.values():
                if lock is not None:
                    lock.close()
        for key in missing.keys() - mine.keys():
            lock = self.store.claim(key, wait=True)  # the other process has stored it, or died
            try:
                stored = self.store.get(key)
                done[key] = stored if stored is not None else self._compute(
                    {key: missing[key]}, label=label)[key]
            finally:
                if lock is not None:
                    lock.close()
        return done

    def _compute(self, missing: dict[str, RunRequest], *, label: str) -> dict[str, dict[str, Any]]:
        """Submit every missing run; store each outcome as it arrives."""
        from tqdm import tqdm

        futures = {self.executor.submit(run_request, r): key for key, r in missing.items()}
        done = {}
        bar = tqdm(total=len(futures), desc=label or "runs", disable=not self.progress, leave=False)
        with bar:
            for future in as_completed(futures):
                key = futures[future]
                outcome = future.result()
                self.store.put(key, missing[key].inputs(), outcome)
                self.computed += 1
                done[key] = outcome
                bar.update()
        return done


@dataclass(frozen=True)
class Evaluation:
    """A candidate and what the virtual lab measured for it.

    Attributes:
        values: all parameter values (SI); simulated: (n_targets,) simulated values (NaN where
            infeasible); residuals: (n_targets,) weighted goal-normalised errors.
    """

    values: dict[str, float]
    simulated: np.ndarray
    residuals: np.ndarray

    @property
    def cost(self) -> float:
        """Half the sum of squared residuals (``scipy.optimize.least_squares``'s cost)."""
        return 0.5 * float(self.residuals @ self.residuals)


@dataclass(frozen=True)
class CalibrationProblem:
    """Fit ``space``'s free parameters of ``ball`` to ``targets`` on a mesh of ``divisions``."""

    ball: BallSpec
    space: ParameterSpace
    targets: tuple[Target, ...]
    divisions: int

    def candidate(self, values: dict[str, float]) -> BallSpec | None:
        """The ball with ``values``, or None if they break the law's cross-field rules."""
        try:
            material = MaterialSpec(
                law=self.space.law.name, values=values, curves=self.ball.material.curves
            )
        except SpecError:
            return None
        return dataclasses.replace(self.ball, material=material)

    def runs(self) -> list[tuple[str, float]]:
        """The distinct (test, speed) runs the targets need (one compression run at most)."""
        return sorted({(t.spec.test, t.speed) for t in self.targets})

    def run_divisions(self, test: str) -> int:
        """The ball mesh of a ``test`` run: ``divisions``, but at most
        :data:`~batball.calibrate.evaluate.COMPRESSION_DIVISIONS` for compression (its runs
        take some 10^5 steps; the same compression run serves the coarse and the fine stage)."""
        if test == "compression":
            return min(self.divisions, COMPRESSION_DIVISIONS)
        return self.divisions

    def evaluate(
        self, points: np.ndarray, evaluator: Evaluator, *, label: str = ""
    ) -> list[Evaluation]:
        """Evaluations of unit-box ``points`` (n_points, n_free), all runs in one parallel batch."""
        values = [self.space.values(u) for u in np.atleast_2d(points)]
        return self.evaluate_values(values, evaluator, label=label)

    def evaluate_values(
        self, candidates: Sequence[dict[str, float]], evaluator: Evaluator, *, label: str = ""
    ) -> list[Evaluation]:
        """Evaluations of parameter sets ``candidates`` (SI), all runs in one parallel batch."""
        balls = [self.candidate(values) for values in candidates]
        requests = [
            RunRequest(ball, test, speed, self.run_divisions(test))
            for ball in balls
            if ball is not None
            for test, speed in self.runs()
        ]
        outcomes = iter(evaluator.run(requests, label=label))
        return [
            self._score(dict(values), ball, outcomes)
            for values, ball in zip(candidates, balls, strict=True)
        ]

    def _score(self, values: dict[str, float], ball: BallSpec | None, outcomes: Any) -> Evaluation:
        """Residuals of one candidate from its runs' outcomes (consumed from ``outcomes``)."""
        n = len(self.targets)
        if ball is None:
            return Evaluation(values, np.full(n, np.nan), np.full(n, INFEASIBLE_RESIDUAL))
        by_run = {run: next(outcomes) for run in self.runs()}
        simulated = np.full(n, np.nan)
        for i, target in enumerate(self.targets):
            outcome = by_run[(target.spec.test, target.speed)]
            if "measures" in outcome:
                simulated[i] = float(outcome["measures"][target.spec.attribute])
        residuals = np.array(
            [
                INFEASIBLE_RESIDUAL if np.isnan(s) else t.residual(s)
                for t, s in zip(self.targets, simulated, strict=True)
            ]
        )
        return Evaluation(values, simulated, residuals)
