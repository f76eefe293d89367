"""Batted-ball speed with its uncertainty: an ensemble of bats consistent with the bat's
measurements times balls consistent with the ball's, each pair run through the BBS test.

The bats. The study's bat (a fitted one, such as ``batball fit-bat --to joint`` writes) and
``samples`` more drawn from its linearised posterior: the sensitivity of the bat's measurements
(weight, balance point, MOI, bending and hoop frequencies; seed Tables 1 and 3 unless the study
gives its own) to the free parameters at the study's bat, each measurement with its resolution
and each parameter with its plausible spread (:mod:`batball.calibrate.bat_sensitivity`), gives
the posterior covariance; a Latin hypercube mapped through it gives the draws. A parameter the
measurements do not see keeps its prior spread.

The balls. Every ball file the study lists, grouped by the ball's name (``type1``, ``type2``):
the ball models that fit the ball's own tests about equally well (for instance one per material
law or hourglass form). They are alternatives, not random draws, so each counts equally.

Each (bat, ball, speed) is one run of the registry's ``bbs`` test, stored under its inputs: a
study that is stopped and started again reuses every run it finished. The runs go to a local
process pool, or to a Dask cluster.

Per cell (ball group and speed) the members give the mean and the standard deviation (each
member weighted equally), the interval mean +- 1.96 sd, and the two-way split of the variance
into the bat's part (the spread of the bat means), the ball's part (the spread of the ball-model
means) and their interaction; the trend (the highest speed minus the lowest) the same way; and
for every two groups at a speed the probability that the first gives the faster batted ball on
the same bat (over every bat and every pair of the two groups' models).
"""

from __future__ import annotations

import csv
import io
import itertools
import math
import time
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from batball.calibrate.bat_fit import (
    DEFAULT_JOINT_FREE,
    FreeParameter,
    JointTargets,
    MassTargets,
    MeshOptions,
    ModalTargets,
)
from batball.errors import SimulationError, SpecError
from batball.specs.bat import BatSpec
from batball.units import MPH, parse_quantity

#: The z value of a two-sided 95 % interval of a normal distribution.
Z95 = 1.959963984540054

#: Keys a study file may have, at the top and in its tables.
_TOP = ("name", "speeds", "seed", "bat", "balls", "mesh")
_BAT = ("spec", "samples", "free", "spread", "targets", "mesh")
_TARGETS = ("weight", "balance_point", "moi", "bending", "hoop")
_MESH = ("divisions", "circumferential", "axial_size", "shell")


@dataclass(frozen=True)
class BatTargets:
    """The bat's measurements the posterior is conditioned on (SI; frequencies Hz)."""

    weight: float
    balance_point: float
    moi_pivot: float
    bending_hz: tuple[float, ...]
    hoop_hz: tuple[float, ...]

    def joint(self, runs_dir: Path | None, reuse: bool = True) -> JointTargets:
        """The :class:`JointTargets` of these measurements, modal runs stored in ``runs_dir``."""
        mass = MassTargets(self.weight, self.balance_point, self.moi_pivot)
        modal = ModalTargets(hoop_hz=self.hoop_hz, bending_hz=self.bending_hz,
                             runs_dir=runs_dir, reuse=reuse)  # fmt: skip
        return JointTargets((mass, modal))


@dataclass(frozen=True)
class EnsembleStudy:
    """An ensemble study (module docs), as read from its TOML file.

    Attributes:
        name: the study's name (its folder's).
        bat: the study's bat (embedded name or file path).
        samples: bats drawn from the posterior besides the study's bat.
        free: the bat parameters varied, with ``spread`` (SI) each.
        targets: the bat's measurements.
        sensitivity_mesh: the bat mesh of the sensitivity's modal analyses.
        balls: ball files or embedded names.
        speeds: inbound ball speeds, m/s.
        mesh: the BBS runs' mesh (option name -> value as a person gives it).
        seed: the Latin hypercube's seed.
    """

    name: str
    bat: str
    samples: int
    free: tuple[FreeParameter, ...]
    spread: tuple[float, ...]
    targets: BatTargets
    sensitivity_mesh: MeshOptions
    balls: tuple[str, ...]
    speeds: tuple[float, ...]
    mesh: dict[str, str] = field(default_factory=dict)
    seed: int = 1


def load_ensemble_study(path: str | Path) -> EnsembleStudy:
    """Read and check an ensemble study file (docs/ensemble.md); paths in it are relative to
    the file's folder.

    Raises:
        SpecError: naming the field (``file``, ``speeds``, ``bat.free``...), the value and what
            is allowed.
    """
    path = Path(path)
    try:
        document = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise SpecError(
            "file", str(path), f"a readable ensemble study file ({exc.strerror})"
        ) from None
    except tomllib.TOMLDecodeError as exc:
        raise SpecError("file", str(path), f"valid TOML ({exc})") from None
    return ensemble_study_from_dict(document, base=path.parent)


def _spread_of(p: FreeParameter, given: dict[str, Any], spec: BatSpec) -> float:
    """A free parameter's spread: ``bat.spread`` gives it (an angle or a quantity with its unit,
    the friction a number), else its default (:func:`default_spread`)."""
    from batball.calibrate.bat_sensitivity import default_spread
    from batball.specs.bat import parse_angle

    if str(p) not in given:
        return default_spread(p, spec)
    value, where = given[str(p)], f"bat.spread.{p}"
    if p.kind == "friction":  # a Coulomb coefficient: a number without a unit
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise SpecError(where, value, "a positive number without a unit, e.g. 0.3")
        found = float(value)
    elif p.kind == "angle":
        found = parse_angle(value, field=where)
    else:
        found = _quantity(value, "mass" if p.kind == "lumped_mass" else "length", where)
    if not (math.isfinite(found) and found > 0):
        raise SpecError(where, value, "a positive spread with its unit")
    return found


def ensemble_study_from_dict(document: Mapping[str, Any], *,
                             base: Path = Path(".")) -> EnsembleStudy:  # fmt: skip
    """The study of a parsed TOML document (see :func:`load_ensemble_study`)."""
    from batball.specs import load_ball_spec, load_bat_spec
    from batball.specs.ball import EMBEDDED_BALLS, FITTED_BALLS
    from batball.specs.bat import EMBEDDED_BATS, FITTED_BATS

    _known(document, "", _TOP)
    name = document.get("name")
    if not isinstance(name, str) or not name or any(c in name for c in "/\\") or name[0] == ".":
        raise SpecError("name", name, "a non-empty name usable as a folder name")
    speeds = tuple(_quantity(v, "velocity", "speeds") for v in _list(document, "speeds"))
    if not speeds or not all(s > 0 for s in speeds) or list(speeds) != sorted(set(speeds)):
        raise SpecError("speeds", document.get("speeds"), "positive speeds, lowest first")
    seed = document.get("seed", 1)
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        raise SpecError("seed", seed, "a non-negative integer")
    bat_table = document.get("bat")
    if not isinstance(bat_table, dict):
        raise SpecError("bat", bat_table, "a [bat] table with at least spec = ...")
    _known(bat_table, "bat.", _BAT)
    bat = _spec_path(bat_table.get("spec"), base, "bat.spec", EMBEDDED_BATS + FITTED_BATS)
    spec = load_bat_spec(bat)
    samples = bat_table.get("samples", 4)
    if not isinstance(samples, int) or isinstance(samples, bool) or not 0 <= samples <= 1000:
        raise SpecError("bat.samples", samples, "an integer from 0 to 1000")
    texts = bat_table.get("free", list(DEFAULT_JOINT_FREE))
    if not isinstance(texts, list) or not texts or not all(isinstance(t, str) for t in texts):
        raise SpecError("bat.free", texts, "a non-empty list of parameter names (fit-bat --free)")
    if len(set(texts)) != len(texts):
        raise SpecError("bat.free", texts, "each parameter once")
    try:
        free = tuple(FreeParameter.parse(t) for t in texts)
        for p in free:
            p.value(spec)  # refused if the bat has no such value
    except SpecError as exc:
        raise SpecError("bat.free", exc.value, exc.allowed) from None
    given = bat_table.get("spread", {})
    if not isinstance(given, dict) or not set(given) <= set(texts):
        raise SpecError("bat.spread", given, f"a table NAME = 'VALUE UNIT' with NAME among "
                        f"bat.free: {', '.join(texts)}")  # fmt: skip

    targets = _bat_targets(bat_table.get("targets", {}))
    embedded = EMBEDDED_BALLS + FITTED_BALLS
    balls = tuple(_spec_path(v, base, "balls", embedded) for v in _list(document, "balls"))
    if not balls or len(set(balls)) != len(balls):
        raise SpecError("balls", document.get("balls"), "a list of ball files or embedded "
                        "names, each once")  # fmt: skip
    for i, source in enumerate(balls):
        try:
            load_ball_spec(source)
        except SpecError as exc:
            raise SpecError(f"balls[{i}].{exc.field}", exc.value, exc.allowed) from None
    sens_mesh = _mesh_table(bat_table.get("mesh", {}), "bat.mesh", ("circumferential",
                                                                   "axial_size"))  # fmt: skip
    mesh = _mesh_table(document.get("mesh", {}), "mesh", _MESH)
    _bbs_setup(mesh, speeds)
    sensitivity_mesh = MeshOptions(
        int(sens_mesh.get("circumferential", 32)),
        _quantity(sens_mesh.get("axial_size", "0.2 in"), "length", "bat.mesh.axial_size"),
    )
    spread = tuple(_spread_of(p, given, spec) for p in free)
    return EnsembleStudy(
        name=name, bat=bat, samples=samples, free=free, spread=spread,
        targets=targets, sensitivity_mesh=sensitivity_mesh, balls=balls, speeds=speeds,
        mesh=mesh, seed=seed,
    )  # fmt: skip


def _bbs_setup(mesh: Mapping[str, str], speeds: Sequence[float]) -> list[Any]:
    """The BBS test's setup of each speed: the test's own checks of the mesh options, so a
    value it refuses stops the study before anything runs."""
    from batball.lab.registry import LAB_TESTS

    test = LAB_TESTS["bbs"]
    try:
        return [test.setup(**mesh, speed=f"{s!r} m/s") for s in speeds]
    except SpecError as exc:
        raise SpecError(f"mesh.{exc.field.replace('-', '_')}", exc.value, exc.allowed) from None


def _bat_targets(table: Any) -> BatTargets:
    """``[bat.targets]``, each value defaulting to seed Tables 1 and 3."""
    from batball.specs.seed import load_seed_tables

    if not isinstance(table, dict):
        raise SpecError("bat.targets", table, "a table of measured values with units")
    _known(table, "bat.targets.", _TARGETS)
    seed = load_seed_tables()
    bat, modal = seed.bat, seed.modal

    def frequencies(key: str, default: tuple[float, ...]) -> tuple[float, ...]:
        if key not in table:
            return default
        where = f"bat.targets.{key}"
        values = table[key] if isinstance(table[key], list) else [table[key]]
        found = tuple(_quantity(v, "frequency", where) for v in values)
        if not found or not all(f > 0 for f in found) or list(found) != sorted(set(found)):
            raise SpecError(where, table[key], "positive frequencies, lowest first")
        return found

    def value(key: str, dimension: str, default: float) -> float:
        if key not in table:
            return default
        return _quantity(table[key], dimension, f"bat.targets.{key}")

    return BatTargets(
        weight=value("weight", "mass", bat.weight_exp),
        balance_point=value("balance_point", "length", bat.balance_point_exp),
        moi_pivot=value("moi", "moment_of_inertia", bat.moi_exp),
        bending_hz=frequencies("bending", (modal.bending_1_exp, modal.bending_2_exp)),
        hoop_hz=frequencies("hoop", (modal.hoop_1_exp, modal.hoop_2_exp)),
    )


def _quantity(value: Any, dimension: str, where: str) -> float:
    """A value with its unit, as a string ("95 mph"); a bare number is refused."""
    if not isinstance(value, str):
        raise SpecError(where, value, f"a {dimension.replace('_', ' ')} with its unit, as a string")
    return parse_quantity(value, dimension, field=where)


def _list(document: Mapping[str, Any], key: str) -> list[Any]:
    value = document.get(key)
    if not isinstance(value, list):
        raise SpecError(key, value, "a list")
    return value


def _known(table: Mapping[str, Any], prefix: str, keys: Sequence[str]) -> None:
    for key in table:
        if key not in keys:
            raise SpecError(f"{prefix}{key}", table[key], f"one of {', '.join(keys)}")


def _spec_path(value: Any, base: Path, where: str, embedded: Sequence[str]) -> str:
    """An embedded name as it is; a file path relative to the study's folder."""
    if not isinstance(value, str) or not value:
        raise SpecError(where, value, "an embedded name or the path of a TOML file")
    if value in embedded or Path(value).is_absolute():
        return value
    return str(base / value)


def _mesh_table(table: Any, where: str, keys: Sequence[str]) -> dict[str, str]:
    """A mesh table's values as the registry's options take them (strings)."""
    if not isinstance(table, dict):
        raise SpecError(where, table, f"a table of {', '.join(keys)}")
    _known(table, f"{where}.", keys)
    out = {}
    for key, value in table.items():
        if key == "shell":
            if not isinstance(value, str):
                raise SpecError(f"{where}.{key}", value, "the bat's shell element, bt or mitc4")
            out[key] = value
        elif key == "axial_size":
            _quantity(value, "length", f"{where}.{key}")
            out[key] = value
        elif not isinstance(value, int) or isinstance(value, bool) or value < 2:
            raise SpecError(f"{where}.{key}", value, "an integer of at least 2")
        else:
            out[key] = str(value)
    return out


# --- the bats ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class EnsembleBat:
    """One bat of the ensemble: its id, its spec and its offsets from the study's bat in
    spreads (zeros for the study's bat itself)."""

    id: str
    spec: BatSpec
    offsets: tuple[float, ...]


def ensemble_bats(study: EnsembleStudy, *, runs_dir: Path | None,
                  reuse: bool = True) -> tuple[list[EnsembleBat], Any]:  # fmt: skip
    """The study's bat and its posterior draws, with the :class:`Sensitivity` they come from.

    Raises:
        SpecError: a draw that leaves a bat invalid (a thickness below its bound: the spreads
            are too wide for a Gaussian).
    """
    from batball.calibrate.bat_sensitivity import bat_sensitivity
    from batball.specs import load_bat_spec

    spec = load_bat_spec(study.bat)
    targets = study.targets.joint(runs_dir, reuse)
    found = bat_sensitivity(spec, targets, study.free, spread=study.spread,
                            mesh=study.sensitivity_mesh)  # fmt: skip
    bats = [EnsembleBat("bat-0", spec, (0.0,) * len(study.free))]
    if study.samples:
        draws = found.posterior_offsets(study.samples, seed=study.seed)
        for k, offsets in enumerate(draws, start=1):
            offsets = tuple(float(z) for z in offsets)
            bats.append(EnsembleBat(f"bat-{k}", drawn_bat(spec, study, offsets, f"bat-{k}"),
                                    offsets))  # fmt: skip
    return bats, found


def drawn_bat(spec: BatSpec, study: EnsembleStudy, offsets: Sequence[float],
              name: str) -> BatSpec:  # fmt: skip
    """``spec`` moved by ``offsets`` (in spreads) along the study's free parameters.

    Raises:
        SpecError: a value outside its parameter's bounds (a ply thinner than 0.001 in, a
            negative mass, an angle outside 0..90 deg), naming the spread that put it there.
    """
    from batball.calibrate.bat_fit import PARAMETER_KINDS

    moved = spec
    for p, z, sd in zip(study.free, offsets, study.spread, strict=True):
        value, kind = p.value(spec) + z * sd, PARAMETER_KINDS[p.kind]
        if not kind.lower <= value <= kind.upper:
            raise SpecError(
                f"bat.spread.{p}", _in_unit(sd, kind.unit),
                f"a spread whose draws stay within the parameter's bounds "
                f"({_in_unit(kind.lower, kind.unit)} to {_in_unit(kind.upper, kind.unit)}); "
                f"{name} draws {_in_unit(value, kind.unit)}",
            )  # fmt: skip
        moved = p.apply(moved, value)
    return moved


def _in_unit(value: float, unit: str) -> str:
    """``value`` (SI) in the parameter's display unit."""
    from batball.units import to_unit

    return f"{to_unit(value, unit):.4g} {unit}"


# --- the runs ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class EnsembleJob:
    """One BBS run: the bat as its spec document (which pickles to a worker), the ball's source,
    the speed [m/s], the mesh options and the store."""

    bat: dict[str, Any]
    ball: str
    speed: float
    mesh: dict[str, str]
    runs_dir: Path | None
    reuse: bool = True


def run_ensemble_job(job: EnsembleJob) -> dict[str, Any]:
    """The BBS [mph] and BBCOR of one job, or ``{"error": why}`` when the test cannot measure
    it (the ensemble reports the member as failed and goes on)."""
    from batball.lab.registry import LAB_TESTS
    from batball.specs import load_ball_spec
    from batball.specs.bat import bat_spec_from_dict

    test = LAB_TESTS["bbs"]
    try:
        spec = bat_spec_from_dict(job.bat, source=f"ensemble bat {job.bat.get('name')}")
        setup = test.setup(**job.mesh, speed=f"{job.speed!r} m/s")
        summary, _ = test.execute({"bat": spec, "ball": load_ball_spec(job.ball)}, setup,
                                  runs_dir=job.runs_dir, reuse=job.reuse)  # fmt: skip
    except (SimulationError, SpecError) as exc:
        return {"error": str(exc)}
    return {"bbs_mph": float(summary["bbs_mph"]), "bbcor": float(summary["bbcor"])}


@dataclass
class EnsembleResult:
    """The members (one row per bat, ball and speed) and the cells made of them."""

    study: EnsembleStudy
    bats: list[EnsembleBat]
    rows: list[dict[str, Any]]
    summary: dict[str, Any]


def run_ensemble(
    study: EnsembleStudy,
    *,
    out_dir: Path,
    runs_dir: Path | None,
    workers: int | None = None,
    scheduler: str | None = None,
    reuse: bool = True,
    log: Callable[[str], None] = lambda text: None,
) -> EnsembleResult:
    """Run every member of ``study`` and write ``members.csv`` and ``summary.json`` to
    ``out_dir`` (atomically). Runs stored under ``runs_dir`` are reused.

    Raises:
        SpecError: bad workers or scheduler, an output folder that cannot be written.
        SimulationError: a cell with no bat all of whose members ran (``members.csv`` is
            written first, with each failure's reason).
    """
    from batball.calibrate.executors import default_workers, open_executor
    from batball.results.store import check_output_folder, write_json_atomic, write_text_atomic
    from batball.specs import load_ball_spec
    from batball.specs.bat import bat_spec_to_toml_dict

    check_output_folder("out", out_dir)
    clock = time.perf_counter()
    bats, found = ensemble_bats(study, runs_dir=runs_dir, reuse=reuse)
    log(f"{len(bats)} bats ({study.samples} drawn from the posterior), "
        f"{len(study.balls)} balls, {len(study.speeds)} speeds")  # fmt: skip
    balls = {source: load_ball_spec(source) for source in study.balls}
    members = list(itertools.product(range(len(bats)), study.balls, study.speeds))
    documents = [bat_spec_to_toml_dict(b.spec) for b in bats]
    jobs = [EnsembleJob(documents[b], source, speed, study.mesh, runs_dir, reuse)
            for b, source, speed in members]  # fmt: skip
    pool = default_workers() if workers is None else workers
    with open_executor(workers=min(pool, len(jobs)), scheduler=scheduler) as executor:
        results = list(executor.map(run_ensemble_job, jobs))
    rows = []
    for (b, source, speed), result in zip(members, results, strict=True):
        rows.append({"bat": bats[b].id, "ball": balls[source].name, "ball_model": source,
                     "speed_mph": speed / MPH, **result})  # fmt: skip
    (out_dir / "summary.json").unlink(missing_ok=True)  # never beside another run's members
    write_text_atomic(out_dir / "members.csv", members_csv(study, bats, rows))
    summary = ensemble_summary(study, bats, found, rows)
    summary["wall_seconds"] = time.perf_counter() - clock
    write_json_atomic(out_dir / "summary.json", summary)
    return EnsembleResult(study, bats, rows, summary)


def members_csv(study: EnsembleStudy, bats: Sequence[EnsembleBat],
                rows: Sequence[Mapping[str, Any]]) -> str:  # fmt: skip
    """One row per member: the bat, its offsets in spreads, the ball, the speed, the BBS."""
    offsets = {b.id: b.offsets for b in bats}
    names = [f"{p} (spreads)" for p in study.free]
    stream = io.StringIO()
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(["bat", *names, "ball", "ball_model", "speed_mph", "bbs_mph", "bbcor",
                     "error"])  # fmt: skip
    for r in rows:
        ran = "error" not in r
        writer.writerow([r["bat"], *(f"{z:.12g}" for z in offsets[r["bat"]]), r["ball"],
                         r["ball_model"], f"{r['speed_mph']:.12g}",
                         f"{r['bbs_mph']:.12g}" if ran else "",
                         f"{r['bbcor']:.12g}" if ran else "",
                         r.get("error", "")])  # fmt: skip
    return stream.getvalue()


# --- the statistics ------------------------------------------------------------------------------


def cell_statistics(values: np.ndarray) -> dict[str, float]:
    """The statistics of a (bats, ball models) array of one cell (module docs): mean, sd, the
    95 % interval, min and max, and the standard deviations of the bat's part, the ball's part
    and their interaction (squares summing to sd^2: a balanced two-way split, each member
    weighted equally)."""
    v = np.asarray(values, dtype=float)
    mean = float(v.mean())
    bat_effect = v.mean(axis=1) - mean
    ball_effect = v.mean(axis=0) - mean
    rest = v - mean - bat_effect[:, None] - ball_effect[None, :]
    sd = float(v.std())
    return {
        "mean": mean, "sd": sd, "low": mean - Z95 * sd, "high": mean + Z95 * sd,
        "min": float(v.min()), "max": float(v.max()),
        "sd_bat": float(np.sqrt(np.mean(bat_effect**2))),
        "sd_ball": float(np.sqrt(np.mean(ball_effect**2))),
        "sd_interaction": float(np.sqrt(np.mean(rest**2))),
    }  # fmt: skip


def probability_faster(first: np.ndarray, second: np.ndarray) -> float:
    """The probability that the first group's ball leaves the bat faster than the second's on
    the same bat: over every bat and every pair of the two groups' models, (bats, models) each.
    A tie counts a half."""
    a, b = np.asarray(first, dtype=float), np.asarray(second, dtype=float)
    diff = a[:, :, None] - b[:, None, :]
    return float(np.mean((diff > 0) + 0.5 * (diff == 0)))


def ensemble_summary(study: EnsembleStudy, bats: Sequence[EnsembleBat], found: Any,
                     rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:  # fmt: skip
    """The study's summary: each cell's statistics against the experiment and the seed's
    LS-DYNA where seed Table 9 has the cell, each trend, each ranking's probability, the
    failed members.

    Raises:
        SimulationError: a cell or trend with no bat all of whose members ran, naming it and
            its members' failures.
    """
    groups = sorted({r["ball"] for r in rows})
    failed = [dict(r) for r in rows if "error" in r]
    cells, arrays = [], {}
    for group, mph in itertools.product(groups, [s / MPH for s in study.speeds]):
        array = _cell_array(rows, group, mph, [b.id for b in bats])
        where = f"ensemble {study.name}, {group} at {mph:.4g} mph"
        arrays[group, mph] = array
        complete = _complete(array, where, [f for f in failed if f["ball"] == group and
                                            math.isclose(f["speed_mph"], mph, rel_tol=1e-9)])
        cell = {"ball": group, "speed_mph": mph, **complete, **_against_seed(group, mph)}
        cells.append(cell)
    trends = []
    low, high = study.speeds[0] / MPH, study.speeds[-1] / MPH
    if len(study.speeds) > 1:
        for group in groups:
            diff = arrays[group, high] - arrays[group, low]
            where = f"ensemble {study.name}, {group} from {low:.4g} to {high:.4g} mph"
            trend = {"ball": group, "from_mph": low, "to_mph": high,
                     **_complete(diff, where, [f for f in failed if f["ball"] == group])}
            exp = [float(c["experiment_mph"]) for c in cells
                   if c["ball"] == group and c["speed_mph"] in (low, high)
                   and "experiment_mph" in c]  # fmt: skip
            if len(exp) == 2:
                trend["experiment_mph"] = exp[1] - exp[0]
            trends.append(trend)
    rankings = []
    for first, second in itertools.combinations(groups, 2):
        for mph in [s / MPH for s in study.speeds]:
            a, b = arrays[first, mph], arrays[second, mph]
            keep = ~(np.isnan(a).any(axis=1) | np.isnan(b).any(axis=1))
            probability = probability_faster(a[keep], b[keep]) if keep.any() else None
            rankings.append({"first": first, "second": second, "speed_mph": mph,
                             "probability_first_faster": probability,
                             "bats": int(keep.sum())})  # fmt: skip
    return {
        "study": study.name,
        "bat": study.bat,
        "bats": [
            {"id": b.id, "offsets_spreads": dict(zip(map(str, study.free), b.offsets, strict=True))}
            for b in bats
        ],
        "free": {str(p): s for p, s in zip(study.free, study.spread, strict=True)},
        "posterior_ratio": dict(
            zip(map(str, study.free), map(float, found.posterior_ratio), strict=True)
        ),  # fmt: skip
        "balls": {
            source: next(r["ball"] for r in rows if r["ball_model"] == source)
            for source in study.balls
        },  # fmt: skip
        "mesh": study.mesh,
        "members": len(rows),
        "failed": failed,
        "cells": cells,
        "trends": trends,
        "rankings": rankings,
    }


def _cell_array(rows: Sequence[Mapping[str, Any]], group: str, mph: float,
                bat_ids: Sequence[str]) -> np.ndarray:  # fmt: skip
    """(bats, the group's ball models) of BBS [mph], NaN where a member failed."""
    models = list(dict.fromkeys(r["ball_model"] for r in rows if r["ball"] == group))
    array = np.full((len(bat_ids), len(models)), np.nan)
    for r in rows:
        if r["ball"] == group and math.isclose(r["speed_mph"], mph, rel_tol=1e-9) \
                and "error" not in r:
            array[bat_ids.index(r["bat"]), models.index(r["ball_model"])] = r["bbs_mph"]
    return array


def _complete(array: np.ndarray, where: str,
              failed: Sequence[Mapping[str, Any]]) -> dict[str, Any]:  # fmt: skip
    """The statistics over the bats whose members all ran (a failed member drops its bat from
    the cell, so the split stays balanced).

    Raises:
        SimulationError: no such bat; ``where`` names the cell, with the first failure.
    """
    keep = ~np.isnan(array).any(axis=1)
    if not keep.any():
        why = f": {failed[0]['error']}" if failed else ""
        raise SimulationError(f"{where}: no bat whose members all ran ({len(failed)} members "
                              f"failed{why}); see members.csv")  # fmt: skip
    return {"stats": cell_statistics(array[keep]), "bats": int(keep.sum()),
            "models": int(array.shape[1])}  # fmt: skip


def _against_seed(group: str, mph: float) -> dict[str, Any]:
    """Seed Table 9's experiment and LS-DYNA values where it has the cell."""
    from batball.specs.seed import load_seed_tables

    try:
        row = load_seed_tables().batted_ball_speed(group, mph)
    except SpecError:
        return {}
    return {"experiment_mph": row.bbs_exp / MPH, "seed_lsdyna_mph": row.bbs_fe / MPH}


__all__ = [
    "BatTargets", "EnsembleBat", "EnsembleJob", "EnsembleResult", "EnsembleStudy", "Z95",
    "cell_statistics", "drawn_bat", "ensemble_bats", "ensemble_summary", "load_ensemble_study",
    "probability_faster", "run_ensemble", "run_ensemble_job",
]  # fmt: skip
