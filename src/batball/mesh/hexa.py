"""Vectorised geometry of eight-node hexahedra (hex8) in LS-DYNA/VTK node order.

All functions take ``points`` of shape (n_points, 3) in m and ``cells`` of shape (n_cells, 8)
(int64, zero-based) and work on every cell at once.
"""

from __future__ import annotations

import numpy as np

# The six faces of a hex8, each ordered so that the right-hand-rule normal points out of the cell.
HEX_FACES = np.array(
    [
        [0, 3, 2, 1],  # bottom
        [4, 5, 6, 7],  # top
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ],
    dtype=np.int64,
)

# For each corner: the three neighbouring corners, ordered so that the edge triad is right-handed
# in an undistorted hex (Verdict / CUBIT hex scaled Jacobian).
HEX_CORNER_NEIGHBOURS = np.array(
    [
        [1, 3, 4],
        [2, 0, 5],
        [3, 1, 6],
        [0, 2, 7],
        [7, 5, 0],
        [4, 6, 1],
        [5, 7, 2],
        [6, 4, 3],
    ],
    dtype=np.int64,
)


def _triple_product(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """a . (b x c) over the last axis, shape (..., 3) -> (...)."""
    return np.einsum("...i,...i->...", a, np.cross(b, c))


def hex_volumes(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Exact volumes of trilinear hexahedra.

    Uses the triple-product formula of Grandy (1997), as in LULESH ``CalcElemVolume``, which
    integrates the trilinear Jacobian exactly; inverted cells give negative volumes.

    Args:
        points: node coordinates, shape (n_points, 3), m.
        cells: hex8 connectivity, shape (n_cells, 8).

    Returns:
        Signed cell volumes, shape (n_cells,), m^3.
    """
    x = points[cells]  # (n_cells, 8, 3)

    def d(i: int, j: int) -> np.ndarray:
        return x[:, i] - x[:, j]

    volume = (
        _triple_product(d(3, 1) + d(7, 2), d(6, 3), d(2, 0))
        + _triple_product(d(4, 3) + d(5, 7), d(6, 4), d(7, 0))
        + _triple_product(d(1, 4) + d(2, 5), d(6, 1), d(5, 0))
    )
    return volume / 12.0


def _all_faces(cells: np.ndarray) -> np.ndarray:
    """Every face of every cell, shape (n_cells * 6, 4), outward-ordered, cell-major."""
    return cells[:, HEX_FACES].reshape(-1, 4)


def unique_rows(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``np.unique(rows, axis=0, return_inverse=True, return_counts=True)`` of integer rows
    (n, k): the distinct rows in lexicographic order, each row's index among them (n,) and
    each distinct row's count.

    Where the rows' ranges fit, each row is packed into one int64 (a mixed-radix number, the
    first column the most significant digit, each column less its smallest value), which sorts
    in the same order as the rows and as one column: NumPy sorts rows through a structured
    view, about six times slower (boundary faces of the 12,096-hex ball: 52 against 8 ms).
    Otherwise the rows are sorted as rows. Both give the same arrays."""
    rows = np.asarray(rows)
    if rows.ndim != 2 or rows.dtype.kind not in "iu":
        raise ValueError(f"unique_rows takes a 2-D integer array, not {rows.dtype} {rows.shape}")
    if rows.shape[0] == 0:
        return rows.copy(), np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    low = rows.min(axis=0).astype(np.int64)
    digits = rows.max(axis=0).astype(np.int64) - low + 1
    if float(np.prod(digits.astype(np.float64))) < 2.0**62:
        packed = np.zeros(rows.shape[0], dtype=np.int64)
        for column in range(rows.shape[1]):
            packed = packed * digits[column] + (rows[:, column].astype(np.int64) - low[column])
        _, first, inverse, counts = np.unique(packed, return_index=True, return_inverse=True,
                                              return_counts=True)  # fmt: skip
        return rows[first], inverse.ravel(), counts
    distinct, inverse, counts = np.unique(rows, axis=0, return_inverse=True, return_counts=True)
    return distinct, inverse.ravel(), counts


def boundary_faces(cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Faces used by exactly one cell, oriented out of that cell (a face is its sorted node
    ids, counted by :func:`unique_rows`).

    Args:
        cells: hex8 connectivity, shape (n_cells, 8).

    Returns:
        ``(faces, owner)``: faces, shape (n_faces, 4) int64, node order giving an outward
        right-hand-rule normal; owner, shape (n_faces,) int64, the cell each face belongs to.
    """
    faces = _all_faces(np.asarray(cells, dtype=np.int64))
    _, inverse, counts = unique_rows(np.sort(faces, axis=1))
    is_boundary = counts[inverse] == 1
    owner = np.nonzero(is_boundary)[0] // HEX_FACES.shape[0]
    return np.ascontiguousarray(faces[is_boundary]), owner.astype(np.int64)


def face_area_vectors(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area vectors of (possibly warped) quadrilaterals, 0.5 * (d13 x d24).

    Args:
        points: node coordinates, shape (n_points, 3), m.
        faces: quad connectivity, shape (n_faces, 4).

    Returns:
        Area vectors along the right-hand-rule normal, shape (n_faces, 3), m^2.
    """
    x = points[faces]
    return 0.5 * np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])


def characteristic_lengths(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """LS-DYNA's default solid time-step length, volume / largest face area.

    Reference: LS-DYNA Theory Manual, "Time step control", solid elements (L_e = v_e / A_e,max).

    Args:
        points: node coordinates, shape (n_points, 3), m.
        cells: hex8 connectivity, shape (n_cells, 8).

    Returns:
        Characteristic lengths, shape (n_cells,), m.
    """
    areas = np.linalg.norm(face_area_vectors(points, _all_faces(cells)), axis=1)
    largest_area = areas.reshape(-1, HEX_FACES.shape[0]).max(axis=1)
    return hex_volumes(points, cells) / largest_area


def scaled_jacobians(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Hex scaled Jacobian: the smallest corner determinant of unit edge vectors.

    At each of the 8 corners the three edges to its neighbours are normalised and the determinant
    of the triad is taken (Verdict / CUBIT, Knupp 2000). 1 for a cube, <= 0 for an inverted corner.

    Args:
        points: node coordinates, shape (n_points, 3), m.
        cells: hex8 connectivity, shape (n_cells, 8).

    Returns:
        Minimum scaled corner Jacobian per cell, shape (n_cells,), dimensionless.
    """
    x = points[cells]  # (n_cells, 8, 3)
    edges = x[:, HEX_CORNER_NEIGHBOURS] - x[:, :, None, :]  # (n_cells, 8, 3, 3)
    lengths = np.linalg.norm(edges, axis=-1, keepdims=True)
    units = np.divide(edges, lengths, out=np.zeros_like(edges), where=lengths > 0.0)
    corner = _triple_product(units[:, :, 0], units[:, :, 1], units[:, :, 2])
    return corner.min(axis=1)


def surface_point_ids(cells: np.ndarray) -> np.ndarray:
    """Nodes on the boundary surface, sorted, shape (n,), int64."""
    faces, _ = boundary_faces(cells)
    return np.unique(faces)
