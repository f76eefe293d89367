"""The ensemble's statistics against closed forms, its study file's checks, and one coarse
ensemble end to end through the CLI (about 30 s)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from batball.calibrate.ensemble import (
    Z95,
    cell_statistics,
    ensemble_study_from_dict,
    load_ensemble_study,
    probability_faster,
)
from batball.cli import main
from batball.errors import SpecError


def test_an_additive_cell_splits_into_its_bat_and_ball_parts() -> None:
    """v[b, m] = 90 + a_b + c_m with zero-mean a and c: the bat's part is the population sd of
    a, the ball's that of c, no interaction, and sd^2 their sum; the interval is mean +- 1.96 sd
    (the two-sided 95 % normal quantile, 1.959964)."""
    a = np.array([-0.3, 0.1, 0.2])
    c = np.array([-1.5, 0.5, 1.0])
    s = cell_statistics(90.0 + a[:, None] + c[None, :])
    assert s["mean"] == pytest.approx(90.0, abs=1e-12)
    assert s["sd_bat"] == pytest.approx(np.sqrt(np.mean(a**2)), rel=1e-12)
    assert s["sd_ball"] == pytest.approx(np.sqrt(np.mean(c**2)), rel=1e-12)
    assert s["sd_interaction"] == pytest.approx(0.0, abs=1e-12)
    assert s["sd"] ** 2 == pytest.approx(np.mean(a**2) + np.mean(c**2), rel=1e-12)
    assert (s["low"], s["high"]) == pytest.approx((90 - Z95 * s["sd"], 90 + Z95 * s["sd"]))
    assert abs(Z95 - 1.959964) < 1e-6
    assert (s["min"], s["max"]) == pytest.approx((90 - 1.8, 90 + 1.2))


def test_an_interaction_is_the_rest_of_the_variance() -> None:
    """v = [[1, -1], [-1, 1]]: both means are zero in every row and column, so all of the
    variance (1) is interaction."""
    s = cell_statistics(np.array([[1.0, -1.0], [-1.0, 1.0]]))
    assert (s["sd_bat"], s["sd_ball"]) == (0.0, 0.0)
    assert s["sd_interaction"] == pytest.approx(1.0) and s["sd"] == pytest.approx(1.0)


def test_the_ranking_probability_counts_pairs_on_the_same_bat() -> None:
    """Two bats; group A's models give (95, 97) on bat 1 and (94, 96) on bat 2, group B's
    (96, 96) and (93, 95). Bat 1: 95 beats neither 96, 97 beats both (2 of 4); bat 2: 94 beats
    93 only, 96 beats both (3 of 4): 5/8. Against B = A's first model, every tie counts a half:
    bat 1 (0.5 + 0.5 + 1 + 1), bat 2 the same: 6/8."""
    a = np.array([[95.0, 97.0], [94.0, 96.0]])
    b = np.array([[96.0, 96.0], [93.0, 95.0]])
    assert probability_faster(a, b) == pytest.approx(5 / 8)
    assert probability_faster(a, a[:, :1].repeat(2, axis=1)) == pytest.approx(6 / 8)


GOOD = {
    "name": "t", "speeds": ["95 mph", "110 mph"], "balls": ["type1", "type2"],
    "bat": {"spec": "fitted", "samples": 1, "free": ["lumped_mass:endcap"]},
}  # fmt: skip


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"speeds": ["110 mph", "95 mph"]}, "speeds"),
        ({"speeds": [95]}, "speeds"),
        ({"colour": "red"}, "colour"),
        ({"name": "../up"}, "name"),
        ({"balls": []}, "balls"),
        ({"balls": ["no-such-ball.toml"]}, "ball"),
        ({"seed": -1}, "seed"),
        ({"mesh": {"divisions": 1}}, "mesh.divisions"),
        ({"mesh": {"axial_size": "0.5"}}, "mesh.axial_size"),
        ({"bat": {**GOOD["bat"], "samples": -2}}, "bat.samples"),
        ({"bat": {**GOOD["bat"], "free": ["thickness:no-such-ply"]}}, "no-such-ply"),
        ({"bat": {**GOOD["bat"], "spread": {"angle:x": "1 deg"}}}, "bat.spread"),
        ({"bat": {**GOOD["bat"], "spread": {"lumped_mass:endcap": "-1 oz"}}}, "bat.spread"),
        ({"bat": {**GOOD["bat"], "targets": {"hoop": ["1950 Hz", "1450 Hz"]}}},
         "bat.targets.hoop"),
        ({"bat": {**GOOD["bat"], "targets": {"weight": "22.1"}}}, "bat.targets.weight"),
    ],
)
def test_a_bad_study_names_its_field(change: dict, field: str) -> None:
    with pytest.raises(SpecError) as caught:
        ensemble_study_from_dict({**GOOD, **change})
    assert field in str(caught.value)


def test_a_good_study_reads_its_units_and_defaults() -> None:
    """Speeds in m/s (95 mph = 42.4688 m/s exactly), the seed's Table 1 and Table 3 as the
    targets unless given, a 0.5-oz default spread for a lumped mass, a given one in SI."""
    study = ensemble_study_from_dict(
        {**GOOD, "bat": {**GOOD["bat"], "spread": {"lumped_mass:endcap": "0.25 oz"},
                         "targets": {"bending": "150 Hz"}}})  # fmt: skip
    assert study.speeds == pytest.approx((95 * 0.44704, 110 * 0.44704), rel=1e-12)
    assert study.spread == pytest.approx((0.25 * 0.028349523125,), rel=1e-12)
    assert study.targets.bending_hz == (150.0,)
    assert study.targets.hoop_hz == (1450.0, 1950.0)  # seed Table 3
    assert study.targets.weight == pytest.approx(22.1 * 0.028349523125, rel=1e-12)


def test_a_coarse_ensemble_end_to_end(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Two bats (the fitted one and one draw), the seed's two balls, one speed, on coarse
    meshes: every member runs; the study's own bat gives the BBS of a direct ``batball bbs``
    run with the same options; a second call reuses
    every stored run (no new run folder) and writes the same summary."""
    study = tmp_path / "study.toml"
    study.write_text(
        'name = "coarse"\nspeeds = ["110 mph"]\nballs = ["type1", "type2"]\n'
        '[bat]\nspec = "fitted"\nsamples = 1\nseed = 0\nfree = ["lumped_mass:endcap"]\n'
        '[bat.mesh]\ncircumferential = 16\naxial_size = "0.5 in"\n'
        '[mesh]\ndivisions = 3\ncircumferential = 8\naxial_size = "1 in"\n', encoding="utf-8")
    runs, out = tmp_path / "runs", tmp_path / "out"
    args = ["ensemble", str(study), "--out", str(out), "--runs-dir", str(runs), "--workers", "0"]
    with pytest.raises(SpecError, match="bat.seed"):  # the seed belongs at the top
        load_ensemble_study(study)
    study.write_text(study.read_text(encoding="utf-8").replace("seed = 0\n", ""),
                     encoding="utf-8")  # fmt: skip
    assert main([*args, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["members"] == 4 and not summary["failed"]
    members = list(csv.DictReader((out / "members.csv").open(encoding="utf-8")))
    assert [(m["bat"], m["ball"]) for m in members] == [
        ("bat-0", "type1"), ("bat-0", "type2"), ("bat-1", "type1"), ("bat-1", "type2")]
    assert main(["bbs", "--bat", "fitted", "--ball", "type1", "--speed", "110 mph",
                 "--divisions", "3", "--circumferential", "8", "--axial-size", "1 in",
                 "--runs-dir", str(tmp_path / "direct"), "--json"]) == 0  # fmt: skip
    direct = json.loads(capsys.readouterr().out)["bbs_mph"]
    assert float(members[0]["bbs_mph"]) == pytest.approx(direct, rel=1e-5)  # 6 digits in csv
    cell = {c["ball"]: c for c in summary["cells"]}
    for group in ("type1", "type2"):
        values = [float(m["bbs_mph"]) for m in members if m["ball"] == group]
        assert cell[group]["stats"]["mean"] == pytest.approx(np.mean(values), rel=1e-5)
        assert cell[group]["stats"]["sd_ball"] == 0.0  # one model per group
        assert cell[group]["experiment_mph"] == {"type1": 97.0, "type2": 93.2}[group]
    a = [float(m["bbs_mph"]) for m in members if m["ball"] == "type1"]
    b = [float(m["bbs_mph"]) for m in members if m["ball"] == "type2"]
    share = np.mean([x > y for x, y in zip(a, b, strict=True)])
    assert summary["rankings"][0]["probability_first_faster"] == pytest.approx(share)
    page = (out / "index.html").read_text(encoding="utf-8")
    low, high = cell["type1"]["stats"]["low"], cell["type1"]["stats"]["high"]
    assert f"{low:.2f} to {high:.2f}" in page and (out / "figures" / "cells.png").stat().st_size
    stored = sorted(map(str, runs.rglob("summary.json")))
    assert main([*args, "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert sorted(map(str, runs.rglob("summary.json"))) == stored
    assert again["cells"] == summary["cells"]
    assert main([*args[:-2], "--workers", "-1"]) == 2
    assert "workers" in capsys.readouterr().err

