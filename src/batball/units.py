"""Quantities at the edges: ``"95 mph"``, ``"22500 psi"``, ``"6.5 oz"`` -> SI floats, and back.

Inside batball every number is an SI float64 (m, kg, s, N, Pa, J, kg/m^3, 1/s). This module is the
only place that knows about other units: :func:`parse_quantity` where input is read,
:func:`format_quantity` / :func:`to_unit` where output is written. Parsing uses one module-level
pint ``UnitRegistry`` (created on first use); conversion factors are cached per unit string, so the
scalar calls stay cheap.

Unit names are pint's: ``oz`` is the avoirdupois mass ounce (28.349523125 g), ``lb`` (and ``lbm``)
the mass pound, ``lbf`` the pound-force (``lb`` * 9.80665 m/s^2), ``psi`` = lbf/in^2,
``mph`` = 0.44704 m/s. Only multiplicative units are supported (no degC).
"""

from __future__ import annotations

import math
import re
from functools import cache, lru_cache
from typing import Any

from batball.errors import SpecError

#: Exact conversion factors to SI for the few units that code writes out by hand (a person's
#: report, a message, a plot axis). Definitions: NIST SP 811 (the international inch, foot and
#: avoirdupois pound; standard gravity 9.80665 m/s^2), the same numbers pint uses.
IN = 0.0254  # m
MPH = 0.44704  # m/s (5280 * 12 in per 3600 s)
OZ = 0.028349523125  # kg (avoirdupois ounce, 0.45359237 kg / 16)
LBF = 4.4482216152605  # N (0.45359237 kg * 9.80665 m/s^2)
PSI = 6894.757293168361  # Pa (LBF / IN**2, rounded to the nearest double)
OZ_IN2 = OZ * IN * IN  # kg m^2 (moment of inertia, seed Table 1's unit)

#: Dimension names accepted by :func:`parse_quantity`: pint dimensionality and an example input.
DIMENSIONS: dict[str, tuple[str, str]] = {
    "length": ("[length]", "12 in"),
    "mass": ("[mass]", "6.5 oz"),
    "velocity": ("[length] / [time]", "95 mph"),
    "pressure": ("[mass] / [length] / [time] ** 2", "22500 psi"),
    "frequency": ("1 / [time]", "75000 1/s"),
    "density": ("[mass] / [length] ** 3", "3.74e-5 lbf*s**2/in**4"),
    "force": ("[mass] * [length] / [time] ** 2", "4700 lbf"),
    "stiffness": ("[mass] / [time] ** 2", "7190 lbf/in"),
    "time": ("[time]", "1.2 ms"),
    "energy": ("[mass] * [length] ** 2 / [time] ** 2", "10 J"),
    "moment_of_inertia": ("[mass] * [length] ** 2", "6920 oz*in**2"),
    "dimensionless": ("", "0.3"),
}

# A leading real number, then the unit expression (possibly empty).
_NUMBER_THEN_UNIT = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")


@cache
def unit_registry() -> Any:
    """The one pint ``UnitRegistry`` of the package (created on first use, ~0.3 s)."""
    import pint

    registry: Any = pint.UnitRegistry()
    registry.define("lbm = pound")
    return registry


@lru_cache(maxsize=512)
def _unit_factor(unit: str) -> tuple[float, Any]:
    """SI value of one ``unit`` and its pint dimensionality; raises ValueError if not a unit."""
    if unit.strip() == "":
        return 1.0, unit_registry().get_dimensionality("")
    registry = unit_registry()
    try:
        one = registry.Quantity(1.0, unit).to_base_units()
        zero = registry.Quantity(0.0, unit).to_base_units()
    except Exception as exc:  # pint raises many kinds (undefined name, syntax, tokenizer)
        raise ValueError(f"not a unit: {unit!r}") from exc
    if zero.magnitude != 0.0:
        raise ValueError(f"offset unit not supported: {unit!r}")
    return float(one.magnitude), one.dimensionality


@lru_cache(maxsize=64)
def _dimensionality(dimension: str) -> Any:
    """Pint dimensionality of a dimension name from :data:`DIMENSIONS`."""
    if dimension not in DIMENSIONS:
        raise ValueError(f"unknown dimension {dimension!r}; expected one of {sorted(DIMENSIONS)}")
    return unit_registry().get_dimensionality(DIMENSIONS[dimension][0])


def allowed_text(dimension: str) -> str:
    """What a field of ``dimension`` accepts, in words: ``"a velocity, e.g. '95 mph'"``."""
    example = DIMENSIONS[dimension][1]
    if dimension == "dimensionless":
        return f"a finite number, e.g. {example}"
    noun = dimension.replace("_", " ")
    article = "an" if noun[0] in "aeiou" else "a"
    return f"{article} {noun} with its unit, e.g. '{example}'"


def parse_quantity(value: str | float | int | Any, dimension: str, *, field: str) -> float:
    """Parse a value with its unit and return it in SI.

    Args:
        value: ``"95 mph"``, ``"22500 psi"``, ``"3.7e-5 lbf*s**2/in**4"`` or a pint quantity; a
            bare number (str or float) only when ``dimension`` is ``"dimensionless"``.
        dimension: a key of :data:`DIMENSIONS` (``"length"``, ``"velocity"``, ``"pressure"`` ...).
        field: dotted path of the input field, for the error message.

    Returns:
        The value in SI units (m, kg, m/s, Pa, 1/s, kg/m^3, N, N/m, s, J, kg m^2).

    Raises:
        SpecError: unparsable text, a missing or wrong unit, or a non-finite value.
        ValueError: ``dimension`` is not a known dimension name (a programming error).
    """
    expected = _dimensionality(dimension)
    magnitude, unit = _split(value, dimension, field=field)
    try:
        factor, dimensionality = _unit_factor(unit)
    except ValueError:
        raise SpecError(field, value, allowed_text(dimension)) from None
    if dimensionality != expected:
        raise SpecError(field, value, allowed_text(dimension))
    return magnitude * factor


def _split(value: str | float | int | Any, dimension: str, *, field: str) -> tuple[float, str]:
    """Split ``value`` into a finite magnitude and a unit string ("" for a bare number); a pint
    quantity (of any registry) gives its magnitude and its unit's name."""
    if hasattr(value, "magnitude") and hasattr(value, "units") and not isinstance(value, str):
        try:
            magnitude, unit = float(value.magnitude), format(value.units, "D")
        except (TypeError, ValueError):
            raise SpecError(field, value, allowed_text(dimension)) from None
        if not math.isfinite(magnitude) or (unit == "dimensionless" and dimension != unit):
            raise SpecError(field, value, allowed_text(dimension))
        return magnitude, "" if unit == "dimensionless" else unit
    if isinstance(value, bool) or not isinstance(value, str | float | int):
        raise SpecError(field, value, allowed_text(dimension))
    if isinstance(value, str):
        match = _NUMBER_THEN_UNIT.match(value)
        if match is None:
            raise SpecError(field, value, allowed_text(dimension))
        magnitude, unit = float(match.group(1)), match.group(2)
    else:
        magnitude, unit = float(value), ""
    if not math.isfinite(magnitude):
        raise SpecError(field, value, allowed_text(dimension))
    if unit == "" and dimension != "dimensionless":
        raise SpecError(field, value, allowed_text(dimension))
    return magnitude, unit


def to_unit(value_si: float, unit: str) -> float:
    """Convert an SI value to ``unit`` (``to_unit(0.44704, "mph") == 1.0``)."""
    return value_si / _unit_factor(unit)[0]


def from_unit(value: float, unit: str) -> float:
    """Convert a value in ``unit`` to SI (``from_unit(1.0, "psi") == 6894.757...``)."""
    return value * _unit_factor(unit)[0]


def format_quantity(value_si: float, unit: str, *, digits: int = 4) -> str:
    """Format an SI value in ``unit`` with ``digits`` significant digits, trailing zeros stripped.

    Args:
        value_si: the value in SI units.
        unit: display unit (``"psi"``, ``"1/s"``, ``"mph"``, ``"oz"``, ``"lbf/in"``, ``"ms"``);
            ``""`` for a bare number.
        digits: significant digits.

    Returns:
        E.g. ``format_quantity(155132650.0, "psi") == "22500 psi"``.
    """
    number = format_number(to_unit(value_si, unit), digits=digits)
    return f"{number} {unit}" if unit else number


def format_number(value: float, *, digits: int = 4) -> str:
    """``value`` to ``digits`` significant digits; e-notation outside 1e-4 <= |value| < 1e15."""
    if not math.isfinite(value):
        return str(value)
    rounded = float(f"{value:.{digits - 1}e}")
    if rounded == 0.0:
        return "0"
    if not 1e-4 <= abs(rounded) < 1e15:
        mantissa, exponent = f"{rounded:.{digits - 1}e}".split("e")
        return f"{_strip_zeros(mantissa)}e{int(exponent)}"
    decimals = max(0, digits - 1 - math.floor(math.log10(abs(rounded))))
    return _strip_zeros(f"{rounded:.{decimals}f}")


def _strip_zeros(text: str) -> str:
    """Drop trailing zeros after a decimal point, and the point itself if nothing follows."""
    return text.rstrip("0").rstrip(".") if "." in text else text


#: The unit suffixes of summary keys (``ds_lbf_per_in``), longest first, each with its SI
#: suffix and the factor to SI. Suffixes already SI (``_j``, ``_hz``, ``_s``, ``_deg``) stay.
SUMMARY_UNITS: tuple[tuple[str, str, float], ...] = (
    ("_oz_in2", "_kg_m2", OZ_IN2),
    ("_lbf_per_in", "_n_per_m", LBF / IN),
    ("_in_per_min", "_m_per_s", IN / 60.0),
    ("_in2", "_m2", IN * IN),
    ("_lbf", "_n", LBF),
    ("_psi", "_pa", PSI),
    ("_mph", "_m_per_s", MPH),
    ("_oz", "_kg", OZ),
    ("_in", "_m", IN),
    ("_ms", "_s", 1e-3),
    ("_g", "_kg", 1e-3),
)


def summary_in_si(summary: Any) -> Any:
    """``summary`` (a run's summary.json object) with every key that names a non-SI unit renamed
    to its SI unit and its numbers converted (nested tables and lists too): ``ds_lbf_per_in``
    becomes ``ds_n_per_m``. Keys without a unit suffix are kept as they are."""
    if isinstance(summary, dict):
        out = {}
        for key, value in summary.items():
            for suffix, si_suffix, factor in SUMMARY_UNITS:
                if isinstance(key, str) and key.endswith(suffix):
                    out[key[: -len(suffix)] + si_suffix] = _scaled(value, factor)
                    break
            else:
                out[key] = summary_in_si(value)
        return out
    if isinstance(summary, list):
        return [summary_in_si(v) for v in summary]
    return summary


def _scaled(value: Any, factor: float) -> Any:
    """Numbers in ``value`` (a number, a list or a table of them) times ``factor``."""
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, int | float):
        return value * factor
    if isinstance(value, list):
        return [_scaled(v, factor) for v in value]
    if isinstance(value, dict):
        return {k: _scaled(v, factor) for k, v in value.items()}
    return value
