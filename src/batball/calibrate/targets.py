"""Calibration targets: measured quantities of a ball at given speeds, with weights.

A target file (TOML) lists one table per measurement, units in strings::

    [[target]]
    quantity = "ccor"            # a key of QUANTITIES
    speed = "95 mph"
    value = 0.380                # a bare number for dimensionless quantities
    weight = 1.0                 # optional (default 1)

    [[target]]
    quantity = "dynamic_stiffness"
    speed = "95 mph"
    value = "7190 lbf/in"

    [[target]]
    quantity = "compression"     # ASTM F1888: force at 0.25 in between flat plates
    value = "375 lbf"            # no speed: the test is quasi-static

A CSV file has the header ``quantity,speed,value,weight`` (weight optional) with the same strings
(an empty speed for a compression target).
The embedded default is the seed's experiment columns (Tables 5-8) for ball types 1 and 2 (the
seed reports no measured compression).
"""

from __future__ import annotations

import csv
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from batball.errors import SpecError
from batball.lab.measures import ImpactMeasures
from batball.units import format_quantity, parse_quantity, to_unit


@dataclass(frozen=True)
class Quantity:
    """A measurable quantity of a ball-impact test.

    Attributes:
        name: the key users type (``"ccor"``).
        test: the virtual test that measures it (``"ccor"``, ``"cor"`` or ``"compression"``).
        attribute: the field of the run's measures it reads (an
            :class:`~batball.lab.measures.ImpactMeasures` field for the impact tests; for the
            compression test see :func:`batball.calibrate.evaluate.compression_measures`).
        dimension: pint dimension name of its value; display_unit: unit for reports.
        tolerance: the issue's goal as a relative error (CCOR 1 %, peak 3 %, DS and contact
            time 5 %; the flat wall's peak force 3 % like the cylinder's; compression 5 %, the
            scatter of its reading between meshes,
            docs/notes/compression.md); residuals are divided by it so that every goal weighs the
            same.
    """

    name: str
    test: str
    attribute: str
    dimension: str
    display_unit: str
    tolerance: float


#: The quantities a target may name, keyed by the names users type.
QUANTITIES: dict[str, Quantity] = {
    q.name: q
    for q in (
        Quantity("ccor", "ccor", "restitution", "dimensionless", "", 0.01),
        Quantity("cor", "cor", "restitution", "dimensionless", "", 0.01),
        Quantity("dynamic_stiffness", "ccor", "dynamic_stiffness", "stiffness", "lbf/in", 0.05),
        Quantity("peak_force", "ccor", "peak_force", "force", "lbf", 0.03),
        Quantity("contact_time", "ccor", "contact_time", "time", "ms", 0.05),
        Quantity("compression", "compression", "compression_fit", "force", "lbf", 0.05),
        # the flat wall's peak force (ASTM F1887 rig with a load cell; COR route)
        Quantity("wall_peak_force", "cor", "peak_force", "force", "lbf", 0.03),
    )
}

#: The tests that take no speed (quasi-static); their targets carry speed 0.
STATIC_TESTS = frozenset({"compression"})

MAX_SPEED = 100.0  # m/s, the impact lab's limit (223 mph)


@dataclass(frozen=True)
class Target:
    """One measured value.

    Attributes:
        quantity: a key of :data:`QUANTITIES`.
        speed: inbound speed [m/s]; 0 for a quasi-static test (compression).
        value: the measurement, SI.
        weight: relative weight in the objective (> 0).
        reference: an optional comparison value, SI (the seed's LS-DYNA result), or None.
    """

    quantity: str
    speed: float
    value: float
    weight: float = 1.0
    reference: float | None = None

    def __post_init__(self) -> None:
        if self.quantity not in QUANTITIES:
            raise SpecError("target.quantity", self.quantity, f"one of {', '.join(QUANTITIES)}")
        if self.spec.test in STATIC_TESTS:
            if self.speed != 0.0:
                raise SpecError(
                    "target.speed", format_quantity(self.speed, "mph"), "none for compression"
                )
        elif not 0.0 < self.speed <= MAX_SPEED:
            raise SpecError(
                "target.speed", format_quantity(self.speed, "mph"), "0 mph < speed <= 223 mph"
            )
        if not self.value > 0.0:
            raise SpecError(f"target.{self.quantity}", self.value, "a positive measured value")
        if not self.weight > 0.0:
            raise SpecError("target.weight", self.weight, "a positive weight")

    @property
    def spec(self) -> Quantity:
        """The quantity's declaration."""
        return QUANTITIES[self.quantity]

    @property
    def label(self) -> str:
        """``"ccor @ 95 mph"``; ``"compression @ 0.25 in"``."""
        if self.spec.test in STATIC_TESTS:
            return f"{self.quantity} @ 0.25 in"
        return f"{self.quantity} @ {to_unit(self.speed, 'mph'):.0f} mph"

    def simulated(self, measures: ImpactMeasures) -> float:
        """The simulated value of this quantity in ``measures`` (SI)."""
        return float(getattr(measures, self.spec.attribute))

    def residual(self, simulated: float) -> float:
        """Weighted relative error in units of the goal: w (sim - meas) / (meas tol)."""
        return self.weight * (simulated - self.value) / (self.value * self.spec.tolerance)


def seed_targets(ball: str, *, speeds_mph: Sequence[float] = (95.0, 110.0)) -> tuple[Target, ...]:
    """The seed's experiment columns (Tables 5-8) for ``ball`` as targets, the seed's LS-DYNA
    values as references."""
    from batball.specs.seed import load_seed_tables

    tables = load_seed_tables()
    targets = []
    for mph in speeds_mph:
        row = tables.ball_impact(ball, mph)
        for quantity, exp, fe in (
            ("ccor", row.ccor_exp, row.ccor_fe),
            ("dynamic_stiffness", row.ds_exp, row.ds_fe),
            ("peak_force", row.peak_exp, row.peak_fe),
            ("contact_time", row.contact_exp, row.contact_fe),
        ):
            targets.append(Target(quantity, row.speed, exp, reference=fe))
    return tuple(targets)


def target_from_dict(row: Mapping[str, Any], *, field: str) -> Target:
    """One target from a TOML table or CSV row of strings with units.

    Raises:
        SpecError: naming ``<field>.<key>`` for an unknown quantity, a missing key, or a value
            or speed without the right unit.
    """
    known = ("quantity", "speed", "value", "weight")
    for key in row:
        if key not in known:
            raise SpecError(f"{field}.{key}", row[key], f"one of the keys {', '.join(known)}")
    name = row.get("quantity")
    if name in (None, ""):
        raise SpecError(f"{field}.quantity", "missing", "a quantity")
    if name not in QUANTITIES:
        raise SpecError(f"{field}.quantity", name, f"one of {', '.join(QUANTITIES)}")
    quantity = QUANTITIES[name]
    static = quantity.test in STATIC_TESTS
    if static and row.get("speed") not in (None, ""):
        raise SpecError(f"{field}.speed", row["speed"], f"no speed: {name} is quasi-static")
    for key in ("value",) if static else ("speed", "value"):
        if row.get(key) in (None, ""):
            raise SpecError(f"{field}.{key}", "missing", f"a {key}")
    raw_weight = row.get("weight")
    weight = 1.0 if raw_weight in (None, "") else float(raw_weight)
    value = parse_quantity(row["value"], quantity.dimension, field=f"{field}.value")
    speed = 0.0 if static else parse_quantity(row["speed"], "velocity", field=f"{field}.speed")
    try:
        return Target(name, speed, value, weight)
    except SpecError as exc:
        raise SpecError(f"{field}.{exc.field.split('.')[-1]}", exc.value, exc.allowed) from None


def load_targets(path: str | Path) -> tuple[Target, ...]:
    """Targets from a TOML (``[[target]]`` tables) or CSV file (header quantity,speed,value,...).

    Raises:
        SpecError: a missing or unreadable file, or any invalid target (naming ``target[i].key``).
    """
    path = Path(path)
    if not path.is_file():
        raise SpecError("targets", str(path), "an existing .toml or .csv file")
    if path.suffix.lower() == ".csv":
        with path.open(newline="", encoding="utf-8") as handle:
            rows: Iterable[Mapping[str, Any]] = list(csv.DictReader(handle))
    else:
        try:
            document = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise SpecError("targets", str(path), f"valid TOML ({exc})") from None
        rows = document.get("target", [])
    targets = tuple(target_from_dict(row, field=f"target[{i}]") for i, row in enumerate(rows))
    if not targets:
        raise SpecError("targets", str(path), "at least one target")
    return targets


def describe_value(target: Target, value: float) -> str:
    """A value of ``target``'s quantity in its display unit (``"7190 lbf/in"``)."""
    unit = target.spec.display_unit
    return f"{value:.4g}" if unit == "" else format_quantity(value, unit)


def targets_toml(targets: Sequence[Target], title: str) -> str:
    """A targets TOML (``[[target]]`` tables, values in each quantity's display unit, six
    figures) that :func:`load_targets` reads back."""
    lines = [f"# {title}", ""]
    for target in targets:
        unit = target.spec.display_unit
        value = to_unit(target.value, unit) if unit else target.value
        text = f'"{value:.6g} {unit}"' if unit else f"{value:.6g}"
        lines += [
            "[[target]]",
            f'quantity = "{target.quantity}"',
            f'speed = "{to_unit(target.speed, "mph"):.6g} mph"',
            f"value = {text}",
            "",
        ]
    return "\n".join(lines)


__all__ = [
    "QUANTITIES",
    "STATIC_TESTS",
    "Quantity",
    "Target",
    "describe_value",
    "load_targets",
    "seed_targets",
    "target_from_dict",
    "targets_toml",
]
