"""Kinematics of the explicit hex: objectivity, the bar wave speed and the stable time step."""

import numpy as np
import pytest

from batball.elements.hex8_block import pack_history, unpack_history
from batball.materials import MATERIAL_LAWS
from batball.mesh import make_box_mesh
from batball.solvers.explicit import ExplicitControls, ExplicitSolver, Model


def solid_model(mesh, constants: np.ndarray, density: float, velocity=None) -> Model:
    """A free body (no contacts) of one material."""
    v = np.zeros((mesh.n_points, 3)) if velocity is None else velocity
    return Model(
        mesh=mesh,
        cell_material=np.zeros(mesh.n_cells, dtype=np.int64),
        material_constants=constants[None, :],
        densities=np.array([density]),
        contacts=(),
        initial_velocity=v,
    )


def rotation_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def voigt_to_matrix(v: np.ndarray) -> np.ndarray:
    return np.array([[v[0], v[3], v[5]], [v[3], v[1], v[4]], [v[5], v[4], v[2]]])


def test_rigid_rotation_carries_the_stress_along_exactly() -> None:
    # docs/physics.md section 6.8: a rigidly rotating pre-stressed element keeps
    # sigma(t) = Q sigma0 Q^T.
    mesh = make_box_mesh((0.01, 0.02, 0.015), (1, 1, 1))
    constants = MATERIAL_LAWS["mat006"].kernel_constants(
        {"bulk_modulus": 5e9, "g0": 1.5e8, "g_inf": 5e6, "beta": 0.0}
    )
    solver = ExplicitSolver(solid_model(mesh, constants, 1000.0), ExplicitControls(end_time=1.0))
    s0 = np.array([3e6, -1e6, -2e6, 1.5e6, -0.5e6, 0.8e6])
    solver.state.history = pack_history(solver.work.volume0, s_inf=s0[None, :])
    x0 = mesh.points.copy()
    n_steps, total_angle, dt = 90, 0.5 * np.pi, 1e-6
    for n in range(1, n_steps + 1):
        old = x0 @ rotation_z(total_angle * (n - 1) / n_steps).T
        new = x0 @ rotation_z(total_angle * n / n_steps).T
        solver.state.points[:] = new
        solver.state.velocities[:] = (new - old) / dt  # chord velocity: mid-step geometry is
        solver.state.dt = dt  # the chord midpoint, so D = 0 exactly
        solver.element_forces()
    q = rotation_z(total_angle)
    expected = q @ voigt_to_matrix(s0) @ q.T
    history = unpack_history(solver.state.history, 1)
    got = voigt_to_matrix(history["s_inf"][0])
    assert np.allclose(got, expected, rtol=0, atol=1e-9 * np.abs(s0).max())
    assert np.linalg.eigvalsh(got) == pytest.approx(np.linalg.eigvalsh(voigt_to_matrix(s0)))
    assert abs(history["pressure"][0]) < 1e-6 * 5e9  # no volume change


def bar_model(n_elements: int, pushed: int):
    """A 0.2-m bar of nu = 0 material (c = sqrt(E/rho) = 447.2 m/s), its left end moving."""
    mesh = make_box_mesh((0.2, 0.005, 0.005), (n_elements, 1, 1))
    e_mod, rho = 200e6, 1000.0
    constants = MATERIAL_LAWS["elastic"].kernel_constants(
        {"youngs_modulus": e_mod, "poissons_ratio": 0.0}
    )
    velocity = np.zeros((mesh.n_points, 3))
    velocity[mesh.points[:, 0] <= pushed * 0.2 / n_elements + 1e-12, 0] = 1.0
    return solid_model(mesh, constants, rho, velocity), np.sqrt(e_mod / rho)


def test_first_time_step_is_tssfac_times_length_over_wave_speed() -> None:
    moving, c = bar_model(80, 10)
    model = solid_model(moving.mesh, moving.material_constants[0], 1000.0)  # at rest: no
    solver = ExplicitSolver(model, ExplicitControls(end_time=1.0))
    solver.cycle()  # compression, hence no bulk-viscosity term in the step
    assert solver.state.dt == pytest.approx(0.9 * 0.0025 / c, rel=1e-12)  # L_e = V / A_max


def test_wave_front_reaches_the_far_end_at_the_bar_speed() -> None:
    model, c = bar_model(80, 10)
    solver = ExplicitSolver(model, ExplicitControls(end_time=1.0))
    far = model.mesh.point_sets["x1"]
    while True:
        solver.cycle()
        if solver.state.velocities[far, 0].mean() > 0.5:  # the doubled front's half height
            break
    distance = 0.2 - 10 * 0.0025
    # the half-height point of a smeared front moves at c; 2 % is about one element's transit
    assert solver.state.time == pytest.approx(distance / c, rel=0.02)


def test_an_inverted_element_stops_the_run_saying_which_and_when() -> None:
    from batball.errors import SimulationError
    from batball.solvers.explicit import BulkViscosity

    mesh = make_box_mesh((0.01, 0.01, 0.01), (1, 1, 1))
    velocity = np.zeros((mesh.n_points, 3))
    velocity[mesh.points[:, 2] > 0.005, 2] = -1e5  # the top face crosses the bottom in one step
    constants = MATERIAL_LAWS["elastic"].kernel_constants(
        {"youngs_modulus": 1e9, "poissons_ratio": 0.3}
    )
    controls = ExplicitControls(end_time=1e-3, bulk_viscosity=BulkViscosity(enabled=False))
    solver = ExplicitSolver(solid_model(mesh, constants, 1000.0, velocity), controls)
    with pytest.raises(SimulationError, match=r"element 0 inverted at t = 0\.00\d+ ms \(step 1\)"):
        solver.run()
