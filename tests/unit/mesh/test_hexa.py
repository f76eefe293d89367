"""Hex8 geometry against analytic values and an independent Gauss-quadrature volume."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from batball.mesh import (
    boundary_faces,
    characteristic_lengths,
    hex_volumes,
    scaled_jacobians,
    surface_point_ids,
)
from batball.mesh.hexa import HEX_FACES, face_area_vectors, unique_rows

UNIT_CUBE = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=np.float64,
)
ONE_CELL = np.arange(8, dtype=np.int64)[None, :]


def block_mesh(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Structured n x n x n block of unit cubes, written independently of the ball mesher."""
    idx = np.arange((n + 1) ** 3).reshape(n + 1, n + 1, n + 1)  # (ix, iy, iz)
    grid = np.stack(np.meshgrid(*[np.arange(n + 1.0)] * 3, indexing="ij"), axis=-1)
    i, j, k = (a.ravel() for a in np.meshgrid(*[np.arange(n)] * 3, indexing="ij"))
    cells = np.stack(
        [idx[i, j, k], idx[i + 1, j, k], idx[i + 1, j + 1, k], idx[i, j + 1, k],
         idx[i, j, k + 1], idx[i + 1, j, k + 1], idx[i + 1, j + 1, k + 1], idx[i, j + 1, k + 1]],
        axis=1,
    )  # fmt: skip
    return grid.reshape(-1, 3), cells


def gauss_volume(x: np.ndarray) -> float:
    """Volume of one trilinear hex, shape (8, 3), by 2x2x2 Gauss quadrature of det J (exact)."""
    signs = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)  # fmt: skip
    g = 1.0 / np.sqrt(3.0)
    total = 0.0
    for xi in np.array(np.meshgrid([-g, g], [-g, g], [-g, g])).reshape(3, -1).T:
        dn = np.empty((8, 3))
        for a in range(3):
            factors = 1.0 + signs * xi
            factors[:, a] = signs[:, a]
            dn[:, a] = np.prod(factors, axis=1) / 8.0
        total += np.linalg.det(x.T @ dn)
    return total


def test_unit_cube_has_volume_length_and_scaled_jacobian_one() -> None:
    assert hex_volumes(UNIT_CUBE, ONE_CELL) == pytest.approx([1.0], abs=1e-15)
    assert characteristic_lengths(UNIT_CUBE, ONE_CELL) == pytest.approx([1.0], abs=1e-15)
    assert scaled_jacobians(UNIT_CUBE, ONE_CELL) == pytest.approx([1.0], abs=1e-15)


def test_sheared_rotated_scaled_box_has_analytic_volume() -> None:
    shear = np.array([[1.0, 0.4, 0.2], [0.0, 1.0, -0.3], [0.0, 0.0, 1.0]])
    scale = np.diag([0.02, 0.03, 0.05])
    angle = 0.7
    rotation = np.array(
        [[np.cos(angle), -np.sin(angle), 0.0], [np.sin(angle), np.cos(angle), 0.0], [0, 0, 1]]
    )
    mapping = rotation @ shear @ scale
    points = UNIT_CUBE @ mapping.T + np.array([0.1, -0.2, 0.3])
    expected = np.linalg.det(mapping)
    assert hex_volumes(points, ONE_CELL) == pytest.approx([expected], rel=1e-12)


def test_distorted_hex_volume_matches_gauss_quadrature() -> None:
    rng = np.random.default_rng(7)
    points = UNIT_CUBE + 0.15 * rng.standard_normal((8, 3))
    assert hex_volumes(points, ONE_CELL)[0] == pytest.approx(gauss_volume(points), rel=1e-12)


def test_parallelepiped_scaled_jacobian_is_sine_of_shear_angle() -> None:
    angle = np.deg2rad(60.0)
    mapping = np.array([[1.0, np.cos(angle), 0.0], [0.0, np.sin(angle), 0.0], [0.0, 0.0, 1.0]])
    points = UNIT_CUBE @ mapping.T
    assert scaled_jacobians(points, ONE_CELL) == pytest.approx([np.sin(angle)], rel=1e-12)


def test_inverted_hex_has_negative_volume_and_scaled_jacobian() -> None:
    mirrored = ONE_CELL[:, [0, 3, 2, 1, 4, 7, 6, 5]]
    assert hex_volumes(UNIT_CUBE, mirrored)[0] == pytest.approx(-1.0)
    assert scaled_jacobians(UNIT_CUBE, mirrored)[0] <= 0.0
    folded = UNIT_CUBE.copy()
    folded[6] = [0.2, 0.2, -0.5]  # top corner pushed through the bottom face
    assert scaled_jacobians(folded, ONE_CELL)[0] <= 0.0


def test_boundary_faces_of_2x2x2_block_are_24_and_outward() -> None:
    points, cells = block_mesh(2)
    faces, owner = boundary_faces(cells)
    assert faces.shape == (24, 4)
    assert owner.shape == (24,)
    area_vectors = face_area_vectors(points, faces)
    np.testing.assert_allclose(area_vectors.sum(axis=0), 0.0, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(area_vectors, axis=1), 1.0)
    away = points[faces].mean(axis=1) - points[cells[owner]].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", area_vectors, away) > 0.0)
    # outward unit-cube faces of the block point along +-x, +-y, +-z four times each
    assert np.all(np.abs(area_vectors).max(axis=1) == pytest.approx(1.0))


@pytest.mark.parametrize(
    ("low", "high", "columns", "dtype"),
    [(-3, 4, 4, np.int64), (0, 50, 3, np.int32), (0, 7, 2, np.uint16),
     (-(2**40), 2**40, 3, np.int64)],  # the last too wide to pack: rows sorted as rows
)  # fmt: skip
def test_unique_rows_is_numpys_unique_over_rows(low: int, high: int, columns: int,
                                                dtype: type) -> None:  # fmt: skip
    rows = np.random.default_rng(3).integers(low, high, (500, columns)).astype(dtype)
    distinct, inverse, counts = unique_rows(rows)
    expected = np.unique(rows, axis=0, return_inverse=True, return_counts=True)
    np.testing.assert_array_equal(distinct, expected[0])
    assert distinct.dtype == rows.dtype
    np.testing.assert_array_equal(inverse, expected[1].ravel())
    np.testing.assert_array_equal(counts, expected[2])


def test_unique_rows_refuses_what_is_not_integer_rows_and_takes_none() -> None:
    with pytest.raises(ValueError, match="2-D integer"):
        unique_rows(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="2-D integer"):
        unique_rows(np.zeros(4, dtype=np.int64))
    distinct, inverse, counts = unique_rows(np.zeros((0, 2), dtype=np.int64))
    assert distinct.shape == (0, 2) and inverse.shape == (0,) and counts.shape == (0,)


@pytest.mark.parametrize("offset", [0, 100_000])
def test_boundary_faces_match_a_count_of_each_faces_cells(offset: int) -> None:
    """Against a dictionary count of every face's node set, with node ids that fit the packed
    integer key (offset 0) and ids too large for it (offset 100,000: the rows are counted)."""
    _, cells = block_mesh(3)
    cells = cells + offset
    uses = Counter(frozenset(face) for cell in cells.tolist() for face in
                   (tuple(cell[i] for i in corners) for corners in HEX_FACES))  # fmt: skip
    expected = [(c, f) for c, cell in enumerate(cells.tolist()) for f, corners in
                enumerate(HEX_FACES) if uses[frozenset(cell[i] for i in corners)] == 1]  # fmt: skip
    faces, owner = boundary_faces(cells)
    assert len(expected) == 6 * 9
    np.testing.assert_array_equal(owner, [c for c, _ in expected])
    np.testing.assert_array_equal(faces, [cells[c, HEX_FACES[f]] for c, f in expected])


def test_surface_point_ids_of_3x3x3_block_exclude_the_8_inner_nodes() -> None:
    points, cells = block_mesh(3)
    surface = surface_point_ids(cells)
    assert surface.size == 4**3 - 2**3
    on_boundary = np.any((points[surface] == 0.0) | (points[surface] == 3.0), axis=1)
    assert np.all(on_boundary)


def test_block_characteristic_length_and_volume() -> None:
    points, cells = block_mesh(2)
    points = points * 0.01
    np.testing.assert_allclose(hex_volumes(points, cells), 1e-6)
    np.testing.assert_allclose(characteristic_lengths(points, cells), 0.01)
