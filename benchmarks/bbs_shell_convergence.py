"""The bat's shell element under mesh refinement: BT against MITC4 in the batted-ball-speed test.

Usage: python benchmarks/bbs_shell_convergence.py [--runs-dir runs/shell-convergence]
       [--json out.json] [--balls type1-fit type2-fit] [--speed "110 mph"] [--workers 2]
       [--finest] [--quick]

The one-point Belytschko-Tsay shells (the seed's, and batball's default for the BBS test until
this study chose MITC4) and the fully integrated co-rotational MITC4 shells give different BBS
on the same mesh (1.0-1.6 mph on the table mesh, docs/notes/bbs.md). Either difference is
discretisation, and both elements converge to one BBS as the bat's mesh is refined, or it is
not. This runs each ball at one speed on the joint bat (``benchmarks/bats/joint_bat.toml``, the
ensemble's) with both elements on three bat meshes, circumferential x axial element size:

    32 x 0.2 in, 48 x 0.1 in (the test's full size), 64 x 0.075 in,

and with ``--finest`` a fourth, 96 x 0.05 in (about eight times a full-size run's work: four
times the shells at half the barrel's step); the ball at the test's full size throughout
(12 divisions). The test's selective mass scaling stays on (its summary's
``added_mass_percent``, reported per run, changes with the mesh). Each run is stored under
``--runs-dir`` and replayed on a second call. For each element the three finest meshes give a
Richardson extrapolation BBS(h) = BBS_0 + C h^p (h the axial size; p from the three values when
the differences shrink monotonically, else none is reported), and the output says how far each
element's full-size BBS is from its extrapolated value and from the other element's.

``--quick`` runs coarse meshes (16 x 0.5, 24 x 0.35, 32 x 0.25, 48 x 0.175 in, a 6-division
ball) to check the script in a minute or two.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
BAT = HERE / "bats" / "joint_bat.toml"
MESHES = ((32, "0.2 in"), (48, "0.1 in"), (64, "0.075 in"))
FINEST = (96, "0.05 in")
QUICK_MESHES = ((16, "0.5 in"), (24, "0.35 in"), (32, "0.25 in"), (48, "0.175 in"))
SHELLS = ("bt", "mitc4")


def run_one(job: dict[str, Any]) -> dict[str, Any]:
    """One BBS run; its BBS [mph], BBCOR, energy balance and wall time."""
    from batball.lab.registry import LAB_TESTS
    from batball.specs import load_ball_spec, load_bat_spec

    test = LAB_TESTS["bbs"]
    setup = test.setup(speed=job["speed"], circumferential=str(job["circumferential"]),
                       axial_size=job["axial_size"], shell=job["shell"],
                       **({"divisions": "6"} if job["quick"] else {}))  # fmt: skip
    clock = time.perf_counter()
    summary, _ = test.execute({"bat": load_bat_spec(str(BAT)), "ball": load_ball_spec(job["ball"])},
                              setup, runs_dir=Path(job["runs_dir"]), reuse=True)  # fmt: skip
    return {**job, "bbs_mph": float(summary["bbs_mph"]), "bbcor": float(summary["bbcor"]),
            "energy_balance_error": summary.get("energy_balance_error"),
            "added_mass_percent": summary.get("added_mass_percent"),
            "n_shells": summary.get("n_shells"), "n_steps": summary.get("n_steps"),
            "wall_s": time.perf_counter() - clock,
            "run_wall_s": summary.get("wall_seconds")}  # fmt: skip


def richardson(h: list[float], f: list[float]) -> dict[str, float] | None:
    """BBS_0, C and p of f = BBS_0 + C h^p through three points with h in a constant or varying
    ratio (p solved by bisection); None unless the differences have one sign and shrink."""
    (h1, h2, h3), (f1, f2, f3) = h, f  # coarse to fine
    d12, d23 = f1 - f2, f2 - f3
    if d12 == 0 or d23 == 0 or (d12 > 0) != (d23 > 0) or abs(d23) >= abs(d12):
        return None

    def residual(p: float) -> float:
        return (h1**p - h2**p) / (h2**p - h3**p) - d12 / d23

    lo, hi = 0.05, 8.0
    if residual(lo) * residual(hi) > 0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if residual(lo) * residual(mid) <= 0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    c = d23 / (h2**p - h3**p)
    return {"bbs0_mph": f3 - c * h3**p, "c": c, "p": p}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs-dir", type=Path, default=Path("runs/shell-convergence"))
    parser.add_argument("--json", type=Path)
    parser.add_argument("--balls", nargs="+", default=["type1-fit"])
    parser.add_argument("--speed", default="110 mph")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--finest", action="store_true", help="add 96 x 0.05 in")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    meshes = QUICK_MESHES if args.quick else MESHES + ((FINEST,) if args.finest else ())
    jobs = [{"ball": ball, "speed": args.speed, "shell": shell, "circumferential": n,
             "axial_size": size, "runs_dir": str(args.runs_dir), "quick": args.quick}
            for n, size in meshes for ball in args.balls for shell in SHELLS]  # fmt: skip
    clock = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        results = []
        for r in pool.map(run_one, jobs):
            print(f"{r['ball']} {r['shell']:5s} {r['circumferential']:3d} x {r['axial_size']:9s}"
                  f" BBS {r['bbs_mph']:.3f} mph  BBCOR {r['bbcor']:.4f}  added mass "
                  f"{r['added_mass_percent']} %  ({r['wall_s']:.0f} s)",
                  flush=True)  # fmt: skip
            results.append(r)
    out: dict[str, Any] = {"bat": str(BAT.relative_to(HERE.parent)), "speed": args.speed,
                           "runs": results, "extrapolated": {},
                           "wall_seconds": time.perf_counter() - clock}  # fmt: skip
    for ball in args.balls:
        for shell in SHELLS:
            rows = [r for r in results if r["ball"] == ball and r["shell"] == shell]
            h = [float(r["axial_size"].split()[0]) for r in rows]
            f = [r["bbs_mph"] for r in rows]
            fit = richardson(h[-3:], f[-3:])
            out["extrapolated"][f"{ball} {shell}"] = fit
            text = (f"BBS_0 {fit['bbs0_mph']:.2f} mph, p {fit['p']:.2f}" if fit
                    else "no monotone convergence in the three finest meshes")  # fmt: skip
            print(f"{ball} {shell}: {text}")
    if args.json:
        args.json.write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    if not all(math.isfinite(r["bbs_mph"]) for r in results):
        raise SystemExit("a run gave a non-finite BBS")


if __name__ == "__main__":
    main()
