"""Penalty forces of the rigid targets against the closed form of a node's depth.

A node inside a half-cylinder's impact face (within its length, on the front side, nearer the
axis than the radius R) is pushed out along its radial direction by k (R - r); a node inside a
wall by k times its depth along the normal. Nodes a hair either side of the cylinder's surface
(1e-12 of R) check that the decision is the depth's sign, whatever shortcut the kernel takes for
nodes clearly outside.
"""

from __future__ import annotations

import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane, add_rigid_contact_forces

R = 0.0254  # [m]
K = 2.0e6  # [N/m]


def run(target: RigidCylinder | RigidPlane, points: np.ndarray, time: float = 0.0) -> tuple:
    """Forces (n, 3) [N], reaction (3,) [N], deepest penetration [m] and nodes in contact."""
    kind, params = target.packed()
    n = points.shape[0]
    forces = np.zeros((n, 3))
    reaction, penetration = np.zeros((1, 3)), np.zeros(1)
    active = add_rigid_contact_forces(
        points, time, np.arange(n), np.full(n, K), np.array([0, n]), np.array([kind]),
        params[None, :], forces, reaction, penetration,
    )  # fmt: skip
    return forces, reaction[0], penetration[0], active


def test_a_half_cylinder_pushes_inside_nodes_out_radially() -> None:
    rng = np.random.default_rng(11)
    velocity = np.array([-3.0, 0.5, 0.0])
    time = 2e-4
    target = RigidCylinder(axis_point=np.array([0.01, 0.0, 0.0]), axis=np.array([0.0, 1.0, 0.0]),
                           front=np.array([1.0, 0.0, 0.0]), radius=R, length=0.3,
                           velocity=velocity)  # fmt: skip
    # radial distances from deep inside to far outside, and a hair either side of R
    radii = np.concatenate([R * rng.uniform(0.2, 2.0, 200), R * np.array([1 - 1e-12, 1 + 1e-12])])
    angle = rng.uniform(-np.pi, np.pi, radii.size)  # the back half (cos < 0) is not a face
    along = rng.uniform(-0.2, 0.2, radii.size)  # beyond +-0.15 m: past the cylinder's ends
    along[-2:] = 0.0
    angle[-2:] = 0.3
    radial = np.stack([np.cos(angle), np.zeros_like(angle), np.sin(angle)], axis=1)
    moved = target.axis_point + velocity * time
    points = moved + radii[:, None] * radial + along[:, None] * target.axis

    depth = R - radii
    touching = (depth > 0) & (np.cos(angle) >= 0) & (np.abs(along) <= 0.15)
    expected = np.where(touching[:, None], K * depth[:, None] * radial, 0.0)
    forces, reaction, penetration, active = run(target, points, time)

    assert touching[-2] and not touching[-1]  # the hair inside and the hair outside
    assert active == touching.sum() > 20
    np.testing.assert_allclose(forces, expected, rtol=1e-9, atol=K * R * 1e-12)
    np.testing.assert_allclose(reaction, -expected.sum(axis=0), rtol=1e-9)
    assert np.isclose(penetration, depth[touching].max(), rtol=1e-9)


def test_a_wall_pushes_nodes_behind_its_face_out_along_its_normal() -> None:
    rng = np.random.default_rng(12)
    normal = np.array([0.0, 0.6, 0.8])
    wall = RigidPlane(point=np.array([0.0, 0.01, 0.0]), normal=normal)
    points = rng.uniform(-0.03, 0.03, (100, 3))
    depth = -((points - wall.point) @ normal)
    expected = np.where(depth[:, None] > 0, K * depth[:, None] * normal, 0.0)
    forces, reaction, penetration, active = run(wall, points)
    assert active == (depth > 0).sum() > 10
    np.testing.assert_allclose(forces, expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(reaction, -expected.sum(axis=0), rtol=1e-12)
    assert np.isclose(penetration, depth.max(), rtol=1e-12)
