"""Bat specs: the embedded default loads as the seed describes it; bad input names the field."""

from __future__ import annotations

import copy
import math
from typing import Any

import pytest
import tomli_w

from batball.errors import SpecError
from batball.specs import (
    bat_spec_from_dict,
    bat_spec_to_toml_dict,
    list_embedded_bats,
    load_bat_spec,
)

IN = 0.0254


@pytest.fixture(scope="module")
def default_document() -> dict[str, Any]:
    return bat_spec_to_toml_dict(load_bat_spec("default"))


def _error_for(document: dict[str, Any]) -> SpecError:
    with pytest.raises(SpecError) as info:
        bat_spec_from_dict(document, source="test")
    return info.value


def test_default_bat_has_the_seeds_ten_parts_and_a_10_in_insert() -> None:
    spec = load_bat_spec("default")
    assert list_embedded_bats() == ["default"]
    assert len(spec.parts) == 10
    assert spec.parts[0].name == "knob" and spec.parts[-1].name == "endcap"
    assert spec.length == pytest.approx(33.1 * IN)
    assert spec.insert is not None
    assert spec.insert.end - spec.insert.start == pytest.approx(10 * IN)
    assert spec.insert.interference == pytest.approx(0.001 * IN)


def test_default_materials_carry_the_minor_poissons_ratio() -> None:
    materials = load_bat_spec("default").materials
    assert materials["carbon"].nu_ab == pytest.approx(0.27, rel=1e-3)
    assert materials["glass"].nu_ab == pytest.approx(0.28, rel=1e-3)


def test_default_barrel_diameter_is_the_softball_limit() -> None:
    spec = load_bat_spec("default")
    assert 2 * spec.outer_radius(27.0 * IN) == pytest.approx(2.25 * IN)


def test_toml_round_trip_gives_the_same_bat(default_document, tmp_path) -> None:
    path = tmp_path / "bat.toml"
    path.write_text(tomli_w.dumps(default_document))
    assert load_bat_spec(path) == load_bat_spec("default")


def test_angle_without_a_unit_is_refused_naming_the_ply(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["parts"][1]["layup"][0]["angle"] = 30
    error = _error_for(document)
    assert error.field == "parts[1].layup[0].angle"
    assert "deg" in str(error)


def test_unknown_material_is_refused_naming_the_ply(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["parts"][3]["layup"][1]["material"] = "kevlar"
    error = _error_for(document)
    assert error.field == "parts[3].layup[1].material"
    assert "carbon, glass" in str(error)


def test_gap_between_parts_is_refused(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["parts"][2]["start"] = "5.5 in"
    assert _error_for(document).field == "parts[2].start"


def test_major_ratio_as_prba_is_refused(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["materials"]["carbon"]["prba"] = 0.27
    assert _error_for(document).field == "materials.carbon.prba"


def test_profile_must_end_at_the_bat_length(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["length"] = "34 in"
    assert _error_for(document).field == "profile.stations[-1].x"


def test_wall_thicker_than_the_handle_radius_is_refused(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["parts"][2]["layup"][0]["thickness"] = "0.5 in"
    assert _error_for(document).field == "parts[2].layup"


def test_insert_outside_the_cylindrical_barrel_is_refused(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["insert"]["start"] = "15 in"
    assert _error_for(document).field == "insert"


def test_unknown_key_is_refused(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["parts"][0]["colour"] = "red"
    assert _error_for(document).field == "parts[0].colour"


def test_missing_file_names_the_bat_field(tmp_path) -> None:
    with pytest.raises(SpecError) as info:
        load_bat_spec(tmp_path / "missing.toml")
    assert info.value.field == "bat"


def test_isotropic_layer_is_accepted(default_document) -> None:
    document = copy.deepcopy(default_document)
    document["materials"]["aluminium"] = {
        "law": "elastic", "density": "2.7 g/cm**3", "youngs_modulus": "70 GPa",
        "poissons_ratio": 0.33,
    }  # fmt: skip
    document["parts"][-1]["layup"].append(
        {"material": "aluminium", "thickness": "0.02 in", "angle": "0 deg"}
    )
    spec = bat_spec_from_dict(document, source="test")
    aluminium = spec.materials["aluminium"]
    assert aluminium.gab == pytest.approx(70e9 / (2 * 1.33))
    assert spec.parts[-1].layup[-1].angle == 0.0
    assert math.isclose(aluminium.density, 2700.0)
