"""Free parameters: declared names only, bounds inside the declaration, log mapping."""

from __future__ import annotations

import math

import pytest

from batball.calibrate import make_parameter_space, parse_bounds
from batball.errors import SpecError
from batball.materials import MATERIAL_LAWS

PSI = 6894.757293168361
MAT006 = MATERIAL_LAWS["mat006"]
START = {"bulk_modulus": 8e5 * PSI, "g0": 22500 * PSI, "g_inf": 750 * PSI, "beta": 75000.0}


def test_log_scale_default_interval_is_a_decade_each_way_and_midpoint_is_geometric() -> None:
    space = make_parameter_space(MAT006, START, ["g0", "beta"])
    g0 = space.free[0]
    assert (g0.lower, g0.upper) == pytest.approx((2250 * PSI, 225000 * PSI))
    assert g0.from_unit(0.5) == pytest.approx(math.sqrt(g0.lower * g0.upper))
    assert space.start_point() == pytest.approx([0.5, 0.5])
    assert space.values([1.0, 0.0])["beta"] == pytest.approx(7500.0)
    assert space.values([1.0, 0.0])["g_inf"] == START["g_inf"]  # fixed parameters keep theirs


def test_given_bounds_are_parsed_with_units() -> None:
    bounds = parse_bounds(["g0=10000 psi:50000 psi", "beta=1e4 1/s:2e5 1/s"], MAT006)
    space = make_parameter_space(MAT006, START, ["g0", "beta"], bounds=bounds)
    assert (space.free[0].lower, space.free[0].upper) == pytest.approx((1e4 * PSI, 5e4 * PSI))
    assert space.free[1].upper == pytest.approx(2e5)


def test_unknown_parameter_is_refused_listing_the_declared_ones() -> None:
    with pytest.raises(SpecError) as info:
        make_parameter_space(MAT006, START, ["g0", "gamma"])
    assert info.value.field == "free" and info.value.value == "gamma"
    assert "bulk_modulus, g0, g_inf, beta" in info.value.allowed


@pytest.mark.parametrize(
    "bound", ["g0=-5 psi:50000 psi", "g0=1000 psi:1e14 psi", "g0=5e4 psi:1e4 psi"]
)
def test_bounds_outside_the_declaration_name_field_value_and_range(bound: str) -> None:
    with pytest.raises(SpecError) as info:
        make_parameter_space(MAT006, START, ["g0"], bounds=parse_bounds([bound], MAT006))
    assert info.value.field == "bounds.g0"
    assert "within the declaration 0 psi" in info.value.allowed


def test_bound_with_wrong_unit_is_refused() -> None:
    with pytest.raises(SpecError) as info:
        parse_bounds(["beta=1e4 psi:2e5 psi"], MAT006)
    assert info.value.field == "bounds.beta"
