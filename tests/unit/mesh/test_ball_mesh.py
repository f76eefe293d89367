"""The O-grid ball: counts, merged nodes, exact surface, positive cells, converging volume."""

from __future__ import annotations

import numpy as np
import pytest

from batball.mesh import (
    Mesh,
    boundary_faces,
    hex_volumes,
    make_ball_mesh,
    mesh_quality,
    scaled_jacobians,
    surface_point_ids,
)
from batball.mesh.hexa import face_area_vectors
from batball.solvers.explicit_kernels import slot_node_ranges

RADIUS = 0.0485  # m, a 12-inch softball is about 0.0485 m in radius
SPHERE_VOLUME = 4.0 / 3.0 * np.pi * RADIUS**3


@pytest.fixture(scope="module", params=[4, 8, 12])
def ball(request: pytest.FixtureRequest) -> tuple[int, Mesh]:
    return request.param, make_ball_mesh(RADIUS, divisions=request.param)


@pytest.mark.parametrize(("divisions", "n_cells"), [(4, 448), (6, 1512), (8, 3584), (12, 12096)])
def test_cell_count_is_seven_blocks_of_divisions_cubed(divisions: int, n_cells: int) -> None:
    assert make_ball_mesh(RADIUS, divisions=divisions).n_cells == n_cells


def test_node_count_is_core_plus_cube_shells(ball: tuple[int, Mesh]) -> None:
    n, mesh = ball
    assert mesh.n_points == (n + 1) ** 3 + n * (6 * n**2 + 2)


def test_no_duplicate_nodes_and_every_node_used(ball: tuple[int, Mesh]) -> None:
    _, mesh = ball
    spacing = np.round(mesh.points / (RADIUS * 1e-6)).astype(np.int64)
    assert np.unique(spacing, axis=0).shape[0] == mesh.n_points
    assert np.array_equal(np.unique(mesh.cells), np.arange(mesh.n_points))


def test_arrays_are_contiguous_with_meshio_orientation(ball: tuple[int, Mesh]) -> None:
    _, mesh = ball
    assert mesh.points.dtype == np.float64 and mesh.points.flags.c_contiguous
    assert mesh.cells.dtype == np.int64 and mesh.cells.flags.c_contiguous
    assert mesh.points.shape[1] == 3 and mesh.cells.shape[1] == 8


def test_surface_set_is_the_boundary_and_lies_on_the_sphere(ball: tuple[int, Mesh]) -> None:
    n, mesh = ball
    surface = mesh.point_sets["surface"]
    assert np.array_equal(np.sort(surface), surface_point_ids(mesh.cells))
    np.testing.assert_allclose(np.linalg.norm(mesh.points[surface], axis=1), RADIUS, rtol=1e-14)
    faces, _ = boundary_faces(mesh.cells)
    assert faces.shape[0] == 6 * n**2


def test_boundary_faces_enclose_the_cell_volume_outwards(ball: tuple[int, Mesh]) -> None:
    _, mesh = ball
    faces, _ = boundary_faces(mesh.cells)
    area_vectors = face_area_vectors(mesh.points, faces)
    centroids = mesh.points[faces].mean(axis=1)
    # divergence theorem: V = 1/3 sum(x . dA) over the outward-oriented surface
    enclosed = np.einsum("ij,ij->", centroids, area_vectors) / 3.0
    total = hex_volumes(mesh.points, mesh.cells).sum()
    assert enclosed == pytest.approx(total, rel=1e-3)


def test_centre_node_is_at_the_origin(ball: tuple[int, Mesh]) -> None:
    _, mesh = ball
    (centre,) = mesh.point_sets["centre"]
    np.testing.assert_allclose(mesh.points[centre], 0.0, atol=1e-18)


def test_odd_divisions_have_no_centre_node() -> None:
    mesh = make_ball_mesh(RADIUS, divisions=5)
    assert "centre" not in mesh.point_sets
    assert mesh.n_cells == 7 * 125


def test_cell_sets_split_core_and_shell(ball: tuple[int, Mesh]) -> None:
    n, mesh = ball
    core, shell = mesh.cell_sets["core"], mesh.cell_sets["shell"]
    assert core.size == n**3 and shell.size == 6 * n**3
    assert np.array_equal(np.sort(np.concatenate([core, shell])), np.arange(mesh.n_cells))


def test_node_numbering_keeps_the_solver_halves_apart(ball: tuple[int, Mesh]) -> None:
    # The explicit solver splits the cells into two contiguous halves on two threads. The cells
    # go in slabs of whole lines and the nodes line by line in the order the cells first use
    # them, so the halves' node ranges should overlap only near the middle: fewer than two
    # node layers of a square of 2 n + 1 nodes a side.
    n, mesh = ball
    (lo0, hi0), (lo1, hi1) = slot_node_ranges(mesh.cells, 2)
    assert lo0 == 0 and hi1 == mesh.n_points
    assert hi0 - lo1 < 2 * (2 * n + 1) ** 2


def test_cells_run_along_lines_of_consecutive_nodes(ball: tuple[int, Mesh]) -> None:
    # Each run of n cells is one line, each cell's face (1, 2, 5, 6) the next one's (0, 3, 4, 7).
    # Along the core's n^2 lines and the other four shell blocks' 4 n^2 every corner's node id
    # rises by one from a cell to the next. The x blocks' lines run radially; the nodes on their
    # edges toward the other blocks lie on those blocks' lines, so only their (n - 2)^2 inner
    # lines a block rise (the element kernel moves such runs of nodes as one span).
    n, mesh = ball
    lines = mesh.cells.reshape(-1, n, 8)
    assert np.array_equal(lines[:, 1:, [0, 3, 4, 7]], lines[:, :-1, [1, 2, 5, 6]])
    rising = np.all(np.diff(lines, axis=1) == 1, axis=2)
    assert rising.sum() == (n - 1) * (n**2 + 4 * n**2 + 2 * (n - 2) ** 2)


@pytest.mark.parametrize("divisions", [3, 4, 12])
def test_numbering_does_not_depend_on_the_radius(divisions: int) -> None:
    # a deck's ball is rebuilt from its radius read back (a few digits) and must have the same
    # nodes and cells: many lines sit exactly on a slab boundary of the ordering, where a
    # radius one part in 1e7 or 1e12 away must not move them
    mesh = make_ball_mesh(RADIUS, divisions=divisions)
    for scale in (1.0 + 1e-12, 1.0 - 1e-12, 1.0 + 3e-7):
        other = make_ball_mesh(RADIUS * scale, divisions=divisions)
        assert np.array_equal(other.cells, mesh.cells)
        np.testing.assert_allclose(other.points, mesh.points * scale, rtol=0, atol=1e-15)


def test_every_cell_has_positive_volume_and_good_shape(ball: tuple[int, Mesh]) -> None:
    n, mesh = ball
    assert np.all(hex_volumes(mesh.points, mesh.cells) > 0.0)
    assert scaled_jacobians(mesh.points, mesh.cells).min() > 0.5
    quality = mesh_quality(mesh)
    assert quality.min_characteristic_length > 0.5 * RADIUS / (2 * n)


def test_volume_converges_to_the_sphere_from_below() -> None:
    errors = [
        mesh_quality(make_ball_mesh(RADIUS, divisions=n)).volume / SPHERE_VOLUME - 1.0
        for n in (4, 8, 12)
    ]
    assert all(error < 0.0 for error in errors)
    assert -errors[0] > -errors[1] > -errors[2]
    assert abs(errors[2]) < 0.015


def test_quality_describe_reports_counts_and_inches() -> None:
    quality = mesh_quality(make_ball_mesh(RADIUS, divisions=4))
    line = quality.describe()
    assert line.startswith("448 hexes, 517 nodes, min scaled Jacobian ")
    assert f"{quality.min_characteristic_length / 0.0254:.3f} in" in line


def test_invalid_arguments_are_rejected() -> None:
    with pytest.raises(ValueError, match="divisions"):
        make_ball_mesh(RADIUS, divisions=0)
    with pytest.raises(ValueError, match="radius"):
        make_ball_mesh(-1.0)
