"""Why batball's barrel compression is linear (final / preload = 2.5) and the seed's experiment
is not (368 / 186 = 1.98): the candidates of docs/notes/barrel.md, each measured on one mesh.

Variants, each a full pre-stress + compression at 0 deg with the curve:
  base          the default bat (3.3-in platens, 0.001-in radial fit, frictionless insert)
  platen-3.86   the seed fixture's 3.86-in platens instead of its FE model's 3.3 in
  fit-0.0001    a ten times weaker fit (0.0001 in), the insert's gaps free to open
  fit-diametral the 0.001 in read as diametral (0.0005 in radial), gaps free to open
  penalty-1e4   contact penalties ten times stiffer (platens and fit)
  bonded        the insert glued to the barrel (tangential ties at the two contact surfaces, with
                the shell offsets): the stick limit of a frictional interface; and the interface
                shear it needs against the mu p a frictional fit could hold
and the reading of the experiment's zero (5-15 lbf of seating load) on each curve.

Run: ``NUMBA_NUM_THREADS=1 PYTHONPATH=src python benchmarks/barrel_diagnosis.py [around]
[axial_in] [variant ...]`` (default 16 around, 0.4 in, every variant: seconds each).
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from batball.contact.shell_contact import PenaltyGaps
from batball.lab.barrel import IN, compress_barrel, condensed_compression, insert_friction
from batball.models.barrel import (
    BarrelModel,
    BarrelTestOptions,
    build_barrel_model,
    compute_prestress,
    contact_areas,
    platen_gaps,
)
from batball.specs import load_bat_spec
from batball.specs.bat import BatSpec

LBF = 4.4482216152605
PSI = 6894.757293168


def tangential_ties(model: BarrelModel) -> sp.csr_matrix:
    """Rows tying the insert's outer surface to the barrel's bore along the hoop and the axis,
    pair r's hoop row at 2 r and axial row at 2 r + 1 (lab/barrel's friction slips, which carry
    the walls' rotations times the surfaces' offsets)."""
    axial, hoop = insert_friction(model, 0.0).slips
    n = axial.shape[0]
    order = np.arange(2 * n).reshape(2, n).T.ravel()
    return sp.csr_matrix(sp.vstack([hoop, axial]).tocsr()[order])


def bonded(model: BarrelModel) -> BarrelModel:
    """The model with the tangential ties added to K (bilateral, zero gap: a stiffness)."""
    ties = tangential_ties(model)
    k = np.repeat(model.interference.stiffness, 2)
    glue = PenaltyGaps(ties, np.zeros(ties.shape[0]), k, bilateral=True)
    return replace(model, stiffness=sp.csr_matrix(model.stiffness + glue.matrix.T
                                                  @ sp.diags(k) @ glue.matrix))  # fmt: skip


def bonded_interface_shear(base: BarrelModel, options: BarrelTestOptions) -> None:
    """How much interface shear the glued insert needs, against the friction a fit pressure p can
    hold (mu p, mu 0.2-0.3): where it needs more, a real (frictional) interface slips."""
    ties, glued = tangential_ties(base), bonded(base)
    prestress = compute_prestress(glued)
    condensed, (_, bottom, springs) = condensed_compression(glued, prestress, options, 0.0,
                                                            insert_may_open=True)  # fmt: skip
    areas, k = contact_areas(base), np.repeat(base.interference.stiffness, 2)
    for travel_in in (0.005, 0.02, 0.07):
        moved, _ = platen_gaps(glued, options, 0.0, travel_in * IN, prestress.u)
        solution = condensed.solve([glued.interference.initial, moved.initial, bottom.initial,
                                    springs.initial])  # fmt: skip
        shear = (k * (ties @ (solution.u - prestress.u))).reshape(-1, 2) / areas[:, None] / PSI
        shear_psi = np.hypot(shear[:, 0], shear[:, 1])
        pressure_psi = solution.forces[0] / areas / PSI
        print(f"{'':14s} bonded at {travel_in:.3f} in: shear added median "
              f"{np.median(shear_psi):.0f} psi, 90th percentile {np.percentile(shear_psi, 90):.0f}"
              f" psi; nodes needing more than 0.2 p / 0.3 p: "
              f"{np.mean(shear_psi > 0.2 * pressure_psi):.0%} / "
              f"{np.mean(shear_psi > 0.3 * pressure_psi):.0%}")


def with_fit(spec: BatSpec, interference_in: float) -> BatSpec:
    """The bat with another radial interference."""
    assert spec.insert is not None
    return replace(spec, insert=replace(spec.insert, interference=interference_in * IN))


def table2_reading(travel: np.ndarray, force: np.ndarray, seat_lbf: float) -> tuple[float, float]:
    """Table 2's pair read off a curve (travel in m, force in lbf) with the gauges zeroed at
    ``seat_lbf`` (0: first touch; the fixture's 5-15 lb seating load), lbf."""
    t, f = np.r_[0.0, travel], np.r_[0.0, force]
    start = float(np.interp(seat_lbf, f, t))
    at = [float(np.interp(start + d, t, f)) for d in (0.02 * IN, 0.07 * IN)]
    return at[0] - seat_lbf, at[1] - at[0]


def run_variant(name: str, model: BarrelModel, options: BarrelTestOptions,
                may_open: bool) -> None:  # fmt: skip
    """Pre-stress, compress at 0 deg to 0.08 in, print the curve and the Table 2 readings."""
    start = time.perf_counter()
    prestress = compute_prestress(model)
    curve = compress_barrel(model, prestress, options, 0.0, curve=True, insert_may_open=may_open)
    force = curve.force / LBF
    fit = prestress.contact_force.sum() / 2 / LBF
    print(f"{name:14s} fit per half {fit:5.0f} lbf, insert top half at 0.07 in "
          f"{np.interp(0.07 * IN, curve.travel, curve.insert_top) / LBF:5.0f} lbf, "
          f"{time.perf_counter() - start:.0f} s")
    print(f"{'':14s} curve (lbf, every 0.01 in) " + " ".join(f"{v:.1f}" for v in force[1::2]))
    for seat in (0.0, 5.0, 15.0):
        p, f = table2_reading(curve.travel, force, seat)
        print(f"{'':14s} zeroed at {seat:2g} lbf: preload {p:6.1f} final {f:6.1f} "
              f"ratio {f / p:.3f}")


def main() -> None:
    """Every variant on the mesh of the command line."""
    around = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    axial = (float(sys.argv[2]) if len(sys.argv) > 2 else 0.4) * IN
    spec = load_bat_spec("default")
    # Levels every 0.005 in to 0.08 in, so that a reading zeroed at 15 lbf stays on the curve.
    options = BarrelTestOptions(orientations_deg=(0.0,), final_travel=0.06 * IN, final_steps=12)
    mesh = {"circumferential": around, "axial_size": axial}
    base = build_barrel_model(spec, **mesh)
    only = sys.argv[3:]
    if not only or "base" in only:
        run_variant("base", base, options, False)
        run_variant("platen-3.86", base, replace(options, platen_diameter=3.86 * IN), False)
    if not only or "penalty-1e4" in only:
        stiff = build_barrel_model(spec, **mesh, penalty_factor=1e4)
        run_variant("penalty-1e4", stiff, replace(options, penalty_factor=1e4), False)
    for name, fit in (("fit-0.0001", 0.0001), ("fit-diametral", 0.0005)):
        if not only or name in only:
            run_variant(name, build_barrel_model(with_fit(spec, fit), **mesh), options, True)
    if not only or "bonded" in only:
        run_variant("bonded", bonded(base), options, True)
        bonded_interface_shear(base, options)


if __name__ == "__main__":
    main()
