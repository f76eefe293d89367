"""Field frames of the explicit runs: what ParaView shows of a ball (and a bat) at a few instants.

A run keeps a frame about every ``end_time / frame_count``; only then are the fields below made
from the state the cycle already holds (nothing is computed on the other steps). Every array of a
frame is float32 (output only: no measured number is taken from a frame). The ball's fields:

point data (n_points, ...):
    ``displacement`` [m] x - X; ``velocity`` [m/s] v^(n+1/2); ``contact_force`` [N], the
    penalty force of the targets (or the bat) on each node, zero off contact;
    ``contact_pressure`` [Pa], its size over the node's share of the ball's undeformed surface
    (a quarter of each boundary face around it), zero inside the ball.
cell data (n_cells, ...):
    ``stress`` [Pa], the element's Cauchy stress (xx, yy, zz, xy, yz, zx: ParaView's symmetric
    tensor order): MAT_006/Prony s_inf + sum h_i - p I with p = K ln(V0/V), the stress the hex
    kernel keeps between cycles (the bulk viscosity q and the hourglass stresses, which the
    kernel adds only inside a cycle, left out); a foam's total stress;
    ``von_mises`` [Pa] sqrt(3/2 s:s) of its deviator s; ``pressure`` [Pa] -tr(sigma)/3 (positive
    in compression); ``volumetric_strain`` ln(V/V0) (negative in compression).

The stress and volume are those of x^n, the positions the cycle's element forces were computed
on; the displacement and velocity are the cycle's update, half a step later.

A bat's (shell mid-surface quads) fields: point data ``displacement`` [m] (from the mesh as
built: the insert's pre-stress fit is part of it), ``velocity`` [m/s], ``angular_velocity``
[rad/s] and ``contact_force`` [N] (the ball's and the insert's); cell data ``von_mises`` [Pa],
the largest plane-stress von Mises sqrt(s_xx^2 - s_xx s_yy + s_yy^2 + 3 s_xy^2) over the plies
of the layered Belytschko-Tsay section (each ply's stress at its mid-height, so the outer and
inner plies' bending is in it), absent for the co-rotational MITC4 shells, which keep no stress.
"""

from __future__ import annotations

from collections.abc import Callable

import numba as nb
import numpy as np

from batball.elements.hex8_block import (
    BLOCK,
    H_H,
    H_P,
    H_PRONY,
    H_S,
    history_terms,
)
from batball.elements.shell_bt import BLOCK as SHELL_BLOCK
from batball.elements.shell_bt import S_LAYERS, ShellForceState
from batball.materials.foam_update import H_STRESS
from batball.mesh.hexa import boundary_faces, face_area_vectors

#: A frame: field name -> float32 array, point data (n_points, ...) or cell data (n_cells, ...).
Frame = dict[str, np.ndarray]

#: The fields of a ball frame that are cell data (the rest are point data).
BALL_CELL_FIELDS = ("stress", "von_mises", "pressure", "volumetric_strain")


def stress_invariants(stress: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The von Mises stress sqrt(3/2 s:s) and the pressure -tr(sigma)/3 of Cauchy stresses
    ``stress`` (n, 6) in Voigt order xx, yy, zz, xy, yz, zx (tensor shear components) [Pa];
    each (n,) [Pa]. One compiled pass without fast-math: each operation rounds as NumPy's
    whole-array arithmetic would, in the order written (xx + yy, then + zz)."""
    stress = np.ascontiguousarray(stress, dtype=np.float64)
    von_mises, pressure = np.empty(stress.shape[0]), np.empty(stress.shape[0])
    _stress_invariants(stress, von_mises, pressure)
    return von_mises, pressure


@nb.njit(cache=True)
def _stress_invariants(stress: np.ndarray, von_mises: np.ndarray, pressure: np.ndarray) -> None:
    """:func:`stress_invariants` into ``von_mises`` and ``pressure``."""
    for c in range(stress.shape[0]):
        xx, yy, zz = stress[c, 0], stress[c, 1], stress[c, 2]
        xy, yz, zx = stress[c, 3], stress[c, 4], stress[c, 5]
        p = -((xx + yy + zz) / 3.0)
        a, b, d = xx + p, yy + p, zz + p
        normal = a * a + b * b + d * d
        squared = normal + 2.0 * (xy * xy + yz * yz + zx * zx)
        von_mises[c] = np.sqrt(1.5 * squared)
        pressure[c] = p


def hex_cell_stress(history: np.ndarray, n_cells: int) -> np.ndarray:
    """The Cauchy stress (n_cells, 6) [Pa] of the viscoelastic hex kernel's block ``history``
    (:func:`batball.elements.hex8_block.pack_history`'s layout): s_inf + the Prony terms' h
    - p I (module docs), in double. Reads only the stress rows, in one compiled pass."""
    stress = np.empty((n_cells, 6))
    _hex_cell_stress(history, history_terms(history), stress)
    return stress


@nb.njit(cache=True)
def _hex_cell_stress(history: np.ndarray, n_terms: int, stress: np.ndarray) -> None:
    """:func:`hex_cell_stress` into ``stress``: row r of cell e of block b at
    ``history[b, r * BLOCK + e]``; s_inf + h, then each further term's h, then - p on the
    normal components, each in double."""
    for c in range(stress.shape[0]):
        b, e = c // BLOCK, c % BLOCK
        p = np.float64(history[b, H_P * BLOCK + e])
        for k in range(6):
            s_inf, h = history[b, (H_S + k) * BLOCK + e], history[b, (H_H + k) * BLOCK + e]
            v = np.float64(s_inf) + np.float64(h)
            for t in range(n_terms - 1):
                v += np.float64(history[b, (H_PRONY + 6 * t + k) * BLOCK + e])
            stress[c, k] = v - p if k < 3 else v


def foam_cell_stress(foam_history: np.ndarray) -> np.ndarray:
    """The total Cauchy stress (n_cells, 6) [Pa] the foam kernel keeps in ``foam_history``."""
    return np.array(foam_history[:, H_STRESS : H_STRESS + 6], dtype=np.float64)


def surface_node_areas(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Each node's share of the hex mesh's boundary surface, a quarter of the area of each
    boundary face around it, (n_points,) [m^2] (0 inside)."""
    faces, _ = boundary_faces(cells)
    area = np.linalg.norm(face_area_vectors(points, faces), axis=1)
    nodal = np.zeros(points.shape[0])
    np.add.at(nodal, faces.ravel(), np.repeat(0.25 * area, 4))
    return nodal


def ball_frame(
    displacement: np.ndarray,
    velocity: np.ndarray,
    contact_force: np.ndarray,
    surface_area: np.ndarray,
    stress: np.ndarray,
    volume: np.ndarray,
    volume0: np.ndarray,
) -> Frame:
    """One ball frame (module docs) from the state's arrays: ``displacement``, ``velocity`` and
    ``contact_force`` (n_points, 3) [m, m/s, N], :func:`surface_node_areas` [m^2], the cells'
    ``stress`` (n_cells, 6) [Pa] and current and initial ``volume``, ``volume0`` (n_cells,)
    [m^3]."""
    von_mises, pressure = stress_invariants(stress)
    fx, fy, fz = np.array(contact_force.T)  # as contiguous rows (see stress_invariants)
    force = np.sqrt(fx * fx + fy * fy + fz * fz)
    on_surface = surface_area > 0.0
    contact_pressure = np.zeros_like(force)
    contact_pressure[on_surface] = force[on_surface] / surface_area[on_surface]
    ratio = np.where(volume > 0.0, volume / volume0, 1.0)
    fields = {
        "displacement": displacement,
        "velocity": velocity,
        "contact_force": contact_force,
        "contact_pressure": contact_pressure,
        "stress": stress,
        "von_mises": von_mises,
        "pressure": pressure,
        "volumetric_strain": np.log(ratio),
    }
    return {name: np.asarray(values, dtype=np.float32) for name, values in fields.items()}


def ply_von_mises(state: ShellForceState, layer_thickness: np.ndarray) -> np.ndarray:
    """The largest plane-stress von Mises stress over the plies of each cell, (n_cells,) [Pa],
    from the layered shells' ``state`` (each ply's xx, yy, xy stress, read in its block layout)
    and each cell's ply thicknesses ``layer_thickness`` (n_cells, n_layers) [m] (0: a padding
    layer, left out)."""
    out = np.zeros(layer_thickness.shape[0])
    _ply_von_mises(state.history, state.block_start, state.n_layers, layer_thickness, out)
    return out


@nb.njit(cache=True)
def _ply_von_mises(history: np.ndarray, block_start: np.ndarray, n_layers: int,
                   thickness: np.ndarray, out: np.ndarray) -> None:  # fmt: skip
    """:func:`ply_von_mises` on the block history: row r of cell e of block b at
    ``history[b, r * BLOCK + e]`` (:class:`batball.elements.shell_bt.ShellForceState`)."""
    for b in range(block_start.shape[0] - 1):
        for e in range(block_start[b + 1] - block_start[b]):
            cell = block_start[b] + e
            largest = 0.0
            for k in range(n_layers):
                if thickness[cell, k] <= 0.0:
                    continue
                at = (S_LAYERS + 3 * k) * SHELL_BLOCK + e
                sxx = history[b, at]
                syy = history[b, at + SHELL_BLOCK]
                sxy = history[b, at + 2 * SHELL_BLOCK]
                largest = max(largest, sxx * (sxx - syy) + syy * syy + 3.0 * sxy * sxy)
            out[cell] = np.sqrt(largest)


def bat_frame(
    displacement: np.ndarray,
    velocity: np.ndarray,
    contact_force: np.ndarray,
    von_mises: np.ndarray | None,
) -> Frame:
    """One bat frame (module docs): nodal ``displacement`` (n_points, 3) [m], ``velocity``
    (n_points, 6) [m/s, rad/s], ``contact_force`` (n_points, 3) [N] and the cells' ply von
    Mises stress (n_cells,) [Pa] (None: not kept)."""
    fields = {
        "displacement": displacement,
        "velocity": velocity[:, :3],
        "angular_velocity": velocity[:, 3:6],
        "contact_force": contact_force,
    }
    if von_mises is not None:
        fields["von_mises"] = von_mises
    return {name: np.asarray(values, dtype=np.float32) for name, values in fields.items()}


class FrameRecorder:
    """Frames at a fixed interval of simulated time: the first at t = 0, then one each time
    ``t`` passes the next multiple of ``interval`` [s] (:meth:`due` is the cheap test a time
    loop makes every step)."""

    def __init__(self, interval: float) -> None:
        self.interval = interval
        self.next_time = 0.0
        self.times: list[float] = []
        self.frames: list[Frame] = []

    def due(self, t: float) -> bool:
        """Whether a frame is due at time ``t`` [s]."""
        return t >= self.next_time

    def record(self, t: float, frame: Callable[[], Frame]) -> bool:
        """Keep ``frame()`` at ``t`` [s] if one is due; returns whether it was."""
        if t < self.next_time:
            return False
        self.add(t, frame())
        self.next_time += self.interval
        return True

    def add(self, t: float, frame: Frame) -> None:
        """Keep ``frame`` at ``t`` [s] (the last frame of a run, whenever it ends); it replaces
        a frame already kept at ``t``."""
        if self.times and t <= self.times[-1]:
            self.frames[-1] = frame
            return
        self.times.append(float(t))
        self.frames.append(frame)

    def stacked(self) -> tuple[np.ndarray, Frame]:
        """The frame times (n_frames,) [s] and each field stacked, (n_frames, ...)."""
        names = self.frames[0].keys() if self.frames else ()
        return np.array(self.times), {n: np.stack([f[n] for f in self.frames]) for n in names}
