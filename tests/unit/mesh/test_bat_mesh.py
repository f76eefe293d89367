"""The bat's shell mesh: sound quads, one set per part, a separate insert, the seed's density."""

from __future__ import annotations

import numpy as np
import pytest

from batball.mesh import make_bat_mesh, quad_normals, shell_quality
from batball.specs import load_bat_spec

IN = 0.0254
SEED_SHELLS = 20494  # "built with 20494 four-noded thin shell elements"


@pytest.fixture(scope="module")
def spec():
    return load_bat_spec("default")


@pytest.fixture(scope="module")
def mesh(spec):
    return make_bat_mesh(spec)


def test_default_density_is_near_the_seeds_shell_count(mesh) -> None:
    assert mesh.n_cells == pytest.approx(SEED_SHELLS, rel=0.03)


def test_no_degenerate_or_inverted_quads(mesh) -> None:
    quality = shell_quality(mesh)
    assert quality.min_area > 0.002 * IN**2
    assert quality.min_scaled_jacobian > 0.95
    assert quality.max_aspect_ratio < 3.0


def test_part_sets_cover_every_cell_once(spec, mesh) -> None:
    names = [p.name for p in spec.parts] + ["insert"]
    assert sorted(mesh.cell_sets) == sorted(names)
    every = np.concatenate([mesh.cell_sets[name] for name in names])
    assert np.array_equal(np.sort(every), np.arange(mesh.n_cells))


def test_part_cells_lie_within_their_axial_span(spec, mesh) -> None:
    centres = mesh.points[mesh.cells].mean(axis=1)
    for part in spec.parts:
        x = centres[mesh.cell_sets[part.name], 0]
        assert x.min() > part.start and x.max() < part.end


def test_insert_is_a_separate_surface_at_its_mid_radius(spec, mesh) -> None:
    insert_nodes = np.unique(mesh.cells[mesh.cell_sets["insert"]])
    outer_cells = np.setdiff1d(np.arange(mesh.n_cells), mesh.cell_sets["insert"])
    assert np.intersect1d(insert_nodes, np.unique(mesh.cells[outer_cells])).size == 0
    # barrel: 2.25-in diameter; wall 0.012 + 0.0633 + 0.015 in; insert 0.015 + 0.030 + 0.015 in
    bore = 1.125 - (0.012 + 0.0633 + 0.015)
    expected = bore + 0.001 - 0.5 * 0.060
    radius = np.hypot(mesh.points[insert_nodes, 1], mesh.points[insert_nodes, 2])
    assert radius == pytest.approx(expected * IN, rel=1e-9)
    x = mesh.points[insert_nodes, 0]
    assert x.min() == pytest.approx(22.0 * IN) and x.max() == pytest.approx(32.0 * IN)


def test_edge_1_2_follows_the_bat_axis_and_normals_point_outward(mesh) -> None:
    x = mesh.points[mesh.cells]
    edge = x[:, 1] - x[:, 0]
    assert np.all(edge[:, 0] > 0.0)
    # no hoop component: nodes 1 and 2 share their angle
    angle_1 = np.arctan2(x[:, 0, 2], x[:, 0, 1])
    angle_2 = np.arctan2(x[:, 1, 2], x[:, 1, 1])
    assert np.abs(angle_1 - angle_2).max() < 1e-12
    centres = x.mean(axis=1)
    radial = centres * np.array([0.0, 1.0, 1.0])
    assert np.all(np.einsum("ij,ij->i", quad_normals(mesh.points, mesh.cells), radial) > 0.0)


def test_handle_nodes_lie_on_the_mid_surface(spec, mesh) -> None:
    points = mesh.points[mesh.point_sets["outer"]]
    handle = np.abs(points[:, 0] - 7.0 * IN) < 1.5 * IN  # inside handle-2, away from its ends
    radius = np.hypot(points[handle, 1], points[handle, 2])
    wall = 0.012 + 0.0472 + 0.015  # in, handle-2's plies
    assert radius == pytest.approx((0.45 - 0.5 * wall) * IN, rel=1e-9)


def test_coarser_and_finer_meshes_on_request(spec, mesh) -> None:
    coarse = make_bat_mesh(spec, circumferential=24, axial_size=0.2 * IN)
    fine = make_bat_mesh(spec, circumferential=96, axial_size=0.05 * IN)
    assert coarse.n_cells == pytest.approx(mesh.n_cells / 4, rel=0.05)
    assert fine.n_cells == pytest.approx(mesh.n_cells * 4, rel=0.05)


def test_invalid_mesh_options_are_refused(spec) -> None:
    with pytest.raises(ValueError, match="circumferential"):
        make_bat_mesh(spec, circumferential=2)
    with pytest.raises(ValueError, match="axial_size"):
        make_bat_mesh(spec, axial_size=0.0)
