"""Validated input: ball and bat specifications, their TOML form, and the seed's tables."""

from __future__ import annotations

from batball.specs.ball import (
    EMBEDDED_BALLS,
    BallHourglass,
    BallSpec,
    MaterialSpec,
    ball_spec_from_dict,
    ball_spec_to_toml_dict,
    list_embedded_balls,
    load_ball_spec,
    material_spec_from_dict,
    material_spec_to_toml_dict,
)
from batball.specs.bat import (
    EMBEDDED_BATS,
    BatSpec,
    InsertSpec,
    PartSpec,
    PlySpec,
    bat_spec_from_dict,
    bat_spec_to_toml_dict,
    list_embedded_bats,
    load_bat_spec,
)
from batball.specs.seed import SeedBallImpact, SeedBattedBallSpeed, SeedTables, load_seed_tables

__all__ = [
    "EMBEDDED_BALLS",
    "EMBEDDED_BATS",
    "BallHourglass",
    "BallSpec",
    "BatSpec",
    "InsertSpec",
    "PartSpec",
    "PlySpec",
    "MaterialSpec",
    "SeedBallImpact",
    "SeedBattedBallSpeed",
    "SeedTables",
    "ball_spec_from_dict",
    "ball_spec_to_toml_dict",
    "bat_spec_from_dict",
    "bat_spec_to_toml_dict",
    "list_embedded_balls",
    "list_embedded_bats",
    "load_ball_spec",
    "load_bat_spec",
    "load_seed_tables",
    "material_spec_from_dict",
    "material_spec_to_toml_dict",
]
