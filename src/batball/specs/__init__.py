"""Validated input: ball specifications, their TOML form, and the seed study's published tables."""

from __future__ import annotations

from batball.specs.ball import (
    EMBEDDED_BALLS,
    BallSpec,
    MaterialSpec,
    ball_spec_from_dict,
    ball_spec_to_toml_dict,
    list_embedded_balls,
    load_ball_spec,
    material_spec_from_dict,
    material_spec_to_toml_dict,
)
from batball.specs.seed import SeedBallImpact, SeedBattedBallSpeed, SeedTables, load_seed_tables

__all__ = [
    "EMBEDDED_BALLS",
    "BallSpec",
    "MaterialSpec",
    "SeedBallImpact",
    "SeedBattedBallSpeed",
    "SeedTables",
    "ball_spec_from_dict",
    "ball_spec_to_toml_dict",
    "list_embedded_balls",
    "load_ball_spec",
    "load_seed_tables",
    "material_spec_from_dict",
    "material_spec_to_toml_dict",
]
