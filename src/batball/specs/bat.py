"""Bat specifications: profile, parts with layups, the insert and the lamina materials, in TOML.

A bat spec file looks like the embedded default (``specs/data/default_bat.toml``)::

    name = "my_bat"
    length = "33.1 in"

    [materials.carbon]             # lamina materials by name; law: a key of LAMINA_LAWS
    law = "mat022"
    density = "1.60 g/cm**3"
    ea = "147 GPa"
    eb = "10.3 GPa"
    ec = "10.3 GPa"
    prba = 0.0189                  # the MINOR Poisson's ratio nu_ba
    gab = "7.0 GPa"
    gbc = "3.5 GPa"
    gca = "7.0 GPa"

    [profile]                      # outer diameter at stations from the knob end, linear between
    stations = [
      { x = "0 in", diameter = "1.0 in" },
      { x = "20 in", diameter = "2.25 in" },
      { x = "33.1 in", diameter = "2.25 in" },
    ]

    [[parts]]                      # contiguous, from the knob end (x = 0) to x = length
    name = "tube"
    start = "0 in"
    end = "33.1 in"
    lumped_mass = "0 oz"           # optional: non-structural mass spread over the part's area
    # plies from the inner surface outward; label: optional, names plies for batball fit-bat
    layup = [
      { material = "carbon", thickness = "0.03 in", angle = "30 deg", braided = true, label = "c" },
    ]

    [insert]                       # optional: a tube pressed into the barrel (double wall)
    start = "22 in"
    end = "32 in"
    interference = "0.001 in"      # radial overlap with the barrel's inner surface before the fit
    layup = [{ material = "carbon", thickness = "0.06 in", angle = "45 deg", braided = true }]

Everything is validated on load; errors are :class:`~batball.errors.SpecError` naming the dotted
field (``"parts[3].layup[1].thickness"``), the value given and what is allowed.

One module (about 550 lines) because it is one schema: the dataclasses, their validation and
their TOML reading and writing, field by field.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from batball.errors import SpecError
from batball.materials import LAMINA_LAWS
from batball.materials.laminate import Laminate, Ply
from batball.materials.orthotropic import OrthotropicLamina
from batball.specs.ball import _reject_unknown_keys, _required
from batball.specs.document import check_name, read_spec_document
from batball.units import allowed_text, format_quantity, parse_quantity

#: Names of the bats shipped as package data (``specs/data/<name>_bat.toml``).
EMBEDDED_BATS: tuple[str, ...] = ("default",)

#: The model of record's bat (docs/fidelity.md): the reconstruction with its barrel braid fitted
#: to Table 3's hoop modes (``specs/data/fitted_bat.toml`` says how).
FITTED_BATS: tuple[str, ...] = ("fitted",)

BAT_KEYS = ("name", "description", "length", "materials", "profile", "parts", "insert")
PART_KEYS = ("name", "start", "end", "layup", "lumped_mass")
INSERT_KEYS = ("start", "end", "layup", "interference", "friction")
#: The largest Coulomb coefficient an insert's interface may have (beyond about 5 it sticks).
MAX_INSERT_FRICTION = 10.0
PLY_KEYS = ("material", "thickness", "angle", "braided", "label")

MAX_LENGTH = 2.0  # m; any bat (softball bats are at most 34 in = 0.8636 m)
_ANGLE_TEXT = "an angle with its unit between -90 deg and 90 deg, e.g. '30 deg'"
_TOML_DIGITS = 12


@dataclass(frozen=True)
class PlySpec:
    """One ply of a layup as specified.

    Attributes:
        material: key of the bat's ``materials`` table.
        thickness: m.
        angle: fibre (or braid half-) angle from the bat axis toward the hoop direction, rad.
        braided: expand into the five-layer [+/-/+/-/+] braid (thicknesses 1/6, 1/4 of t).
        label: optional name shared by the plies that ``batball fit-bat`` may change together.
    """

    material: str
    thickness: float
    angle: float
    braided: bool = False
    label: str = ""


@dataclass(frozen=True)
class PartSpec:
    """A component along the bat: an axial span of the shell with one layup.

    Attributes:
        name: unique part name (``"knob"``, ``"barrel-2"``); also the mesh's cell-set name.
        start, end: axial span from the knob end, m.
        layup: plies from the inner surface outward.
        lumped_mass: non-structural mass spread over the part's area (knob, end cap), kg.
    """

    name: str
    start: float
    end: float
    layup: tuple[PlySpec, ...]
    lumped_mass: float = 0.0


@dataclass(frozen=True)
class InsertSpec:
    """The tube pressed into the barrel (the seed's 10-in insert, 0.001-in interference fit).

    Attributes:
        start, end: axial span from the knob end, m; inside a cylindrical stretch of the barrel.
        layup: plies from the inner surface outward.
        interference: radial overlap of the insert's outer surface with the barrel's inner
            surface before assembly, m (the delta of docs/physics.md section 8, case 9).
        friction: the interface's Coulomb coefficient once fitted, used by the tests that load
            the insert (barrel compression, batted-ball speed; the fit itself is pressed
            frictionless): 0 slides freely (the seed's), a large value (5 and more) sticks, the
            limit of a bonded insert; at most :data:`MAX_INSERT_FRICTION`.
    """

    start: float
    end: float
    layup: tuple[PlySpec, ...]
    interference: float = 0.0
    friction: float = 0.0


@dataclass(frozen=True)
class BatSpec:
    """A bat: length, outer profile, parts with layups, optional insert, lamina materials (SI).

    Attributes:
        name: short name.
        length: overall length, m.
        stations: ``(x, outer diameter)`` pairs, m, x from 0 to length (see :attr:`station_array`).
        parts: contiguous components from the knob end to the end cap.
        insert: the insert, or None for a single-wall bat.
        materials: lamina materials by the names the layups use.
        description: one line for reports.
    """

    name: str
    length: float
    stations: tuple[tuple[float, float], ...]
    parts: tuple[PartSpec, ...]
    insert: InsertSpec | None
    materials: Mapping[str, OrthotropicLamina] = field(default_factory=dict)
    description: str = ""

    def __post_init__(self) -> None:
        stations = np.asarray(self.stations, dtype=np.float64)
        object.__setattr__(self, "stations", tuple((float(x), float(d)) for x, d in stations))
        object.__setattr__(self, "materials", MappingProxyType(dict(self.materials)))
        _check_bat(self)

    @property
    def station_array(self) -> np.ndarray:
        """The profile stations, shape (n_stations, 2): axial position and outer diameter, m."""
        return np.array(self.stations, dtype=np.float64).reshape(-1, 2)

    def outer_radius(self, x: np.ndarray | float) -> np.ndarray:
        """Outer radius of the profile at axial positions ``x`` (m), same shape, m."""
        stations = self.station_array
        return 0.5 * np.interp(x, stations[:, 0], stations[:, 1])

    def laminate(self, layup: tuple[PlySpec, ...]) -> Laminate:
        """The :class:`Laminate` of a layup, its materials looked up in :attr:`materials`."""
        return Laminate(
            tuple(
                Ply(self.materials[p.material], p.thickness, p.angle, braided=p.braided)
                for p in layup
            )
        )

    def part(self, name: str) -> PartSpec:
        """The part called ``name``; SpecError listing the part names if none."""
        for part in self.parts:
            if part.name == name:
                return part
        raise SpecError("part", name, f"one of {', '.join(p.name for p in self.parts)}")

    def insert_outer_radius(self) -> float:
        """Outer radius of the insert before the fit: the barrel's smallest inner radius over the
        insert's span plus the interference, m."""
        if self.insert is None:
            raise ValueError("this bat has no insert")
        spans = [p for p in self.parts if p.start < self.insert.end and p.end > self.insert.start]
        inner = min(
            float(self.outer_radius(0.5 * (self.insert.start + self.insert.end)))
            - self.laminate(p.layup).thickness
            for p in spans
        )
        return inner + self.insert.interference


def _check_bat(spec: BatSpec) -> None:
    """Cross-field checks of a :class:`BatSpec`: profile, part cover, materials, walls, insert."""
    check_name("name", spec.name)
    if not (math.isfinite(spec.length) and 0.0 < spec.length <= MAX_LENGTH):
        raise SpecError("length", format_quantity(spec.length, "in"), "0 in < length <= 78.74 in")
    _check_stations(spec.station_array, spec.length)
    _check_parts(spec)
    if spec.insert is not None:
        _check_insert(spec)


def _check_stations(stations: np.ndarray, length: float) -> None:
    """Stations: at least two, x strictly increasing from 0 to ``length``, diameters > 0."""
    field_ = "profile.stations"
    if stations.ndim != 2 or stations.shape[0] < 2 or stations.shape[1] != 2:
        raise SpecError(field_, stations.tolist(), "at least two {x, diameter} stations")
    x, diameter = stations[:, 0], stations[:, 1]
    for i in range(stations.shape[0]):
        if not diameter[i] > 0.0:
            raise SpecError(f"{field_}[{i}].diameter", format_quantity(diameter[i], "in"), "> 0")
        if i > 0 and not x[i] > x[i - 1]:
            raise SpecError(f"{field_}[{i}].x", format_quantity(x[i], "in"), "x increasing")
    if abs(x[0]) > 1e-9:
        raise SpecError(f"{field_}[0].x", format_quantity(x[0], "in"), "0 in (the knob end)")
    if abs(x[-1] - length) > 1e-9:
        raise SpecError(f"{field_}[-1].x", format_quantity(x[-1], "in"), "the bat's length")


def _check_parts(spec: BatSpec) -> None:
    """Parts: unique names, contiguous from 0 to the length, valid layups, walls inside the bat."""
    if not spec.parts:
        raise SpecError("parts", [], "at least one [[parts]] table")
    seen: set[str] = set()
    previous_end = 0.0
    for i, part in enumerate(spec.parts):
        path = f"parts[{i}]"
        check_name(f"{path}.name", part.name)
        if part.name in seen or part.name == "insert":
            raise SpecError(f"{path}.name", part.name, "a unique non-empty name other than insert")
        seen.add(part.name)
        if abs(part.start - previous_end) > 1e-9:
            shown = format_quantity(part.start, "in")
            raise SpecError(f"{path}.start", shown, "the previous part's end (parts contiguous)")
        if not part.end > part.start:
            raise SpecError(f"{path}.end", format_quantity(part.end, "in"), "> start")
        if not (math.isfinite(part.lumped_mass) and part.lumped_mass >= 0.0):
            raise SpecError(f"{path}.lumped_mass", part.lumped_mass, ">= 0 oz")
        _check_layup(spec, part.layup, part.start, part.end, field=f"{path}.layup")
        previous_end = part.end
    if abs(previous_end - spec.length) > 1e-9:
        last = f"parts[{len(spec.parts) - 1}].end"
        raise SpecError(last, format_quantity(previous_end, "in"), "the bat's length")


def _check_layup(
    spec: BatSpec, layup: tuple[PlySpec, ...], start: float, end: float, *, field: str
) -> None:
    """A non-empty layup of known materials, positive thicknesses, angles within +/-90 deg."""
    if not layup:
        raise SpecError(field, [], "at least one ply")
    for k, ply in enumerate(layup):
        if ply.material not in spec.materials:
            names = ", ".join(sorted(spec.materials)) or "(no [materials] given)"
            raise SpecError(f"{field}[{k}].material", ply.material, f"one of {names}")
        if not (math.isfinite(ply.thickness) and ply.thickness > 0.0):
            raise SpecError(f"{field}[{k}].thickness", ply.thickness, "a positive length")
        if not abs(ply.angle) <= 0.5 * math.pi + 1e-12:
            raise SpecError(f"{field}[{k}].angle", format_quantity(ply.angle, "deg"), _ANGLE_TEXT)
    wall = sum(ply.thickness for ply in layup)
    smallest = float(np.min(spec.outer_radius(np.linspace(start, end, 64))))
    if not wall < smallest:
        allowed = (
            f"a wall thinner than the smallest outer radius ({format_quantity(smallest, 'in')})"
        )
        raise SpecError(field, format_quantity(wall, "in"), allowed)


def _check_insert(spec: BatSpec) -> None:
    """The insert lies in a cylindrical stretch of the barrel and fits inside its wall."""
    insert = spec.insert
    assert insert is not None
    if not (0.0 <= insert.start < insert.end <= spec.length):
        shown = [format_quantity(insert.start, "in"), format_quantity(insert.end, "in")]
        raise SpecError("insert.start, insert.end", shown, "0 <= start < end <= length")
    radii = spec.outer_radius(np.linspace(insert.start, insert.end, 64))
    if np.ptp(radii) > 1e-9:
        raise SpecError(
            "insert", format_quantity(insert.start, "in"), "a span of constant diameter"
        )
    if not (math.isfinite(insert.interference) and insert.interference >= 0.0):
        raise SpecError("insert.interference", insert.interference, ">= 0 in")
    if not (math.isfinite(insert.friction) and 0.0 <= insert.friction <= MAX_INSERT_FRICTION):
        raise SpecError("insert.friction", insert.friction,
                        f"a Coulomb coefficient 0 .. {MAX_INSERT_FRICTION:g}")  # fmt: skip
    _check_layup(spec, insert.layup, insert.start, insert.end, field="insert.layup")
    if not spec.laminate(insert.layup).thickness < spec.insert_outer_radius():
        raise SpecError("insert.layup", "too thick", "a wall thinner than the barrel's bore radius")


def bat_spec_from_dict(document: Mapping[str, Any], *, source: str) -> BatSpec:
    """Build and validate a :class:`BatSpec` from a parsed TOML document.

    Args:
        document: keys :data:`BAT_KEYS`; lengths, masses, moduli and angles as strings with units.
        source: where the document came from (a path, ``"embedded bat 'default'"``); added to a
            raised error as a note.

    Raises:
        SpecError: naming the dotted field (``"parts[2].layup[0].angle"``).
    """
    try:
        return _build_bat_spec(document)
    except SpecError as exc:
        exc.add_note(f"in the bat spec {source}")
        raise


def _build_bat_spec(document: Mapping[str, Any]) -> BatSpec:
    """:func:`bat_spec_from_dict` without the source note."""
    _reject_unknown_keys(document, list(BAT_KEYS), prefix="")
    description = document.get("description", "")
    if not isinstance(description, str):
        raise SpecError("description", description, "a string")
    parts = _table_list(document, "parts", field="parts")
    return BatSpec(
        name=_required(document, "name", field="name", allowed="a non-empty string"),
        length=_quantity(document, "length", "length", field="length"),
        stations=_stations_from_dict(
            _required(document, "profile", field="profile", allowed="a [profile] table")
        ),
        parts=tuple(_part_from_dict(table, field=f"parts[{i}]") for i, table in enumerate(parts)),
        insert=_insert_from_dict(document["insert"]) if "insert" in document else None,
        materials=_materials_from_dict(
            _required(document, "materials", field="materials", allowed="a [materials] table")
        ),
        description=description,
    )


def _quantity(table: Mapping[str, Any], key: str, dimension: str, *, field: str) -> float:
    """``table[key]`` parsed as a ``dimension`` quantity (SI); SpecError naming ``field``."""
    raw = _required(table, key, field=field, allowed=allowed_text(dimension))
    return parse_quantity(raw, dimension, field=field)


def _table_list(table: Mapping[str, Any], key: str, *, field: str) -> list[Mapping[str, Any]]:
    """``table[key]`` as a list of tables (``[[parts]]``, ``layup = [{...}, ...]``)."""
    items = _required(table, key, field=field, allowed="a list of tables")
    if not isinstance(items, list):
        raise SpecError(field, items, "a list of tables")
    for i, item in enumerate(items):
        if not isinstance(item, Mapping):
            raise SpecError(f"{field}[{i}]", item, "a table")
    return items


def parse_angle(value: object, *, field: str) -> float:
    """An angle with its unit (``"30 deg"``), in rad; a bare number is refused (deg or rad?)."""
    if not isinstance(value, str) or re.search(r"[A-Za-z]", value) is None:
        raise SpecError(field, value, _ANGLE_TEXT)
    return parse_quantity(value, "dimensionless", field=field)


def _materials_from_dict(table: object) -> dict[str, OrthotropicLamina]:
    """``[materials.<name>]`` tables -> laminae, validated by their law's declarations."""
    if not isinstance(table, Mapping) or not table:
        raise SpecError("materials", table, "a [materials.<name>] table per lamina material")
    materials = {}
    for name, entry in table.items():
        field_ = f"materials.{name}"
        if not isinstance(entry, Mapping):
            raise SpecError(field_, entry, "a table with 'law' and the law's parameters")
        laws = ", ".join(sorted(LAMINA_LAWS))
        law_name = _required(entry, "law", field=f"{field_}.law", allowed=f"one of {laws}")
        if law_name not in LAMINA_LAWS:
            raise SpecError(f"{field_}.law", law_name, f"one of {laws}")
        law = LAMINA_LAWS[law_name]
        _reject_unknown_keys(entry, ["law", *[p.name for p in law.parameters]], prefix=f"{field_}.")
        values = {
            p.name: _quantity(entry, p.name, p.dimension, field=f"{field_}.{p.name}")
            for p in law.parameters
        }
        materials[check_name(field_, name)] = law.lamina(values, name=name)
    return materials


def _stations_from_dict(table: object) -> tuple[tuple[float, float], ...]:
    """``[profile] stations = [{x, diameter}, ...]`` -> ``((x, diameter), ...)``, m."""
    if not isinstance(table, Mapping):
        raise SpecError("profile", table, "a table with 'stations'")
    _reject_unknown_keys(table, ["stations"], prefix="profile.")
    rows = []
    for i, station in enumerate(_table_list(table, "stations", field="profile.stations")):
        path = f"profile.stations[{i}]"
        _reject_unknown_keys(station, ["x", "diameter"], prefix=f"{path}.")
        rows.append(
            (
                _quantity(station, "x", "length", field=f"{path}.x"),
                _quantity(station, "diameter", "length", field=f"{path}.diameter"),
            )
        )
    return tuple(rows)


def _ply_from_dict(table: Mapping[str, Any], *, field: str) -> PlySpec:
    """One ply table ``{material, thickness, angle, braided, label}``."""
    _reject_unknown_keys(table, list(PLY_KEYS), prefix=f"{field}.")
    material = _required(table, "material", field=f"{field}.material", allowed="a material name")
    braided, label = table.get("braided", False), table.get("label", "")
    if not isinstance(braided, bool):
        raise SpecError(f"{field}.braided", braided, "true or false")
    if label != "":
        check_name(f"{field}.label", label)
    return PlySpec(
        material=str(material),
        thickness=_quantity(table, "thickness", "length", field=f"{field}.thickness"),
        angle=parse_angle(_required(table, "angle", field=f"{field}.angle", allowed=_ANGLE_TEXT),
                     field=f"{field}.angle"),
        braided=braided,
        label=label,
    )  # fmt: skip


def _layup_from_dict(table: Mapping[str, Any], *, field: str) -> tuple[PlySpec, ...]:
    """``layup = [{...}, ...]`` -> plies, inner surface first."""
    plies = _table_list(table, "layup", field=f"{field}.layup")
    return tuple(_ply_from_dict(ply, field=f"{field}.layup[{k}]") for k, ply in enumerate(plies))


def _part_from_dict(table: Mapping[str, Any], *, field: str) -> PartSpec:
    """One ``[[parts]]`` table."""
    _reject_unknown_keys(table, list(PART_KEYS), prefix=f"{field}.")
    name = _required(table, "name", field=f"{field}.name", allowed="a non-empty string")
    lumped = table.get("lumped_mass", "0 oz")
    return PartSpec(
        name=str(name),
        start=_quantity(table, "start", "length", field=f"{field}.start"),
        end=_quantity(table, "end", "length", field=f"{field}.end"),
        layup=_layup_from_dict(table, field=field),
        lumped_mass=parse_quantity(lumped, "mass", field=f"{field}.lumped_mass"),
    )


def _insert_from_dict(table: object) -> InsertSpec:
    """The ``[insert]`` table."""
    if not isinstance(table, Mapping):
        raise SpecError("insert", table, "a table with start, end, layup, interference and "
                        "friction")  # fmt: skip
    _reject_unknown_keys(table, list(INSERT_KEYS), prefix="insert.")
    return InsertSpec(
        start=_quantity(table, "start", "length", field="insert.start"),
        end=_quantity(table, "end", "length", field="insert.end"),
        layup=_layup_from_dict(table, field="insert"),
        interference=parse_quantity(
            table.get("interference", "0 in"), "length", field="insert.interference"
        ),
        friction=_coefficient(table.get("friction", 0.0), field="insert.friction"),
    )


def _coefficient(value: object, *, field: str) -> float:
    """A dimensionless number from TOML (a number, not a string with a unit)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise SpecError(field, value, "a number without a unit, e.g. 0.3")
    return float(value)


def list_embedded_bats() -> list[str]:
    """Names accepted by :func:`load_bat_spec` without a path (``["default"]``)."""
    return list(EMBEDDED_BATS)


def load_bat_spec(name_or_path: str | Path) -> BatSpec:
    """Load an embedded bat by name, or a bat spec TOML file by path.

    Args:
        name_or_path: ``"default"`` (the reconstruction of the seed's bat), ``"fitted"`` (the
            model of record's bat) or a TOML file path.

    Raises:
        SpecError: neither an embedded name nor an existing file, invalid TOML, invalid content.
    """
    document, source = read_spec_document(
        name_or_path, kind="bat", embedded=EMBEDDED_BATS + FITTED_BATS,
        file_pattern="{name}_bat.toml",
    )
    return bat_spec_from_dict(document, source=source)


def _length_text(value: float) -> str:
    """A length in inches with 12 significant digits (round-trips to 1e-12)."""
    return format_quantity(value, "in", digits=_TOML_DIGITS)


def _layup_to_list(layup: tuple[PlySpec, ...]) -> list[dict[str, Any]]:
    """Plies as TOML inline tables."""
    rows: list[dict[str, Any]] = []
    for ply in layup:
        row: dict[str, Any] = {
            "material": ply.material,
            "thickness": _length_text(ply.thickness),
            "angle": format_quantity(ply.angle, "deg", digits=_TOML_DIGITS),
            "braided": ply.braided,
        }
        if ply.label:
            row["label"] = ply.label
        rows.append(row)
    return rows


def _materials_to_dict(materials: Mapping[str, OrthotropicLamina]) -> dict[str, Any]:
    """``[materials.<name>]`` tables, as MAT_022 (an isotropic layer is written as MAT_022 too)."""
    law = LAMINA_LAWS["mat022"]
    out: dict[str, Any] = {}
    for name, lamina in materials.items():
        table: dict[str, Any] = {"law": law.name}
        for p in law.parameters:
            value = getattr(lamina, p.name)
            table[p.name] = (
                value if p.display_unit == ""
                else format_quantity(value, p.display_unit, digits=_TOML_DIGITS)
            )  # fmt: skip
        out[name] = table
    return out


def bat_spec_to_toml_dict(spec: BatSpec) -> dict[str, Any]:
    """A TOML-able (and JSON-able) dict of ``spec`` with unit strings, for run folders, hashing
    and ``batball fit-bat`` output; :func:`bat_spec_from_dict` of it equals ``spec`` to 1e-12."""
    document: dict[str, Any] = {
        "name": spec.name,
        "description": spec.description,
        "length": _length_text(spec.length),
        "materials": _materials_to_dict(spec.materials),
        "profile": {
            "stations": [
                {"x": _length_text(x), "diameter": _length_text(d)} for x, d in spec.stations
            ]
        },
        "parts": [
            {
                "name": p.name,
                "start": _length_text(p.start),
                "end": _length_text(p.end),
                "lumped_mass": format_quantity(p.lumped_mass, "oz", digits=_TOML_DIGITS),
                "layup": _layup_to_list(p.layup),
            }
            for p in spec.parts
        ],
    }
    if spec.insert is not None:
        document["insert"] = {
            "start": _length_text(spec.insert.start),
            "end": _length_text(spec.insert.end),
            "interference": _length_text(spec.insert.interference),
            "layup": _layup_to_list(spec.insert.layup),
        }
        if spec.insert.friction > 0.0:  # written only when set, so older run keys still match
            document["insert"]["friction"] = float(f"{spec.insert.friction:.{_TOML_DIGITS}g}")
    return document
