"""``batball calibrate``: options, the run of a study and its report (table or JSON).

Import-light at module level (the CLI builds its parser from here); the heavy imports happen
when the command runs.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from batball.errors import SpecError

#: Parameters fitted by default, per model (``--free`` replaces them).
DEFAULT_FREE: dict[str, tuple[str, ...]] = {
    "mat006": ("bulk_modulus", "g0", "g_inf", "beta"),
    "prony3": ("g_inf", "g1", "beta1", "g2", "beta2", "g3", "beta3"),
    # foams: the curves' level, the hysteresis and the viscous coefficient
    "mat057": ("curve_scale", "hu", "shape", "damp"),
    "mat083": ("curve_scale", "hu", "shape", "damp"),
}

#: The example foam ball whose material starts a ``--model mat057/mat083`` calibration.
FOAM_EXAMPLES = {"mat057": "foam057", "mat083": "foam083"}


def add_calibrate_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``batball calibrate``."""
    p.add_argument("--ball", default="type1", help="embedded ball (type1, type2) or a TOML file")
    p.add_argument("--model", choices=sorted(DEFAULT_FREE), help="material model (ball's own)")
    p.add_argument("--targets", type=Path, help="TOML or CSV of targets (default: seed Tables 5-8)")
    p.add_argument("--fit-speeds", action="append", help="fit only targets at this speed; repeat")
    p.add_argument("--hourglass-type", type=int, help="the ball's hexes' hourglass control as "
                   "part of the model, LS-DYNA IHQ 1-5 (default: the ball file's, else viscous 1)")
    p.add_argument("--hourglass-coefficient", type=float, help="its QH/QM (default: the ball "
                   "file's, else 0.1); each replaces that value of the ball's own control")
    p.add_argument("--free", action="append", help="a parameter to fit; repeat (default: model's)")
    p.add_argument("--bound", action="append", default=[], help="NAME=LOWER:UPPER with units")
    p.add_argument("--quick", action="store_true", help="coarse mesh only, small budget")
    p.add_argument("--global-points", type=int, help="Latin-hypercube points (12; quick 6)")
    p.add_argument("--coarse-divisions", type=int, help="coarse ball mesh (8; quick 6)")
    p.add_argument("--fine-divisions", type=int, default=12, help="full ball mesh (12)")
    p.add_argument("--max-evaluations", type=int, help="least-squares evaluations (25; quick 10)")
    p.add_argument("--study", type=Path, help="SQLite study file (runs/calibrate-BALL-MODEL.db)")
    p.add_argument("--workers", type=int, help="local process pool size (default: CPU cores)")
    p.add_argument("--scheduler", help="Dask scheduler address instead of the local pool (one "
                   "you trust: Dask exchanges pickled data, and unpickling runs code)")
    p.add_argument("--save", type=Path, help="write the fitted ball as a spec TOML file")
    p.add_argument("--no-progress", action="store_true", help="no progress bars")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def optimiser_options(args: argparse.Namespace) -> Any:
    """The :class:`~batball.calibrate.OptimiserOptions` of the parsed options."""
    from batball.calibrate import OptimiserOptions

    quick = args.quick
    if args.max_evaluations is not None and args.max_evaluations < 1:
        raise SpecError("max-evaluations", args.max_evaluations, "an integer >= 1")
    options = OptimiserOptions(
        global_points=args.global_points if args.global_points is not None else 6 if quick else 12,
        coarse_divisions=(
            args.coarse_divisions if args.coarse_divisions is not None else 6 if quick else 8
        ),
        coarse_evaluations=(
            args.max_evaluations if args.max_evaluations is not None else 10 if quick else 25
        ),
        fine_divisions=None if quick else args.fine_divisions,
    )  # every value checked by OptimiserOptions itself
    if quick and args.fine_divisions != 12:  # the default: --quick never runs the full mesh
        raise SpecError("fine-divisions", args.fine_divisions, "no value with --quick")
    return options


def starting_ball(args: argparse.Namespace) -> Any:
    """The ball to calibrate, its material converted to ``--model`` if that differs."""
    from batball.materials.prony import prony_from_mat006
    from batball.specs import MaterialSpec, load_ball_spec

    ball = with_hourglass_options(load_ball_spec(args.ball), args)
    model = args.model or ball.material.law
    if model not in DEFAULT_FREE:
        raise SpecError("model", model, f"one of {', '.join(DEFAULT_FREE)}")
    if model == ball.material.law:
        return ball
    if model in FOAM_EXAMPLES:  # a seed ball as a foam: the example foam's material, its size
        material = load_ball_spec(FOAM_EXAMPLES[model]).material
        return dataclasses.replace(ball, material=material)
    if ball.material.law != "mat006" or not model.startswith("prony"):
        raise SpecError(
            "model", model, f"the ball's own law {ball.material.law}, prony3, mat057 or mat083"
        )
    values = prony_from_mat006(ball.material.values, n_terms=int(model.removeprefix("prony")))
    return dataclasses.replace(ball, material=MaterialSpec(law=model, values=values))


def with_hourglass_options(ball: Any, args: argparse.Namespace) -> Any:
    """``ball`` with the hourglass control of ``--hourglass-type``/``--hourglass-coefficient``
    as part of its model, or ``ball`` as it is when neither is given. A value not given is the
    ball's own, else the solver default (IHQ 1, coefficient 0.1): ``--hourglass-coefficient
    0.02`` on a ball with IHQ 4 keeps IHQ 4."""
    from batball.specs import BallHourglass

    # (callers that build their own namespace, such as the routes command, may leave them out)
    kind = getattr(args, "hourglass_type", None)
    coefficient = getattr(args, "hourglass_coefficient", None)
    if kind is None and coefficient is None:
        return ball
    own = ball.hourglass or BallHourglass(type=1, coefficient=0.1)
    hourglass = BallHourglass(type=own.type if kind is None else kind,
                              coefficient=own.coefficient if coefficient is None
                              else coefficient)  # fmt: skip
    return dataclasses.replace(ball, hourglass=hourglass)


def default_study(ball: Any) -> Path:
    """``runs/calibrate-BALL-LAW[-ihqN].db``: a ball whose model names its hourglass control
    gets its own study file (its runs have their own keys in any case)."""
    suffix = "" if ball.hourglass is None else f"-ihq{ball.hourglass.type}"
    return Path("runs") / f"calibrate-{ball.name}-{ball.material.law}{suffix}.db"


def select_targets(args: argparse.Namespace, ball_name: str) -> tuple[Any, Any]:
    """(all targets, the ones fitted): ``--targets`` or the seed's, filtered by ``--fit-speeds``."""
    from batball.calibrate import load_targets, seed_targets
    from batball.specs.ball import EMBEDDED_BALLS
    from batball.units import parse_quantity

    if args.targets is not None:
        targets = load_targets(args.targets)
    elif ball_name in EMBEDDED_BALLS:
        targets = seed_targets(ball_name)
    else:
        raise SpecError("targets", "none", "a --targets file for a ball other than type1/type2")
    if not args.fit_speeds:
        return targets, targets
    speeds = [parse_quantity(s, "velocity", field="fit-speeds") for s in args.fit_speeds]
    fitted = tuple(
        t for t in targets if t.speed == 0.0 or any(abs(t.speed - s) < 0.05 for s in speeds)
    )  # a quasi-static target (compression, speed 0) stays in the fit
    if all(t.speed == 0.0 for t in fitted):
        raise SpecError("fit-speeds", args.fit_speeds, "speeds that some target has")
    return targets, fitted


def run_calibrate_command(args: argparse.Namespace) -> int:
    """``batball calibrate``."""
    import json

    from batball.results.store import check_output_file

    ball = starting_ball(args)
    targets, fitted_targets = select_targets(args, ball.name)
    options = optimiser_options(args)
    study = args.study or default_study(ball)
    check_output_file("study", study)
    if args.save is not None:
        check_output_file("save", args.save)
    if args.workers is not None and args.workers < 0:
        raise SpecError("workers", args.workers, "0 (this process) or a positive pool size")
    fitted_ball, summary = run_calibration(
        ball, options, study=study, targets=targets, fitted=fitted_targets,
        free=args.free, bounds=args.bound, workers=args.workers, scheduler=args.scheduler,
        progress=not args.no_progress,
    )  # fmt: skip
    if args.save is not None:
        save_ball(fitted_ball, args.save)
        summary["saved"] = str(args.save)
    print(json.dumps(summary, indent=2) if args.json else describe_calibration(summary))
    return 0


def run_calibration(
    ball: Any,
    options: Any,
    *,
    study: Path,
    targets: Sequence[Any],
    fitted: Sequence[Any] | None = None,
    free: Sequence[str] | None = None,
    bounds: Sequence[str] = (),
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = False,
) -> tuple[Any, dict[str, Any]]:
    """Calibrate ``ball``'s material to ``targets``: the fitted ball and the JSON-able summary.

    What ``batball calibrate`` runs, for other callers (``batball reproduce``). ``fitted``: the
    targets the fit uses (default all; the others are predicted); ``free``: parameters to fit
    (default :data:`DEFAULT_FREE` of the ball's law); ``bounds``: ``NAME=LOWER:UPPER`` strings;
    ``study``: the SQLite study file, created or resumed (finished runs are not repeated);
    ``workers``: local pool size (default: CPU cores; 0 runs in this process).
    """
    from batball.calibrate import (
        CalibrationProblem,
        Evaluator,
        StudyStore,
        calibrate,
        make_parameter_space,
        open_executor,
        parse_bounds,
        predict,
    )
    from batball.calibrate.executors import default_workers

    start = time.perf_counter()
    targets = tuple(targets)
    fitted_targets = targets if fitted is None else tuple(fitted)
    law = ball.material.material_law
    space = make_parameter_space(
        law, ball.material.values, free or DEFAULT_FREE[law.name],
        bounds=parse_bounds(list(bounds), law),
    )  # fmt: skip
    study.parent.mkdir(parents=True, exist_ok=True)
    store = StudyStore(study)
    try:
        problem = CalibrationProblem(
            ball, space, fitted_targets, divisions=options.coarse_divisions
        )
        workers = default_workers() if workers is None else workers
        with open_executor(workers=workers, scheduler=scheduler) as executor:
            evaluator = Evaluator(store, executor, progress=progress)
            result = calibrate(problem, evaluator, options)
            everything = dataclasses.replace(result.problem, targets=targets)
            final = predict(everything, evaluator, result.best.values)
        fitted_ball = everything.candidate(result.best.values)
        summary = calibration_summary(
            ball=fitted_ball, space=space, targets=targets, fitted=fitted_targets, final=final,
            result=result, store=store, computed=evaluator.computed,
            wall_seconds=time.perf_counter() - start,
        )  # fmt: skip
    finally:
        store.close()
    summary["study"] = str(study)
    return fitted_ball, summary


def save_ball(ball: Any, path: Path) -> None:
    """Write ``ball`` as a spec TOML (readable by ``load_ball_spec`` and every test command)."""
    import tomli_w

    from batball.results.store import write_text_atomic
    from batball.specs.ball import ball_spec_to_toml_dict

    document = ball_spec_to_toml_dict(ball)
    document["description"] = f"calibrated by batball calibrate ({ball.material.law})"
    write_text_atomic(path, tomli_w.dumps(document))


def _percent(value: float | None, measured: float) -> float | None:
    """100 (value - measured) / measured, or None."""
    if value is None or value != value:
        return None
    return 100.0 * (value - measured) / measured


def _display(value: float | None, unit: str) -> float | None:
    """An SI value in ``unit`` ("" = dimensionless); None for a missing or NaN value."""
    from batball.units import to_unit

    if value is None or value != value:
        return None
    return to_unit(value, unit) if unit else value


def target_rows(targets: Sequence[Any], fitted: Sequence[Any], simulated: Any) -> list[dict]:
    """One JSON-able row per target: measured, fitted, seed LS-DYNA and both % differences."""
    from batball.units import to_unit

    rows = []
    for target, value in zip(targets, simulated, strict=True):
        unit = target.spec.display_unit
        rows.append(
            {
                "target": target.label,
                "quantity": target.quantity,
                "speed_mph": round(to_unit(target.speed, "mph"), 3) if target.speed else None,
                "unit": unit,
                "measured": _display(target.value, unit),
                "fitted": _display(float(value), unit),
                "seed_fe": _display(target.reference, unit),
                "fitted_pct": _percent(float(value), target.value),
                "seed_fe_pct": _percent(target.reference, target.value),
                "goal_pct": 100.0 * target.spec.tolerance,
                "used_in_fit": target in fitted,
            }
        )
    return rows


def calibration_summary(
    *,
    ball: Any,
    space: Any,
    targets: Sequence[Any],
    fitted: Sequence[Any],
    final: Any,
    result: Any,
    store: Any,
    computed: int,
    wall_seconds: float,
) -> dict[str, Any]:
    """The JSON-able outcome of a calibration."""
    return {
        "ball": ball.name,
        "model": space.law.name,
        "hourglass": None if ball.hourglass is None else dataclasses.asdict(ball.hourglass),
        "parameters": space.describe(final.values),
        "parameters_si": {p.name: final.values[p.name] for p in space.free},
        "targets": target_rows(targets, fitted, final.simulated),
        "stages": [
            {
                "name": s.name,
                "divisions": s.divisions,
                "candidates": s.n_candidates,
                "cost": s.best.cost,
            }
            for s in result.stages
        ],  # fmt: skip
        "divisions": result.problem.divisions,
        "runs_computed": computed,
        "runs_stored": len(store),
        "wall_seconds": wall_seconds,
    }


def describe_calibration(s: Mapping[str, Any]) -> str:
    """The text report: the per-target table and the fitted parameters."""
    hg = s.get("hourglass")
    form = "" if hg is None else f", hourglass IHQ {hg['type']} {hg['coefficient']}"
    lines = [
        f"calibration of ball {s['ball']} ({s['model']}{form}, final mesh divisions "
        f"{s['divisions']})",
        f"  {'target':<26} {'measured':>9} {'fitted':>9} {'seed FE':>9} {'fit %':>7} {'FE %':>7}",
    ]
    for r in s["targets"]:
        mark = "" if r["used_in_fit"] else "  (predicted)"
        name = f"{r['target']} [{r['unit'] or '-'}]"

        def num(v: float | None) -> str:
            return f"{v:9.4g}" if v is not None else f"{'-':>9}"

        def pct(v: float | None) -> str:
            return f"{v:+7.1f}" if v is not None else f"{'-':>7}"

        lines.append(
            f"  {name:<26} {num(r['measured'])} {num(r['fitted'])} {num(r['seed_fe'])} "
            f"{pct(r['fitted_pct'])} {pct(r['seed_fe_pct'])}{mark}"
        )
    lines.append(
        "  fitted parameters: " + ", ".join(f"{k} = {v}" for k, v in s["parameters"].items())
    )
    lines.append(
        f"  {s['runs_computed']} runs computed, {s['runs_stored']} in the study {s['study']}, "
        f"{s['wall_seconds']:.0f} s"
    )
    if "saved" in s:
        lines.append(f"  fitted ball written to {s['saved']}")
    return "\n".join(lines)
