"""What Table 2 adds to the joint bat fit: the sensitivity of Tables 1, 2 and 3 to the bat's
free parameters and the insert's friction, and what that does to the bat's band on Table 9.

Usage: python benchmarks/bat_table2_sensitivity.py [--runs-dir runs/joint-bat] [--json out.json]
       [--step] [--bbs BALL ...] [--quick]

The bat is the jointly fitted one (``benchmarks/bats/joint_bat.toml``, fitted to Tables 1 and 3
by ``bat_joint_fit.py``). Free: its seven parameters (``bat_joint_fit.py``) and the insert's
Coulomb coefficient ``friction:insert``, each with its default plausible spread taken at the
model of record's bat (as ``bat_joint_fit.py`` took them, so the BBS gradients it stored in
``benchmarks/bats/joint_band.json`` hold). Targets: Table 1 (weight, balance point, MOI),
Table 3 (two bending, two hoop frequencies) and Table 2 (preload, final load: the explicit,
geometrically nonlinear squeeze on MITC4 shells at the four orientations), with the
resolutions of :func:`batball.calibrate.bat_fit.joint_resolution`.

Steps, each stored under ``--runs-dir`` so that a second call replays them:

1. Table 2 at 0 deg on the full mesh (48 x 0.1 in) and the table mesh (32 x 0.2 in): their ratio
   is the mesh correction of the table-mesh loads (:class:`~batball.calibrate.bat_fit.
   BarrelTargets`' ``correction``), so the misfits are the full mesh's;
2. the sensitivity on the table mesh: the Jacobian in resolutions per spread for all nine
   targets, its singular values and combinations, each parameter's posterior over prior spread
   with and without Table 2's rows;
3. the bat's linearised band on the 110-mph cells with and without Table 2: sqrt(g^T C g) with
   C the posterior covariance and g the BBS gradients (seven from ``joint_band.json``; the
   friction's with ``--bbs``: the balls' BBS at 110 mph on the joint bat with the friction one
   spread up, full size, BT shells, the model of record's settings, less the joint bat's as
   ``bat_joint_fit.py`` stored it in ``benchmarks/bats/joint_fit.json``);
4. with ``--step``, one Gauss-Newton step of the regularised fit with Table 2 from the joint
   bat (the prior centred on the model of record's bat, as the joint fit's), linearised on the
   Jacobian above, and that bat evaluated on the full mesh: Tables 1-3, and with ``--bbs``
   its 110-mph Table 9 cells.

``--quick`` runs it all on a 16 x 0.4 in bat with one orientation to check the script.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path
from typing import Any

import numpy as np
from bat_joint_fit import INSERT_FREE, evaluate, labelled_start, table9, targets

from batball.calibrate.bat_fit import (
    DEFAULT_JOINT_FREE,
    BarrelTargets,
    FreeParameter,
    JointTargets,
    MeshOptions,
)
from batball.calibrate.bat_sensitivity import Sensitivity, bat_sensitivity, default_spread
from batball.specs import load_bat_spec
from batball.units import IN

HERE = Path(__file__).resolve().parent
FRICTION = "friction:insert"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs-dir", type=Path, default=Path("runs/joint-bat"))
    parser.add_argument("--json", type=Path, default=None, help="write every number here")
    parser.add_argument("--quick", action="store_true", help="16 x 0.5 in, one orientation")
    parser.add_argument("--step", action="store_true", help="one Gauss-Newton step with "
                        "Table 2, evaluated on the full mesh")  # fmt: skip
    parser.add_argument("--bbs", nargs="*", default=[], help="balls whose 110-mph BBS gives "
                        "the friction's gradient (and with --step the stepped bat's Table 9)")
    args = parser.parse_args()
    table, full = (MeshOptions(16, 0.4 * IN),) * 2 if args.quick else (
        MeshOptions(32, 0.2 * IN), MeshOptions(48, 0.1 * IN))  # fmt: skip
    orientations = (0.0,) if args.quick else (0.0, 90.0, 45.0, -45.0)
    start = labelled_start()
    joint_bat = load_bat_spec(HERE / "bats" / "joint_bat.toml")
    free = tuple(FreeParameter.parse(t) for t in (*DEFAULT_JOINT_FREE, *INSERT_FREE, FRICTION))
    spreads = tuple(default_spread(p, start) for p in free)
    out: dict[str, Any] = {"mesh": {"table": dataclasses.asdict(table),
                                    "full": dataclasses.asdict(full)},
                           "orientations_deg": list(orientations)}  # fmt: skip

    # 1. the mesh correction of the loads, at 0 deg
    at_zero = BarrelTargets(orientations_deg=(0.0,), runs_dir=args.runs_dir)
    coarse, fine = (at_zero.achieved(joint_bat, mesh) for mesh in (table, full))
    correction = tuple(f / c for f, c in zip(fine, coarse, strict=True))
    out["table2_at_0deg"] = {"table_mesh_lbf": coarse, "full_mesh_lbf": fine,
                             "correction": correction}  # fmt: skip
    print(json.dumps(out["table2_at_0deg"]), flush=True)

    # 2. the sensitivity with all nine targets
    barrel = BarrelTargets(orientations_deg=orientations, correction=correction,
                           runs_dir=args.runs_dir)  # fmt: skip
    modal_mass = targets(args.runs_dir)
    joint = JointTargets((*modal_mass.parts, barrel))
    clock = time.perf_counter()
    found = bat_sensitivity(joint_bat, joint, free, spread=spreads, mesh=table)
    out["sensitivity_seconds"] = time.perf_counter() - clock
    out["sensitivity"] = found.summary()
    without = rows(found, exclude=barrel.names)
    out["posterior_ratio_without_table2"] = dict(zip(
        (str(p) for p in free), without.posterior_ratio.round(3).tolist(), strict=True))
    print(json.dumps(out["sensitivity"], indent=1), flush=True)
    print(json.dumps(out["posterior_ratio_without_table2"], indent=1), flush=True)

    # 3. the band: the friction's BBS gradient, then sqrt(g^T C g) with and without Table 2
    gradient = json.loads((HERE / "bats" / "joint_band.json").read_text())["bbs_gradient"]
    if args.bbs:
        base = stored_table9(args.bbs) if not args.quick else {}
        if len(base) < len(args.bbs):
            base = table9(joint_bat, args.bbs, args.runs_dir, args.quick, speeds=(110,))
        friction = free[-1]
        rubbing = friction.apply(joint_bat, spreads[-1])
        moved = table9(rubbing, args.bbs, args.runs_dir, args.quick, speeds=(110,))
        gradient[FRICTION] = {cell: moved[cell]["bbs_mph"] - base[cell]["bbs_mph"]
                              for cell in base}  # fmt: skip
        out["bbs_110"] = {"joint": base, "friction_one_spread": moved}
        out["bbs_gradient"] = gradient
        out["bat_band_mph"] = band(found, without, free, gradient)
        print(json.dumps(out["bat_band_mph"], indent=1), flush=True)

    # 4. one Gauss-Newton step of the regularised fit with Table 2
    if args.step:
        offset = np.array([(p.value(joint_bat) - p.value(start)) / s
                           for p, s in zip(free, spreads, strict=True)])  # fmt: skip
        delta = gauss_newton(found, offset)
        stepped = joint_bat
        for p, s, d in zip(free, spreads, delta, strict=True):
            stepped = p.apply(stepped, max(p.value(joint_bat) + d * s, 0.0))
        stepped = dataclasses.replace(stepped, name="joint-table2", description=(
            "the joint bat after one linearised step toward Tables 1-3 "
            "(benchmarks/bat_table2_sensitivity.py)"))  # fmt: skip
        out["step_spreads"] = dict(zip((str(p) for p in free), delta.round(3).tolist(),
                                       strict=True))  # fmt: skip
        out["step_values"] = {str(p): p.value(stepped) for p in free}
        print(json.dumps(out["step_spreads"], indent=1), flush=True)
        full_barrel = BarrelTargets(orientations_deg=orientations, runs_dir=args.runs_dir)
        full_joint = JointTargets((*modal_mass.parts, full_barrel))
        for name, spec in (("joint", joint_bat), ("stepped", stepped)):
            out[f"{name}_full_mesh"] = evaluate(spec, full_joint, full)
            print(name, json.dumps(out[f"{name}_full_mesh"], indent=1), flush=True)
        if args.bbs:
            out["stepped_table9"] = table9(stepped, args.bbs, args.runs_dir, args.quick,
                                           speeds=(110,))  # fmt: skip
            print(json.dumps(out["stepped_table9"], indent=1), flush=True)
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1), encoding="utf-8")


def stored_table9(balls: list[str]) -> dict[str, Any]:
    """The joint bat's 110-mph cells as ``bat_joint_fit.py --bbs`` stored them (same code, same
    settings), for the balls named; missing ones are left out."""
    stored = json.loads((HERE / "bats" / "joint_fit.json").read_text())["table9"]
    cells = (f"{Path(name).stem} @ 110 mph" for name in balls)
    return {cell: stored[cell] for cell in cells if cell in stored}


def rows(found: Sensitivity, *, exclude: tuple[str, ...]) -> Sensitivity:
    """The same sensitivity without the targets named in ``exclude``."""
    keep = [k for k, name in enumerate(found.names) if name not in exclude]
    pick = [found.names, found.wanted, found.resolution, found.achieved]
    names, wanted, resolution, achieved = (tuple(v[k] for k in keep) for v in pick)
    return dataclasses.replace(found, names=names, wanted=wanted, resolution=resolution,
                               achieved=achieved, jacobian=found.jacobian[keep])  # fmt: skip


def band(found: Sensitivity, without: Sensitivity, free: tuple[FreeParameter, ...],
         gradient: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:  # fmt: skip
    """Per 110-mph cell, the bat's linearised BBS spread [mph, one standard deviation]: a
    priori, after Tables 1 and 3, and after Tables 1-3."""
    cells = gradient[FRICTION].keys()
    out = {}
    for cell in cells:
        g = np.array([gradient[str(p)][cell] for p in free])
        out[cell] = {"prior_sd_mph": float(np.linalg.norm(g)),
                     "tables_1_3_sd_mph": without.propagated_spread(g),
                     "tables_1_2_3_sd_mph": found.propagated_spread(g)}  # fmt: skip
    return out


def gauss_newton(found: Sensitivity, offset: np.ndarray) -> np.ndarray:
    """The step [spreads] that minimises |r + J d|^2 + |offset + d|^2, linearised: r the
    misfits in resolutions at the bat, offset its distance from the prior's centre."""
    j, r = found.jacobian, found.misfit()
    return np.asarray(-np.linalg.solve(j.T @ j + np.eye(j.shape[1]), j.T @ r + offset))


if __name__ == "__main__":
    main()
