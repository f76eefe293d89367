"""MAT_057 / MAT_083 pointwise behaviour against closed forms from the spec's own curve points.

Every expectation is computed here from the example balls' curve points with numpy (np.interp,
trapezoid energies), independently of the law's packed tables and Numba update.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from batball.errors import SpecError
from batball.materials.foam import FoamCurve
from batball.materials.foam_update import N_HISTORY, foam_stress, rate_curve_stress
from batball.specs import MaterialSpec, ball_spec_from_dict, ball_spec_to_toml_dict, load_ball_spec

PSI = 6894.757293168361


def _material(name: str, **changes: float) -> MaterialSpec:
    material = load_ball_spec(name).material
    values = dict(material.values) | changes
    return MaterialSpec(law=material.law, values=values, curves=material.curves)


def _stress(material: MaterialSpec, f: np.ndarray, history: np.ndarray, d=None, dt=1e-6):
    """Cauchy stress (3, 3) [Pa] of one point, history updated in place."""
    scratch = np.zeros((6, 3, 3))
    d = np.zeros((3, 3)) if d is None else d
    foam_stress(f, d, dt, history, material.foam_table().arrays(), scratch)
    return scratch[3].copy()


def _curve(material: MaterialSpec, i: int = 0) -> tuple[np.ndarray, np.ndarray]:
    c = material.curves[i]
    return np.asarray(c.strain), np.asarray(c.stress)


@pytest.mark.parametrize(
    ("scale", "strain_scale"), [(1.0, 1.0), (1.7, 1.0), (1.7, 0.8), (1.0, 1.3)]
)
def test_uniaxial_compression_follows_the_loading_curve(scale: float, strain_scale: float) -> None:
    # the curve used is SFO * f(e / SFA) (LS-DYNA *DEFINE_CURVE's ordinate and abscissa scales)
    material = _material("foam057", curve_scale=scale, curve_strain_scale=strain_scale)
    strain, stress = _curve(material)
    history = np.zeros(N_HISTORY)
    for x in (0.02, 0.05, 0.13, 0.27, 0.45, 0.66):  # increasing: loading all the way
        s = strain_scale * x  # inside the scaled curve (np.interp does not extrapolate)
        sigma = _stress(material, np.diag([1.0 - s, 1.0, 1.0]), history)
        # lateral stretches are 1, so the Cauchy stress equals the nominal stress
        expected = -scale * np.interp(x, strain, stress)
        assert sigma[0, 0] == pytest.approx(expected, rel=1e-12)


def test_the_strain_scale_moves_the_contact_modulus_and_defaults_to_one() -> None:
    material = _material("foam057", curve_scale=2.0)
    document = ball_spec_to_toml_dict(load_ball_spec("foam057"))
    del document["material"]["curve_strain_scale"]  # a spec written before the parameter existed
    assert ball_spec_from_dict(document, source="test").material.values["curve_strain_scale"] == 1.0
    strain, stress = _curve(material)
    steepest = np.max(np.diff(stress) / np.diff(strain))
    youngs = material.values["youngs_modulus"]
    for strain_scale in (1.0, 0.5, 1.4):
        scaled = _material("foam057", curve_scale=2.0, curve_strain_scale=strain_scale)
        # LS-DYNA's max(E, largest slope): the scaled curve's slopes are SFO / SFA times f's
        expected = max(youngs, 2.0 * steepest / strain_scale)
        assert scaled.kernel_constants()[0] == pytest.approx(expected, rel=1e-12)


def test_a_strain_scale_past_the_largest_strain_is_a_spec_error() -> None:
    # foam057's curve ends at 0.7: 0.7 * 1.42 = 0.994 > 0.99
    document = ball_spec_to_toml_dict(load_ball_spec("foam057"))
    document["material"]["curve_strain_scale"] = 1.42
    with pytest.raises(SpecError) as error:
        ball_spec_from_dict(document, source="test")
    assert error.value.field == "material.curve_strain_scale"
    assert "1.41429" in str(error.value)
    document["material"]["curve_strain_scale"] = 1.41
    ball_spec_from_dict(document, source="test")


def test_no_lateral_coupling_and_the_nominal_to_cauchy_map() -> None:
    material = _material("foam057")
    strain, stress = _curve(material)
    sigma = _stress(material, np.diag([0.7, 1.0, 1.0]), np.zeros(N_HISTORY))
    assert sigma[1, 1] == 0.0 and sigma[2, 2] == 0.0  # zero Poisson's ratio: nothing laterally
    assert np.abs(sigma - np.diag(np.diag(sigma))).max() == 0.0
    # compression 0.3 along x with the sides stretched: sigma_1 = tau_1 / (lambda_2 lambda_3),
    # and the sides carry E e / (lambda_1 lambda_3)
    young = material.values["youngs_modulus"]
    sigma = _stress(material, np.diag([0.7, 1.1, 1.05]), np.zeros(N_HISTORY))
    assert sigma[0, 0] == pytest.approx(-np.interp(0.3, strain, stress) / (1.1 * 1.05), rel=1e-12)
    assert sigma[1, 1] == pytest.approx(young * 0.1 / (0.7 * 1.05), rel=1e-12)
    assert sigma[2, 2] == pytest.approx(young * 0.05 / (0.7 * 1.1), rel=1e-12)


def _energy(strain: np.ndarray, stress: np.ndarray, s: float) -> float:
    """int_0^s f: a fine trapezoid of np.interp (exact for the piecewise-linear curve)."""
    x = np.linspace(0.0, s, 20001)
    return float(np.trapezoid(np.interp(x, strain, stress), x))


@pytest.mark.parametrize(
    ("hu", "shape", "strain_scale"),
    [(0.2, 2.0, 1.0), (0.5, 1.0, 1.0), (0.05, 0.5, 1.0), (0.2, 2.0, 0.8)],
)
def test_unloading_scales_the_curve_by_the_hu_shape_damage(
    hu: float, shape: float, strain_scale: float
) -> None:
    material = _material("foam057", hu=hu, shape=shape, curve_strain_scale=strain_scale)
    strain, stress = _curve(material)
    # the scaled curve f(e / SFA): its energy at e is SFA * (f's energy at e / SFA), and SFA
    # cancels in W / W_max
    strain = strain * strain_scale
    history = np.zeros(N_HISTORY)
    _stress(material, np.diag([0.6, 1.0, 1.0]), history)  # load to 40 %
    w_max = _energy(strain, stress, 0.4)
    for s in (0.3, 0.1, 0.02):  # unload
        sigma = _stress(material, np.diag([1.0 - s, 1.0, 1.0]), history)
        ratio = sigma[0, 0] / -np.interp(s, strain, stress)
        damage = (1.0 - hu) * (1.0 - (_energy(strain, stress, s) / w_max) ** shape)
        assert ratio == pytest.approx(1.0 - damage, rel=1e-6)
    # nearly fully unloaded, the stress ratio is HU
    # (W / W_max)^SHAPE < 1e-5 at 1e-6 strain even for SHAPE = 0.5
    sigma = _stress(material, np.diag([1.0 - 1e-6, 1.0, 1.0]), history)
    assert sigma[0, 0] / -np.interp(1e-6, strain, stress) == pytest.approx(hu, rel=1e-3)


def test_mat083_interpolates_linearly_between_the_rate_curves() -> None:
    material = _material("foam083")
    table = material.foam_table()
    (s0, f0), (s1, f1), (s2, f2) = (_curve(material, i) for i in range(3))
    rates = [c.strain_rate for c in material.curves]
    args = table.rates, table.strains, table.stresses, table.counts
    for s in (0.08, 0.35):
        for w in (0.0, 0.25, 0.5, 1.0):
            rate = rates[1] + w * (rates[2] - rates[1])
            expected = (1 - w) * np.interp(s, s1, f1) + w * np.interp(s, s2, f2)
            assert rate_curve_stress(*args, rate, s) == pytest.approx(expected, rel=1e-12)
        assert rate_curve_stress(*args, 0.0, s) == pytest.approx(np.interp(s, s0, f0))
        assert rate_curve_stress(*args, 1e5, s) == pytest.approx(np.interp(s, s2, f2))


def test_mat083_point_takes_its_rate_from_the_compression_rate() -> None:
    # a fast filter (cut-off x dt >> 1) passes the rate through: the stress at 550 1/s is midway
    material = _material("foam083", rate_filter=1e9)
    (_, _), (s1, f1), (s2, f2) = (_curve(material, i) for i in range(3))
    d = np.diag([-550.0, 0.0, 0.0])
    sigma = _stress(material, np.diag([0.8, 1.0, 1.0]), np.zeros(N_HISTORY), d=d, dt=1e-6)
    expected = -0.5 * (np.interp(0.2, s1, f1) + np.interp(0.2, s2, f2))
    assert sigma[0, 0] == pytest.approx(expected, rel=1e-9)


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    k = axis / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


@pytest.mark.parametrize("name", ["foam057", "foam083"])
def test_a_rigid_rotation_leaves_the_stress_invariants_unchanged(name: str) -> None:
    material = _material(name)
    f = np.array([[0.75, 0.08, -0.03], [0.02, 0.93, 0.05], [-0.04, 0.01, 1.04]])
    r = _rotation(np.array([0.3, -1.0, 0.6]), 1.1)
    sigma = _stress(material, f, np.zeros(N_HISTORY))
    rotated = _stress(material, r @ f, np.zeros(N_HISTORY))
    scale = np.abs(sigma).max()
    assert np.trace(rotated) == pytest.approx(np.trace(sigma), rel=1e-12)
    assert np.linalg.det(rotated) == pytest.approx(np.linalg.det(sigma), rel=1e-10)
    i2 = [0.5 * (np.trace(a) ** 2 - np.trace(a @ a)) for a in (sigma, rotated)]
    assert i2[1] == pytest.approx(i2[0], rel=1e-12)
    assert np.abs(rotated - r @ sigma @ r.T).max() < 1e-12 * scale


def _with_curve(name: str, **curve_changes) -> dict:
    document = ball_spec_to_toml_dict(load_ball_spec(name))
    document["material"]["curves"][0].update(curve_changes)
    return document


@pytest.mark.parametrize(
    ("changes", "field"),
    [
        ({"stress": [0.0, 150.0, 240.0, 200.0, 420.0, 560.0, 820.0, 1400.0, 2800.0]}, "stress"),
        ({"strain": [0.0, 0.05, 0.1, 0.1, 0.3, 0.4, 0.5, 0.6, 0.7]}, "strain"),
        ({"stress_unit": "in"}, "stress_unit"),
        ({"stress": [1.0, 150.0, 240.0, 330.0, 420.0, 560.0, 820.0, 1400.0, 2800.0]}, "stress"),
    ],
)
def test_bad_curves_are_spec_errors_naming_the_field(changes: dict, field: str) -> None:
    with pytest.raises(SpecError) as error:
        ball_spec_from_dict(_with_curve("foam057", **changes), source="test")
    assert error.value.field == f"material.curves[0].{field}"


@pytest.mark.parametrize(("law", "hu"), [("foam057", 0.0), ("foam057", 1.5), ("foam083", -0.1)])
def test_hu_outside_its_range_is_a_spec_error(law: str, hu: float) -> None:
    document = ball_spec_to_toml_dict(load_ball_spec(law))
    document["material"]["hu"] = hu
    with pytest.raises(SpecError) as error:
        ball_spec_from_dict(document, source="test")
    assert error.value.field == "material.hu"


def test_mat083_rates_must_increase_and_mat006_takes_no_curves() -> None:
    document = ball_spec_to_toml_dict(load_ball_spec("foam083"))
    document["material"]["curves"][1]["strain_rate"] = "0.001 1/s"
    with pytest.raises(SpecError) as error:
        ball_spec_from_dict(document, source="test")
    assert error.value.field == "material.curves.strain_rate"
    mat006 = load_ball_spec("type1").material
    curve = FoamCurve(strain=(0.0, 0.1), stress=(0.0, 1e6))
    with pytest.raises(SpecError):
        dataclasses.replace(mat006, curves=(curve,))


@pytest.mark.parametrize("name", ["foam057", "foam083"])
def test_foam_ball_spec_round_trips_through_toml(name: str) -> None:
    ball = load_ball_spec(name)
    again = ball_spec_from_dict(ball_spec_to_toml_dict(ball), source="test")
    assert again.material.law == ball.material.law
    assert dict(again.material.values) == pytest.approx(dict(ball.material.values), rel=1e-12)
    for a, b in zip(again.material.curves, ball.material.curves, strict=True):
        assert a.strain == b.strain and a.strain_rate == pytest.approx(b.strain_rate)
        assert np.allclose(a.stress, b.stress, rtol=1e-12, atol=0)
    assert ball.material.curves[0].stress[3] == pytest.approx(330.0 * PSI)


def test_the_returned_tangent_is_the_unloading_slope() -> None:
    # HU 0.1, SHAPE 4: unloading is several times stiffer than loading
    material = _material("foam057", hu=0.1, shape=4.0)
    table = material.foam_table().arrays()
    history = np.zeros(N_HISTORY)
    _stress(material, np.diag([0.6, 1.0, 1.0]), history)  # load to 40 %
    scratch, d = np.zeros((6, 3, 3)), np.zeros((3, 3))

    def tau(s: float) -> tuple[float, float]:
        h = history.copy()
        tangent = foam_stress(np.diag([1.0 - s, 1.0, 1.0]), d, 1e-6, h, table, scratch)
        return scratch[3][0, 0], tangent

    s, step = 0.37, 1e-6
    slope = (tau(s - step)[0] - tau(s + step)[0]) / (2 * step)  # d tau / d e, e = -s
    # the Cauchy tangent lambda_i^2 / J d tau_i / d e_i, J = 1 - s: (1 - s) slope along x, and
    # E / (1 - s) along the unstrained sides (tension branch)
    lateral = material.values["youngs_modulus"] / (1.0 - s)
    assert tau(s)[1] == pytest.approx(max((1.0 - s) * slope, lateral), rel=1e-4)
    strain, stress = _curve(material)
    loading_slope = np.interp(s, strain[1:], np.diff(stress) / np.diff(strain))  # segment 0.3-0.4
    assert slope > 3.0 * loading_slope
