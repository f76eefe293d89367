"""Field files read back with meshio and ElementTree."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

from batball.mesh import Mesh, make_ball_mesh
from batball.results.fields import write_time_series, write_vtu


@pytest.fixture(scope="module")
def ball() -> Mesh:
    return make_ball_mesh(0.0485, divisions=2)


def test_vtu_reads_back_with_points_cells_and_fields(ball: Mesh, tmp_path: Path) -> None:
    u = 1e-3 * ball.points
    pressure = np.linspace(0.0, 1.0, ball.n_cells)
    write_vtu(tmp_path / "frame.vtu", ball, u, cell_data={"pressure": pressure})
    back = meshio.read(tmp_path / "frame.vtu")
    assert back.points.shape == (ball.n_points, 3)
    assert back.cells_dict["hexahedron"].shape == (ball.n_cells, 8)
    np.testing.assert_array_equal(back.cells_dict["hexahedron"], ball.cells)
    np.testing.assert_allclose(back.point_data["displacement"], u)
    np.testing.assert_allclose(back.cell_data["pressure"][0], pressure)


def test_pvd_series_lists_every_frame_with_its_time(ball: Mesh, tmp_path: Path) -> None:
    times = np.array([0.0, 1e-4, 2e-4])
    displacements = np.stack([t * 10.0 * ball.points for t in times])
    speed = np.ones((3, ball.n_points))
    write_time_series(
        tmp_path / "impact.pvd", ball, times, displacements, point_data={"speed": speed}
    )
    datasets = ET.parse(tmp_path / "impact.pvd").getroot().findall("./Collection/DataSet")
    assert [float(d.get("timestep", "nan")) for d in datasets] == times.tolist()
    for frame, dataset in enumerate(datasets):
        back = meshio.read(tmp_path / dataset.get("file", ""))
        assert back.points.shape[0] == ball.n_points
        assert back.cells_dict["hexahedron"].shape[0] == ball.n_cells
        np.testing.assert_allclose(back.point_data["displacement"], displacements[frame])


def test_xdmf_series_reads_back(ball: Mesh, tmp_path: Path) -> None:
    pytest.importorskip("h5py")
    times = np.array([0.0, 1e-4])
    displacements = np.zeros((2, ball.n_points, 3))
    write_time_series(tmp_path / "impact.xdmf", ball, times, displacements)
    assert (tmp_path / "impact.h5").is_file()  # beside the .xdmf, not in the cwd
    with meshio.xdmf.TimeSeriesReader(tmp_path / "impact.xdmf") as reader:
        points, cells = reader.read_points_cells()
        assert points.shape[0] == ball.n_points
        assert cells[0].data.shape == (ball.n_cells, 8)
        assert reader.num_steps == 2


def test_mismatched_frames_are_rejected(ball: Mesh, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="frames"):
        write_time_series(tmp_path / "x.pvd", ball, np.zeros(2), np.zeros((3, ball.n_points, 3)))
    with pytest.raises(ValueError, match="pvd or .xdmf"):
        write_time_series(tmp_path / "x.vtu", ball, np.zeros(1), np.zeros((1, ball.n_points, 3)))
