"""``batball compare-calibrations`` and ``batball synthetic-data`` (issue 12): every route end to
end on a tiny ball and bat with a tiny budget, and the pieces with closed forms."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from batball.calibrate.dma import load_dma_csv, write_dma_csv
from batball.calibrate.routes import (
    SYNTHETIC_DMA_HZ,
    _impact_start,
    exact_dma,
    load_measured_bbs,
    measure_synthetic,
    shear_relaxation,
)
from batball.cli import main
from batball.errors import SpecError
from batball.specs import load_ball_spec

ROOT = Path(__file__).resolve().parents[3]
TRUTH = ROOT / "benchmarks" / "routes" / "synthetic" / "true-ball.toml"
PSI = 6894.757293168361
TINY_BAT = ["--circumferential", "8", "--axial-size", "1 in"]


def test_relaxation_of_mat006_and_prony_at_zero_and_long_times() -> None:
    """G(0) = G0 and G(t >> 1/beta) = G_inf for MAT_006 (docs/physics.md section 1.1);
    G(0) = G_inf + sum G_i for Prony. The seed's type-1 ball: G0 22,500 psi, G_inf 750 psi."""
    mat006 = load_ball_spec("type1").material
    g = shear_relaxation(mat006, [0.0, 1.0])
    assert g[0] / PSI == pytest.approx(22500.0, rel=1e-12)
    assert g[1] / PSI == pytest.approx(750.0, rel=1e-12)
    truth = load_ball_spec(TRUTH).material
    assert shear_relaxation(truth, [0.0])[0] / PSI == pytest.approx(
        1006 + 13190 + 1787 + 1695, rel=1e-12
    )


def test_prony_ball_converts_to_a_mat006_start_with_the_same_g0_and_g_inf() -> None:
    start = _impact_start(load_ball_spec(TRUTH), "mat006")
    assert start.material.values["g0"] / PSI == pytest.approx(17678.0, rel=1e-12)
    assert start.material.values["g_inf"] / PSI == pytest.approx(1006.0, rel=1e-12)
    # the modulus-weighted mean rate, computed by hand
    beta = (13190 * 58300 + 1787 * 24760 + 1695 * 718500) / (13190 + 1787 + 1695)
    assert start.material.values["beta"] == pytest.approx(beta, rel=1e-12)


def test_exact_dma_of_the_truth_has_the_prony_limits() -> None:
    """At 10 Hz every term is relaxed (w tau < 0.01): G' -> G_inf within 0.03 %; at 1 MHz the
    slowest two are glassy and the fastest (beta 7.2e5 1/s, w tau = 8.7) nearly: G' short of
    G0 = 17,678 psi by 1695 / (1 + 8.7^2) = 22 psi, so within 0.2 %."""
    data = exact_dma(load_ball_spec(TRUTH), SYNTHETIC_DMA_HZ)
    assert data.storage[0] / PSI == pytest.approx(1006.0, rel=3e-4)
    assert data.storage[-1] / PSI == pytest.approx(17678.0, rel=2e-3)
    assert data.frequency_hz[0] == pytest.approx(10.0) and data.frequency_hz[-1] == pytest.approx(
        1e6
    )


def test_synthetic_files_are_readable_by_the_routes(tmp_path: Path) -> None:
    """measure_synthetic on a 4-division ball: the targets load, the DMA CSV reads back the truth
    to its 10 written digits, the BBS file round-trips."""
    from batball.calibrate import load_targets

    truth = load_ball_spec(TRUTH)
    paths = measure_synthetic(truth, tmp_path, divisions=4, bbs_runs={95.0: 89.5})
    cor = load_targets(paths["cor"])
    assert [t.quantity for t in cor] == ["cor", "wall_peak_force"] * 2
    ccor = load_targets(paths["ccor"])
    assert {t.quantity for t in ccor} == {"ccor", "dynamic_stiffness", "peak_force",
                                          "contact_time"}  # fmt: skip
    assert all(0.1 < t.value < 0.7 for t in ccor if t.quantity == "ccor")
    dma = load_dma_csv(paths["dma"], modulus="shear")
    np.testing.assert_allclose(dma.storage, exact_dma(truth, SYNTHETIC_DMA_HZ).storage, rtol=1e-9)
    assert load_measured_bbs(paths["bbs"]) == {95.0: pytest.approx(89.5)}


def _tiny_route_files(folder: Path) -> dict[str, Path]:
    """One speed per impact route (plausible softball values; the test checks plumbing), the
    truth's exact DMA moduli, a measured BBS."""
    folder.mkdir(parents=True)
    files = {name: folder / name for name in ("cor.toml", "ccor.toml", "dma.csv", "bbs.toml")}
    files["cor.toml"].write_text(
        '[[target]]\nquantity = "cor"\nspeed = "95 mph"\nvalue = 0.33\n\n'
        '[[target]]\nquantity = "wall_peak_force"\nspeed = "95 mph"\nvalue = "5400 lbf"\n'
    )
    files["ccor.toml"].write_text(
        '[[target]]\nquantity = "ccor"\nspeed = "95 mph"\nvalue = 0.37\n\n'
        '[[target]]\nquantity = "dynamic_stiffness"\nspeed = "95 mph"\nvalue = "6700 lbf/in"\n'
    )
    write_dma_csv(files["dma.csv"], exact_dma(load_ball_spec(TRUTH), SYNTHETIC_DMA_HZ))
    files["bbs.toml"].write_text('[[bbs]]\nspeed = "95 mph"\nvalue = "88 mph"\n')
    return files


def test_each_route_runs_end_to_end(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """cor, ccor and dma routes in one command on a 4-division ball and an 8 x 1-in bat, with
    the smallest budget (the start and one least-squares step): a plumbing test (the numbers
    mean nothing on these meshes), checking what holds whatever the mesh: the error is the
    prediction minus the measured BBS, BBS = 85 + 110 e_A with |e_A| < 1 (ASA,
    docs/physics.md section 4.2), the DMA ball keeps the given K and fits the exact moduli of its
    own model."""
    f = _tiny_route_files(tmp_path / "data")
    args = ["compare-calibrations", "--ball", "type1", "--cor-targets", str(f["cor.toml"]),
            "--ccor-targets", str(f["ccor.toml"]), "--dma", str(f["dma.csv"]),
            "--bulk-modulus", "243500 psi", "--measured-bbs", str(f["bbs.toml"]),
            "--speeds", "95 mph", "--divisions", "4", *TINY_BAT, "--global-points", "0",
            "--max-evaluations", "1", "--workers", "0", "--end-time", "1.5 ms",
            "--runs-dir", str(tmp_path / "runs"), "--json"]  # fmt: skip
    assert main(args) == 0
    report = json.loads(capsys.readouterr().out)
    routes = {r["route"]: r for r in report["routes"]}
    assert list(routes) == ["cor", "ccor", "dma"]
    for r in routes.values():
        assert abs(r["bbs_mph"]["95"] - 85.0) < 110.0
        assert r["bbs_error_mph"]["95"] == pytest.approx(r["bbs_mph"]["95"] - 88.0, abs=1e-12)
    assert routes["dma"]["law"] == "prony3"
    assert routes["dma"]["parameters"]["bulk_modulus"] == "2.435e+05 psi"
    assert routes["cor"]["law"] == routes["ccor"]["law"] == "mat006"
    assert routes["dma"]["fit"]["rms_relative_residual"] < 1e-6  # exact moduli, same model
    assert report["best_route"] in routes


def test_no_route_data_and_bad_use_are_spec_errors(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    base = ["compare-calibrations", "--ball", str(TRUTH), *TINY_BAT, "--runs-dir", str(tmp_path)]
    assert main(base) == 2
    assert "routes" in capsys.readouterr().err
    assert main([*base, "--use", "flat=ball.toml"]) == 2
    assert "use" in capsys.readouterr().err
    with pytest.raises(SpecError, match="measured-bbs"):
        load_measured_bbs(tmp_path / "none.toml")


def test_seed_ball_defaults_to_seed_ccor_targets_and_table_9() -> None:
    """For an embedded ball with no files: the CCOR route on the seed's Tables 5-8 (8 targets)
    and the measured BBS of Table 9 (type 1: 96.5 and 97.0 mph at 95 and 110 mph, the seed's
    experiment column); ``--use`` replaces the route's calibration by a ball file."""
    import argparse

    from batball.calibrate.routes_command import add_compare_arguments, measured_bbs, route_data

    parser = argparse.ArgumentParser()
    add_compare_arguments(parser)
    args = parser.parse_args([])
    routes = route_data(args, "type1")
    assert [r.route for r in routes] == ["ccor"]
    assert len(routes[0].targets) == 8
    bbs = measured_bbs(args, "type1", [95.0, 110.0])
    assert bbs == {95.0: pytest.approx(96.5, abs=0.05), 110.0: pytest.approx(97.0, abs=0.05)}
    fitted = ROOT / "benchmarks" / "calibration" / "type1-mat006.toml"
    args = parser.parse_args(["--use", f"ccor={fitted}"])
    reused = route_data(args, "type1")
    assert reused[0].calibrated is not None and reused[0].calibrated.material.law == "mat006"
