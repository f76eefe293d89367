"""Field output for ParaView: single frames as VTU, time series as PVD (+VTU) or XDMF (+HDF5).

Points are the reference configuration; the displacement is point data ``"displacement"`` (m), so
ParaView's "Warp By Vector" shows the deformed shape. All data are SI.

A ``.pvd`` series needs only meshio; an ``.xdmf`` series uses meshio's XDMF TimeSeriesWriter,
which needs the optional dependency h5py (imported where it is used).
"""

from __future__ import annotations

import importlib.util
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path

import meshio
import numpy as np

from batball.mesh.mesh import Mesh
from batball.results.store import atomic_path

HEX_CELL_TYPE = "hexahedron"


def _meshio_mesh(mesh: Mesh) -> meshio.Mesh:
    """The mesh as a meshio.Mesh with one hexahedron block."""
    return meshio.Mesh(mesh.points, [(HEX_CELL_TYPE, mesh.cells)])


def _checked_rows(
    data: Mapping[str, np.ndarray], kind: str, count_name: str, count: int
) -> dict[str, np.ndarray]:
    """Contiguous copies of ``data``, each checked to have ``count`` rows."""
    for name, values in data.items():
        if np.shape(values)[0] != count:
            raise ValueError(
                f"{kind} data {name!r} has {np.shape(values)[0]} rows, "
                f"expected {count_name} = {count}"
            )
    return {name: np.ascontiguousarray(values) for name, values in data.items()}


def _frame_point_data(
    mesh: Mesh, displacement: np.ndarray | None, point_data: Mapping[str, np.ndarray] | None
) -> dict[str, np.ndarray]:
    """Point data of one frame, each array of leading dimension n_points, checked."""
    data = dict(point_data or {})
    if displacement is not None:
        data["displacement"] = displacement
    return _checked_rows(data, "point", "n_points", mesh.n_points)


def _frame_cell_data(
    mesh: Mesh, cell_data: Mapping[str, np.ndarray] | None
) -> dict[str, np.ndarray]:
    """Cell data of one frame, each array of leading dimension n_cells, checked."""
    data = dict(cell_data or {})
    return _checked_rows(data, "cell", "n_cells", mesh.n_cells)


def write_vtu(
    path: Path,
    mesh: Mesh,
    displacement: np.ndarray | None = None,
    *,
    point_data: Mapping[str, np.ndarray] | None = None,
    cell_data: Mapping[str, np.ndarray] | None = None,
) -> None:
    """Write one frame as a binary VTK unstructured-grid file.

    Args:
        path: output ``.vtu`` file.
        mesh: the reference mesh (points in m).
        displacement: nodal displacement, shape (n_points, 3), m; stored as ``"displacement"``.
        point_data: further nodal fields, each shape (n_points, ...), SI.
        cell_data: cell fields, each shape (n_cells, ...), SI.
    """
    out = _meshio_mesh(mesh)
    out.point_data = _frame_point_data(mesh, displacement, point_data)
    out.cell_data = {name: [values] for name, values in _frame_cell_data(mesh, cell_data).items()}
    with atomic_path(Path(path)) as tmp:  # a reader never sees half a frame
        meshio.write(tmp, out, file_format="vtu", binary=True)


def _frame_slice(data: Mapping[str, np.ndarray] | None, frame: int) -> dict[str, np.ndarray] | None:
    """The given frame of every array in a (n_frames, ...) mapping."""
    return None if data is None else {name: values[frame] for name, values in data.items()}


def _check_series(
    times: np.ndarray,
    displacements: np.ndarray,
    point_data: Mapping[str, np.ndarray] | None,
    cell_data: Mapping[str, np.ndarray] | None,
) -> None:
    """Every series has one entry per time."""
    n_frames = np.shape(times)[0]
    series = {"displacements": displacements, **(point_data or {}), **(cell_data or {})}
    for name, values in series.items():
        if np.shape(values)[0] != n_frames:
            raise ValueError(f"{name!r} has {np.shape(values)[0]} frames, expected {n_frames}")


def _write_pvd(path: Path, times: np.ndarray, frame_files: list[Path]) -> None:
    """ParaView collection file listing the frame files (relative to it) with their times."""
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    collection = ET.SubElement(root, "Collection")
    for time, frame_file in zip(times, frame_files, strict=True):
        ET.SubElement(
            collection,
            "DataSet",
            timestep=repr(float(time)),
            group="",
            part="0",
            file=frame_file.relative_to(path.parent).as_posix(),
        )
    ET.indent(root)
    with atomic_path(path) as tmp:
        ET.ElementTree(root).write(tmp, encoding="utf-8", xml_declaration=True)


def _write_pvd_series(
    path: Path,
    mesh: Mesh,
    times: np.ndarray,
    displacements: np.ndarray,
    point_data: Mapping[str, np.ndarray] | None,
    cell_data: Mapping[str, np.ndarray] | None,
) -> None:
    """PVD collection plus one VTU per frame in the folder ``<stem>/`` beside it."""
    frame_dir = path.parent / path.stem
    frame_dir.mkdir(parents=True, exist_ok=True)
    frame_files = [frame_dir / f"{path.stem}_{i:05d}.vtu" for i in range(len(times))]
    for i, frame_file in enumerate(frame_files):  # one file per frame
        write_vtu(
            frame_file,
            mesh,
            displacements[i],
            point_data=_frame_slice(point_data, i),
            cell_data=_frame_slice(cell_data, i),
        )
    _write_pvd(path, times, frame_files)


class _SideBySideTimeSeriesWriter(meshio.xdmf.TimeSeriesWriter):
    """meshio's XDMF writer, with the .h5 file beside the .xdmf file instead of in the cwd."""

    def __enter__(self) -> _SideBySideTimeSeriesWriter:
        import h5py  # optional dependency, needed only for XDMF

        self.h5_filename = str(self.filename.with_suffix(".h5"))
        self.h5_file = h5py.File(self.h5_filename, "w")
        return self


def _write_xdmf_series(
    path: Path,
    mesh: Mesh,
    times: np.ndarray,
    displacements: np.ndarray,
    point_data: Mapping[str, np.ndarray] | None,
    cell_data: Mapping[str, np.ndarray] | None,
) -> None:
    """XDMF time series with its HDF5 heavy-data file beside it (needs h5py)."""
    if importlib.util.find_spec("h5py") is None:
        raise ImportError("writing .xdmf needs h5py; install it or write a .pvd series")
    with _SideBySideTimeSeriesWriter(path) as writer:
        writer.write_points_cells(mesh.points, [(HEX_CELL_TYPE, mesh.cells)])
        for i, time in enumerate(times):  # one block per frame
            frame_points = _frame_point_data(mesh, displacements[i], _frame_slice(point_data, i))
            frame_cells = _frame_cell_data(mesh, _frame_slice(cell_data, i))
            writer.write_data(
                float(time),
                point_data=frame_points,
                cell_data={name: [v] for name, v in frame_cells.items()},
            )


def write_time_series(
    path: Path,
    mesh: Mesh,
    times: np.ndarray,
    displacements: np.ndarray,
    *,
    point_data: Mapping[str, np.ndarray] | None = None,
    cell_data: Mapping[str, np.ndarray] | None = None,
) -> None:
    """Write a time series of fields on a fixed mesh for ParaView.

    The format follows the suffix of ``path``: ``.pvd`` writes a ParaView collection and one binary
    VTU per frame in the folder ``<stem>/`` beside it (meshio only); ``.xdmf`` writes an XDMF
    time series with ``<stem>.h5`` beside it (needs h5py).

    Args:
        path: output ``.pvd`` or ``.xdmf`` file.
        mesh: the reference mesh (points in m).
        times: frame times, shape (n_frames,), s.
        displacements: nodal displacements, shape (n_frames, n_points, 3), m.
        point_data: further nodal fields, each shape (n_frames, n_points, ...), SI.
        cell_data: cell fields, each shape (n_frames, n_cells, ...), SI.
    """
    path = Path(path)
    times = np.asarray(times, dtype=np.float64)
    _check_series(times, displacements, point_data, cell_data)
    if path.suffix == ".pvd":
        _write_pvd_series(path, mesh, times, displacements, point_data, cell_data)
    elif path.suffix == ".xdmf":
        _write_xdmf_series(path, mesh, times, displacements, point_data, cell_data)
    else:
        raise ValueError(f"time series path must end in .pvd or .xdmf, got {path.name!r}")
