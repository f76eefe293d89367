"""The bat tests' keyword decks read back: export -> read -> run equals the direct run (modal,
barrel); export -> read equals the exported model (barrel, bbs; the bbs run round trip is in
test_keyword_bbs_roundtrip.py).

Tolerances: long format (20-column fields, shortest repr) keeps every double, so the model read
back is the direct one to 1e-12; the modal frequencies then agree to the eigen-solver's
convergence (ARPACK shift-invert, measured 5e-9 on this mesh: 1e-7). Standard format keeps 5 to
6 significant digits a real (layer thicknesses 0.0078667 in, moduli): the frequencies moved by
7e-6 at most, measured; 5e-5. Barrel (preload and final load, 0 deg): measured 3e-10 (long) and
1.6e-8 (standard) off the direct run; 1e-8 and 1e-6. Coarse meshes (8 shells around, 1-in rings):
about a second each.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from batball.errors import SpecError
from batball.lab.barrel import run_barrel_compression
from batball.lab.decks import run_barrel_deck, run_modal_deck
from batball.lab.modal import bat_modes
from batball.lsdyna.bat import (
    barrel_deck,
    barrel_platens,
    barrel_support_nodes,
    bbs_deck,
    modal_deck,
)
from batball.lsdyna.bat_model import ball_of, pivot_band, read_bat_deck, rigid_shells, supports
from batball.lsdyna.cards import unit_system
from batball.lsdyna.model import read_deck
from batball.mesh.bat import make_bat_mesh
from batball.models.barrel import BarrelTestOptions, build_barrel_model, compute_prestress
from batball.models.bat import bat_section
from batball.models.bbs import BbsSetup, build_bbs_model
from batball.specs import load_ball_spec
from batball.specs.bat import load_bat_spec

IN, LBF = 0.0254, 4.4482216152605
MESH = {"circumferential": 8, "axial_size": 1.0 * IN}
U = unit_system("in-lbf-s")


@pytest.mark.parametrize(("long", "rtol"), [(True, 1e-7), (False, 5e-5)])
def test_modal_deck_runs_as_the_direct_modal_test(tmp_path: Path, long: bool, rtol: float) -> None:
    spec = load_bat_spec("default")
    direct = bat_modes(spec, n_modes=14, insert="bonded", **MESH)  # the deck ties the insert
    path = tmp_path / "modal.k"
    path.write_text(modal_deck(spec, n_modes=14, long=long, **MESH))
    summary = run_modal_deck(read_bat_deck(path))
    flexible = np.array(summary["frequencies_hz"][6:])
    np.testing.assert_allclose(flexible, direct.frequencies[6:], rtol=rtol)
    assert summary["labels"] == list(direct.labels)


def test_modal_deck_section_is_the_direct_section(tmp_path: Path) -> None:
    spec = load_bat_spec("default")
    path = tmp_path / "modal.k"
    path.write_text(modal_deck(spec, n_modes=12, long=True, **MESH))
    bat = read_bat_deck(path)
    mesh = make_bat_mesh(spec, **MESH)
    np.testing.assert_allclose(bat.mesh.points, mesh.points, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(bat.mesh.cells, mesh.cells)
    direct, read = bat_section(spec, mesh), bat.section()
    for name in ("abd", "shear", "areal_mass", "rotary_inertia"):
        expected = getattr(direct, name)
        scale = np.abs(expected).max()
        np.testing.assert_allclose(getattr(read, name), expected, rtol=0, atol=1e-12 * scale)


def test_barrel_deck_reads_back_the_exported_model(tmp_path: Path) -> None:
    spec, options = load_bat_spec("default"), BarrelTestOptions()
    path = tmp_path / "barrel.k"
    path.write_text(barrel_deck(spec, options, long=True, **MESH))
    bat = read_bat_deck(path)
    assert bat.test == "barrel" and bat.elform == 16
    mesh = make_bat_mesh(spec, **MESH)
    np.testing.assert_allclose(bat.mesh.points, mesh.points, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(bat.mesh.cell_sets["insert"], mesh.cell_sets["insert"])
    rings, on_axis = barrel_support_nodes(spec, options, 0.0, **MESH)
    held = supports(bat)
    np.testing.assert_array_equal(held[0][0], rings)
    np.testing.assert_array_equal(held[1][0], on_axis)
    assert [dofs for _, dofs in held] == [(1, 0, 0, 0, 0, 0), (0, 0, 1, 0, 0, 0)]
    platens = rigid_shells(bat, U)
    for pid, expected in zip((2, 3), barrel_platens(spec, options, 0.0), strict=True):
        got = platens[pid]
        assert got.radius == pytest.approx(expected.radius, rel=1e-12)
        np.testing.assert_allclose(got.axis_point, expected.axis_point, atol=1e-12)
        np.testing.assert_allclose(np.abs(got.axis), np.abs(expected.axis), atol=1e-12)
        np.testing.assert_allclose(got.front, expected.front, atol=1e-9)
    travel = bat.deck.curves[3][-1, 1] * IN
    assert travel == pytest.approx(options.preload_travel + options.final_travel, rel=1e-12)
    assert bat.deck.curve_sidr[1] == 1  # the fit's stiffness ramp acts in dynamic relaxation


@pytest.mark.parametrize(("long", "rtol"), [(True, 1e-8), (False, 1e-6)])
def test_barrel_deck_runs_as_the_direct_barrel_test(
    tmp_path: Path, long: bool, rtol: float
) -> None:
    spec, options = load_bat_spec("default"), BarrelTestOptions(orientations_deg=(0.0,))
    model = build_barrel_model(spec, **MESH)
    direct = run_barrel_compression(model, compute_prestress(model), options)
    path = tmp_path / "barrel.k"
    path.write_text(barrel_deck(spec, options, long=long, **MESH))
    summary = run_barrel_deck(read_bat_deck(path))
    assert summary["preload_lbf"] * LBF == pytest.approx(direct.preloads()[0], rel=rtol)
    assert summary["final_load_lbf"] * LBF == pytest.approx(direct.final_loads()[0], rel=rtol)


def test_barrel_deck_with_other_supports_is_an_error(tmp_path: Path) -> None:
    text = barrel_deck(load_bat_spec("default"), BarrelTestOptions(), **MESH)
    at = text.index("*BOUNDARY_SPC_SET")
    path = tmp_path / "barrel.k"
    path.write_text(text[:at] + text[at:].replace("*BOUNDARY_SPC_SET", "$", 1))  # axial one gone
    with pytest.raises(SpecError, match="batball's supports"):
        run_barrel_deck(read_bat_deck(path))


def test_bbs_deck_reads_back_the_exported_model(tmp_path: Path) -> None:
    spec, ball = load_bat_spec("default"), load_ball_spec("type1")
    setup = BbsSetup(ball_divisions=2, pivot_band=1.0 * IN, **MESH)
    path = tmp_path / "bbs.k"
    path.write_text(bbs_deck(spec, ball, setup, long=True))
    bat = read_bat_deck(path)
    model = build_bbs_model(spec, ball, setup)
    assert bat.test == "bbs" and bat.elform == 2
    np.testing.assert_allclose(bat.mesh.points, model.bat_mesh.points, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(pivot_band(bat), model.coupled.bat.band)
    ball_mesh, constants, velocity = ball_of(bat, U)
    n_bat = model.bat_mesh.n_points
    np.testing.assert_allclose(ball_mesh.points, model.coupled.points[n_bat:], atol=1e-15)
    np.testing.assert_array_equal(ball_mesh.cells, model.ball_cells)
    np.testing.assert_allclose(velocity, model.coupled.velocity[n_bat:], rtol=1e-12)
    np.testing.assert_allclose(constants[0], model.coupled.ball.material_constants[0],
                               rtol=1e-12)  # fmt: skip
    kinds = sorted(c["kind"] for c in bat.deck.contacts)
    assert kinds == ["CONTACT_AUTOMATIC_SURFACE_TO_SURFACE",
                     "CONTACT_SURFACE_TO_SURFACE_INTERFERENCE"]  # fmt: skip


def test_impact_reader_refuses_a_bat_deck(tmp_path: Path) -> None:
    setup = BbsSetup(ball_divisions=2, pivot_band=1.0 * IN, **MESH)
    path = tmp_path / "bbs.k"
    path.write_text(bbs_deck(load_bat_spec("default"), load_ball_spec("type1"), setup))
    with pytest.raises(SpecError, match="PART_COMPOSITE"):
        read_deck(path)


def test_a_lamina_strength_batball_cannot_honour_is_an_error(tmp_path: Path) -> None:
    text = modal_deck(load_bat_spec("default"), n_modes=12, **MESH)
    lines = text.splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("*MAT_COMPOSITE_DAMAGE"))
    strengths = 1 + next(i for i in range(at, len(lines)) if lines[i].startswith("$#      sc"))
    lines[strengths] = f"{'':10}{'120000.0':>10}" + lines[strengths][20:]  # XT = 120 ksi
    path = tmp_path / "modal.k"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(SpecError, match=rf"MAT_COMPOSITE_DAMAGE at .*modal.k:{at + 1} XT"):
        read_bat_deck(path)


def test_a_modal_deck_whose_insert_floats_free_is_an_error(tmp_path: Path) -> None:
    text = modal_deck(load_bat_spec("default"), n_modes=12, **MESH)
    start = text.index("*CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET")
    path = tmp_path / "modal.k"
    path.write_text(text[:start] + "*END\n")  # the insert's tie removed
    with pytest.raises(SpecError, match="'insert' only for the SURFA part"):
        read_bat_deck(path)
    path.write_text(text[:start].replace("\ninsert\n", "\nsleeve\n") + "*END\n")
    with pytest.raises(SpecError, match="more than one piece"):
        read_bat_deck(path)
