"""Design studies: a planted optimum found, the Pareto front and the influences against closed
forms, certification margins, resuming, and bad study files refused in one line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from batball.design import design_study_from_dict, load_design_study, run_design_study
from batball.design.run import Design, influence, pareto_front
from batball.design.study import Constraint, Mesh, Objective
from batball.errors import SpecError
from batball.lab.registry import LAB_TESTS
from batball.specs import load_bat_spec
from batball.units import OZ

COARSE = {"circumferential": 8, "axial_size": "1 in", "ball_divisions": 2}


def study(**extra: object) -> dict[str, object]:
    document: dict[str, object] = {
        "name": "planted", "bat": "default", "mesh": COARSE,
        "sampling": {"designs": 8, "seed": 3},
        "parameter": [{"name": "endcap", "set": "lumped_mass:endcap",
                       "range": ["0 oz", "3 oz"]}],
    }  # fmt: skip
    document.update(extra)
    return document


def moi_with_endcap(mass_oz: float, runs: Path) -> float:
    """The props test's MOI of the default bat with ``mass_oz`` on its end cap."""
    from batball.calibrate.bat_fit import FreeParameter

    spec = FreeParameter.parse("lumped_mass:endcap").apply(load_bat_spec("default"),
                                                           mass_oz * OZ)  # fmt: skip
    props = LAB_TESTS["props"]
    setup = props.setup(circumferential=8, axial_size="1 in")
    return props.execute({"bat": spec}, setup, runs_dir=runs, reuse=True)[0]["moi_pivot_oz_in2"]


def test_a_planted_moi_optimum_is_found(tmp_path: Path) -> None:
    """The MOI is linear in the end cap's lumped mass (parallel axes), so the mass that gives a
    target MOI is the interpolation between two props runs; the study must find it."""
    i0, i3 = moi_with_endcap(0.0, tmp_path / "runs"), moi_with_endcap(3.0, tmp_path / "runs")
    assert moi_with_endcap(1.5, tmp_path / "runs") == pytest.approx((i0 + i3) / 2, rel=1e-9)
    target = i0 + 0.37 * (i3 - i0)  # a mass of 1.11 oz, which no Sobol point hits
    doc = study(optimise={"evaluations": 20},
                objective=[{"response": "moi_pivot_oz_in2", "target": f"{target} oz*in**2"}])
    result = run_design_study(design_study_from_dict(doc), out_dir=tmp_path / "out",
                              runs_dir=tmp_path / "runs", workers=0)  # fmt: skip
    best = result.ranking[0]
    assert best.values[0] / OZ == pytest.approx(0.37 * 3.0, abs=0.005)  # 0.2 % of the range
    assert abs(best.responses["moi_pivot_oz_in2"] - target) < 1.0  # oz*in^2
    assert best.stage == "optimise"
    best_file = next((tmp_path / "out" / "best").glob("1-*.toml"))
    assert load_bat_spec(best_file).part("endcap").lumped_mass == pytest.approx(best.values[0])


def test_minimum_weight_is_the_thinnest_wall(tmp_path: Path) -> None:
    """Weight grows with a ply's thickness: its minimum is the range's lower end."""
    doc = study(parameter=[{"name": "carbon", "set": "thickness:barrel-carbon",
                            "range": ["0.02 in", "0.08 in"]}],
                optimise={"evaluations": 12}, objective=[{"minimize": "weight_oz"}])  # fmt: skip
    result = run_design_study(design_study_from_dict(doc), out_dir=tmp_path / "out",
                              runs_dir=tmp_path / "runs", workers=0)  # fmt: skip
    assert result.ranking[0].values[0] / 0.0254 == pytest.approx(0.02, abs=0.0006)


def test_a_study_resumes_from_its_stored_runs(tmp_path: Path) -> None:
    """The second run, in a process pool, finds every run the first (in this process) stored."""
    doc = design_study_from_dict(study(objective=[{"minimize": "weight_oz"}]))
    first = run_design_study(doc, out_dir=tmp_path / "a", runs_dir=tmp_path / "runs", workers=0)
    stored = sorted(p.name for p in (tmp_path / "runs").iterdir())
    again = run_design_study(doc, out_dir=tmp_path / "b", runs_dir=tmp_path / "runs", workers=2)
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == stored  # nothing new ran
    assert [d.responses for d in again.designs] == [d.responses for d in first.designs]


def designs(points: list[tuple[float, float]]) -> list[Design]:
    mesh = Mesh(8, 0.0254, 2)
    return [Design(f"d{i}", "sample", mesh, (0.0,), {"a": a, "b": b})
            for i, (a, b) in enumerate(points)]  # fmt: skip


def test_the_pareto_front_of_two_objectives() -> None:
    """Maximise a, minimise b: (3, 3), (2, 1) and (1, 0) are not beaten in both; (2, 2) is
    beaten by (2, 1) and (1, 1) by (1, 0)."""
    found = designs([(3, 3), (2, 2), (2, 1), (1, 1), (1, 0)])
    s = design_study_from_dict(study())
    s = type(s)(**{**s.__dict__, "objectives": (Objective("a", "max"), Objective("b", "min"))})
    assert pareto_front(s, found) == {"d0", "d2", "d4"}


def test_influence_recovers_a_linear_response() -> None:
    """y = 2 x1 - x2 exactly: the standardised coefficients are 2 sd(x1)/sd(y) and -sd(x2)/sd(y),
    R² = 1."""
    rng = np.random.default_rng(0)
    x = rng.uniform(size=(30, 2))
    y = 2 * x[:, 0] - x[:, 1]
    s = design_study_from_dict(study(parameter=[
        {"name": "p1", "set": "lumped_mass:endcap", "range": ["0 oz", "1 oz"]},
        {"name": "p2", "set": "thickness:barrel-carbon", "range": ["0.02 in", "0.08 in"]}]))
    mesh = Mesh(8, 0.0254, 2)
    found = [Design(f"d{i}", "sample", mesh, tuple(row), {"weight_oz": v})
             for i, (row, v) in enumerate(zip(x, y, strict=True))]  # fmt: skip
    coef = influence(s, found)["weight_oz"]
    assert coef["p1"] == pytest.approx(2 * x[:, 0].std() / y.std(), rel=1e-9)
    assert coef["p2"] == pytest.approx(-x[:, 1].std() / y.std(), rel=1e-9)
    assert coef["r2"] == pytest.approx(1.0, abs=1e-12)


def test_the_asa_rule_is_98_mph_at_110_mph() -> None:
    doc = study(ball=[{"name": "type1", "speeds": ["95 mph", "110 mph"]}],
                constraint=[{"rule": "asa-2004-bbs"}])  # fmt: skip
    (c,) = design_study_from_dict(doc).constraints
    assert (c.response, c.upper, c.lower) == ("bbs_type1_110mph", 98.0, None)
    assert c.margin(96.5) == pytest.approx(1.5) and c.margin(98.4) == pytest.approx(-0.4)
    assert Constraint("weight_oz", lower=20.0, upper=24.0).margin(23.0) == pytest.approx(1.0)


@pytest.mark.parametrize(("change", "field"), [
    ({"name": "a b"}, "name"),
    ({"bogus": 1}, "bogus"),
    ({"parameter": []}, "parameter"),
    ({"parameter": [{"name": "x", "set": "angle:nosuch", "range": ["1 deg", "2 deg"]}]},
     "parameter[0].set"),
    ({"parameter": [{"name": "x", "set": "angle:barrel-carbon", "range": ["10", "20 deg"]}]},
     "parameter[0].range"),
    ({"parameter": [{"name": "x", "set": "angle:barrel-carbon", "range": ["30 deg", "20 deg"]}]},
     "parameter[0].range"),
    ({"parameter": [{"name": "x", "set": "lumped_mass:endcap", "range": ["-1 oz", "2 oz"]}]},
     "parameter[0].range"),
    ({"sampling": {"method": "grid"}}, "sampling.method"),
    ({"sampling": {"designs": 0}}, "sampling.designs"),
    ({"mesh": {"circumferential": 3}}, "mesh.circumferential"),
    ({"constraint": [{"rule": "nope"}]}, "constraint[0].rule"),
    ({"constraint": [{"rule": "asa-2004-bbs"}]}, "constraint[0].rule"),  # no 110-mph ball
    ({"constraint": [{"response": "weight_oz", "max": "24"}]}, "constraint[0].max"),
    ({"objective": [{"maximize": "bbs_type9_110mph"}]}, "objective"),
    ({"ball": [{"name": "nosuch"}]}, "ball"),
    ({"optimise": {"evaluations": 5}}, "optimise.evaluations"),  # and no objective
    ({"ball": [{"name": "league", "stamp": "375 / .44"}]}, "ball[0].stamp"),
    ({"ball": [{"name": "league", "stamp": ".44/375", "priors": ["nosuch"]}]}, "ball[0].priors"),
    ({"ball": [{"name": "league", "stamp": ".44/375", "priors": ["type1", "type1"]}]},
     "ball[0].priors"),
    ({"ball": [{"name": "league", "stamp": ".44/375", "fit_evaluations": 0}]},
     "ball[0].fit_evaluations"),
    ({"confirm": {"rounds": 0}}, "confirm.rounds"),
])
def test_a_bad_study_is_one_error_naming_its_field(change: dict, field: str) -> None:
    with pytest.raises(SpecError) as error:
        design_study_from_dict(study(**change))
    assert error.value.field.startswith(field), str(error.value)


def test_the_command_line_refuses_a_missing_study_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from batball.cli import main

    assert main(["design", str(tmp_path / "none.toml")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("batball: error: study") and err.count("\n") == 1
    with pytest.raises(SpecError):
        load_design_study(tmp_path / "none.toml")


def test_a_design_no_test_can_measure_is_recorded_and_the_study_goes_on(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A design whose run fails (here: every end cap over 2 oz, as a ball still on the bat at
    the end time would) is a row with its reason, never ranked, and the study finishes."""
    import batball.design.run as design_run
    from batball.errors import SimulationError
    from batball.report.design_page import write_design_page

    real = design_run.design_responses

    def failing(job: design_run.DesignJob) -> dict[str, float]:
        if float(job.bat["parts"][-1]["lumped_mass"].split()[0]) > 2.0:  # the end cap, oz
            raise SimulationError("the ball is still touching the bat at the end time")
        return real(job)

    monkeypatch.setattr(design_run, "design_responses", failing)
    doc = design_study_from_dict(study(objective=[{"minimize": "weight_oz"}]))
    result = run_design_study(doc, out_dir=tmp_path / "out", runs_dir=tmp_path / "runs",
                              workers=0)  # fmt: skip
    failed = [d for d in result.designs if d.error]
    assert failed and all(d.values[0] / OZ > 2.0 for d in failed)
    assert all("still touching" in d.error and "endcap" in d.error for d in failed)
    assert not any(d.error for d in result.ranking if d.feasible)
    rows = design_run.load_rows(tmp_path / "out")
    assert sum(bool(r["error"]) for r in rows) == len(failed)
    assert write_design_page(tmp_path / "out").is_file()  # the page draws with failed rows


def test_the_confirmation_offset_is_confirmed_minus_screened(tmp_path: Path) -> None:
    """The best design rerun on a finer bat mesh: the offset the summary reports is exactly its
    confirmed weight minus its screened weight (one confirmed design: the mean of one)."""
    import json

    doc = design_study_from_dict(study(
        objective=[{"minimize": "weight_oz"}],
        confirm={"top": 1, "circumferential": 16, "axial_size": "0.5 in", "ball_divisions": 2},
    ))  # fmt: skip
    result = run_design_study(doc, out_dir=tmp_path / "out", runs_dir=tmp_path / "runs",
                              workers=0)  # fmt: skip
    (confirmed,) = [d for d in result.designs if d.stage == "confirm"]
    screened = next(d for d in result.designs if d.id == confirmed.id and d.stage == "sample")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    expected = confirmed.responses["weight_oz"] - screened.responses["weight_oz"]
    assert expected != 0.0  # the meshes differ
    assert summary["confirmation_offset"]["weight_oz"] == pytest.approx(expected, rel=1e-12)


def test_a_second_confirmation_round_reads_the_screening_mesh_by_the_first_ones_offset(
    tmp_path: Path,
) -> None:
    """Weight against a limit: the finer confirmation mesh weighs every design more by the same
    delta (the end cap's lumped mass is exact on both meshes, so the weight is the bare bat's
    plus the mass). With the limit set half a delta above the design nearest 2 oz, the first
    round confirms that design and finds it over the limit; the second round must rerun the
    heaviest design whose screened weight plus delta is within the limit: the next lighter one.
    Only that one is a best design, and the summary names it the best confirmed."""
    import json

    from batball.design.run import sample_unit

    def weight(mass_oz: float, circumferential: int, axial: str) -> float:
        from batball.calibrate.bat_fit import FreeParameter

        props = LAB_TESTS["props"]
        setup = props.setup(circumferential=circumferential, axial_size=axial)
        spec = FreeParameter.parse("lumped_mass:endcap").apply(load_bat_spec("default"),
                                                               mass_oz * OZ)  # fmt: skip
        return props.execute({"bat": spec}, setup, runs_dir=tmp_path / "runs",
                             reuse=True)[0]["weight_oz"]  # fmt: skip

    delta = weight(0.0, 16, "0.5 in") - weight(0.0, 8, "1 in")
    assert weight(3.0, 16, "0.5 in") - weight(3.0, 8, "1 in") == pytest.approx(delta, abs=1e-9)
    assert delta > 0.1  # oz: the meshes differ enough to fail the first round
    doc = study(objective=[{"maximize": "weight_oz"}],
                confirm={"top": 1, "rounds": 2, "circumferential": 16, "axial_size": "0.5 in",
                         "ball_divisions": 2})  # fmt: skip
    masses = sorted(3.0 * sample_unit(design_study_from_dict(doc))[:, 0])  # oz
    k = int(np.argmin([abs(m - 2.0) for m in masses]))
    limit = weight(masses[k], 8, "1 in") + delta / 2
    assert masses[k + 1] > masses[k] + delta / 2  # so design k is the screening mesh's best
    # the heaviest design whose screened weight plus delta is within the limit
    j = max(i for i, m in enumerate(masses) if m + delta <= masses[k] + delta / 2)
    doc["constraint"] = [{"response": "weight_oz", "max": f"{limit} oz"}]
    result = run_design_study(design_study_from_dict(doc), out_dir=tmp_path / "out",
                              runs_dir=tmp_path / "runs", workers=0)  # fmt: skip
    first, second = [d for d in result.designs if d.stage == "confirm"]
    assert (first.round, second.round) == (1, 2)
    assert first.values[0] / OZ == pytest.approx(masses[k], rel=1e-9)
    assert not first.feasible
    assert first.responses["weight_oz"] == pytest.approx(limit + delta / 2, abs=1e-6)
    assert second.values[0] / OZ == pytest.approx(masses[j], rel=1e-9)
    assert second.feasible
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    assert summary["best_confirmed"] == second.id
    assert summary["best"][0]["design"] == second.id
    assert first.id not in [b["design"] for b in summary["best"]]
    assert next((tmp_path / "out" / "best").glob("1-*.toml")).name == f"1-{second.id}.toml"


def test_a_league_ball_carries_each_priors_bbs_and_its_stamped_cor(tmp_path: Path) -> None:
    """A ``[[ball]]`` given by its stamp is fitted per prior on the study's ball mesh (here a
    budget too small to meet the stamp: what is checked is how the fitted balls are used). Each
    prior's BBS column is the lab's BBS test of that prior's fitted ball on the design; the
    league column is the largest of them and the spread their range; the BPF divides the BBCOR
    by the stamped COR, 0.44, as USSSA's rule does. A second run reuses the fits and the runs."""
    from batball.specs import load_ball_spec

    league = {"name": "league", "stamp": ".44/375", "fit_points": 0, "fit_evaluations": 1}
    doc = study(sampling={"designs": 1, "seed": 3}, ball=[league],
                mesh={**COARSE, "ball_divisions": 4},
                constraint=[{"rule": "asa-2004-bbs"}, {"rule": "usssa-bpf-1.20"}])  # fmt: skip
    parsed = design_study_from_dict(doc)
    assert {"bbs_league_110mph_type1", "bbs_league_110mph_type2",
            "bbs_league_110mph_spread"} <= set(parsed.responses)  # fmt: skip
    result = run_design_study(parsed, out_dir=tmp_path / "out", runs_dir=tmp_path / "runs",
                              workers=0)  # fmt: skip
    (design,) = result.designs
    r = design.responses
    fits = {row["prior"]: row for row in result.league_balls}
    assert set(fits) == {"type1", "type2"}
    bbs = LAB_TESTS["bbs"]
    setup = bbs.setup(circumferential=8, axial_size="1 in", divisions=4, speed="110 mph")
    from batball.design.run import design_spec
    from batball.specs.bat import bat_spec_from_dict, bat_spec_to_toml_dict

    # the design's bat as its job carries it (a spec document: the end cap's mass in oz, which
    # reads back 1e-12 off, enough to move a BBS on this coarse mesh by 0.01 mph)
    spec = design_spec(load_bat_spec("default"), parsed.parameters, design.values, "d")
    bat = bat_spec_from_dict(bat_spec_to_toml_dict(spec), source="design")
    for prior, row in fits.items():
        ball = load_ball_spec(row["spec"])
        assert ball.name == f"league-d4-{prior}"  # the fit's ball, from the fit's prior
        assert ball.mass == load_ball_spec(prior).mass
        direct = bbs.execute({"bat": bat, "ball": ball}, setup, runs_dir=tmp_path / "direct",
                             reuse=True)[0]
        assert r[f"bbs_league_110mph_{prior}"] == pytest.approx(direct["bbs_mph"], rel=1e-9)
    each = [r["bbs_league_110mph_type1"], r["bbs_league_110mph_type2"]]
    assert r["bbs_league_110mph"] == max(each)
    assert r["bbs_league_110mph_spread"] == pytest.approx(max(each) - min(each), rel=1e-12)
    assert r["bpf_league_110mph"] == pytest.approx(r["bbcor_league_110mph"] / 0.44, rel=1e-12)
    runs = sorted(p.name for p in (tmp_path / "runs").rglob("*") if p.is_dir())
    again = run_design_study(parsed, out_dir=tmp_path / "out", runs_dir=tmp_path / "runs",
                             workers=0)  # fmt: skip
    assert again.designs[0].responses == r
    assert sorted(p.name for p in (tmp_path / "runs").rglob("*") if p.is_dir()) == runs
