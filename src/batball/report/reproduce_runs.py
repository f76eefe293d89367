"""The runners of ``batball reproduce``: each runs (or reuses) one virtual test of the study through
the lab registry, for the model of record or the solver check, and returns its runs with the
values keyed as the tables' rows (:mod:`batball.report.seed_comparison`).
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any

from batball.report.reproduce_setup import (
    CHECK_BAT_SHELL,
    CHECK_NUMERICS,
    FOAM_SFS,
    FULL_MESHES,
    Inputs,
    MeshSizes,
    RunnerOutput,
    SkippedError,
    lab_run,
    metres,
)
from batball.report.runs import ReportFigure, TestRun
from batball.report.seed_comparison import (
    BALL_CASES,
)
from batball.specs import BallSpec, BatSpec
from batball.units import PSI


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
    if runs:  # the constants the check ran with, carried by its first run
        runs[0] = dataclasses.replace(runs[0], values={**runs[0].values, **constants})
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
                                       shell=CHECK_BAT_SHELL, **CHECK_NUMERICS)))  # fmt: skip
