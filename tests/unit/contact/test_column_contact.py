"""Node-to-column penalty contact (contact/columns.py) against closed forms: the gap along a
cylinder's and a cone's normal, and forces that are the gradient of the penalty energy
k p^2 / 2 (so the pair is conservative, with no net force or moment), also when a node slides
from one ring's segment to the next."""

from __future__ import annotations

import numpy as np
import pytest

from batball.contact.columns import ColumnContact
from batball.mesh.bat import revolve_rings

N_AROUND = 12
RING_X = np.array([0.0, 0.02, 0.04, 0.06])
SLAVE_T, MASTER_T = 0.002, 0.003  # contact thicknesses (half walls), m
STIFFNESS = 1e6  # N/m


def tube_and_slaves(
    outer: np.ndarray, slave_x: np.ndarray, slave_r: np.ndarray, slave_phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The outer tube's rings (radii ``outer`` at RING_X) and slave nodes at (x, r, phi); returns
    points, master rings (n_rings, N_AROUND) and slave ids."""
    tube, _ = revolve_rings(RING_X, outer, circumferential=N_AROUND)
    slaves = np.column_stack([slave_x, slave_r * np.cos(slave_phi), slave_r * np.sin(slave_phi)])
    points = np.vstack([tube, slaves])
    rings = np.arange(tube.shape[0]).reshape(RING_X.size, N_AROUND)
    return points, rings, np.arange(tube.shape[0], points.shape[0])


def contact(points: np.ndarray, rings: np.ndarray, slaves: np.ndarray) -> ColumnContact:
    return ColumnContact("test", slaves, np.full(slaves.size, SLAVE_T),
                         np.full(slaves.size, STIFFNESS), rings,
                         np.full(points.shape[0], MASTER_T), points)  # fmt: skip


def energy_and_forces(pair: ColumnContact, points: np.ndarray) -> tuple[float, np.ndarray]:
    forces = np.zeros_like(points)
    pair.add_forces(points, forces)
    return 0.5 * float(np.sum(pair.slave_stiffness * pair.penetration**2)), forces


@pytest.mark.parametrize("slope", [0.0, 0.25])
def test_the_gap_is_the_distance_along_the_cylinder_or_cone_normal(slope: float) -> None:
    # master radius R(x) = R0 + x tan(alpha); a slave at radius r below column 5 at x = 0.03:
    # its distance to the cone's generator along the normal is (R(x) - r) cos(alpha)
    r0 = 0.025
    r = r0 + slope * 0.03 - 0.0045
    phi = 2 * np.pi * 5 / N_AROUND
    points, rings, slaves = tube_and_slaves(r0 + slope * RING_X, np.array([0.03]),
                                            np.array([r]), np.array([phi]))  # fmt: skip
    pair = contact(points, rings, slaves)
    _, forces = energy_and_forces(pair, points)
    cos_a = 1.0 / np.hypot(1.0, slope)
    gap = (r0 + slope * 0.03 - r) * cos_a
    p = SLAVE_T + MASTER_T - gap
    assert p > 0
    assert pair.penetration[0] == pytest.approx(p, rel=1e-12)
    normal = np.array([-slope * cos_a, cos_a * np.cos(phi), cos_a * np.sin(phi)])  # outward
    np.testing.assert_allclose(forces[slaves[0]], -STIFFNESS * p * normal, rtol=0, atol=1e-9)
    np.testing.assert_allclose(forces.sum(axis=0), 0.0, atol=1e-9)


def test_forces_are_the_gradient_of_the_penalty_energy_with_no_net_force_or_moment() -> None:
    rng = np.random.default_rng(7)
    x = np.array([0.008, 0.013, 0.027, 0.033, 0.046, 0.052])  # 3 mm or more from the rings
    n = x.size
    points, rings, slaves = tube_and_slaves(
        np.full(RING_X.size, 0.025), x, np.full(n, 0.021),
        2 * np.pi * rng.integers(0, N_AROUND, n) / N_AROUND,
    )  # fmt: skip
    pair = contact(points, rings, slaves)
    # a deformed, turned state: every node moved by up to 0.2 mm, the slaves slid sideways
    points = points + 2e-4 * rng.uniform(-1, 1, points.shape)
    energy, forces = energy_and_forces(pair, points)
    assert (pair.penetration > 0).all()
    h = 1e-8
    for node in np.concatenate([slaves, np.unique(rings[:, :])]):
        for k in range(3):
            shifted = points.copy()
            shifted[node, k] += h
            up, _ = energy_and_forces(pair, shifted)
            shifted[node, k] -= 2 * h
            down, _ = energy_and_forces(pair, shifted)
            # force = -dW/dx by central differences (error ~ h^2 W''' and round-off 1e-16 W / h)
            assert forces[node, k] == pytest.approx(-(up - down) / (2 * h), abs=1e-5)
    scale = np.abs(forces).max()
    assert scale > 1.0
    np.testing.assert_allclose(forces.sum(axis=0), 0.0, atol=1e-12 * scale)
    moment = np.cross(points, forces).sum(axis=0)
    np.testing.assert_allclose(moment, 0.0, atol=1e-12 * scale * 0.03)
    assert energy > 0


def test_a_node_sliding_over_a_ring_changes_segment_without_a_jump() -> None:
    # straight cylinder: the force is the same just before and after the ring at x = 0.04,
    # and the slave's segment follows it
    phi = 2 * np.pi * 3 / N_AROUND
    points, rings, slaves = tube_and_slaves(np.full(RING_X.size, 0.025), np.array([0.035]),
                                            np.array([0.0205]), np.array([phi]))  # fmt: skip
    pair = contact(points, rings, slaves)
    seen = []
    for x in (0.0399999, 0.0400001, 0.055, 0.025):
        moved = points.copy()
        moved[slaves[0], 0] = x
        _, forces = energy_and_forces(pair, moved)
        seen.append((int(pair.ring[0]), forces[slaves[0]].copy()))
    assert [ring for ring, _ in seen] == [1, 2, 2, 1]
    expected = -STIFFNESS * (SLAVE_T + MASTER_T - (0.025 - 0.0205)) * np.array(
        [0.0, np.cos(phi), np.sin(phi)]
    )
    for _, force in seen:
        np.testing.assert_allclose(force, expected, atol=1e-9)


def test_friction_sticks_as_a_spring_then_slides_at_mu_times_the_normal_force() -> None:
    # a node pressed on a straight tube, moved along the axis: the friction force on it is
    # -k delta while k delta < mu f_n (k the pair's penalty), then mu f_n against the motion
    phi = 2 * np.pi * 2 / N_AROUND
    points, rings, slaves = tube_and_slaves(np.full(RING_X.size, 0.025), np.array([0.03]),
                                            np.array([0.0205]), np.array([phi]))  # fmt: skip
    pair = contact(points, rings, slaves)
    pair.start_friction(0.2, points)
    normal = STIFFNESS * (SLAVE_T + MASTER_T - (0.025 - 0.0205))
    for delta, expected in ((1e-8, -STIFFNESS * 1e-8), (2e-8, -STIFFNESS * 2e-8),
                            (1e-3, -0.2 * normal)):  # fmt: skip
        moved = points.copy()
        moved[slaves[0], 0] += delta
        forces = np.zeros_like(points)
        pair.add_forces(moved, forces)
        assert pair.friction_force[0, 0] == pytest.approx(expected, rel=1e-6)
        np.testing.assert_allclose(pair.friction_force[0, 1:], 0.0, atol=1e-9 * normal)
        np.testing.assert_allclose(forces.sum(axis=0), 0.0, atol=1e-9 * normal)


def pressed_pair(mu: float) -> tuple[ColumnContact, np.ndarray, np.ndarray, float]:
    """A slave pressed on a straight tube at phi = 60 deg, friction on: pair, points, the
    slave's outward unit normal, the normal force [N]."""
    phi = 2 * np.pi * 2 / N_AROUND
    points, rings, slaves = tube_and_slaves(np.full(RING_X.size, 0.025), np.array([0.03]),
                                            np.array([0.0205]), np.array([phi]))  # fmt: skip
    pair = contact(points, rings, slaves)
    pair.start_friction(mu, points)
    normal = STIFFNESS * (SLAVE_T + MASTER_T - (0.025 - 0.0205))
    return pair, points, np.array([0.0, np.cos(phi), np.sin(phi)]), normal


def test_a_wall_rotation_slides_the_faces_by_the_thickness_times_the_angle() -> None:
    # Both walls turn by dtheta about the hoop direction e_h = x x e_r with their mid-surfaces
    # still: e_h x e_r = -x, so the slave's face (an arm a_s outside it, towards the master)
    # moves by -a_s dtheta along x and the master's (a_m inside it) by +a_m dtheta: the faces
    # slide by (a_s + a_m) dtheta, the mid-surfaces' distance d = 4.5 mm times dtheta (the
    # penalty's 0.5-mm overlap is shared, a = t d / (t_s + t_m)); friction pulls the slave
    # along with k times the slip, and each face's force has a moment about its node.
    pair, points, radial, normal = pressed_pair(0.2)
    hoop = np.cross([1.0, 0.0, 0.0], radial)
    dtheta = 1e-6
    spin = np.zeros_like(points)
    spin[:] = dtheta * hoop
    pair.rotation_step = spin
    forces = np.zeros_like(points)
    pair.add_forces(points, forces)
    distance = 0.025 - 0.0205
    assert pair.friction_force[0, 0] == pytest.approx(STIFFNESS * distance * dtheta, rel=1e-6)
    np.testing.assert_allclose(pair.friction_force[0, 1:], 0.0, atol=1e-9 * normal)
    # moments: (a_s m) x f on the slave, m = e_r towards the master; the master's sum to
    # (a_m m) x f
    f, arm = pair.friction_force[0], distance / (SLAVE_T + MASTER_T)
    slave_moment = arm * SLAVE_T * np.cross(radial, f)
    np.testing.assert_allclose(pair.moments[pair.slave_nodes[0]], slave_moment, rtol=1e-9)
    master_total = pair.moments.sum(axis=0) - pair.moments[pair.slave_nodes[0]]
    np.testing.assert_allclose(master_total, arm * MASTER_T * np.cross(radial, f), rtol=1e-9)


def test_a_rigid_turn_of_both_walls_does_not_slide_the_faces() -> None:
    # nodes and their rotations turned together about the bat axis: no slip, no friction
    pair, points, _, normal = pressed_pair(0.2)
    angle = 1e-6
    turn = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(angle), -np.sin(angle)],
                     [0.0, np.sin(angle), np.cos(angle)]])  # fmt: skip
    spin = np.zeros_like(points)
    spin[:, 0] = angle
    pair.rotation_step = spin
    pair.add_forces(points @ turn.T, np.zeros_like(points))
    np.testing.assert_allclose(pair.friction_force, 0.0, atol=1e-9 * normal)
