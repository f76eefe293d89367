"""The keyword reader: fixed, free and long format, comments, *INCLUDE, and clear errors.

Expected values are the numbers typed into the small decks below (Keyword Manual Vol I, "General
card format": fixed columns, comma-separated free format, '$' comments, long format 20 columns).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.errors import SpecError
from batball.lsdyna.deck import read_keyword_file, split_fields
from batball.lsdyna.export import impact_deck
from batball.lsdyna.model import parse_deck, read_deck
from batball.models.impact import ImpactSetup, build_impact_model, make_target
from batball.specs import load_ball_spec

MPH = 0.44704


def write(folder: Path, name: str, text: str) -> Path:
    """Write a deck file and return its path."""
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def node(path: Path) -> dict[int, tuple[float, float, float]]:
    """The nodes of a deck."""
    return parse_deck(path).nodes


def test_fixed_and_free_format_give_the_same_node(tmp_path: Path) -> None:
    fixed = write(
        tmp_path,
        "a.k",
        "*KEYWORD\n*NODE\n      12        1.25e-3           -2.5            3.0\n*END\n",
    )
    free = write(tmp_path, "b.k", "*KEYWORD\n*NODE\n12, 1.25e-3, -2.5, 3.0\n*END\n")
    assert node(fixed) == node(free) == {12: (1.25e-3, -2.5, 3.0)}


def test_comments_and_lines_after_end_are_ignored(tmp_path: Path) -> None:
    path = write(
        tmp_path, "c.k",
        "$ header\n*KEYWORD\n*NODE\n$ nid x y z\n       1            1.0\n*END\n*NODE\n2,9,9,9\n",
    )  # fmt: skip
    assert node(path) == {1: (1.0, 0.0, 0.0)}


def test_long_format_suffix_and_fortran_exponent(tmp_path: Path) -> None:
    line = "7".rjust(20) + "1.5-3".rjust(20) + "2.0".rjust(20) + "-4.".rjust(20)
    path = write(tmp_path, "d.k", f"*KEYWORD\n*NODE +\n{line}\n*END\n")
    assert node(path) == {7: (1.5e-3, 2.0, -4.0)}


def test_include_is_read_relative_to_the_including_file(tmp_path: Path) -> None:
    write(tmp_path, "mesh/nodes.k", "*KEYWORD\n*NODE\n3,1,2,3\n*END\n")
    main = write(tmp_path, "main.k", "*KEYWORD\n*INCLUDE\nmesh/nodes.k\n*NODE\n4,5,6,7\n*END\n")
    assert node(main) == {3: (1.0, 2.0, 3.0), 4: (5.0, 6.0, 7.0)}


def test_missing_include_names_the_file_and_line(tmp_path: Path) -> None:
    main = write(tmp_path, "main.k", "*KEYWORD\n*INCLUDE\nnowhere.k\n*END\n")
    with pytest.raises(SpecError, match=r"main\.k:3.*nowhere\.k"):
        read_keyword_file(main)


def test_unsupported_keyword_names_keyword_file_and_line(tmp_path: Path) -> None:
    path = write(
        tmp_path, "e.k", "*KEYWORD\n$ a comment\n*NODE\n1,0,0,0\n*BOUNDARY_SPC_NODE\n1,0\n"
    )
    with pytest.raises(SpecError, match=r"\*BOUNDARY_SPC_NODE at .*e\.k:5.*unsupported"):
        parse_deck(path)


def test_unreadable_number_names_field_and_line(tmp_path: Path) -> None:
    path = write(tmp_path, "f.k", "*KEYWORD\n*NODE\n1, 0.0, abc, 0.0\n")
    with pytest.raises(SpecError, match=r"\*NODE\.Y at .*f\.k:3"):
        parse_deck(path)


def test_unhonoured_field_is_an_error_not_a_silent_drop(tmp_path: Path) -> None:
    path = write(
        tmp_path, "g.k",
        "*KEYWORD\n*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n1,2,3,3\n0.2\n1.0,1.0\n",
    )  # fmt: skip
    with pytest.raises(SpecError, match=r"FS at .*g\.k:2.*no such feature"):
        parse_deck(path)


def test_two_card_element_solid(tmp_path: Path) -> None:
    one = "*ELEMENT_SOLID\n" + "".join(str(v).rjust(8) for v in (5, 1, *range(1, 9))) + "\n"
    two = "*ELEMENT_SOLID\n       5       1\n" + "".join(str(v).rjust(8) for v in range(1, 9))
    a = parse_deck(write(tmp_path, "h1.k", one)).solids[0][:3]
    b = parse_deck(write(tmp_path, "h2.k", two + "\n")).solids[0][:3]
    assert a == b == (5, 1, list(range(1, 9)))


def test_free_format_split_keeps_field_order(tmp_path: Path) -> None:
    path = write(
        tmp_path, "i.k", "*KEYWORD\n*MAT_VISCOELASTIC\n3, 1.1e-4, 8e5, 2.25e4, 750, 75000\n"
    )
    block = read_keyword_file(path)[1]
    f = split_fields(block.cards[0], block.name, 0, block.long)
    assert (f["mid"], f["ro"], f["bulk"], f["g0"], f["gi"], f["beta"]) == (
        3, 1.1e-4, 8e5, 2.25e4, 750.0, 75000.0,
    )  # fmt: skip


@pytest.mark.parametrize("units", ["in-lbf-s", "m-N-s", "mm-N-ms"])
def test_deck_reads_back_to_the_direct_model(units: str, tmp_path: Path) -> None:
    """Export then read, in each unit system: the same mesh, material, velocity and target as
    build_impact_model (reals in 10 columns keep 5 significant digits: 1e-4 relative)."""
    ball = load_ball_spec("type1")
    setup = ImpactSetup("ccor", 95 * MPH, divisions=2)
    path = write(tmp_path, "ccor.k", impact_deck(ball, setup, units))
    direct = build_impact_model(ball, setup)
    read = read_deck(path, units=units).model
    np.testing.assert_allclose(read.mesh.points, direct.mesh.points, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(read.mesh.cells, direct.mesh.cells)
    np.testing.assert_allclose(read.material_constants, direct.material_constants, rtol=1e-4)
    np.testing.assert_allclose(read.densities, direct.densities, rtol=1e-4)
    np.testing.assert_allclose(read.initial_velocity, direct.initial_velocity, rtol=1e-6)
    (c_read,), (c_direct,) = read.contacts, direct.contacts
    np.testing.assert_array_equal(c_read.node_ids, c_direct.node_ids)
    np.testing.assert_allclose(c_read.stiffness, c_direct.stiffness, rtol=1e-4)
    target, fitted = make_target(setup, ball.radius), c_read.target
    assert isinstance(target, RigidCylinder) and isinstance(fitted, RigidCylinder)
    assert fitted.radius == pytest.approx(target.radius, rel=1e-9)
    assert fitted.length == pytest.approx(target.length, rel=1e-9)
    np.testing.assert_allclose(fitted.axis_point, target.axis_point, atol=1e-12)
    np.testing.assert_allclose(fitted.front, target.front, atol=1e-9)


def test_free_format_deck_reads_like_the_fixed_one(tmp_path: Path) -> None:
    """The exported deck rewritten with commas (fields split at their columns) reads the same."""
    from batball.lsdyna.cards import LAYOUTS

    text = impact_deck(load_ball_spec("type1"), ImpactSetup("cor", 60 * MPH, divisions=2))
    out, keyword, index = [], "", 0
    for line in text.splitlines():
        if line.startswith("*"):
            keyword, index = line[1:].strip(), 0
        elif not line.startswith("$") and keyword in LAYOUTS and keyword not in ("TITLE", "PART"):
            layout = LAYOUTS[keyword][min(index, len(LAYOUTS[keyword]) - 1)]
            cuts = np.cumsum([0] + [w for _, w, _ in layout])
            line = ",".join(line[a:b].strip() for a, b in zip(cuts[:-1], cuts[1:], strict=True))
            index += 1 if keyword not in ("NODE", "ELEMENT_SOLID", "ELEMENT_SHELL") else 0
        out.append(line)
    fixed = read_deck(write(tmp_path, "fixed.k", text)).model
    free = read_deck(write(tmp_path, "free.k", "\n".join(out) + "\n")).model
    np.testing.assert_array_equal(free.mesh.points, fixed.mesh.points)
    np.testing.assert_array_equal(free.material_constants, fixed.material_constants)
    np.testing.assert_array_equal(free.contacts[0].stiffness, fixed.contacts[0].stiffness)
    plane_free, plane_fixed = free.contacts[0].target, fixed.contacts[0].target
    assert isinstance(plane_free, RigidPlane) and isinstance(plane_fixed, RigidPlane)
    np.testing.assert_array_equal(plane_free.point, plane_fixed.point)
    # the wall face of F1887 (make_target): z = -(radius + gap), normal +z
    wall = make_target(ImpactSetup("cor", 60 * MPH), load_ball_spec("type1").radius)
    assert plane_free.point[2] == pytest.approx(wall.point[2], rel=1e-12)
    np.testing.assert_allclose(plane_free.normal, wall.normal, atol=1e-12)


def test_contact_thickness_override_moves_the_face(tmp_path: Path) -> None:
    """SBST (the rigid side's contact thickness) replaces the shell thickness: the wall face
    moves by (SBST - t) / 2 toward the ball (Keyword Manual, *CONTACT card 3)."""
    text = impact_deck(load_ball_spec("type1"), ImpactSetup("cor", 60 * MPH, divisions=2))
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("*CONTACT_AUTOMATIC"))
    card3 = i + 6  # keyword, $# + card 1, $# + card 2, $# + card 3
    assert lines[card3].split()[:2] == ["1.0", "1.0"]
    lines[card3] = lines[card3].ljust(30) + "0.25".rjust(10)  # SBST = 0.25 in, columns 31-40
    plain = read_deck(write(tmp_path, "a.k", text)).model.contacts[0].target
    thick = read_deck(write(tmp_path, "b.k", "\n".join(lines) + "\n")).model.contacts[0].target
    assert isinstance(plain, RigidPlane) and isinstance(thick, RigidPlane)
    shift = (thick.point - plain.point)[2] / 0.0254
    assert shift == pytest.approx((0.25 - 0.05) / 2, rel=1e-9)


def test_elastic_ball_is_written_as_mat_001_and_read_back(tmp_path: Path) -> None:
    """An elastic ball goes out as *MAT_ELASTIC (E in psi, PR) and comes back with the kernel
    constants K = E / (3 (1 - 2 nu)), G = E / (2 (1 + nu)) of E = 10,000 psi, nu = 0.45."""
    from batball.specs import ball_spec_from_dict

    ball = ball_spec_from_dict(
        {
            "name": "elastic",
            "circumference": "12 in",
            "mass": "6.93 oz",
            "material": {"law": "elastic", "youngs_modulus": "10000 psi", "poissons_ratio": 0.45},
        },
        source="keyword test",
    )
    text = impact_deck(ball, ImpactSetup("cor", 60 * MPH, divisions=2))
    assert "*MAT_ELASTIC" in text and "*MAT_VISCOELASTIC" not in text
    constants = read_deck(write(tmp_path, "e.k", text)).model.material_constants[0]
    psi = 4.4482216152605 / 0.0254**2
    e, nu = 10000 * psi, 0.45
    np.testing.assert_allclose(
        constants, [e / (3 * (1 - 2 * nu)), e / (2 * (1 + nu)), e / (2 * (1 + nu)), 0.0], rtol=1e-9
    )


def test_prony_ball_is_refused_with_its_keyword() -> None:
    """A generalised viscoelastic ball (MAT_GENERAL_VISCOELASTIC) is not written yet: a clear
    error, not a deck with the wrong material."""
    from batball.specs import ball_spec_from_dict

    ball = ball_spec_from_dict(
        {
            "name": "prony",
            "circumference": "12 in",
            "mass": "6.93 oz",
            "material": {
                "law": "prony2", "bulk_modulus": "800000 psi", "g_inf": "750 psi",
                "g1": "20000 psi", "beta1": "75000 1/s", "g2": "1000 psi", "beta2": "1000 1/s",
            },
        },
        source="keyword test",
    )  # fmt: skip
    with pytest.raises(SpecError, match="MAT_GENERAL_VISCOELASTIC"):
        impact_deck(ball, ImpactSetup("cor", 60 * MPH, divisions=2))


def test_deck_without_initial_velocity_or_moving_plate_is_refused(tmp_path: Path) -> None:
    text = impact_deck(load_ball_spec("type1"), ImpactSetup("cor", 60 * MPH, divisions=2))
    lines = text.splitlines()
    i = lines.index("*INITIAL_VELOCITY_GENERATION")
    del lines[i : i + 5]  # the keyword, two cards and their $# lines
    assert lines[i].startswith("*CONTACT")
    with pytest.raises(SpecError, match="INITIAL_VELOCITY_GENERATION"):
        read_deck(write(tmp_path, "v.k", "\n".join(lines) + "\n"))


def test_text_beyond_a_cards_fields_is_an_error(tmp_path: Path) -> None:
    """A fixed-format card with text past its last field (e.g. MAT_RIGID card 2's SPCNID, which
    batball does not read) is refused, not cut off."""
    card2 = "       1.0       7.0       7.0        12"
    path = write(tmp_path, "r.k", f"*KEYWORD\n*MAT_RIGID\n2,7.8e-4,3e7,0.3\n{card2}\n0.0\n")
    with pytest.raises(SpecError, match=r"\*MAT_RIGID at .*r\.k:4.*nothing after column 30"):
        parse_deck(path)
