"""The N-term Prony law (MAT_076 style) in the hex kernel: N = 1 is MAT_006, N = 3 follows the
closed-form response to a constant deviatoric rate (docs/physics.md section 1.3, summed over
terms)."""

from __future__ import annotations

import numpy as np
import pytest

from batball.elements.hex8 import compute_hex8_forces
from batball.elements.hex8_block import pack_history, unpack_history
from batball.materials import MATERIAL_LAWS
from batball.materials.prony import relaxation_modulus

PSI = 6894.757293168361
CUBE = 0.01 * np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=np.float64,
)
PRONY3 = {
    "bulk_modulus": 8e5 * PSI, "g_inf": 750 * PSI,
    "g1": 15000 * PSI, "beta1": 75000.0,
    "g2": 5000 * PSI, "beta2": 8000.0,
    "g3": 1750 * PSI, "beta3": 600000.0,
}  # fmt: skip


def drive_pure_shear(constants: np.ndarray, *, rate: float, dt: float, n_steps: int) -> np.ndarray:
    """Shear one cube at constant engineering rate ``rate`` (pure shear, no spin) through the
    kernel; the shear stress sigma_xy after each step [Pa], shape (n_steps,)."""
    n_terms = (constants.size - 2) // 2
    points = CUBE.copy()
    grad = np.array([[0.0, 0.5 * rate, 0.0], [0.5 * rate, 0.0, 0.0], [0.0, 0.0, 0.0]])
    cells = np.arange(8)[None, :]
    history = pack_history(np.array([1e-6]), n_terms=n_terms)
    forces, volume, step, energy = np.zeros((1, 8, 3)), np.zeros(1), np.zeros(1), np.zeros((1, 3))
    tau = np.empty(n_steps)
    for n in range(n_steps):
        velocities = (points - points.mean(axis=0)) @ grad.T
        points = points + dt * velocities
        compute_hex8_forces(
            points, velocities, cells, dt, np.zeros(1, dtype=np.int64), constants[None, :],
            np.array([1000.0]), history, 1, 0.0, 0.0, 0.0, forces, volume, step, energy,
        )  # fmt: skip
        stresses = unpack_history(history, 1)
        tau[n] = stresses["s_inf"][0, 3] + stresses["h"][0, 3::6].sum()
    return tau


def closed_form_shear(values: dict, rate: float, time: np.ndarray) -> np.ndarray:
    """tau(t) = G_inf rate t + sum_i G_i rate (1 - exp(-beta_i t)) / beta_i."""
    tau = values["g_inf"] * rate * time
    for i in (1, 2, 3):
        g, beta = values[f"g{i}"], values[f"beta{i}"]
        tau = tau + g * rate * (1.0 - np.exp(-beta * time)) / beta
    return tau


def test_prony1_constants_are_mat006_constants_with_g1_the_relaxing_modulus() -> None:
    mat006 = {"bulk_modulus": 8e5 * PSI, "g0": 22500 * PSI, "g_inf": 750 * PSI, "beta": 75000.0}
    prony1 = {"bulk_modulus": 8e5 * PSI, "g_inf": 750 * PSI, "g1": 21750 * PSI, "beta1": 75000.0}
    np.testing.assert_allclose(
        MATERIAL_LAWS["prony1"].kernel_constants(prony1),
        MATERIAL_LAWS["mat006"].kernel_constants(mat006), rtol=1e-15,
    )  # fmt: skip


def test_three_term_kernel_with_two_empty_terms_reduces_to_mat006() -> None:
    """The 3-term kernel path (extra rows and factors) with G2 = G3 = 0 gives MAT_006 stress."""
    mat006 = MATERIAL_LAWS["mat006"].kernel_constants(
        {"bulk_modulus": 8e5 * PSI, "g0": 22500 * PSI, "g_inf": 750 * PSI, "beta": 75000.0}
    )
    empty = dict(PRONY3, g1=21750 * PSI, g2=0.0, g3=0.0)
    prony = MATERIAL_LAWS["prony3"].kernel_constants(empty)
    kwargs = {"rate": 1000.0, "dt": 1e-6, "n_steps": 300}
    # round-off only: both paths evaluate the same recursion (fastmath may reorder sums)
    np.testing.assert_allclose(
        drive_pure_shear(prony, **kwargs), drive_pure_shear(mat006, **kwargs), rtol=1e-12
    )


def test_three_term_kernel_matches_the_closed_form_at_constant_rate() -> None:
    """The recursion is exact for a constant rate (docs/physics.md section 1.3), term by term; what
    is left is the pure-shear flow's second-order geometry change over 2 ms at 1000/s (gamma = 2e-2:
    the kernel's L is exact for a linear velocity field, so 1e-6 relative is round-off)."""
    constants = MATERIAL_LAWS["prony3"].kernel_constants(PRONY3)
    rate, dt, n_steps = 1000.0, 1e-6, 2000
    tau = drive_pure_shear(constants, rate=rate, dt=dt, n_steps=n_steps)
    expected = closed_form_shear(PRONY3, rate, dt * np.arange(1, n_steps + 1))
    np.testing.assert_allclose(tau, expected, rtol=1e-6)
    # the three terms matter: one term (G1 alone) differs by far more than the tolerance
    assert (
        abs(expected[-1] - closed_form_shear(dict(PRONY3, g2=0.0, g3=0.0), rate, dt * n_steps))
        > 0.05 * expected[-1]
    )


def test_relaxation_modulus_starts_at_g0_and_ends_at_g_inf() -> None:
    g = relaxation_modulus(PRONY3, np.array([0.0, 1.0]))
    assert g[0] == pytest.approx(PRONY3["g_inf"] + PRONY3["g1"] + PRONY3["g2"] + PRONY3["g3"])
    assert g[1] == pytest.approx(PRONY3["g_inf"])


def test_prony3_material_spec_round_trips_through_toml_and_checks_bounds() -> None:
    from batball.errors import SpecError
    from batball.specs.ball import (
        MaterialSpec,
        material_spec_from_dict,
        material_spec_to_toml_dict,
    )

    spec = MaterialSpec(law="prony3", values=PRONY3)
    table = material_spec_to_toml_dict(spec)
    assert table["g2"] == "5000 psi" and table["beta3"] == "600000 1/s"
    again = material_spec_from_dict(table)
    for name, value in PRONY3.items():
        assert again.values[name] == pytest.approx(value, rel=1e-11)
    with pytest.raises(SpecError) as info:
        MaterialSpec(law="prony3", values=dict(PRONY3, g2=-1.0))
    assert info.value.field == "material.g2"
