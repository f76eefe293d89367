"""Explicit-solver options: mass-proportional damping and translating rigid targets."""

import numpy as np
import pytest

from batball.contact.rigid import RigidPlane
from batball.errors import SpecError
from batball.materials import MATERIAL_LAWS
from batball.mesh import make_box_mesh
from batball.solvers.explicit import (
    BALANCE,
    ENERGY_COLUMNS,
    ExplicitControls,
    Model,
    RigidContact,
    run_explicit,
)

STEEL = MATERIAL_LAWS["elastic"].kernel_constants({"youngs_modulus": 200e9, "poissons_ratio": 0.3})


def box_model(velocity: np.ndarray, contacts: tuple[RigidContact, ...] = ()) -> Model:
    mesh = make_box_mesh((0.01, 0.01, 0.01), (2, 2, 2))
    return Model(
        mesh=mesh,
        cell_material=np.zeros(mesh.n_cells, dtype=np.int64),
        material_constants=STEEL[None, :],
        densities=np.array([7800.0]),
        contacts=contacts,
        initial_velocity=np.tile(velocity, (mesh.n_points, 1)),
    )


def test_mass_damping_decays_a_rigid_drift_as_exp_minus_c_t() -> None:
    """m dv/dt = -c m v: v = v0 exp(-c t); the dissipated energy closes the balance."""
    c = 5.0e4  # 1/s: over 8e-5 s the speed falls to about exp(-4)
    v0 = np.array([1.0, -2.0, 0.5])
    run = run_explicit(box_model(v0), ExplicitControls(8e-5, mass_damping=c))
    # the recorded velocity is v^(n+1/2), half a step before the recorded time t^(n+1)
    t_mid = run.time[-1] - 0.5 * (run.time[-1] - run.time[-2])
    # central differences: the per-step factor (1 - c h/2)/(1 + c h/2) = exp(-c h) (1 + O((c h)^3))
    # with c h < 0.04 here (h = 0.9 x 5 mm / 5.9 km/s), so after ~100 steps the relative error
    # stays below 1e-3
    assert np.allclose(run.com_velocity[-1], v0 * np.exp(-c * t_mid), rtol=1e-3)
    kinetic0 = 0.5 * run.mass * float(v0 @ v0)
    damping = run.energies[-1, ENERGY_COLUMNS.index("damping")]
    assert damping == pytest.approx(kinetic0 * (1 - np.exp(-2 * c * t_mid)), rel=2e-3)
    assert abs(run.energies[:, BALANCE]).max() < 2e-3 * kinetic0


def test_a_translating_wall_pushes_a_body_at_rest() -> None:
    """A wall moving at u toward a free body starting at rest: momentum reaches about m u
    (the penalty spring throws the body off, so after separation its speed is 2u at most)."""
    u = 0.5
    mesh = make_box_mesh((0.01, 0.01, 0.01), (2, 2, 2))
    bottom = np.flatnonzero(np.isclose(mesh.points[:, 2], 0.0))
    wall = RigidPlane(np.array([0.0, 0.0, -1e-4]), np.array([0.0, 0.0, 1.0]), np.array([0, 0, u]))
    contact = RigidContact("wall", wall, bottom, np.full(bottom.size, 1e7))
    model = box_model(np.zeros(3), (contact,))
    # the balance is checked against 1 % of the final kinetic energy, about m u^2 / 2 or more
    controls = ExplicitControls(end_time=3e-3, max_energy_error=0.05, energy_floor=1e-2 * 1e-3)
    run = run_explicit(model, controls)
    assert run.contact_nodes.any()
    # nothing moves before the wall arrives at t = 1e-4 / u = 0.2 ms
    assert np.all(run.contact_nodes[run.time < 0.19e-3] == 0)
    vz = run.com_velocity[-1, 2]
    assert u < vz <= 2 * u * 1.01
    # the reaction on the wall is opposite to the push: negative z while in contact
    assert run.reaction[run.contact_nodes > 0, 0, 2].max() <= 0.0


def test_a_negative_damping_is_refused() -> None:
    with pytest.raises(SpecError, match="mass_damping"):
        ExplicitControls(end_time=1.0, mass_damping=-1.0)
