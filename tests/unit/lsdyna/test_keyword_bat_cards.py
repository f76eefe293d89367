"""Each keyword the bat decks add, checked column by column against the manual's card layout.

The column ranges are typed here from the cited transcriptions of the LS-DYNA Keyword User's
Manual Vol I (ansys/pydyna's generated keyword classes, auto/<group>/<keyword>.py: each field's
start column and width), independently of ``batball.lsdyna.cards.LAYOUTS``: *PART_COMPOSITE
(part/part_composite.py), *MAT_COMPOSITE_DAMAGE (mat/mat_composite_damage.py),
*CONTROL_IMPLICIT_GENERAL, *CONTROL_IMPLICIT_EIGENVALUE, *CONTROL_DYNAMIC_RELAXATION
(control/...), *CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET and
*CONTACT_SURFACE_TO_SURFACE_INTERFERENCE (contact/...), *BOUNDARY_SPC_SET (boundary/...),
*CONSTRAINED_NODAL_RIGID_BODY_SPC (constrained/...). The values are checked against the default
bat spec's TOML numbers (specs/data/default_bat.toml) in in-lbf-s units (1 in = 0.0254 m,
1 lbf = 4.4482216152605 N, 1 psi = 6894.757 Pa, 1 oz = 0.028349523125 kg).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_keyword_cards import blocks, num, read, tens

from batball.lsdyna.bat import barrel_deck, bbs_deck, modal_deck
from batball.mesh.bat import make_bat_mesh
from batball.mesh.shell import quad_areas
from batball.models.barrel import BarrelTestOptions
from batball.models.bbs import BbsSetup
from batball.specs import load_ball_spec
from batball.specs.bat import load_bat_spec

IN, LBF, OZ = 0.0254, 4.4482216152605, 0.028349523125
PSI = LBF / IN**2
MESH = {"circumferential": 8, "axial_size": 1.0 * IN}


@pytest.fixture(scope="module")
def modal() -> dict[str, list[list[str]]]:
    return blocks(modal_deck(load_bat_spec("default"), n_modes=12, **MESH))


@pytest.fixture(scope="module")
def barrel() -> dict[str, list[list[str]]]:
    return blocks(barrel_deck(load_bat_spec("default"), BarrelTestOptions(), **MESH))


@pytest.fixture(scope="module")
def bbs() -> dict[str, list[list[str]]]:
    setup = BbsSetup(ball_divisions=2, pivot_band=1.0 * IN, **MESH)
    return blocks(bbs_deck(load_bat_spec("default"), load_ball_spec("type1"), setup))


def test_part_composite_columns(modal: dict[str, list[list[str]]]) -> None:
    title, pid_card, *layers = modal["PART_COMPOSITE"][0]
    assert title.strip() == "knob"
    f = read(pid_card, tens("pid", "elform", "shrf", "nloc", "marea", "hgid", "adpopt", "thshel"))
    assert (int(f["pid"]), int(f["elform"])) == (101, 16)
    assert num(f["shrf"]) == pytest.approx(5 / 6, rel=1e-6)
    # MAREA: the knob's 1.0 oz spread over its mesh area, lbf s^2/in per in^2
    mesh = make_bat_mesh(load_bat_spec("default"), **MESH)
    area = quad_areas(mesh.points, mesh.cells)[mesh.cell_sets["knob"]].sum() / IN**2
    assert num(f["marea"]) == pytest.approx(1.0 * OZ / (LBF / IN) / area, rel=1e-4)
    g = read(layers[0], tens("mid1", "thick1", "b1", "tmid1", "mid2", "thick2", "b2", "tmid2"))
    # first ply: glass 0.012 in braided at 45 deg -> +45 at t/6, -45 at t/4
    assert (num(g["thick1"]), num(g["b1"])) == (pytest.approx(0.002), 45.0)
    assert (num(g["thick2"]), num(g["b2"])) == (pytest.approx(0.003), -45.0)
    assert g["mid1"] == g["mid2"] and g["tmid1"] == g["tmid2"] == ""
    # 3 braided plies = 15 layers, two a card
    assert len(layers) == 8 and read(layers[-1], tens("mid1", "thick1", "b1"))["b1"] == "30"


def test_mat_composite_damage_columns(modal: dict[str, list[list[str]]]) -> None:
    by_ea = {}
    for c1, c2, c3, c4, c5 in modal["MAT_COMPOSITE_DAMAGE"]:
        f = read(c1, tens("mid", "ro", "ea", "eb", "ec", "prba", "prca", "prcb"))
        by_ea[round(num(f["ea"]) * PSI / 1e9)] = (f, c2, c3, c4, c5)
    f, c2, _, c4, c5 = by_ea[41]  # glass
    assert num(f["ro"]) == pytest.approx(1970.0 / (LBF / IN**4), rel=1e-4)
    assert num(f["eb"]) * PSI == pytest.approx(10.4e9, rel=1e-4)
    assert num(f["prba"]) == pytest.approx(0.07102, rel=1e-4)
    g = read(c2, tens("gab", "gbc", "gca", "kfail", "aopt", "macf", "atrack"))
    assert [num(g[k]) * PSI / 1e9 for k in ("gab", "gbc", "gca")] == pytest.approx([4.3, 3.5, 4.3])
    assert (num(g["aopt"]), int(g["macf"])) == (0.0, 1)
    assert num(read(c4, tens("v1", "v2", "v3", "d1", "d2", "d3", "beta"))["beta"]) == 0.0
    s = read(c5, tens("sc", "xt", "yt", "yc", "alph", "sn", "syz", "szx"))
    assert num(s["xt"]) == num(s["sc"]) == 1e20 and s["alph"] == ""


def test_implicit_controls_columns(modal: dict[str, list[list[str]]]) -> None:
    g = read(modal["CONTROL_IMPLICIT_GENERAL"][0][0],
             tens("imflag", "dt0", "imform", "nsbs", "igs", "cnstn", "form", "zero_v"))  # fmt: skip
    assert int(g["imflag"]) == 1
    e = read(
        modal["CONTROL_IMPLICIT_EIGENVALUE"][0][0],
        tens("neig", "center", "lflag", "lftend", "rflag", "rhtend", "eigmth", "shfscl"),
    )
    assert int(e["neig"]) == 12 and e["eigmth"] == "" and e["center"] == ""
    assert num(read(modal["CONTROL_TERMINATION"][0][0], tens("endtim"))["endtim"]) == 0.0


def test_tied_contact_columns(modal: dict[str, list[list[str]]]) -> None:
    c1, _, _ = modal["CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET"][0]
    f = read(c1, tens("surfa", "surfb", "surfatyp", "surfbtyp"))
    assert [int(f[k]) for k in ("surfa", "surfb", "surfatyp", "surfbtyp")] == [111, 1, 3, 2]
    part_set = read(modal["SET_PART_LIST"][0][1], tens(*(f"pid{i}" for i in range(1, 9))))
    assert [int(v) for v in part_set.values()] == list(range(101, 109))  # outer parts 101..110


def test_interference_contact_and_relaxation_columns(barrel: dict[str, list[list[str]]]) -> None:
    c1, _, _, c4 = barrel["CONTACT_SURFACE_TO_SURFACE_INTERFERENCE"][0]
    f = read(c1, tens("surfa", "surfb", "surfatyp", "surfbtyp"))
    assert [int(f[k]) for k in ("surfa", "surfb", "surfatyp", "surfbtyp")] == [111, 1, 3, 2]
    g = read(c4, tens("lcid1", "lcid2"))
    curves = {int(read(c[0], tens("lcid", "sidr"))["lcid"]): c for c in barrel["DEFINE_CURVE"]}
    ramp, full = curves[int(g["lcid1"])], curves[int(g["lcid2"])]
    assert read(ramp[0], tens("lcid", "sidr"))["sidr"] == "1"  # active in relaxation only
    points = {"a1": (1, 20), "o1": (21, 40)}
    assert [num(read(p, points)["o1"]) for p in ramp[1:]] == [0.0, 1.0]
    assert [num(read(p, points)["o1"]) for p in full[1:]] == [1.0, 1.0]
    d = read(
        barrel["CONTROL_DYNAMIC_RELAXATION"][0][0],
        tens("nrcyck", "drtol", "drfctr", "drterm", "tssfdr", "irelal", "edttl", "idrflg"),
    )
    assert (int(d["nrcyck"]), num(d["drtol"]), num(d["drfctr"])) == (250, 0.001, 0.995)


def test_spc_and_platen_motion_columns(barrel: dict[str, list[list[str]]]) -> None:
    spcs = [read(c[0], tens("nsid", "cid", "dofx", "dofy", "dofz", "dofrx", "dofry", "dofrz"))
            for c in barrel["BOUNDARY_SPC_SET"]]  # fmt: skip
    assert [(s["nsid"], s["dofx"], s["dofz"]) for s in spcs] == [("1", "1", ""), ("2", "", "1")]
    m = read(barrel["BOUNDARY_PRESCRIBED_MOTION_RIGID"][0][0],
             tens("pid", "dof", "vad", "lcid", "sf", "vid", "death", "birth"))  # fmt: skip
    assert [int(m[k]) for k in ("pid", "dof", "vad")] == [2, 2, 2]  # y displacement
    assert num(m["sf"]) == -1.0
    rigid = read(barrel["MAT_RIGID"][0][1], tens("cmo", "con1", "con2"))
    assert [num(rigid[k]) for k in ("cmo", "con1", "con2")] == [1.0, 6.0, 7.0]  # free in y


def test_nodal_rigid_body_columns(bbs: dict[str, list[list[str]]]) -> None:
    c1, c2 = bbs["CONSTRAINED_NODAL_RIGID_BODY_SPC"][0]
    f = read(c1, tens("pid", "cid", "nsid", "pnode", "iprt", "drflag", "rrflag"))
    assert (int(f["pid"]), int(f["nsid"])) == (900, 3)
    g = read(c2, tens("cmo", "con1", "con2"))
    assert [num(g[k]) for k in ("cmo", "con1", "con2")] == [1.0, 7.0, 4.0]
    v = read(
        bbs["INITIAL_VELOCITY_GENERATION"][0][0], tens("id", "styp", "omega", "vx", "vy", "vz")
    )
    assert num(v["vy"]) == pytest.approx(-110 * 0.44704 / IN, rel=1e-5)  # 110 mph along -y
    assert np.isclose(num(v["vx"]), 0.0)


def test_stiffness_form_ball_leaves_the_bat_shells_at_the_default() -> None:
    """A ball whose model names IHQ 4 writes it on its own *HOURGLASS (HGID 1); the bat's shells
    (no HGID) take *CONTROL_HOURGLASS, which stays at LS-DYNA's default IHQ 1, QH 0.1 (Keyword
    Manual Vol I, *CONTROL_HOURGLASS defaults), whatever the ball."""
    import dataclasses

    from batball.specs.ball import BallHourglass

    ball = dataclasses.replace(load_ball_spec("type1"),
                               hourglass=BallHourglass(type=4, coefficient=0.01))  # fmt: skip
    setup = BbsSetup(ball_divisions=2, pivot_band=1.0 * IN, **MESH)
    deck = blocks(bbs_deck(load_bat_spec("default"), ball, setup))
    hg = read(deck["HOURGLASS"][0][0], tens("hgid", "ihq", "qm"))
    assert (int(hg["hgid"]), int(hg["ihq"]), num(hg["qm"])) == (1, 4, 0.01)
    glob = read(deck["CONTROL_HOURGLASS"][0][0], tens("ihq", "qh"))
    assert (int(glob["ihq"]), num(glob["qh"])) == (1, 0.1)
