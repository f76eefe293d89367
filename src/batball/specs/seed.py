"""The seed study's published numbers (Tables 1-9), in SI, for comparison and regression tests.

Source: the seed study, "Batted-Ball Performance of a Composite Softball Bat as a Function of
Ball Type" (a composite softball bat and two ball types, modelled in HyperMesh + LS-DYNA). The
values live in ``specs/data/seed_tables.toml`` with their units; ``_exp`` fields are the
measurements, ``_fe`` fields the seed's LS-DYNA results, and ``*_pct_printed`` the
"% Difference" columns exactly as printed (see the notes in the TOML file).
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import resources
from typing import Any, TypeVar

from batball.errors import SpecError
from batball.specs.ball import MaterialSpec, material_spec_from_dict
from batball.units import parse_quantity, to_unit


@dataclass(frozen=True)
class SeedBatProperties:
    """Table 1: weight (kg), MOI about the 6-in point (kg m^2), balance point and length (m)."""

    length: float
    weight_exp: float
    weight_fe: float
    moi_exp: float
    moi_fe: float
    balance_point_exp: float
    balance_point_fe: float


@dataclass(frozen=True)
class SeedBarrelCompression:
    """Table 2: preload and final load (N) at the preload and additional displacements (m)."""

    preload_displacement: float
    final_displacement: float
    preload_exp: float
    preload_fe: float
    final_load_exp: float
    final_load_fe: float


@dataclass(frozen=True)
class SeedModal:
    """Table 3: free-free frequencies, Hz (cycles per second)."""

    bending_1_exp: float
    bending_1_fe: float
    bending_2_exp: float
    bending_2_fe: float
    hoop_1_exp: float
    hoop_1_fe: float
    hoop_2_exp: float
    hoop_2_fe: float


@dataclass(frozen=True)
class SeedBallImpact:
    """Tables 5-8 for one ball at one speed against the rigid half-cylinder (ASTM F2845).

    Attributes:
        ball: ``"type1"`` or ``"type2"``.
        speed: inbound speed, m/s.
        ccor_exp, ccor_fe: cylindrical coefficient of restitution (Table 5).
        ds_exp, ds_fe: dynamic stiffness, N/m (Table 6).
        peak_exp, peak_fe: peak load, N (Table 7).
        contact_exp, contact_fe: contact time, s (Table 8).
        ccor_pct_printed, ds_pct_printed, peak_pct_printed, contact_pct_printed: the printed
            "% Difference" columns, percent.
    """

    ball: str
    speed: float
    ccor_exp: float
    ccor_fe: float
    ds_exp: float
    ds_fe: float
    peak_exp: float
    peak_fe: float
    contact_exp: float
    contact_fe: float
    ccor_pct_printed: float
    ds_pct_printed: float
    peak_pct_printed: float
    contact_pct_printed: float


@dataclass(frozen=True)
class SeedBattedBallSpeed:
    """Table 9: batted-ball speed (m/s) for one ball at one inbound speed (m/s), 6-in location."""

    ball: str
    speed: float
    bbs_exp: float
    bbs_fe: float
    bbs_pct_printed: float


@dataclass(frozen=True)
class SeedTables:
    """All the seed's tables. Look rows up with :meth:`ball_impact` and friends."""

    bat: SeedBatProperties
    barrel: SeedBarrelCompression
    modal: SeedModal
    ball_materials: tuple[tuple[str, MaterialSpec], ...]
    ball_impacts: tuple[SeedBallImpact, ...]
    batted_ball_speeds: tuple[SeedBattedBallSpeed, ...]

    def ball_material(self, ball: str) -> MaterialSpec:
        """Table 4: the MAT_006 parameters of ``ball`` (``"type1"``, ``"type2"``)."""
        for name, material in self.ball_materials:
            if name == ball:
                return material
        raise SpecError("ball", ball, f"one of {', '.join(n for n, _ in self.ball_materials)}")

    def ball_impact(self, ball: str, speed_mph: float) -> SeedBallImpact:
        """Tables 5-8 for ``ball`` at ``speed_mph`` (95 or 110)."""
        return _find_row(self.ball_impacts, ball, speed_mph)

    def batted_ball_speed(self, ball: str, speed_mph: float) -> SeedBattedBallSpeed:
        """Table 9 for ``ball`` at ``speed_mph`` (95 or 110)."""
        return _find_row(self.batted_ball_speeds, ball, speed_mph)


_Row = TypeVar("_Row", SeedBallImpact, SeedBattedBallSpeed)


def _find_row(rows: tuple[_Row, ...], ball: str, speed_mph: float) -> _Row:
    """The row of ``ball`` whose speed rounds to ``speed_mph``; SpecError listing rows if none."""
    for row in rows:
        if row.ball == ball and abs(to_unit(row.speed, "mph") - speed_mph) < 0.5:
            return row
    have = ", ".join(f"{r.ball} at {to_unit(r.speed, 'mph'):.0f} mph" for r in rows)
    raise SpecError("ball, speed", f"{ball} at {speed_mph} mph", f"one of {have}")


def load_seed_tables() -> SeedTables:
    """Read ``specs/data/seed_tables.toml`` into :class:`SeedTables` (SI values)."""
    data = resources.files("batball.specs").joinpath("data", "seed_tables.toml")
    document = tomllib.loads(data.read_text(encoding="utf-8"))
    return SeedTables(
        bat=_bat_properties(document["bat_properties"]),
        barrel=_barrel_compression(document["barrel_compression"]),
        modal=SeedModal(**_pairs(document["modal"], "frequency", field="modal")),
        ball_materials=tuple(
            (name, material_spec_from_dict({"law": "mat006", **table}, field="ball_material"))
            for name, table in document["ball_material"].items()
        ),
        ball_impacts=tuple(_ball_impact(row) for row in document["ball_impact"]),
        batted_ball_speeds=tuple(_batted_ball_speed(row) for row in document["batted_ball_speed"]),
    )


def _pair(table: Mapping[str, Any], dimension: str, *, field: str) -> tuple[float, float]:
    """``(experiment, fe)`` of an ``{experiment = ..., fe = ...}`` table, in SI."""
    return (
        parse_quantity(table["experiment"], dimension, field=f"{field}.experiment"),
        parse_quantity(table["fe"], dimension, field=f"{field}.fe"),
    )


def _pairs(table: Mapping[str, Any], dimension: str, *, field: str) -> dict[str, float]:
    """``{<key>_exp: ..., <key>_fe: ...}`` for every ``{experiment, fe}`` sub-table of ``table``."""
    out = {}
    for key, value in table.items():
        if isinstance(value, Mapping):
            out[f"{key}_exp"], out[f"{key}_fe"] = _pair(value, dimension, field=f"{field}.{key}")
    return out


def _bat_properties(table: Mapping[str, Any]) -> SeedBatProperties:
    """Table 1."""
    weight = _pair(table["weight"], "mass", field="bat_properties.weight")
    moi = _pair(table["moi"], "moment_of_inertia", field="bat_properties.moi")
    balance_point = _pair(table["balance_point"], "length", field="bat_properties.balance_point")
    return SeedBatProperties(
        length=parse_quantity(table["length"], "length", field="bat_properties.length"),
        weight_exp=weight[0],
        weight_fe=weight[1],
        moi_exp=moi[0],
        moi_fe=moi[1],
        balance_point_exp=balance_point[0],
        balance_point_fe=balance_point[1],
    )


def _barrel_compression(table: Mapping[str, Any]) -> SeedBarrelCompression:
    """Table 2."""
    field = "barrel_compression"
    return SeedBarrelCompression(
        preload_displacement=parse_quantity(
            table["preload_displacement"], "length", field=f"{field}.preload_displacement"
        ),
        final_displacement=parse_quantity(
            table["final_displacement"], "length", field=f"{field}.final_displacement"
        ),
        **_pairs(table, "force", field=field),
    )


def _ball_impact(row: Mapping[str, Any]) -> SeedBallImpact:
    """One row of Tables 5-8."""
    field = f"ball_impact.{row['ball']}"
    ccor = _pair(row["ccor"], "dimensionless", field=f"{field}.ccor")
    ds = _pair(row["dynamic_stiffness"], "stiffness", field=f"{field}.dynamic_stiffness")
    peak = _pair(row["peak_force"], "force", field=f"{field}.peak_force")
    contact = _pair(row["contact_time"], "time", field=f"{field}.contact_time")
    pct = row["percent_difference"]
    return SeedBallImpact(
        ball=row["ball"],
        speed=parse_quantity(row["speed"], "velocity", field=f"{field}.speed"),
        ccor_exp=ccor[0], ccor_fe=ccor[1],
        ds_exp=ds[0], ds_fe=ds[1],
        peak_exp=peak[0], peak_fe=peak[1],
        contact_exp=contact[0], contact_fe=contact[1],
        ccor_pct_printed=float(pct["ccor"]),
        ds_pct_printed=float(pct["dynamic_stiffness"]),
        peak_pct_printed=float(pct["peak_force"]),
        contact_pct_printed=float(pct["contact_time"]),
    )  # fmt: skip


def _batted_ball_speed(row: Mapping[str, Any]) -> SeedBattedBallSpeed:
    """One row of Table 9."""
    field = f"batted_ball_speed.{row['ball']}"
    bbs = _pair(row["bbs"], "velocity", field=f"{field}.bbs")
    return SeedBattedBallSpeed(
        ball=row["ball"],
        speed=parse_quantity(row["speed"], "velocity", field=f"{field}.speed"),
        bbs_exp=bbs[0],
        bbs_fe=bbs[1],
        bbs_pct_printed=float(row["percent_difference"]),
    )
