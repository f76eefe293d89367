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
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from batball.report.reproduce_runs import (
    run_barrel,
    run_batted_ball_speed,
    run_bbs_check,
    run_calibrate,
    run_ccor,
    run_ccor_check,
    run_compression,
    run_modal,
    run_props,
)
from batball.report.reproduce_setup import (
    CHECK_NUMERICS,
    Inputs,
    NotYetAvailableError,
    ReproduceOptions,
    Runner,
    SkippedError,
)
from batball.report.runs import ReportFigure, TestRun
from batball.report.seed_comparison import (
    CALIBRATED_BALLS,
    ComparisonTable,
    comparison_tables,
)
from batball.results.store import write_json_atomic, write_text_atomic
from batball.specs import load_ball_spec, load_bat_spec, load_seed_tables
from batball.units import IN


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

    @property
    def warnings(self) -> list[str]:
        """What the reader should know before the numbers: coarse meshes behind numbers the
        report sets beside the experiment, and each run's own warnings, with its label."""
        out = []
        if self.indicative:
            out.append("coarse meshes (--quick): every number beside the experiment is "
                       "indicative and the report gives no verdicts; run without --quick")
        for outcome in self.outcomes:
            for run in outcome.runs:
                out += [f"{outcome.test.name} {run.label}: {w}"
                        for w in run.summary.get("warnings", [])]  # fmt: skip
        return out


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
        "warnings": result.warnings,
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
