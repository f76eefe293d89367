"""Run a barrel compression deck (:func:`batball.lsdyna.bat.barrel_deck`) in batball.

batball's barrel test (:mod:`batball.lab.barrel`) builds its contacts from a bat spec (the bore
radius, the interference, the walls at each station), so the deck's bat is turned back into one
(:func:`spec_from_deck`): the profile from the outer rings (mid-surface radius plus half the
mean wall, the inverse of :func:`batball.mesh.bat.outer_ring_radii`), one part per composite
part (its layers as single-angle plies, its lumped mass = MAREA x area), the insert's span and
interference from its mesh (its outer surface minus the barrel's bore). The spec is checked by
rebuilding the mesh from it: it must be the deck's, node for node. The protocol comes from the
deck: platen diameter and position (the fitted rigid half-cylinders), preload and total travel
(the travel curve's points), the orientation (the top platen's DOF); the supports must be the
ones batball's protocol places, else a SpecError. batball's own contact penalty is used (the
deck has no field for it; as the ball decks' penalty, it is batball's rule).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from batball.contact.rigid import RigidCylinder
from batball.errors import SpecError
from batball.lsdyna.bat_model import BatDeck, contact_side, rigid_shells, supports
from batball.lsdyna.cards import unit_system
from batball.mesh.bat import make_bat_mesh
from batball.mesh.shell import quad_areas
from batball.models.barrel import BarrelTestOptions, compression_supports
from batball.specs.bat import BatSpec, InsertSpec, PartSpec, PlySpec


def plies_of(bat: BatDeck, name: str) -> tuple[PlySpec, ...]:
    """A part's layers as single-angle spec plies (material = the lamina's name)."""
    return tuple(PlySpec(ply.material.name, ply.thickness, ply.angle)
                 for ply in bat.laminates[name].plies)  # fmt: skip


def outer_parts(bat: BatDeck, rings_x: np.ndarray, n: int) -> list[PartSpec]:
    """The outer wall's parts sorted along the bat: span from their cells' rings, lumped mass =
    non-structural mass per area x mesh area."""
    areas = quad_areas(bat.mesh.points, bat.mesh.cells)
    parts = []
    for name, cells in bat.mesh.cell_sets.items():
        if name == "insert":
            continue
        bands = cells // n
        lumped = float(bat.extra_areal_mass[cells][0] * areas[cells].sum())
        parts.append(PartSpec(name, float(rings_x[bands.min()]), float(rings_x[bands.max() + 1]),
                              plies_of(bat, name), lumped))  # fmt: skip
    return sorted(parts, key=lambda p: p.start)


def spec_from_deck(bat: BatDeck, *, name: str = "deck") -> BatSpec:
    """The bat spec whose mesh is the deck's (module docs); SpecError if none rebuilds it."""
    n = bat.circumferential
    outer = bat.mesh.points[bat.mesh.point_sets["outer"]].reshape(-1, n, 3)
    x, r_mid = outer[:, 0, 0], np.hypot(outer[:, 0, 1], outer[:, 0, 2])
    parts = outer_parts(bat, x, n)
    starts = np.array([p.start for p in parts])
    walls = np.array([bat.laminates[p.name].thickness for p in parts])
    after = np.clip(np.searchsorted(starts, x, side="right") - 1, 0, len(parts) - 1)
    before = np.clip(np.searchsorted(starts, x, side="left") - 1, 0, len(parts) - 1)
    diameter = 2.0 * (r_mid + 0.25 * (walls[after] + walls[before]))
    materials = {ply.material.name: ply.material for lam in bat.laminates.values()
                 for ply in lam.plies}  # fmt: skip
    draft = BatSpec(name, float(x[-1]), tuple(zip(x, diameter, strict=True)), tuple(parts),
                    None, materials)  # fmt: skip
    spec = BatSpec(name, draft.length, draft.stations, draft.parts, insert_of(bat, draft),
                   materials)  # fmt: skip
    check_rebuilds(bat, spec)
    return spec


def insert_of(bat: BatDeck, draft: BatSpec) -> InsertSpec | None:
    """The insert's span, plies and interference (its outer surface minus the bore)."""
    if "insert" not in bat.mesh.point_sets:
        return None
    points = bat.mesh.points[bat.mesh.point_sets["insert"]]
    start, end = float(points[:, 0].min()), float(points[:, 0].max())
    wall = bat.laminates["insert"].thickness
    outer = float(np.hypot(points[0, 1], points[0, 2])) + 0.5 * wall
    probe = InsertSpec(start, end, plies_of(bat, "insert"), 0.0)
    bore = BatSpec(draft.name, draft.length, draft.stations, draft.parts, probe,
                   draft.materials).insert_outer_radius()  # fmt: skip
    return InsertSpec(start, end, probe.layup, outer - bore)


def mesh_sizes(bat: BatDeck) -> dict[str, Any]:
    """circumferential and an axial size that rebuilds the deck's rings (the insert's spacing)."""
    points = bat.mesh.points
    if "insert" in bat.mesh.point_sets:
        x = np.unique(points[bat.mesh.point_sets["insert"], 0])
    else:
        x = np.unique(points[bat.mesh.point_sets["outer"], 0])
    return {"circumferential": bat.circumferential, "axial_size": float(np.diff(x).max())}


def check_rebuilds(bat: BatDeck, spec: BatSpec) -> None:
    """The spec's mesh must be the deck's, node for node (1e-9 of the bat's length)."""
    mesh = make_bat_mesh(spec, **mesh_sizes(bat))
    same = mesh.points.shape == bat.mesh.points.shape and np.array_equal(mesh.cells, bat.mesh.cells)
    if not same or np.abs(mesh.points - bat.mesh.points).max() > 1e-9 * spec.length:
        raise SpecError(
            "bat shells",
            "a mesh batball's bat mesher does not rebuild",
            "the rings of a bat spec's mesh (as batball export writes them)",
        )


def options_from_deck(bat: BatDeck, spec: BatSpec) -> tuple[BarrelTestOptions, float]:
    """The protocol (platens, travels) and the orientation [deg] a barrel deck describes."""
    u = unit_system(bat.units)
    platens = rigid_shells(bat, u)
    motion = bat.deck.motions.get(2)
    if sorted(platens) != [2, 3] or motion is None or motion.get("vad") != 2:
        raise SpecError("barrel deck", sorted(platens),
                        "rigid platens 2 (moved by displacement, VAD 2) and 3")  # fmt: skip
    check_platen_contacts(bat)
    top = platens[2]
    if not isinstance(top, RigidCylinder):
        raise SpecError("rigid part 2", "flat", "a half-cylinder platen")
    orientation = {2: 0.0, 3: 90.0}.get(int(motion.get("dof") or 0))
    if orientation is None:
        raise SpecError(f"*BOUNDARY_PRESCRIBED_MOTION_RIGID at {motion['where']} DOF",
                        motion.get("dof"), "2 (y: 0 deg) or 3 (z: 90 deg)")  # fmt: skip
    curve = bat.deck.curves[int(motion["lcid"])] * u.length
    if curve.shape[0] != 3 or curve[0, 1] != 0.0:
        raise SpecError("travel curve", curve.shape[0], "(0, 0), (t, preload), (1, total)")
    options = BarrelTestOptions(
        platen_diameter=2.0 * top.radius, distance_from_cap=spec.length - top.axis_point[0],
        preload_travel=float(curve[1, 1]), final_travel=float(curve[2, 1] - curve[1, 1]),
        orientations_deg=(orientation,),
    )  # fmt: skip
    return options, orientation


def check_platen_contacts(bat: BatDeck) -> None:
    """One frictionless *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE of all outer parts on each
    platen (batball's platen contact), besides the insert's interference contact."""
    outer = sorted(pid for pid, p in bat.deck.composites.items() if p["title"] != "insert")
    pairs = sorted(
        (sorted(contact_side(bat.deck, c, "a")), sorted(contact_side(bat.deck, c, "b")))
        for c in bat.deck.contacts if c["kind"] == "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"
    )  # fmt: skip
    if pairs != [(outer, [2]), (outer, [3])]:
        raise SpecError(
            "barrel deck contacts",
            pairs,
            "the outer parts (SURFA) on platen 2 and on platen 3 (SURFB)",
        )


def check_supports(bat: BatDeck, model: Any, options: BarrelTestOptions, angle: float) -> None:
    """The deck's *BOUNDARY_SPC_SETs must be the supports batball's protocol places."""
    dofs, _ = compression_supports(model, options, angle)
    rings = np.sort(dofs // 6)
    held = supports(bat)
    sideways = (0, 0, 1, 0, 0, 0) if angle == 0.0 else (0, 1, 0, 0, 0, 0)
    ok = len(held) == 2 and held[0][1] == (1, 0, 0, 0, 0, 0) and held[1][1] == sideways
    ok = ok and np.array_equal(np.sort(held[0][0]), rings)
    ok = ok and bool(np.isin(held[1][0], rings).all()) and held[1][0].size == 4
    if not ok:
        raise SpecError("*BOUNDARY_SPC_SET", [(n.size, d) for n, d in held],
                        "batball's supports: the rings under the platen centre held axially, "
                        "their four load-axis nodes sideways")  # fmt: skip
