"""Read an LS-DYNA keyword deck into a batball explicit model: hex parts, rigid shell targets,
contact, initial velocity and controls; run it as an impact test.

Every keyword of the deck must be one this module knows (:data:`SUPPORTED`), and every field that
batball cannot honour (friction, contact damping, mass scaling, spinning initial velocity, a rigid
part that is not fixed, ...) must be blank or its default: anything else is a
:class:`~batball.errors.SpecError` naming the keyword, the field, the file and the line, never a
silent drop. *DATABASE_* requests are accepted (batball keeps its own complete histories).

A rigid shell part becomes batball's analytic target: flat (every facet normal the same) gives a
:class:`~batball.contact.rigid.RigidPlane`, a facet set whose normals all lie normal to one axis
gives a :class:`~batball.contact.rigid.RigidCylinder` (a least-squares circle through the nodes
seen along the axis; the part must lie on it to 1e-6 of its radius). Its contact face is the
mid-surface offset by half the shell thickness toward the ball, as LS-DYNA's automatic contacts
place it. Units: the deck's numbers are read in one consistent system (:data:`~batball.lsdyna.cards.
UNIT_SYSTEMS`, in-lbf-s by default) and converted to SI.

One module (about 720 lines) because it is one reader: the deck's parse, the checks of what
batball can honour, and the assembly of the model share the deck structure; the bat decks'
readers are their own modules (bat_model, bat_barrel, bat_bbs).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.errors import SpecError
from batball.lsdyna.cards import UnitSystem, unit_system
from batball.lsdyna.deck import CardLine, KeywordBlock, read_keyword_file, split_fields
from batball.materials.base import BULK
from batball.mesh import Mesh
from batball.models.ball import ContactOptions, ball_contact_stiffness, estimate_first_step
from batball.solvers.explicit import (
    BulkViscosity,
    ExplicitControls,
    HourglassControl,
    Model,
    RigidContact,
)
from batball.units import IN

#: Keywords with a fixed number of cards: (least, most).
CARD_COUNTS = {
    "PART": (2, 2), "SECTION_SOLID": (1, 1), "SECTION_SHELL": (2, 2), "MAT_ELASTIC": (1, 1),
    "MAT_VISCOELASTIC": (1, 1), "MAT_RIGID": (3, 3), "HOURGLASS": (1, 1),
    "CONTROL_TERMINATION": (1, 1), "CONTROL_TIMESTEP": (1, 1), "CONTROL_HOURGLASS": (1, 1),
    "CONTROL_BULK_VISCOSITY": (1, 1), "CONTROL_CONTACT": (1, 1),
    "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE": (3, 4), "INITIAL_VELOCITY_GENERATION": (2, 2),
    "TITLE": (1, 1), "DATABASE_GLSTAT": (1, 1), "BOUNDARY_PRESCRIBED_MOTION_RIGID": (1, 1),
    "DAMPING_GLOBAL": (1, 1), "DATABASE_MATSUM": (1, 1),
    "DATABASE_RCFORC": (1, 1), "DATABASE_NODOUT": (1, 1), "DATABASE_BINARY_D3PLOT": (1, 1),
    # bat decks (read into batball.lsdyna.bat_model; the impact reader refuses them)
    "MAT_COMPOSITE_DAMAGE": (5, 5), "CONTROL_IMPLICIT_GENERAL": (1, 1),
    "CONTROL_IMPLICIT_EIGENVALUE": (1, 1), "CONTROL_DYNAMIC_RELAXATION": (1, 1),
    "CONTACT_SURFACE_TO_SURFACE_INTERFERENCE": (4, 4),
    "CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET": (3, 3), "BOUNDARY_SPC_SET": (1, 1),
    "CONSTRAINED_NODAL_RIGID_BODY_SPC": (2, 2),
}  # fmt: skip
#: Keywords only the bat tests' decks use (:mod:`batball.lsdyna.bat_model` reads them).
BAT_KEYWORDS = {"PART_COMPOSITE", "MAT_COMPOSITE_DAMAGE", "CONTROL_IMPLICIT_GENERAL",
                "CONTROL_IMPLICIT_EIGENVALUE", "CONTROL_DYNAMIC_RELAXATION",
                "CONTACT_SURFACE_TO_SURFACE_INTERFERENCE",
                "CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET", "BOUNDARY_SPC_SET",
                "CONSTRAINED_NODAL_RIGID_BODY_SPC"}  # fmt: skip
#: Keywords whose cards repeat (one record per card, or a header card then a list).
REPEATED = {"NODE", "ELEMENT_SOLID", "ELEMENT_SHELL", "SET_PART_LIST", "SET_NODE_LIST",
            "DATABASE_HISTORY_NODE", "DEFINE_CURVE", "PART_COMPOSITE"}  # fmt: skip
SUPPORTED = {"KEYWORD", *CARD_COUNTS, *REPEATED}

#: Fields that must be blank or zero because batball has no such feature.
MUST_BE_ZERO = {
    "PART": ("eosid", "grav", "adpopt", "tmid"),
    "MAT_ELASTIC": ("da", "db", "k"),
    "HOURGLASS": ("ibq", "q1", "q2", "qb", "qw"),
    "CONTROL_TERMINATION": ("endcyc", "endeng", "endmas"),
    "CONTROL_TIMESTEP": ("lctm", "ms1st"),  # DT2MS: a bbs deck's mass scaling (lsdyna.bat_bbs)
    "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE": ("fs", "fd", "dc", "vc", "vdc", "bt", "dt", "saboxid",
                                             "sbboxid", "lcidab"),
    "INITIAL_VELOCITY_GENERATION": ("omega", "ivatn", "icid"),
    "CONTROL_CONTACT": ("penopt", "thkchg"),
    "BOUNDARY_PRESCRIBED_MOTION_RIGID": ("vid", "birth"),
    "DAMPING_GLOBAL": ("lcid", "stx", "sty", "stz", "srx", "sry", "srz"),
    "MAT_COMPOSITE_DAMAGE": ("kfail", "aopt", "beta", "alph"),
    "CONTACT_SURFACE_TO_SURFACE_INTERFERENCE": ("fs", "fd", "dc", "vc", "vdc", "bt", "saboxid",
                                                "sbboxid"),
    "CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET": ("saboxid", "sbboxid", "bt"),
    "BOUNDARY_SPC_SET": ("cid",),
    "CONSTRAINED_NODAL_RIGID_BODY_SPC": ("cid", "pnode", "drflag", "rrflag"),
    "CONTROL_IMPLICIT_EIGENVALUE": ("center", "lflag", "rflag", "shfscl"),
}  # fmt: skip


@dataclass
class Deck:
    """The parsed content of a deck, still in the deck's units, keyed by the deck's ids."""

    nodes: dict[int, tuple[float, float, float]] = field(default_factory=dict)
    solids: list[tuple[int, int, list[int], str]] = field(default_factory=list)
    shells: list[tuple[int, int, list[int], str]] = field(default_factory=list)
    parts: dict[int, dict[str, Any]] = field(default_factory=dict)
    sections: dict[int, dict[str, Any]] = field(default_factory=dict)
    materials: dict[int, dict[str, Any]] = field(default_factory=dict)
    hourglass: dict[int, dict[str, Any]] = field(default_factory=dict)
    controls: dict[str, dict[str, Any]] = field(default_factory=dict)
    contacts: list[dict[str, Any]] = field(default_factory=list)
    velocities: list[dict[str, Any]] = field(default_factory=list)
    motions: dict[int, dict[str, Any]] = field(default_factory=dict)
    curves: dict[int, np.ndarray] = field(default_factory=dict)
    part_sets: dict[int, list[int]] = field(default_factory=dict)
    node_sets: dict[int, list[int]] = field(default_factory=dict)
    curve_sidr: dict[int, int] = field(default_factory=dict)
    composites: dict[int, dict[str, Any]] = field(default_factory=dict)
    spcs: list[dict[str, Any]] = field(default_factory=list)
    nodal_rigid_bodies: list[dict[str, Any]] = field(default_factory=list)
    title: str = ""
    ignored: list[str] = field(default_factory=list)  # "*KEYWORD at file:line", output only


#: Keywords that only choose what LS-DYNA writes or how it reports (no physics): a deck from
#: HyperMesh always has some. They are read past, each listed in ``Deck.ignored`` and in the
#: run's warnings; batball records every history and energy itself.
OUTPUT_ONLY = {"CONTROL_ENERGY", "CONTROL_OUTPUT", "CONTROL_CPU", "CONTROL_PARALLEL",
               "CONTROL_MPP_IO_NOD3DUMP", "CONTROL_REPORT"}  # fmt: skip


def output_only(name: str) -> bool:
    """Whether keyword ``name`` changes no physics: an output request or an output control."""
    return name.startswith("DATABASE_") or name in OUTPUT_ONLY


def parse_deck(path: str | Path, *, include_root: str | Path | None = None) -> Deck:
    """Read every keyword of the deck at ``path`` (includes expanded, inside ``include_root``
    if named, else the deck's folder) into a :class:`Deck`."""
    deck = Deck()
    for block in read_keyword_file(path, include_root=include_root):
        if block.name not in SUPPORTED and output_only(block.name):
            deck.ignored.append(f"*{block.name} at {block.where()}")
            continue
        if block.name not in SUPPORTED:
            raise SpecError(
                f"*{block.name} at {block.where()}", "unsupported keyword",
                f"one of the keywords batball reads: {', '.join(sorted(SUPPORTED))}",
            )  # fmt: skip
        if block.name in CARD_COUNTS:
            least, most = CARD_COUNTS[block.name]
            if not least <= len(block.cards) <= most:
                raise SpecError(
                    f"*{block.name} at {block.where()}", f"{len(block.cards)} cards",
                    f"{least} to {most} cards" if least < most else f"{least} card(s)",
                )  # fmt: skip
        _store(deck, block)
    return deck


def _cards(block: KeywordBlock) -> list[dict[str, Any]]:
    """The fields of each card of a fixed-count keyword, checked against MUST_BE_ZERO."""
    cards = [split_fields(c, block.name, i, block.long) for i, c in enumerate(block.cards)]
    merged = {k: v for card in cards for k, v in card.items()}
    for name in MUST_BE_ZERO.get(block.name, ()):
        value: Any = merged.get(name)
        if value not in (None, 0, 0.0) and not (name == "dt" and value >= 1e20):
            raise SpecError(
                f"*{block.name}.{name.upper()} at {block.where()}", value,
                "blank or 0 (batball has no such feature)",
            )  # fmt: skip
    return cards


def _store(deck: Deck, block: KeywordBlock) -> None:
    """File one keyword block's content into ``deck``."""
    name = block.name
    if name in ("KEYWORD",) or name.startswith("DATABASE_"):
        return  # output requests: batball records every history itself
    if name in ("NODE", "ELEMENT_SOLID", "ELEMENT_SHELL"):
        _store_records(deck, block)
    elif name in ("SET_PART_LIST", "SET_NODE_LIST"):
        _store_set(deck, block)
    elif name == "DEFINE_CURVE":
        _store_curve(deck, block)
    elif name == "PART_COMPOSITE":
        _store_composite(deck, block)
    else:
        cards = _cards(block)
        merged = {k: v for card in cards for k, v in card.items()}
        merged["where"] = block.where()
        _file_fixed(deck, name, merged)


def _file_fixed(deck: Deck, name: str, fields: dict[str, Any]) -> None:
    """File the fields of a fixed-count keyword under its id."""
    if name == "TITLE":
        deck.title = str(fields.get("title") or "")
    elif name == "PART":
        deck.parts[_id(fields, "pid", name)] = fields
    elif name.startswith("SECTION_"):
        deck.sections[_id(fields, "secid", name)] = {**fields, "kind": name}
    elif name.startswith("MAT_"):
        deck.materials[_id(fields, "mid", name)] = {**fields, "kind": name}
    elif name == "HOURGLASS":
        deck.hourglass[_id(fields, "hgid", name)] = fields
    elif name.startswith("CONTROL_"):
        deck.controls[name] = fields
    elif name.startswith("CONTACT_"):
        deck.contacts.append({**fields, "kind": name})
    elif name == "BOUNDARY_SPC_SET":
        deck.spcs.append(fields)
    elif name == "CONSTRAINED_NODAL_RIGID_BODY_SPC":
        deck.nodal_rigid_bodies.append(fields)
    elif name == "INITIAL_VELOCITY_GENERATION":
        deck.velocities.append(fields)
    elif name == "BOUNDARY_PRESCRIBED_MOTION_RIGID":
        deck.motions[_id(fields, "pid", name)] = fields
    elif name == "DAMPING_GLOBAL":
        deck.controls[name] = fields


def _id(fields: dict[str, Any], key: str, name: str) -> int:
    """The positive id field ``key`` of a keyword."""
    value = fields.get(key)
    if not isinstance(value, int) or value <= 0:
        raise SpecError(f"*{name}.{key.upper()} at {fields['where']}", value, "a positive id")
    return value


def _store_records(deck: Deck, block: KeywordBlock) -> None:
    """*NODE, *ELEMENT_SOLID (one- or two-card form) and *ELEMENT_SHELL records."""
    cards = [c for c in block.cards if c.text.strip()]
    i = 0
    while i < len(cards):
        card = cards[i]
        f = split_fields(card, block.name, 0, block.long)
        if block.name == "NODE":
            _check_zero(f, ("tc", "rc"), block.name, card)
            xyz = (f.get("x") or 0.0, f.get("y") or 0.0, f.get("z") or 0.0)
            deck.nodes[_id({**f, "where": card.where()}, "nid", "NODE")] = xyz  # type: ignore[assignment]
        else:
            n = 8 if block.name == "ELEMENT_SOLID" else 4
            nodes = [f.get(f"n{k}") for k in range(1, n + 1)]
            if block.name == "ELEMENT_SOLID" and all(v is None for v in nodes):
                i += 1  # two-card form: EID PID, then N1..N10 in 8-column fields
                nodes = _node_card(cards, i, block)
            if any(not isinstance(v, int) or v <= 0 for v in nodes):
                raise SpecError(f"*{block.name} at {card.where()}", card.text.strip(),
                                f"{n} positive node ids")  # fmt: skip
            target = deck.solids if block.name == "ELEMENT_SOLID" else deck.shells
            target.append((int(f["eid"]), int(f["pid"]), nodes, card.where()))  # type: ignore
        i += 1


def _node_card(cards: list[CardLine], i: int, block: KeywordBlock) -> list[Any]:
    """N1..N8 of a two-card *ELEMENT_SOLID (N9, N10 must be blank)."""
    if i >= len(cards):
        raise SpecError(f"*{block.name} at {block.where()}", "a missing node card", "N1..N8")
    text = cards[i].text
    width = 20 if block.long else 8
    raw = text.split(",") if "," in text else [text[k : k + width] for k in range(0, 80, width)]
    values = [v.strip() for v in raw]
    if any(values[8:]):
        raise SpecError(f"*ELEMENT_SOLID at {cards[i].where()}", text.strip(), "8-node hexes")
    ids: list[Any] = []
    for v in values[:8]:
        try:
            number = float(v) if v else None
        except ValueError:
            number = math.nan
        if number is not None and not (math.isfinite(number) and number == int(number)):
            raise SpecError(f"*ELEMENT_SOLID at {cards[i].where()}", v, "a node id")
        ids.append(None if number is None else int(number))
    return ids


def _check_zero(
    fields: dict[str, Any], names: tuple[str, ...], keyword: str, card: CardLine
) -> None:
    """Fields that must be blank or zero on a record card."""
    for name in names:
        if fields.get(name) not in (None, 0):
            raise SpecError(f"*{keyword}.{name.upper()} at {card.where()}", fields[name],
                            "blank or 0 (no constraints on nodes)")  # fmt: skip


def _store_set(deck: Deck, block: KeywordBlock) -> None:
    """*SET_PART_LIST (kept) and *SET_NODE_LIST (read, no batball use without a reference)."""
    if not block.cards:
        raise SpecError(f"*{block.name} at {block.where()}", "no cards", "a SID card")
    head = split_fields(block.cards[0], block.name, 0, block.long)
    ids: list[int] = []
    for card in block.cards[1:]:
        ids += [int(v) for v in split_fields(card, block.name, 1, block.long).values() if v]  # type: ignore[call-overload]
    sid = _id({**head, "where": block.where()}, "sid", block.name)
    if block.name == "SET_PART_LIST":
        deck.part_sets[sid] = ids
    else:
        deck.node_sets[sid] = ids


def _store_curve(deck: Deck, block: KeywordBlock) -> None:
    """*DEFINE_CURVE: LCID and (abscissa, ordinate) points; scale factors and offsets must be
    their defaults (SFA = SFO = 1, OFFA = OFFO = 0, DATTYP = 0); SIDR 0 (transient) or 1 (the
    dynamic relaxation phase only, kept in ``deck.curve_sidr`` for the bat reader)."""
    cards = [c for c in block.cards if c.text.strip()]
    if len(cards) < 2:
        raise SpecError(f"*DEFINE_CURVE at {block.where()}", len(cards), "a header and points")
    head = split_fields(cards[0], block.name, 0, block.long)
    for name, default in (("sfa", 1), ("sfo", 1), ("offa", 0), ("offo", 0), ("dattyp", 0)):
        if head.get(name) not in (None, default, float(default)):
            raise SpecError(f"*DEFINE_CURVE.{name.upper()} at {block.where()}", head[name],
                            f"blank or {default}")  # fmt: skip
    points = [split_fields(c, block.name, 1, block.long) for c in cards[1:]]
    xy = np.array([[p.get("a1") or 0.0, p.get("o1") or 0.0] for p in points])
    lcid = _id({**head, "where": block.where()}, "lcid", block.name)
    if head.get("sidr") not in (None, 0, 1):
        raise SpecError(f"*DEFINE_CURVE.SIDR at {block.where()}", head["sidr"], "blank, 0 or 1")
    deck.curves[lcid], deck.curve_sidr[lcid] = xy, int(head.get("sidr") or 0)  # type: ignore[call-overload]


def _store_composite(deck: Deck, block: KeywordBlock) -> None:
    """*PART_COMPOSITE: title, the PID card, then two layers (MID, THICK, B, TMID) a card."""
    cards = [c for c in block.cards if c.text.strip()]
    if len(cards) < 3:
        raise SpecError(f"*PART_COMPOSITE at {block.where()}", f"{len(cards)} cards",
                        "a title, the PID card and at least one layer card")  # fmt: skip
    title = split_fields(cards[0], block.name, 0, block.long).get("title") or ""
    fields = {**split_fields(cards[1], block.name, 1, block.long), "where": block.where()}
    for name in ("adpopt", "thshel", "hgid", "nloc"):
        if fields.get(name) not in (None, 0, 0.0):
            raise SpecError(f"*PART_COMPOSITE.{name.upper()} at {block.where()}", fields[name],
                            "blank or 0 (batball has no such feature)")  # fmt: skip
    layers = []
    for card in cards[2:]:
        f = split_fields(card, block.name, 2, block.long)
        for j in (1, 2):
            if f.get(f"tmid{j}") not in (None, 0):
                raise SpecError(f"*PART_COMPOSITE.TMID{j} at {card.where()}", f[f"tmid{j}"],
                                "blank or 0 (no thermal materials)")  # fmt: skip
            if f.get(f"mid{j}") is not None:
                layers.append((f[f"mid{j}"], f.get(f"thick{j}") or 0.0, f.get(f"b{j}") or 0.0,
                               card.where()))  # fmt: skip
    deck.composites[_id(fields, "pid", block.name)] = {**fields, "title": str(title).strip(),
                                                       "layers": layers}  # fmt: skip


@dataclass(frozen=True)
class DeckModel:
    """A deck read into batball: the model, its run controls, and what the impact measures need.

    Attributes:
        test: "ccor" (the first target is a cylinder), "cor" (a flat wall) or "compression" (a
            moving plate). ignored: the output keywords read past, each as ``*NAME at file:line``.
        speed: the body's initial speed, or the plate's for compression [m/s]; title: the
            deck's *TITLE; units: its unit system; displacement: compression reading point [m].
    """

    model: Model
    controls: ExplicitControls
    test: str
    speed: float
    title: str
    units: str
    displacement: float = 0.0
    ignored: tuple[str, ...] = ()


def read_deck(
    path: str | Path,
    *,
    units: str = "in-lbf-s",
    separation_time: float | None = 0.1e-3,
    displacement: float = 0.25 * IN,
    precision: str = "single",
    include_root: str | Path | None = None,
) -> DeckModel:
    """Read the deck at ``path`` (numbers in ``units``) into a :class:`DeckModel`.

    ``separation_time`` is batball's own stopping rule for impacts (run on this long after the
    last contact; None runs to the deck's ENDTIM), which LS-DYNA decks have no field for. A deck
    with a moving plate is a compression test, read at ``displacement`` of ball deformation
    (F1888: 0.25 in), and runs to ENDTIM. ``precision`` is an impact deck's element arithmetic
    (as ``batball ccor``'s; LS-DYNA's is the executable's, not the deck's); a compression deck
    runs double, as ``batball compression``. ``include_root``: see :func:`parse_deck`.
    """
    u = unit_system(units)
    deck = parse_deck(path, include_root=include_root)
    _refuse_bat_keywords(deck, path)
    solid_parts = sorted({pid for _, pid, _, _ in deck.solids})
    if not solid_parts:
        raise SpecError(f"deck {path}", "no *ELEMENT_SOLID", "a hex-meshed body")
    mesh, node_ids = _solid_mesh(deck, u)
    constants, densities, cell_material = _materials(deck, solid_parts, u)
    step = deck.controls.get("CONTROL_TIMESTEP", {})
    if step.get("dt2ms"):
        raise SpecError(f"*CONTROL_TIMESTEP.DT2MS at {step['where']}", step["dt2ms"],
                        "blank or 0 (the ball tests have no mass scaling)")  # fmt: skip
    controls = _controls(deck, solid_parts, u, separation_time)
    velocity = _initial_velocity(deck, mesh, node_ids, u)
    contacts = _contacts(deck, mesh, constants, densities, controls, u, solid_parts)
    model = Model(
        mesh=mesh,
        cell_material=cell_material,
        material_constants=constants,
        densities=densities,
        contacts=contacts,
        initial_velocity=velocity,
    )
    moving = [c.target.velocity for c in contacts if c.target.velocity is not None]
    unused = set(deck.motions) - {
        pid for c in deck.contacts for pid in (c.get("surfb"), c.get("surfa"))
    }
    if unused:
        raise SpecError("*BOUNDARY_PRESCRIBED_MOTION_RIGID", sorted(unused), "a contact's part")
    if moving:
        controls = _compression_controls(controls, model, len(contacts), displacement)
        speed = float(np.linalg.norm(moving[0]))
        return DeckModel(model, controls, "compression", speed, deck.title, u.name, displacement,
                         tuple(deck.ignored))  # fmt: skip
    speed = float(np.linalg.norm(velocity[0]))
    if not speed > 0 or np.abs(velocity - velocity[0]).max() > 1e-12 * speed:
        raise SpecError(
            "*INITIAL_VELOCITY_GENERATION", "none or not the same on every ball node",
            "one velocity of the whole ball (impact) or a moving plate (compression)",
        )  # fmt: skip
    test = "ccor" if isinstance(contacts[0].target, RigidCylinder) else "cor"
    controls = dataclasses.replace(controls, precision=precision)
    return DeckModel(model, controls, test, speed, deck.title, u.name, ignored=tuple(deck.ignored))


def _refuse_bat_keywords(deck: Deck, path: str | Path) -> None:
    """An impact or compression deck may not hold what only the bat reader honours."""
    kinds = {c["kind"] for c in deck.contacts} - {"CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"}
    used = kinds | ({"PART_COMPOSITE"} if deck.composites else set())
    used |= {name for name in deck.controls if name in BAT_KEYWORDS}
    used |= {"BOUNDARY_SPC_SET"} if deck.spcs else set()
    used |= {"CONSTRAINED_NODAL_RIGID_BODY_SPC"} if deck.nodal_rigid_bodies else set()
    used |= {f"MAT_COMPOSITE_DAMAGE {m}" for m, v in deck.materials.items()
             if v["kind"] == "MAT_COMPOSITE_DAMAGE"}  # fmt: skip
    if used or any(deck.curve_sidr.values()):
        raise SpecError(
            f"deck {path}",
            sorted(used) or "a SIDR 1 curve",
            "a ball test's keywords only (a bat deck is read by the bat reader)",
        )


def _compression_controls(
    controls: ExplicitControls, model: Model, n_contacts: int, displacement: float
) -> ExplicitControls:
    """A compression deck's controls: run to ENDTIM, and the energy floor run_compression uses
    (1 % of the relaxed Hertz estimate of the plates' work)."""
    import dataclasses

    from batball.models.compression import relaxed_hertz

    top = model.contacts[0].target
    if n_contacts != 2 or top.velocity is None or model.contacts[1].target.velocity is not None:
        raise SpecError("compression deck", f"{n_contacts} contacts",
                        "two plates, the first (top) moving, the second fixed")  # fmt: skip
    radius = float(np.linalg.norm(model.mesh.points, axis=1).max())
    hertz = relaxed_hertz(model.material_constants[0], radius, displacement)[0]
    return dataclasses.replace(
        controls, separation_time=None, frame_count=20,
        energy_floor=0.01 * 0.4 * hertz * displacement,
    )  # fmt: skip


def _solid_mesh(deck: Deck, u: UnitSystem) -> tuple[Mesh, np.ndarray]:
    """The hex mesh [m] of every solid element, nodes numbered in the deck's node order."""
    used = {n for _, _, nodes, _ in deck.solids for n in nodes}
    missing = sorted(used - set(deck.nodes))
    if missing:
        raise SpecError("*ELEMENT_SOLID", f"node {missing[0]}", "a node defined by *NODE")
    order = [n for n in deck.nodes if n in used]
    index = {n: i for i, n in enumerate(order)}
    points = np.array([deck.nodes[n] for n in order], dtype=np.float64) * u.length
    cells = np.array([[index[n] for n in nodes] for _, _, nodes, _ in deck.solids], dtype=np.int64)
    return Mesh(points=points, cells=cells), np.array(order, dtype=np.int64)


def _materials(
    deck: Deck, solid_parts: list[int], u: UnitSystem
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Kernel constants [SI] and density per solid part, and each hex's row."""
    rows, densities = [], []
    for pid in solid_parts:
        part = _lookup(deck.parts, pid, "*PART", "PID")
        section = _lookup(deck.sections, part["secid"], f"*PART {pid} SECID", "*SECTION_SOLID")
        if section["kind"] != "SECTION_SOLID" or (section.get("elform") or 1) != 1:
            raise SpecError(f"*SECTION at {section['where']}", section.get("elform"),
                            "*SECTION_SOLID with ELFORM 1 (one-point hexes)")  # fmt: skip
        mat = _lookup(deck.materials, part["mid"], f"*PART {pid} MID", "*MAT")
        rows.append(_kernel_constants(mat, u))
        densities.append(_positive(mat, "ro") * u.density)
    index = {pid: i for i, pid in enumerate(solid_parts)}
    cell_material = np.array([index[pid] for _, pid, _, _ in deck.solids], dtype=np.int64)
    return np.array(rows), np.array(densities), cell_material


def _kernel_constants(mat: dict[str, Any], u: UnitSystem) -> np.ndarray:
    """The hex kernel's constants [SI] of the *MAT card of a registered law (the law whose
    ``lsdyna_keyword`` is the card; each parameter read from its ``lsdyna_field``, blank = 0)."""
    from batball.materials import MATERIAL_LAWS

    laws = [law for law in MATERIAL_LAWS.values() if law.lsdyna_keyword == f"*{mat['kind']}"]
    if not laws:
        raise SpecError(
            f"*{mat['kind']} at {mat['where']}", "on a solid part",
            "*MAT_VISCOELASTIC or *MAT_ELASTIC for hexes",
        )  # fmt: skip
    law = laws[0]
    values = {
        p.name: (mat.get(p.lsdyna_field.lower()) or 0.0) * u.size(p.dimension)
        for p in law.parameters
    }
    law.check(values, prefix=f"*{mat['kind']} at {mat['where']}")
    return law.kernel_constants(values)


def _lookup(table: dict[int, dict[str, Any]], key: Any, where: str, what: str) -> dict[str, Any]:
    """``table[key]`` or a SpecError saying which reference is dangling."""
    if key not in table:
        raise SpecError(where, key, f"the id of a {what} in the deck")
    return table[key]


def _positive(fields: dict[str, Any], name: str) -> float:
    """A field that must be a positive number."""
    value = fields.get(name)
    if not isinstance(value, float | int) or not value > 0:
        raise SpecError(f"{name.upper()} at {fields['where']}", value, "a positive number")
    return float(value)


def _controls(
    deck: Deck, solid_parts: list[int], u: UnitSystem, separation_time: float | None
) -> ExplicitControls:
    """End time, TSSFAC, DTMIN, hourglass and bulk viscosity of the deck (LS-DYNA defaults)."""
    c = deck.controls
    term = c.get("CONTROL_TERMINATION")
    if term is None or not (term.get("endtim") or 0) > 0:
        raise SpecError("*CONTROL_TERMINATION.ENDTIM", None, "a positive end time")
    step = c.get("CONTROL_TIMESTEP", {})
    bulk = c.get("CONTROL_BULK_VISCOSITY", {})
    if bulk.get("type") not in (None, 1, -1):
        raise SpecError(f"*CONTROL_BULK_VISCOSITY.TYPE at {bulk['where']}", bulk["type"], "1")
    q1 = 1.5 if bulk.get("q1") is None else bulk["q1"]
    q2 = 0.06 if bulk.get("q2") is None else bulk["q2"]
    dtmin = term.get("dtmin") or 0.0
    damping = (c.get("DAMPING_GLOBAL", {}).get("valdmp") or 0.0) / u.time
    return ExplicitControls(
        mass_damping=damping,
        end_time=term["endtim"] * u.time,
        time_step_scale=step.get("tssfac") or 0.9,
        hourglass=_hourglass(deck, solid_parts),
        bulk_viscosity=BulkViscosity(q1=q1, q2=q2, enabled=(q1, q2) != (0.0, 0.0)),
        separation_time=separation_time,
        min_step_ratio=dtmin if dtmin > 0 else 1e-3,
    )


def _hourglass(deck: Deck, solid_parts: list[int]) -> HourglassControl:
    """The one hourglass control of the solid parts: their *HOURGLASS, else *CONTROL_HOURGLASS."""
    glob = deck.controls.get("CONTROL_HOURGLASS", {})
    default = (glob.get("ihq") or 1, 0.1 if glob.get("qh") is None else glob["qh"])
    chosen = set()
    for pid in solid_parts:
        hgid = deck.parts[pid].get("hgid") or 0
        if hgid:
            hg = _lookup(deck.hourglass, hgid, f"*PART {pid} HGID", "*HOURGLASS")
            chosen.add((hg.get("ihq") or default[0], 0.1 if hg.get("qm") is None else hg["qm"]))
        else:
            chosen.add(default)
    if len(chosen) > 1:
        raise SpecError("*HOURGLASS", sorted(chosen), "one hourglass control for all solid parts")
    ihq, qh = chosen.pop()
    return HourglassControl(type=int(ihq), coefficient=float(qh))


def _part_ids(deck: Deck, surf: Any, kind: Any, where: str) -> list[int]:
    """The parts a contact side names: a part (type 3) or a *SET_PART_LIST (type 2)."""
    if kind == 3:
        return [int(surf)]
    if kind == 2:
        return list(_lookup({k: {"p": v} for k, v in deck.part_sets.items()}, surf, where,
                            "*SET_PART_LIST")["p"])  # fmt: skip
    raise SpecError(f"{where} SURFATYP/SURFBTYP", kind, "2 (part set) or 3 (part)")


def _initial_velocity(deck: Deck, mesh: Mesh, node_ids: np.ndarray, u: UnitSystem) -> np.ndarray:
    """Nodal initial velocity [m/s] from *INITIAL_VELOCITY_GENERATION (STYP 1 set, 2 part)."""
    velocity = np.zeros((mesh.n_points, 3))
    index = {int(n): i for i, n in enumerate(node_ids)}
    for gen in deck.velocities:
        styp = {1: 2, 2: 3}.get(gen.get("styp"))  # type: ignore[arg-type]
        if styp is None:
            raise SpecError(f"*INITIAL_VELOCITY_GENERATION.STYP at {gen['where']}", gen["styp"],
                            "1 (part set) or 2 (part)")  # fmt: skip
        parts = set(_part_ids(deck, gen.get("id"), styp, gen["where"]))
        v = np.array([gen.get(k) or 0.0 for k in ("vx", "vy", "vz")]) * u.velocity
        for _, pid, nodes, _ in deck.solids:
            if pid in parts:
                velocity[[index[n] for n in nodes]] = v
    return velocity


def _contacts(
    deck: Deck,
    mesh: Mesh,
    constants: np.ndarray,
    densities: np.ndarray,
    controls: ExplicitControls,
    u: UnitSystem,
    solid_parts: list[int],
) -> tuple[RigidContact, ...]:
    """One batball contact per *CONTACT card: the solid side's surface against a rigid target."""
    if not deck.contacts:
        raise SpecError("deck", "no *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", "a contact")
    if len(solid_parts) > 1 and np.ptp(constants[:, BULK]) > 0:
        raise SpecError("solid parts", solid_parts, "one bulk modulus for the contact penalty")
    slsfac = deck.controls.get("CONTROL_CONTACT", {}).get("slsfac") or 0.1
    out: list[RigidContact] = []
    for c in deck.contacts:
        a = _part_ids(deck, c.get("surfa"), c.get("surfatyp") or 0, c["where"])
        b = _part_ids(deck, c.get("surfb"), c.get("surfbtyp") or 0, c["where"])
        rigid = b if set(a) <= set(solid_parts) else a
        if set(a) | set(b) != set(solid_parts) | set(rigid) or set(rigid) & set(solid_parts):
            raise SpecError(
                f"*CONTACT at {c['where']}",
                (a, b),
                "the solid parts on one side, one rigid shell part on the other",
            )
        soft = c.get("soft") or 0
        sfs = c.get("sfsa" if rigid is b else "sfsb") or 1.0  # the solid side's factor
        options = ContactOptions(
            soft=soft,
            slsfac=slsfac,
            sfs=sfs,
            sofscl=0.1 if c.get("sofscl") is None else c["sofscl"],
        )
        density = float(densities.max())
        first_dt = estimate_first_step(mesh, constants[0], density) * controls.time_step_scale
        bulk = float(constants[0, BULK])
        nodes, k = ball_contact_stiffness(mesh, bulk, density, options, first_dt)
        for name in ("sfsat", "sfsbt"):
            if c.get(name) not in (None, 1.0):
                raise SpecError(f"*CONTACT.{name.upper()} at {c['where']}", c[name], "blank or 1")
        # SAST/SBST: an explicit contact thickness of the rigid side replaces its shell thickness
        override = c.get("sbst" if rigid is b else "sast") or 0.0
        if c.get("sast" if rigid is b else "sbst"):
            raise SpecError(f"*CONTACT at {c['where']}", "a solid-side contact thickness",
                            "blank (solids have no contact thickness)")  # fmt: skip
        target = _rigid_target(deck, rigid, mesh, u, override * u.length)
        out.append(RigidContact(f"contact {len(out) + 1}", target, nodes, k))
    return tuple(out)


def _rigid_target(
    deck: Deck, parts: list[int], mesh: Mesh, u: UnitSystem, contact_thickness: float = 0.0
) -> RigidPlane | RigidCylinder:
    """batball's analytic target from one fixed *MAT_RIGID shell part (see the module notes)."""
    if len(parts) != 1:
        raise SpecError("*CONTACT rigid side", parts, "one rigid shell part")
    pid = parts[0]
    part = _lookup(deck.parts, pid, "*CONTACT SURFB", "*PART")
    mat = _lookup(deck.materials, part["mid"], f"*PART {pid} MID", "*MAT")
    velocity = _rigid_velocity(deck, pid, mat, u)
    section = _lookup(deck.sections, part["secid"], f"*PART {pid} SECID", "*SECTION_SHELL")
    if section["kind"] != "SECTION_SHELL":
        raise SpecError(f"*PART {pid} SECID", section["kind"], "a *SECTION_SHELL (rigid shells)")
    thickness = contact_thickness or _positive(section, "t1") * u.length
    quads = [nodes for _, p, nodes, _ in deck.shells if p == pid]
    if not quads:
        raise SpecError(f"*PART {pid}", "no *ELEMENT_SHELL", "the rigid part's shells")
    xyz = np.array([[deck.nodes[n] for n in q] for q in quads]) * u.length
    target = fit_target(xyz, thickness, mesh.points.mean(axis=0), where=f"rigid part {pid}")
    if velocity is None:
        return target
    if not isinstance(target, RigidPlane):
        raise SpecError(f"rigid part {pid}", "a moving cylinder", "a moving flat plate")
    return RigidPlane(point=target.point, normal=target.normal, velocity=velocity)


def _rigid_velocity(deck: Deck, pid: int, mat: dict[str, Any], u: UnitSystem) -> np.ndarray | None:
    """None for a fixed rigid part (CMO 1, CON1 = CON2 = 7); the velocity [m/s] of a part that
    moves along z at a constant speed (CON1 4, CON2 7 and *BOUNDARY_PRESCRIBED_MOTION_RIGID DOF 3,
    VAD 0 on a constant curve). Anything else is a SpecError."""
    fixed = (mat.get("cmo"), mat.get("con1"), mat.get("con2")) == (1.0, 7.0, 7.0)
    sliding = (mat.get("cmo"), mat.get("con1"), mat.get("con2")) == (1.0, 4.0, 7.0)
    motion = deck.motions.get(pid)
    if mat["kind"] != "MAT_RIGID" or not (fixed or sliding) or fixed == (motion is not None):
        raise SpecError(
            f"*{mat['kind']} at {mat['where']}", f"rigid part {pid}",
            "*MAT_RIGID fixed (CMO 1, CON1 7, CON2 7), or moving in z (CON1 4, CON2 7) with a "
            "*BOUNDARY_PRESCRIBED_MOTION_RIGID",
        )  # fmt: skip
    if motion is None:
        return None
    where = f"*BOUNDARY_PRESCRIBED_MOTION_RIGID at {motion['where']}"
    if motion.get("dof") != 3 or motion.get("vad") or (motion.get("death") or 1e28) < 1e27:
        raise SpecError(where, (motion.get("dof"), motion.get("vad"), motion.get("death")),
                        "DOF 3, VAD 0 (velocity), no DEATH")  # fmt: skip
    curve = _lookup({k: {"c": v} for k, v in deck.curves.items()}, motion.get("lcid"), where,
                    "*DEFINE_CURVE")["c"]  # fmt: skip
    end = deck.controls["CONTROL_TERMINATION"]["endtim"]
    if np.ptp(curve[:, 1]) > 0 or curve[:, 0].min() > 0 or curve[:, 0].max() < end:
        raise SpecError(where, "LCID curve", "a constant curve over 0..ENDTIM (constant speed)")
    speed = (1.0 if motion.get("sf") is None else motion["sf"]) * curve[0, 1]
    return np.array([0.0, 0.0, speed * u.velocity])


def fit_target(
    quads: np.ndarray, thickness: float, body_centre: np.ndarray, *, where: str
) -> RigidPlane | RigidCylinder:
    """The plane or half-cylinder a set of shell quads (n, 4, 3) [m] lies on, its face offset
    half a ``thickness`` toward ``body_centre``; SpecError if it is neither."""
    normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    eigval, eigvec = np.linalg.eigh(normals.T @ normals / len(normals))
    points = quads.reshape(-1, 3)
    tol = 1e-10
    if eigval[1] < tol:  # every normal parallel: a wall
        n = eigvec[:, 2]
        centre = points.mean(axis=0)
        n = n if (body_centre - centre) @ n > 0 else -n
        if np.abs((points - centre) @ n).max() > 1e-9 * np.ptp(points, axis=0).max():
            raise SpecError(where, "not flat", "a flat or cylindrical rigid shell part")
        return RigidPlane(point=centre + 0.5 * thickness * n, normal=n)
    if eigval[0] > tol:
        raise SpecError(where, "neither flat nor a cylinder", "a flat or cylindrical shell part")
    axis = eigvec[:, 0]
    e1 = eigvec[:, 2]
    e2 = np.cross(axis, e1)
    x, y = points @ e1, points @ e2
    # least-squares circle x^2 + y^2 = 2 a x + 2 b y + c (Kasa fit)
    a, b, c = np.linalg.lstsq(np.stack([2 * x, 2 * y, np.ones_like(x)], axis=1),
                              x**2 + y**2, rcond=None)[0]  # fmt: skip
    r_mid = float(np.sqrt(c + a * a + b * b))
    if np.abs(np.hypot(x - a, y - b) - r_mid).max() > 1e-6 * r_mid:
        raise SpecError(where, "not on one circle", "a flat or cylindrical rigid shell part")
    s = points @ axis
    centre = a * e1 + b * e2 + 0.5 * (s.min() + s.max()) * axis
    radial = points - centre - np.outer((points - centre) @ axis, axis)
    front = radial.mean(axis=0)
    return RigidCylinder(axis_point=centre, axis=axis, front=front / np.linalg.norm(front),
                         radius=r_mid + 0.5 * thickness, length=float(np.ptp(s)))  # fmt: skip


