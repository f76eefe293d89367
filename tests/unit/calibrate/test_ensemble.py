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
        ({"speeds": [95.0]}, "speeds"),  # a bare number is not taken as m/s
        ({"colour": "red"}, "colour"),
        ({"name": "../up"}, "name"),
        ({"balls": []}, "balls"),
        ({"balls": ["no-such-ball.toml"]}, "balls[0]"),
        ({"balls": ["type1", "type1"]}, "balls"),
        ({"seed": -1}, "seed"),
        ({"mesh": {"divisions": 1}}, "mesh.divisions"),
        ({"mesh": {"axial_size": "0.5"}}, "mesh.axial_size"),
        ({"mesh": {"axial_size": 0.5}}, "mesh.axial_size"),
        ({"mesh": {"circumferential": 2}}, "mesh.circumferential"),  # the BBS test's own check
        ({"mesh": {"shell": "q4"}}, "mesh.shell"),
        ({"bat": {**GOOD["bat"], "mesh": {"axial_size": 0.5}}}, "bat.mesh.axial_size"),
        ({"bat": {**GOOD["bat"], "free": ["lumped_mass:endcap"] * 2}}, "bat.free"),
        ({"bat": {**GOOD["bat"], "samples": -2}}, "bat.samples"),
        ({"bat": {**GOOD["bat"], "free": ["thickness:no-such-ply"]}}, "bat.free"),
        ({"bat": {**GOOD["bat"], "spread": {"angle:x": "1 deg"}}}, "bat.spread"),
        ({"bat": {**GOOD["bat"], "spread": {"lumped_mass:endcap": "-1 oz"}}}, "bat.spread"),
        ({"bat": {**GOOD["bat"], "targets": {"hoop": ["1950 Hz", "1450 Hz"]}}},
         "bat.targets.hoop"),
        ({"bat": {**GOOD["bat"], "targets": {"weight": "22.1"}}}, "bat.targets.weight"),
        ({"bat": {**GOOD["bat"], "targets": {"weight": 22.1}}}, "bat.targets.weight"),
    ],
)
def test_a_bad_study_names_its_field(change: dict, field: str) -> None:
    with pytest.raises(SpecError) as caught:
        ensemble_study_from_dict({**GOOD, **change})
    assert caught.value.field.startswith(field) or field in caught.value.field


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
    assert float(members[0]["bbs_mph"]) == pytest.approx(direct, rel=1e-9)  # 12 digits in csv
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



def test_a_drawn_bat_outside_its_parameters_bounds_names_the_spread() -> None:
    """A draw that would make the end cap's mass negative (a spread too wide for a Gaussian)
    is refused by the spread's field, with the bound and the drawn value; one inside moves
    the mass by offset x spread."""
    from batball.calibrate.ensemble import drawn_bat
    from batball.specs import load_bat_spec

    study = ensemble_study_from_dict({**GOOD, "bat": {
        **GOOD["bat"], "spread": {"lumped_mass:endcap": "1 oz"}}})  # fmt: skip
    spec = load_bat_spec(study.bat)
    mass = spec.part("endcap").lumped_mass
    moved = drawn_bat(spec, study, (0.5,), "bat-1")
    assert moved.part("endcap").lumped_mass == pytest.approx(mass + 0.5 * 0.028349523125)
    with pytest.raises(SpecError, match=r"^bat.spread.lumped_mass:endcap: .*bat-2 draws -"):
        drawn_bat(spec, study, (-mass / 0.028349523125 - 1.0,), "bat-2")


def _synthetic_rows(bat_effect: list[float], model_effect: dict[str, float],
                    speeds: tuple[float, ...]) -> list[dict]:  # fmt: skip
    """Additive members: BBS = 90 + the bat's effect + the model's effect (+1 mph at the
    higher speed for type 1, so its trend is exactly 1 mph)."""
    rows = []
    for b, effect in enumerate(bat_effect):
        for model, m_effect in model_effect.items():
            for mph in speeds:
                bump = 1.0 if model.startswith("type1") and mph == speeds[-1] else 0.0
                rows.append({"bat": f"bat-{b}", "ball": model[:5], "ball_model": model,
                             "speed_mph": mph, "bbs_mph": 90 + effect + m_effect + bump,
                             "bbcor": 0.5})  # fmt: skip
    return rows


def test_the_summary_of_several_models_drops_a_failed_members_bat_from_its_cell() -> None:
    """Two models per ball type and three bats, additive: each cell's bat and ball parts are the
    closed form's (population sd of the effects) with no interaction, the trend is exactly
    1 mph with no spread; a failed member drops its bat from its cell, its trend and its
    ranking only; a cell with no complete bat stops the summary, naming that cell and its
    members' failure, not another cell's."""
    from types import SimpleNamespace

    from batball.calibrate.ensemble import EnsembleBat, ensemble_summary
    from batball.errors import SimulationError

    models = {"type1": 0.0, "type1-fit": 2.0, "type2": -1.0, "type2-fit": 1.0}
    study = ensemble_study_from_dict({**GOOD, "balls": list(models)})
    speeds = (95.0, 110.0)
    bat_effect = [0.0, 0.6, -0.6]
    bats = [EnsembleBat(f"bat-{b}", None, (0.0,)) for b in range(3)]  # type: ignore[arg-type]
    found = SimpleNamespace(posterior_ratio=[0.5])
    rows = _synthetic_rows(bat_effect, models, speeds)
    why = "type2-fit on bat-2 at 110 mph diverged"
    for r in rows:
        if (r["bat"], r["ball_model"], r["speed_mph"]) == ("bat-2", "type2-fit", 110.0):
            del r["bbs_mph"], r["bbcor"]
            r["error"] = why
    summary = ensemble_summary(study, bats, found, rows)
    cells = {(c["ball"], c["speed_mph"]): c for c in summary["cells"]}
    full = cells["type1", 95.0]["stats"]
    assert cells["type1", 95.0]["bats"] == 3 and cells["type1", 95.0]["models"] == 2
    assert full["sd_bat"] == pytest.approx(np.std(bat_effect), abs=1e-12)
    assert full["sd_ball"] == pytest.approx(1.0, abs=1e-12)  # effects 0 and 2 about their mean
    assert full["sd_interaction"] == pytest.approx(0.0, abs=1e-12)
    assert full["mean"] == pytest.approx(91.0, abs=1e-12)
    assert cells["type2", 110.0]["bats"] == 2  # bat-2 dropped here only
    assert cells["type2", 95.0]["bats"] == 3
    assert cells["type2", 110.0]["stats"]["sd_bat"] == pytest.approx(0.3, abs=1e-12)  # 0, 0.6
    trends = {t["ball"]: t for t in summary["trends"]}
    assert trends["type1"]["stats"]["mean"] == pytest.approx(1.0, abs=1e-12)
    assert trends["type1"]["stats"]["sd"] == pytest.approx(0.0, abs=1e-12)
    assert trends["type2"]["bats"] == 2
    ranking = {r["speed_mph"]: r for r in summary["rankings"]}
    assert ranking[110.0]["bats"] == 2 and ranking[95.0]["bats"] == 3
    # type1 models 90+{0,2}, type2 {89,91} on the same bat: 3 of 4 pairs faster at 95 mph
    assert ranking[95.0]["probability_first_faster"] == pytest.approx(3 / 4)
    assert summary["failed"] == [r for r in rows if "error" in r]
    for r in rows:
        if r["ball"] == "type2" and r["speed_mph"] == 110.0 and r["bat"] != "bat-2":
            del r["bbs_mph"], r["bbcor"]
            r["error"] = "other"
    with pytest.raises(SimulationError, match=r"type2 at 110 mph: no bat .*failed: "):
        ensemble_summary(study, bats, found, rows)
