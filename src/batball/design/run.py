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

from batball.design.rules import BALL_COR_SPEED, bpf_column
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
    balls: tuple[tuple[str, str, tuple[float, ...]], ...]  # (name, source, speeds m/s)
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

    for name, source, speeds in job.balls:
        ball = load_ball_spec(source)
        for speed in speeds:
            setup = bbs.setup(**mesh, divisions=job.mesh.ball_divisions, speed=f"{speed!r} m/s")
            s, _ = bbs.execute({"bat": spec, "ball": ball}, setup, **store)
            bbs_col, bbcor_col, ea_col = BallChoice(name, source, speeds).columns(speed)
            out |= {bbs_col: s["bbs_mph"], bbcor_col: s["bbcor"],
                    ea_col: s["collision_efficiency"]}  # fmt: skip
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
                 progress: Callable[[int], None] | None) -> None:  # fmt: skip
        self.study, self.base, self.runs_dir, self.reuse = study, base, runs_dir, reuse
        self.executor, self.cors, self.progress = executor, cors, progress
        self.designs: list[Design] = []

    def job(self, design: Design) -> DesignJob:
        study = self.study
        spec = design_spec(self.base, study.parameters, design.values, f"{study.name}-{design.id}")
        balls = tuple((b.name, b.source, b.speeds) for b in study.balls)
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
        design.margins = {}
        for c in self.study.constraints:
            key = c.label if not c.rule else f"{c.label}__{c.response}"
            design.margins[key] = c.margin(responses[c.response])
        self.designs.append(design)
        if self.progress is not None:
            self.progress(len(self.designs))

    def describe(self, design: Design) -> str:
        return ", ".join(f"{p.name} {p.to_unit(v):.4g} {p.unit}"
                         for p, v in zip(self.study.parameters, design.values, strict=True))


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
    cors = ({b.name: ball_cor(b.source, study.mesh.ball_divisions, runs_dir, reuse)
             for b in study.balls} if study.needs_ball_cor else {})  # fmt: skip
    stage_seconds["ball_cor"] = time.perf_counter() - t0
    bar = _bar(progress, study.designs, "designs")
    workers = default_workers() if workers is None else workers
    with open_executor(workers=workers, scheduler=scheduler) as executor:
        ev = _Evaluator(study, base, runs_dir, reuse, executor, cors,
                        None if bar is None else lambda n: _update(bar, n))  # fmt: skip
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
        top = [d for d in ranking if d.feasible][: study.confirm_top]
        say(f"confirming the best {len(top)} on {study.confirm.label}")
        with open_executor(workers=0) as inline:  # full-size runs use every core each
            ev.executor = inline
            confirmed = ev.evaluate([d.values for d in top], "confirm", study.confirm)
        stage_seconds["confirm"] = time.perf_counter() - t0
    front = pareto_front(study, screened)
    result = DesignResult(study, screened + confirmed, ranking, front,
                          influence(study, screened), cors, Path(out_dir),
                          time.perf_counter() - start, stage_seconds)  # fmt: skip
    write_outputs(result, base)
    return result


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
    best = [d for d in result.ranking if d.feasible][: max(study.confirm_top, 3)]
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
                                 "feasible": confirmed[d.id].feasible}  # fmt: skip
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
