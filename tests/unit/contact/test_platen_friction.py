"""Coulomb friction between rigid targets (the barrel test's platens) and shell surfaces.

* ``contact/rigid.add_rigid_friction_forces``, the explicit law, on one slave by hand: a stick
  spring k_t times the tangential slip, the normal part of a slip ignored, capped at mu f_n
  along the trial direction, nothing out of contact, and the old force turned into a new
  tangent plane keeping its size.
* ``contact/shell_contact.rigid_cylinder_slips``, the statics' slip rows, against rigid motions
  with known answers: a translation along the cylinder's axis slides every surface point by it,
  a rotation theta of the node about the bat's axis slides a surface o off the mid-surface by
  o theta, and a motion along the contact normal slides nothing.
"""

from __future__ import annotations

import numpy as np
import pytest

from batball.contact.rigid import add_rigid_friction_forces
from batball.contact.shell_contact import rigid_cylinder_gaps, rigid_cylinder_slips

K_T, MU = 1e6, 0.3  # N/m, -


def friction_step(normal: np.ndarray, slip: np.ndarray,
                  state: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    friction = np.zeros((1, 3)) if state is None else state
    out = np.zeros((1, 3))
    add_rigid_friction_forces(normal[None], slip[None], MU, np.array([K_T]), friction, out)
    return friction[0], out[0]


def test_a_small_slip_sticks_as_a_spring_on_its_tangential_part() -> None:
    normal = np.array([0.0, 0.0, 100.0])  # f_n = 100 N, limit 30 N
    slip = np.array([1e-5, -2e-5, 7e-3])  # the normal part does not count
    friction, out = friction_step(normal, slip)
    np.testing.assert_allclose(friction, [10.0, -20.0, 0.0], rtol=1e-12)
    np.testing.assert_allclose(out, friction, rtol=1e-12)


def test_a_large_slip_slides_at_mu_times_the_normal_force_along_the_trial() -> None:
    normal = np.array([0.0, 100.0, 0.0])
    friction, _ = friction_step(normal, np.array([3e-4, 0.0, 4e-4]))  # trial 500 N
    np.testing.assert_allclose(friction, [MU * 100.0 * 0.6, 0.0, MU * 100.0 * 0.8], rtol=1e-12)


def test_a_free_slave_carries_no_friction() -> None:
    friction, out = friction_step(np.zeros(3), np.array([1e-5, 0.0, 0.0]),
                                  np.array([[5.0, 0.0, 0.0]]))  # fmt: skip
    assert np.all(friction == 0.0) and np.all(out == 0.0)


def test_a_turned_normal_carries_the_old_force_into_the_new_tangent_plane() -> None:
    angle = 0.1
    normal = 100.0 * np.array([np.sin(angle), 0.0, np.cos(angle)])
    friction, _ = friction_step(normal, np.zeros(3), np.array([[10.0, 0.0, 0.0]]))
    assert friction @ normal == pytest.approx(0.0, abs=1e-12)
    assert friction[0] == pytest.approx(10.0 * np.cos(angle) ** 2, rel=1e-12)  # projected


IN = 0.0254
RADIUS, PLATEN = 1.1 * IN, 1.65 * IN  # a barrel's mid-surface and the platen's radius, m
OFFSET = 0.05 * IN  # the outer surface's distance from the mid-surface, m


@pytest.fixture(scope="module")
def ring():  # noqa: ANN201
    """Top half of a bat ring at three stations under a platen whose axis runs along z above
    the bat (load along y): nodes, offsets, the platen's axis point and direction."""
    angles = np.linspace(0.25 * np.pi, 0.75 * np.pi, 5)
    points = np.array([[x, RADIUS * np.cos(a), RADIUS * np.sin(a)]
                       for x in (-0.3 * IN, 0.0, 0.3 * IN) for a in angles])  # fmt: skip
    points = points[:, [0, 2, 1]]  # the angles run about x with y up
    nodes = np.arange(points.shape[0])
    axis_point = np.array([0.0, RADIUS + OFFSET + PLATEN, 0.0])
    return points, nodes, np.full(nodes.size, OFFSET), axis_point, np.array([0.0, 0.0, 1.0])


def slips_of(ring, motion: np.ndarray) -> np.ndarray:  # noqa: ANN001
    points, nodes, offsets, axis_point, axis = ring
    rows = rigid_cylinder_slips(points, nodes=nodes, offsets=offsets, axis_point=axis_point,
                                axis_direction=axis)  # fmt: skip
    return np.column_stack([r @ motion.ravel() for r in rows])


def rigid_cylinder_frame(ring) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """The contact normals (from the gaps' rows) and the distances, by the gaps' function."""
    points, nodes, offsets, axis_point, axis = ring
    gaps = rigid_cylinder_gaps(points, nodes=nodes, offsets=offsets, axis_point=axis_point,
                               axis_direction=axis, radius=PLATEN, stiffness=np.ones(nodes.size))
    normals = gaps.matrix.toarray().reshape(nodes.size, -1, 6)[np.arange(nodes.size), nodes, :3]
    return normals, gaps.initial


def test_a_translation_along_the_platen_axis_slides_every_point_by_it(ring) -> None:  # noqa: ANN001
    motion = np.zeros((ring[0].shape[0], 6))
    motion[:, 2] = 1e-4
    s = slips_of(ring, motion)
    np.testing.assert_allclose(s[:, 0], -1e-4, rtol=1e-12)  # the platen minus the surface
    np.testing.assert_allclose(s[:, 1], 0.0, atol=1e-18)


def test_a_node_turning_about_the_bat_axis_slides_its_surface_by_offset_times_angle(
        ring) -> None:  # noqa: ANN001 # fmt: skip
    points = ring[0]
    theta = 1e-3
    motion = np.zeros((points.shape[0], 6))
    motion[:, 3] = theta
    s = slips_of(ring, motion)
    # the surface point o r moves by theta x (o r): o theta along the hoop direction x cross r,
    # which is the platen's axis at the top node
    radial = points.copy()
    radial[:, 0] = 0.0
    radial /= np.linalg.norm(radial, axis=1, keepdims=True)
    moved = OFFSET * theta * np.cross([1.0, 0.0, 0.0], radial)
    normals, _ = rigid_cylinder_frame(ring)
    along = moved @ ring[4]
    around = np.einsum("ij,ij->i", moved, np.cross(normals, ring[4]))
    np.testing.assert_allclose(s[:, 0], -along, atol=1e-15)
    np.testing.assert_allclose(s[:, 1], -around, atol=1e-15)
    assert np.abs(s).max() == pytest.approx(OFFSET * theta, rel=1e-12)


def test_a_motion_along_each_contact_normal_slides_nothing(ring) -> None:  # noqa: ANN001
    normals, _ = rigid_cylinder_frame(ring)
    motion = np.zeros((ring[0].shape[0], 6))
    motion[:, :3] = 1e-4 * normals
    np.testing.assert_allclose(slips_of(ring, motion), 0.0, atol=1e-18)
