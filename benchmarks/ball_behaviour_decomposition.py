"""Which ball behaviour sets the batted-ball speed: the two ball sets through four targets.

Usage: python benchmarks/ball_behaviour_decomposition.py [--runs-dir runs/decomposition]
       [--quick] [--json out.json]

The ball sets:

- ``seed``: the seed's Table 4 MAT_006 balls (``type1``, ``type2``) with the hourglass control
  that reproduces the seed's LS-DYNA Tables 5-8 (IHQ 4, QM 0.01): the solver check's balls.
- ``fitted``: the model of record's balls (``type1-fit``, ``type2-fit``, MAT_057 foams fitted to
  the experiment's Tables 5-8), with the settings they were fitted with.
- ``seed-viscous``: the seed's balls with batball's default hourglass control (viscous, type 1,
  0.1) instead of the stiffness form: what the hourglass form itself does (the cylinder and the
  flexible bat only).
- ``mat006-fit``: the MAT_006 balls fitted to the experiment's Tables 5-8 on the 12-division ball
  (``benchmarks/calibration/type{1,2}-mat006.toml``, viscous hourglass): the seed's law fitted
  (the cylinder, the rigid bat and the flexible bats).
- ``mat006-ihq4-fit``: the same law fitted the same way with the seed's stiffness hourglass form
  (IHQ 4, QM 0.01) as part of the model (``benchmarks/calibration/type{1,2}-mat006-ihq4.toml``,
  the form in the files' ``[hourglass]``): the seed's model form, fitted to the experiment (the
  cylinder, the rigid bat and the flexible bats).
- ``prony3-fit``: three relaxation times instead of one (``type{1,2}-prony3.toml``, fitted from
  the MAT_006 fits; viscous hourglass): what a broader relaxation spectrum does (the cylinder and
  the flexible bats).

Each ball, at 95 and 110 mph, against four targets that give the ball more and more to share the
collision with: the rigid half-cylinder of ASTM F2845 (the CCOR test), the model of record's bat
held still (``fixed_bat``), the same bat as a rigid body on the 6-in pivot (``rigid_bat``), and
the flexible bat on the pivot (the BBS test of ASTM F2219). The flexible bat also runs with the
reconstruction ``default``, so the first table is Table 9 code to code at both bats.

Per run, from ``history.csv`` and the ball's field frames: contact time (force above 0), time
to peak force, peak force, the ball's largest compression (the diameter minus its shortest
extent, from the field frames, so at the frames' spacing) and mean compressive strain rate
(compression / diameter / time to peak), and the energies as fractions of the ball's initial
kinetic energy: the ball's internal energy at its peak and at the end (kept: dissipated, plus
the strain energy of the ball's vibration), the ball's hourglass energy at its peak and at the
end, the bat's internal energy at its peak and at the end; what each returned (peak minus end);
the energy the ball's bulk viscosity dissipated;
and the outcome: the rebound over the inbound speed (every target), BBCOR and BBS on the
pivoting bats. On the bats
the contact time counts every step with a contact force; on the cylinder it is the CCOR test's
(force above a fraction of the peak), so the two are not comparable.

Every run is stored in ``--runs-dir`` under its inputs: a second call reuses them (the tables are
made again in seconds), an interrupted one resumes. Full size (12,096-hex balls, 48 x 0.1 in
shells) is 92 runs, about an hour and a half on 2 cores; ``--quick`` (6-division balls, 16 x 0.5 in
shells) checks the script in a minute or two.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
from pathlib import Path
from typing import Any

import numpy as np

from batball.errors import SimulationError
from batball.lab.bbs_run import run_bbs_test
from batball.lab.registry import LAB_TESTS
from batball.results.fields import read_fields
from batball.specs import load_ball_spec, load_bat_spec
from batball.specs.seed import load_seed_tables
from batball.units import MPH

#: The ball sets: name -> (balls, registry options of their numerics).
BALL_SETS: dict[str, tuple[tuple[str, str], dict[str, Any]]] = {
    "seed": (("type1", "type2"), {"hourglass_type": 4, "hourglass_coefficient": 0.01}),
    "fitted": (("type1-fit", "type2-fit"), {}),
    "seed-viscous": (("type1", "type2"), {}),
    "mat006-fit": (("benchmarks/calibration/type1-mat006.toml",
                    "benchmarks/calibration/type2-mat006.toml"), {}),
    "mat006-ihq4-fit": (("benchmarks/calibration/type1-mat006-ihq4.toml",
                         "benchmarks/calibration/type2-mat006-ihq4.toml"), {}),
    "prony3-fit": (("benchmarks/calibration/type1-prony3.toml",
                    "benchmarks/calibration/type2-prony3.toml"), {}),
}
#: Ball sets run on some targets only (target, bat); in Table 9 when on both flexible bats.
PARTIAL_SETS = {"seed-viscous": (("cylinder", "fitted"), ("flexible bat", "fitted")),
                "mat006-fit": (("cylinder", "fitted"), ("rigid bat", "fitted"),
                               ("flexible bat", "fitted"), ("flexible bat", "default")),
                "mat006-ihq4-fit": (("cylinder", "fitted"), ("rigid bat", "fitted"),
                                    ("flexible bat", "fitted"), ("flexible bat", "default")),
                "prony3-fit": (("cylinder", "fitted"), ("flexible bat", "fitted"),
                               ("flexible bat", "default"))}
SPEEDS_MPH = (95, 110)
TARGETS = ("cylinder", "held bat", "rigid bat", "flexible bat")
#: The model of record's bat (the decomposition) and the reconstruction (Table 9 code to code).
BAT, OTHER_BAT = "fitted", "default"


def history(folder: Path) -> dict[str, np.ndarray]:
    """A run's history.csv as columns."""
    with open(folder / "history.csv", encoding="utf-8", newline="") as stream:
        rows = list(csv.DictReader(stream))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def compression_in(folder: Path, diameter_in: float) -> float:
    """The ball's largest compression along the flight (y in the bat runs, z on the cylinder)
    over its field frames [in]: the diameter minus the ball's extent."""
    series = read_fields(folder, deformed=True)
    ball = series["ball"] if "ball" in series else series["fields"]
    extents = []
    for mesh in ball.meshes:
        points = mesh.points
        spans = points.max(axis=0) - points.min(axis=0)
        extents.append(spans.min())  # the flattened direction is the shortest
    return diameter_in - min(extents) / 0.0254


def measures(folder: Path, summary: dict[str, Any], diameter_in: float) -> dict[str, float]:
    """The decomposition's numbers of one run (module docs)."""
    h = history(folder)
    t, f = h["time_ms"], h["contact_force_lbf"]
    touching = np.nonzero(f > 0.0)[0]
    start = t[touching[0]] if touching.size else 0.0
    peak_time = t[int(np.argmax(f))] - start
    bat_run = "ball_internal_energy_j" in h
    kinetic0 = h["kinetic_energy_j"][0]
    ball_int = h["ball_internal_energy_j" if bat_run else "internal_energy_j"]
    ball_hg = h["ball_hourglass_energy_j" if bat_run else "hourglass_energy_j"]
    bat_int = h["bat_internal_energy_j"] if bat_run else np.zeros_like(t)
    bulk = h["ball_bulk_viscosity_energy_j" if bat_run else "bulk_viscosity_energy_j"]
    compression = compression_in(folder, diameter_in)
    out = {
        "contact_time_ms": float(summary["contact_time_ms"]),
        "time_to_peak_ms": float(peak_time),
        "peak_force_lbf": float(summary["peak_force_lbf"]),
        "compression_in": compression,
        "strain_rate_per_s": compression / diameter_in / (peak_time * 1e-3),
        "ball_stored": float(ball_int.max() / kinetic0),
        "ball_kept": float(ball_int[-1] / kinetic0),
        "hourglass_peak": float(ball_hg.max() / kinetic0),
        "hourglass_kept": float(ball_hg[-1] / kinetic0),
        "bat_peak": float(bat_int.max() / kinetic0),
        "bat_kept": float(bat_int[-1] / kinetic0),
        "bulk_viscosity_kept": float(bulk[-1] / kinetic0),
    }
    if bat_run:
        out["bbcor"] = float(summary["bbcor"])
        out["bbs_mph"] = float(summary["bbs_mph"])
        out["restitution"] = float(summary["rebound_mph"] / summary["inbound_mph"])
    else:
        out["restitution"] = float(summary["ccor"])
    return out


def run_case(ball_name: str, numerics: dict[str, Any], mph: int, target: str, bat_name: str,
             sizes: tuple[int, int, str], runs_dir: Path) -> dict[str, float]:  # fmt: skip
    """One ball at one speed against one target; its :func:`measures`."""
    ball = load_ball_spec(ball_name)
    divisions, around, axial = sizes
    if target == "cylinder":
        test = LAB_TESTS["ccor"]
        setup = test.setup(speed=f"{mph} mph", divisions=divisions, **numerics)
        summary, folder = test.execute({"ball": ball}, setup, runs_dir=runs_dir, reuse=True)
    else:
        test = LAB_TESTS["bbs"]
        # a bat that gives nothing (held, rigid) holds a soft ball longer than the 2-ms default
        longer = {} if target == "flexible bat" else {"end_time": "4 ms"}
        # the BT shells this decomposition was run with (docs/fidelity.md, 2026-11-28)
        setup = test.setup(speed=f"{mph} mph", divisions=divisions, circumferential=around,
                           axial_size=axial, rigid_bat=target == "rigid bat", shell="bt",
                           **longer, **numerics)  # fmt: skip
        bat = load_bat_spec(bat_name)
        if target == "held bat":
            setup = dataclasses.replace(setup, fixed_bat=True)
            summary, folder = run_bbs_test(bat, ball, setup, runs_dir=runs_dir)
        else:
            summary, folder = test.execute({"bat": bat, "ball": ball}, setup, runs_dir=runs_dir,
                                           reuse=True)  # fmt: skip
    return measures(Path(folder), summary, ball.circumference / np.pi / 0.0254)


def main() -> None:
    """Run (or reuse) every case and print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs-dir", type=Path, default=Path("runs/decomposition"))
    parser.add_argument("--quick", action="store_true", help="6-division balls, 16 x 0.5 in")
    parser.add_argument("--json", type=Path, default=None, help="write every number here")
    args = parser.parse_args()
    sizes = (6, 16, "0.5 in") if args.quick else (12, 48, "0.1 in")
    results: dict[str, dict[str, float]] = {}
    for set_name, (balls, numerics) in BALL_SETS.items():
        for ball in balls:
            for mph in SPEEDS_MPH:
                cases = [(target, BAT) for target in TARGETS] + [("flexible bat", OTHER_BAT)]
                if set_name in PARTIAL_SETS:
                    cases = list(PARTIAL_SETS[set_name])
                for target, bat in cases:
                    key = f"{set_name}|{ball}|{mph}|{target}|{bat}"
                    print(f"running {key}", flush=True)
                    try:
                        results[key] = run_case(ball, numerics, mph, target, bat, sizes,
                                                args.runs_dir)  # fmt: skip
                    except SimulationError as exc:  # recorded, and the other cases go on
                        print(f"  failed: {exc}", flush=True)
                        results[key] = {"error": str(exc)}  # type: ignore[dict-item]
    if args.json is not None:
        args.json.write_text(json.dumps(results, indent=1), encoding="utf-8")
    print(table9(results))
    print()
    print(decomposition(results))


def table9(results: dict[str, dict[str, float]]) -> str:
    """Table 9 code to code: each ball set at both bats, against the experiment and LS-DYNA."""
    seed = load_seed_tables()
    lines = ["| ball set | ball @ speed | experiment | seed LS-DYNA | "
             f"`{OTHER_BAT}` bat | `{BAT}` bat |", "|---|---|---|---|---|---|"]  # fmt: skip
    for set_name, (balls, _) in BALL_SETS.items():
        if ("flexible bat", OTHER_BAT) not in PARTIAL_SETS.get(set_name, [("flexible bat",
                                                                          OTHER_BAT)]):
            continue
        for ball in balls:
            for mph in SPEEDS_MPH:
                seed_name = "type1" if "type1" in ball else "type2"
                row = seed.batted_ball_speed(seed_name, mph)
                exp, fe = row.bbs_exp / MPH, row.bbs_fe / MPH
                cells = []
                for bat in (OTHER_BAT, BAT):
                    run = results[f"{set_name}|{ball}|{mph}|flexible bat|{bat}"]
                    if "error" in run:
                        cells.append("failed")
                        continue
                    bbs = run["bbs_mph"]
                    cells.append(f"{bbs:.2f} ({100 * (bbs / exp - 1):+.1f} %)")
                lines.append(f"| {set_name} | {Path(ball).stem} @ {mph} mph | {exp:.1f} | "
                             f"{fe:.1f} | "
                             + " | ".join(cells) + " |")  # fmt: skip
    return "\n".join(lines)


def decomposition(results: dict[str, dict[str, float]]) -> str:
    """The decomposition, every ball and speed against the four targets (the model of record's
    bat), as two tables: the contact and the outcome, then the energies."""
    contact_head = ("| ball set | ball @ mph | target | contact ms | to peak ms | peak lbf | "
                    "compression in | strain rate 1/s | rebound ratio | BBCOR | BBS mph |")
    energy_head = ("| ball set | ball @ mph | target | ball stored / kept | hourglass peak / kept "
                   "| bat peak / kept | returned: ball / hourglass / bat | bulk viscosity |")
    tables = []
    for head in (contact_head, energy_head):
        lines = [head, "|" + "---|" * (head.count("|") - 1)]
        for key, m in results.items():
            set_name, ball, mph, target, bat = key.split("|")
            if bat != BAT:
                continue
            row = f"| {set_name} | {Path(ball).stem} @ {mph} | {target} | "
            if "error" in m:
                lines.append(row + f"failed: {m['error']} |")
            elif head is contact_head:
                pivoting = target in ("rigid bat", "flexible bat")  # BBCOR, BBS need the pivot
                lines.append(
                    row + f"{m['contact_time_ms']:.3f} | {m['time_to_peak_ms']:.3f} | "
                    f"{m['peak_force_lbf']:.0f} | {m['compression_in']:.3f} | "
                    f"{m['strain_rate_per_s']:.0f} | {m['restitution']:.3f} | "
                    + (f"{m['bbcor']:.3f} | {m['bbs_mph']:.2f} |" if pivoting else "- | - |")
                )
            else:
                returned = (m["ball_stored"] - m["ball_kept"],
                            m["hourglass_peak"] - m["hourglass_kept"],
                            m["bat_peak"] - m["bat_kept"])  # fmt: skip
                lines.append(
                    row + f"{m['ball_stored']:.3f} / {m['ball_kept']:.3f} | "
                    f"{m['hourglass_peak']:.3f} / {m['hourglass_kept']:.3f} | "
                    f"{m['bat_peak']:.3f} / {m['bat_kept']:.3f} | "
                    + " / ".join(f"{x:.3f}" for x in returned)
                    + f" | {m['bulk_viscosity_kept']:.3f} |"
                )
        tables.append("\n".join(lines))
    return "\n\n".join(tables)


if __name__ == "__main__":
    main()
