"""O-grid hexahedral sphere: a central cube block and six radial blocks, one per cube face.

Every node is named by an integer key ``(layer, qx, qy, qz)``: ``q`` is the node's position on a
structured cube of half-side ``divisions`` in doubled index units (so both even and odd
``divisions`` give integers) and ``layer`` is 0 in the core and 1 .. divisions outwards in the
shell. Blocks that share a face produce the same keys there, so merging is exact integer
``np.unique`` on keys, and coordinates are computed once per merged node from its key.
"""

from __future__ import annotations

import numpy as np

from batball.mesh.hexa import unique_rows
from batball.mesh.mesh import Mesh

# Shape constants, chosen by a sweep over divisions 4 and 12 for the largest minimum scaled
# Jacobian (~0.75) and the most uniform characteristic length (max/min ~1.5).
CORE_HALF_SIZE = 0.37
"""Half-side of the core cube as a fraction of the radius (before blending)."""
CORE_BLEND = 0.6
"""Fraction by which core nodes are pulled from the cube toward concentric spheres."""
CORE_TAN_WEIGHT = 0.6
"""Weight of the equiangular (tan) spacing on the core grid; 0 = uniform, 1 = fully tan."""
RADIAL_GROWTH = 0.8
"""Ratio of the outermost to the innermost radial spacing in the shell (1 = uniform)."""


def _hex_cells(ids: np.ndarray) -> np.ndarray:
    """Hexes of a structured block of node ids, shape (ni+1, nj+1, nk+1) -> (ni*nj*nk, 8).

    The (i, j, k) axes must be right-handed in space for the cells to have positive volume.
    """
    c = ids
    corners = [
        c[:-1, :-1, :-1], c[1:, :-1, :-1], c[1:, 1:, :-1], c[:-1, 1:, :-1],
        c[:-1, :-1, 1:], c[1:, :-1, 1:], c[1:, 1:, 1:], c[:-1, 1:, 1:],
    ]  # fmt: skip
    return np.stack([corner.ravel() for corner in corners], axis=1)


def _core_keys(divisions: int) -> np.ndarray:
    """Keys of the core block, shape (divisions+1, divisions+1, divisions+1, 4)."""
    q = np.arange(-divisions, divisions + 1, 2)
    qx, qy, qz = np.meshgrid(q, q, q, indexing="ij")
    return np.stack([np.zeros_like(qx), qx, qy, qz], axis=-1)


def _shell_keys(divisions: int, axis: int, sign: int) -> np.ndarray:
    """Keys of the shell block on cube face ``sign * e_axis``, shape (n+1, n+1, n+1, 4).

    Block axes are (t1, t2, radial) with t1 x t2 = sign * e_axis, so the block is right-handed.
    """
    q = np.arange(-divisions, divisions + 1, 2)
    t1, t2 = (axis + 1) % 3, (axis + 2) % 3
    if sign < 0:
        t1, t2 = t2, t1
    qi, qj, layer = np.meshgrid(q, q, np.arange(divisions + 1), indexing="ij")
    keys = np.empty(qi.shape + (4,), dtype=np.int64)
    keys[..., 0] = layer
    keys[..., 1 + axis] = sign * divisions
    keys[..., 1 + t1] = qi
    keys[..., 1 + t2] = qj
    return keys


def _merge_blocks(
    key_blocks: list[np.ndarray],
) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """Merge structured blocks of keys into unique keys and per-block cells, each block's cells
    with axis 0 fastest: a run of ni cells is one line along the block's first axis.

    Returns:
        ``(keys, cells, block_cell_ids)``: unique keys (n_points, 4), cells (n_cells, 8) int64,
        and the cell indices of each block.
    """
    flat = np.concatenate([k.reshape(-1, 4) for k in key_blocks])
    keys, inverse, _ = unique_rows(flat)
    cell_blocks, block_cell_ids, node_start, cell_start = [], [], 0, 0
    for block in key_blocks:  # seven blocks, not a loop over elements
        n_block = block.shape[0] * block.shape[1] * block.shape[2]
        ids = inverse[node_start : node_start + n_block].reshape(block.shape[:3])
        shape = (block.shape[0] - 1, block.shape[1] - 1, block.shape[2] - 1, 8)
        cells = _hex_cells(ids).reshape(shape).transpose(2, 1, 0, 3).reshape(-1, 8)
        cell_blocks.append(cells)
        block_cell_ids.append(np.arange(cell_start, cell_start + cells.shape[0]))
        node_start += n_block
        cell_start += cells.shape[0]
    return keys, np.concatenate(cell_blocks), block_cell_ids


def _slab_order(positions: np.ndarray, n_slabs: int) -> np.ndarray:
    """The order of items at these integer positions (n, 3) along slabs: by the slab of z, then
    of y, then of x, ``n_slabs`` slabs of equal width across the range in each direction.

    Integer arithmetic throughout: the mesh is symmetric, so many positions sit exactly on a
    slab boundary, where floating-point round-off (a radius that differs in the last digit)
    would move them from one slab to the next and renumber the mesh."""
    low, high = positions.min(axis=0), positions.max(axis=0)
    width = np.maximum(high - low, 1)
    slab = np.minimum((positions - low) * n_slabs // width, n_slabs - 1)
    return np.lexsort((slab[:, 0], slab[:, 1], slab[:, 2]))


def _inverse(order: np.ndarray) -> np.ndarray:
    """The inverse of the permutation ``order``: the new index of each old one."""
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return rank


def _x_lines(keys: np.ndarray, divisions: int) -> tuple[np.ndarray, np.ndarray]:
    """Each node's line of nodes running in x, and its place along it: ``(line, place)``, line
    keys (n, 3) and integer places (n,).

    The other four shell blocks' lines of nodes in x (tangential) run across the block, ends
    included: divisions + 1 nodes, the two end nodes shared with the x shell blocks. The core's
    x-lines run on radially through the two x shell blocks, from the sphere at -x to the sphere
    at +x (3 divisions + 1 nodes), except those on the core's faces toward the other blocks:
    their nodes in the x blocks already lie on those blocks' lines, so they hold the core's
    divisions + 1 nodes only. (Giving the shared nodes to the radial lines instead leaves the
    tangential lines' end cells without runs: 82 % of the corners of four-cell groups run on
    the 12-division ball that way, 95 % this way.)"""
    n = divisions
    layer, qx, qy, qz = keys.T
    through = (layer == 0) | ((np.abs(qx) == n) & (np.abs(qy) < n) & (np.abs(qz) < n))
    place = np.where(layer == 0, n + (qx + n) // 2, (qx + n) // 2)
    place = np.where(through & (layer > 0), np.where(qx < 0, n - layer, 2 * n + layer), place)
    return np.stack([qy, qz, np.where(through, -1, layer)], axis=1), place


def _along_x(block: np.ndarray, divisions: int) -> np.ndarray:
    """A block of keys (ni+1, nj+1, nk+1, 4) with its axes turned so that axis 0 runs along
    its x-lines (:func:`_x_lines`), the place rising, and the axes still right-handed."""
    _, place = _x_lines(block.reshape(-1, 4), divisions)
    place = place.reshape(block.shape[:3])
    rising = [np.mean(np.diff(place, axis=a) == 1) for a in range(3)]
    falling = [np.mean(np.diff(place, axis=a) == -1) for a in range(3)]
    axis = int(np.argmax(np.maximum(rising, falling)))
    sign = 1 if rising[axis] >= falling[axis] else -1
    order = [axis] + [a for a in range(3) if a != axis]
    even = order in ([0, 1, 2], [1, 2, 0], [2, 0, 1])
    turned = np.transpose(block, (*order, 3))
    if sign < 0:
        turned = turned[::-1]
    if even != (sign > 0):  # one reflection so far: a second keeps the volumes positive
        turned = turned[:, :, ::-1]
    return turned


def _number_nodes(
    keys: np.ndarray, cells: np.ndarray, divisions: int
) -> tuple[np.ndarray, np.ndarray]:
    """The node order (old ids in new order) and the cells renumbered: line by line
    (:func:`_x_lines`), the lines in the order the cells first use them, each line's nodes in
    order of place.

    The cells run along the same lines, corner 1 one place on from corner 0, so along a line
    each corner's node id rises by one from a cell to the next: the element kernel then loads
    the nodes of four such cells as one run of memory (:mod:`batball.elements.hex8_block`). With
    the cells in slabs, each half's nodes are nearly one run, overlapping only near the middle
    where the update's two threads meet."""
    line, place = _x_lines(keys, divisions)
    _, line_id, _ = unique_rows(line)
    first_use = np.full(line_id.max() + 1, len(cells))
    users = np.broadcast_to(np.arange(len(cells))[:, None], cells.shape)
    np.minimum.at(first_use, line_id[cells], users)
    order = np.lexsort((place, line_id, first_use[line_id]))
    return order, _inverse(order)[cells]


def _core_positions(xi: np.ndarray, radius: float) -> np.ndarray:
    """Core-grid map of cube coordinates xi in [-1, 1]^3, shape (n, 3), to positions [m].

    Partial equiangular spacing, then a partial pull of each cube shell |xi|_inf = s toward the
    sphere of radius s, which rounds off the core's corners.
    """
    angle = CORE_TAN_WEIGHT * np.pi / 4.0
    spaced = np.tan(angle * xi) / np.tan(angle) if angle > 0.0 else xi
    norm_inf = np.abs(spaced).max(axis=1, keepdims=True)
    norm_2 = np.linalg.norm(spaced, axis=1, keepdims=True)
    ratio = np.divide(norm_inf, norm_2, out=np.ones_like(norm_2), where=norm_2 > 0.0)
    return CORE_HALF_SIZE * radius * spaced * ((1.0 - CORE_BLEND) + CORE_BLEND * ratio)


def _sphere_positions(xi: np.ndarray, radius: float) -> np.ndarray:
    """Equiangular projection of cube-surface coordinates xi, shape (n, 3), onto the sphere [m]."""
    direction = np.tan(np.pi / 4.0 * xi)
    return radius * direction / np.linalg.norm(direction, axis=1, keepdims=True)


def _radial_weights(layer: np.ndarray, divisions: int) -> np.ndarray:
    """Fraction of the way from the core face to the sphere, 0 .. 1, for integer layers."""
    t = layer / divisions
    if RADIAL_GROWTH == 1.0:
        return t
    rate = np.log(RADIAL_GROWTH)
    return np.expm1(rate * t) / np.expm1(rate)


def _positions(keys: np.ndarray, divisions: int, radius: float) -> np.ndarray:
    """Node coordinates from merged keys, shape (n_points, 4) -> (n_points, 3), m."""
    xi = keys[:, 1:] / divisions
    weight = _radial_weights(keys[:, 0], divisions)[:, None]
    points = (1.0 - weight) * _core_positions(xi, radius)
    on_shell = keys[:, 0] > 0
    points[on_shell] += weight[on_shell] * _sphere_positions(xi[on_shell], radius)
    outer = keys[:, 0] == divisions
    # place the surface exactly on the sphere (no rounding left from the blend)
    points[outer] = _sphere_positions(xi[outer], radius)
    return points


def make_ball_mesh(radius: float, *, divisions: int = 12) -> Mesh:
    """Hexahedral O-grid mesh of a solid sphere.

    A core of divisions^3 hexes and six shell blocks of divisions^3 hexes each (divisions x
    divisions tangential, divisions radial): 7 * divisions^3 hexes in all (12,096 for 12).
    Surface nodes use an equiangular (gnomonic tan) map of the cube faces; the core cube is
    rounded toward a sphere so that the cells at its corners are not too sharp.

    Args:
        radius: sphere radius, m.
        divisions: cells along each edge of each block, >= 1.

    Returns:
        The mesh, with point sets ``"surface"`` (nodes on the sphere) and ``"centre"`` (the node at
        the centre, for even divisions) and cell sets ``"core"`` and ``"shell"``.
    """
    if divisions < 1:
        raise ValueError(f"divisions must be >= 1, got {divisions}")
    if not radius > 0.0:
        raise ValueError(f"radius must be > 0 m, got {radius}")
    blocks = [_core_keys(divisions)]
    blocks += [_shell_keys(divisions, axis, sign) for axis in range(3) for sign in (1, -1)]
    keys, cells, block_cell_ids = _merge_blocks([_along_x(block, divisions) for block in blocks])
    points = _positions(keys, divisions, radius)
    # whole lines in slabs of their centroids in key space (integer sums of q over the line's
    # corners: the same order on the sphere, as q rises with x, y and z in every block)
    line_sums = keys[cells, 1:].sum(axis=1).reshape(-1, divisions, 3).sum(axis=1)
    lines = _slab_order(line_sums, 2 * divisions)
    order = (lines[:, None] * divisions + np.arange(divisions)).ravel()
    rank = _inverse(order)
    cells, block_cell_ids = cells[order], [np.sort(rank[ids]) for ids in block_cell_ids]
    node_order, cells = _number_nodes(keys, cells, divisions)
    keys, points = keys[node_order], points[node_order]
    point_sets = {"surface": np.nonzero(keys[:, 0] == divisions)[0]}
    centre = np.nonzero((keys[:, 0] == 0) & np.all(keys[:, 1:] == 0, axis=1))[0]
    if centre.size:
        point_sets["centre"] = centre
    cell_sets = {"core": block_cell_ids[0], "shell": np.concatenate(block_cell_ids[1:])}
    return Mesh(points, cells, point_sets, cell_sets)
