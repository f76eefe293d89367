"""The embedded default bat against the seed's Table 1 (weight, MOI at the 6-in pivot, BP)."""

from __future__ import annotations

import pytest

from batball.lab.props import bat_mass_properties
from batball.specs import load_bat_spec, load_seed_tables

TOLERANCE = 0.005  # 0.5 % for each quantity (issue 6)


@pytest.fixture(scope="module")
def props():
    return bat_mass_properties(load_bat_spec("default"))[0]


@pytest.fixture(scope="module")
def table_1():
    return load_seed_tables().bat


def test_weight_matches_table_1(props, table_1) -> None:
    assert props.mass == pytest.approx(table_1.weight_exp, rel=TOLERANCE)


def test_moi_about_the_6_in_pivot_matches_table_1(props, table_1) -> None:
    assert props.moi_pivot == pytest.approx(table_1.moi_exp, rel=TOLERANCE)


def test_balance_point_matches_table_1(props, table_1) -> None:
    assert props.balance_point == pytest.approx(table_1.balance_point_exp, rel=TOLERANCE)


def test_moi_about_the_centre_of_mass_is_the_parallel_axis_value(props, table_1) -> None:
    # docs/physics.md section 4.3: I_cm = I_p - m d^2 = 1947.5 oz*in^2 for Table 1's numbers
    oz_in2 = 0.028349523125 * 0.0254**2
    assert props.moi_cm / oz_in2 == pytest.approx(1947.5, rel=2 * TOLERANCE)
