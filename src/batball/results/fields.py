"""Field output for ParaView: single frames as VTU, time series as PVD (+VTU) or XDMF (+HDF5),
and the reader of a run's series.

Points are the reference configuration; the displacement is point data ``"displacement"`` (m), so
ParaView's "Warp By Vector" shows the deformed shape. All data are SI. A mesh is hexahedra (the
ball), quads (the bat's shells, a rigid target's surface) or triangles.

A ``.pvd`` series needs only meshio; an ``.xdmf`` series uses meshio's XDMF TimeSeriesWriter,
which needs the optional dependency h5py (imported where it is used). meshio reads no ``.pvd``:
:func:`read_fields` reads the collection's XML and each frame's VTU with meshio.
"""

from __future__ import annotations

import importlib.util
import os
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import meshio
import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.mesh.mesh import CellMesh
from batball.mesh.shell import ShellMesh
from batball.results.store import atomic_path

HEX_CELL_TYPE = "hexahedron"

#: meshio's cell type of a mesh by its nodes per cell.
CELL_TYPES = {8: HEX_CELL_TYPE, 4: "quad", 3: "triangle"}


def cell_type(mesh: CellMesh) -> str:
    """meshio's name of the mesh's cells (``"hexahedron"``, ``"quad"``, ``"triangle"``)."""
    per_cell = mesh.cells.shape[1]
    if per_cell not in CELL_TYPES:
        raise ValueError(f"cells of {per_cell} nodes have no field output; expected 8, 4 or 3")
    return CELL_TYPES[per_cell]


def _meshio_mesh(mesh: CellMesh) -> meshio.Mesh:
    """The mesh as a meshio.Mesh with one block of its cells."""
    return meshio.Mesh(mesh.points, [(cell_type(mesh), mesh.cells)])


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
    mesh: CellMesh, displacement: np.ndarray | None, point_data: Mapping[str, np.ndarray] | None
) -> dict[str, np.ndarray]:
    """Point data of one frame, each array of leading dimension n_points, checked."""
    data = dict(point_data or {})
    if displacement is not None:
        data["displacement"] = displacement
    return _checked_rows(data, "point", "n_points", mesh.n_points)


def _frame_cell_data(
    mesh: CellMesh, cell_data: Mapping[str, np.ndarray] | None
) -> dict[str, np.ndarray]:
    """Cell data of one frame, each array of leading dimension n_cells, checked."""
    data = dict(cell_data or {})
    return _checked_rows(data, "cell", "n_cells", mesh.n_cells)


def write_vtu(
    path: Path,
    mesh: CellMesh,
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
    mesh: CellMesh,
    times: np.ndarray,
    displacements: np.ndarray,
    point_data: Mapping[str, np.ndarray] | None,
    cell_data: Mapping[str, np.ndarray] | None,
) -> None:
    """PVD collection plus one VTU per frame in the folder ``<stem>/`` beside it."""
    frame_dir = path.parent / path.stem
    frame_dir.mkdir(parents=True, exist_ok=True)
    frame_files = [frame_dir / f"{path.stem}_{i:05d}.vtu" for i in range(len(times))]

    def write_frame(i: int) -> None:
        write_vtu(
            frame_files[i],
            mesh,
            displacements[i],
            point_data=_frame_slice(point_data, i),
            cell_data=_frame_slice(cell_data, i),
        )

    # one file per frame, over threads: most of a frame's time is zlib's compression, which
    # releases the GIL
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        list(pool.map(write_frame, range(len(frame_files))))
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
    mesh: CellMesh,
    times: np.ndarray,
    displacements: np.ndarray,
    point_data: Mapping[str, np.ndarray] | None,
    cell_data: Mapping[str, np.ndarray] | None,
) -> None:
    """XDMF time series with its HDF5 heavy-data file beside it (needs h5py)."""
    if importlib.util.find_spec("h5py") is None:
        raise ImportError("writing .xdmf needs h5py; install it or write a .pvd series")
    with _SideBySideTimeSeriesWriter(path) as writer:
        writer.write_points_cells(mesh.points, [(cell_type(mesh), mesh.cells)])
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
    mesh: CellMesh,
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


def target_surfaces(
    targets: Sequence[RigidPlane | RigidCylinder], *, center: np.ndarray, size: float
) -> tuple[ShellMesh, np.ndarray, np.ndarray]:
    """The rigid targets as one quad surface at t = 0 (each target's ``surface``): the mesh, each
    cell's target index (n_cells,) and each point's target velocity (n_points, 3) [m/s].

    Args:
        targets: the fixtures, in the run's contact order.
        center: (3,) where a flat wall's square is centred (its foot on the wall) [m].
        size: a flat wall's side [m].
    """
    pieces = [target.surface(center=center, size=size) for target in targets]
    sizes = [len(points) for points, _ in pieces]
    offsets = np.cumsum([0, *sizes])
    points = np.concatenate([points for points, _ in pieces])
    cells = np.concatenate([quads + offsets[k] for k, (_, quads) in enumerate(pieces)])
    index = np.repeat(np.arange(len(pieces)), [len(quads) for _, quads in pieces])
    speeds = [np.zeros(3) if t.velocity is None else np.asarray(t.velocity, float) for t in targets]
    velocity = np.repeat(np.array(speeds).reshape(-1, 3), sizes, axis=0)
    return ShellMesh(points, cells), index, velocity


def write_target_series(
    path: Path,
    targets: Sequence[RigidPlane | RigidCylinder],
    times: np.ndarray,
    *,
    center: np.ndarray,
    size: float,
) -> None:
    """The rigid targets of a run as their own time series beside the body's (ParaView shows
    them together): quads in their place at t = 0, each frame's ``"displacement"`` their
    prescribed motion v t [m], ``"velocity"`` [m/s] point data, ``"target"`` (the contact's
    index) cell data. Arguments as :func:`target_surfaces`; ``times`` (n_frames,) [s]."""
    mesh, index, velocity = target_surfaces(targets, center=center, size=size)
    times = np.asarray(times, dtype=np.float64)
    n_frames = len(times)
    frames = np.ones((n_frames, 1, 1), dtype=np.float32)
    write_time_series(
        path,
        mesh,
        times,
        (times[:, None, None] * velocity[None]).astype(np.float32),
        point_data={"velocity": frames * velocity.astype(np.float32)},
        cell_data={"target": np.tile(index.astype(np.int32), (n_frames, 1))},
    )


@dataclass(frozen=True)
class FieldSeries:
    """A time series read back: the frame times and one meshio Mesh per frame.

    Attributes:
        name: the series' name, its ``.pvd`` file's stem (``"fields"``, ``"target"``,
            ``"bat"``).
        times: (n_frames,) [s].
        meshes: the frames; each holds ``points`` (n_points, 3) [m], its cells and its
            ``point_data`` and ``cell_data`` (meshio's: one array per cell block) in SI.
    """

    name: str
    times: np.ndarray
    meshes: list[meshio.Mesh]

    def __len__(self) -> int:
        return len(self.meshes)

    def point_field(self, name: str) -> np.ndarray:
        """Point data ``name`` of every frame, (n_frames, n_points, ...)."""
        return np.stack([mesh.point_data[name] for mesh in self.meshes])

    def cell_field(self, name: str) -> np.ndarray:
        """Cell data ``name`` of every frame (the cell blocks one after the other),
        (n_frames, n_cells, ...)."""
        return np.stack([np.concatenate(mesh.cell_data[name]) for mesh in self.meshes])


def read_pvd(path: Path, *, deformed: bool = False) -> FieldSeries:
    """A ParaView collection ``path`` (``.pvd``) and its frames, read with meshio.

    Args:
        path: the ``.pvd`` file; its frames' paths are relative to it.
        deformed: give each frame's points in the deformed place, reference plus its
            ``"displacement"`` point data (where it has one), instead of the reference.
    """
    path = Path(path)
    datasets = ET.parse(path).getroot().findall("./Collection/DataSet")
    times = np.array([float(d.get("timestep", "nan")) for d in datasets])
    meshes = [meshio.read(path.parent / d.get("file", "")) for d in datasets]
    if deformed:
        for mesh in meshes:
            if "displacement" in mesh.point_data:
                mesh.points = mesh.points + mesh.point_data["displacement"]
    return FieldSeries(path.stem, times, meshes)


def read_fields(source: Path, *, deformed: bool = False) -> dict[str, FieldSeries]:
    """The field time series of a run folder (every ``.pvd`` in it), or of one ``.pvd`` file,
    by name (the file's stem: ``"fields"``, ``"target"``, ``"ball"``, ``"bat"``).

    Args:
        source: a run folder or a ``.pvd`` file.
        deformed: points in the deformed place (:func:`read_pvd`).

    Raises:
        FileNotFoundError: no such file or folder, or a folder without a ``.pvd``.
    """
    source = Path(source)
    if source.is_file():
        return {source.stem: read_pvd(source, deformed=deformed)}
    collections = sorted(source.glob("*.pvd")) if source.is_dir() else []
    if not collections:
        raise FileNotFoundError(f"no field series (.pvd) in {source}")
    return {pvd.stem: read_pvd(pvd, deformed=deformed) for pvd in collections}
