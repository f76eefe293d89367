"""Each keyword of an exported deck, checked column by column against the manual's card layout.

The column ranges below are typed from the cited layouts (LS-DYNA Keyword User's Manual Vol I,
as transcribed in ansys/pydyna's generated keyword classes: field start column and width; *NODE
also on Altair's node_lsdyna_r page): 1-based, inclusive. They are written here independently of
``batball.lsdyna.cards.LAYOUTS``. Each test checks that no number straddles a field boundary
and that the fields hold the model's values, read at those columns, in the deck's in-lbf-s units
(1 in = 0.0254 m, 1 lbf = 4.4482216152605 N, 1 psi = 6894.757 Pa).
"""

from __future__ import annotations

import numpy as np
import pytest

from batball.lsdyna.export import impact_deck
from batball.models.ball import ball_body
from batball.models.impact import ImpactSetup, make_target
from batball.specs import load_ball_spec

IN, LBF, MPH = 0.0254, 4.4482216152605, 0.44704
PSI = LBF / IN**2


def tens(*names: str) -> dict[str, tuple[int, int]]:
    """Standard 10-column fields in order: name -> (first column, last column)."""
    return {name: (10 * i + 1, 10 * i + 10) for i, name in enumerate(names)}


def eights(*names: str) -> dict[str, tuple[int, int]]:
    """8-column integer fields in order."""
    return {name: (8 * i + 1, 8 * i + 8) for i, name in enumerate(names)}


NODE = {"nid": (1, 8), "x": (9, 24), "y": (25, 40), "z": (41, 56), "tc": (57, 64), "rc": (65, 72)}


@pytest.fixture(scope="module")
def deck() -> dict[str, list[list[str]]]:
    """The coarse ccor deck of ball type1 at 95 mph, as {keyword: [[data lines], ...]}."""
    return blocks(impact_deck(load_ball_spec("type1"), ImpactSetup("ccor", 95 * MPH, divisions=2)))


def blocks(text: str) -> dict[str, list[list[str]]]:
    """{keyword: [[data lines of each occurrence], ...]} of a deck's text ($ lines skipped)."""
    out: dict[str, list[list[str]]] = {}
    current: list[str] = []
    for line in text.splitlines():
        if line.startswith("$"):
            continue
        if line.startswith("*"):
            current = []
            out.setdefault(line[1:].strip(), []).append(current)
        else:
            current.append(line)
    return out


def read(line: str, layout: dict[str, tuple[int, int]]) -> dict[str, str]:
    """The stripped text of each field; every non-blank run lies inside one field."""
    bounds = sorted(layout.values())
    for start in range(len(line)):
        if line[start] != " " and (start == 0 or line[start - 1] == " "):
            end = start
            while end + 1 < len(line) and line[end + 1] != " ":
                end += 1
            inside = [a <= start + 1 and end + 1 <= b for a, b in bounds]
            assert any(inside), f"{line!r}: text at columns {start + 1}-{end + 1} straddles fields"
    return {name: line[a - 1 : b].strip() for name, (a, b) in layout.items()}


def num(text: str) -> float:
    """A field's number (blank = 0)."""
    return float(text) if text else 0.0


def test_node_columns(deck: dict[str, list[list[str]]]) -> None:
    body = ball_body(load_ball_spec("type1"), 2, ImpactSetup("ccor", 1.0).contact, 0.9)
    first = read(deck["NODE"][0][0], NODE)
    assert int(first["nid"]) == 1
    xyz = [num(first[k]) for k in "xyz"]
    np.testing.assert_allclose(xyz, body.mesh.points[0] / IN, rtol=1e-12, atol=1e-12)


def test_element_solid_columns(deck: dict[str, list[list[str]]]) -> None:
    body = ball_body(load_ball_spec("type1"), 2, ImpactSetup("ccor", 1.0).contact, 0.9)
    f = read(deck["ELEMENT_SOLID"][0][0], eights("eid", "pid", *(f"n{i}" for i in range(1, 9))))
    assert (int(f["eid"]), int(f["pid"])) == (1, 1)
    assert [int(f[f"n{i}"]) for i in range(1, 9)] == list(body.mesh.cells[0] + 1)


def test_element_shell_columns(deck: dict[str, list[list[str]]]) -> None:
    f = read(deck["ELEMENT_SHELL"][0][0], eights("eid", "pid", "n1", "n2", "n3", "n4"))
    assert int(f["pid"]) == 2
    assert len({f["n1"], f["n2"], f["n3"], f["n4"]}) == 4


def test_part_columns(deck: dict[str, list[list[str]]]) -> None:
    ball, target = deck["PART"]
    assert ball[0].strip() == "ball"
    f = read(ball[1], tens("pid", "secid", "mid", "eosid", "hgid", "grav", "adpopt", "tmid"))
    assert [int(num(f[k])) for k in ("pid", "secid", "mid", "hgid")] == [1, 1, 1, 1]
    g = read(target[1], tens("pid", "secid", "mid"))
    assert [int(num(g[k])) for k in ("pid", "secid", "mid")] == [2, 2, 2]


def test_section_columns(deck: dict[str, list[list[str]]]) -> None:
    f = read(deck["SECTION_SOLID"][0][0], tens("secid", "elform", "aet"))
    assert (int(f["secid"]), int(f["elform"])) == (1, 1)
    shell = deck["SECTION_SHELL"][0]
    g = read(shell[0], tens("secid", "elform", "shrf", "nip", "propt", "qr", "icomp", "setyp"))
    assert (int(g["secid"]), int(g["elform"]), int(g["nip"])) == (2, 2, 2)
    t = read(shell[1], tens("t1", "t2", "t3", "t4"))
    assert [num(t[k]) for k in ("t1", "t2", "t3", "t4")] == [0.05] * 4


def test_mat_viscoelastic_columns(deck: dict[str, list[list[str]]]) -> None:
    ball = load_ball_spec("type1")
    body = ball_body(ball, 2, ImpactSetup("ccor", 1.0).contact, 0.9)
    f = read(deck["MAT_VISCOELASTIC"][0][0], tens("mid", "ro", "bulk", "g0", "gi", "beta"))
    v = ball.material.values
    assert int(f["mid"]) == 1
    # 10 columns hold 5 significant digits at worst: 1e-4 relative
    assert num(f["ro"]) == pytest.approx(body.density / (LBF / IN**4), rel=1e-4)
    assert num(f["bulk"]) == pytest.approx(v["bulk_modulus"] / PSI, rel=1e-4)
    assert num(f["g0"]) == pytest.approx(v["g0"] / PSI, rel=1e-4)
    assert num(f["gi"]) == pytest.approx(v["g_inf"] / PSI, rel=1e-4)
    assert num(f["beta"]) == pytest.approx(v["beta"], rel=1e-4)


def test_mat_rigid_columns(deck: dict[str, list[list[str]]]) -> None:
    card1, card2, _ = deck["MAT_RIGID"][0]
    f = read(card1, tens("mid", "ro", "e", "pr", "n", "couple", "m", "alias"))
    assert int(f["mid"]) == 2
    assert num(f["e"]) == pytest.approx(200e9 / PSI, rel=1e-4)  # steel, psi
    assert num(f["pr"]) == 0.3
    g = read(card2, tens("cmo", "con1", "con2"))
    assert [num(g[k]) for k in ("cmo", "con1", "con2")] == [1.0, 7.0, 7.0]


def test_hourglass_columns(deck: dict[str, list[list[str]]]) -> None:
    f = read(deck["HOURGLASS"][0][0], tens("hgid", "ihq", "qm", "ibq", "q1", "q2", "qb", "qw"))
    assert (int(f["hgid"]), int(f["ihq"]), num(f["qm"])) == (1, 1, 0.1)
    g = read(deck["CONTROL_HOURGLASS"][0][0], tens("ihq", "qh"))
    assert (int(g["ihq"]), num(g["qh"])) == (1, 0.1)


def test_control_columns(deck: dict[str, list[list[str]]]) -> None:
    term = read(deck["CONTROL_TERMINATION"][0][0], tens("endtim", "endcyc", "dtmin"))
    assert num(term["endtim"]) == 4e-3
    step = read(deck["CONTROL_TIMESTEP"][0][0], tens("dtinit", "tssfac", "isdo"))
    assert num(step["tssfac"]) == 0.9
    bulk = read(deck["CONTROL_BULK_VISCOSITY"][0][0], tens("q1", "q2", "type"))
    assert (num(bulk["q1"]), num(bulk["q2"]), int(bulk["type"])) == (1.5, 0.06, 1)
    contact = read(deck["CONTROL_CONTACT"][0][0], tens("slsfac", "rwpnal", "islchk", "shlthk"))
    assert num(contact["slsfac"]) == 0.1


def test_database_columns(deck: dict[str, list[list[str]]]) -> None:
    assert "DATABASE_NODOUT" not in deck  # it would write nothing without a history node list
    for name, dt in (("GLSTAT", 1e-5), ("MATSUM", 1e-6), ("RCFORC", 1e-6)):
        f = read(deck[f"DATABASE_{name}"][0][0], tens("dt", "binary", "lcur", "ioopt"))
        assert (num(f["dt"]), int(f["binary"])) == (dt, 1), name
    d3 = read(deck["DATABASE_BINARY_D3PLOT"][0][0], tens("dt", "lcdt", "beam", "npltc"))
    assert num(d3["dt"]) == 1e-4


def test_initial_velocity_generation_columns(deck: dict[str, list[list[str]]]) -> None:
    card1, _ = deck["INITIAL_VELOCITY_GENERATION"][0]
    f = read(card1, tens("id", "styp", "omega", "vx", "vy", "vz", "ivatn", "icid"))
    assert (int(f["id"]), int(f["styp"]), num(f["omega"])) == (1, 2, 0.0)
    assert (num(f["vx"]), num(f["vy"]), num(f["vz"])) == (0.0, 0.0, -1672.0)  # 95 mph in in/s


def test_contact_columns(deck: dict[str, list[list[str]]]) -> None:
    cards = deck["CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"][0]
    c1 = read(cards[0], tens("surfa", "surfb", "surfatyp", "surfbtyp", "saboxid", "sbboxid"))
    assert [int(c1[k]) for k in ("surfa", "surfb", "surfatyp", "surfbtyp")] == [1, 2, 3, 3]
    c2 = read(cards[1], tens("fs", "fd", "dc", "vc", "vdc", "penchk", "bt", "dt"))
    assert (num(c2["fs"]), num(c2["fd"])) == (0.0, 0.0)
    c3 = read(cards[2], tens("sfsa", "sfsb", "sast", "sbst"))
    assert num(c3["sfsa"]) == 1.0
    ca = read(cards[3], tens("soft", "sofscl", "lcidab", "maxpar"))
    assert (int(ca["soft"]), num(ca["sofscl"])) == (0, 0.1)


def test_title_and_target_geometry(deck: dict[str, list[list[str]]]) -> None:
    assert "ccor" in deck["TITLE"][0][0]
    # the shells' mid-surface lies half the 0.05-in thickness behind the 2.63-in cylinder face
    target = make_target(ImpactSetup("ccor", 1.0), load_ball_spec("type1").radius)
    rows = [read(line, NODE) for line in deck["NODE"][0]]
    shell = np.array([[num(r[k]) for k in "xyz"] for r in rows if int(r["nid"]) > 10**6])
    axis_z = target.axis_point[2] / IN
    radius = np.hypot(shell[:, 1], shell[:, 2] - axis_z)
    np.testing.assert_allclose(radius, 2.63 / 2 - 0.025, rtol=1e-9)


def test_compression_keywords_columns() -> None:
    """The compression deck's own keywords: *DEFINE_CURVE (header in 10 columns, points in two
    20-column fields), *BOUNDARY_PRESCRIBED_MOTION_RIGID, *DAMPING_GLOBAL, and the moving
    plate's *MAT_RIGID (CON1 4: x, y fixed)."""
    from batball.lsdyna.export import compression_deck
    from batball.models.compression import CompressionSetup, build_compression_model

    ball = load_ball_spec("type1")
    setup = CompressionSetup(divisions=2)
    text = compression_deck(ball, setup)
    blocks: dict[str, list[list[str]]] = {}
    current: list[str] = []
    for line in text.splitlines():
        if line.startswith("*"):
            current = []
            blocks.setdefault(line[1:].strip(), []).append(current)
        elif not line.startswith("$"):
            current.append(line)
    header, *points = blocks["DEFINE_CURVE"][0]
    assert int(read(header, tens("lcid", "sidr", "sfa", "sfo"))["lcid"]) == 1
    for p in points:
        assert num(read(p, {"a1": (1, 20), "o1": (21, 40)})["o1"]) == 1.0
    f = read(blocks["BOUNDARY_PRESCRIBED_MOTION_RIGID"][0][0],
             tens("pid", "dof", "vad", "lcid", "sf", "vid", "death", "birth"))  # fmt: skip
    assert [int(f[k]) for k in ("pid", "dof", "vad", "lcid")] == [2, 3, 0, 1]
    assert num(f["sf"]) == pytest.approx(-1.0 / 60.0, rel=1e-4)  # 1 in/min in in/s
    _, _, damping = build_compression_model(ball, setup)
    d = read(blocks["DAMPING_GLOBAL"][0][0], tens("lcid", "valdmp", "stx", "sty", "stz"))
    assert (int(d["lcid"]), num(d["valdmp"])) == (0, pytest.approx(damping, rel=1e-4))
    top = read(blocks["MAT_RIGID"][0][1], tens("cmo", "con1", "con2"))
    assert [num(top[k]) for k in ("cmo", "con1", "con2")] == [1.0, 4.0, 7.0]
