"""Ball specs: the embedded seed balls load; bad input is refused with the field named."""

from __future__ import annotations

import copy
import math
import pickle
from pathlib import Path
from typing import Any

import pytest

from batball.errors import SpecError
from batball.specs import (
    BallHourglass,
    BallSpec,
    MaterialSpec,
    ball_spec_from_dict,
    ball_spec_to_toml_dict,
    list_embedded_balls,
    load_ball_spec,
)

PSI = 0.45359237 * 9.80665 / 0.0254**2
OUNCE = 0.45359237 / 16.0


def _valid_document() -> dict[str, Any]:
    return {
        "name": "test",
        "circumference": "12 in",
        "mass": "6.75 oz",
        "material": {
            "law": "mat006",
            "bulk_modulus": "800000 psi",
            "g0": "22500 psi",
            "g_inf": "750 psi",
            "beta": "75000 1/s",
        },
    }


def _error_for(document: dict[str, Any]) -> SpecError:
    with pytest.raises(SpecError) as info:
        ball_spec_from_dict(document, source="test")
    return info.value


def test_embedded_balls_are_the_seed_types() -> None:
    assert list_embedded_balls() == ["type1", "type2"]


@pytest.mark.parametrize(
    ("name", "mass_oz", "table4"),
    [
        ("type1", 6.93, (800000.0, 22500.0, 750.0, 75000.0)),
        ("type2", 6.53, (100000.0, 11000.0, 640.0, 60000.0)),
    ],
)
def test_embedded_ball_has_seed_table4_constants(
    name: str, mass_oz: float, table4: tuple[float, float, float, float]
) -> None:
    ball = load_ball_spec(name)
    bulk, g0, g_inf, beta = table4
    assert ball.name == name
    assert ball.circumference == pytest.approx(0.3048, rel=1e-14)
    assert ball.radius == pytest.approx(0.3048 / (2 * math.pi), rel=1e-14)
    assert ball.mass == pytest.approx(mass_oz * OUNCE, rel=1e-14)
    assert ball.material.law == "mat006"
    values = ball.material.values
    assert values["bulk_modulus"] == pytest.approx(bulk * PSI, rel=1e-12)
    assert values["g0"] == pytest.approx(g0 * PSI, rel=1e-12)
    assert values["g_inf"] == pytest.approx(g_inf * PSI, rel=1e-12)
    assert values["beta"] == pytest.approx(beta, rel=1e-15)


def test_mean_density_of_a_12in_6p75oz_ball_is_about_400_kg_per_m3() -> None:
    ball = ball_spec_from_dict(_valid_document(), source="test")
    # docs/physics.md, units: 3.74e-5 lbf s^2/in^4 = 400 kg/m^3.
    assert ball.mean_density == pytest.approx(400.0, rel=0.005)


def test_toml_dict_round_trips_and_is_stable() -> None:
    ball = load_ball_spec("type1")
    document = ball_spec_to_toml_dict(ball)
    assert document["mass"] == "6.93 oz"
    assert document["circumference"] == "12 in"
    assert document["material"]["g0"] == "22500 psi"
    again = ball_spec_from_dict(document, source="round trip")
    assert again.mass == pytest.approx(ball.mass, rel=1e-12)
    assert dict(again.material.values) == pytest.approx(dict(ball.material.values), rel=1e-12)
    assert ball_spec_to_toml_dict(again) == document


def test_specs_are_hashable_and_picklable() -> None:
    ball = load_ball_spec("type2")
    assert pickle.loads(pickle.dumps(ball)) == ball
    assert hash(ball) == hash(load_ball_spec("type2"))


def test_load_from_path(tmp_path: Path) -> None:
    path = tmp_path / "ball.toml"
    path.write_text(
        'name = "soft"\ncircumference = "11.88 in"\nmass = "6.25 oz"\n'
        '[material]\nlaw = "elastic"\nyoungs_modulus = "2000 psi"\npoissons_ratio = 0.45\n'
    )
    ball = load_ball_spec(str(path))
    assert ball.description == ""
    assert ball.material.values["poissons_ratio"] == 0.45
    assert ball.material.values["youngs_modulus"] == pytest.approx(2000 * PSI, rel=1e-12)


def test_unknown_name_or_missing_file_is_refused() -> None:
    with pytest.raises(SpecError, match="ball: 'type3'.*type1, type2"):
        load_ball_spec("type3")


def test_invalid_toml_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "broken.toml"
    path.write_text("name = \n")
    with pytest.raises(SpecError, match="valid TOML"):
        load_ball_spec(path)


@pytest.mark.parametrize("key", ["name", "circumference", "mass", "material"])
def test_missing_field_is_named(key: str) -> None:
    document = _valid_document()
    del document[key]
    error = _error_for(document)
    assert error.field == key
    assert str(error).startswith(f"{key}: 'missing'")


def test_missing_material_parameter_is_named_with_dotted_path() -> None:
    document = _valid_document()
    del document["material"]["beta"]
    assert _error_for(document).field == "material.beta"


@pytest.mark.parametrize(
    ("path", "value", "field"),
    [
        (("material", "g0"), "-22500 psi", "material.g0"),
        (("material", "bulk_modulus"), "-1 psi", "material.bulk_modulus"),
        (("material", "g_inf"), "30000 psi", "material.g_inf"),  # G_inf > G0
        (("material", "beta"), "75000 psi", "material.beta"),
        (("mass",), "95 psi", "mass"),
        (("mass",), "6.5", "mass"),
        (("mass",), "-6.5 oz", "mass"),
        (("mass",), "30 lb", "mass"),
        (("circumference",), "95 mph", "circumference"),
        (("circumference",), "2 m", "circumference"),
        (("name",), "", "name"),
        (("description",), 3, "description"),
    ],
)
def test_bad_value_is_refused_naming_the_field(
    path: tuple[str, ...], value: Any, field: str
) -> None:
    document = _valid_document()
    target = document
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    error = _error_for(document)
    assert error.field == field
    assert str(error).startswith(f"{field}: ")


def test_g_inf_above_g0_message_gives_the_bound() -> None:
    document = _valid_document()
    document["material"]["g_inf"] = "30000 psi"
    assert "g_inf <= g0 (22500 psi)" in str(_error_for(document))


def test_unknown_keys_are_refused() -> None:
    document = _valid_document()
    document["colour"] = "yellow"
    assert _error_for(document).field == "colour"
    document = _valid_document()
    document["material"]["g1"] = "1 psi"
    assert _error_for(document).field == "material.g1"


def test_unknown_law_lists_registered_laws() -> None:
    document = copy.deepcopy(_valid_document())
    document["material"]["law"] = "mat999"
    error = _error_for(document)
    assert error.field == "material.law"
    assert "elastic" in str(error) and "mat006" in str(error)


def test_error_carries_the_source_as_a_note() -> None:
    document = _valid_document()
    del document["mass"]
    with pytest.raises(SpecError) as info:
        ball_spec_from_dict(document, source="my_ball.toml")
    assert any("my_ball.toml" in note for note in info.value.__notes__)


def test_dataclasses_validate_when_built_directly() -> None:
    with pytest.raises(SpecError, match="material.g_inf"):
        MaterialSpec(
            law="mat006", values={"bulk_modulus": 1e9, "g0": 1e6, "g_inf": 2e6, "beta": 1e4}
        )
    material = MaterialSpec(law="elastic", values={"youngs_modulus": 1e7, "poissons_ratio": 0.3})
    with pytest.raises(SpecError, match="mass"):
        BallSpec(name="b", circumference=0.3, mass=0.0, material=material)


def test_a_ball_may_name_its_hourglass_control_and_it_round_trips() -> None:
    """The [hourglass] table is part of the ball's model; a ball without one writes none, so
    the run keys of the balls that name none are what they were."""
    document = _valid_document()
    assert "hourglass" not in ball_spec_to_toml_dict(ball_spec_from_dict(document, source="t"))
    document["hourglass"] = {"type": 4, "coefficient": 0.01}
    ball = ball_spec_from_dict(document, source="test")
    assert ball.hourglass == BallHourglass(type=4, coefficient=0.01)
    written = ball_spec_to_toml_dict(ball)
    assert written["hourglass"] == {"type": 4, "coefficient": 0.01}
    assert ball_spec_from_dict(written, source="round trip") == ball


@pytest.mark.parametrize(
    ("table", "field"),
    [
        ({"type": 6, "coefficient": 0.01}, "hourglass.type"),
        ({"type": 4.0, "coefficient": 0.01}, "hourglass.type"),  # an IHQ is an integer
        ({"type": "4", "coefficient": 0.01}, "hourglass.type"),
        ({"type": 4, "coefficient": -0.01}, "hourglass.coefficient"),
        ({"type": 4, "coefficient": 0.6}, "hourglass.coefficient"),
        ({"type": 4, "coefficient": "0.01"}, "hourglass.coefficient"),
        ({"type": 4}, "hourglass.coefficient"),
        ({"type": 4, "coefficient": 0.01, "qb": 0.1}, "hourglass.qb"),
        ("IHQ 4", "hourglass"),
    ],
)
def test_a_bad_hourglass_table_is_refused_naming_the_field(table: Any, field: str) -> None:
    document = _valid_document()
    document["hourglass"] = table
    error = _error_for(document)
    assert error.field == field
    assert str(error).startswith(f"{field}: ")
