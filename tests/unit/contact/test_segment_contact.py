"""Node-to-segment penalty contact: the bucket search finds every box that holds a node, and the
penalty force on a flat sheet of quads is k p along the normal, its reaction shared by the
bilinear weights (hand-computed expectations)."""

from __future__ import annotations

import numpy as np
import pytest

from batball.contact.segments import (
    MAX_CANDIDATES,
    SegmentContact,
    search_candidates,
    segment_boxes,
)


def flat_sheet(n: int, size: float) -> tuple[np.ndarray, np.ndarray]:
    """n x n unit quads of side ``size`` in the plane z = 0, normals +z."""
    xs = np.arange(n + 1) * size
    gx, gy = np.meshgrid(xs, xs, indexing="ij")
    points = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)])
    ids = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    cells = np.column_stack(
        [ids[:-1, :-1].ravel(), ids[1:, :-1].ravel(), ids[1:, 1:].ravel(), ids[:-1, 1:].ravel()]
    )
    return points, cells


def test_bucket_search_finds_every_box_holding_a_node() -> None:
    rng = np.random.default_rng(3)
    sheet, cells = flat_sheet(12, 0.01)
    sheet[:, 2] = 0.002 * rng.standard_normal(len(sheet))  # a warped sheet
    nodes = rng.uniform([-0.01, -0.01, -0.01], [0.13, 0.13, 0.01], size=(500, 3))
    points = np.vstack([sheet, nodes])
    slaves = np.arange(len(sheet), len(points))
    grow = np.full(len(cells), 0.003)
    candidates, counts = search_candidates(points, slaves, cells, grow)
    boxes = segment_boxes(points, cells, grow)
    for row, node in enumerate(slaves):
        x = points[node]
        inside = np.all((x >= boxes[:, :3]) & (x <= boxes[:, 3:]), axis=1)
        expected = set(np.flatnonzero(inside))
        assert len(expected) <= MAX_CANDIDATES
        assert set(candidates[row, : counts[row]]) == expected


def sheet_contact(points: np.ndarray, cells: np.ndarray, slaves: np.ndarray, *, two_sided: bool,
                  thickness: float, k: float) -> SegmentContact:  # fmt: skip
    pair = SegmentContact(
        "test", slaves, np.zeros(slaves.size), np.full(slaves.size, k), cells,
        np.full(len(cells), thickness), two_sided=two_sided, depth=0.004, margin=0.001,
    )  # fmt: skip
    pair.search(points)
    return pair


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_shell_penalty_force_and_reaction(side: float) -> None:
    """A node 0.4 mm from a 1-mm half-thickness shell penetrates 0.6 mm from either side."""
    sheet, cells = flat_sheet(4, 0.01)
    node = np.array([[0.0125, 0.0175, side * 0.0004]])  # in cell (1, 1), xi = -0.5, eta = 0.5
    points = np.vstack([sheet, node])
    slave = np.array([len(sheet)])
    pair = sheet_contact(points, cells, slave, two_sided=True, thickness=0.001, k=1e6)
    forces = np.zeros_like(points)
    assert pair.add_forces(points, forces) == 1
    assert forces[slave[0]] == pytest.approx([0.0, 0.0, side * 1e6 * 0.0006], rel=1e-9)
    assert forces.sum(axis=0) == pytest.approx(np.zeros(3), abs=1e-9)  # action = reaction
    cell = cells[pair.contact_segment[0]]
    shares = -forces[cell, 2] / forces[slave[0], 2]
    expected = 0.25 * np.array([1.5 * 0.5, 0.5 * 0.5, 0.5 * 1.5, 1.5 * 1.5])  # N_a(-0.5, 0.5)
    assert shares == pytest.approx(expected, rel=1e-9)


def test_solid_face_is_one_sided_and_separated_nodes_feel_nothing() -> None:
    sheet, cells = flat_sheet(4, 0.01)
    nodes = np.array([
        [0.015, 0.015, -0.001],  # 1 mm under an outward (+z) face: pushed out along +z
        [0.015, 0.025, -0.006],  # deeper than the 4-mm depth: not taken as contact
        [0.025, 0.025, 0.0005],  # outside
        [0.060, 0.015, -0.001],  # beside the sheet
    ])  # fmt: skip
    points = np.vstack([sheet, nodes])
    slaves = np.arange(len(sheet), len(points))
    pair = sheet_contact(points, cells, slaves, two_sided=False, thickness=0.0, k=2e5)
    forces = np.zeros_like(points)
    assert pair.add_forces(points, forces) == 1
    assert forces[slaves[0]] == pytest.approx([0.0, 0.0, 2e5 * 0.001], rel=1e-9)
    assert np.all(forces[slaves[1:]] == 0.0)


def test_initial_overlap_is_ignored_when_offset() -> None:
    sheet, cells = flat_sheet(3, 0.01)
    node = np.array([[0.015, 0.015, 0.0007]])
    points = np.vstack([sheet, node])
    slave = np.array([len(sheet)])
    pair = sheet_contact(points, cells, slave, two_sided=True, thickness=0.001, k=1e6)
    pair.gap_offset = pair.initial_overlap(points)
    assert pair.gap_offset[0] == pytest.approx(0.0003, rel=1e-9)
    forces = np.zeros_like(points)
    pair.search(points)
    assert pair.add_forces(points, forces) == 0
    points[slave[0], 2] -= 0.0001  # 0.1 mm further in: force from there on
    pair.add_forces(points, forces)
    assert forces[slave[0], 2] == pytest.approx(1e6 * 0.0001, rel=1e-6)
