"""Ball specifications: size, mass and material, read from TOML with units in strings.

A ball spec file looks like the embedded defaults (``specs/data/type1.toml``)::

    name = "type1"
    description = "..."            # optional
    circumference = "12 in"
    mass = "6.93 oz"

    [material]
    law = "mat006"                 # a key of batball.materials.MATERIAL_LAWS
    bulk_modulus = "800000 psi"
    g0 = "22500 psi"
    g_inf = "750 psi"
    beta = "75000 1/s"

A foam ball (``law = "mat057"`` or ``"mat083"``, :mod:`batball.materials.foam`) gives its scalar
fields and its loading curve(s) as an array of tables, stresses as numbers in ``stress_unit``::

    [[material.curves]]
    strain_rate = "0 1/s"            # MAT_083: one curve per rate, rates increasing
    strain = [0.0, 0.05, 0.2]        # nominal, compression positive
    stress = [0.0, 150.0, 330.0]
    stress_unit = "psi"

(``specs/data/foam057.toml`` and ``foam083.toml`` are complete examples.)

A ball may name the hourglass control of its one-point hexes as part of its model (LS-DYNA's
``*HOURGLASS`` card of the ball's part); without one the tests use the solver default, the
viscous IHQ 1 with QH 0.1, and a test's own ``--hourglass-type``/``--hourglass-coefficient``
replace the ball's::

    [hourglass]
    type = 4                       # LS-DYNA IHQ: 1-3 viscous, 4-5 stiffness
    coefficient = 0.01             # QH (viscous) or QM (stiffness), 0-0.5

A generalised viscoelastic ball (``law = "prony3"``, :mod:`batball.materials.prony`) gives
``bulk_modulus``, ``g_inf`` and ``g1``/``beta1`` .. ``g3``/``beta3`` instead of ``g0``, ``g_inf``,
``beta``; ``batball calibrate --save`` writes either kind.

Everything is validated on load; errors are :class:`~batball.errors.SpecError` naming the dotted
field (``"material.g_inf"``), the value given and what is allowed.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from batball.errors import SpecError
from batball.materials import MATERIAL_LAWS, MaterialLaw
from batball.materials.foam import FoamCurve, FoamLaw, FoamTable
from batball.specs.document import check_name, read_spec_document
from batball.units import allowed_text, format_quantity, parse_quantity

#: Names of the balls shipped as package data (``specs/data/<name>.toml``): the seed's types 1, 2.
EMBEDDED_BALLS: tuple[str, ...] = ("type1", "type2")

#: The model of record's balls (docs/fidelity.md): the seed's two ball types as MAT_057 foam,
#: fitted by ``batball calibrate`` to the experiment columns of the seed's Tables 5-8. Each file
#: names the seed ball it models (``name = "type1"``) and the commands that made it.
FITTED_BALLS: tuple[str, ...] = ("type1-fit", "type2-fit")

#: Example balls shipped as package data beside the seed's: foam balls for MAT_057 and MAT_083
#: (their files say where the numbers come from).
EXAMPLE_BALLS: tuple[str, ...] = ("foam057", "foam083")

#: Keys of one ``[[material.curves]]`` table of a foam ball.
CURVE_KEYS: tuple[str, ...] = ("strain_rate", "strain", "stress", "stress_unit")

#: Keys of a ball spec document (``description`` is optional).
BALL_KEYS: tuple[str, ...] = (
    "name", "description", "circumference", "mass", "material", "hourglass",
)  # fmt: skip

#: LS-DYNA's hourglass types (IHQ) of a one-point solid a ball may name: 1-3 viscous, 4-5
#: stiffness (the solver's hex supports these; :data:`batball.elements.hex8.HOURGLASS_TYPES`).
BALL_HOURGLASS_TYPES: tuple[int, ...] = (1, 2, 3, 4, 5)
#: Largest hourglass coefficient QH/QM a ball may name (LS-DYNA's recommended range ends at 0.15;
#: the solver accepts up to 0.5).
MAX_HOURGLASS_COEFFICIENT = 0.5

MAX_CIRCUMFERENCE = 1.0  # m; any ball, not only the 12-in softball (0.3048 m)
MAX_MASS = 10.0  # kg

# Significant digits when writing SI values back to unit strings: exact enough to round-trip.
_TOML_DIGITS = 12


class ParameterValues(Mapping[str, float]):
    """An immutable, hashable, picklable ``{parameter name: SI value}`` mapping."""

    def __init__(self, values: Mapping[str, float]) -> None:
        self._values = {name: float(value) for name, value in values.items()}

    def __getitem__(self, name: str) -> float:
        return self._values[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __hash__(self) -> int:
        return hash(tuple(self._values.items()))

    def __repr__(self) -> str:
        return f"ParameterValues({self._values!r})"


@dataclass(frozen=True)
class MaterialSpec:
    """A material law and its parameter values.

    Attributes:
        law: key of :data:`batball.materials.MATERIAL_LAWS` (``"mat006"``, ``"elastic"``).
        values: ``{parameter name: value}`` in SI (Pa, 1/s, ...), one entry per declared
            parameter of the law, in declaration order (a parameter with a declared default
            may be left out and gets it).
        curves: the loading curves of a foam law (MAT_057: one; MAT_083: one per strain rate);
            empty for the other laws.

    Raises:
        SpecError: unknown law, unknown or missing parameter, or a value out of its bounds
            (field names ``"material.<parameter>"``); bad or missing curves
            (``"material.curves[i].stress"``), or curves for a law without them.
    """

    law: str
    values: Mapping[str, float]
    curves: tuple[FoamCurve, ...] = ()

    def __post_init__(self) -> None:
        law = material_law(self.law, field="material.law")
        _reject_unknown_keys(self.values, [p.name for p in law.parameters], prefix="material.")
        defaults = {p.name: p.default for p in law.parameters if p.default is not None}
        values = {**defaults, **self.values}
        law.check(values, prefix="material")
        ordered = {p.name: float(values[p.name]) for p in law.parameters}
        object.__setattr__(self, "values", ParameterValues(ordered))
        object.__setattr__(self, "curves", tuple(self.curves))
        if isinstance(law, FoamLaw):
            law.check_curves(self.curves, self.values, prefix="material")
        elif self.curves:
            raise SpecError("material.curves", f"{len(self.curves)} curves", f"none for {law.name}")

    def kernel_constants(self) -> np.ndarray:
        """The hex kernel's constants of the law (:meth:`MaterialLaw.kernel_constants`); for a
        foam, its isotropic stand-ins (:meth:`FoamLaw.kernel_constants`)."""
        law = self.material_law
        if isinstance(law, FoamLaw):
            return law.kernel_constants(self.values, self.curves)
        return law.kernel_constants(self.values)

    def foam_table(self) -> FoamTable | None:
        """The packed foam constants for the foam kernel, or None for a non-foam law."""
        law = self.material_law
        return law.foam_table(self.values, self.curves) if isinstance(law, FoamLaw) else None

    @property
    def material_law(self) -> MaterialLaw:
        """The registered law declaration."""
        return MATERIAL_LAWS[self.law]


@dataclass(frozen=True)
class BallHourglass:
    """The hourglass control of a ball's one-point hexes, part of the ball's model.

    Attributes:
        type: LS-DYNA IHQ (:data:`BALL_HOURGLASS_TYPES`: 1-3 viscous, 4-5 stiffness).
        coefficient: QH (viscous) or QM (stiffness), 0 to :data:`MAX_HOURGLASS_COEFFICIENT`.

    Raises:
        SpecError: naming ``hourglass.type`` or ``hourglass.coefficient``.
    """

    type: int
    coefficient: float

    def __post_init__(self) -> None:
        if type(self.type) is not int or self.type not in BALL_HOURGLASS_TYPES:
            raise SpecError("hourglass.type", self.type,
                            f"an integer, one of {', '.join(map(str, BALL_HOURGLASS_TYPES))}")
        value = self.coefficient
        numeric = isinstance(value, int | float) and not isinstance(value, bool)
        if not (numeric and math.isfinite(value) and 0.0 <= value <= MAX_HOURGLASS_COEFFICIENT):
            raise SpecError("hourglass.coefficient", value,
                            f"a number 0 <= coefficient <= {MAX_HOURGLASS_COEFFICIENT}")
        object.__setattr__(self, "coefficient", float(value))


@dataclass(frozen=True)
class BallSpec:
    """A ball: size, mass and material, all SI.

    Attributes:
        name: short name (``"type1"``).
        circumference: great-circle circumference, m (12 in = 0.3048 m).
        mass: total mass, kg (6.93 oz = 0.19646 kg).
        material: the (homogeneous) material of the ball.
        description: one line for reports.
        hourglass: the hourglass control of the ball's hexes when the model names one (None:
            the test's, by default the solver's viscous IHQ 1, QH 0.1).

    Raises:
        SpecError: empty name, circumference not in (0, 1] m, mass not in (0, 10] kg.
    """

    name: str
    circumference: float
    mass: float
    material: MaterialSpec
    description: str = ""
    hourglass: BallHourglass | None = None

    def __post_init__(self) -> None:
        check_name("name", self.name)
        _check_range("circumference", self.circumference, MAX_CIRCUMFERENCE, "in")
        _check_range("mass", self.mass, MAX_MASS, "oz")
        if not isinstance(self.material, MaterialSpec):
            raise SpecError("material", self.material, "a MaterialSpec")
        if self.hourglass is not None and not isinstance(self.hourglass, BallHourglass):
            raise SpecError("hourglass", self.hourglass, "a BallHourglass or None")

    @property
    def radius(self) -> float:
        """Radius of the sphere with this circumference, m."""
        return self.circumference / (2.0 * math.pi)

    @property
    def volume(self) -> float:
        """Volume of the sphere, m^3."""
        return 4.0 / 3.0 * math.pi * self.radius**3

    @property
    def mean_density(self) -> float:
        """Mass over volume, kg/m^3 (about 400 kg/m^3 for a 12-in, 6.75-oz softball)."""
        return self.mass / self.volume


def _check_range(name: str, value: float, upper: float, unit: str) -> None:
    """Raise :class:`SpecError` unless ``0 < value <= upper`` (SI), shown in ``unit``."""
    if not (isinstance(value, int | float) and math.isfinite(value) and 0.0 < value <= upper):
        shown = format_quantity(value, unit) if isinstance(value, int | float) else value
        raise SpecError(name, shown, f"0 {unit} < {name} <= {format_quantity(upper, unit)}")


def material_law(law: object, *, field: str) -> MaterialLaw:
    """The registered law named ``law``; :class:`SpecError` listing the registered names if none."""
    if not isinstance(law, str) or law not in MATERIAL_LAWS:
        raise SpecError(field, law, f"one of {', '.join(sorted(MATERIAL_LAWS))}")
    return MATERIAL_LAWS[law]


def _reject_unknown_keys(table: Mapping[str, Any], known: list[str], *, prefix: str) -> None:
    """Raise :class:`SpecError` naming the first key of ``table`` that is not in ``known``."""
    for key, value in table.items():
        if key not in known:
            raise SpecError(f"{prefix}{key}", value, f"one of the keys {', '.join(known)}")


def _required(table: Mapping[str, Any], key: str, *, field: str, allowed: str) -> Any:
    """``table[key]``, or :class:`SpecError` ``(field, "missing", allowed)``."""
    if key not in table:
        raise SpecError(field, "missing", allowed)
    return table[key]


def material_spec_from_dict(table: object, *, field: str = "material") -> MaterialSpec:
    """Build a :class:`MaterialSpec` from a TOML table ``{law = ..., <parameter> = "<value>"}``.

    Args:
        table: the ``[material]`` table; values are strings with units (bare numbers for
            dimensionless parameters).
        field: dotted path of the table, for error messages.

    Raises:
        SpecError: naming ``"<field>.<key>"`` for a missing, unknown or invalid entry.
    """
    if not isinstance(table, Mapping):
        raise SpecError(field, table, "a table with 'law' and the law's parameters")
    names = ", ".join(sorted(MATERIAL_LAWS))
    law = material_law(
        _required(table, "law", field=f"{field}.law", allowed=f"one of {names}"),
        field=f"{field}.law",
    )
    foam = isinstance(law, FoamLaw)
    keys = ["law", *[p.name for p in law.parameters], *(["curves"] if foam else [])]
    _reject_unknown_keys(table, keys, prefix=f"{field}.")
    values = {}
    for p in law.parameters:
        path = f"{field}.{p.name}"
        if p.default is not None and p.name not in table:
            continue  # MaterialSpec fills it in
        raw = _required(table, p.name, field=path, allowed=allowed_text(p.dimension))
        values[p.name] = parse_quantity(raw, p.dimension, field=path)
    curves: tuple[FoamCurve, ...] = ()
    if foam:
        raw_curves = _required(
            table, "curves", field=f"{field}.curves", allowed="[[material.curves]] tables"
        )
        if not isinstance(raw_curves, list):
            raise SpecError(f"{field}.curves", raw_curves, "an array of tables")
        curves = tuple(
            curve_from_dict(c, field=f"{field}.curves[{i}]") for i, c in enumerate(raw_curves)
        )
    return MaterialSpec(law=law.name, values=values, curves=curves)


def curve_from_dict(table: object, *, field: str) -> FoamCurve:
    """A :class:`FoamCurve` from ``{strain_rate, strain, stress, stress_unit}`` (SI inside).

    Raises:
        SpecError: naming ``<field>.<key>`` for a missing, unknown or malformed entry.
    """
    if not isinstance(table, Mapping):
        raise SpecError(field, table, "a table with strain, stress and stress_unit")
    _reject_unknown_keys(table, list(CURVE_KEYS), prefix=f"{field}.")
    unit = _required(table, "stress_unit", field=f"{field}.stress_unit", allowed="e.g. 'psi'")
    factor = parse_quantity(f"1 {unit}", "pressure", field=f"{field}.stress_unit")
    rate = parse_quantity(table.get("strain_rate", "0 1/s"), "frequency",
                          field=f"{field}.strain_rate")  # fmt: skip
    columns = {}
    for key in ("strain", "stress"):
        raw = _required(table, key, field=f"{field}.{key}", allowed="an array of numbers")
        numeric = isinstance(raw, list) and all(
            isinstance(x, int | float) and not isinstance(x, bool) for x in raw
        )
        if not numeric:
            raise SpecError(f"{field}.{key}", raw, "an array of numbers")
        columns[key] = tuple(float(x) for x in raw)
    stress = tuple(factor * x for x in columns["stress"])
    return FoamCurve(strain=columns["strain"], stress=stress, strain_rate=rate)


def ball_spec_from_dict(document: Mapping[str, Any], *, source: str) -> BallSpec:
    """Build and validate a :class:`BallSpec` from a parsed TOML document.

    Args:
        document: keys :data:`BALL_KEYS`; quantities and masses as strings with units.
        source: where the document came from (a path, ``"embedded ball 'type1'"``); added to
            a raised error as a note.

    Raises:
        SpecError: naming the dotted field (``"mass"``, ``"material.g_inf"``).
    """
    try:
        return _build_ball_spec(document)
    except SpecError as exc:
        exc.add_note(f"in the ball spec {source}")
        raise


def _build_ball_spec(document: Mapping[str, Any]) -> BallSpec:
    """:func:`ball_spec_from_dict` without the source note."""
    _reject_unknown_keys(document, list(BALL_KEYS), prefix="")
    name = _required(document, "name", field="name", allowed="a non-empty string")
    description = document.get("description", "")
    if not isinstance(description, str):
        raise SpecError("description", description, "a string")
    quantities = {}
    for key, dimension in (("circumference", "length"), ("mass", "mass")):
        raw = _required(document, key, field=key, allowed=allowed_text(dimension))
        quantities[key] = parse_quantity(raw, dimension, field=key)
    material = material_spec_from_dict(
        _required(document, "material", field="material", allowed="a [material] table")
    )
    return BallSpec(
        name=name,
        circumference=quantities["circumference"],
        mass=quantities["mass"],
        material=material,
        description=description,
        hourglass=hourglass_from_dict(document["hourglass"]) if "hourglass" in document else None,
    )


def hourglass_from_dict(table: object, *, field: str = "hourglass") -> BallHourglass:
    """A :class:`BallHourglass` from the ``[hourglass]`` table ``{type = 4, coefficient = 0.01}``.

    Raises:
        SpecError: naming ``<field>.<key>`` for a missing, unknown or invalid entry.
    """
    if not isinstance(table, Mapping):
        raise SpecError(field, table, "a table with type and coefficient")
    _reject_unknown_keys(table, ["type", "coefficient"], prefix=f"{field}.")
    return BallHourglass(
        type=_required(table, "type", field=f"{field}.type", allowed="an LS-DYNA IHQ, 1-5"),
        coefficient=_required(table, "coefficient", field=f"{field}.coefficient",
                              allowed=f"a number 0-{MAX_HOURGLASS_COEFFICIENT}"),
    )  # fmt: skip


def list_embedded_balls() -> list[str]:
    """Names accepted by :func:`load_ball_spec` without a path (``["type1", "type2"]``)."""
    return list(EMBEDDED_BALLS)


def load_ball_spec(name_or_path: str | Path) -> BallSpec:
    """Load an embedded ball by name, or a ball spec TOML file by path.

    Args:
        name_or_path: an embedded ball (``"type1"``, ``"type2"``: the seed's Table 4 balls;
            ``"type1-fit"``, ``"type2-fit"``: the model of record's; ``"foam057"``,
            ``"foam083"``: examples) or the path of a TOML file.

    Raises:
        SpecError: neither an embedded name nor an existing file, invalid TOML, invalid content.
    """
    document, source = read_spec_document(
        name_or_path,
        kind="ball",
        embedded=EMBEDDED_BALLS + FITTED_BALLS + EXAMPLE_BALLS,
        file_pattern="{name}.toml",
    )
    return ball_spec_from_dict(document, source=source)


def material_spec_to_toml_dict(spec: MaterialSpec) -> dict[str, Any]:
    """The ``[material]`` table of ``spec``: values as strings in their display units (and a
    foam's curves)."""
    table: dict[str, Any] = {"law": spec.law}
    for p in spec.material_law.parameters:
        value = spec.values[p.name]
        table[p.name] = (
            value
            if p.display_unit == ""
            else format_quantity(value, p.display_unit, digits=_TOML_DIGITS)
        )
    if spec.curves:
        table["curves"] = [curve_to_toml_dict(c) for c in spec.curves]
    return table


def curve_to_toml_dict(curve: FoamCurve) -> dict[str, Any]:
    """The ``[[material.curves]]`` table of ``curve``: stresses in psi, 12 digits."""
    from batball.units import to_unit

    return {
        "strain_rate": format_quantity(curve.strain_rate, "1/s", digits=_TOML_DIGITS),
        "strain": list(curve.strain),
        "stress": [float(f"{to_unit(s, 'psi'):.{_TOML_DIGITS}g}") for s in curve.stress],
        "stress_unit": "psi",
    }


def ball_spec_to_toml_dict(spec: BallSpec) -> dict[str, Any]:
    """A TOML-able (and JSON-able) dict of ``spec`` with unit strings, for run folders and hashing.

    Values are written with 12 significant digits, so :func:`ball_spec_from_dict` of the result
    equals ``spec`` to a relative 1e-12.
    """
    return {
        "name": spec.name,
        "description": spec.description,
        "circumference": format_quantity(spec.circumference, "in", digits=_TOML_DIGITS),
        "mass": format_quantity(spec.mass, "oz", digits=_TOML_DIGITS),
        "material": material_spec_to_toml_dict(spec.material),
        # only when the ball names one, so the keys of the balls without one stay as they were
        **({"hourglass": {"type": spec.hourglass.type, "coefficient": spec.hourglass.coefficient}}
           if spec.hourglass is not None else {}),
    }  # fmt: skip
