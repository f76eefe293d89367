"""The fields a run writes for ParaView, read back with batball.read_fields: ball, target, bat."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import batball
from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.elements.hex8_block import pack_history
from batball.lab.protocol import run_warnings
from batball.results.fields import read_fields, target_surfaces
from batball.solvers.frames import hex_cell_stress, stress_invariants
from batball.units import IN, LBF, MPH


def von_mises_by_hand(s: np.ndarray) -> np.ndarray:
    """sqrt(((sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2) / 2 + 3 (sxy^2 + syz^2 + szx^2))."""
    sxx, syy, szz, sxy, syz, szx = (s[:, k].astype(np.float64) for k in range(6))
    normal = 0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
    return np.sqrt(normal + 3.0 * (sxy**2 + syz**2 + szx**2))


def test_invariants_of_a_pressure_a_tension_and_a_shear() -> None:
    p, sigma, tau = 2.0e6, 3.0e6, 1.0e6
    stress = np.array(
        [[-p, -p, -p, 0, 0, 0], [sigma, 0, 0, 0, 0, 0], [0, 0, 0, tau, 0, 0]], dtype=float
    )
    von_mises, pressure = stress_invariants(stress)
    np.testing.assert_allclose(von_mises, [0.0, sigma, np.sqrt(3.0) * tau], atol=1e-9)
    np.testing.assert_allclose(pressure, [p, -sigma / 3.0, 0.0], atol=1e-9)


@pytest.mark.parametrize("n_terms", [1, 3])
def test_the_hex_stress_is_s_inf_plus_every_h_less_the_pressure(n_terms: int) -> None:
    rng = np.random.default_rng(n_terms)
    n = 21  # two blocks, the second part-filled
    s_inf, h = rng.normal(size=(n, 6)), rng.normal(size=(n, 6 * n_terms))
    pressure = rng.normal(size=n)
    history = pack_history(np.ones(n), s_inf, h, pressure, rng.normal(size=(n, 4, 3)),
                           n_terms=n_terms)  # fmt: skip
    expected = s_inf + sum(h[:, 6 * k : 6 * k + 6] for k in range(n_terms))
    expected[:, :3] -= pressure[:, None]
    np.testing.assert_allclose(hex_cell_stress(history, n), expected, rtol=1e-12, atol=1e-12)


def test_target_surfaces_lie_on_the_targets_with_outward_quads() -> None:
    wall = RigidPlane(point=np.array([0.0, 0.0, -0.05]), normal=np.array([0.0, 0.0, 1.0]),
                      velocity=np.array([0.0, 0.0, 0.2]))  # fmt: skip
    cylinder = RigidCylinder(axis_point=np.zeros(3), axis=np.array([1.0, 0.0, 0.0]),
                             front=np.array([0.0, 0.0, 1.0]), radius=0.03, length=0.15)  # fmt: skip
    mesh, index, velocity = target_surfaces([wall, cylinder], center=np.zeros(3), size=0.2)
    on_wall = mesh.cells[index == 0]
    np.testing.assert_allclose(mesh.points[on_wall.ravel(), 2], -0.05)
    on_cylinder = np.unique(mesh.cells[index == 1])
    np.testing.assert_allclose(np.hypot(*mesh.points[on_cylinder, 1:].T), 0.03)
    assert (mesh.points[on_cylinder, 2] >= -1e-12).all()  # the front half only
    p = mesh.points[mesh.cells]
    normals = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    centres = p.mean(axis=1)
    assert normals[index == 0, 2].min() > 0  # out of the wall, toward the ball
    assert (np.einsum("ij,ij->i", normals[index == 1, 1:], centres[index == 1, 1:]) > 0).all()
    np.testing.assert_allclose(velocity[np.unique(on_wall)], [[0.0, 0.0, 0.2]] * 4)
    np.testing.assert_allclose(velocity[on_cylinder], 0.0)


@pytest.fixture(scope="module")
def ccor(tmp_path_factory: pytest.TempPathFactory) -> batball.Result:
    return batball.ccor("type1", divisions=4, runs_dir=tmp_path_factory.mktemp("runs"))


def test_a_ccor_run_reads_back_with_its_fields(ccor: batball.Result) -> None:
    series = batball.read_fields(ccor)
    assert set(series) == {"fields", "target"}
    ball = series["fields"]
    assert len(ball) > 10 and np.all(np.diff(ball.times) > 0)
    for name in ("displacement", "velocity", "contact_force", "contact_pressure"):
        assert np.isfinite(ball.point_field(name)).all(), name
    for name in ("stress", "von_mises", "pressure", "volumetric_strain"):
        assert np.isfinite(ball.cell_field(name)).all(), name
    velocity = ball.point_field("velocity")
    np.testing.assert_allclose(velocity[0, :, 2], -ccor.summary["inbound_mph"] * MPH, rtol=1e-6)
    # the frame of the largest contact force: its von Mises stress against the tensor's
    force = ball.point_field("contact_force")
    frame = int(np.argmax(force[:, :, 2].sum(axis=1)))
    mesh = ball.meshes[frame]
    stress = mesh.cell_data["stress"][0]
    np.testing.assert_allclose(mesh.cell_data["von_mises"][0], von_mises_by_hand(stress),
                               rtol=1e-5, atol=1e-3 * stress.std())  # fmt: skip
    np.testing.assert_allclose(mesh.cell_data["pressure"][0], -stress[:, :3].mean(axis=1),
                               rtol=1e-5, atol=1e-4 * stress.std())  # fmt: skip
    assert mesh.cell_data["von_mises"][0].max() > 1e5  # squeezed: Pa, not a stray zero
    # the nodes' contact forces add up to the load cell at that instant (history.csv)
    history = ccor.history
    row = int(np.argmin(np.abs(history["time_ms"] * 1e-3 - ball.times[frame])))
    load_cell = history["contact_force_lbf"][row] * LBF
    np.testing.assert_allclose(force[frame, :, 2].sum(), load_cell, rtol=1e-4)
    pressure = mesh.point_data["contact_pressure"]
    touching = np.linalg.norm(mesh.point_data["contact_force"], axis=1) > 0
    assert (pressure[touching] > 0).all() and (pressure[~touching] == 0).all()
    assert (force[0] == 0).all() and (force[-1] == 0).all()  # before and after the impact


def test_the_target_series_holds_the_cylinder_in_place(ccor: batball.Result) -> None:
    """The 2.63-in cylinder, axis along x, its top 0.002 in below the 6-in-around ball."""
    target = batball.read_fields(ccor.run_dir / "target.pvd", deformed=True)["target"]
    assert len(target) == len(batball.read_fields(ccor)["fields"])
    points = target.meshes[-1].points
    np.testing.assert_allclose(np.ptp(points[:, 0]), 6.0 * IN)
    np.testing.assert_allclose(np.ptp(points[:, 1]), 2.63 * IN)
    ball = batball.read_fields(ccor)["fields"].meshes[0].points
    np.testing.assert_allclose(points[:, 2].max(), ball[:, 2].min() - 0.002 * IN, atol=1e-9)
    np.testing.assert_allclose(target.point_field("displacement"), 0.0)


def test_the_deformed_points_are_reference_plus_displacement(ccor: batball.Result) -> None:
    reference = read_fields(ccor.run_dir / "fields.pvd")["fields"]
    deformed = read_fields(ccor.run_dir, deformed=True)["fields"]
    frame = len(reference) // 2
    np.testing.assert_allclose(
        deformed.meshes[frame].points,
        reference.meshes[frame].points + reference.meshes[frame].point_data["displacement"],
    )


def test_the_run_manifest_lists_the_frames(ccor: batball.Result) -> None:
    files = json.loads((ccor.run_dir / "summary.json").read_text())["files"]
    assert "target.pvd" in files and "fields/fields_00001.vtu" in files
    assert "target/target_00001.vtu" in files


def test_a_folder_without_series_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="no field series"):
        batball.read_fields(tmp_path)


def test_pyvista_opens_the_series(ccor: batball.Result) -> None:
    pyvista = pytest.importorskip("pyvista")
    reader = pyvista.get_reader(str(ccor.run_dir / "fields.pvd"))
    assert len(reader.time_values) == len(batball.read_fields(ccor)["fields"])
    reader.set_active_time_point(len(reader.time_values) // 2)
    assert "von_mises" in reader.read()[0].cell_data


def test_penetration_warning_only_with_a_soft_penalty(ccor: batball.Result,
                                                      tmp_path: Path) -> None:  # fmt: skip
    """The default penalty lets the ball sink about 1 % of its deflection into the cylinder;
    SFS = 0.01 about half of it, which the run flags."""
    s = ccor.summary
    assert 0 < s["max_penetration_in"] < 0.05 * s["max_deflection_in"]
    assert not any("sank" in w for w in s["warnings"])
    soft = batball.ccor("type1", divisions=4, sfs=0.01, runs_dir=tmp_path).summary
    assert soft["max_penetration_in"] > 0.05 * soft["max_deflection_in"]
    (warning,) = [w for w in soft["warnings"] if "sank" in w]
    assert "--sfs" in warning
    # a spring ball's largest compression is m v^2 / F_peak = F_peak / DS (both per the run)
    spring = s["peak_force_lbf"] / s["ds_lbf_per_in"]
    assert 0.5 * spring < s["max_deflection_in"] < 2.0 * spring


def test_run_warnings_flag_a_deep_penetration() -> None:
    assert run_warnings({"max_penetration_in": 0.004, "max_deflection_in": 0.5}) == []
    (warning,) = run_warnings({"max_penetration_in": 0.1, "max_deflection_in": 0.5})
    assert "20.0 %" in warning and "over 5 %" in warning
    assert run_warnings({"max_penetration_in": 0.1}) == []  # a test without a deflection


def test_a_coarse_bbs_writes_ball_and_bat_series(tmp_path: Path) -> None:
    # the one-point BT shells keep their plies' stresses; the MITC4 shells (the default) do not
    r = batball.bbs(divisions=4, circumferential=16, axial_size="0.5 in", runs_dir=tmp_path,
                    shell="bt")  # fmt: skip
    series = batball.read_fields(r)
    assert {"ball", "bat"} <= set(series)
    ball, bat = series["ball"], series["bat"]
    np.testing.assert_array_equal(ball.times, bat.times)
    assert 20 <= len(bat) <= 61
    assert "quad" in bat.meshes[0].cells_dict and "hexahedron" in ball.meshes[0].cells_dict
    ply = bat.cell_field("von_mises")
    assert np.isfinite(ply).all() and ply.max() > 1e6  # the plies are loaded: Pa
    assert np.isfinite(ball.cell_field("von_mises")).all()
    assert ball.cell_field("von_mises").max() > 1e5
    for name in ("displacement", "velocity", "contact_force"):
        assert np.isfinite(bat.point_field(name)).all()
    # the ball's nodal contact forces at its frames, along -y (the ball flies along -y)
    assert ball.point_field("contact_force")[:, :, 1].sum(axis=1).max() > 100.0 * LBF
