"""Targets: the seed's columns, user files with units, residuals, bad input."""

from __future__ import annotations

from pathlib import Path

import pytest

from batball.calibrate import Target, load_targets, seed_targets
from batball.errors import SpecError

LBF_PER_IN = 4.4482216152605 / 0.0254  # N/m
MPH = 0.44704  # m/s


def test_seed_targets_are_the_experiment_columns_of_tables_5_to_8() -> None:
    targets = {t.label: t for t in seed_targets("type1")}
    assert len(targets) == 8
    assert targets["ccor @ 95 mph"].value == pytest.approx(0.380)
    assert targets["ccor @ 95 mph"].reference == pytest.approx(0.381)
    assert targets["dynamic_stiffness @ 110 mph"].value == pytest.approx(7260 * LBF_PER_IN)
    assert targets["contact_time @ 95 mph"].value == pytest.approx(1.03e-3)


def test_toml_and_csv_targets_are_read_with_their_units(tmp_path: Path) -> None:
    toml = tmp_path / "t.toml"
    toml.write_text(
        '[[target]]\nquantity = "dynamic_stiffness"\nspeed = "95 mph"\nvalue = "7190 lbf/in"\n'
        '[[target]]\nquantity = "contact_time"\nspeed = "42.4688 m/s"\nvalue = "1.03 ms"\n'
        "weight = 2\n"
    )
    csv = tmp_path / "t.csv"
    csv.write_text(
        "quantity,speed,value,weight\nccor,110 mph,0.355,\npeak_force,95 mph,4700 lbf,3\n"
    )
    ds, contact = load_targets(toml)
    assert ds.value == pytest.approx(7190 * LBF_PER_IN) and ds.speed == pytest.approx(95 * MPH)
    assert contact.value == pytest.approx(1.03e-3) and contact.weight == 2.0
    ccor, peak = load_targets(csv)
    assert (ccor.value, ccor.weight, ccor.speed) == pytest.approx((0.355, 1.0, 110 * MPH))
    assert peak.value == pytest.approx(4700 * 4.4482216152605) and peak.weight == 3.0


def test_residual_is_the_weighted_error_in_units_of_the_goal() -> None:
    # CCOR's goal is 1 %: 1 % high is a residual of 1, times the weight
    assert Target("ccor", 42.0, 0.4, weight=2.0).residual(0.404) == pytest.approx(2.0)
    # peak force's goal is 3 %: 3 % low is -1
    assert Target("peak_force", 42.0, 1000.0).residual(970.0) == pytest.approx(-1.0)


@pytest.mark.parametrize(
    ("row", "field"),
    [
        ('quantity = "dynamic_stiffness"\nspeed = "95 mph"\nvalue = "7190 psi"', "target[0].value"),
        ('quantity = "ccor"\nspeed = "95"\nvalue = 0.38', "target[0].speed"),
        ('quantity = "hardness"\nspeed = "95 mph"\nvalue = 1', "target[0].quantity"),
        ('quantity = "ccor"\nspeed = "95 mph"', "target[0].value"),
        ('quantity = "ccor"\nspeed = "95 mph"\nvalue = 0.38\nweight = -1', "target[0].weight"),
    ],
)
def test_bad_targets_name_the_field(tmp_path: Path, row: str, field: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(f"[[target]]\n{row}\n")
    with pytest.raises(SpecError) as info:
        load_targets(path)
    assert info.value.field == field


def test_compression_target_is_read_with_its_force_unit_and_no_speed(tmp_path: Path) -> None:
    toml = tmp_path / "c.toml"
    toml.write_text('[[target]]\nquantity = "compression"\nvalue = "375 lbf"\nweight = 2\n')
    csv = tmp_path / "c.csv"
    csv.write_text("quantity,speed,value\ncompression,,1.668 kN\nccor,95 mph,0.38\n")
    (compression,) = load_targets(toml)
    assert compression.value == pytest.approx(375 * 4.4482216152605)  # 1668.08 N
    assert (compression.speed, compression.weight) == (0.0, 2.0)
    assert compression.label == "compression @ 0.25 in"
    # its goal is 5 %: 5 % high is a residual of 1, times the weight
    assert compression.residual(1.05 * compression.value) == pytest.approx(2.0)
    from_csv, ccor = load_targets(csv)
    assert from_csv.value == pytest.approx(1668.0) and from_csv.speed == 0.0
    assert ccor.speed == pytest.approx(95 * MPH)


@pytest.mark.parametrize(
    ("row", "field"),
    [
        ('quantity = "compression"\nvalue = "375 psi"', "target[0].value"),
        ('quantity = "compression"\nvalue = 375', "target[0].value"),
        ('quantity = "compression"\nvalue = "375 lbf/in"', "target[0].value"),
        ('quantity = "compression"\nspeed = "95 mph"\nvalue = "375 lbf"', "target[0].speed"),
        ('quantity = "compression"\nvalue = "-375 lbf"', "target[0].compression"),
    ],
)
def test_bad_compression_targets_name_the_field(tmp_path: Path, row: str, field: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(f"[[target]]\n{row}\n")
    with pytest.raises(SpecError) as info:
        load_targets(path)
    assert info.value.field == field
