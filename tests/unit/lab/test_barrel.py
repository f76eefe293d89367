"""The double-wall bat's interference fit and barrel compression on a coarse mesh (16 x 0.4 in).

Expectations are closed forms (docs/physics.md section 6.7 thin rings, the membrane hoop force
N = p R_c), the linearity of a frictionless elastic fit, and symmetry; the store and the CLI
are checked for their files and reuse.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from batball.cli import main
from batball.errors import SpecError
from batball.lab.barrel import membrane_stress, run_barrel_compression
from batball.models.barrel import (
    BarrelModel,
    BarrelTestOptions,
    Prestress,
    build_barrel_model,
    compute_prestress,
    contact_areas,
    thin_ring_interference_pressure,
)
from batball.specs import load_bat_spec
from batball.units import IN

COARSE = {"circumferential": 16, "axial_size": 0.4 * IN}


@pytest.fixture(scope="module")
def model() -> BarrelModel:
    return build_barrel_model(load_bat_spec("default"), **COARSE)


@pytest.fixture(scope="module")
def prestress(model: BarrelModel) -> Prestress:
    return compute_prestress(model, ramp_steps=2)


def test_mean_fit_pressure_matches_the_thin_ring_formula(model, prestress) -> None:
    """Within 3 %: the formula's R^2 against the membrane R R_c (about +-4 % for each wall,
    largely cancelling) and the barrel's restraint beyond the insert's ends (sqrt(R t) = 0.3 in
    against a 10-in insert)."""
    mean = prestress.contact_force.sum() / contact_areas(model).sum()
    assert mean == pytest.approx(thin_ring_interference_pressure(model.spec), rel=0.03)
    assert prestress.active.all()


def test_the_ramped_overlap_loads_linearly_and_ends_where_one_step_does(model, prestress) -> None:
    """A frictionless elastic fit is linear in the overlap and path-independent."""
    assert prestress.ramp_pressure[0] == pytest.approx(0.5 * prestress.ramp_pressure[1], rel=1e-9)
    one_step = compute_prestress(model, ramp_steps=1)
    np.testing.assert_allclose(one_step.contact_force, prestress.contact_force, rtol=1e-8)


def test_hoop_stresses_follow_the_membrane_balance(model, prestress) -> None:
    """Barrel in tension, insert in compression, with N = p R_c carried by each wall: the median
    mean hoop stress under the insert's middle within 5 % of p R_c / t (hoop N of a thin ring)."""
    spec = model.spec
    assert spec.insert is not None
    pressure = prestress.contact_force.sum() / contact_areas(model).sum()
    bore = spec.insert_outer_radius() - spec.insert.interference
    stress = membrane_stress(model, prestress.u)[:, 1]
    centre_x = model.mesh.points[model.mesh.cells, 0].mean(axis=1)
    middle = np.abs(centre_x - 0.5 * (spec.insert.start + spec.insert.end)) < 2 * IN
    for name, sign in (("barrel-2", 1.0), ("insert", -1.0)):
        cells = np.intersect1d(model.mesh.cell_sets[name] if name != "barrel-2" else
                               np.concatenate([model.mesh.cell_sets["barrel-2"],
                                               model.mesh.cell_sets["barrel-3"]]),
                               np.flatnonzero(middle))  # fmt: skip
        layup = spec.insert.layup if name == "insert" else spec.part(name).layup
        expected = sign * pressure * bore / spec.laminate(layup).thickness
        assert np.median(stress[cells]) == pytest.approx(expected, rel=0.05)


def test_compression_is_the_same_at_every_orientation_and_balanced(model, prestress) -> None:
    """The reconstructed bat is axisymmetric and the mesh meets the platens at nodes: preload
    and final load agree across 0, 90, 45, -45 deg (1e-6); the insert's top and bottom halves
    carry equal contact force (the test is symmetric about the bat's axis); force grows."""
    result = run_barrel_compression(model, prestress, BarrelTestOptions())
    np.testing.assert_allclose(result.preloads(), result.preloads()[0], rtol=1e-6)
    np.testing.assert_allclose(result.final_loads(), result.final_loads()[0], rtol=1e-6)
    curve = result.curves[0]
    np.testing.assert_allclose(curve.insert_top, curve.insert_bottom, rtol=1e-6)
    assert np.all(np.diff(curve.force) > 0) and result.preloads()[0] > 0
    assert curve.insert_top[-1] > prestress.contact_force.sum() / 2  # squeezed harder


def test_bad_bats_and_meshes_are_refused() -> None:
    spec = load_bat_spec("default")
    with pytest.raises(SpecError, match="circumferential"):
        build_barrel_model(spec, circumferential=12, axial_size=0.4 * IN)
    from dataclasses import replace

    with pytest.raises(SpecError, match="insert"):
        build_barrel_model(replace(spec, insert=None), **COARSE)


def test_cli_prints_table2_numbers_writes_the_folder_and_reuses_the_prestress(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["barrel", "--bat", "default", "--json", "--runs-dir", str(tmp_path),
            "--circumferential", "16", "--axial-size", "0.4 in"]  # fmt: skip
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary.keys() >= {"preload_lbf", "final_load_lbf", "interference_pressure_psi",
                              "wall_seconds"}  # fmt: skip
    assert summary["prestress_reused"] is False
    folder = Path(summary["run_folder"])
    for name in ("summary.json", "force_travel.csv", "force_travel.png", "prestress.png"):
        assert (folder / name).is_file()
    assert (Path(summary["prestress_folder"]) / "prestress.npz").is_file()
    # Without the compression run, the next one starts from the stored pre-stress (drdisp).
    (folder / "summary.json").unlink()
    assert main(args) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["prestress_reused"] is True
    assert again["preload_lbf"] == pytest.approx(summary["preload_lbf"], rel=1e-9)


def test_cli_refuses_a_zero_ramp(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    args = ["barrel", "--ramp-steps", "0", "--runs-dir", str(tmp_path)]
    assert main(args) == 2
    assert "ramp-steps" in capsys.readouterr().err


def test_cli_hourglass_ratio_belongs_to_the_explicit_bt_shells(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    base = ["barrel", "--runs-dir", str(tmp_path), "--hourglass-ratio"]
    assert main([*base, "0.5"]) == 2  # the static MITC4 shells have no hourglass control
    assert "hourglass-ratio" in capsys.readouterr().err
    assert main([*base, "0.5", "--solver", "explicit"]) == 2  # nor the co-rotational MITC4
    assert "--shell bt" in capsys.readouterr().err
    assert main([*base, "5", "--solver", "explicit", "--shell", "bt"]) == 2  # beyond r = 1
    assert "hourglass_ratio" in capsys.readouterr().err
    assert main(["barrel", "--runs-dir", str(tmp_path), "--shell", "bt"]) == 2  # static
    assert "shell" in capsys.readouterr().err


def test_condensed_compression_equals_the_active_set_iteration(model, prestress) -> None:
    """The condensed solve (one factorisation, a small exact LCP per level) and the plain
    active-set iteration over every gap reach the same penalty solution, within 1e-6 of the
    force. The iteration needs a 1-nm hysteresis to stop two gaps cycling (the error it allows
    is at most k x 1 nm per gap held in the wrong state); the measured difference is below
    that, so 1e-6 is the iteration's tolerance, not the condensed solve's."""
    from batball.models.barrel import compression_supports, platen_gaps
    from batball.solvers.static_contact import solve_static_contact

    options = BarrelTestOptions(orientations_deg=(45.0,), curve_orientations=0)
    condensed = run_barrel_compression(model, prestress, options).curves[0]
    fixed, springs = compression_supports(model, options, 45.0)
    load = np.array([0.0, np.cos(np.radians(45.0)), np.sin(np.radians(45.0))])
    for travel, force in zip(condensed.travel, condensed.force, strict=True):
        top, bottom = platen_gaps(model, options, 45.0, travel, prestress.u)
        solution = solve_static_contact(
            model.stiffness, [model.interference, top, bottom, springs], fixed_dofs=fixed,
            initial_active=[prestress.active, top.initial <= 0, bottom.initial <= 1e-12,
                            np.ones(4, bool)], hysteresis=1e-9, max_iterations=60,
        )  # fmt: skip
        translation = np.zeros((model.mesh.n_points, 6))
        translation[:, :3] = load
        cosine = top.matrix @ translation.ravel()
        assert -(solution.forces[1] * cosine).sum() == pytest.approx(force, rel=1e-6)


def test_the_insert_halves_are_split_by_node_angle(model) -> None:
    """Figure 13's top and bottom halves: every insert node on one side, except the two columns
    on the dividing plane (2 of 16 around), which count half to each."""
    from batball.lab.barrel import halves, insert_cosines
    from batball.models.barrel import load_axes

    cosine = insert_cosines(model, load_axes(0.0)[0])
    assert np.mean(np.abs(cosine) < 1e-9) == pytest.approx(2 / 16)
    top, bottom = halves(np.where(cosine > 1e-9, 1.0, 0.0), cosine)
    assert (top, bottom) == (pytest.approx(np.sum(cosine > 1e-9)), 0.0)


def test_cli_runs_the_squeeze_with_friction_and_refuses_a_negative_one(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    base = ["barrel", "--json", "--runs-dir", str(tmp_path), "--circumferential", "8",
            "--axial-size", "1 in"]  # fmt: skip
    assert main(base) == 0
    frictionless = json.loads(capsys.readouterr().out)
    assert main([*base, "--friction", "0.3"]) == 0
    rubbing = json.loads(capsys.readouterr().out)
    assert rubbing["insert_friction"] == 0.3 and frictionless["insert_friction"] == 0.0
    assert rubbing["preload_lbf"] > frictionless["preload_lbf"]  # sticking stiffens the start
    assert main([*base, "--friction", "-0.1"]) == 2
    assert "friction" in capsys.readouterr().err
    assert main([*base, "--platen-friction", "0.3"]) == 0
    assert json.loads(capsys.readouterr().out)["platen_friction"] == 0.3
    assert main([*base, "--platen-friction", "11"]) == 2
    assert "platen_friction: 11" in capsys.readouterr().err


def test_cli_runs_the_explicit_squeeze_into_its_own_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    base = ["barrel", "--runs-dir", str(tmp_path), "--circumferential", "8",
            "--axial-size", "1 in", "--solver", "explicit"]  # fmt: skip
    assert main([*base, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["solver"].startswith("explicit")
    assert summary.keys() >= {"preload_lbf", "final_load_lbf", "interference_pressure_psi",
                              "wall_seconds", "settling", "cycles"}  # fmt: skip
    assert len(summary["preload_by_orientation_lbf"]) == 4
    assert summary["preload_lbf"] > 0 and summary["final_load_lbf"] > 0
    folder = Path(summary["run_folder"])
    assert folder.name.startswith("barrel-explicit-")
    for name in ("summary.json", "force_travel.csv", "force_travel.png"):
        assert (folder / name).is_file()
    assert main(base) == 0  # the stored run, told in words with the solver named
    assert "solver: explicit: co-rotational MITC4" in capsys.readouterr().out
    # the one-point shells with LS-DYNA's hourglass control are softer under the platens
    assert main([*base, "--shell", "bt", "--hourglass-ratio", "0.01", "--json"]) == 0
    soft = json.loads(capsys.readouterr().out)
    assert soft["run_folder"] != summary["run_folder"] and soft["shell"] == "bt"
    assert soft["preload_lbf"] < summary["preload_lbf"]


def test_an_interrupted_explicit_run_resumes_after_the_last_orientation_done(
    tmp_path: Path,
) -> None:
    from batball.lab.barrel_explicit import ExplicitBarrelOptions
    from batball.lab.barrel_run import orientation_file, run_explicit_barrel_test
    from batball.models.barrel import BarrelTestOptions
    from batball.specs import load_bat_spec

    spec = load_bat_spec("default")
    test = BarrelTestOptions(orientations_deg=(0.0, 90.0), curve_orientations=0)
    explicit = ExplicitBarrelOptions(circumferential=8, axial_size=1.0 * IN)
    first, folder = run_explicit_barrel_test(spec, runs_dir=tmp_path, options=test,
                                             explicit=explicit)  # fmt: skip
    # interrupted after 0 deg: no summary, the 90-deg record lost; mark the kept one
    (folder / "summary.json").unlink()
    orientation_file(folder, 90.0).unlink()
    kept = json.loads(orientation_file(folder, 0.0).read_text())
    kept["cycles"] = 7
    orientation_file(folder, 0.0).write_text(json.dumps(kept))
    resumed, _ = run_explicit_barrel_test(spec, runs_dir=tmp_path, options=test,
                                          explicit=explicit)  # fmt: skip
    assert resumed["cycles"] == 7 + first["cycles"] // 2  # 0 deg read back, 90 deg run again
    # the fit relaxed by the first run is restored (drdisp), and the squeeze from it is the same
    assert not first["prestress_reused"] and resumed["prestress_reused"]
    assert resumed["interference_pressure_psi"] == pytest.approx(
        first["interference_pressure_psi"], rel=1e-12)
    assert resumed["preload_lbf"] == pytest.approx(first["preload_lbf"], rel=1e-12)


def test_summary_seed_table2_is_the_papers_table_in_whole_pounds() -> None:
    """Seed Table 2 as printed (lbf): experiment 186 / 368, LS-DYNA 155 / 386. The summary reads
    it from specs/seed.py in newtons and must give the printed pounds back."""
    from batball.lab.barrel_run import seed_table2

    assert seed_table2() == {
        "experiment": {"preload_lbf": 186.0, "final_load_lbf": 368.0},
        "seed_lsdyna": {"preload_lbf": 155.0, "final_load_lbf": 386.0},
    }
