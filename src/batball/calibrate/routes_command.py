"""``batball compare-calibrations`` and ``batball synthetic-data``.

Import-light at module level (the CLI builds its parser from here).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path
from typing import Any

from batball.errors import SpecError
from batball.units import MPH

#: Defaults of the comparison's meshes: the coarse ball and bat the synthetic data set uses.
DEFAULT_DIVISIONS = 8


def add_bbs_run_arguments(p: argparse.ArgumentParser) -> None:
    """The BBS runs' end time and time-step scale (both commands)."""
    p.add_argument("--end-time", default="2 ms", help="longest BBS run (2 ms)")
    p.add_argument(
        "--time-step-scale", type=float, default=0.9, help="BBS runs' time-step scale (0.9)"
    )


def add_compare_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``batball compare-calibrations`` (the bat mesh options come from cli)."""
    p.add_argument(
        "--ball",
        default="type1",
        help="base ball: its size and mass, and the impact routes' starting material",
    )
    p.add_argument("--cor-targets", type=Path, help="flat-wall route: cor/wall_peak_force targets")
    p.add_argument(
        "--ccor-targets",
        type=Path,
        help="cylinder route: targets (default for type1/type2: seed Tables 5-8)",
    )
    p.add_argument("--no-ccor", action="store_true", help="skip the cylinder route")
    p.add_argument("--dma", type=Path, help="DMA route: CSV frequency_hz,storage_psi,loss_psi ...")
    p.add_argument(
        "--dma-modulus",
        choices=("shear", "tensile"),
        default="shear",
        help="the DMA moduli are shear G (default) or tensile E",
    )
    p.add_argument("--poisson-ratio", type=float, help="nu for tensile DMA data")
    p.add_argument("--bulk-modulus", help="K for the DMA ball (default: the base ball's)")
    p.add_argument(
        "--use",
        action="append",
        default=[],
        help="ROUTE=BALL.toml: a ball already calibrated by that route; repeat",
    )
    p.add_argument(
        "--model",
        default="mat006",
        choices=("mat006", "prony1", "prony2", "prony3"),
        help="model fitted by the impact routes (mat006)",
    )
    p.add_argument("--prony-terms", type=int, default=3, help="Prony terms of the DMA fit (3)")
    p.add_argument("--speeds", action="append", help="BBS inbound speed; repeat (95, 110 mph)")
    p.add_argument(
        "--measured-bbs",
        type=Path,
        help="TOML of [[bbs]] speed, value (measured); 'none': no measured BBS (else, for "
        "type1/type2, the seed's Table 9)",
    )
    p.add_argument("--truth", help="a known true ball (synthetic data): its BBS and G(t) too")
    p.add_argument(
        "--divisions",
        type=int,
        default=DEFAULT_DIVISIONS,
        help="ball mesh of the calibrations and the BBS runs (8)",
    )
    p.add_argument("--global-points", type=int, default=8, help="Latin-hypercube points (8)")
    p.add_argument("--max-evaluations", type=int, default=15, help="least-squares budget (15)")
    p.add_argument("--workers", type=int, help="process pool size (default: CPU cores)")
    add_bbs_run_arguments(p)


def add_synthetic_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``batball synthetic-data``."""
    p.add_argument(
        "--truth",
        default="benchmarks/routes/synthetic/true-ball.toml",
        help="the true ball (a Prony or MAT_057/MAT_083 foam ball TOML)",
    )
    p.add_argument(
        "--out",
        type=Path,
        default=Path("benchmarks/routes/synthetic"),
        help="folder for the route data files",
    )
    p.add_argument("--divisions", type=int, default=DEFAULT_DIVISIONS, help="ball mesh (8)")
    p.add_argument("--speeds", action="append", help="BBS inbound speed; repeat (95, 110 mph)")
    p.add_argument(
        "--no-bbs",
        action="store_true",
        help="skip the truth's BBS runs (bbs.toml then says so), e.g. to make the impact and "
        "DMA data quickly",
    )
    add_bbs_run_arguments(p)


def add_noise_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``batball synthetic-noise``."""
    from batball.calibrate.noise import NoiseLevels

    d = NoiseLevels()
    p.add_argument(
        "--source",
        type=Path,
        default=Path("benchmarks/routes/synthetic"),
        help="folder of exact route data (batball synthetic-data's --out)",
    )
    p.add_argument("--out", type=Path, required=True, help="folder for seed-<N>/ copies")
    p.add_argument("--seeds", type=int, nargs="+", default=[1], help="one noisy copy per seed")
    p.add_argument("--restitution-sd", type=float, default=d.restitution, help="COR/CCOR, abs.")
    p.add_argument("--force-sd", type=float, default=d.force, help="DS, peak forces, relative")
    p.add_argument("--contact-time-sd", type=float, default=d.contact_time, help="relative")
    p.add_argument("--dma-sd", type=float, default=d.dma, help="DMA moduli, relative")


def run_noise_command(args: argparse.Namespace) -> int:
    """``batball synthetic-noise``: seeded noisy copies of a synthetic route data set."""
    from batball.calibrate.noise import DMA_FILES, TARGET_FILES, NoiseLevels, write_noisy_data
    from batball.results.store import check_output_folder

    data = (*TARGET_FILES, *DMA_FILES)
    if not any((args.source / name).is_file() for name in data):
        raise SpecError("source", str(args.source),
                        f"a folder holding route data ({', '.join(data)})")  # fmt: skip
    check_output_folder("out", args.out)
    levels = NoiseLevels(
        restitution=args.restitution_sd,
        force=args.force_sd,
        contact_time=args.contact_time_sd,
        dma=args.dma_sd,
    )
    written = {}
    for seed in args.seeds:
        paths = write_noisy_data(args.source, args.out / f"seed-{seed}", seed=seed, levels=levels)
        written[str(seed)] = {k: v.as_posix() for k, v in paths.items()}
    print(json.dumps({"levels": dataclasses.asdict(levels), "files": written}, indent=2))
    return 0


def _speeds_mph(args: argparse.Namespace) -> list[float]:
    from batball.units import parse_quantity

    texts = args.speeds or ["95 mph", "110 mph"]
    return [round(parse_quantity(t, "velocity", field="speeds") / MPH, 3) for t in texts]


def _bbs_setup(args: argparse.Namespace) -> Any:
    """The BBS setup of the options, built by the lab registry's bbs entry (the speed is set per
    run); the time-step scale, which ``batball bbs`` does not take, is set on it after."""
    import dataclasses

    from batball.lab.registry import LAB_TESTS

    if not 0.0 < args.time_step_scale <= 1.0:
        raise SpecError("time-step-scale", args.time_step_scale, "0 < scale <= 1")
    setup = LAB_TESTS["bbs"].setup(
        divisions=args.divisions, circumferential=args.circumferential,
        axial_size=args.axial_size, pivot=args.pivot, end_time=args.end_time,
    )  # fmt: skip
    return dataclasses.replace(setup, time_step_scale=args.time_step_scale)


def route_data(args: argparse.Namespace, ball_name: str) -> list[Any]:
    """The routes whose data the options give, in the order cor, ccor, dma."""
    from batball.calibrate import load_targets, seed_targets
    from batball.calibrate.dma import load_dma_csv
    from batball.calibrate.routes import ROUTES, RouteData
    from batball.specs import load_ball_spec
    from batball.specs.ball import EMBEDDED_BALLS
    from batball.units import parse_quantity

    reused = {}
    for item in args.use:
        route, _, path = item.partition("=")
        if route not in ROUTES or not path:
            raise SpecError("use", item, f"ROUTE=BALL.toml with ROUTE one of {', '.join(ROUTES)}")
        reused[route] = RouteData(route, calibrated=load_ball_spec(path), source=path)
    k = (
        None
        if args.bulk_modulus is None
        else parse_quantity(args.bulk_modulus, "pressure", field="bulk-modulus")
    )
    routes = []
    if "cor" in reused:
        routes.append(reused["cor"])
    elif args.cor_targets is not None:
        routes.append(
            RouteData("cor", load_targets(args.cor_targets), source=str(args.cor_targets))
        )
    if "ccor" in reused:
        routes.append(reused["ccor"])
    elif args.ccor_targets is not None:
        routes.append(
            RouteData("ccor", load_targets(args.ccor_targets), source=str(args.ccor_targets))
        )
    elif not args.no_ccor and ball_name in EMBEDDED_BALLS:
        routes.append(RouteData("ccor", seed_targets(ball_name), source="seed Tables 5-8"))
    if "dma" in reused:
        routes.append(reused["dma"])
    elif args.dma is not None:
        data = load_dma_csv(
            args.dma, modulus=args.dma_modulus, poisson_ratio=args.poisson_ratio, bulk_modulus=k
        )
        routes.append(RouteData("dma", dma=data, bulk_modulus=k, source=str(args.dma)))
    if not routes:
        raise SpecError("routes", "none", "--cor-targets, --ccor-targets, --dma or --use data")
    return routes


def measured_bbs(args: argparse.Namespace, ball_name: str, speeds: list[float]) -> dict:
    """{speed mph: measured BBS mph}: the --measured-bbs file, else the seed's Table 9."""
    from batball.calibrate.routes import load_measured_bbs
    from batball.specs.ball import EMBEDDED_BALLS
    from batball.specs.seed import load_seed_tables

    if args.measured_bbs is not None:
        if str(args.measured_bbs) == "none":
            return {}
        return load_measured_bbs(args.measured_bbs)
    if ball_name not in EMBEDDED_BALLS:
        return {}
    tables = load_seed_tables()
    return {
        mph: tables.batted_ball_speed(ball_name, mph).bbs_exp / MPH
        for mph in speeds
        if mph in (95.0, 110.0)
    }


def run_compare_command(args: argparse.Namespace) -> int:
    """``batball compare-calibrations``."""
    from batball.calibrate.routes import RouteOptions, compare_routes
    from batball.specs import load_ball_spec, load_bat_spec

    if args.poisson_ratio is not None and not -1.0 < args.poisson_ratio < 0.5:
        raise SpecError("poisson-ratio", args.poisson_ratio, "-1 < nu < 0.5")
    base = load_ball_spec(args.ball)
    speeds = _speeds_mph(args)
    options = RouteOptions(
        model=args.model,
        prony_terms=args.prony_terms,
        global_points=args.global_points,
        max_evaluations=args.max_evaluations,
        divisions=args.divisions,
        study_dir=args.runs_dir,
        workers=args.workers,
    )
    report = compare_routes(
        base,
        route_data(args, base.name),
        options,
        bat=load_bat_spec(args.bat),
        bbs_setup=_bbs_setup(args),
        speeds_mph=speeds,
        measured=measured_bbs(args, base.name, speeds),
        runs_dir=args.runs_dir,
        truth=None if args.truth is None else load_ball_spec(args.truth),
    )
    print(json.dumps(report, indent=2) if args.json else describe_comparison(report))
    return 0


def describe_comparison(r: dict[str, Any]) -> str:
    """The text table: per route, the BBS per speed against the measured, and G(t)."""
    speeds = list(r["measured_bbs_mph"]) or list(r["routes"][0]["bbs_mph"])
    head = "  ".join(f"{s + ' mph':>16}" for s in speeds)
    lines = [
        f"calibration routes for ball {r['ball']} (impact routes fit {r['model']}, "
        f"{r['divisions']}-division ball)",
        f"  {'route':<8} {'BBS (error), mph':<10}",
        f"  {'':<8} {head}",
    ]

    def cells(bbs: dict, err: dict) -> str:
        return "  ".join(
            f"{bbs[s]:7.2f} ({err[s]:+6.2f})" if s in err else f"{bbs[s]:16.2f}"
            for s in speeds
            if s in bbs
        )

    if r["measured_bbs_mph"]:
        lines.append(
            f"  {'measured':<8} " + "  ".join(f"{r['measured_bbs_mph'][s]:16.2f}" for s in speeds)
        )
    if "truth" in r:
        lines.append(f"  {'truth':<8} {cells(r['truth']['bbs_mph'], {})}")
    for row in r["routes"]:
        lines.append(f"  {row['route']:<8} {cells(row['bbs_mph'], row['bbs_error_mph'])}")
    lines.append("  shear relaxation G(t), psi, at " + ", ".join(r["routes"][0]["relaxation_psi"]))
    for row in ([{"route": "truth", **r["truth"]}] if "truth" in r else []) + r["routes"]:
        g = ", ".join(f"{v:.0f}" for v in row["relaxation_psi"].values())
        lines.append(f"  {row['route']:<8} {row['law']:<7} {g}")
    if r.get("best_route"):
        lines.append(f"  closest BBS (mean |error| over the speeds): {r['best_route']}")
    return "\n".join(lines)


def run_synthetic_command(args: argparse.Namespace) -> int:
    """``batball synthetic-data``: measure the true ball and write the routes' data files."""
    from batball.calibrate.routes import measure_synthetic
    from batball.lab.bbs_run import run_bbs_test
    from batball.results.store import check_output_folder
    from batball.specs import load_ball_spec, load_bat_spec

    truth = load_ball_spec(args.truth)
    setup, bat = _bbs_setup(args), load_bat_spec(args.bat)
    check_output_folder("out", args.out)
    check_output_folder("runs-dir", args.runs_dir)
    bbs = {}
    for mph in [] if args.no_bbs else _speeds_mph(args):
        summary, _ = run_bbs_test(
            bat, truth, dataclasses.replace(setup, speed=mph * MPH), runs_dir=args.runs_dir
        )
        bbs[mph] = float(summary["bbs_mph"])
    mesh = f"{bat.name}, {args.circumferential} shells round, axial size {args.axial_size}"
    if args.no_bbs:
        mesh += "; not measured (--no-bbs)"
    paths = measure_synthetic(
        truth, args.out, divisions=args.divisions, bbs_runs=bbs, bbs_mesh=mesh
    )
    report = {
        "truth": truth.name,
        "files": {k: str(v) for k, v in paths.items()},
        "bbs_mph": {f"{k:g}": v for k, v in bbs.items()},
    }
    print(json.dumps(report, indent=2))
    return 0
