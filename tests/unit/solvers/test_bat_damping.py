"""The bat's damping relative to its rigid turn (solvers/ball_bat.advance_bat, ``damping``):
a deformation velocity with no forces decays as (1 - c dt)^n, a rigid turn about the pivot is
not damped, and the angular momentum about the pivot is kept."""

import numpy as np
import pytest

from batball.solvers.ball_bat import advance_bat

DT = 1e-6  # s
C = 2000.0  # 1/s: c dt = 0.002 a step


def free_bat(seed: int = 0) -> dict:
    """Twelve free nodes around a pivot at the origin and a two-node band, no forces."""
    rng = np.random.default_rng(seed)
    points = rng.uniform(-0.3, 0.3, (14, 3))
    mass = np.repeat(rng.uniform(0.01, 0.02, (14, 1)), 6, axis=1)
    mass[:, 3:] = 1e-6
    moving = np.ones(14, dtype=np.bool_)
    band = np.array([12, 13])
    moving[band] = False
    return {"points": points, "mass": mass, "moving": moving, "band": band,
            "pivot": np.zeros(3)}  # fmt: skip


def step(bat: dict, velocity: np.ndarray, omega: np.ndarray, damping: float) -> np.ndarray:
    out = np.zeros(5)
    n = velocity.shape[0]
    advance_bat(np.zeros((n, 6)), np.zeros((n, 3)), bat["mass"], velocity, bat["points"],
                bat["moving"], bat["band"], bat["pivot"], 1.0, omega, damping, np.zeros((n, 6)),
                DT, DT, DT, out)  # fmt: skip
    return out


def test_a_deformation_velocity_decays_as_the_closed_form() -> None:
    bat = free_bat()
    velocity = np.zeros((14, 6))
    velocity[:12, 2] = np.linspace(-1.0, 1.0, 12)  # along the axis of the turn: no rigid part
    start = velocity.copy()
    omega = np.zeros(1)
    dissipated = 0.0
    kinetic0 = 0.5 * np.sum(bat["mass"] * velocity**2)
    for _ in range(100):
        dissipated -= step(bat, velocity, omega, C)[4]
    # no forces: v_{n+1} = v_n - dt c v_n (the damping force from the velocity before)
    np.testing.assert_allclose(velocity[:12, 2], start[:12, 2] * (1 - C * DT) ** 100, rtol=1e-12)
    kinetic = 0.5 * np.sum(bat["mass"] * velocity**2)
    # the damping's work is the kinetic energy lost (central differences: to O(c dt))
    assert dissipated == pytest.approx(kinetic0 - kinetic, rel=2 * C * DT)


def test_a_rigid_turn_about_the_pivot_is_not_damped() -> None:
    bat = free_bat()
    w = 3.0  # rad/s
    velocity = np.zeros((14, 6))
    velocity[:, 0] = -w * bat["points"][:, 1]
    velocity[:, 1] = w * bat["points"][:, 0]
    velocity[:, 5] = w
    before = velocity.copy()
    out = step(bat, velocity, np.array([w]), C)
    np.testing.assert_allclose(velocity[:12], before[:12], rtol=0, atol=1e-15)
    assert abs(out[4]) < 1e-15


def test_the_damping_keeps_the_angular_momentum_about_the_pivot() -> None:
    bat = free_bat(1)
    rng = np.random.default_rng(2)
    velocity = rng.normal(size=(14, 6))
    velocity[12:] = 0.0
    omega = np.zeros(1)
    momentum = [step(bat, velocity, omega, 0.0)[3]]  # the first step sets the band's velocity
    for _ in range(50):
        momentum.append(step(bat, velocity, omega, C)[3])
    assert np.ptp(momentum) < 1e-12 * np.max(np.abs(momentum))
