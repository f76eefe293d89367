"""Running a design study: sample the design space, evaluate every design with the virtual tests,
search locally from the best, rank, confirm the best on a finer mesh, and write the results.

Every evaluation is a run of the lab registry's tests (``props`` always; ``modal``, ``barrel``
and ``bbs`` as the study's responses need), stored in the results store under its inputs: a study
that is stopped and started again reuses every run it finished, so it resumes where it stopped.
Designs are evaluated in a local process pool (or on a Dask cluster); the local search is serial.

The outputs, in the study's folder: ``designs.csv`` (one row per evaluated design: its stage and
mesh, its parameters, its responses, each constraint's margin, whether it is feasible and on the
Pareto front of the objectives), ``best/<rank>-<design>.toml`` (the best feasible designs as bat
specs), and ``summary.json`` (the study, the best designs, each parameter's influence on each
response, wall times).
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import math
import time
import warnings
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from batball.design.rules import BALL_COR_SPEED, BallChoice, bpf_column
from batball.design.study import DesignParameter, DesignStudy, Mesh, response_unit
from batball.errors import SimulationError
from batball.specs.bat import BatSpec
from batball.units import MPH

#: The penalty per unit of relative constraint violation added to the local search's score.
VIOLATION_PENALTY = 1e3


@dataclass(frozen=True)
class DesignJob:
    """One design to evaluate: the bat (as its spec document, which pickles to a worker), the
    mesh, what to run and where the runs are stored."""

    bat: dict[str, Any]
    mesh: Mesh
    #: (name, sources, speeds m/s, prior names): one source for a ball given by its spec; a
    #: league ball's one per prior, named by ``prior names``.
    balls: tuple[tuple[str, tuple[str, ...], tuple[float, ...], tuple[str, ...]], ...]
    modal: bool
    barrel: bool
    runs_dir: Path
    reuse: bool = True


def _length(value_m: float) -> str:
    return f"{value_m!r} m"


def evaluate_design(job: DesignJob) -> dict[str, Any]:
    """The responses of one design (module docs; units in the names), or ``{"error": why}``
    when a test cannot measure it (a ball still on the bat at the end time, a solver that
    stopped): the study records the design as failed and goes on."""
    try:
        return design_responses(job)
    except SimulationError as exc:
        return {"error": str(exc)}


def design_responses(job: DesignJob) -> dict[str, float]:
    """The responses of one design; a :class:`SimulationError` where a test fails."""
    from batball.lab.registry import LAB_TESTS
    from batball.specs import load_ball_spec
    from batball.specs.bat import bat_spec_from_dict

    spec = bat_spec_from_dict(job.bat, source=f"design {job.bat['name']}")
    store = {"runs_dir": job.runs_dir, "reuse": job.reuse}
    mesh = {"circumferential": job.mesh.circumferential,
            "axial_size": _length(job.mesh.axial_size)}  # fmt: skip
    props = LAB_TESTS["props"]
    s, _ = props.execute({"bat": spec}, props.setup(**mesh), **store)
    out = {"weight_oz": s["weight_oz"], "balance_point_in": s["balance_point_in"],
           "moi_pivot_oz_in2": s["moi_pivot_oz_in2"]}  # fmt: skip
    if job.modal:
        modal = LAB_TESTS["modal"]
        s, _ = modal.execute({"bat": spec}, modal.setup(**mesh), **store)
        bending, hoop = list(s["bending_hz"]) + [math.nan] * 2, list(s["hoop_hz"]) + [math.nan] * 2
        out |= {"bending1_hz": bending[0], "bending2_hz": bending[1], "hoop1_hz": hoop[0],
                "hoop2_hz": hoop[1]}  # fmt: skip
    if job.barrel:
        barrel = LAB_TESTS["barrel"]
        s, _ = barrel.execute({"bat": spec}, barrel.setup(**mesh), **store)
        out |= {"barrel_preload_lbf": s["preload_lbf"],
                "barrel_final_load_lbf": s["final_load_lbf"]}  # fmt: skip
    bbs = LAB_TESTS["bbs"]
    from batball.design.rules import BallChoice

    for name, sources, speeds, priors in job.balls:
        balls = [load_ball_spec(source) for source in sources]
        choice = BallChoice(name, sources[0], speeds, stamp=(0.0, 0.0) if priors else None,
                            prior_names=priors)  # fmt: skip
        for speed in speeds:
            setup = bbs.setup(**mesh, divisions=job.mesh.ball_divisions, speed=f"{speed!r} m/s")
            runs = [bbs.execute({"bat": spec, "ball": ball}, setup, **store)[0] for ball in balls]
            bbs_col, bbcor_col, ea_col = choice.columns(speed)
            # a league ball: each prior's BBS, and the largest of each response over them
            out |= {bbs_col: max(s["bbs_mph"] for s in runs),
                    bbcor_col: max(s["bbcor"] for s in runs),
                    ea_col: max(s["collision_efficiency"] for s in runs)}  # fmt: skip
            if priors:
                *each, spread = choice.spread_columns(speed)
                out |= {col: s["bbs_mph"] for col, s in zip(each, runs, strict=True)}
                out[spread] = max(s["bbs_mph"] for s in runs) - min(s["bbs_mph"] for s in runs)
    return {k: float(v) for k, v in out.items()}


def ball_cor(source: str, divisions: int, runs_dir: Path, reuse: bool = True) -> float:
    """The ball's COR on the flat wall of ASTM F1887 at 60 mph, on ``divisions``."""
    from batball.lab.registry import LAB_TESTS
    from batball.specs import load_ball_spec

    cor = LAB_TESTS["cor"]
    setup = cor.setup(speed=f"{BALL_COR_SPEED!r} m/s", divisions=divisions)
    s, _ = cor.execute({"ball": load_ball_spec(source)}, setup, runs_dir=runs_dir, reuse=reuse)
    return float(s["cor"])


@dataclass
class Design:
    """One evaluated design: its id, stage, mesh, parameter values (SI) and responses."""

    id: str
    stage: str
    mesh: Mesh
    values: tuple[float, ...]
    responses: dict[str, float] = field(default_factory=dict)
    margins: dict[str, float] = field(default_factory=dict)
    error: str = ""
    #: The confirmation round that reran it (0: a screening design).
    round: int = 0

    @property
    def feasible(self) -> bool:
        """Evaluated, and every constraint's margin at least zero."""
        return not self.error and all(m >= 0.0 for m in self.margins.values())


@dataclass
class DesignResult:
    """A finished study: every design, the ranking, the influences, where the files are."""

    study: DesignStudy
    designs: list[Design]
    ranking: list[Design]
    pareto: set[str]
    influence: dict[str, dict[str, float]]
    ball_cor: dict[str, float]
    out_dir: Path
    seconds: float
    stage_seconds: dict[str, float]
    #: The league balls fitted to their stamps (one row per ball mesh and prior).
    league_balls: list[dict[str, Any]] = field(default_factory=list)


def design_id(values: Sequence[float]) -> str:
    """A short stable name of a point of the design space (its values to 1e-9 relative)."""
    text = ",".join(f"{v:.9e}" for v in values)
    return "d" + hashlib.sha256(text.encode()).hexdigest()[:8]


def sample_unit(study: DesignStudy) -> np.ndarray:
    """``study.designs`` points of the unit cube, (n, d): scrambled Sobol or Latin hypercube."""
    from scipy.stats import qmc

    d = len(study.parameters)
    sampler = (qmc.Sobol(d, scramble=True, seed=study.seed) if study.method == "sobol"
               else qmc.LatinHypercube(d, seed=study.seed))  # fmt: skip
    with warnings.catch_warnings():  # Sobol's balance note for a count that is not 2^m
        warnings.simplefilter("ignore", UserWarning)
        return np.asarray(sampler.random(study.designs))


def design_spec(base: BatSpec, parameters: Sequence[DesignParameter],
                values: Sequence[float], name: str) -> BatSpec:  # fmt: skip
    """The base bat with each parameter set to its value, named ``name``."""
    import dataclasses

    spec = base
    for parameter, value in zip(parameters, values, strict=True):
        spec = parameter.apply(spec, float(value))
    return dataclasses.replace(spec, name=name)


class _Evaluator:
    """Evaluates designs of one study (batches through an executor), keeping them in order."""

    def __init__(self, study: DesignStudy, base: BatSpec, runs_dir: Path, reuse: bool,
                 executor: Executor, cors: dict[str, float],
                 progress: Callable[[int], None] | None, workers: int | None = 0,
                 log: Callable[[str], None] | None = None) -> None:  # fmt: skip
        self.study, self.base, self.runs_dir, self.reuse = study, base, runs_dir, reuse
        self.executor, self.cors, self.progress = executor, cors, progress
        self.workers, self.log = workers, log or (lambda _text: None)
        self.designs: list[Design] = []
        #: The league balls fitted per ball mesh: {divisions: {ball name: [LeagueBall]}}.
        self.league: dict[int, dict[str, list[Any]]] = {}

    def league_balls(self, divisions: int) -> dict[str, list[Any]]:
        """Each league ball of the study fitted to its stamp on ``divisions`` (once per mesh;
        stored in the runs folder, so a study started again resumes the fits)."""
        if divisions not in self.league:
            self.league[divisions] = {
                b.name: fit_study_league_ball(b, divisions, self.runs_dir, self.workers, self.log)
                for b in self.study.balls if b.stamp is not None
            }  # fmt: skip
        return self.league[divisions]

    def job(self, design: Design) -> DesignJob:
        study = self.study
        spec = design_spec(self.base, study.parameters, design.values, f"{study.name}-{design.id}")
        league = self.league_balls(design.mesh.ball_divisions)
        balls = tuple(
            (b.name, (b.source,), b.speeds, ()) if b.stamp is None else
            (b.name, tuple(str(lb.spec_file) for lb in league[b.name]), b.speeds, b.prior_names)
            for b in study.balls
        )  # fmt: skip
        from batball.specs.bat import bat_spec_to_toml_dict

        return DesignJob(bat_spec_to_toml_dict(spec), design.mesh, balls, study.needs_modal,
                         study.needs_barrel, self.runs_dir, self.reuse)  # fmt: skip

    def evaluate(self, points: Sequence[Sequence[float]], stage: str, mesh: Mesh) -> list[Design]:
        designs = [Design(design_id(v), stage, mesh, tuple(float(x) for x in v)) for v in points]
        jobs = [self.job(d) for d in designs]
        for design, responses in zip(designs, self.executor.map(evaluate_design, jobs),
                                     strict=True):  # fmt: skip
            self.finish(design, responses)
        return designs

    def finish(self, design: Design, responses: dict[str, Any]) -> None:
        bad = [k for k, v in responses.items() if k != "error" and not math.isfinite(v)]
        if "error" in responses or bad:
            why = responses.get("error") or f"response {bad[0]} is not finite"
            design.error = f"{why} ({self.describe(design)})"
            self.designs.append(design)
            if self.progress is not None:
                self.progress(len(self.designs))
            return
        for ball in self.study.balls:
            for speed in ball.speeds:
                if self.study.needs_ball_cor:
                    bbcor = responses[ball.columns(speed)[1]]
                    responses[bpf_column(ball, speed)] = bbcor / self.cors[ball.name]
        design.responses = responses
        design.margins = constraint_margins(self.study, responses)
        self.designs.append(design)
        if self.progress is not None:
            self.progress(len(self.designs))

    def describe(self, design: Design) -> str:
        return ", ".join(f"{p.name} {p.to_unit(v):.4g} {p.unit}"
                         for p, v in zip(self.study.parameters, design.values, strict=True))


def fit_study_league_ball(
    ball: BallChoice, divisions: int, runs_dir: Path, workers: int | None,
    log: Callable[[str], None],
) -> list[Any]:  # fmt: skip
    """A study's league ball (a ``[[ball]]`` with a ``stamp``) fitted on ``divisions``, one
    :class:`batball.design.league.LeagueBall` per prior; a fit that misses the stamp by more
    than its goal (COR 1 %, compression 5 %) is said in the log and kept in summary.json."""
    from batball.calibrate.optimise import OptimiserOptions
    from batball.design.league import fit_league_ball, league_targets, load_priors

    assert ball.stamp is not None
    budget = OptimiserOptions(global_points=ball.fit_points, coarse_divisions=divisions,
                              coarse_evaluations=ball.fit_evaluations, fine_divisions=None)
    targets = league_targets(*ball.stamp)
    log(f"fitting league ball {ball.name} to its stamp on the {divisions}-division ball, "
        f"priors {', '.join(ball.prior_names)}")
    out = []
    for prior in load_priors(ball.priors):
        league = fit_league_ball(f"{ball.name}-d{divisions}", prior, targets, budget=budget,
                                 runs_dir=runs_dir / "league", workers=workers)  # fmt: skip
        missed = {q: r for q, r in league.residuals.items() if abs(r) > 1.0}
        if missed:
            log(f"  league ball {league.ball.name} misses its stamp: "
                + ", ".join(f"{q} {r:+.2f} goals" for q, r in missed.items()))
        out.append(league)
    return out


def score(study: DesignStudy, design: Design) -> float:
    """The first objective's score (smaller is better) plus a penalty for each constraint's
    violation relative to its limit; with no objective, the violation alone; a failed design
    scores 1e30."""
    if design.error:
        return 1e30
    violation = 0.0
    for c in study.constraints:
        value = design.responses[c.response]
        limit = c.upper if c.upper is not None else c.lower
        scale = abs(limit) if limit else 1.0
        violation += max(0.0, -c.margin(value)) / scale
    if not study.objectives:
        return VIOLATION_PENALTY * violation
    objective = study.objectives[0]
    value = objective.score(design.responses[objective.response])
    return value + VIOLATION_PENALTY * violation * (abs(value) + 1.0)


def pareto_front(study: DesignStudy, designs: Sequence[Design]) -> set[str]:
    """The ids of the feasible designs no other feasible design beats in every objective (with
    one objective: the best)."""
    feasible = [d for d in designs if d.feasible]
    if not study.objectives or not feasible:
        return set()
    scores = np.array([[o.score(d.responses[o.response]) for o in study.objectives]
                       for d in feasible])  # fmt: skip
    front = set()
    for i, row in enumerate(scores):
        dominated = np.any(np.all(scores <= row, axis=1) & np.any(scores < row, axis=1))
        if not dominated:
            front.add(feasible[i].id)
    return front


def influence(study: DesignStudy, designs: Sequence[Design]) -> dict[str, dict[str, float]]:
    """Each parameter's standardised regression coefficient on each response over the sampled
    designs (a linear fit of the standardised response on the standardised parameters; its R²
    under ``"r2"``): the change of the response, in its standard deviations, per standard
    deviation of the parameter. Empty with fewer designs than parameters + 2."""
    sample = [d for d in designs if d.stage == "sample" and not d.error]
    d = len(study.parameters)
    if len(sample) < d + 2:
        return {}
    x = np.array([d_.values for d_ in sample])
    x = (x - x.mean(axis=0)) / np.where(x.std(axis=0) > 0, x.std(axis=0), 1.0)
    out: dict[str, dict[str, float]] = {}
    for response in study.responses:
        if any(response not in d_.responses for d_ in sample):
            continue
        y = np.array([d_.responses[response] for d_ in sample])
        if not y.std() > 0:
            continue
        z = (y - y.mean()) / y.std()
        a = np.column_stack([x, np.ones(len(z))])
        coef, *_ = np.linalg.lstsq(a, z, rcond=None)
        r2 = 1.0 - float(np.sum((a @ coef - z) ** 2)) / float(np.sum(z**2))
        out[response] = {p.name: float(c) for p, c in zip(study.parameters, coef[:d], strict=True)}
        out[response]["r2"] = r2
    return out


def run_design_study(
    study: DesignStudy,
    *,
    out_dir: Path,
    runs_dir: Path,
    workers: int | None = None,
    scheduler: str | None = None,
    reuse: bool = True,
    progress: bool = False,
    log: Callable[[str], None] | None = None,
) -> DesignResult:
    """Run ``study`` (module docs) and write its files into ``out_dir``.

    Raises:
        SpecError: a design the bat spec refuses (a parameter value it cannot take).
        SimulationError: a design whose response is not finite, naming the design.
    """
    from batball.calibrate.executors import default_workers, open_executor
    from batball.results.store import check_output_folder
    from batball.specs import load_bat_spec

    check_output_folder("out", out_dir)
    check_output_folder("runs-dir", runs_dir)
    say = log or (lambda _text: None)
    start = time.perf_counter()
    base = load_bat_spec(study.bat)
    design_spec(base, study.parameters, [p.lower for p in study.parameters], "check")
    stage_seconds: dict[str, float] = {}
    t0 = time.perf_counter()
    # the BPF's denominator: a ball's COR at 60 mph on the screening mesh, a league ball's stamp
    cors = ({b.name: b.stamp[0] if b.stamp is not None else
             ball_cor(b.source, study.mesh.ball_divisions, runs_dir, reuse)
             for b in study.balls} if study.needs_ball_cor else {})  # fmt: skip
    stage_seconds["ball_cor"] = time.perf_counter() - t0
    bar = _bar(progress, study.designs, "designs")
    workers = default_workers() if workers is None else workers
    with open_executor(workers=workers, scheduler=scheduler) as executor:
        tick = None if bar is None else lambda n: _update(bar, n)
        ev = _Evaluator(study, base, runs_dir, reuse, executor, cors, tick, workers, say)
        t0 = time.perf_counter()
        ev.league_balls(study.mesh.ball_divisions)
        if ev.league[study.mesh.ball_divisions]:
            stage_seconds["league_balls"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        unit = sample_unit(study)
        points = [[p.value_at(u) for p, u in zip(study.parameters, row, strict=True)]
                  for row in unit]  # fmt: skip
        say(f"sampling {len(points)} designs ({study.method}) on {study.mesh.label}")
        ev.evaluate(points, "sample", study.mesh)
        stage_seconds["sample"] = time.perf_counter() - t0
        if bar is not None:
            bar.close()
        if study.optimise_evaluations:
            t0 = time.perf_counter()
            say(f"local search: {study.optimise_evaluations} evaluations from the best design")
            _local_search(study, ev)
            stage_seconds["optimise"] = time.perf_counter() - t0
    screened = list(ev.designs)
    ranking = sorted(_unique(screened), key=lambda d: (not d.feasible, score(study, d)))
    confirmed: list[Design] = []
    if study.confirm is not None and study.confirm_top:
        t0 = time.perf_counter()
        confirmed = _confirm(study, ev, ranking, say)
        stage_seconds["confirm"] = time.perf_counter() - t0
    front = pareto_front(study, screened)
    result = DesignResult(study, screened + confirmed, ranking, front,
                          influence(study, screened), cors, Path(out_dir),
                          time.perf_counter() - start, stage_seconds,
                          league_rows(ev.league))  # fmt: skip
    write_outputs(result, base)
    return result


def _confirm(study: DesignStudy, ev: _Evaluator, ranking: Sequence[Design],
             say: Callable[[str], None]) -> list[Design]:  # fmt: skip
    """The confirmation rounds (:func:`confirmation_candidates`), in this process: a full-size
    run uses every core itself."""
    from batball.calibrate.executors import open_executor

    assert study.confirm is not None
    confirmed: list[Design] = []
    with open_executor(workers=0) as inline:
        ev.executor = inline
        for round_ in range(1, study.confirm_rounds + 1):
            top = confirmation_candidates(study, ranking, confirmed)
            if not top:
                break
            say(f"confirming {len(top)} designs on {study.confirm.label} (round {round_})")
            new = ev.evaluate([d.values for d in top], "confirm", study.confirm)
            for d in new:
                d.round = round_
            confirmed += new
    return confirmed


def constraint_margins(study: DesignStudy, responses: dict[str, float]) -> dict[str, float]:
    """Each constraint's margin (a rule's named with its response), in the response's unit."""
    margins: dict[str, float] = {}
    for c in study.constraints:
        key = c.label if not c.rule else f"{c.label}__{c.response}"
        value = c.margin(responses[c.response])
        margins[key] = min(value, margins.get(key, value))
    return margins


def corrected_ranking(study: DesignStudy, ranking: Sequence[Design],
                      confirmed: Sequence[Design]) -> list[Design] | None:  # fmt: skip
    """The screened designs not yet confirmed that stay feasible once their screening values are
    corrected by what the confirmation measured, best first: each constraint's margin taken at
    its worst over the offsets (confirmed minus screened) of the confirmed designs, the objective
    with their mean. None when nothing was confirmed (no offset to correct by)."""
    screened = {d.id: d for d in ranking}
    offsets = [{r: c.responses[r] - screened[c.id].responses[r] for r in c.responses}
               for c in confirmed if not c.error and c.id in screened]  # fmt: skip
    if not offsets:
        return None
    done = {d.id for d in confirmed}
    candidates = []
    for d in ranking:
        if d.error or d.id in done:
            continue
        shadow = Design(d.id, d.stage, d.mesh, d.values,
                        {r: v + float(np.mean([o[r] for o in offsets])) if r in offsets[0] else v
                         for r, v in d.responses.items()})  # fmt: skip
        worst = [constraint_margins(study, {r: v + o.get(r, 0.0) for r, v in d.responses.items()})
                 for o in offsets]  # fmt: skip
        shadow.margins = {key: min(m[key] for m in worst) for key in worst[0]}
        if shadow.feasible:
            candidates.append((score(study, shadow), d))
    candidates.sort(key=lambda item: item[0])
    return [d for _, d in candidates]


def confirmation_candidates(study: DesignStudy, ranking: Sequence[Design],
                            confirmed: Sequence[Design]) -> list[Design]:  # fmt: skip
    """The designs the next confirmation round reruns: in the first, the best ``confirm_top``
    feasible ones on the screening mesh; in a later one, the best ``confirm_top`` of
    :func:`corrected_ranking` (none: the rounds stop)."""
    if not confirmed:
        return [d for d in ranking if d.feasible][: study.confirm_top]
    return (corrected_ranking(study, ranking, confirmed) or [])[: study.confirm_top]


def best_designs(result: DesignResult) -> list[Design]:
    """The best designs, as best/ and summary.json list them: those feasible on the
    confirmation mesh first (ranked on it), then those not rerun that are feasible on the
    screening mesh, corrected by the confirmation's offsets where there are any
    (:func:`corrected_ranking`); a design the confirmation mesh found infeasible is left out."""
    study = result.study
    confirmed = [d for d in result.designs if d.stage == "confirm" and not d.error]
    screened = {d.id: d for d in result.ranking}
    sure = sorted((c for c in confirmed if c.feasible), key=lambda c: score(study, c))
    rest = corrected_ranking(study, result.ranking, confirmed)
    if rest is None:
        rest = [d for d in result.ranking if d.feasible]
    return [screened[c.id] for c in sure if c.id in screened] + rest


def league_rows(league: dict[int, dict[str, list[Any]]]) -> list[dict[str, Any]]:
    """summary.json's rows of the league balls: each mesh's fit per prior, what it reached."""
    from batball.design.league import LEAGUE_FREE
    from batball.units import LBF

    return [{"ball": name, "prior": lb.prior, "ball_divisions": divisions,
             "spec": str(lb.spec_file), "cor": lb.cor, "compression_lbf": lb.compression / LBF,
             "residuals_in_goals": dict(lb.residuals),
             "fitted_pa": {k: lb.ball.material.values[k] for k in LEAGUE_FREE}, "runs": lb.runs}
            for divisions, balls in sorted(league.items())
            for name, fits in balls.items() for lb in fits]  # fmt: skip


def _unique(designs: Sequence[Design]) -> list[Design]:
    seen: dict[str, Design] = {}
    for d in designs:
        seen.setdefault(d.id, d)
    return list(seen.values())


def _local_search(study: DesignStudy, ev: _Evaluator) -> None:
    """Nelder-Mead in the unit cube from the best sampled design, on the screening mesh, for
    ``optimise_evaluations`` evaluations (each design evaluated once: repeats are looked up)."""
    from scipy.optimize import minimize

    parameters = study.parameters
    spans = np.array([p.upper - p.lower for p in parameters])
    lows = np.array([p.lower for p in parameters])
    best = min(ev.designs, key=lambda d: score(study, d))
    known = {d.id: d for d in ev.designs}
    budget = [study.optimise_evaluations]

    def f(u: np.ndarray) -> float:
        values = tuple(float(v) for v in lows + np.clip(u, 0.0, 1.0) * spans)
        key = design_id(values)
        if key not in known:
            if budget[0] <= 0:
                raise _BudgetSpentError
            budget[0] -= 1
            (known[key],) = ev.evaluate([values], "optimise", study.mesh)
        return score(study, known[key])

    u0 = (np.array(best.values) - lows) / spans
    simplex = [u0] + [np.clip(u0 + 0.15 * np.eye(len(u0))[i] * (1 if u0[i] < 0.5 else -1),
                              0.0, 1.0) for i in range(len(u0))]  # fmt: skip
    with contextlib.suppress(_BudgetSpentError):
        minimize(f, u0, method="Nelder-Mead", bounds=[(0.0, 1.0)] * len(u0),
                 options={"initial_simplex": np.array(simplex), "xatol": 1e-4, "fatol": 0.0,
                          "maxfev": 10 * study.optimise_evaluations})  # fmt: skip


class _BudgetSpentError(Exception):
    """The local search used its evaluations."""


def _bar(enabled: bool, total: int, unit: str) -> Any:
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, unit=unit, leave=False)


def _update(bar: Any, n: int) -> None:
    bar.n = min(n, bar.total)
    bar.refresh()


def rows(result: DesignResult) -> list[dict[str, Any]]:
    """``designs.csv``'s rows (units in the column names)."""
    study = result.study
    ranks = {d.id: i + 1 for i, d in enumerate(d for d in result.ranking if d.feasible)}
    out = []
    for d in result.designs:
        row: dict[str, Any] = {"design": d.id, "stage": d.stage, "mesh": d.mesh.label}
        for p, v in zip(study.parameters, d.values, strict=True):
            row[p.column] = p.to_unit(v)
        row.update(d.responses)
        row.update(d.margins)
        row["feasible"] = d.feasible
        row["error"] = d.error
        row["pareto"] = d.stage != "confirm" and d.id in result.pareto
        row["rank"] = ranks.get(d.id) if d.stage != "confirm" else None
        row["round"] = d.round if d.stage == "confirm" else None
        out.append(row)
    return out


def write_outputs(result: DesignResult, base: BatSpec) -> None:
    """designs.csv, best/<rank>-<id>.toml and summary.json, each written atomically."""
    import tomli_w

    from batball.results.store import write_json_atomic, write_text_atomic
    from batball.specs.bat import bat_spec_to_toml_dict

    study, out = result.study, result.out_dir
    table = rows(result)
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(dict.fromkeys(k for r in table for k in r)),
                            lineterminator="\n")  # fmt: skip
    writer.writeheader()
    writer.writerows({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in r.items()}
                     for r in table)  # fmt: skip
    write_text_atomic(out / "designs.csv", buffer.getvalue())
    best = best_designs(result)[: max(study.confirm_top * study.confirm_rounds, 3)]
    for rank, d in enumerate(best, start=1):
        spec = design_spec(base, study.parameters, d.values, f"{study.name}-{d.id}")
        header = (f"# Design {d.id} of batball design study {study.name!r}, rank {rank}: "
                  + ", ".join(f"{p.name} = {p.to_unit(v):.6g} {p.unit}"
                              for p, v in zip(study.parameters, d.values, strict=True)) + "\n")
        write_text_atomic(out / "best" / f"{rank}-{d.id}.toml",
                          header + tomli_w.dumps(bat_spec_to_toml_dict(spec)))  # fmt: skip
    write_json_atomic(out / "summary.json", summary_document(result, best))


def confirmation_offset(result: DesignResult) -> dict[str, float]:
    """Per response, the mean of (confirmed - screened) over the designs confirmed on the finer
    mesh: how far the screening mesh is off, which a margin on the screening mesh must be read
    against. Empty without confirmed designs."""
    screened = {d.id: d for d in result.designs if d.stage != "confirm" and not d.error}
    pairs = [(screened[d.id], d) for d in result.designs
             if d.stage == "confirm" and not d.error and d.id in screened]  # fmt: skip
    if not pairs:
        return {}
    return {r: float(np.mean([c.responses[r] - s.responses[r] for s, c in pairs]))
            for r in pairs[0][1].responses}  # fmt: skip


def summary_document(result: DesignResult, best: Sequence[Design]) -> dict[str, Any]:
    """summary.json of a study."""
    study = result.study
    confirmed = {d.id: d for d in result.designs if d.stage == "confirm"}

    def entry(d: Design) -> dict[str, Any]:
        item: dict[str, Any] = {
            "design": d.id,
            "parameters": {p.column: p.to_unit(v)
                           for p, v in zip(study.parameters, d.values, strict=True)},
            "responses": d.responses,
            "margins": d.margins,
            "feasible": d.feasible,
        }  # fmt: skip
        if d.id in confirmed:
            item["confirmed"] = {"mesh": confirmed[d.id].mesh.label,
                                 "responses": confirmed[d.id].responses,
                                 "margins": confirmed[d.id].margins,
                                 "feasible": confirmed[d.id].feasible,
                                 "round": confirmed[d.id].round}  # fmt: skip
        return item

    return {
        "study": study.name,
        "description": study.description,
        "bat": study.bat,
        "parameters": [{"name": p.name, "set": p.setting, "unit": p.unit,
                        "range": [p.to_unit(p.lower), p.to_unit(p.upper)]}
                       for p in study.parameters],  # fmt: skip
        "balls": [{"name": b.name, "source": b.source, "speeds_mph": [v / MPH for v in b.speeds]}
                  for b in study.balls],  # fmt: skip
        "responses": {r: response_unit(r) for r in study.responses},
        "constraints": [{"response": c.response, "min": c.lower, "max": c.upper,
                         "rule": c.rule or None} for c in study.constraints],  # fmt: skip
        "rules": [{"name": r.name, "title": r.title, "source": r.source} for r in study.rules],
        "objectives": [{"response": o.response, "sense": o.sense, "target": o.target}
                       for o in study.objectives],  # fmt: skip
        "mesh": study.mesh.label,
        "confirm_mesh": None if study.confirm is None else study.confirm.label,
        "ball_cor": result.ball_cor,
        "designs": {stage: sum(d.stage == stage for d in result.designs)
                    for stage in ("sample", "optimise", "confirm")},  # fmt: skip
        "feasible": sum(d.feasible for d in result.designs if d.stage != "confirm"),
        "failed": [{"design": d.id, "stage": d.stage, "error": d.error}
                   for d in result.designs if d.error],  # fmt: skip
        "best": [entry(d) for d in best],
        "pareto": sorted(result.pareto),
        "influence": result.influence,
        "confirmation_offset": confirmation_offset(result),
        "confirm_rounds": study.confirm_rounds,
        "best_confirmed": next((d.id for d in best if d.id in confirmed
                                and confirmed[d.id].feasible), None),  # fmt: skip
        "league_balls": result.league_balls,
        "wall_seconds": result.seconds,
        "stage_seconds": result.stage_seconds,
    }


def load_rows(out_dir: Path) -> list[dict[str, Any]]:
    """designs.csv read back (numbers as floats, True/False as bools)."""
    with open(Path(out_dir) / "designs.csv", encoding="utf-8", newline="") as stream:
        table = list(csv.DictReader(stream))

    def value(text: str) -> Any:
        if text in ("True", "False"):
            return text == "True"
        try:
            return float(text)
        except ValueError:
            return text or None

    return [{k: value(v) for k, v in row.items()} for row in table]
