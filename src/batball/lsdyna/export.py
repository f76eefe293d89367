"""Write a ball-impact test (CCOR against the F2845 half-cylinder, COR against the F1887 wall) as
a complete LS-DYNA keyword deck, built from the same objects as :func:`batball.lab.impact.
run_impact` (:func:`~batball.models.ball.ball_body`, :func:`~batball.models.impact.make_target`).

The ball is part 1 (hexes, ELFORM 1, its material law's *MAT card). batball's analytic rigid
target becomes part 2, a mesh of *MAT_RIGID shells fixed in space (CMO = 1, CON1 = CON2 = 7), and
the penalty contact stays a penalty contact: *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE with the ball
as SURFA and the target as SURFB, SOFT/SOFSCL on card A, SFSA on card 3 and SLSFAC on
*CONTROL_CONTACT, which are the fields batball's contact stiffness reads. A *RIGIDWALL would
have been shorter but is a constraint (no SLSFAC/SOFT penalty), so it would change the force
history that CCOR, DS and contact time are measured on. Automatic contacts offset a shell's
contact surface by half its thickness, so the shells lie half a thickness behind batball's face:
the contact face is where batball's is.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from contextvars import ContextVar
from typing import Any

import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.errors import SpecError
from batball.lsdyna.cards import (
    LAYOUTS,
    UnitSystem,
    comment_header,
    format_card,
    unit_system,
)
from batball.models.ball import ball_body, with_ball_hourglass
from batball.models.compression import TRAVEL_MARGIN, CompressionSetup, build_compression_model
from batball.models.impact import ImpactSetup, make_target
from batball.solvers.explicit import HourglassControl
from batball.specs import BallSpec
from batball.units import IN, MPH
from batball.version import __version__

#: Shell thickness of the rigid target [m]; only its contact offset matters (it is rigid).
TARGET_THICKNESS = 0.05 * IN
#: Steel for the rigid part's contact stiffness (E, nu, density; SI). LS-DYNA uses the rigid
#: part's E and PR only to size the penalty on its side of the contact.
STEEL = (200e9, 0.3, 7850.0)
BALL_PART, TARGET_PART = 1, 2
TARGET_NODE_START = 1_000_001
TARGET_ELEMENT_START = 1_000_001


#: Whether the deck being written uses long format (20 columns a field, *KEYWORD LONG=Y).
_LONG: ContextVar[bool] = ContextVar("long_format", default=False)


def card(name: str, index: int, values: Mapping[str, object]) -> str:
    """One card of the deck being written, standard or long format."""
    return format_card(name, index, values, long=_LONG.get())


def head(name: str, index: int) -> str:
    """The ``$#`` field-name line of one card of the deck being written."""
    return comment_header(name, index, long=_LONG.get())


def keyword(name: str, *cards: Mapping[str, object], comment: bool = True) -> list[str]:
    """``*NAME`` and its cards, each under a ``$#`` line naming its fields."""
    lines = [f"*{name}"]
    for i, values in enumerate(cards):
        if comment:
            lines.append(head(name, i))
        lines.append(card(name, i, values))
    return lines


def material_cards(ball: BallSpec, density: float, u: UnitSystem) -> list[str]:
    """The ball's *MAT card (MID 1) in units ``u``, driven by the law's declaration: its
    ``lsdyna_keyword`` names the card and each parameter's ``lsdyna_field`` its field."""
    law = ball.material.material_law
    name = law.lsdyna_keyword.lstrip("*")
    if name not in LAYOUTS:
        raise SpecError(
            "material.law", ball.material.law,
            f"a law whose keyword batball writes ({law.lsdyna_keyword} is not one yet)",
        )  # fmt: skip
    values: dict[str, object] = {"mid": 1, "ro": density / u.density}
    for p in law.parameters:
        values[p.lsdyna_field.lower()] = ball.material.values[p.name] / u.size(p.dimension)
    return keyword(name, values)


def target_shells(
    target: RigidPlane | RigidCylinder, ball_radius: float
) -> tuple[np.ndarray, np.ndarray]:
    """Nodes [m] and quads (0-based) of the target's mid-surface, half a thickness behind its face.

    The cylinder's front half is cut in 96 facets around and 24 along (chord sag 1.8e-4 in on the
    2.63-in cylinder); the wall is a square of four ball diameters, 20 x 20 quads. Quads are
    ordered so that their normals point toward the ball.
    """
    half = 0.5 * TARGET_THICKNESS
    if isinstance(target, RigidPlane):
        n = np.asarray(target.normal, dtype=float) / np.linalg.norm(target.normal)
        e1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        s = np.linspace(-4 * ball_radius, 4 * ball_radius, 21)
        a, b = np.meshgrid(s, s, indexing="ij")
        centre = np.asarray(target.point, dtype=float) - half * n
        points = centre + a.reshape(-1, 1) * e1 + b.reshape(-1, 1) * e2
        return points, _grid_quads(21, 21)
    axis = np.asarray(target.axis, dtype=float) / np.linalg.norm(target.axis)
    front = np.asarray(target.front, dtype=float) / np.linalg.norm(target.front)
    side = np.cross(axis, front)
    theta = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 97)
    s = np.linspace(-0.5 * target.length, 0.5 * target.length, 25)
    r = target.radius - half
    radial = np.cos(theta)[:, None] * front + np.sin(theta)[:, None] * side
    points = (
        np.asarray(target.axis_point, dtype=float)
        + (r * radial)[:, None, :]
        + s[None, :, None] * axis
    ).reshape(-1, 3)
    quads = _grid_quads(97, 25)
    # (theta, s) grid: d/dtheta x d/ds = r (front x ... ) -> orient outward (away from the axis)
    p = points[quads]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 3] - p[:, 0])
    outward = p.mean(axis=1) - np.asarray(target.axis_point)
    if np.einsum("ij,ij->i", normal, outward).mean() < 0:
        quads = quads[:, ::-1]
    return points, quads


def _grid_quads(n_a: int, n_b: int) -> np.ndarray:
    """Quads of a structured n_a x n_b node grid numbered a-major."""
    a, b = np.meshgrid(np.arange(n_a - 1), np.arange(n_b - 1), indexing="ij")
    first = (a * n_b + b).ravel()
    return np.stack([first, first + n_b, first + n_b + 1, first + 1], axis=1)


def node_lines(points: np.ndarray, start: int, u: UnitSystem) -> Iterable[str]:
    """*NODE cards for ``points`` [m] numbered from ``start``."""
    for i, (x, y, z) in enumerate(points / u.length):
        yield card("NODE", 0, {"nid": start + i, "x": x, "y": y, "z": z})


def control_cards(setup: Any, end_time: float, u: UnitSystem,
                  mass_scaling_step: float | None = None) -> list[str]:  # fmt: skip
    """*CONTROL_* cards: end time, TSSFAC, hourglass, bulk viscosity and the contact SLSFAC of a
    test setup (ImpactSetup, CompressionSetup or BbsSetup); with ``mass_scaling_step`` [s,
    TSSFAC applied], mass scaling of the elements whose step is below it (DT2MS < 0).

    *CONTROL_HOURGLASS carries LS-DYNA's default (IHQ 1, QH 0.1): it governs every part without
    an HGID, which in a bat deck are the bat's shells. The ball's own control goes on its
    *HOURGLASS (:func:`part_cards`), so a stiffness-form ball does not change the bat."""
    bv = setup.bulk_viscosity
    q1, q2 = (bv.q1, bv.q2) if bv.enabled else (0.0, 0.0)
    step = {"dtinit": 0.0, "tssfac": setup.time_step_scale}
    default = HourglassControl()
    if mass_scaling_step is not None:
        step["dt2ms"] = -mass_scaling_step / setup.time_step_scale / u.time
    return [
        *keyword("CONTROL_TERMINATION", {"endtim": end_time / u.time}),
        *keyword("CONTROL_TIMESTEP", step),
        *keyword("CONTROL_HOURGLASS", {"ihq": default.type, "qh": default.coefficient}),
        *keyword("CONTROL_BULK_VISCOSITY", {"q1": q1, "q2": q2, "type": 1}),
        *keyword("CONTROL_CONTACT", {"slsfac": setup.contact.slsfac}),
    ]  # fmt: skip


def database_cards(u: UnitSystem, fine: float, coarse: float, plot: float) -> list[str]:
    """Histories the measurements need, every ``fine`` s: RCFORC (the load cells) and MATSUM (the
    ball's momentum and velocity); every ``coarse`` s: GLSTAT (energies); D3PLOT fields every
    ``plot`` s. (No NODOUT: it writes only the nodes a *DATABASE_HISTORY_NODE lists, and no
    measurement needs one.)"""
    fine, coarse, plot = fine / u.time, coarse / u.time, plot / u.time
    return [
        *keyword("DATABASE_GLSTAT", {"dt": coarse, "binary": 1}),
        *keyword("DATABASE_MATSUM", {"dt": fine, "binary": 1}),
        *keyword("DATABASE_RCFORC", {"dt": fine, "binary": 1}),
        *keyword("DATABASE_BINARY_D3PLOT", {"dt": plot}),
    ]


def part_cards(setup: Any, targets: tuple[str, ...]) -> list[str]:
    """Parts, sections and the *HOURGLASS card of the ball; one rigid part per target (2, 3..)."""
    rigid = [
        line
        for i, name in enumerate(targets)
        for line in keyword(
            "PART", {"heading": name}, {"pid": TARGET_PART + i, "secid": 2, "mid": TARGET_PART + i}
        )
    ]
    return [
        *keyword("PART", {"heading": "ball"}, {
            "pid": BALL_PART, "secid": 1, "mid": 1, "eosid": 0, "hgid": 1}),
        *keyword("SECTION_SOLID", {"secid": 1, "elform": 1}),
        *keyword("HOURGLASS", {
            "hgid": 1, "ihq": setup.hourglass.type, "qm": setup.hourglass.coefficient}),
        *rigid,
    ]  # fmt: skip


def target_cards(u: UnitSystem, con1: tuple[float, ...] = (7.0,)) -> list[str]:
    """*SECTION_SHELL, and a *MAT_RIGID per target (MID 2, 3, ..): CMO 1, rotations fixed
    (CON2 7), translations by ``con1`` (7 = fixed, 4 = x and y fixed: a platen moving in z)."""
    t = TARGET_THICKNESS / u.length
    e, nu, rho = STEEL
    lines = keyword("SECTION_SHELL", {"secid": 2, "elform": 2, "shrf": 0.8333, "nip": 2},
                    {"t1": t, "t2": t, "t3": t, "t4": t})  # fmt: skip
    for i, c1 in enumerate(con1):
        lines += keyword(
            "MAT_RIGID",
            {"mid": TARGET_PART + i, "ro": rho / u.density, "e": e / u.pressure, "pr": nu},
            {"cmo": 1.0, "con1": c1, "con2": 7.0},
            {"a1": 0.0},
        )
    return lines


def contact_cards(setup: Any, target_part: int = TARGET_PART) -> list[str]:
    """The ball (SURFA, part) against a target (SURFB, part), frictionless penalty."""
    c = setup.contact
    return keyword(
        "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE",
        {"surfa": BALL_PART, "surfb": target_part, "surfatyp": 3, "surfbtyp": 3},
        {"fs": 0.0, "fd": 0.0},
        {"sfsa": c.sfs, "sfsb": 1.0},
        {"soft": c.soft, "sofscl": c.sofscl},
    )


def impact_deck(
    ball: BallSpec, setup: ImpactSetup, units: str = "in-lbf-s", *, long: bool = False
) -> str:
    """The keyword deck of one ball-impact test, as text (``long``: 20-column fields, which keep
    every real to full double precision; standard 10-column reals keep 5 to 6 digits)."""
    token = _LONG.set(long)
    try:
        return _impact_deck(ball, setup, unit_system(units))
    finally:
        _LONG.reset(token)


def _impact_deck(ball: BallSpec, setup: ImpactSetup, u: UnitSystem) -> str:
    """The deck's text, in the format _LONG says."""
    setup = with_ball_hourglass(setup, ball)
    body = ball_body(ball, setup.divisions, setup.contact, setup.time_step_scale)
    target = make_target(setup, ball.radius)
    speed = setup.speed / u.velocity
    lines = header_lines(ball, setup, u)
    lines += keyword("TITLE", {"title": f"batball {setup.test} ball {ball.name} ({u.name})"})
    lines += control_cards(setup, setup.end_time, u) + database_cards(u, 1e-6, 1e-5, 1e-4)
    lines += part_cards(setup, (f"rigid {setup.test} target",))
    lines += material_cards(ball, body.density, u) + target_cards(u)
    lines += mesh_lines(body.mesh.points, body.mesh.cells, [target_shells(target, ball.radius)], u)
    lines += keyword(
        "INITIAL_VELOCITY_GENERATION",
        {"id": BALL_PART, "styp": 2, "omega": 0.0, "vx": 0.0, "vy": 0.0, "vz": -speed},
        {"xc": 0.0, "yc": 0.0, "zc": 0.0},
    )
    lines += contact_cards(setup)
    lines.append("*END")
    return "\n".join(lines) + "\n"


def mesh_lines(
    points: np.ndarray,
    cells: np.ndarray,
    shells: list[tuple[np.ndarray, np.ndarray]],
    u: UnitSystem,
) -> list[str]:
    """*NODE, *ELEMENT_SOLID (ball, part 1, ids from 1) and *ELEMENT_SHELL (target i: part 2 + i,
    node and element ids from 1,000,001 + 100,000 i; none without targets)."""
    lines = ["*NODE", head("NODE", 0), *node_lines(points, 1, u), *target_node_lines(shells, u)]
    lines += ["*ELEMENT_SOLID", head("ELEMENT_SOLID", 0)]
    for i, cell in enumerate(cells):
        nodes = {f"n{k + 1}": int(n) + 1 for k, n in enumerate(cell)}
        lines.append(card("ELEMENT_SOLID", 0, {"eid": i + 1, "pid": BALL_PART, **nodes}))
    return lines + target_element_lines(shells)


def target_node_lines(shells: list[tuple[np.ndarray, np.ndarray]], u: UnitSystem) -> list[str]:
    """*NODE cards of rigid target i's shell nodes [m], ids from 1,000,001 + 100,000 i."""
    return [line for i, (points, _) in enumerate(shells)
            for line in node_lines(points, TARGET_NODE_START + 100_000 * i, u)]  # fmt: skip


def target_element_lines(shells: list[tuple[np.ndarray, np.ndarray]]) -> list[str]:
    """*ELEMENT_SHELL of rigid target i (part 2 + i, element ids from 1,000,001 + 100,000 i);
    nothing without targets."""
    if not shells:
        return []
    lines = ["*ELEMENT_SHELL", head("ELEMENT_SHELL", 0)]
    for t, (_, quads) in enumerate(shells):
        start = TARGET_NODE_START + 100_000 * t
        for i, quad in enumerate(quads):
            nodes = {f"n{k + 1}": int(n) + start for k, n in enumerate(quad)}
            eid = TARGET_ELEMENT_START + 100_000 * t + i
            lines.append(card("ELEMENT_SHELL", 0, {"eid": eid, "pid": TARGET_PART + t, **nodes}))
    return lines


def header_lines(ball: BallSpec, setup: ImpactSetup, u: UnitSystem) -> list[str]:
    """Comment lines saying what the deck is, its units and where each measurement is read."""
    return [
        f"$ batball {__version__}: {setup.test} test of ball '{ball.name}' at "
        f"{setup.speed / MPH:.6g} mph, {setup.divisions} divisions",
        f"$ units {u.name}: {u.description}",
        "$ part 1 = ball (moving along -z), part 2 = rigid target (fixed)",
        "$ CCOR/COR = part 1 z-velocity after separation (MATSUM) / inbound speed;",
        "$ peak force and contact time from RCFORC (1 % of peak); DS = F^2/(m v^2)",
        "*KEYWORD LONG=Y" if _LONG.get() else "*KEYWORD",
    ]


def write_impact_deck(
    path: str, ball: BallSpec, setup: Any, units: str, *, long: bool = False
) -> int:
    """Write the deck of an ImpactSetup or CompressionSetup to ``path``; returns its lines."""
    from pathlib import Path

    if isinstance(setup, CompressionSetup):
        text = compression_deck(ball, setup, units, long=long)
    else:
        text = impact_deck(ball, setup, units, long=long)
    Path(path).write_text(text, encoding="ascii")
    return text.count("\n")


def compression_deck(
    ball: BallSpec, setup: CompressionSetup, units: str = "in-lbf-s", *, long: bool = False
) -> str:
    """The keyword deck of the F1888 compression test as batball runs it: the mass-scaled ball
    (RO = s x density, stated in the header) between a fixed bottom plate (part 3) and a top
    plate (part 2) moving down at the test rate (*BOUNDARY_PRESCRIBED_MOTION_RIGID, velocity,
    with a constant *DEFINE_CURVE), and batball's mass-proportional damping as *DAMPING_GLOBAL
    (force -VALDMP m v, the same law)."""
    token = _LONG.set(long)
    try:
        return _compression_deck(ball, setup, unit_system(units))
    finally:
        _LONG.reset(token)


def _compression_deck(ball: BallSpec, setup: CompressionSetup, u: UnitSystem) -> str:
    """The compression deck's text."""
    setup = with_ball_hourglass(setup, ball)
    model, scale, damping = build_compression_model(ball, setup)
    top, bottom = (c.target for c in model.contacts)
    end = TRAVEL_MARGIN * setup.displacement / setup.rate
    shells = [target_shells(top, ball.radius), target_shells(bottom, ball.radius)]
    lines = [
        f"$ batball {__version__}: compression (ASTM F1888) of ball '{ball.name}', "
        f"{setup.divisions} divisions, plate {setup.rate / IN * 60:.6g} in/min",
        f"$ units {u.name}: {u.description}",
        f"$ RO is mass-scaled by s = {scale:.6g} (batball quasi-static plan, "
        "docs/notes/compression.md)",
        "$ part 1 = ball, part 2 = top plate (moves -z), part 3 = bottom plate (fixed)",
        f"$ compression = mean plate force (RCFORC) at {setup.displacement / IN:.6g} in of ball "
        "deformation (plate travel minus penetrations)",
        "*KEYWORD LONG=Y" if _LONG.get() else "*KEYWORD",
        *keyword("TITLE", {"title": f"batball compression ball {ball.name} ({u.name})"}),
        *control_cards(setup, end, u),
        *database_cards(u, end / 2000, end / 200, end / 20),
        *part_cards(setup, ("rigid top plate", "rigid bottom plate")),
        *material_cards(ball, float(model.densities[0]), u),
        *target_cards(u, con1=(4.0, 7.0)),
        *mesh_lines(model.mesh.points, model.mesh.cells, shells, u),
        *keyword("DEFINE_CURVE", {"lcid": 1}),
        card("DEFINE_CURVE", 1, {"a1": 0.0, "o1": 1.0}),
        card("DEFINE_CURVE", 1, {"a1": 2 * end / u.time, "o1": 1.0}),
        *keyword("BOUNDARY_PRESCRIBED_MOTION_RIGID", {
            "pid": TARGET_PART, "dof": 3, "vad": 0, "lcid": 1, "sf": -setup.rate / u.velocity}),
        *keyword("DAMPING_GLOBAL", {"lcid": 0, "valdmp": damping * u.time}),
        *contact_cards(setup, TARGET_PART),
        *contact_cards(setup, TARGET_PART + 1),
        "*END",
    ]  # fmt: skip
    return "\n".join(lines) + "\n"
