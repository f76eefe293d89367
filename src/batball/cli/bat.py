"""``batball fit-bat``: chosen layup or lumped-mass values of a bat fitted to its measured mass
properties or hoop frequencies; and the bat options that commands outside the registry share."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

from batball.cli.options import add_json_option, add_options, add_store_options, add_subject
from batball.errors import SpecError
from batball.lab.registry import AXIAL_SIZE, CIRCUMFERENTIAL, PIVOT, parse_options

#: The bat's mesh and pivot, as every bat command declares them.
BAT_MESH_AND_PIVOT = (CIRCUMFERENTIAL, AXIAL_SIZE, PIVOT)


def add_bat_mesh_options(p: argparse.ArgumentParser) -> None:
    """``--bat``, the mesh density, the pivot and ``--json``."""
    add_subject(p, "bat")
    add_options(p, BAT_MESH_AND_PIVOT)
    add_json_option(p)


def bat_mesh_options(args: argparse.Namespace) -> dict[str, Any]:
    """circumferential, axial_size and pivot (SI) from the parsed options, checked."""
    return parse_options(BAT_MESH_AND_PIVOT, args)


def add_fit_bat_parser(sub: Any) -> None:
    """``batball fit-bat``: adjust chosen bat parameters to measured mass properties or hoop
    frequencies."""
    help_text = ("fit chosen layup or lumped-mass values of a bat to its weight, BP and MOI, "
                 "or to its measured hoop frequencies")  # fmt: skip
    p = sub.add_parser("fit-bat", help=help_text, description=help_text)
    add_bat_mesh_options(p)
    p.add_argument(
        "--to",
        choices=("mass", "hoop", "joint"),
        default="mass",
        help="what to match: mass (weight, balance point, MOI; seed Table 1), hoop (the "
        "first two hoop frequencies of the free-free modal test, insert as contact; Table 3) or "
        "joint (Table 1 and Table 3's two bending and two hoop frequencies together, each "
        "weighted by its measurement resolution, regularised by each parameter's spread)",
    )
    p.add_argument(
        "--barrel",
        action="store_true",
        help="with --to joint: Table 2's preload and final load as targets too (--preload, "
        "--final-load; resolutions 5 and 3 %%), each evaluation the explicit, geometrically "
        "nonlinear squeeze on MITC4 shells at the four orientations (about a minute on the "
        "32 x 0.2 in mesh, several on the full one; the loads are the mesh's own, and a coarse "
        "mesh's are stiff: 8-11 %% on 32 x 0.2 in)",
    )
    p.add_argument("--preload", help="with --barrel: target preload (default seed Table 2's "
                   "186 lbf)")  # fmt: skip
    p.add_argument("--final-load", help="with --barrel: target final load (default seed Table "
                   "2's 368 lbf)")  # fmt: skip
    p.add_argument(
        "--spread",
        action="append",
        default=[],
        help="NAME=VALUE: a free parameter's plausible spread (one standard deviation) with its "
        "unit, e.g. 'lumped_mass:endcap=0.5 oz', 'friction:insert=0.3'; repeat (default: 5 deg "
        "for an angle, 15 %% of a thickness, 0.5 oz for a lumped mass, 0.3 for the insert's "
        "friction); used by --to joint and --sensitivity",
    )
    p.add_argument(
        "--sensitivity",
        action="store_true",
        help="instead of fitting, report what the targets pin: the Jacobian in resolutions per "
        "spread, its singular values and parameter combinations, and each parameter's "
        "posterior spread over its prior spread",
    )
    p.add_argument(
        "--free",
        action="append",
        help="a parameter to adjust: lumped_mass:<part>, thickness:<ply label>[@<part>+...], "
        "angle:<ply label>[@<part>+...] or friction:insert (the insert's Coulomb coefficient, "
        "seen only with --barrel); repeat it (default for --to mass: lumped_mass:endcap, "
        "thickness:handle-glass, thickness:barrel-carbon; for --to hoop: "
        "angle:barrel-carbon@barrel-1+barrel-2+barrel-3+endcap; for --to joint: those four "
        "and angle:handle-glass@knob+handle-1+handle-2+handle-3)",
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
    p.add_argument(
        "--bending",
        nargs="+",
        default=["146 Hz", "555 Hz"],
        help="target free-free bending frequencies, lowest first, for --to joint (seed Table 3: "
        "'146 Hz' '555 Hz')",
    )
    p.add_argument("--output", type=Path, help="write the fitted bat to this TOML file "
                   "(not with --sensitivity, which fits nothing)")  # fmt: skip
    add_store_options(p)
    p.set_defaults(handler=run_fit_bat_command)


def run_fit_bat_command(args: argparse.Namespace) -> int:
    """``batball fit-bat``; exits with status 1 when the fit fails or a bound stops it."""
    from batball.calibrate.bat_fit import (
        DEFAULT_FREE,
        DEFAULT_HOOP_FREE,
        DEFAULT_JOINT_FREE,
        FreeParameter,
        MeshOptions,
        fit_bat,
        fit_summary,
        write_fitted_bat,
    )
    from batball.calibrate.bat_sensitivity import bat_sensitivity
    from batball.results.store import check_output_file, check_output_folder
    from batball.specs import load_bat_spec

    spec = load_bat_spec(args.bat)
    options = bat_mesh_options(args)
    pivot = options.pop("pivot")
    if args.output is not None:
        if args.sensitivity:
            raise SpecError("output", str(args.output), "no --output with --sensitivity (it "
                            "fits nothing; --json writes its report)")  # fmt: skip
        check_output_file("output", args.output)
    if args.barrel and args.to != "joint":
        raise SpecError("barrel", f"--to {args.to}", "--to joint (Table 2 joins Tables 1 and 3)")
    for name in ("preload", "final_load"):
        if getattr(args, name) is not None and not args.barrel:
            raise SpecError(name.replace("_", "-"), getattr(args, name), "only with --barrel")
    if args.spread and args.to != "joint":
        raise SpecError("spread", " ".join(args.spread), "--to joint (only the joint fit and "
                        "--sensitivity use spreads)")  # fmt: skip
    check_output_folder("runs-dir", args.runs_dir)
    targets = fit_targets(args, pivot)
    default_free = {"mass": DEFAULT_FREE, "hoop": DEFAULT_HOOP_FREE, "joint": DEFAULT_JOINT_FREE}
    free = tuple(FreeParameter.parse(text) for text in (args.free or default_free[args.to]))
    if not args.barrel and any(p.kind == "friction" for p in free):
        raise SpecError("free", "friction:insert", "only with --barrel (no other target sees "
                        "the insert's friction)")  # fmt: skip
    spreads = parameter_spreads(args.spread, free, spec)
    if args.sensitivity:
        if args.to != "joint":
            raise SpecError("sensitivity", f"--to {args.to}", "--to joint (targets with "
                            "resolutions)")  # fmt: skip
        found = bat_sensitivity(spec, targets, free, spread=spreads, mesh=MeshOptions(**options))
        report = {"bat": spec.name, "targets": targets.description, **found.summary()}
        print(json.dumps(report, indent=2) if args.json else describe_sensitivity(report))
        return 0
    prior = spreads if args.to == "joint" else None
    fit = fit_bat(spec, targets, free, **options, prior_sd=prior)
    if args.output is not None:
        write_fitted_bat(args.output, fit)
    summary = fit_summary(fit, targets)
    print(json.dumps(summary, indent=2) if args.json else describe_fit(summary))
    return 0 if fit.matched else 1


def fit_targets(args: argparse.Namespace, pivot: float) -> Any:
    """The targets of ``--to``: mass, hoop or both with the bending frequencies (joint)."""
    from batball.calibrate.bat_fit import (
        BarrelTargets,
        JointTargets,
        MassTargets,
        ModalTargets,
        seed_table2_lbf,
    )
    from batball.units import LBF, parse_quantity

    hoop = frequencies("hoop", args.hoop)
    mass = MassTargets(
        weight=parse_quantity(args.weight, "mass", field="weight"),
        balance_point=parse_quantity(args.balance_point, "length", field="balance-point"),
        moi_pivot=parse_quantity(args.moi, "moment_of_inertia", field="moi"),
        pivot=pivot,
    )
    store = {"runs_dir": args.runs_dir, "reuse": not args.no_reuse}
    if args.to == "mass":
        return mass
    if args.to == "hoop":
        return ModalTargets(hoop_hz=hoop, **store)
    bending = frequencies("bending", args.bending)
    parts: tuple[Any, ...] = (mass, ModalTargets(hoop_hz=hoop, bending_hz=bending, **store))
    if args.barrel:
        seed = seed_table2_lbf()
        given = (("preload", args.preload, seed[0]), ("final-load", args.final_load, seed[1]))
        loads = tuple(default if text is None else parse_quantity(text, "force", field=name) / LBF
                      for name, text, default in given)  # fmt: skip
        for name, value in zip(("preload", "final-load"), loads, strict=True):
            if not value > 0.0:
                raise SpecError(name, f"{value:g} lbf", "a positive load, e.g. '186 lbf'")
        parts = (*parts, BarrelTargets(wanted_lbf=loads, **store))
    return JointTargets(parts)


def frequencies(field: str, texts: list[str]) -> tuple[float, ...]:
    """Measured frequencies [Hz] from ``texts`` ('1450 Hz'), positive and lowest first."""
    from batball.units import parse_quantity

    found = tuple(parse_quantity(text, "frequency", field=field) for text in texts)
    if not all(f > 0 for f in found) or list(found) != sorted(set(found)):
        raise SpecError(field, " ".join(texts), "positive frequencies, lowest first")
    return found


def parameter_spreads(texts: list[str], free: tuple[Any, ...], spec: Any) -> tuple[float, ...]:
    """Each free parameter's spread: ``--spread NAME=VALUE`` or its default."""
    from batball.calibrate.bat_fit import PARAMETER_KINDS
    from batball.calibrate.bat_sensitivity import default_spread
    from batball.specs.bat import parse_angle
    from batball.units import parse_quantity

    def parse(kind: str, value: str) -> float:
        if kind == "friction":
            try:
                found = float(value)
            except ValueError:
                raise SpecError("spread", value, "a number without a unit, e.g. 0.3") from None
            return found if math.isfinite(found) else -1.0  # refused below as not positive
        if kind == "angle":
            return parse_angle(value, field="spread")
        return parse_quantity(value, "mass" if kind == "lumped_mass" else "length", field="spread")

    given: dict[str, float] = {}
    names = [str(p) for p in free]
    for text in texts:
        name, _, value = text.rpartition("=")
        if name not in names:
            raise SpecError("spread", text, f"NAME=VALUE with NAME one of {', '.join(names)}")
        kind = free[names.index(name)].kind
        unit = PARAMETER_KINDS[kind].unit
        given[name] = parse(kind, value)
        if not given[name] > 0.0:
            example = f"1 {unit}" if unit else "0.3"
            raise SpecError("spread", text, f"a positive spread, e.g. '{name}={example}'")
    return tuple(given.get(str(p), default_spread(p, spec)) for p in free)


def describe_sensitivity(s: dict[str, Any]) -> str:
    """The identifiability report as text: combinations, then each parameter's ratio."""
    lines = [f"What {s['targets']} pin on bat {s['bat']} (resolutions per spread):"]
    for k, c in enumerate(s["combinations"], start=1):
        weights = ", ".join(f"{w:+.2f} {p}" for p, w in c["parameters"].items() if abs(w) >= 0.1)
        moved = ", ".join(f"{n} {v:+.2f}" for n, v in c["moves_targets"].items()
                          if abs(v) >= 0.1)  # fmt: skip
        lines.append(f"  {k}. singular value {c['singular_value']:.3g}: {weights}")
        lines.append(f"     moves {moved or 'no target by 0.1 resolution'}")
    lines.append("  posterior spread / prior spread (1: the targets say nothing about it):")
    for p, ratio in s["posterior_ratio"].items():
        lines.append(f"    {p:<52} {ratio:.3f}  (spread {s['spread'][p]})")
    return "\n".join(lines)


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
