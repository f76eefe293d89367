"""``batball reproduce``: the seed study rerun in one command, written as an HTML report.

A registry (:data:`REPRODUCTION_TESTS`) names each virtual test of the study, the seed tables it
fills and its runner. A runner runs (or reuses from the run store) the test and returns its runs:
summaries, the values keyed as the tables' rows (:mod:`batball.report.seed_comparison`) and the
figures to show.

Two sets of inputs are run. The model of record (the embedded balls ``type1-fit`` and
``type2-fit``, fitted to Tables 5-8, and the bat ``fitted``, fitted to Table 1 and Table 3's hoop
modes) fills every table and is compared with the experiment. The solver check runs the seed's own
Table 4 balls with the hourglass control that reproduces its LS-DYNA (IHQ 4, QM 0.01) on the
reconstructed bat, and is compared with the seed's LS-DYNA column. A test whose code is not there
yet has no runner, or raises :class:`NotYetAvailableError`, and the report says "not yet available"
where its numbers would be: no value in the report comes from anywhere but a run.

Output, in ``out_dir``: ``index.html`` (static, inline CSS), ``summary.json``, ``<table>.csv`` per
table and ``figures/*.png``.
"""

from __future__ import annotations

import csv
import json
import shutil
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from batball.report.runs import ReportFigure, TestRun
from batball.report.seed_comparison import (
    BALL_CASES,
    CALIBRATED_BALLS,
    ComparisonTable,
    comparison_tables,
)
from batball.results.store import load_cached_summary, write_json_atomic, write_text_atomic
from batball.specs import BallSpec, BatSpec, load_ball_spec, load_bat_spec, load_seed_tables
from batball.units import IN, PSI


@dataclass(frozen=True)
class MeshSizes:
    """Mesh density of every test: ball divisions (12 = the seed's 12,096 hexes), bat shells."""

    ball_divisions: int
    bat_circumferential: int
    bat_axial_size: float  # m
    #: the barrel compression's static contact solve is the costliest bat test: its own mesh
    barrel_circumferential: int = 16
    barrel_axial_size: float = 0.4 * IN  # m
    #: batted-ball speed (coupled runs): ball divisions, bat shells around, axial size [m]
    bbs: tuple[int, int, float] = (4, 16, 0.5 * IN)
    #: the meshes the model of record was fitted and checked on: only these get verdicts
    converged: bool = False


#: The full-size meshes: the seed's 12,096-hex ball (the mesh the balls were fitted on); the bat
#: mesh of ``batball props``/``modal``/``barrel``, 48 x 0.1 in (on 32 x 0.2 in the barrel test's
#: loads are 6-10 % stiff, docs/notes/barrel.md), also for the batted-ball speed (on 32 x 0.2 in
#: the seed's type-1 ball's BBS is 0.7 mph lower, docs/fidelity.md).
FULL_MESHES = MeshSizes(
    ball_divisions=12,
    bat_circumferential=48,
    bat_axial_size=0.1 * IN,
    barrel_circumferential=48,
    barrel_axial_size=0.1 * IN,
    bbs=(12, 48, 0.1 * IN),
    converged=True,
)
#: ``--quick``: coarse meshes for CI and a first look (1,512 hexes per ball, 2,832 bat shells;
#: 1,512 hexes on 16 x 0.5 in shells for the batted-ball speed). Its values are indicative.
QUICK_MESHES = MeshSizes(ball_divisions=6, bat_circumferential=16, bat_axial_size=0.25 * IN,
                         bbs=(6, 16, 0.5 * IN))  # fmt: skip

#: The solver check's ball numerics: the hourglass control with which the seed's Table 4 balls
#: reproduce its LS-DYNA Tables 5-8 (docs/notes/ball-impact.md).
CHECK_NUMERICS: dict[str, Any] = {"hourglass_type": 4, "hourglass_coefficient": 0.01}

#: The compression test's contact scale SFS for a foam ball (``batball compression --sfs``).
FOAM_SFS = 5.0


def log_to_stderr(message: str) -> None:
    """Progress line on stderr."""
    print(f"[reproduce] {message}", file=sys.stderr, flush=True)


@dataclass(frozen=True)
class ReproduceOptions:
    """What to run and where.

    Attributes:
        out_dir: the report folder (created).
        runs_dir: the run store; runs with unchanged inputs are reused from it.
        meshes: mesh sizes (:data:`FULL_MESHES` or :data:`QUICK_MESHES`).
        reuse: reuse stored runs (False reruns everything).
        balls, bat: the model of record (embedded names or spec files; each ball's spec names
            the seed ball type it models).
        check_balls, check_bat: the solver check's (the seed's Table 4 balls, the reconstructed
            bat).
        log: progress sink.
        command: the command line, as the report states it.
        calibrate: also refit both seed balls with MAT_006 (``--calibrate``; a refit section).
        workers: the calibration's local process pool (None: CPU cores; 0: this process).
    """

    out_dir: Path
    runs_dir: Path
    meshes: MeshSizes = FULL_MESHES
    reuse: bool = True
    balls: tuple[str, ...] = ("type1-fit", "type2-fit")
    bat: str = "fitted"
    check_balls: tuple[str, ...] = ("type1", "type2")
    check_bat: str = "default"
    log: Callable[[str], None] = log_to_stderr
    command: str = "batball reproduce"
    calibrate: bool = False
    workers: int | None = None


@dataclass(frozen=True)
class RunnerOutput:
    """What a runner returns: its runs and any figures drawn from several of them."""

    runs: tuple[TestRun, ...]
    figures: tuple[ReportFigure, ...] = ()


@dataclass(frozen=True)
class Inputs:
    """The specs every runner shares (loaded once) and the options."""

    options: ReproduceOptions
    balls: tuple[BallSpec, ...]
    bat: BatSpec
    check_balls: tuple[BallSpec, ...] = ()
    check_bat: BatSpec | None = None

    @property
    def figures_dir(self) -> Path:
        return self.options.out_dir / "figures"


class NotYetAvailableError(Exception):
    """A registered test whose code is not in this installation yet; the message says why."""


class SkippedError(NotYetAvailableError):
    """A test left out of this invocation by its options; the message says how to include it."""


Runner = Callable[[Inputs], RunnerOutput]


@dataclass(frozen=True)
class ReproductionTest:
    """An entry of the registry: a virtual test of the study and how it fills the tables.

    Attributes:
        name: the name users type (``"ccor"``); tables refer to it.
        title: what it is, with its standard.
        tables: ids of the tables it fills (``"table5"``).
        run: the runner, or None while the test does not exist.
        missing: why it is not yet available (when ``run`` is None).
    """

    name: str
    title: str
    tables: tuple[str, ...]
    run: Runner | None
    missing: str = ""


@dataclass(frozen=True)
class TestOutcome:
    """A registry test after the reproduction: its runs, or why there are none."""

    test: ReproductionTest
    runs: tuple[TestRun, ...] = ()
    figures: tuple[ReportFigure, ...] = ()
    missing: str = ""
    seconds: float = 0.0
    skipped: bool = False  # left out by the options (``missing`` says how to include it)

    @property
    def available(self) -> bool:
        return not self.missing


def timed_run(
    inputs: Inputs, label: str, call: Callable[[], tuple[dict[str, Any], Path]]
) -> tuple[dict[str, Any], Path, bool, float]:
    """Call a ``run_*_test``; returns its summary, folder, whether it was reused and the seconds.

    A run counts as reused when its folder held a complete summary before the call.
    """
    runs_dir = inputs.options.runs_dir
    stored = (
        {p.parent.name for p in runs_dir.glob("*/summary.json")} if runs_dir.is_dir() else set()
    )
    inputs.options.log(f"{label} ...")
    start = time.perf_counter()
    summary, folder = call()
    seconds = time.perf_counter() - start
    reused = (
        inputs.options.reuse and folder.name in stored and load_cached_summary(folder) is not None
    )
    inputs.options.log(f"{label}: {'reused' if reused else 'ran'} in {seconds:.1f} s ({folder})")
    return summary, folder, reused, seconds


def lab_run(
    inputs: Inputs, label: str, name: str, subjects: dict[str, Any], **options: Any
) -> tuple[dict[str, Any], Path, bool, float]:
    """Run (or reuse) the registry's test ``name`` with ``options`` (SI lengths as metres,
    :func:`metres`), timed as :func:`timed_run` times it: the same run ``batball <name>`` makes
    with those options. A test whose modules are not in this installation is not yet available.
    """
    from batball.lab.registry import LAB_TESTS

    test = LAB_TESTS[name]
    setup = test.setup(**options)
    try:
        return timed_run(
            inputs, label,
            lambda: test.run(subjects, setup, runs_dir=inputs.options.runs_dir,
                             reuse=inputs.options.reuse, progress=None),
        )  # fmt: skip
    except ModuleNotFoundError as exc:
        reason = f"the {name} test is not in this installation ({exc})"
        raise NotYetAvailableError(reason) from exc


def metres(value: float) -> Any:
    """A length in metres as a quantity, for a registry option (which takes no bare number)."""
    from batball.units import unit_registry

    return unit_registry().Quantity(value, "m")


def run_props(inputs: Inputs) -> RunnerOutput:
    """Table 1: weight, balance point and MOI of the bat (ASTM F2398)."""
    m = inputs.options.meshes
    summary, folder, reused, seconds = lab_run(
        inputs, "props (bat)", "props", {"bat": inputs.bat},
        circumferential=m.bat_circumferential, axial_size=metres(m.bat_axial_size),
    )  # fmt: skip
    values = {
        "props/weight": summary["weight_oz"],
        "props/moi": summary["moi_pivot_oz_in2"],
        "props/balance_point": summary["balance_point_in"],
    }
    figure = ReportFigure(
        folder / "bat.png",
        "bat_mesh.png",
        f"The bat's shell mesh ({summary['n_shells']:,} shells), by part",
        "bat",
    )
    return RunnerOutput((TestRun("bat", summary, folder, reused, seconds, values, (figure,)),))


def run_modal(inputs: Inputs) -> RunnerOutput:
    """Table 3: the bat's first two free-free bending and hoop frequencies."""
    m = inputs.options.meshes
    summary, folder, reused, seconds = lab_run(
        inputs, "modal (bat)", "modal", {"bat": inputs.bat},
        circumferential=m.bat_circumferential, axial_size=metres(m.bat_axial_size),
    )  # fmt: skip
    values = {}
    for kind in ("bending", "hoop"):
        for k, frequency in enumerate(summary[f"{kind}_hz"][:2]):
            values[f"modal/{kind}_{k + 1}"] = float(frequency)
    figure = ReportFigure(
        folder / "modes.png",
        "bat_modes.png",
        "The bat's first bending and hoop mode shapes (free-free)",
        "modes",
    )
    return RunnerOutput((TestRun("bat", summary, folder, reused, seconds, values, (figure,)),))


def material_values(ball: BallSpec, prefix: str = "") -> dict[str, float]:
    """Table 4 keys of the MAT_006 constants a ball was run with, in psi and 1/s."""
    units = {"bulk_modulus": PSI, "g0": PSI, "g_inf": PSI, "beta": 1.0}
    return {
        f"{prefix}material/{ball.name}/{name}": ball.material.values[name] / scale
        for name, scale in units.items()
        if name in ball.material.values
    }


#: Quantities of ``batball calibrate``'s targets -> the key prefixes of the report's tables.
CALIBRATION_QUANTITIES = {
    "ccor": "ccor",
    "dynamic_stiffness": "ds",
    "peak_force": "peak",
    "contact_time": "contact",
}


def calibration_options(meshes: MeshSizes) -> Any:
    """The optimiser options of the reproduction: ``batball calibrate``'s defaults for the full
    meshes, its ``--quick`` settings (coarse mesh only, small budget) for coarser ones."""
    from batball.calibrate import OptimiserOptions

    if meshes.ball_divisions >= FULL_MESHES.ball_divisions:
        return OptimiserOptions(fine_divisions=meshes.ball_divisions)
    return OptimiserOptions(
        global_points=6,
        coarse_divisions=meshes.ball_divisions,
        coarse_evaluations=10,
        fine_divisions=None,
    )


def calibration_values(ball: BallSpec, summary: dict[str, Any]) -> dict[str, float]:
    """The report's values of one calibration: the fitted constants
    (``calibrated/material/type1/g0``, psi or 1/s) and, per target, the fitted ball's simulated
    value (``calibrated/ds/type1/95mph``, in the target's unit)."""
    values = material_values(ball, "calibrated/")
    for row in summary["targets"]:
        prefix = CALIBRATION_QUANTITIES.get(row["quantity"])
        if prefix is None or row["fitted"] is None:
            continue
        values[f"calibrated/{prefix}/{ball.name}/{round(row['speed_mph'])}mph"] = row["fitted"]
    return values


def run_calibrate(inputs: Inputs) -> RunnerOutput:
    """The refit section: each seed ball's MAT_006 constants fitted to Tables 5-8 experiments.

    The SQLite study lives in the run store as ``calibrate-BALL-MODEL.db`` (the name
    ``batball calibrate`` uses under ``runs/``): it is keyed by each run's inputs, so a rerun
    reads every finished evaluation back and only computes what is new. ``--no-reuse`` starts a
    fresh study file (``...-fresh.db``, replaced each time) and leaves the shared one alone.
    """
    if not inputs.options.calibrate:
        raise SkippedError("skipped: add --calibrate to refit the seed's balls with MAT_006")
    from batball.calibrate import seed_targets
    from batball.calibrate.command import run_calibration

    options = calibration_options(inputs.options.meshes)
    runs = []
    for ball in inputs.check_balls:
        suffix = "" if inputs.options.reuse else "-fresh"
        study = inputs.options.runs_dir / f"calibrate-{ball.name}-{ball.material.law}{suffix}.db"
        if not inputs.options.reuse:
            study.unlink(missing_ok=True)
        inputs.options.log(f"calibrate {ball.name} ({study}) ...")
        start = time.perf_counter()
        fitted, summary = run_calibration(
            ball, options, study=study, targets=seed_targets(ball.name),
            workers=inputs.options.workers,
        )  # fmt: skip
        seconds = time.perf_counter() - start
        reused = summary["runs_computed"] == 0
        inputs.options.log(
            f"calibrate {ball.name}: {summary['runs_computed']} runs computed, "
            f"{summary['runs_stored']} in the study, {seconds:.1f} s"
        )
        runs.append(
            TestRun(ball.name, summary, study, reused, seconds, calibration_values(fitted, summary))
        )
    return RunnerOutput(tuple(runs))


def impact_runs(inputs: Inputs, balls: tuple[BallSpec, ...], prefix: str,
                **numerics: Any) -> list[TestRun]:  # fmt: skip
    """Each ball at 95 and 110 mph against the rigid half-cylinder (ASTM F2845); values keyed
    ``prefix + "ccor/type1/95mph"`` and so on."""
    runs = []
    for ball in balls:
        for name, mph in BALL_CASES:
            if name != ball.name:
                continue
            label = f"{prefix}{ball.name} at {mph} mph"
            summary, folder, reused, seconds = lab_run(
                inputs, f"ccor {label}", "ccor", {"ball": ball}, speed=f"{mph} mph",
                divisions=inputs.options.meshes.ball_divisions, **numerics,
            )  # fmt: skip
            case = f"{ball.name}/{mph}mph"
            values = {
                f"{prefix}ccor/{case}": summary["ccor"],
                f"{prefix}ds/{case}": summary["ds_lbf_per_in"],
                f"{prefix}peak/{case}": summary["peak_force_lbf"],
                f"{prefix}contact/{case}": summary["contact_time_ms"],
            }
            figure = ReportFigure(
                folder / "force_time.png",
                f"force_time_{prefix.strip('/')}{'_' if prefix else ''}{ball.name}_{mph}mph.png",
                f"Load-cell force, {ball.name} at {mph} mph"
                + (" (the seed's ball, solver check)" if prefix else ""),
                "force-time" if not prefix else "check",
            )
            runs.append(TestRun(label, summary, folder, reused, seconds, values, (figure,)))
    return runs


def run_ccor(inputs: Inputs) -> RunnerOutput:
    """Tables 5-8: the model of record's balls at 95 and 110 mph against the half-cylinder."""
    from batball.report.reproduce_figures import plot_energy_histories, plot_force_time_cases

    runs = impact_runs(inputs, inputs.balls, "")
    inputs.figures_dir.mkdir(parents=True, exist_ok=True)
    derived = (
        *plot_force_time_cases(inputs.figures_dir, runs),
        plot_energy_histories(inputs.figures_dir, runs),
    )
    return RunnerOutput(tuple(runs), derived)


def run_ccor_check(inputs: Inputs) -> RunnerOutput:
    """Solver check, Tables 4-8: the seed's Table 4 balls (IHQ 4, QM 0.01) on the cylinder."""
    runs = impact_runs(inputs, inputs.check_balls, "check/", **CHECK_NUMERICS)
    constants = {k: v for ball in inputs.check_balls for k, v in
                 material_values(ball, "check/").items()}  # fmt: skip
    if runs:
        first = runs[0]
        runs[0] = TestRun(first.label, first.summary, first.folder, first.reused, first.seconds,
                          {**first.values, **constants}, first.figures)  # fmt: skip
    return RunnerOutput(tuple(runs))


def run_barrel(inputs: Inputs) -> RunnerOutput:
    """Table 2: interference pre-stress, then barrel compression at four orientations."""
    m = inputs.options.meshes
    summary, folder, reused, seconds = lab_run(
        inputs, "barrel compression (bat)", "barrel", {"bat": inputs.bat},
        circumferential=m.barrel_circumferential, axial_size=metres(m.barrel_axial_size),
    )  # fmt: skip
    values = {
        "barrel/preload": summary["preload_lbf"],
        "barrel/final_load": summary["final_load_lbf"],
    }
    figures = (
        ReportFigure(
            folder / "prestress.png",
            "barrel_prestress.png",
            "Pre-stress of the insert's interference fit in the barrel and insert",
            "prestress",
        ),
        ReportFigure(
            folder / "force_travel.png",
            "barrel_force_travel.png",
            "Barrel compression force against platen travel",
            "prestress",
        ),
    )
    return RunnerOutput((TestRun("bat", summary, folder, reused, seconds, values, figures),))


def run_compression(inputs: Inputs) -> RunnerOutput:
    """Ball compression (ASTM F1888) of each ball; the seed publishes no values to compare."""
    runs = []
    for ball in inputs.balls:
        # a foam's contact penalty (its E_eff, fifty times below a MAT_006 ball's K) lets the
        # plates sink 0.03 in at SFS 1; SFS 5 keeps it under 0.01 in (docs/notes/foams.md)
        contact = {"sfs": FOAM_SFS} if ball.material.curves else {}
        summary, folder, reused, seconds = lab_run(
            inputs, f"compression {ball.name}", "compression", {"ball": ball},
            divisions=inputs.options.meshes.ball_divisions, **contact,
        )  # fmt: skip
        figure = ReportFigure(
            folder / "force_displacement.png",
            f"compression_{ball.name}.png",
            f"Compression force against displacement, {ball.name}",
            "compression",
        )
        runs.append(
            TestRun(
                ball.name,
                summary,
                folder,
                reused,
                seconds,
                {f"compression/{ball.name}": summary["compression_lbf"]},
                (figure,),
            )
        )
    return RunnerOutput(tuple(runs))


def bbs_runs(inputs: Inputs, bat: BatSpec, balls: tuple[BallSpec, ...], prefix: str,
             **numerics: Any) -> list[TestRun]:  # fmt: skip
    """Each ball fired at 95 and 110 mph at ``bat`` pivoting 6 in from the knob; values keyed
    ``prefix + "bbs/type1/95mph"``."""
    sizes = inputs.options.meshes.bbs
    runs = []
    for ball in balls:
        for name, mph in BALL_CASES:
            if name != ball.name:
                continue
            label = f"{prefix}{ball.name} at {mph} mph"
            summary, folder, reused, seconds = lab_run(
                inputs, f"bbs {label}", "bbs", {"bat": bat, "ball": ball},
                speed=f"{mph} mph", divisions=sizes[0], circumferential=sizes[1],
                axial_size=metres(sizes[2]), **numerics,
            )  # fmt: skip
            figure = ReportFigure(
                folder / "force_time.png",
                f"bbs_{prefix.strip('/')}{'_' if prefix else ''}{ball.name}_{mph}mph.png",
                f"Ball-bat contact force, {ball.name} at {mph} mph"
                + (" (the seed's ball, solver check)" if prefix else ""),
                "bbs" if not prefix else "check",
            )
            values = {f"{prefix}bbs/{ball.name}/{mph}mph": summary["bbs_mph"]}
            runs.append(TestRun(label, summary, folder, reused, seconds, values, (figure,)))
    return runs


def run_batted_ball_speed(inputs: Inputs) -> RunnerOutput:
    """Table 9: the model of record's balls at 95 and 110 mph at its bat (ASTM F2219)."""
    return RunnerOutput(tuple(bbs_runs(inputs, inputs.bat, inputs.balls, "")))


def run_bbs_check(inputs: Inputs) -> RunnerOutput:
    """Solver check, Table 9: the seed's Table 4 balls (IHQ 4, QM 0.01) at the reconstructed
    bat."""
    assert inputs.check_bat is not None
    return RunnerOutput(tuple(bbs_runs(inputs, inputs.check_bat, inputs.check_balls, "check/",
                                       **CHECK_NUMERICS)))  # fmt: skip


#: The study's virtual tests in page order, keyed by the names users type.
REPRODUCTION_TESTS: dict[str, ReproductionTest] = {
    test.name: test
    for test in (
        ReproductionTest(
            "props", "bat weight, balance point, MOI (ASTM F2398)", ("table1",), run_props
        ),
        ReproductionTest(
            "barrel",
            "insert pre-stress and barrel compression (seed Table 2)",
            ("table2",),
            run_barrel,
        ),
        ReproductionTest(
            "modal", "free-free bending and hoop modes of the bat", ("table3",), run_modal
        ),
        ReproductionTest(
            "ccor",
            "CCOR, dynamic stiffness, peak force, contact time (ASTM F2845)",
            ("table5", "table6", "table7", "table8"),
            run_ccor,
        ),
        ReproductionTest(
            "compression", "ball compression (ASTM F1888)", ("compression",), run_compression
        ),
        ReproductionTest(
            "bbs",
            "batted-ball speed at the 6-in location (ASTM F2219)",
            ("table9",),
            run_batted_ball_speed,
        ),
        ReproductionTest(
            "ccor-check",
            "solver check: the seed's balls on the half-cylinder (ASTM F2845)",
            ("table4", "check_impact"),
            run_ccor_check,
        ),
        ReproductionTest(
            "bbs-check",
            "solver check: the seed's balls at the reconstructed bat (ASTM F2219)",
            ("check_table9",),
            run_bbs_check,
        ),
        ReproductionTest(
            "calibrate",
            "refit of the seed's balls (MAT_006) to its CCOR, DS, peak, contact time",
            tuple(f"calibrated_{ball}" for ball in CALIBRATED_BALLS),
            run_calibrate,
        ),
    )
}


def run_test(test: ReproductionTest, inputs: Inputs) -> TestOutcome:
    """Run one registry test; a missing runner or module gives an outcome saying why."""
    if test.run is None:
        inputs.options.log(f"{test.name}: not yet available ({test.missing})")
        return TestOutcome(test, missing=test.missing)
    start = time.perf_counter()
    try:
        output = test.run(inputs)
    except SkippedError as exc:
        inputs.options.log(f"{test.name}: {exc}")
        return TestOutcome(test, missing=str(exc), skipped=True)
    except NotYetAvailableError as exc:
        inputs.options.log(f"{test.name}: not yet available ({exc})")
        return TestOutcome(test, missing=str(exc))
    return TestOutcome(test, output.runs, output.figures, seconds=time.perf_counter() - start)


@dataclass(frozen=True)
class Reproduction:
    """Everything the report shows."""

    options: ReproduceOptions
    inputs: Inputs
    outcomes: tuple[TestOutcome, ...]
    tables: tuple[ComparisonTable, ...]
    values: dict[str, float]
    environment: dict[str, Any]
    seconds: float
    figures: tuple[ReportFigure, ...] = field(default=())

    @property
    def indicative(self) -> bool:
        """Whether the meshes are coarser than the converged ones (no verdicts then)."""
        return not self.options.meshes.converged


def reproduce(
    options: ReproduceOptions, *, tests: dict[str, ReproductionTest] | None = None
) -> Reproduction:
    """Run every registry test (or ``tests``), then write the report into ``options.out_dir``."""
    from batball.report.provenance import environment

    start = time.perf_counter()
    inputs = Inputs(
        options,
        tuple(load_ball_spec(name) for name in options.balls),
        load_bat_spec(options.bat),
        tuple(load_ball_spec(name) for name in options.check_balls),
        load_bat_spec(options.check_bat),
    )
    outcomes = tuple(run_test(t, inputs) for t in (tests or REPRODUCTION_TESTS).values())
    values = {k: v for o in outcomes for r in o.runs for k, v in r.values.items()}
    figures = tuple(
        f for o in outcomes for f in (*(g for r in o.runs for g in r.figures), *o.figures)
    )
    result = Reproduction(
        options,
        inputs,
        outcomes,
        comparison_tables(load_seed_tables(), refit=options.calibrate),
        values,
        environment(),
        time.perf_counter() - start,
        figures,
    )
    write_report(result)
    return result


def copy_figures(result: Reproduction) -> None:
    """Copy each figure into ``out_dir/figures`` (figures drawn there already stay)."""
    target = result.options.out_dir / "figures"
    target.mkdir(parents=True, exist_ok=True)
    for figure in result.figures:
        destination = target / figure.name
        if figure.source.resolve() != destination.resolve():
            shutil.copyfile(figure.source, destination)


def write_report(result: Reproduction) -> None:
    """index.html, summary.json, one CSV per table and the figures, in ``out_dir``."""
    from batball.report.reproduce_html import render_report

    out_dir = result.options.out_dir
    out_dir.mkdir(parents=True, exist_ok=True)
    copy_figures(result)
    for table in result.tables:
        write_table_csv(out_dir / f"{table.id}.csv", table, result.values, result.indicative)
    write_json_atomic(out_dir / "summary.json", summary_document(result))
    write_text_atomic(out_dir / "index.html", render_report(result))
    result.options.log(
        f"report: {(out_dir / 'index.html').as_posix()} ({result.seconds:.1f} s in all)"
    )


def write_table_csv(path: Path, table: ComparisonTable, values: dict[str, float],
                    indicative: bool = False) -> None:  # fmt: skip
    """One table as CSV: quantity, unit, experiment, seed LS-DYNA, batball, the % differences."""
    import io

    from batball.report.seed_comparison import table_records

    records = table_records(table, values, indicative=indicative)
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(records[0]), lineterminator="\n")
    writer.writeheader()
    for record in records:
        writer.writerow({k: ("" if v is None else v) for k, v in record.items()})
    write_text_atomic(path, buffer.getvalue())


def summary_document(result: Reproduction) -> dict[str, Any]:
    """summary.json: options, environment, each test's runs (or why none), every table."""
    from batball.report.reproduce_html import verdict_counts
    from batball.report.seed_comparison import table_records

    m = result.options.meshes
    return {
        "command": result.options.command,
        "meshes": {
            "ball_divisions": m.ball_divisions,
            "bat_circumferential": m.bat_circumferential,
            "bat_axial_size_in": m.bat_axial_size / IN,
            "bbs_ball_divisions": m.bbs[0],
            "bbs_bat_circumferential": m.bbs[1],
            "bbs_bat_axial_size_in": m.bbs[2] / IN,
            "converged": m.converged,
        },
        "model_of_record": {
            "balls": list(result.options.balls),
            "bat": result.options.bat,
        },
        "solver_check": {
            "balls": list(result.options.check_balls),
            "bat": result.options.check_bat,
            "numerics": CHECK_NUMERICS,
        },
        "verdicts": verdict_counts(result),
        "environment": result.environment,
        "wall_seconds": result.seconds,
        "tests": {
            o.test.name: {
                "title": o.test.title,
                "tables": list(o.test.tables),
                "available": o.available,
                "skipped": o.skipped,
                "missing": o.missing or None,
                "seconds": o.seconds,
                "runs": [
                    {
                        "label": r.label,
                        "reused": r.reused,
                        "seconds": r.seconds,
                        "run_folder": r.folder.as_posix(),
                        "summary": r.summary,
                    }
                    for r in o.runs
                ],
            }
            for o in result.outcomes
        },
        "tables": {
            t.id: {
                "title": t.title,
                "test": t.test,
                "note": t.note,
                "section": t.section,
                "rows": table_records(t, result.values, indicative=result.indicative),
            }
            for t in result.tables
        },
    }


def dump_summary(result: Reproduction) -> str:
    """summary.json's text (for ``--json``)."""
    return json.dumps(summary_document(result), indent=2, default=str)
