"""The co-rotational MITC4 shell of the explicit solvers (issue 8) against the statics' MITC4
stiffness and the invariances a co-rotational element owes.

The bat's own coarse mesh (8 around, 1-in rings: curved, several laminates, unsymmetric layups)
with the statics' section. Expectations:

* **Small motions = the statics.** With the nodes moved by eps u and turned by eps theta, the
  forces are -K (eps u, eps theta) with K the statics' assembled stiffness, up to the next order
  in eps: relative error proportional to eps (measured 1.2e-6 at eps = 1e-5 of a 1-mm field,
  1.2e-7 at 1e-6); asserted below 1e-5 and shrinking tenfold with eps.
* **Rigid motions strain nothing**, whatever their size: forces below 1e-12 of the small-motion
  forces' scale for a 1.3-rad turn and a 0.5-m shift.
* **Objectivity.** A deformed state turned rigidly by Q (nodes and nodal rotations) gives the
  same forces and moments turned by Q: to 1e-9 relative (round-off of the frames).
* **Balance.** The forces sum to zero and their moment about any point vanishes, in a state with
  rotations of 0.2 rad between neighbouring nodes (the removed second-order moment, module docs).
* **Rotation vectors by the series.** A corner rotation whose squared sine lies just below the
  series' threshold gets angle / sine once, not again by atan2 after the series has scaled it
  over the threshold; there and across the series' range (squared sines 1e-12 to the threshold)
  the angle is arcsin(s) to 1e-15 relative: the series' truncation is below 1.2e-18 of the sum
  (SERIES_SINE2), the rest is rounding, a few units of 2.2e-16 in the Horner sum, the sine and
  arcsin. Above the threshold atan2 gives the angle, to the same tolerance.
* **Assembly.** The nodes' forces are the sums of their cells': the forces of the whole mesh
  against those of its even and its odd cells taken as two meshes (each node's neighbouring
  cells alternate between the two) and added, to 1e-9 of the largest (measured 2e-16): the
  halves' cells of one shape may take their common stiffness from another cell of that shape,
  equal to SHAPE_TOLERANCE (1e-12 m on cells of 2-25 mm), which bounds the difference far
  below a corner lost or counted twice (of the order of the forces). The chunks split into 1,
  2, 3 or 7 runs, where nodes shared by two runs take the kernel's other path, give the same
  bits (each node sums its corners in cell order); a node of no cell gets zero. This mesh has
  kinds split over two chunks, a kind of exactly one chunk and kinds of a few cells.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from batball.elements.shell_corotational import (
    CHUNK,
    DOF_GROUP,
    PRODUCT_ORDER,
    SERIES_SINE2,
    W_COS,
    W_D,
    W_F,
    W_ROWS,
    CorotationalShellForces,
    advance_rotations,
    cell_and_node_forces,
    critical_step,
    distinct_cells,
    dof,
    local_product,
    rotation_runs,
    rotation_vectors,
)
from batball.elements.shell_stiffness import ShellSection, assemble_shell_stiffness, shell_section
from batball.mesh.bat import make_bat_mesh
from batball.models.bat import bat_laminates
from batball.specs import load_bat_spec

IN = 0.0254


@pytest.fixture(scope="module")
def bat():  # noqa: ANN201
    spec = load_bat_spec("default")
    mesh = make_bat_mesh(spec, circumferential=8, axial_size=1.0 * IN)
    return mesh, shell_section(*bat_laminates(spec, mesh))


def forces_at(mesh, section, points: np.ndarray, turn: np.ndarray) -> np.ndarray:  # noqa: ANN001
    """Forces on the nodes with the nodes at ``points`` and each node turned by the rotation
    vector ``turn`` (n, 3) from the undeformed state (one call, dt = 1)."""
    shells = CorotationalShellForces(mesh.points, mesh.cells, section)
    velocity = np.zeros((mesh.n_points, 6))
    velocity[:, 3:] = turn
    out = np.zeros((mesh.n_points, 6))
    shells(points, velocity, 1.0, out)
    return out


def field(n: int, seed: int = 3) -> np.ndarray:
    """A random field: 1 mm on translations, 1 rad on rotations."""
    u = np.random.default_rng(seed).standard_normal((n, 6))
    u[:, :3] *= 1e-3
    return u


def test_small_motions_give_the_statics_forces(bat) -> None:  # noqa: ANN001
    mesh, section = bat
    stiffness = assemble_shell_stiffness(mesh, section)
    u = field(mesh.n_points)
    errors = []
    for eps in (1e-5, 1e-6):
        got = forces_at(mesh, section, mesh.points + eps * u[:, :3], eps * u[:, 3:])
        expected = -(stiffness @ (eps * u).ravel()).reshape(-1, 6)
        errors.append(np.abs(got - expected).max() / np.abs(expected).max())
    assert errors[0] < 1e-5
    assert errors[1] < 0.2 * errors[0]  # the error is of the next order in eps


def test_rigid_motions_strain_nothing(bat) -> None:  # noqa: ANN001
    mesh, section = bat
    turn = np.array([0.3, -1.1, 0.7])  # 1.3 rad
    q = Rotation.from_rotvec(turn).as_matrix()
    got = forces_at(mesh, section, mesh.points @ q.T + 0.5, np.tile(turn, (mesh.n_points, 1)))
    scale = np.abs(forces_at(mesh, section, mesh.points + 1e-6 * field(mesh.n_points)[:, :3],
                             1e-6 * field(mesh.n_points)[:, 3:])).max()  # fmt: skip
    assert np.abs(got).max() < 1e-12 * scale / 1e-6


def deformed_then_turned(mesh, section, q_turn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """Forces of a deformed state (1e-4 of the field), and of the same state turned by Q."""
    u = 0.1 * field(mesh.n_points)
    plain = forces_at(mesh, section, mesh.points + u[:, :3], u[:, 3:])
    q = Rotation.from_rotvec(q_turn)
    composed = (q * Rotation.from_rotvec(u[:, 3:])).as_rotvec()  # Q R_a
    turned = forces_at(mesh, section, (mesh.points + u[:, :3]) @ q.as_matrix().T, composed)
    return plain, turned


def test_forces_turn_with_the_body(bat) -> None:  # noqa: ANN001
    mesh, section = bat
    q_turn = np.array([-0.4, 0.9, 1.6])
    plain, turned = deformed_then_turned(mesh, section, q_turn)
    q = Rotation.from_rotvec(q_turn).as_matrix()
    expected = np.hstack([plain[:, :3] @ q.T, plain[:, 3:] @ q.T])
    np.testing.assert_allclose(turned, expected, atol=1e-9 * np.abs(plain).max())


def test_forces_are_balanced_in_a_strongly_turned_state(bat) -> None:  # noqa: ANN001
    mesh, section = bat
    u = 0.2 * field(mesh.n_points, seed=5)  # 0.2 rad between nodes, 0.2 mm
    points = mesh.points + u[:, :3]
    got = forces_at(mesh, section, points, u[:, 3:])
    scale = np.abs(got).max()
    np.testing.assert_allclose(got[:, :3].sum(axis=0), 0.0, atol=1e-9 * scale)
    moment = np.cross(points - 0.3, got[:, :3]).sum(axis=0) + got[:, 3:].sum(axis=0)
    np.testing.assert_allclose(moment, 0.0, atol=1e-9 * scale * np.abs(points).max())


def test_cells_of_a_ring_share_one_stiffness(bat) -> None:  # noqa: ANN001
    mesh, section = bat
    relative = mesh.points[mesh.cells] - mesh.points[mesh.cells].mean(axis=1, keepdims=True)
    _, kind = distinct_cells(relative @ np.eye(3), section)  # not turned into the frames
    assert kind.max() + 1 > mesh.n_cells // 8  # the axes differ from cell to cell
    shells = CorotationalShellForces(mesh.points, mesh.cells, section)
    assert shells.stiffness.shape[0] <= mesh.n_cells // 8  # in the frames: one per ring


def test_the_dof_rows_group_each_kind_of_dof() -> None:
    rows = [[dof(a, k) for a in range(4)] for k in range(6)]
    assert sorted(r for group in rows for r in group) == list(range(24))  # one row each
    for k, group in enumerate(rows):  # a kind of dof fills one 4-row block, corner by corner
        assert group == [4 * DOF_GROUP[k] + a for a in range(4)]
    # K0's dof 6 a + k (corner by corner) sits at row dof(a, k) of the kernel's product
    assert all(PRODUCT_ORDER[dof(a, k)] == 6 * a + k for a in range(4) for k in range(6))


def test_the_local_product_skips_only_blocks_of_zeros(bat) -> None:  # noqa: ANN001
    """f = K0 d on the kernel's dof rows against NumPy's dense product of the element's K0 in
    its own dof order (corner by corner), for every kind of cell of the bat."""
    mesh, section = bat
    shells = CorotationalShellForces(mesh.points, mesh.cells, section)
    ordered, nonzero = shells.product
    # w couples with neither u, v nor theta_z; theta_z with neither theta_x nor theta_y
    assert np.all(nonzero.sum(axis=(1, 2)) == 26)
    rng = np.random.default_rng(3)
    row = np.array([[dof(a, k) for k in range(6)] for a in range(4)]).ravel()
    for kind in range(shells.stiffness.shape[0]):
        d = rng.standard_normal((24, CHUNK))  # corner a's dof k in row 6 a + k
        w = np.full(W_ROWS * CHUNK, np.nan)
        w.reshape(W_ROWS, CHUNK)[W_D + row] = d
        local_product(ordered[kind], nonzero[kind], w)
        got = w.reshape(W_ROWS, CHUNK)[W_F + row]
        expected = shells.stiffness[kind] @ d
        # the two sum a row's 24 terms in different orders: each within 24 eps of the row's sum
        # of |K d| <= 5 sum |K| (|d| < 5 for these samples), 2.7e-14 sum |K|; a wrongly skipped
        # block would be off by a whole entry of K, many orders above this
        np.testing.assert_allclose(
            got, expected, rtol=0.0, atol=1e-13 * np.abs(shells.stiffness[kind]).sum(axis=1).max()
        )


def test_the_critical_step_is_the_stiffest_element_mode() -> None:
    """Two nodes of unit mass on one cell's worth of stiffness: omega_max^2 from a dense
    eigen-solve of M^-1 K, the same definition by another route (numpy's eigvalsh)."""
    spec = load_bat_spec("default")
    mesh = make_bat_mesh(spec, circumferential=8, axial_size=4.0 * IN)
    section = shell_section(*bat_laminates(spec, mesh))
    shells = CorotationalShellForces(mesh.points, mesh.cells, section)
    mass = np.random.default_rng(2).uniform(0.5, 2.0, (mesh.n_points, 6)) * 1e-3
    stiffness = assemble_shell_stiffness(mesh, section).toarray()
    scale = 1.0 / np.sqrt(mass.ravel())
    largest = np.linalg.eigvalsh(scale[:, None] * stiffness * scale[None, :]).max()
    assert critical_step(shells, mass) == pytest.approx(2.0 / np.sqrt(largest), rel=1e-3)


@pytest.mark.parametrize("runs", [1, 2, 3, 7])
def test_the_nodes_forces_are_the_sums_of_their_cells(bat, runs: int) -> None:  # noqa: ANN001
    mesh, section = bat
    points = np.vstack([mesh.points, [[1.0, 1.0, 1.0]]])  # and a node of no cell
    u = field(points.shape[0])

    def forces(part: slice, n_runs: int) -> np.ndarray:
        cells = mesh.cells[part]
        shells = CorotationalShellForces(points, cells, ShellSection(
            *(a[part] for a in (section.abd, section.shear, section.areal_mass,
                                section.rotary_inertia))))  # fmt: skip
        out = np.full((points.shape[0], 6), np.nan)
        cell_and_node_forces(points + u[:, :3], shells.cells, shells.state.history,
                             shells.constants, shells.product,
                             (shells.chunk_start, shells.chunk_kind), shells.corners,
                             shells.corner_kinds(n_runs), shells.shared, out, n_runs)  # fmt: skip
        return out

    sizes = np.diff(CorotationalShellForces(points, mesh.cells, section).chunk_start)
    assert sizes.max() == CHUNK and sizes.min() < CHUNK  # full and partial chunks
    out = forces(slice(None), runs)
    # every node's neighbouring cells alternate between the halves
    expected = forces(slice(0, None, 2), 1) + forces(slice(1, None, 2), 1)
    scale = np.abs(expected).max()
    assert scale > 0.0 and np.all(out[-1] == 0.0)
    np.testing.assert_allclose(out, expected, rtol=0.0, atol=1e-9 * scale)
    # each node sums its corners in cell order, whichever run makes them: the same bits
    np.testing.assert_array_equal(out, forces(slice(None), 1))


@pytest.mark.parametrize(
    "sine2",
    [SERIES_SINE2 * (1.0 - below) for below in (1e-3, 1e-6, 1e-9)]  # the series' edge
    + [1e-12, 1e-8, 1e-5, 1e-4, 1e-3, 3e-3]  # across its range
    + [SERIES_SINE2 * 1.001, 0.1, 0.5],  # atan2's
)
def test_a_rotation_vector_is_its_angle_once(sine2: float) -> None:
    axis = np.array([2.0, -1.0, 2.0]) / 3.0
    s = np.sqrt(sine2) * axis
    w = np.zeros(W_ROWS * CHUNK)
    for a in range(4):
        for k in range(3):
            w[(W_D + dof(a, 3 + k)) * CHUNK] = s[k]
        w[(W_COS + a) * CHUNK] = np.sqrt(1.0 - sine2)
    rotation_vectors(w, 1)
    expected = np.arcsin(np.sqrt(sine2)) * axis
    got = np.array([w[(W_D + dof(0, 3 + k)) * CHUNK] for k in range(3)])
    np.testing.assert_allclose(got, expected, rtol=1e-15)


@pytest.mark.parametrize("runs", [1, 2, 3, 7])
def test_each_run_turns_the_nodes_of_its_first_corners(bat, runs: int) -> None:  # noqa: ANN001
    """rotation_runs: every node once, in the run that holds the chunk of the first cell (in
    the kernel's cell order) that has it, by a search over the cells; a node of no cell in run
    0. And the rotations advanced run by run are those of one run (each node's own update)."""
    mesh, section = bat
    points = np.vstack([mesh.points, [[1.0, 1.0, 1.0]]])  # and a node of no cell
    shells = CorotationalShellForces(points, mesh.cells, section)
    n_chunks = shells.chunk_kind.size
    order, start = rotation_runs(shells.corners[4], n_chunks, runs)
    assert np.array_equal(np.sort(order), np.arange(points.shape[0]))
    expected = np.zeros(points.shape[0], dtype=np.int64)
    taken = min(runs, n_chunks)
    bounds = [r * n_chunks // taken for r in range(taken + 1)]
    for node in range(mesh.n_points):
        first_cell = np.flatnonzero((shells.cells == node).any(axis=1))[0]
        chunk = np.searchsorted(shells.chunk_start, first_cell, side="right") - 1
        expected[node] = np.searchsorted(bounds, chunk, side="right") - 1
    got = np.empty_like(expected)
    for r in range(taken):
        got[order[start[r] : start[r + 1]]] = r
    assert np.array_equal(got, expected) and start[-1] == points.shape[0]
    velocity = field(points.shape[0])
    turned = [shells.state.history.copy() for _ in range(2)]
    advance_rotations(turned[0], velocity, 0.01, (order, start))  # series and trig
    advance_rotations(turned[1], velocity, 0.01, rotation_runs(shells.corners[4], n_chunks, 1))
    np.testing.assert_array_equal(turned[0], turned[1])
    assert np.abs(turned[0] - shells.state.history).max() > 1e-6  # they did turn
