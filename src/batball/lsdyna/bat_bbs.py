"""Run a batted-ball-speed deck (:func:`batball.lsdyna.bat.bbs_deck`) in batball.

batball's bbs test (:mod:`batball.lab.bbs`) builds its model from a bat spec, a ball spec and a
:class:`~batball.models.bbs.BbsSetup`, so the deck is turned back into those three and the model
is built by :func:`~batball.models.bbs.build_bbs_model`, the same path as ``batball bbs``:

* the bat: :func:`~batball.lsdyna.bat_barrel.spec_from_deck` (checked to rebuild the deck's
  shells node for node);
* the ball: its *MAT card (a registered law, each parameter from its LS-DYNA field), its size
  from the hexes (centre = mean node, radius = farthest node), its mass = RO x the hexes'
  volume, its mesh divisions from the hex count (7 d^3);
* the setup: speed from *INITIAL_VELOCITY_GENERATION (the whole ball along -y), impact point
  and gap from the ball's centre, TSSFAC, ENDTIM, hourglass and bulk viscosity from the
  controls (as the impact decks), the contact's SOFT, SOFSCL, SFSA and SLSFAC, the insert's
  fit from the interference contact (its pre-stress by batball's own dynamic relaxation);
* the pivot: the deck's *CONSTRAINED_NODAL_RIGID_BODY_SPC, which LS-DYNA turns about the
  band's centre of mass; that point (it must lie on the bat's axis) is the pivot, and the band
  is the deck's node set.

The model built is then checked against the deck: the ball's nodes and hexes must be the
deck's (1e-9 of the bat's length). Anything batball cannot honour is a SpecError naming the
keyword, the field and the line. The BBS constants (pitch and swing speed) are not deck
content: ``pitch_speed`` and ``swing_speed`` (ASA 25 and 85 mph by default).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from batball.elements.shell_stiffness import SHEAR_FACTOR
from batball.errors import SpecError
from batball.lsdyna.bat_barrel import mesh_sizes, spec_from_deck
from batball.lsdyna.bat_model import (
    BatDeck,
    ball_of,
    contact_side,
    insert_part,
    pivot_band,
)
from batball.lsdyna.cards import UnitSystem, unit_system
from batball.lsdyna.model import _controls, _hourglass, _part_ids
from batball.materials import MATERIAL_LAWS
from batball.mesh import Mesh, hex_volumes
from batball.models.ball import ContactOptions
from batball.models.bbs import BbsModel, BbsSetup, build_bbs_model
from batball.specs import BallSpec
from batball.specs.ball import MaterialSpec
from batball.specs.bat import BatSpec
from batball.units import IN

#: batball's dynamic relaxation factor (LS-DYNA DRFCTR's default), the only one it runs.
DRFCTR = 0.995
#: How far a rebuilt node may lie from the deck's, over the bat's length (as the bat reader).
REBUILD_TOLERANCE = 1e-9
INTERFERENCE = "CONTACT_SURFACE_TO_SURFACE_INTERFERENCE"
BALL_CONTACT = "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"


@dataclasses.dataclass(frozen=True)
class BbsDeck:
    """A bbs deck turned back into batball's inputs and model (SI).

    Attributes:
        bat, ball, setup: the specs and setup ``batball bbs`` would run.
        model: built by :func:`~batball.models.bbs.build_bbs_model`, its pivot band the deck's.
        band_offset: the band's centre of mass (the pivot) minus the mid-point of the band's
            rings along the bat [m]: what LS-DYNA's rotation centre adds over a symmetric band.
    """

    bat: BatSpec
    ball: BallSpec
    setup: BbsSetup
    model: BbsModel
    band_offset: float


def read_bbs_deck(
    bat: BatDeck,
    *,
    separation_time: float = BbsSetup.separation_time,
    pitch_speed: float = BbsSetup.pitch_speed,
    swing_speed: float = BbsSetup.swing_speed,
    precision: str = BbsSetup.precision,
) -> BbsDeck:
    """Turn a bbs :class:`BatDeck` into the bbs test's specs, setup and model (module docs);
    ``precision`` is the ball kernel's (a run option, not in the deck: LS-DYNA's precision is
    the executable's)."""
    u = unit_system(bat.units)
    ball_pid = check_bbs_keywords(bat)
    spec = spec_from_deck(bat)
    ball_mesh, ball, velocity = ball_from_deck(bat, ball_pid, u)
    centre = ball_mesh.points.mean(axis=0)
    band = pivot_band(bat)
    band_x = bat.mesh.points[band, 0]
    middle = 0.5 * float(band_x.min() + band_x.max())
    controls = _controls(bat.deck, [ball_pid], u, separation_time)
    step = bat.deck.controls.get("CONTROL_TIMESTEP", {})
    dt2ms = step.get("dt2ms") or 0.0
    if dt2ms > 0.0:
        raise SpecError(f"*CONTROL_TIMESTEP.DT2MS at {step['where']}", dt2ms,
                        "blank, 0 or negative (mass added only to the shells whose step is "
                        "below TSSFAC |DT2MS|)")  # fmt: skip
    mass_scaling = -dt2ms * u.time * controls.time_step_scale if dt2ms < 0.0 else None
    setup = BbsSetup(
        speed=ball_speed(bat, ball_pid, velocity), pitch_speed=pitch_speed,
        swing_speed=swing_speed, impact_from_cap=spec.length - float(centre[0]),
        pivot_from_knob=middle, pivot_band=min(0.5 * float(np.ptp(band_x)) + 1e-9, 3.0 * IN),
        ball_divisions=ball_divisions(ball_mesh), gap=ball_gap(spec, ball, centre),
        end_time=controls.end_time, separation_time=separation_time,
        time_step_scale=controls.time_step_scale, hourglass=_hourglass(bat.deck, [ball_pid]),
        bulk_viscosity=controls.bulk_viscosity, contact=ball_contact_options(bat, ball_pid),
        rigid_bat=band.size == bat.mesh.n_points, precision=precision, mass_scaling=mass_scaling,
        insert_friction=0.0,  # the deck's insert contact is frictionless
        **mesh_sizes(bat),
    )  # fmt: skip
    where = bat.deck.nodal_rigid_bodies[0]["where"]
    model = with_pivot(build_bbs_model(spec, ball, setup), band, where)
    check_ball_rebuilds(model, ball_mesh, spec)
    setup = dataclasses.replace(setup, pivot_from_knob=model.pivot_x)
    return BbsDeck(spec, ball, setup, model, model.pivot_x - middle)


def check_bbs_keywords(bat: BatDeck) -> int:
    """What a bbs deck may hold besides the bat and the pivot (module docs); its ball part id."""
    deck = bat.deck
    balls = sorted({pid for _, pid, _, _ in deck.solids})
    others = sorted(set(deck.parts) - set(balls))
    if len(balls) != 1 or others:
        raise SpecError(f"*PART at {deck.parts[others[0]]['where']}" if others else "*PART",
                        others or balls, "one part of hexes (the ball) and no rigid parts: "
                        "the bat is the *PART_COMPOSITE shells")  # fmt: skip
    present = [name for name, there in (
        ("*BOUNDARY_SPC_SET", deck.spcs), ("*BOUNDARY_PRESCRIBED_MOTION_RIGID", deck.motions),
        ("*DAMPING_GLOBAL", "DAMPING_GLOBAL" in deck.controls),
        ("*CONTROL_IMPLICIT_GENERAL", "CONTROL_IMPLICIT_GENERAL" in deck.controls),
    ) if there]  # fmt: skip
    if present:
        raise SpecError("bbs deck", present, "none: the bat is free but for the pivot band")
    if bat.elform != 2 or not math.isclose(bat.shear_factor, SHEAR_FACTOR, rel_tol=1e-5):
        raise SpecError("*PART_COMPOSITE ELFORM/SHRF", (bat.elform, bat.shear_factor),
                        f"ELFORM 2 (Belytschko-Tsay) and SHRF {SHEAR_FACTOR:.6g} (batball's "
                        "explicit shells)")  # fmt: skip
    term = deck.controls.get("CONTROL_TERMINATION", {})
    if term.get("dtmin") not in (None, 0.0):
        raise SpecError(f"*CONTROL_TERMINATION.DTMIN at {term['where']}", term["dtmin"],
                        "blank or 0 (batball's coupled run has no step floor)")  # fmt: skip
    check_contacts(bat, balls[0])
    check_relaxation(bat)
    return balls[0]


def outer_part_ids(bat: BatDeck) -> list[int]:
    """The composite parts of the outer wall (all but the insert)."""
    insert = insert_part(bat.deck)
    return sorted(pid for pid in bat.deck.composites if pid != insert)


def check_contacts(bat: BatDeck, ball_pid: int) -> None:
    """One *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE of the ball (SURFA) on the outer parts
    (SURFB), and with an insert one interference contact of it on the outer parts."""
    outer = outer_part_ids(bat)
    pairs = sorted((c["kind"], sorted(contact_side(bat.deck, c, "a")),
                    sorted(contact_side(bat.deck, c, "b"))) for c in bat.deck.contacts)  # fmt: skip
    expected = [(BALL_CONTACT, [ball_pid], outer)]
    if "insert" in bat.mesh.cell_sets:
        insert = [pid for pid in bat.deck.composites if pid not in outer]
        expected.append((INTERFERENCE, insert, outer))
    if pairs != sorted(expected):
        raise SpecError("bbs deck contacts", pairs,
                        f"{sorted(expected)}: the ball (SURFA) on the outer parts, and the "
                        "insert's interference fit on them")  # fmt: skip
    for c in bat.deck.contacts:
        where = f"*{c['kind']} at {c['where']}"
        for name, allowed in (("sfsb", (None, 1.0)), ("sfsat", (None, 1.0)),
                              ("sfsbt", (None, 1.0)), ("sast", (None, 0.0)),
                              ("sbst", (None, 0.0))):  # fmt: skip
            if c.get(name) not in allowed:
                raise SpecError(f"{where} {name.upper()}", c[name],
                                "blank (batball's penalty and shell offsets)")  # fmt: skip
        if c["kind"] == INTERFERENCE and c.get("sfsa") not in (None, 1.0):
            raise SpecError(f"{where} SFSA", c["sfsa"], "blank or 1 (batball's insert penalty)")
        if c["kind"] == BALL_CONTACT and (c.get("soft") or 0) not in (0, 1):
            raise SpecError(f"{where} SOFT", c["soft"], "0 or 1")


def check_relaxation(bat: BatDeck) -> None:
    """The insert's fit as batball presses it: *CONTROL_DYNAMIC_RELAXATION with DRFCTR 0.995
    and TSSFDR blank, LCID1 a 0 -> 1 ramp for the relaxation (SIDR 1), LCID2 a constant 1 (the
    full fit in the transient); no other curve."""
    deck = bat.deck
    fits = [c for c in deck.contacts if c["kind"] == INTERFERENCE]
    used = {int(c.get(k) or 0) for c in fits for k in ("lcid1", "lcid2")}
    if set(deck.curves) - used:
        raise SpecError("*DEFINE_CURVE", sorted(set(deck.curves) - used),
                        "only the insert fit's LCID1 and LCID2 curves")  # fmt: skip
    dr = deck.controls.get("CONTROL_DYNAMIC_RELAXATION")
    if not fits:
        return
    if dr is None or dr.get("drfctr") not in (None, DRFCTR) or dr.get("tssfdr") not in (None, 0.0):
        raise SpecError(f"*CONTROL_DYNAMIC_RELAXATION at {dr['where'] if dr else 'none'} "
                        "DRFCTR/TSSFDR", (dr or {}).get("drfctr"),
                        f"present, DRFCTR blank or {DRFCTR}, TSSFDR blank or 0 (batball's "
                        "relaxation of the insert's fit)")  # fmt: skip
    fit = fits[0]
    for name, sidr, shape in (("lcid1", 1, "a ramp from 0 to 1"), ("lcid2", 0, "constant 1")):
        lcid = int(fit.get(name) or 0)
        curve = deck.curves.get(lcid)
        ramp = curve is not None and curve[0, 1] == 0.0 and curve[-1, 1] == 1.0
        ok = curve is not None and deck.curve_sidr[lcid] == sidr and (
            ramp and bool(np.all(np.diff(curve[:, 1]) >= 0)) if sidr else
            bool(np.all(curve[:, 1] == 1.0)))  # fmt: skip
        if not ok:
            raise SpecError(f"*{INTERFERENCE} at {fit['where']} {name.upper()}", lcid,
                            f"a *DEFINE_CURVE with SIDR {sidr}, {shape}")  # fmt: skip


def ball_from_deck(bat: BatDeck, pid: int, u: UnitSystem) -> tuple[Mesh, BallSpec, np.ndarray]:
    """The ball's hexes [m], its spec (module docs) and its nodes' velocity (n, 3) [m/s]."""
    mesh, _, velocity = ball_of(bat, u)
    mat = bat.deck.materials[bat.deck.parts[pid]["mid"]]
    law_name = next(name for name, law in MATERIAL_LAWS.items()
                    if law.lsdyna_keyword == f"*{mat['kind']}")  # fmt: skip
    law = MATERIAL_LAWS[law_name]
    values = {p.name: (mat.get(p.lsdyna_field.lower()) or 0.0) * u.size(p.dimension)
              for p in law.parameters}  # fmt: skip
    radius = float(np.linalg.norm(mesh.points - mesh.points.mean(axis=0), axis=1).max())
    mass = float(mat["ro"]) * u.density * float(hex_volumes(mesh.points, mesh.cells).sum())
    ball = BallSpec("deck", 2.0 * math.pi * radius, mass, MaterialSpec(law_name, values),
                    f"ball of part {pid} read from a bbs deck")  # fmt: skip
    return mesh, ball, velocity


def ball_divisions(mesh: Mesh) -> int:
    """The O-grid's divisions d of a ball of 7 d^3 hexes (:func:`batball.mesh.make_ball_mesh`)."""
    d = round((mesh.n_cells / 7) ** (1 / 3))
    if 7 * d**3 != mesh.n_cells:
        raise SpecError("*ELEMENT_SOLID", f"{mesh.n_cells} hexes",
                        "batball's O-grid ball of 7 d^3 hexes")  # fmt: skip
    return d


def ball_speed(bat: BatDeck, pid: int, velocity: np.ndarray) -> float:
    """The ball's speed along -y [m/s]: one velocity of the whole ball, on the ball only."""
    for gen in bat.deck.velocities:
        styp = {1: 2, 2: 3}.get(int(gen.get("styp") or 0))
        parts = _part_ids(bat.deck, gen.get("id"), styp, gen["where"])
        if parts != [pid]:
            raise SpecError(f"*INITIAL_VELOCITY_GENERATION at {gen['where']} ID", gen.get("id"),
                            f"the ball (part {pid}): the bat starts at rest")  # fmt: skip
    speed = -float(velocity[0, 1])
    along = np.zeros(3)
    along[1] = -speed
    if not speed > 0 or np.abs(velocity - along).max() > 1e-12 * speed:
        where = bat.deck.velocities[0]["where"] if bat.deck.velocities else "none"
        raise SpecError(
            f"*INITIAL_VELOCITY_GENERATION at {where} VX/VY/VZ",
            velocity[0].tolist(),
            "one velocity of the whole ball, along -y (VX = VZ = 0, VY < 0)",
        )
    return speed


def ball_gap(spec: BatSpec, ball: BallSpec, centre: np.ndarray) -> float:
    """The ball's clearance over the barrel [m]; it must sit above the impact point (z = 0)."""
    gap = float(centre[1] - spec.outer_radius(centre[0]) - ball.radius)
    if abs(centre[2]) > REBUILD_TOLERANCE * spec.length or not gap > 0:
        raise SpecError("ball *NODE", f"centre {centre.tolist()} m",
                        "a ball over the bat's top (y > 0, z = 0), clear of it")  # fmt: skip
    return gap


def ball_contact_options(bat: BatDeck, ball_pid: int) -> ContactOptions:
    """SOFT, SOFSCL, SFSA of the ball's contact and *CONTROL_CONTACT's SLSFAC."""
    c = next(c for c in bat.deck.contacts if c["kind"] == BALL_CONTACT)
    slsfac = bat.deck.controls.get("CONTROL_CONTACT", {}).get("slsfac") or 0.1
    return ContactOptions(soft=int(c.get("soft") or 0), slsfac=slsfac, sfs=c.get("sfsa") or 1.0,
                          sofscl=0.1 if c.get("sofscl") is None else c["sofscl"])  # fmt: skip


def band_centre(model: BbsModel, band: np.ndarray, where: str) -> float:
    """The band's centre of mass along the bat [m] (LS-DYNA turns a nodal rigid body about
    it), from the model's lumped translational masses; it must lie on the bat's axis."""
    mass = model.coupled.bat.mass[band, 0]
    centre = mass @ model.coupled.points[band] / mass.sum()
    radius = float(np.hypot(model.coupled.points[band, 1], model.coupled.points[band, 2]).max())
    if np.hypot(centre[1], centre[2]) > 1e-9 * radius:
        raise SpecError(
            f"*CONSTRAINED_NODAL_RIGID_BODY_SPC at {where} NSID",
            f"{band.size} nodes",
            "a band of whole rings (its centre of mass on the bat's axis)",
        )
    return float(centre[0])


def with_pivot(model: BbsModel, band: np.ndarray, where: str) -> BbsModel:
    """``model`` with the deck's pivot band, turning about the band's centre of mass (batball's
    rule, the rings within +-band of the pivot, gives the same only for a symmetric band)."""
    pivot_x = band_centre(model, band, where)
    bat = dataclasses.replace(model.coupled.bat, band=np.sort(band),
                              pivot=np.array([pivot_x, 0.0, 0.0]))  # fmt: skip
    coupled = dataclasses.replace(model.coupled, bat=bat)
    return dataclasses.replace(model, coupled=coupled, pivot_x=pivot_x)


def check_ball_rebuilds(model: BbsModel, ball_mesh: Mesh, spec: BatSpec) -> None:
    """The built ball's nodes and hexes must be the deck's (1e-9 of the bat's length)."""
    points = model.coupled.points[model.bat_mesh.n_points :]
    same = points.shape == ball_mesh.points.shape and np.array_equal(
        model.ball_cells, ball_mesh.cells
    )
    if not same or np.abs(points - ball_mesh.points).max() > REBUILD_TOLERANCE * spec.length:
        raise SpecError("ball *NODE/*ELEMENT_SOLID", "a ball batball's mesher does not rebuild",
                        "batball's O-grid ball (as batball export bbs writes it)")  # fmt: skip


