"""The bat fitted jointly to Tables 1 and 3, and what those tables pin.

Usage: python benchmarks/bat_joint_fit.py [--runs-dir runs/joint-bat] [--json out.json]
       [--output joint_bat.toml] [--quick]

The start is the model of record's bat (``fitted``: Table 1 fitted by the end cap and two ply
thicknesses, the barrel braid fitted to the hoop modes), with the insert's plies labelled so that
they can be freed (``insert-glass``, ``insert-carbon``; labels change nothing else). Free: the
end cap's mass, the handle glass and barrel carbon thicknesses, the barrel braid angle, the
handle's braid angle, and the insert carbon's thickness and braid angle, each with its default
plausible spread (:mod:`batball.calibrate.bat_sensitivity`). Targets: Table 1 (weight, balance
point, MOI) and Table 3 (two bending, two hoop frequencies) with the resolutions of
:func:`batball.calibrate.bat_fit.joint_resolution`.

Steps, each stored under ``--runs-dir`` so that a second call replays them:

1. the sensitivity at the start: the Jacobian in resolutions per spread, its singular values and
   combinations, and each parameter's posterior over prior spread;
2. the regularised joint fit (``fit_bat`` with ``prior_sd``) on the table mesh (32 x 0.2 in,
   10-20 s a modal analysis; its frequencies are within about 1 % of the full mesh's);
3. the start and the fitted bat evaluated on the full mesh (48 x 0.1 in), so the residuals are
   the full model's;
4. with ``--bbs BALL ...``, Table 9 on the jointly fitted bat at full size (BT shells, the model
   of record's settings when it ran) for each ball: predicted cells, since no step above saw
   Table 9; and
   for each parameter the targets leave unpinned (posterior over prior spread above 0.5), the
   same balls' BBS at 110 mph with that parameter one spread higher: how far what Tables 1 and 3
   cannot see moves Table 9; with ``--all-parameters`` every parameter's, and the bat's
   linearised band on each 110-mph cell, sqrt(g^T C g) with C the posterior covariance of the
   parameters in spreads (:meth:`~batball.calibrate.bat_sensitivity.Sensitivity.propagated_spread`).

``--quick`` runs it all on a 16 x 0.5 in bat to check the script (a minute or two).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
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
    fit_bat,
    fit_summary,
    seed_bending_hz,
    write_fitted_bat,
)
from batball.calibrate.bat_sensitivity import bat_sensitivity, default_spread
from batball.specs import BatSpec, load_bat_spec
from batball.specs.seed import load_seed_tables
from batball.units import IN

INSERT_FREE = ("thickness:insert-carbon@insert", "angle:insert-carbon@insert")


def labelled_start() -> BatSpec:
    """The model of record's bat with its insert's plies labelled by material."""
    spec = load_bat_spec("fitted")
    assert spec.insert is not None
    layup = tuple(dataclasses.replace(p, label=f"insert-{p.material}") for p in spec.insert.layup)
    return dataclasses.replace(spec, insert=dataclasses.replace(spec.insert, layup=layup))


def targets(runs_dir: Path) -> JointTargets:
    """Seed Table 1 and Table 3 (experiment columns), the frequencies stored in ``runs_dir``."""
    bat = load_seed_tables().bat
    mass = MassTargets(weight=bat.weight_exp, balance_point=bat.balance_point_exp,
                       moi_pivot=bat.moi_exp)  # fmt: skip
    modal = ModalTargets(bending_hz=seed_bending_hz(), runs_dir=runs_dir)
    return JointTargets((mass, modal))


def evaluate(spec: BatSpec, joint: JointTargets, mesh: MeshOptions) -> dict[str, Any]:
    """The targets of ``spec`` on ``mesh``, with their misfits in per cent and resolutions."""
    achieved = joint.achieved(spec, mesh)
    rows = {}
    for name, value, wanted, r in zip(joint.names, achieved, joint.wanted, joint.resolution,
                                      strict=True):  # fmt: skip
        rows[name] = {"value": value, "wanted": wanted, "percent": 100 * (value / wanted - 1),
                      "resolutions": (value / wanted - 1) / r}  # fmt: skip
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs-dir", type=Path, default=Path("runs/joint-bat"))
    parser.add_argument("--json", type=Path, default=None, help="write every number here")
    parser.add_argument("--output", type=Path, default=None, help="write the fitted bat here")
    parser.add_argument("--quick", action="store_true", help="16 x 0.5 in for every step")
    parser.add_argument("--all-parameters", action="store_true", help="with --bbs: the BBS "
                        "gradient of every free parameter, not only the unpinned ones, and the "
                        "bat's linearised posterior band on each 110-mph cell")  # fmt: skip
    parser.add_argument("--bbs", nargs="*", default=[], help="balls whose Table 9 to run on "
                        "the jointly fitted bat (embedded names or files)")  # fmt: skip
    args = parser.parse_args()
    table, full = (MeshOptions(16, 0.5 * IN),) * 2 if args.quick else (
        MeshOptions(32, 0.2 * IN), MeshOptions(48, 0.1 * IN))  # fmt: skip
    start = labelled_start()
    joint = targets(args.runs_dir)
    free = tuple(FreeParameter.parse(t) for t in (*DEFAULT_JOINT_FREE, *INSERT_FREE))
    spreads = tuple(default_spread(p, start) for p in free)
    out: dict[str, Any] = {"mesh": {"table": dataclasses.asdict(table),
                                    "full": dataclasses.asdict(full)}}  # fmt: skip
    clock = time.perf_counter()
    found = bat_sensitivity(start, joint, free, spread=spreads, mesh=table)
    out["sensitivity"] = found.summary()
    out["sensitivity_seconds"] = time.perf_counter() - clock
    print(json.dumps(out["sensitivity"], indent=1), flush=True)
    clock = time.perf_counter()
    fit = fit_bat(start, joint, free, circumferential=table.circumferential,
                  axial_size=table.axial_size, prior_sd=spreads)  # fmt: skip
    out["fit"] = fit_summary(fit, joint)
    out["fit"]["shift_in_spreads"] = {
        str(p): (v - v0) / s
        for p, v0, v, s in zip(free, fit.initial, fit.values, spreads, strict=True)
    }
    out["fit_seconds"] = time.perf_counter() - clock
    print(json.dumps(out["fit"], indent=1), flush=True)
    joint_bat = dataclasses.replace(fit.spec, name="joint", description=(
        "the model of record's bat fitted jointly to Tables 1 and 3 (benchmarks/bat_joint_fit.py)"))
    if args.output is not None:
        write_fitted_bat(args.output, dataclasses.replace(fit, spec=joint_bat))
    for name, spec in (("start", start), ("joint", fit.spec)):
        out[f"{name}_full_mesh"] = evaluate(spec, joint, full)
    print(report(out, free))
    if args.bbs:
        out["table9"] = table9(joint_bat, args.bbs, args.runs_dir, args.quick)
        print(json.dumps(out["table9"], indent=1), flush=True)
        out["bbs_gradient"] = {}
        for p, spread in zip(free, spreads, strict=True):
            pinned = out["sensitivity"]["posterior_ratio"][str(p)] <= 0.5
            if pinned and not args.all_parameters:
                continue
            moved = p.apply(joint_bat, p.value(joint_bat) + spread)
            cells = table9(moved, args.bbs, args.runs_dir, args.quick, speeds=(110,))
            out["bbs_gradient"][str(p)] = {
                cell: value["bbs_mph"] - out["table9"][cell]["bbs_mph"]
                for cell, value in cells.items()
            }
        print(json.dumps(out["bbs_gradient"], indent=1))
        if args.all_parameters:
            out["bat_band_mph"] = bat_band(found, free, out["bbs_gradient"])
            print(json.dumps(out["bat_band_mph"], indent=1))
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1), encoding="utf-8")


def bat_band(found: Any, free: tuple[FreeParameter, ...],
             gradient: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:  # fmt: skip
    """Per 110-mph cell, the BBS spread [mph, one standard deviation] that the bat's parameters
    carry: a priori (the spreads alone) and a posteriori (after Tables 1 and 3), linearised."""
    cells = next(iter(gradient.values())).keys()
    band = {}
    for cell in cells:
        g = np.array([gradient[str(p)][cell] for p in free])
        band[cell] = {"prior_sd_mph": float(np.linalg.norm(g)),
                      "posterior_sd_mph": found.propagated_spread(g)}  # fmt: skip
    return band


def table9(bat: BatSpec, balls: list[str], runs_dir: Path, quick: bool,
           speeds: tuple[int, ...] = (95, 110)) -> dict[str, Any]:  # fmt: skip
    """Each ball's BBS at 95 and 110 mph on ``bat`` against the experiment [mph, %]."""
    from batball.lab.registry import LAB_TESTS
    from batball.specs import load_ball_spec
    from batball.units import MPH

    test, seed = LAB_TESTS["bbs"], load_seed_tables()
    sizes = {"divisions": 6, "circumferential": 16, "axial_size": "0.5 in"} if quick else {}
    cells: dict[str, Any] = {}
    for name in balls:
        ball = load_ball_spec(name)
        for mph in speeds:
            # the one-point BT shells these cells were stored with (the model of record's
            # element when they ran; docs/decisions.md)
            setup = test.setup(speed=f"{mph} mph", shell="bt", **sizes)
            summary, _ = test.execute({"bat": bat, "ball": ball}, setup, runs_dir=runs_dir,
                                      reuse=True)  # fmt: skip
            exp = seed.batted_ball_speed(ball.name, mph).bbs_exp / MPH
            bbs = float(summary["bbs_mph"])
            cells[f"{Path(name).stem} @ {mph} mph"] = {
                "bbs_mph": bbs, "experiment_mph": exp, "percent": 100 * (bbs / exp - 1)}
    return cells


def report(out: dict[str, Any], free: tuple[FreeParameter, ...]) -> str:
    """Markdown: the fit's parameters, then the targets before and after on the full mesh."""
    lines = ["| parameter | spread | start | joint fit | shift (spreads) | posterior / prior |",
             "|---|---|---|---|---|---|"]  # fmt: skip
    fit, sens = out["fit"], out["sensitivity"]
    for p in free:
        name = str(p)
        values = fit["parameters"][name]
        lines.append(f"| `{name}` | {sens['spread'][name]} | {values['initial']} | "
                     f"{values['fitted']} | {fit['shift_in_spreads'][name]:+.2f} | "
                     f"{sens['posterior_ratio'][name]:.2f} |")  # fmt: skip
    lines += ["", "| target | experiment | start (full mesh) | joint fit (full mesh) |",
              "|---|---|---|---|"]  # fmt: skip
    for name, row in out["joint_full_mesh"].items():
        before = out["start_full_mesh"][name]
        lines.append(f"| {name} | {row['wanted']:.5g} | {before['value']:.5g} "
                     f"({before['percent']:+.2f} %) | {row['value']:.5g} "
                     f"({row['percent']:+.2f} %) |")  # fmt: skip
    lines += ["", "singular values: " + ", ".join(
        f"{c['singular_value']:.3g}" for c in sens["combinations"])]  # fmt: skip
    return "\n".join(lines)


if __name__ == "__main__":
    main()
