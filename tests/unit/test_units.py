"""Parsing and formatting of quantities at the edges, against exact unit definitions."""

from __future__ import annotations

import math

import pytest

from batball.errors import SpecError
from batball.units import format_quantity, from_unit, parse_quantity, to_unit

# Exact definitions (NIST SP 811): 1 in = 0.0254 m, 1 lb = 0.45359237 kg, g_n = 9.80665 m/s^2.
INCH = 0.0254
POUND = 0.45359237
OUNCE = POUND / 16.0  # 0.028349523125 kg
LBF = POUND * 9.80665
PSI = LBF / INCH**2  # 6894.757293168361 Pa
MPH = 1609.344 / 3600.0  # 0.44704 m/s


@pytest.mark.parametrize(
    ("text", "dimension", "expected"),
    [
        ("95 mph", "velocity", 95 * 0.44704),
        ("22500 psi", "pressure", 22500 * 6894.757293168361),
        ("6.5 oz", "mass", 6.5 * 0.028349523125),
        ("12 in", "length", 0.3048),
        ("75000 1/s", "frequency", 75000.0),
        ("3.7e-5 lbf*s**2/in**4", "density", 3.7e-5 * LBF / INCH**4),
        ("2 lb", "mass", 2 * POUND),
        ("2 lbm", "mass", 2 * POUND),
        ("4700 lbf", "force", 4700 * LBF),
        ("7190 lbf/in", "stiffness", 7190 * LBF / INCH),
        ("1.2 ms", "time", 1.2e-3),
        ("10 J", "energy", 10.0),
        ("6920 oz*in**2", "moment_of_inertia", 6920 * OUNCE * INCH**2),
        ("0.3", "dimensionless", 0.3),
        ("95mph", "velocity", 95 * MPH),
    ],
)
def test_parse_quantity_returns_si(text: str, dimension: str, expected: float) -> None:
    assert parse_quantity(text, dimension, field="x") == pytest.approx(expected, rel=1e-12)


def test_unit_definitions_match_exact_values() -> None:
    assert from_unit(1.0, "mph") == pytest.approx(0.44704, rel=1e-15)
    assert from_unit(1.0, "psi") == pytest.approx(6894.757, rel=1e-7)
    assert from_unit(1.0, "oz") == pytest.approx(0.028349523125, rel=1e-14)
    assert from_unit(1.0, "lbf") == pytest.approx(4.4482216152605, rel=1e-13)


def test_module_constants_are_the_exact_definitions_and_pints() -> None:
    """The constants the code writes reports with (one home: batball.units) are NIST SP 811's
    exact values, and the same as pint's conversions that the input side uses."""
    from batball import units

    for name, exact, unit in (("IN", INCH, "in"), ("MPH", MPH, "mph"), ("OZ", OUNCE, "oz"),
                              ("LBF", LBF, "lbf"), ("PSI", PSI, "psi")):  # fmt: skip
        value = getattr(units, name)
        assert value == pytest.approx(exact, rel=1e-15), name
        assert value == pytest.approx(from_unit(1.0, unit), rel=1e-15), name


def test_bare_number_is_accepted_only_when_dimensionless() -> None:
    assert parse_quantity(0.45, "dimensionless", field="x") == 0.45
    assert parse_quantity(2, "dimensionless", field="x") == 2.0
    with pytest.raises(SpecError, match="speed"):
        parse_quantity("95", "velocity", field="speed")
    with pytest.raises(SpecError, match="speed"):
        parse_quantity(95.0, "velocity", field="speed")


@pytest.mark.parametrize(
    ("value", "dimension"),
    [
        ("95 psi", "velocity"),
        ("95 psi", "mass"),
        ("6.5 floz", "mass"),  # fluid ounce is a volume, not the mass ounce
        ("ninety mph", "velocity"),
        ("95 furlongs per", "velocity"),
        ("nan mph", "velocity"),
        ("inf psi", "pressure"),
        (float("nan"), "dimensionless"),
        (float("inf"), "dimensionless"),
        (True, "dimensionless"),
        ("20 degC", "dimensionless"),
        ("", "length"),
    ],
)
def test_bad_input_raises_spec_error_naming_field_and_value(value: object, dimension: str) -> None:
    with pytest.raises(SpecError) as info:
        parse_quantity(value, dimension, field="ball.speed")  # type: ignore[arg-type]
    message = str(info.value)
    assert message.startswith("ball.speed: ")
    assert repr(value) in message
    assert "\n" not in message
    assert info.value.field == "ball.speed"


def test_wrong_dimension_message_says_what_is_allowed() -> None:
    with pytest.raises(SpecError, match=r"velocity.*'95 mph'"):
        parse_quantity("95 psi", "velocity", field="speed")


def test_unknown_dimension_name_is_a_programming_error() -> None:
    with pytest.raises(ValueError, match="unknown dimension"):
        parse_quantity("1 m", "lenght", field="x")


@pytest.mark.parametrize(
    ("value_si", "unit", "expected"),
    [
        (155132650.0, "psi", "22500 psi"),
        (75000.0, "1/s", "75000 1/s"),
        (95 * MPH, "mph", "95 mph"),
        (6.93 * OUNCE, "oz", "6.93 oz"),
        (12 * INCH, "in", "12 in"),
        (4390 * LBF, "lbf", "4390 lbf"),
        (6153 * LBF / INCH, "lbf/in", "6153 lbf/in"),
        (1.2e-3, "ms", "1.2 ms"),
        (0.381, "", "0.381"),
        (0.0, "psi", "0 psi"),
        (-750 * PSI, "psi", "-750 psi"),
        (123456.0, "", "123500"),
        (2.5e-7, "", "2.5e-7"),
    ],
)
def test_format_quantity_uses_significant_digits(value_si: float, unit: str, expected: str) -> None:
    assert format_quantity(value_si, unit) == expected


def test_format_quantity_digits_option() -> None:
    assert format_quantity(math.pi, "", digits=6) == "3.14159"
    assert format_quantity(22513.37 * PSI, "psi", digits=7) == "22513.37 psi"


def test_to_unit_and_from_unit_are_inverse() -> None:
    assert to_unit(0.44704, "mph") == pytest.approx(1.0, rel=1e-15)
    assert to_unit(from_unit(6.93, "oz"), "oz") == pytest.approx(6.93, rel=1e-15)
    assert to_unit(1.0, "ms") == pytest.approx(1000.0, rel=1e-15)


def test_a_summary_in_si_renames_and_converts_by_the_key_units() -> None:
    from batball.units import summary_in_si

    si = summary_in_si({
        "ds_lbf_per_in": 7190.0, "inbound_mph": 95.0, "contact_time_ms": 1.03,
        "moi_pivot_oz_in2": 6920.0, "rate_in_per_min": 1.0, "bending_hz": [146.0, 555.0],
        "seed_table2": {"experiment": {"preload_lbf": 186.0}}, "ccor": 0.38, "ball": "type1",
        "warnings": [],
    })  # fmt: skip
    # independent figures: 1 lbf/in = 175.1268 N/m, 1 mph = 0.44704 m/s exactly,
    # 1 oz in^2 = 0.028349523125 kg * 0.0254^2 m^2, 1 lbf = 4.4482216152605 N
    assert si["ds_n_per_m"] == pytest.approx(7190.0 * 175.126835, rel=1e-8)
    assert si["inbound_m_per_s"] == pytest.approx(42.4688, rel=1e-12)
    assert si["contact_time_s"] == pytest.approx(1.03e-3, rel=1e-12)
    assert si["moi_pivot_kg_m2"] == pytest.approx(6920 * 0.028349523125 * 0.0254**2, rel=1e-12)
    assert si["rate_m_per_s"] == pytest.approx(0.0254 / 60, rel=1e-12)
    assert si["bending_hz"] == [146.0, 555.0]  # already SI
    assert si["seed_table2"]["experiment"]["preload_n"] == pytest.approx(186 * 4.4482216152605)
    assert (si["ccor"], si["ball"], si["warnings"]) == (0.38, "type1", [])


def test_the_command_line_prints_si_on_request(capsys: pytest.CaptureFixture[str],
                                               tmp_path) -> None:  # fmt: skip
    import json

    from batball.cli import main

    args = ["props", "--circumferential", "8", "--axial-size", "1 in", "--runs-dir", str(tmp_path)]
    assert main([*args, "--json"]) == 0
    us = json.loads(capsys.readouterr().out)
    assert main([*args, "--json", "--units", "si"]) == 0
    si = json.loads(capsys.readouterr().out)
    assert si["weight_kg"] == pytest.approx(us["weight_oz"] * 0.028349523125, rel=1e-12)
    assert "weight_oz" not in si
