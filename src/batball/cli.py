"""The command line: ``batball <test> ...``; ``--json`` prints one JSON object on stdout.

Bad input exits with status 2 and one line naming the field, the value and what is allowed; a
numerical failure exits with status 3 and says where and when.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from batball.errors import SimulationError, SpecError

#: Default speeds: the seed's lower CCOR speed (F2845) and F1887's nominal 60 mph.
DEFAULT_SPEEDS = {"ccor": "95 mph", "cor": "60 mph"}


def add_impact_parser(sub: Any, test: str, help_text: str) -> None:
    """The options of a ball-impact test."""
    p = sub.add_parser(test, help=help_text, description=help_text)
    p.add_argument("--ball", default="type1", help="embedded ball (type1, type2) or a TOML file")
    p.add_argument(
        "--speed",
        default=DEFAULT_SPEEDS[test],
        help=f"inbound speed with its unit (default {DEFAULT_SPEEDS[test]!r})",
    )
    p.add_argument(
        "--divisions",
        type=int,
        default=12,
        help="ball mesh size: 12 gives the seed's 12,096 hexes (default 12)",
    )
    p.add_argument("--hourglass-type", type=int, default=1, help="LS-DYNA IHQ 1-5 (default 1)")
    p.add_argument("--hourglass-coefficient", type=float, default=0.1, help="QH/QM (0.1)")
    p.add_argument("--no-bulk-viscosity", action="store_true", help="switch bulk viscosity off")
    p.add_argument("--soft", type=int, default=0, help="contact SOFT option, 0 or 1 (default 0)")
    p.add_argument(
        "--contact-threshold",
        type=float,
        default=0.01,
        help="contact-time level as a fraction of the peak force (default 0.01)",
    )
    add_precision_option(p)
    add_store_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=run_impact_command, test=test)


def add_precision_option(p: Any) -> None:
    """``--precision``: the ball's element arithmetic (docs/precision.md)."""
    p.add_argument(
        "--precision",
        choices=("single", "double"),
        default="single",
        help="element arithmetic of the ball (default single, as LS-DYNA's default executable; "
        "results agree with double to about 1e-6 in CCOR, docs/precision.md)",
    )


def add_store_options(p: Any) -> None:
    """Where runs are stored, and whether a stored run with the same inputs is reused."""
    p.add_argument("--runs-dir", type=Path, default=Path("runs"), help="results store (runs/)")
    p.add_argument("--no-reuse", action="store_true", help="run even if the same run is stored")


def build_parser() -> argparse.ArgumentParser:
    """The ``batball`` parser with its subcommands."""
    parser = argparse.ArgumentParser(prog="batball", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    add_reproduce_parser(sub)  # the main job first in the help
    add_impact_parser(
        sub, "ccor", "CCOR and dynamic stiffness against the 2.63-in half-cylinder (ASTM F2845)"
    )
    add_impact_parser(sub, "cor", "COR against a rigid flat wall (ASTM F1887)")
    add_props_parser(sub)
    add_fit_bat_parser(sub)
    add_modal_parser(sub)
    add_compression_parser(sub)
    add_calibrate_parser(sub)
    add_barrel_parser(sub)
    add_export_parser(sub)
    add_run_deck_parser(sub)
    add_bbs_parser(sub)
    add_routes_parsers(sub)
    return parser


def add_compression_parser(sub: Any) -> None:
    """``batball compression``: the ball's compression between flat plates (ASTM F1888)."""
    help_text = "ball compression: force at 0.25 in between flat plates at 1 in/min (ASTM F1888)"
    p = sub.add_parser("compression", help=help_text, description=help_text)
    p.add_argument("--ball", default="type1", help="embedded ball (type1, type2) or a TOML file")
    p.add_argument("--displacement", default="0.25 in", help="plate travel (default '0.25 in')")
    p.add_argument("--rate", default="1 in/min", help="plate speed (default '1 in/min')")
    p.add_argument(
        "--divisions", type=int, default=12, help="ball mesh size (12 = 12,096 hexes; default 12)"
    )
    p.add_argument("--hourglass-type", type=int, default=1, help="LS-DYNA IHQ 1-5 (default 1)")
    p.add_argument("--hourglass-coefficient", type=float, default=0.1, help="QH/QM (0.1)")
    p.add_argument(
        "--quasi-static-ratio",
        type=float,
        default=60.0,
        help="loading time in radians of the mass-scaled squash mode (default 60)",
    )
    p.add_argument(
        "--sfs", type=float, default=1.0,
        help="contact penalty scale SFS (default 1; foam balls need about 5)",
    )  # fmt: skip
    add_store_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=run_compression_command)


def run_compression_command(args: argparse.Namespace) -> int:
    """``batball compression``."""
    from batball.lab.compression import CompressionSetup
    from batball.lab.compression_run import run_compression_test
    from batball.lab.impact import ContactOptions
    from batball.solvers.explicit import HourglassControl
    from batball.specs import load_ball_spec
    from batball.units import parse_quantity

    ball = load_ball_spec(args.ball)
    setup = CompressionSetup(
        displacement=parse_quantity(args.displacement, "length", field="displacement"),
        rate=parse_quantity(args.rate, "velocity", field="rate"),
        divisions=args.divisions,
        hourglass=HourglassControl(
            type=args.hourglass_type, coefficient=args.hourglass_coefficient
        ),
        quasi_static_ratio=args.quasi_static_ratio,
        contact=ContactOptions(sfs=args.sfs),
    )
    update, bar = progress_bar(setup.displacement / setup.rate, enabled=True, unit="s")
    try:
        summary, _ = run_compression_test(
            ball, setup, runs_dir=args.runs_dir, reuse=not args.no_reuse, progress=update
        )
    finally:
        bar.close()
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(describe_compression(summary))
    return 0


def describe_compression(s: dict[str, Any]) -> str:
    """A short human report of a compression summary, every number with its unit."""
    return "\n".join(
        [
            f"Compression of ball {s['ball']} ({s['ball_mass_oz']:.2f} oz), "
            f"{s['displacement_in']:.3g} in at {s['rate_in_per_min']:.3g} in/min",
            f"  {'compression':<26} {s['compression_lbf']:.1f} lbf",
            f"  {'kinetic / internal energy':<26} {100 * s['kinetic_to_internal_energy']:.3f} %",
            f"  {'top - bottom plate force':<26} "
            f"{100 * s['plate_force_difference_fraction']:.2f} % of the force",
            f"  {'energy balance error':<26} {100 * s['energy_balance_error']:.3f} %",
            f"  {s['n_cells']} hexes, {s['n_steps']} steps, {s['wall_seconds']:.1f} s",
            f"  results in {s['run_folder']}",
        ]
    )


# --- batball calibrate (issue 4); the command lives in batball.calibrate.command -------------


def add_calibrate_parser(sub: Any) -> None:
    """``batball calibrate``: fit a ball's material model to measured impact data."""
    from batball.calibrate.command import add_calibrate_arguments, run_calibrate_command

    help_text = "fit a ball's material model to measured CCOR, DS, peak force and contact time"
    p = sub.add_parser("calibrate", help=help_text, description=help_text)
    add_calibrate_arguments(p)
    p.set_defaults(handler=run_calibrate_command)


# --- end of batball calibrate ------------------------------------------------------------------


def add_bat_mesh_options(p: Any) -> None:
    """The options every bat command shares: which bat, the mesh density and the pivot."""
    p.add_argument("--bat", default="default", help="embedded bat (default) or a TOML file")
    p.add_argument(
        "--circumferential",
        type=int,
        default=48,
        help="shells around the circumference (default 48; with 0.1 in: 20,928 shells)",
    )
    p.add_argument(
        "--axial-size", default="0.1 in", help="largest shell length along the bat (0.1 in)"
    )
    p.add_argument("--pivot", default="6 in", help="pivot distance from the knob end (6 in)")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def add_props_parser(sub: Any) -> None:
    """``batball props``: weight, balance point and MOI of a bat (ASTM F2398)."""
    help_text = "weight, balance point and MOI about the 6-in pivot of a bat (ASTM F2398)"
    p = sub.add_parser("props", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    add_store_options(p)
    p.set_defaults(handler=run_props_command)


def add_modal_parser(sub: Any) -> None:
    """``batball modal``: free-free bending and hoop frequencies of a bat (seed Table 3)."""
    help_text = "free-free modes of a bat: first two bending and hoop frequencies (seed Table 3)"
    p = sub.add_parser("modal", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    p.add_argument("--modes", type=int, default=30, help="modes to compute (default 30)")
    p.add_argument("--insert", choices=("bonded", "contact"), default="contact",
                   help="the pre-stressed fit's contact (default: radial springs, frictionless "
                        "sliding; docs/modal.md), or the insert tied to the barrel")  # fmt: skip
    add_store_options(p)
    p.set_defaults(handler=run_modal_command)


def add_fit_bat_parser(sub: Any) -> None:
    """``batball fit-bat``: adjust chosen bat parameters to measured mass properties or hoop
    frequencies."""
    help_text = ("fit chosen layup or lumped-mass values of a bat to its weight, BP and MOI, "
                 "or to its measured hoop frequencies")  # fmt: skip
    p = sub.add_parser("fit-bat", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    p.add_argument(
        "--to",
        choices=("mass", "hoop"),
        default="mass",
        help="what to match: mass (weight, balance point, MOI; seed Table 1) or hoop (the "
        "first two hoop frequencies of the free-free modal test, insert as contact; Table 3)",
    )
    p.add_argument(
        "--free",
        action="append",
        help="a parameter to adjust: lumped_mass:<part>, thickness:<ply label>[@<part>+...] or "
        "angle:<ply label>[@<part>+...]; repeat it (default for --to mass: lumped_mass:endcap, "
        "thickness:handle-glass, thickness:barrel-carbon; for --to hoop: "
        "angle:barrel-carbon@barrel-1+barrel-2+barrel-3+endcap)",
    )
    p.add_argument("--weight", default="22.1 oz", help="target weight (seed Table 1: 22.1 oz)")
    p.add_argument(
        "--balance-point", default="21.0 in", help="target balance point from the knob (21.0 in)"
    )
    p.add_argument(
        "--moi", default="6920 oz*in**2", help="target MOI about the pivot (6920 oz*in**2)"
    )
    p.add_argument(
        "--hoop",
        nargs="+",
        default=["1450 Hz", "1950 Hz"],
        help="target hoop frequencies, lowest first (seed Table 3: '1450 Hz' '1950 Hz')",
    )
    p.add_argument("--output", type=Path, help="write the fitted bat to this TOML file")
    add_store_options(p)
    p.set_defaults(handler=run_fit_bat_command)


def bat_mesh_options(args: argparse.Namespace) -> dict[str, Any]:
    """circumferential, axial_size and pivot (SI) from the parsed options, validated."""
    from batball.units import parse_quantity

    if args.circumferential < 3:
        raise SpecError("circumferential", args.circumferential, "an integer >= 3")
    axial_size = parse_quantity(args.axial_size, "length", field="axial-size")
    if not axial_size > 0:
        raise SpecError("axial-size", args.axial_size, "a positive length, e.g. '0.1 in'")
    pivot = parse_quantity(args.pivot, "length", field="pivot")
    return {"circumferential": args.circumferential, "axial_size": axial_size, "pivot": pivot}


def run_props_command(args: argparse.Namespace) -> int:
    """``batball props``."""
    from batball.lab.props_run import run_props_test
    from batball.specs import load_bat_spec

    spec = load_bat_spec(args.bat)
    summary, _ = run_props_test(
        spec, runs_dir=args.runs_dir, reuse=not args.no_reuse, **bat_mesh_options(args)
    )
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(describe_props(summary))
    return 0


def run_modal_command(args: argparse.Namespace) -> int:
    """``batball modal`` (the pivot option is accepted and unused)."""
    from batball.lab.modal_run import run_modal_test
    from batball.specs import load_bat_spec

    if args.modes < 8:
        raise SpecError("modes", args.modes, "an integer >= 8 (six rigid-body modes come first)")
    spec = load_bat_spec(args.bat)
    options = bat_mesh_options(args)
    summary, _ = run_modal_test(
        spec, runs_dir=args.runs_dir, reuse=not args.no_reuse, n_modes=args.modes,
        circumferential=options["circumferential"], axial_size=options["axial_size"],
        insert=args.insert,
    )  # fmt: skip
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(describe_modal(summary))
    return 0


def describe_modal(s: dict[str, Any]) -> str:
    """A short human report of a modal summary beside the seed's Table 3."""
    table = s["seed_table3"]
    lines = [f"Free-free modes of bat {s['bat']} (insert {s['insert']})",
             f"  {'':<10} {'batball':>16} {'experiment':>16} {'seed LS-DYNA':>16}"]  # fmt: skip
    for key, name in (("bending_hz", "bending"), ("hoop_hz", "hoop")):
        ours = ", ".join(f"{f:.0f}" for f in s[key])
        exp = ", ".join(f"{f:.0f}" for f in table[key]["experiment"])
        dyna = ", ".join(f"{f:.0f}" for f in table[key]["seed_lsdyna"])
        lines.append(f"  {name + ' Hz':<10} {ours:>16} {exp:>16} {dyna:>16}")
    lines.append(f"  {s['n_modes']} modes ({s['n_rigid']} rigid), {s['n_shells']} shells, "
                 f"{s['wall_seconds']:.1f} s")  # fmt: skip
    lines.append(f"  results in {s['run_folder']}")
    return "\n".join(lines)


def describe_props(s: dict[str, Any]) -> str:
    """A short human report of a props summary, every number with its unit."""
    return "\n".join(
        [
            f"Mass properties of bat {s['bat']} ({s['length_in']:.1f} in), ASTM F2398",
            f"  {'weight':<28} {s['weight_oz']:.2f} oz",
            f"  {'balance point from knob end':<28} {s['balance_point_in']:.2f} in",
            f"  {'MOI about the pivot':<28} {s['moi_pivot_oz_in2']:.0f} oz*in^2 "
            f"(pivot {s['pivot_in']:g} in from the knob end)",
            f"  {'MOI about the centre of mass':<28} {s['moi_cm_oz_in2']:.0f} oz*in^2",
            f"  {s['n_shells']} shells, {s['wall_seconds']:.2f} s",
            f"  results in {s['run_folder']}",
        ]
    )


def run_fit_bat_command(args: argparse.Namespace) -> int:
    """``batball fit-bat``; exits with status 1 when the fit fails or a bound stops it."""
    from batball.lab.fit_bat import (
        DEFAULT_FREE,
        DEFAULT_HOOP_FREE,
        FreeParameter,
        HoopTargets,
        MassTargets,
        fit_bat,
        fit_summary,
        write_fitted_bat,
    )
    from batball.specs import load_bat_spec
    from batball.units import parse_quantity

    spec = load_bat_spec(args.bat)
    options = bat_mesh_options(args)
    pivot = options.pop("pivot")
    targets: MassTargets | HoopTargets
    if args.to == "mass":
        targets = MassTargets(
            weight=parse_quantity(args.weight, "mass", field="weight"),
            balance_point=parse_quantity(args.balance_point, "length", field="balance-point"),
            moi_pivot=parse_quantity(args.moi, "moment_of_inertia", field="moi"),
            pivot=pivot,
        )
    else:
        hoop = tuple(parse_quantity(text, "frequency", field="hoop") for text in args.hoop)
        if not all(f > 0 for f in hoop) or list(hoop) != sorted(set(hoop)):
            raise SpecError("hoop", " ".join(args.hoop), "positive frequencies, lowest first")
        targets = HoopTargets(hoop_hz=hoop, runs_dir=args.runs_dir, reuse=not args.no_reuse)
    default_free = DEFAULT_FREE if args.to == "mass" else DEFAULT_HOOP_FREE
    free = tuple(FreeParameter.parse(text) for text in (args.free or default_free))
    fit = fit_bat(spec, targets, free, **options)
    if args.output is not None:
        write_fitted_bat(args.output, fit)
    summary = fit_summary(fit, targets)
    print(json.dumps(summary, indent=2) if args.json else describe_fit(summary))
    return 0 if fit.matched else 1


def describe_fit(s: dict[str, Any]) -> str:
    """A short human report of a fit summary."""
    kind = "least squares, " if s["least_squares"] else ""
    lines = [f"Fit of bat {s['bat']} to {s['fitted_to']} ({kind}{s['n_evaluations']} "
             f"evaluations, {'converged' if s['success'] else 'NOT converged'})"]  # fmt: skip
    for name, p in s["parameters"].items():
        lines.append(f"  {name:<28} {p['initial']} -> {p['fitted']}")
    for key, value in s["properties"].items():
        lines.append(f"  {key:<28} {value:.5g}   (target {s['targets'][key]:.5g}, "
                     f"{s['error_percent'][key]:+.2f} %)")  # fmt: skip
    if not s["matched"]:
        bounds = ", ".join(s["at_bound"]) or "none"
        lines.append(f"  targets NOT met; parameters at a bound: {bounds}")
    return "\n".join(lines)


def impact_setup(args: argparse.Namespace) -> Any:
    """An ImpactSetup from the parsed options (units parsed here, at the edge)."""
    from batball.lab.impact import ContactOptions, ImpactSetup
    from batball.solvers.explicit import BulkViscosity, HourglassControl
    from batball.units import parse_quantity

    speed = parse_quantity(args.speed, "velocity", field="speed")
    if not speed > 0:
        raise SpecError("speed", args.speed, "a positive speed, e.g. '95 mph'")
    return ImpactSetup(
        test=args.test,
        speed=speed,
        divisions=args.divisions,
        hourglass=HourglassControl(
            type=args.hourglass_type, coefficient=args.hourglass_coefficient
        ),
        bulk_viscosity=BulkViscosity(enabled=not args.no_bulk_viscosity),
        contact=ContactOptions(soft=args.soft),
        contact_threshold=args.contact_threshold,
        precision=args.precision,
    )


def progress_bar(
    end_time: float, enabled: bool, unit: str = "ms"
) -> tuple[Callable[[float], None], Any]:
    """A tqdm bar over simulated time (in ``unit``, ms or s) on stderr; only on a terminal."""
    from tqdm import tqdm

    factor = 1e3 if unit == "ms" else 1.0
    bar = tqdm(
        total=round(end_time * factor, 3),
        unit=unit,
        desc="simulated",
        leave=False,
        disable=None if enabled else True,
        bar_format="{l_bar}{bar}| {n:.2f}/{total} " + unit,
    )

    def update(t: float) -> None:
        bar.n = round(t * factor, 3)
        bar.refresh()

    return update, bar


def run_impact_command(args: argparse.Namespace) -> int:
    """``batball ccor`` / ``batball cor``."""
    from batball.lab.impact_run import run_impact_test
    from batball.specs import load_ball_spec

    ball = load_ball_spec(args.ball)
    setup = impact_setup(args)
    update, bar = progress_bar(setup.end_time, enabled=True)
    try:
        summary, folder = run_impact_test(
            ball, setup, runs_dir=args.runs_dir, reuse=not args.no_reuse, progress=update
        )
    finally:
        bar.close()
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(describe_impact(summary))
    return 0


def describe_impact(s: dict[str, Any]) -> str:
    """A short human report of an impact summary, every number with its unit."""
    name = s["test"].upper()
    return "\n".join(
        [
            f"{name} of ball {s['ball']} ({s['ball_mass_oz']:.2f} oz) "
            f"at {s['inbound_mph']:.1f} mph",
            f"  {name:<22} {s[s['test']]:.3f}",
            f"  {'rebound speed':<22} {s['rebound_mph']:.1f} mph",
            f"  {'dynamic stiffness':<22} {s['ds_lbf_per_in']:.0f} lb/in",
            f"  {'peak force':<22} {s['peak_force_lbf']:.0f} lbf",
            f"  {'contact time':<22} {s['contact_time_ms']:.3f} ms",
            f"  {'energy balance error':<22} {100 * s['energy_balance_error']:.2f} %",
            f"  {s['n_cells']} hexes, {s['n_steps']} steps, {s['wall_seconds']:.1f} s",
            f"  results in {s['run_folder']}",
        ]
    )


# --- batball reproduce ---------------------------------------------------------------------------


def add_reproduce_parser(sub: Any) -> None:
    """``batball reproduce``: every available test of the seed study, as an HTML report."""
    help_text = "rerun the seed study (Tables 1-9) and write an HTML report with figures"
    p = sub.add_parser("reproduce", help=help_text, description=help_text)
    p.add_argument(
        "--quick",
        action="store_true",
        help="coarse meshes (ball divisions 6, 16 bat shells around): a first look, CI",
    )
    p.add_argument("--out", type=Path, default=Path("report"), help="report folder (report/)")
    p.add_argument(
        "--calibrate",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="calibrate both balls (Table 4); default: yes, but not with --quick",
    )
    add_store_options(p)
    p.add_argument("--json", action="store_true", help="print summary.json on stdout")
    p.set_defaults(handler=run_reproduce_command)  # fmt: skip


def run_reproduce_command(args: argparse.Namespace) -> int:
    """``batball reproduce``; progress on stderr, the report's path (or its JSON) on stdout."""
    from batball.report.reproduce import (
        FULL_MESHES,
        QUICK_MESHES,
        ReproduceOptions,
        dump_summary,
        reproduce,
    )

    calibrate = not args.quick if args.calibrate is None else args.calibrate
    flag = {None: [], True: ["--calibrate"], False: ["--no-calibrate"]}[args.calibrate]
    command = " ".join(["batball", "reproduce", *(["--quick"] if args.quick else []), *flag,
                        "--out", args.out.as_posix(), "--runs-dir", args.runs_dir.as_posix(),
                        *(["--no-reuse"] if args.no_reuse else [])])  # fmt: skip
    options = ReproduceOptions(out_dir=args.out, runs_dir=args.runs_dir,
                               meshes=QUICK_MESHES if args.quick else FULL_MESHES,
                               reuse=not args.no_reuse, command=command,
                               calibrate=calibrate)  # fmt: skip
    result = reproduce(options)
    print(dump_summary(result) if args.json else describe_reproduction(result))
    return 0


def describe_reproduction(result: Any) -> str:
    """Where the report is, how batball compares with the seed's LS-DYNA, what is missing."""
    from batball.report.reproduce_html import verdict_counts

    counts = verdict_counts(result)
    missing = (
        ", ".join(o.test.name for o in result.outcomes if not o.available and not o.skipped)
        or "none"
    )
    skipped = [f"  {o.test.name} {o.missing}" for o in result.outcomes if o.skipped]
    return "\n".join([
        f"report: {(result.options.out_dir / 'index.html').as_posix()}",
        f"  batball closer to the experiment than the seed's LS-DYNA in {counts['closer']} cells, "
        f"as close in {counts['tie']}, farther in {counts['farther']}",
        f"  not yet available: {missing}",
        *skipped,
        f"  {result.seconds:.1f} s",
    ])  # fmt: skip


# --- batball barrel (issue 8) -------------------------------------------------------------------


def add_barrel_parser(sub: Any) -> None:
    """``batball barrel``: insert pre-stress and barrel compression of a bat (seed Table 2)."""
    help_text = "interference-fit pre-stress and barrel compression of a bat (seed Table 2)"
    p = sub.add_parser("barrel", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    p.add_argument(
        "--ramp-steps",
        type=int,
        default=1,
        help="static steps removing the insert's overlap (default 1: the fit is "
        "linear and frictionless, so the end state does not depend on the path)",
    )
    p.add_argument(
        "--friction",
        type=float,
        default=0.0,
        help="Coulomb coefficient between insert and barrel during the squeeze (default 0, "
        "as the seed; the fit itself stays frictionless; docs/barrel.md)",
    )
    p.add_argument(
        "--platen-friction",
        type=float,
        default=0.0,
        help="Coulomb coefficient between the platens and the barrel (default 0, as the seed; "
        "docs/barrel.md, 'Friction at the platens')",
    )
    p.add_argument(
        "--solver",
        choices=("static", "explicit"),
        default="static",
        help="static: linear MITC4 shells, penalty contact, small displacements (default); "
        "explicit: shells relaxed at each travel, geometrically nonlinear (docs/barrel.md, "
        "'Geometric nonlinearity')",
    )
    p.add_argument(
        "--shell",
        choices=("mitc4", "bt"),
        default=None,
        help="with --solver explicit: mitc4, the statics' MITC4 shells made co-rotational "
        "(default), or bt, the BBS test's one-point Belytschko-Tsay shells",
    )
    p.add_argument(
        "--hourglass-ratio",
        type=float,
        default=None,
        help="with --shell bt: hourglass ratio r of the one-point shells, 0 < r <= 1 "
        "(default 1; LS-DYNA's 0.01 is 14-17 %% softer under the platens, docs/barrel.md)",
    )
    add_store_options(p)
    p.set_defaults(handler=run_barrel_command)


def run_barrel_command(args: argparse.Namespace) -> int:
    """``batball barrel`` (the pivot option is accepted and unused)."""
    from batball.lab.barrel import BarrelTestOptions
    from batball.lab.barrel_run import run_barrel_test
    from batball.specs import load_bat_spec

    if args.ramp_steps < 1:
        raise SpecError("ramp-steps", args.ramp_steps, "an integer >= 1")
    spec = load_bat_spec(args.bat)
    options = bat_mesh_options(args)
    test = BarrelTestOptions(friction=args.friction, platen_friction=args.platen_friction)
    if args.solver == "explicit":
        from batball.lab.barrel_explicit import ExplicitBarrelOptions
        from batball.lab.barrel_run import run_explicit_barrel_test

        shell = args.shell or "mitc4"
        if args.hourglass_ratio is not None and shell != "bt":
            raise SpecError("hourglass-ratio", args.hourglass_ratio,
                            "only with --shell bt (MITC4 shells have none)")  # fmt: skip
        ratio = {} if args.hourglass_ratio is None else {"hourglass_ratio": args.hourglass_ratio}
        explicit = ExplicitBarrelOptions(circumferential=options["circumferential"],
                                         axial_size=options["axial_size"], shell=shell,
                                         **ratio)  # fmt: skip
        summary, _ = run_explicit_barrel_test(
            spec, runs_dir=args.runs_dir, options=test, explicit=explicit,
            reuse=not args.no_reuse,
        )  # fmt: skip
    else:
        if args.hourglass_ratio is not None or args.shell is not None:
            name, value = ("shell", args.shell) if args.shell else ("hourglass-ratio",
                                                                    args.hourglass_ratio)
            raise SpecError(name, value, "only with --solver explicit")  # fmt: skip
        summary, _ = run_barrel_test(
            spec, runs_dir=args.runs_dir, reuse=not args.no_reuse, ramp_steps=args.ramp_steps,
            circumferential=options["circumferential"], axial_size=options["axial_size"],
            options=test,
        )  # fmt: skip
    print(json.dumps(summary, indent=2) if args.json else describe_barrel(summary))
    return 0


def describe_barrel(s: dict[str, Any]) -> str:
    """A short human report of a barrel summary beside the seed's Table 2."""
    exp, seed = s["seed_table2"]["experiment"], s["seed_table2"]["seed_lsdyna"]
    return "\n".join([
        f"barrel compression of {s['bat']} (mean of {len(s['orientations_deg'])} orientations)",
        f"  preload    {s['preload_lbf']:7.1f} lbf  (experiment {exp['preload_lbf']:.0f}, "
        f"seed FE {seed['preload_lbf']:.0f})",
        f"  final load {s['final_load_lbf']:7.1f} lbf  (experiment {exp['final_load_lbf']:.0f}, "
        f"seed FE {seed['final_load_lbf']:.0f})",
        f"  solver: {s.get('solver', 'static: linear MITC4 shells')}",
        f"  friction during the squeeze: mu = {s.get('insert_friction', 0.0):g} insert-barrel, "
        f"{s.get('platen_friction', 0.0):g} platens-barrel",
        f"  interference pressure {s['interference_pressure_psi']:.1f} psi (thin rings "
        f"{s['interference_pressure_thin_ring_psi']:.1f} psi)",
        f"  {s['n_shells']} shells, {s['wall_seconds']:.1f} s, results in {s['run_folder']}",
    ])  # fmt: skip


# --- batball export / batball run (LS-DYNA keyword decks) -----------------------------------------


def add_export_parser(sub: Any) -> None:
    """``batball export ccor|cor|compression|modal|barrel|bbs``: the test as a keyword deck."""
    help_text = "write a ball or bat test as a complete LS-DYNA keyword deck (docs/lsdyna.md)"
    p = sub.add_parser("export", help=help_text, description=help_text)
    p.add_argument("test", choices=["ccor", "cor", "compression", *BAT_EXPORTS],
                   help="the test to export")  # fmt: skip
    p.add_argument("--ball", default="type1", help="embedded ball (type1, type2) or a TOML file")
    p.add_argument("--speed", default=None, help="inbound speed with its unit (test default)")
    p.add_argument("--divisions", type=int, default=12, help="ball mesh size (default 12)")
    p.add_argument("--hourglass-type", type=int, default=1, help="LS-DYNA IHQ 1-5 (default 1)")
    p.add_argument("--hourglass-coefficient", type=float, default=0.1, help="QH/QM (0.1)")
    p.add_argument("--no-bulk-viscosity", action="store_true", help="Q1 = Q2 = 0")
    p.add_argument("--soft", type=int, default=0, help="contact SOFT option, 0 or 1 (default 0)")
    p.add_argument("--units", default="in-lbf-s", help="in-lbf-s (default), m-N-s or mm-N-ms")
    p.add_argument("--long", action="store_true", help="long format: 20-column fields")
    p.add_argument("-o", "--output", required=True, help="the deck file to write (.k)")
    add_bat_export_options(p)
    p.set_defaults(handler=run_export_command, contact_threshold=0.01, precision="single")


def run_export_command(args: argparse.Namespace) -> int:
    """Write the deck and say where."""
    from batball.io.keyword_export import write_impact_deck
    from batball.specs import load_ball_spec

    if args.test in BAT_EXPORTS:
        return run_bat_export(args)
    ball = load_ball_spec(args.ball)
    if args.test == "compression":
        from batball.lab.compression import CompressionSetup
        from batball.solvers.explicit import BulkViscosity, HourglassControl

        setup: Any = CompressionSetup(
            divisions=args.divisions,
            hourglass=HourglassControl(args.hourglass_type, args.hourglass_coefficient),
            bulk_viscosity=BulkViscosity(enabled=not args.no_bulk_viscosity),
        )
        what = "compression (F1888, 1 in/min to 0.25 in)"
    else:
        args.speed = args.speed or DEFAULT_SPEEDS[args.test]
        setup = impact_setup(args)
        what = f"{args.test} at {args.speed}"
    n_lines = write_impact_deck(args.output, ball, setup, args.units, long=args.long)
    print(f"wrote {args.output}: {what} of ball {ball.name}, {n_lines} lines, units {args.units}")
    return 0


def add_run_deck_parser(sub: Any) -> None:
    """``batball run deck.k``: read a keyword deck and run it as an impact test."""
    help_text = "read an LS-DYNA keyword deck (ball hexes + rigid target) and run it"
    p = sub.add_parser("run", help=help_text, description=help_text)
    p.add_argument("deck", type=Path, help="the keyword file (*INCLUDEs are followed)")
    p.add_argument("--units", default="in-lbf-s", help="the deck's units (default in-lbf-s)")
    p.add_argument(
        "--separation-time",
        default=None,
        help="stop this long after the ball leaves the target (0.1 ms; bbs decks 0.2 ms, as "
        "batball bbs; 'none' runs an impact deck to ENDTIM)",
    )
    p.add_argument("--contact-threshold", type=float, default=0.01, help="contact-time level")
    p.add_argument(
        "--displacement", default="0.25 in", help="compression decks: where the force is read"
    )
    add_precision_option(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=run_deck_command)


def run_deck_command(args: argparse.Namespace) -> int:
    """Read, run and report a deck with the impact measurements."""
    from batball.io.keyword_model import parse_deck, read_deck, run_deck
    from batball.units import parse_quantity

    if parse_deck(args.deck).composites:
        return run_bat_deck_command(args)
    text = args.separation_time or "0.1 ms"
    separation = (
        None
        if text.strip().lower() == "none"
        else parse_quantity(text, "time", field="separation-time")
    )
    displacement = parse_quantity(args.displacement, "length", field="displacement")
    deck = read_deck(
        args.deck, units=args.units, separation_time=separation, displacement=displacement,
        precision=args.precision,
    )  # fmt: skip
    unit = "s" if deck.test == "compression" else "ms"
    update, bar = progress_bar(deck.controls.end_time, enabled=True, unit=unit)
    try:
        summary = run_deck(deck, threshold=args.contact_threshold, progress=update)
    finally:
        bar.close()
    summary["deck"] = str(args.deck)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    if deck.test == "compression":
        print("\n".join([
            f"compression of deck {args.deck} at {summary['rate_in_per_min']:.3g} in/min",
            f"  {'force at ' + format(summary['displacement_in'], '.3g') + ' in':<22} "
            f"{summary['compression_lbf']:.1f} lbf (power-law fit "
            f"{summary['compression_fit_lbf']:.1f} lbf)",
            f"  {'top-bottom difference':<22} "
            f"{100 * summary['plate_force_difference_fraction']:.2f} %",
            f"  {'energy balance error':<22} {100 * summary['energy_balance_error']:.2f} %",
            f"  {summary['n_cells']} hexes, {summary['n_steps']} steps",
        ]))  # fmt: skip
        return 0
    name = summary["test"].upper()
    print("\n".join([
        f"{name} of deck {args.deck} ({summary['ball_mass_oz']:.2f} oz) "
        f"at {summary['inbound_mph']:.1f} mph",
        f"  {name:<22} {summary[summary['test']]:.3f}",
        f"  {'rebound speed':<22} {summary['rebound_mph']:.1f} mph",
        f"  {'dynamic stiffness':<22} {summary['ds_lbf_per_in']:.0f} lb/in",
        f"  {'peak force':<22} {summary['peak_force_lbf']:.0f} lbf",
        f"  {'contact time':<22} {summary['contact_time_ms']:.3f} ms",
        f"  {'energy balance error':<22} {100 * summary['energy_balance_error']:.2f} %",
        f"  {summary['n_cells']} hexes, {summary['n_steps']} steps",
    ]))  # fmt: skip
    return 0


# --- batball bbs (issue 9) ---------------------------------------------------------------------


def add_bbs_parser(sub: Any) -> None:
    """``batball bbs``: batted-ball speed of a ball fired at the pivoting bat (seed Table 9)."""
    help_text = "batted-ball speed: a ball fired at the bat pivoting 6 in from the knob (Table 9)"
    p = sub.add_parser("bbs", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    p.add_argument("--ball", default="type1", help="embedded ball (type1, type2) or a TOML file")
    p.add_argument("--speed", default="110 mph", help="inbound ball speed (110 mph)")
    p.add_argument("--pitch-speed", default="25 mph", help="BBS pitch speed v_p (ASA: 25 mph)")
    p.add_argument("--swing-speed", default="85 mph", help="BBS bat speed v_b (ASA: 85 mph)")
    p.add_argument("--ball-divisions", type=int, default=12,
                   help="ball mesh divisions (12 = the seed's 12,096 hexes)")  # fmt: skip
    p.add_argument("--impact", default="6 in", help="impact point from the end cap (6 in)")
    p.add_argument("--pivot-band", default="0.5 in",
                   help="half width of the rigid handle band at the pivot (0.5 in)")  # fmt: skip
    p.add_argument("--end-time", default="2 ms", help="longest run (2 ms, as the seed)")
    p.add_argument("--rigid-bat", action="store_true",
                   help="the bat as a rigid body on the pivot (verification)")  # fmt: skip
    p.add_argument("--mass-scaling", default="barrel",
                   help="selective mass scaling of the shells below a target step (LS-DYNA "
                        "DT2MS < 0): barrel (default: the barrel's or the ball's step), off, "
                        "or the target step, e.g. '2e-7 s'")  # fmt: skip
    p.add_argument("--insert-friction", type=float, default=0.0,
                   help="Coulomb coefficient between insert and barrel during the impact "
                        "(default 0, as the seed; the fit is pressed frictionless)")  # fmt: skip
    p.add_argument("--bat-damping", default="0 1/s",
                   help="damping c of the bat's deformation relative to its rigid turn, "
                        "e.g. '1000 1/s' (as LS-DYNA *DAMPING_RELATIVE; default 0: none, as "
                        "the seed)")  # fmt: skip
    p.add_argument("--hourglass-ratio", type=float, default=None,
                   help="hourglass ratio r of the bat's one-point shells, 0 < r <= 1 (default "
                        "LS-DYNA's 0.01)")  # fmt: skip
    p.add_argument("--shell", choices=("bt", "mitc4"), default="bt",
                   help="the bat's shells: bt, one-point Belytschko-Tsay as the seed (default), "
                        "or mitc4, the statics' MITC4 made co-rotational")  # fmt: skip
    add_precision_option(p)
    add_store_options(p)
    p.set_defaults(handler=run_bbs_command)


def bbs_setup(args: argparse.Namespace) -> Any:
    """The BbsSetup of the parsed options (units parsed here, validated by the setup)."""
    from batball.lab.bbs import BbsSetup
    from batball.units import parse_quantity

    mesh = bat_mesh_options(args)

    def speed(text: str, name: str) -> float:
        return parse_quantity(text, "velocity", field=name)

    return BbsSetup(
        speed=speed(args.speed, "speed"), pitch_speed=speed(args.pitch_speed, "pitch-speed"),
        swing_speed=speed(args.swing_speed, "swing-speed"),
        impact_from_cap=parse_quantity(args.impact, "length", field="impact"),
        pivot_from_knob=mesh["pivot"],
        pivot_band=parse_quantity(args.pivot_band, "length", field="pivot-band"),
        ball_divisions=args.ball_divisions, circumferential=mesh["circumferential"],
        axial_size=mesh["axial_size"], rigid_bat=args.rigid_bat,
        end_time=parse_quantity(args.end_time, "time", field="end-time"),
        mass_scaling=mass_scaling_option(args.mass_scaling), precision=args.precision,
        insert_friction=args.insert_friction,
        bat_damping=parse_quantity(args.bat_damping, "frequency", field="bat-damping"),
        bat_shell=args.shell,
        **({} if args.hourglass_ratio is None
           else {"shell_hourglass_ratio": args.hourglass_ratio}),
    )  # fmt: skip


def mass_scaling_option(text: str) -> float | str | None:
    """``--mass-scaling``: "barrel", "off" (None) or a target step (parsed to seconds)."""
    from batball.units import parse_quantity

    if text in ("barrel", "off"):
        return None if text == "off" else text
    return parse_quantity(text, "time", field="mass-scaling")


def run_bbs_command(args: argparse.Namespace) -> int:
    """``batball bbs``."""
    from batball.lab.bbs_run import run_bbs_test
    from batball.specs import load_ball_spec, load_bat_spec

    setup = bbs_setup(args)
    bat, ball = load_bat_spec(args.bat), load_ball_spec(args.ball)
    summary, _ = run_bbs_test(bat, ball, setup, runs_dir=args.runs_dir, reuse=not args.no_reuse)
    print(json.dumps(summary, indent=2) if args.json else describe_bbs(summary))
    return 0


def describe_bbs(s: dict[str, Any]) -> str:
    """A short human report of a batted-ball-speed summary, every number with its unit."""
    return "\n".join([
        f"batted-ball speed of {s['ball']} on {s['bat']} at {s['inbound_mph']:.1f} mph",
        f"  BBS {s['bbs_mph']:.2f} mph (v_p {s['pitch_speed_mph']:.0f}, v_b "
        f"{s['swing_speed_mph']:.0f} mph)",
        f"  e_A {s['collision_efficiency']:.4f}, rebound {s['rebound_mph']:.2f} mph, BBCOR "
        f"{s['bbcor']:.4f} (from the bat's rotation {s['bbcor_from_bat_rotation']:.4f}), k "
        f"{s['k']:.4f}",
        f"  peak force {s['peak_force_lbf']:.0f} lbf, contact {s['contact_time_ms']:.3f} ms, "
        f"energy balance error {100 * s['energy_balance_error']:.2f} %",
        *([f"  insert fit {s['interference_pressure_psi']:.1f} psi, "
           + ("restored from the store" if s.get("prestress_reused") else "relaxed in this run")]
          if s.get("interference_pressure_psi") is not None else []),
        f"  {s['n_shells']} {s.get('bat_shell', 'bt').upper()} shells + {s['n_hexes']} hexes, "
        f"{s['n_steps']} steps, "
        f"{s['wall_seconds']:.1f} s, results in {s['run_folder']}",
    ])  # fmt: skip


# --- batball compare-calibrations, synthetic-data (issue 12); in batball.calibrate.routes_command


def add_routes_parsers(sub: Any) -> None:
    """``batball compare-calibrations``, ``synthetic-data`` and ``synthetic-noise``."""
    from batball.calibrate.routes_command import (
        add_compare_arguments,
        add_noise_arguments,
        add_synthetic_arguments,
        run_compare_command,
        run_noise_command,
        run_synthetic_command,
    )

    help_text = "calibrate a ball by each route with data (flat COR, CCOR, DMA) and compare BBS"
    p = sub.add_parser("compare-calibrations", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    add_compare_arguments(p)
    add_store_options(p)
    p.set_defaults(handler=run_compare_command)
    help_text = "measure a known true ball with the virtual tests: each route's data files"
    p = sub.add_parser("synthetic-data", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    add_synthetic_arguments(p)
    add_store_options(p)
    p.set_defaults(handler=run_synthetic_command)
    help_text = "seeded noisy copies of a synthetic route data set (assumed lab repeatability)"
    p = sub.add_parser("synthetic-noise", help=help_text, description=help_text)
    add_noise_arguments(p)
    p.set_defaults(handler=run_noise_command)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``batball`` command."""
    args = build_parser().parse_args(argv)
    try:
        return int(args.handler(args))
    except SpecError as exc:
        print(f"batball: error: {exc}", file=sys.stderr)
        return 2
    except SimulationError as exc:
        print(f"batball: simulation stopped: {exc}", file=sys.stderr)
        return 3


# --- batball export modal|barrel|bbs, batball run of a bat deck (issue 11) ----------------------

BAT_EXPORTS = ("modal", "barrel", "bbs")


def add_bat_export_options(p: Any) -> None:
    """The bat tests' export options (mesh, modes, orientation, pivot band)."""
    p.add_argument("--bat", default="default", help="bat tests: embedded bat or a TOML file")
    p.add_argument("--circumferential", type=int, default=48, help="bat: shells around (48)")
    p.add_argument("--axial-size", default="0.1 in", help="bat: largest shell length (0.1 in)")
    p.add_argument("--modes", type=int, default=30, help="modal: modes incl. 6 rigid (30)")
    p.add_argument("--orientation", type=float, default=0.0,
                   help="barrel: bat rotation about its axis, 0 or 90 deg (0)")  # fmt: skip
    p.add_argument("--pivot-band", default="0.5 in", help="bbs: rigid band half width (0.5 in)")


def run_bat_export(args: argparse.Namespace) -> int:
    """Write a bat test's deck (modal, barrel or bbs) and say where."""
    from pathlib import Path

    from batball.io.keyword_bat import barrel_deck, bbs_deck, modal_deck
    from batball.specs import load_ball_spec, load_bat_spec
    from batball.units import parse_quantity

    spec = load_bat_spec(args.bat)
    mesh = {
        "circumferential": args.circumferential,
        "axial_size": parse_quantity(args.axial_size, "length", field="axial-size"),
    }
    if args.test == "modal":
        if args.modes < 8:
            raise SpecError("modes", args.modes, "an integer >= 8 (six rigid-body modes first)")
        text = modal_deck(spec, n_modes=args.modes, units=args.units, long=args.long, **mesh)
    elif args.test == "barrel":
        from batball.lab.barrel import BarrelTestOptions

        text = barrel_deck(spec, BarrelTestOptions(), orientation_deg=args.orientation,
                           units=args.units, long=args.long, **mesh)  # fmt: skip
    else:
        text = bbs_deck(spec, load_ball_spec(args.ball), bat_export_bbs_setup(args, mesh),
                        units=args.units, long=args.long)  # fmt: skip
    Path(args.output).write_text(text, encoding="ascii")
    print(f"wrote {args.output}: {args.test} of bat {spec.name}, {text.count(chr(10))} lines, "
          f"units {args.units}")  # fmt: skip
    return 0


def bat_export_bbs_setup(args: argparse.Namespace, mesh: dict[str, Any]) -> Any:
    """The BbsSetup of ``batball export bbs``'s options (speed default 110 mph)."""
    from batball.lab.bbs import BbsSetup
    from batball.lab.impact import ContactOptions
    from batball.solvers.explicit import BulkViscosity, HourglassControl
    from batball.units import parse_quantity

    return BbsSetup(
        speed=parse_quantity(args.speed or "110 mph", "velocity", field="speed"),
        ball_divisions=args.divisions,
        pivot_band=parse_quantity(args.pivot_band, "length", field="pivot-band"),
        hourglass=HourglassControl(args.hourglass_type, args.hourglass_coefficient),
        bulk_viscosity=BulkViscosity(enabled=not args.no_bulk_viscosity),
        contact=ContactOptions(soft=args.soft),
        **mesh,
    )


def run_bat_deck_command(args: argparse.Namespace) -> int:
    """``batball run`` of a bat deck: modal, barrel or bbs (docs/lsdyna.md)."""
    from batball.io.keyword_bat_barrel import run_barrel_deck
    from batball.io.keyword_bat_model import read_bat_deck, run_modal_deck

    bat = read_bat_deck(args.deck, units=args.units)
    if bat.test == "bbs":
        return run_bbs_deck_command(args, bat)
    summary = run_modal_deck(bat) if bat.test == "modal" else run_barrel_deck(bat)
    summary["deck"] = str(args.deck)
    if args.json:
        print(json.dumps(summary, indent=2))
    elif bat.test == "barrel":
        print(f"Barrel compression of deck {args.deck} at {summary['orientation_deg']:g} deg "
              f"({summary['n_shells']} shells): preload {summary['preload_lbf']:.1f} lbf, "
              f"final load {summary['final_load_lbf']:.1f} lbf")  # fmt: skip
    else:
        print("\n".join([
            f"Free-free modes of deck {args.deck} ({summary['n_shells']} shells)",
            "  bending " + (", ".join(f"{f:.1f} Hz" for f in summary["bending_hz"]) or "none"),
            "  hoop    " + (", ".join(f"{f:.1f} Hz" for f in summary["hoop_hz"]) or "none"),
        ]))  # fmt: skip
    return 0


def run_bbs_deck_command(args: argparse.Namespace, bat: Any) -> int:
    """``batball run`` of a bbs deck: the summary ``batball bbs`` prints (no run folder)."""
    from batball.io.keyword_bat_bbs import run_bbs_deck
    from batball.units import parse_quantity

    text = args.separation_time or "0.2 ms"
    if text.strip().lower() == "none":
        raise SpecError("separation-time", text, "a time: the rebound is read over it (0.2 ms)")
    separation = parse_quantity(text, "time", field="separation-time")
    summary = run_bbs_deck(bat, separation_time=separation, precision=args.precision)
    summary["deck"] = str(args.deck)
    summary["run_folder"] = None
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    print(describe_bbs({**summary, "run_folder": f"none (deck {args.deck})"}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
