"""MAT_006 pointwise update against its closed forms (docs/physics.md section 1.3; section 8,
case 2)."""

import numpy as np
import pytest

from batball.materials import MATERIAL_LAWS
from batball.materials.viscoelastic import update_viscoelastic_points

PSI = 6894.757293168361
TYPE1 = {"bulk_modulus": 800000 * PSI, "g0": 22500 * PSI, "g_inf": 750 * PSI, "beta": 75000.0}


def shear_history(rate: float, dt: float, n_steps: int, constants: np.ndarray) -> np.ndarray:
    """Shear stress tau_xy after each of n_steps at a constant engineering shear rate [Pa]."""
    s_inf = np.zeros((1, 6))
    h = np.zeros((1, 6))
    de = np.zeros((1, 6))
    de[0, 3] = 0.5 * rate * dt  # tensor shear increment = gamma_dot dt / 2
    tau = np.empty(n_steps)
    for n in range(n_steps):
        update_viscoelastic_points(s_inf, h, de, constants, dt)
        tau[n] = s_inf[0, 3] + h[0, 3]
    return tau


def test_constant_shear_rate_matches_closed_form_1790_psi() -> None:
    # docs/physics.md section 1.3: gamma_dot = 1000/s, dt = 1 us, 2000 steps, ball-1 constants
    # -> 1790.0 psi.
    constants = MATERIAL_LAWS["mat006"].kernel_constants(TYPE1)
    tau = shear_history(1000.0, 1e-6, 2000, constants)
    t = 2e-3
    g0, gi, beta = TYPE1["g0"], TYPE1["g_inf"], TYPE1["beta"]
    closed = gi * 1000.0 * t + (g0 - gi) * 1000.0 * (1 - np.exp(-beta * t)) / beta
    assert tau[-1] == pytest.approx(closed, rel=1e-9)  # exact for a constant rate
    assert tau[-1] / PSI == pytest.approx(1790.0, abs=0.05)


def test_recursion_is_exact_for_any_step_size_at_constant_rate() -> None:
    constants = MATERIAL_LAWS["mat006"].kernel_constants(TYPE1)
    coarse = shear_history(1000.0, 1e-4, 20, constants)[-1]  # beta dt = 7.5, far from small
    fine = shear_history(1000.0, 1e-7, 20000, constants)[-1]
    assert coarse == pytest.approx(fine, rel=1e-8)


def test_held_strain_relaxes_to_g_inf_with_time_constant_one_over_beta() -> None:
    constants = MATERIAL_LAWS["mat006"].kernel_constants(TYPE1)
    g0, gi, beta = TYPE1["g0"], TYPE1["g_inf"], TYPE1["beta"]
    gamma = 0.01
    s_inf, h = np.zeros((1, 6)), np.zeros((1, 6))
    de = np.zeros((1, 6))
    de[0, 3] = 0.5 * gamma
    update_viscoelastic_points(s_inf, h, de, constants, 1e-12)  # a step strain
    assert s_inf[0, 3] + h[0, 3] == pytest.approx(g0 * gamma, rel=1e-6)
    de[:] = 0.0
    hold = 1.0 / beta
    for _ in range(1000):
        update_viscoelastic_points(s_inf, h, de, constants, hold / 1000)
    expected = gi * gamma + (g0 - gi) * gamma * np.exp(-1.0)
    # the "step" is a ramp over 1e-12 s, which relaxes by beta dt / 2 = 4e-8 meanwhile
    assert s_inf[0, 3] + h[0, 3] == pytest.approx(expected, rel=1e-7)
    for _ in range(30):
        update_viscoelastic_points(s_inf, h, de, constants, hold)
    assert s_inf[0, 3] + h[0, 3] == pytest.approx(gi * gamma, rel=1e-9)


def test_elastic_law_maps_to_k_and_g() -> None:
    e, nu = 50e6, 0.3
    k, g0, gi, beta = MATERIAL_LAWS["elastic"].kernel_constants(
        {"youngs_modulus": e, "poissons_ratio": nu}
    )
    assert k == pytest.approx(e / (3 * (1 - 2 * nu)))
    assert g0 == gi == pytest.approx(e / (2 * (1 + nu)))
    assert beta == 0.0
