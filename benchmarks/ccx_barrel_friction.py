"""Barrel compression in CalculiX with a Coulomb-friction contact between insert and barrel.

Tests docs/notes/barrel.md's leading hypothesis for Table 2's stiff start (issue 8): friction at the
insert-barrel interface sticks at first and slips later, raising the preload (0.02 in) more than
the final load (0.07 in). The model is ``ccx_barrel_nlgeom.py``'s (one eighth, C3D8I per ply,
rigid 3.3-in platen with node-to-surface penalty contact; its functions are imported), except at
the interface: instead of the radial *EQUATION tie, a surface-to-surface *CONTACT PAIR (slave:
the insert's outer faces, master: the barrel's inner faces) with a linear pressure-overclosure
penalty and, for mu > 0, *FRICTION (mu, stick slope = penalty / 100, the CalculiX manual's advice).

Step 1, the fit: the insert is built 0.001 in larger in radius (the 0.001-in radial
interference) and the geometric overclosure is resolved by the contact, the platen held clear of
the barrel (it starts CLEARANCE above the barrel's unloaded top). Step 2, the test: the platen
moves down; the travel is counted from first touch (the barrel's top after the fit, as batball
zeroes at first touch), and the force at 0.01-in steps of that travel is interpolated from the
increments (automatic, at most 0.002 in of travel each).

Run: ``python benchmarks/ccx_barrel_friction.py [folder] [mu ...] [--penalty K] [--nlgeom]``
(needs ``ccx``; default mu 0 0.1 0.2 0.3, K 1e8 psi/in). Prints, per run, the fit pressure, the
force curve, Table 2's pair (F(0.02), F(0.07) - F(0.02)), and the share of the interface's
contact points that slip (|tau| >= 0.99 mu p) at some travels.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ccx_barrel_nlgeom import (  # noqa: E402
    N_AROUND,
    axial_stations,
    hexes,
    id_lines,
    platen_surface_cards,
    positive,
    tube_and_platen_cards,
)

INTERFERENCE = 0.001  # in, radial
CLEARANCE = 0.001  # in, the platen's start above the unloaded barrel (the fit swells it less)
HALF_TRAVEL_STEP = 0.001  # in, each platen per increment (0.002 in of travel)
TRAVEL = 0.07  # in, from first touch


def deck(mu: float, penalty: float, nlgeom: bool) -> str:
    """The whole .inp: step 1 the fit, step 2 the platen travel."""
    cards = tube_and_platen_cards(INTERFERENCE, CLEARANCE)
    lines, insert_ids, barrel_ids, coords, ref, rot = cards
    lines += interface_cards(insert_ids, barrel_ids, coords, mu, penalty)
    lines += symmetry_cards(insert_ids, barrel_ids)
    outer = barrel_ids[:, :, -1]
    near = outer[: np.searchsorted(axial_stations(), 1.3), : N_AROUND // 2 + 1]
    top = int(outer[0, 0])  # x = 0, theta = 0: under the platen's line
    lines += id_lines("*NSET, NSET=SLAVE", near)
    lines += ["*SURFACE, NAME=SSLAVE, TYPE=NODE", "SLAVE",
              "*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
              "1.0e9, 1.0", "*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE",
              "SSLAVE, SPLATEN", "*NSET, NSET=NREF", f"{ref}", "*NSET, NSET=NTOP", f"{top}"]
    n_inc = int(round((CLEARANCE + 0.5 * TRAVEL + 0.002) / HALF_TRAVEL_STEP))
    step = "*STEP" + (", NLGEOM" if nlgeom else "") + ", INC=500"
    # Contact points flipping at near-zero pressure (the fit is self-equilibrated, so the mean
    # nodal force that scales the residual test is small before the platen bites) need more
    # iterations before a cut-back and a residual test of 2 % rather than 0.5 % of that mean.
    controls = ["*CONTROLS, PARAMETERS=TIME INCREMENTATION", "20, 30, 9, 200, 10, 4, , 5",
                "*CONTROLS, PARAMETERS=FIELD, FIELD=DISPLACEMENT", "0.02, 0.05"]
    lines += [step, "*STATIC", "0.25, 1.0, 1e-4, 0.25", *controls,
              "*BOUNDARY", f"{ref}, 1, 1, 0.0", f"{ref}, 3, 3, 0.0", f"{rot}, 1, 3, 0.0",
              f"{ref}, 2, 2, 0.0",
              "*NODE PRINT, NSET=NTOP", "U", "*NODE PRINT, NSET=NREF", "RF",
              "*CONTACT PRINT", "CSTR", "*END STEP",
              step, "*STATIC", f"{1.0 / n_inc:.12f}, 1.0, 1e-5, {1.0 / n_inc:.12f}", *controls,
              "*BOUNDARY", f"{ref}, 2, 2, {-n_inc * HALF_TRAVEL_STEP:.10f}",
              "*NODE PRINT, NSET=NREF", "U, RF", "*CONTACT PRINT", "CSTR",
              "*END STEP"]  # fmt: skip
    return "\n".join(lines) + "\n"


def interface_cards(insert_ids: np.ndarray, barrel_ids: np.ndarray,
                    coords: dict[int, np.ndarray], mu: float,
                    penalty: float) -> list[str]:  # fmt: skip
    """Surface-to-surface contact of the insert's outer (slave) on the barrel's inner faces."""
    n_cells = len(hexes(insert_ids[:, :, 0:2]))
    lines = []
    for name, ids, ply, layer in (("SINSERT", insert_ids, 2, -1), ("SBARREL", barrel_ids, 0, 0)):
        cells = positive(hexes(ids[:, :, ply:ply + 2]), coords)
        first = 1 + n_cells * (ply + (3 if name == "SBARREL" else 0))
        faces = platen_surface_cards(cells, first, set(ids[:, :, layer].ravel().tolist()))
        lines += [f"*SURFACE, NAME={name}, TYPE=ELEMENT"] + faces[1:]
    lines += ["*SURFACE INTERACTION, NAME=FIT", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
              f"{penalty:.6e}"]  # fmt: skip
    if mu > 0.0:  # CalculiX wants mu > 0; no *FRICTION is frictionless
        lines += ["*FRICTION", f"{mu:.6f}, {penalty / 100.0:.6e}"]
    lines += ["*CONTACT PAIR, INTERACTION=FIT, TYPE=SURFACE TO SURFACE", "SINSERT, SBARREL"]
    return lines


def symmetry_cards(insert_ids: np.ndarray, barrel_ids: np.ndarray) -> list[str]:
    """Symmetry planes x = 0, z = 0 (theta = 0) and y = 0 (theta = 90 deg), global dofs."""
    lines = ["*BOUNDARY"]
    for ids in (insert_ids, barrel_ids):
        lines += [f"{n}, 1, 1, 0.0" for n in ids[0].ravel()]
        lines += [f"{n}, 3, 3, 0.0" for n in ids[:, 0].ravel()]
        lines += [f"{n}, 2, 2, 0.0" for n in ids[:, -1].ravel()]
    return lines


def blocks(dat: str, header: str) -> list[np.ndarray]:
    """Each .dat block whose title starts with ``header``: rows of numbers."""
    out = []
    parts = re.split(r"\n\s*\n", dat)
    for k, part in enumerate(parts):
        if part.strip().startswith(header) and k + 1 < len(parts):
            rows = [line.split() for line in parts[k + 1].strip().splitlines()]
            out.append(np.array([[float(v) for v in row] for row in rows if row]))
    return out


def analyse(dat: str, mu: float) -> dict:
    """Fit pressure, force-travel curve from first touch, Table 2 pair, slip shares."""
    tops = blocks(dat, "displacements (vx,vy,vz) for set NTOP")
    n_fit = len(tops)  # step 1's increments (its blocks come first)
    top = tops[-1][0, 2]
    ref_u = np.array([b[0, 2] for b in blocks(dat, "displacements (vx,vy,vz) for set NREF")])
    ref_f = np.array([4.0 * abs(b[0, 2]) for b in blocks(dat, "forces (fx,fy,fz) for set NREF")])
    ref_f = ref_f[n_fit:]
    cstr = blocks(dat, "contact stress (slave node,press,tang1,tang2)")
    cstr = cstr[n_fit - 1:]  # the end of the fit, then step 2's increments
    travel = 2.0 * (-ref_u - (CLEARANCE - top))
    grid = np.arange(0.01, TRAVEL + 1e-9, 0.01)
    force = np.interp(grid, travel, ref_f)
    fit = cstr[0]
    pressure = fit[:, 1]
    result = {"swell": top, "fit_mean_psi": float(pressure.mean()), "grid": grid,
              "fit_range_psi": (float(pressure.min()), float(pressure.max())),
              "fit_closed": float(np.mean(pressure > 0.0)), "force": force}  # fmt: skip
    result["preload"] = float(np.interp(0.02, travel, ref_f))
    result["final"] = float(np.interp(0.07, travel, ref_f)) - result["preload"]
    slip = []
    for t_want in (0.002, 0.005, 0.01, 0.02, 0.04, 0.07):
        k = int(np.argmin(np.abs(travel - t_want)))
        c = cstr[k + 1]  # cstr[0] is the fit
        p, tau = c[:, 1], np.hypot(c[:, 2], c[:, 3])
        closed = p > 0.0
        share = float(np.mean(tau[closed] >= 0.99 * mu * p[closed])) if mu > 0 else 1.0
        slip.append((float(travel[k]), share, float(np.mean(closed))))
    result["slip"] = slip
    return result


def run(folder: Path, mu: float, penalty: float, nlgeom: bool) -> tuple[dict, float]:
    """Write, run and read one deck; (results, wall seconds)."""
    name = f"fric_mu{mu:g}_k{penalty:.0e}" + ("_nlgeom" if nlgeom else "")
    (folder / f"{name}.inp").write_text(deck(mu, penalty, nlgeom))
    ccx = shutil.which("ccx")
    if ccx is None:
        raise SystemExit("ccx is not on PATH")
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    start = time.perf_counter()
    proc = subprocess.run([ccx, "-i", name], cwd=folder, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    (folder / f"{name}.log").write_text(proc.stdout + proc.stderr)
    if proc.returncode != 0 or "*ERROR" in proc.stdout:
        raise SystemExit(f"ccx failed on {name} (see {folder / name}.log)")
    return analyse((folder / f"{name}.dat").read_text(), mu), wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", nargs="?", default="ccx_barrel_friction")
    parser.add_argument("mu", nargs="*", type=float, default=[0.0, 0.1, 0.2, 0.3])
    parser.add_argument("--penalty", type=float, default=1.0e8, help="psi/in")
    parser.add_argument("--nlgeom", action="store_true")
    args = parser.parse_args()
    folder = Path(args.folder)
    folder.mkdir(parents=True, exist_ok=True)
    for mu in args.mu:
        r, wall = run(folder, mu, args.penalty, args.nlgeom)
        print(f"mu {mu:g}, penalty {args.penalty:.0e} psi/in"
              + (", NLGEOM" if args.nlgeom else ", linear") + f": ccx {wall:.0f} s wall")
        print(f"  fit: mean pressure {r['fit_mean_psi']:.1f} psi (contact points "
              f"{r['fit_range_psi'][0]:.1f} to {r['fit_range_psi'][1]:.1f}, "
              f"{100 * r['fit_closed']:.0f} % closed); barrel top swell {r['swell']:.6f} in")
        print("  force (lbf) at " + ", ".join(f"{t:.2f}: {f:.1f}"
                                              for t, f in zip(r["grid"], r["force"], strict=True)))
        print(f"  preload {r['preload']:.1f} lbf, final {r['final']:.1f} lbf, "
              f"ratio {r['final'] / r['preload']:.3f}")
        print("  slipping share of closed interface points (travel: slip, closed): " + ", ".join(
            f"{t:.3f}: {100 * s:.0f} %, {100 * c:.0f} %" for t, s, c in r["slip"]))  # fmt: skip
        sys.stdout.flush()


if __name__ == "__main__":
    main()
