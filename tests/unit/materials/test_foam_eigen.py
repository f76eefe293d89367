"""The foam's eigen-decomposition of b = F F^T, one point at a time and a block at once."""

from __future__ import annotations

import numpy as np
import pytest

from batball.materials.foam_update import (
    EIGEN_LANES,
    EIGEN_V,
    block_symmetric_eigen,
    eigen_block,
    symmetric_eigen,
)


def _matrices() -> np.ndarray:
    """Symmetric 3 x 3 matrices of the kinds a foam meets, and degenerate ones (n, 3, 3)."""
    rng = np.random.default_rng(11)
    small = np.eye(3) + rng.normal(0.0, 1e-6, (20, 3, 3))
    moderate = np.eye(3) + rng.normal(0.0, 0.1, (40, 3, 3))
    large = np.eye(3) + rng.normal(0.0, 0.5, (40, 3, 3))
    stretched = np.concatenate([small, moderate, large])
    b = np.einsum("nij,nkj->nik", stretched, stretched)
    special = np.array(
        [np.eye(3), np.diag([1.0, 2.0, 3.0]), np.diag([2.0, 2.0, 3.0]), np.zeros((3, 3)),
         np.full((3, 3), np.nan), np.diag([0.3, 0.3, 0.3])]
    )  # fmt: skip
    return np.concatenate([b, special])


def _scalar(matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    values, vectors = np.empty_like(matrices), np.empty_like(matrices)
    for i, m in enumerate(matrices):
        a, v = m.copy(), np.empty((3, 3))
        symmetric_eigen(a, v)
        values[i], vectors[i] = a, v
    return values, vectors


def _block(matrices: np.ndarray, lanes: int) -> tuple[np.ndarray, np.ndarray]:
    """The block routine over consecutive groups of ``lanes`` matrices (the rest of a block
    holds what the previous group left there, as in the kernel)."""
    values, vectors = np.empty_like(matrices), np.empty_like(matrices)
    w = eigen_block()
    rows = w.reshape(-1, EIGEN_LANES)
    for start in range(0, len(matrices), lanes):
        group = matrices[start : start + lanes]
        n = len(group)
        rows[:9, :n] = group.reshape(n, 9).T
        block_symmetric_eigen(w, n)
        values[start : start + n] = rows[:9, :n].T.reshape(n, 3, 3)
        vectors[start : start + n] = rows[EIGEN_V : EIGEN_V + 9, :n].T.reshape(n, 3, 3)
    return values, vectors


@pytest.mark.parametrize("lanes", [1, 7, EIGEN_LANES])
def test_a_block_gives_each_point_the_bits_of_one_at_a_time(lanes: int) -> None:
    """Each lane runs the same checks and rotations in the same order as the one-point routine
    (no multiply-add contraction in either), so the results agree bit for bit, NaN included."""
    matrices = _matrices()
    values, vectors = _scalar(matrices)
    block_values, block_vectors = _block(matrices, lanes)
    assert np.array_equal(block_values, values, equal_nan=True)
    assert np.array_equal(block_vectors, vectors, equal_nan=True)


def test_the_decomposition_agrees_with_lapack() -> None:
    """Eigenvalues against numpy.linalg.eigvalsh and the reconstruction V diag(lambda) V^T, to
    1e-13 of the largest eigenvalue (the Jacobi sweeps stop at 1e-15 of the trace)."""
    matrices = _matrices()
    # the NaN and the zero matrix have nothing to compare
    matrices = matrices[
        np.isfinite(matrices).all(axis=(1, 2)) & (np.abs(matrices).max(axis=(1, 2)) > 0)
    ]
    values, vectors = _block(matrices, EIGEN_LANES)
    diagonal = np.einsum("nii->ni", values)
    expected = np.linalg.eigvalsh(matrices)
    scale = np.abs(expected).max(axis=1, keepdims=True)
    assert np.abs(np.sort(diagonal, axis=1) - expected).max() <= 1e-13 * scale.max()
    rebuilt = np.einsum("nik,nk,njk->nij", vectors, diagonal, vectors)
    assert (np.abs(rebuilt - matrices).max(axis=(1, 2)) <= 1e-13 * scale[:, 0]).all()
    assert np.abs(np.einsum("nki,nkj->nij", vectors, vectors) - np.eye(3)).max() < 1e-13
