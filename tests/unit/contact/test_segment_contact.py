"""Node-to-segment penalty contact: the bucket search finds every box that holds a node, and the
penalty force on a flat sheet of quads is k p along the normal, its reaction shared by the
bilinear weights (hand-computed expectations)."""

from __future__ import annotations

import numpy as np
import pytest

from batball.contact.segments import (
    MAX_CANDIDATES,
    PENALTY_BLOCK,
    SegmentContact,
    search_candidates,
    segment_boxes,
    slave_penalties,
    slave_penalty_forces,
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
    """Against a brute-force check of every box: each node's candidates in segment order, and
    the segments that are some node's candidate."""
    rng = np.random.default_rng(3)
    sheet, cells = flat_sheet(12, 0.01)
    sheet[:, 2] = 0.002 * rng.standard_normal(len(sheet))  # a warped sheet
    nodes = rng.uniform([-0.01, -0.01, -0.01], [0.13, 0.13, 0.01], size=(500, 3))
    points = np.vstack([sheet, nodes])
    slaves = np.arange(len(sheet), len(points))
    grow = np.full(len(cells), 0.003)
    candidates, counts, active = search_candidates(points, slaves, cells, grow)
    boxes = segment_boxes(points, cells, grow)
    union: set[int] = set()
    outside = 0
    for row, node in enumerate(slaves):
        x = points[node]
        inside = np.all((x >= boxes[:, :3]) & (x <= boxes[:, 3:]), axis=1)
        expected = set(np.flatnonzero(inside))
        assert len(expected) <= MAX_CANDIDATES
        assert list(candidates[row, : counts[row]]) == sorted(expected)
        union |= expected
        outside += not np.all((x >= boxes[:, :3].min(axis=0)) & (x <= boxes[:, 3:].max(axis=0)))
    assert outside > 50  # nodes beyond every box: the search skips them
    assert list(active) == sorted(union)  # the segments any node may touch, once each


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


def tube(radius: float, n_around: int, rings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A polygonal tube about the x axis: ``rings`` (x positions), node j of a ring at angle
    2 pi j / n_around; cells oriented alike (normals outward)."""
    phi = 2.0 * np.pi * np.arange(n_around) / n_around
    points = np.array([[x, radius * np.cos(p), radius * np.sin(p)] for x in rings for p in phi])
    ids = np.arange(points.shape[0]).reshape(len(rings), n_around)
    nxt = np.roll(ids, -1, axis=1)
    cells = np.column_stack([ids[:-1].ravel(), ids[1:].ravel(), nxt[1:].ravel(),
                             nxt[:-1].ravel()])  # fmt: skip
    return points, cells


@pytest.mark.parametrize("smooth", [False, True])
def test_smoothed_normals_remove_the_flip_at_a_facet_corner(smooth: bool) -> None:
    """A node just inside a 16-sided tube, radially under one of its nodes (the corner of four
    facets), nudged 1e-9 rad either way: the facet it takes changes, and so does a facet
    normal's direction, by 2 pi / 16 (the two facets' normals, at -+pi / 16 from the node's
    angle). With smoothed normals (each node's the mean of its facets' normals, radial by
    symmetry) the push is the nodal normals interpolated at the node's projection on the facet,
    which lies s = 0.8 mm / (2 R) of the chord from the corner: it turns by about s sin(2 pi /
    16) rad, 0.29 deg either side, instead of 11.25 (a jump 38 times smaller, not none: the
    projection is along the facet's normal, not the smoothed one)."""
    radius, n_around = 0.03, 16
    sheet, cells = tube(radius, n_around, np.array([0.0, 0.01, 0.02]))
    directions = []
    for nudge in (-1e-9, 1e-9):
        node = (radius - 0.0008) * np.array([0.0, np.cos(nudge), np.sin(nudge)])
        node[0] = 0.01
        points = np.vstack([sheet, node])
        slave = np.array([len(sheet)])
        pair = SegmentContact("tube", slave, np.zeros(1), np.full(1, 1e6), cells,
                              np.full(len(cells), 0.001), two_sided=True, depth=0.0,
                              margin=0.001, smooth=smooth)  # fmt: skip
        pair.search(points)
        forces = np.zeros_like(points)
        assert pair.add_forces(points, forces) == 1
        assert forces.sum(axis=0) == pytest.approx(np.zeros(3), abs=1e-12)  # action = reaction
        moment = np.cross(points, forces).sum(axis=0)  # the pair acts along one line
        assert moment == pytest.approx(np.zeros(3), abs=1e-9 * np.abs(forces).max() * radius)
        directions.append(forces[slave[0]] / np.linalg.norm(forces[slave[0]]))
    tilt = np.degrees(np.arctan2(np.array(directions)[:, 2], -np.array(directions)[:, 1]))
    if smooth:
        theta, s_chord = 2.0 * np.pi / n_around, 0.0008 / (2.0 * radius)
        expected = np.degrees(np.arctan2(s_chord * np.sin(theta),
                                         1.0 - s_chord + s_chord * np.cos(theta)))  # fmt: skip
        assert tilt == pytest.approx([expected, -expected], rel=1e-6)
    else:
        assert sorted(np.abs(tilt)) == pytest.approx([180.0 / n_around] * 2, rel=1e-6)
        assert tilt[0] * tilt[1] < 0.0  # the push turns over as the node crosses the corner


@pytest.mark.parametrize(("two_sided", "smooth"), [(True, False), (False, False), (True, True)])
def test_serial_and_parallel_penalty_kernels_agree_bit_for_bit(two_sided: bool,
                                                               smooth: bool) -> None:  # fmt: skip
    """The pass a contact takes on one thread (small) and the one over the threads (large) are
    one computation per slave: every output the same bits, whichever runs, over more slaves
    than a parallel task holds and not a whole number of tasks."""
    rng = np.random.default_rng(11)
    sheet, cells = flat_sheet(10, 0.01)
    sheet[:, 2] = 0.0005 * rng.standard_normal(len(sheet))
    nodes = rng.uniform([0.0, 0.0, -0.0015], [0.1, 0.1, 0.0015], size=(3 * PENALTY_BLOCK + 5, 3))
    points = np.vstack([sheet, nodes])
    slaves = np.arange(len(sheet), len(points))
    pair = SegmentContact("test", slaves, np.zeros(slaves.size), np.full(slaves.size, 1e6), cells,
                          np.full(len(cells), 0.001), two_sided=two_sided, depth=0.004,
                          margin=0.001, smooth=smooth)  # fmt: skip
    pair.search(points)
    pair.add_forces(points, np.zeros_like(points))  # the planes and nodal normals
    outputs = []
    for parallel in (False, True):
        out = (np.full((slaves.size, 3), np.nan), np.full(slaves.size, -7),
               np.full((slaves.size, 4), np.nan), np.full(slaves.size, np.nan))  # fmt: skip
        arguments = (points, slaves, pair.slave_thickness, pair.slave_stiffness, cells,
                     pair.segment_thickness, two_sided, pair.depth, pair.gap_offset,
                     pair.candidates, pair.n_candidates, pair.planes, pair.node_normals,
                     *out)  # fmt: skip
        if parallel:
            slave_penalty_forces(*arguments)
        else:
            slave_penalties(0, slaves.size, *arguments)
        outputs.append(out)
    assert np.count_nonzero(outputs[0][1] >= 0) > 20  # many slaves in contact
    for serial, parallel in zip(*outputs, strict=True):
        assert np.array_equal(serial, parallel)
