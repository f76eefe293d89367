"""One-point (uniform-strain) hexahedron for explicit dynamics: LS-DYNA solid ELFORM 1.

Each step, for every element (``compute_hex8_forces``):

1. the velocity gradient L = sum_I v_I (x) B_I / V from v^(n-1/2) on the mid-step geometry
   x^(n-1/2) = x^n - dt/2 v^(n-1/2) (Flanagan & Belytschko 1981 uniform strain);
2. the stored deviatoric stresses rotated by the Hughes-Winget (Cayley) rotation of W dt, which is
   exactly orthogonal, so the update is objective (docs/physics.md section 6.8);
3. the material update (MAT_006, docs/physics.md section 1.3) and the pressure p = K ln(V0/V);
4. bulk viscosity q = rho l (Q1 l tr(D)^2 - Q2 c tr(D)) for tr(D) < 0, l = V^(1/3) (LS-DYNA's
   default Q1 = 1.5, Q2 = 0.06; docs/physics.md section 6.2);
5. nodal forces f_I = -sigma B_I on the geometry x^n, plus hourglass forces:
   LS-DYNA IHQ = 1 (viscous on the base vectors Gamma, a_h = QH rho V^(2/3) c / 4),
   IHQ = 2 (Flanagan-Belytschko viscous on the orthogonalised gamma, same coefficient) or
   IHQ = 4 (Flanagan-Belytschko stiffness, incremental hourglass "stress" with
   kappa = QM (K + 4/3 G0) sum(B.B) / (3 V); the exact LS-DYNA constant is not public, this is
   the Flanagan-Belytschko form with a coefficient of the same order);
6. the element's stable step L_e / (Q + sqrt(Q^2 + c^2)) with L_e = V / A_max and
   Q = Q2 c + Q1 L_e |tr(D)| under compression (LS-DYNA Theory Manual, time step control).

Energies are integrated per element with the midpoint rule: internal (stress power, including the
viscoelastic dissipation), hourglass and bulk-viscosity work.

The arithmetic is written on the element's corner-sign modes (``hex8_geometry``), which gives B,
L, the hourglass vectors and the nodal forces with about half the operations of the node-wise
form, and runs SIMD across blocks of elements (``hex8_block``); ``tests/unit/elements`` checks it
against a plain per-element implementation of the steps above.
"""

from __future__ import annotations

from collections.abc import Callable

import numba as nb
import numpy as np

from batball.elements.hex8_block import (
    BLOCK,
    R_MAT,
    element_block_fb_stiffness,
    element_block_fb_stiffness_2,
    element_block_fb_stiffness_3,
    element_block_fb_viscous,
    element_block_fb_viscous_2,
    element_block_fb_viscous_3,
    element_block_viscous,
    element_block_viscous_2,
    element_block_viscous_3,
    gather_material,
    gather_nodes,
    history_rows,
    history_terms,
    material_factors,
    scatter_forces,
    scatter_outputs,
)
from batball.numerics import FASTMATH

#: LS-DYNA hourglass types (IHQ) the solid element supports.
HOURGLASS_TYPES = {
    1: "LS-DYNA standard viscous",
    2: "Flanagan-Belytschko viscous",
    3: "Flanagan-Belytschko viscous",
    4: "Flanagan-Belytschko stiffness",
    5: "Flanagan-Belytschko stiffness",
}

#: Columns of the per-slot energy increments written by the kernel.
ENERGY_INTERNAL, ENERGY_HOURGLASS, ENERGY_BULK_VISCOSITY = 0, 1, 2


def kernel_ids(ids: np.ndarray) -> np.ndarray:
    """``ids`` (node ids or material rows) as the element kernels take them: contiguous int32.

    32-bit ids halve the index traffic of a cycle, which streams all of them, and one integer
    type means one compiled kernel per form (about 30 s each) whichever caller it serves. The
    same array when it already is one, else a copy: callers that step keep theirs converted.
    """
    return np.ascontiguousarray(ids, dtype=np.int32)


@nb.njit
def slot_cells(slot: int, n_slots: int, n_cells: int) -> tuple[int, int]:
    """The cells [first, end) of one slot of the element kernel: the blocks of BLOCK cells split
    into ``n_slots`` equal contiguous runs (so a slot's cells are whole blocks of the history)."""
    n_blocks = (n_cells + BLOCK - 1) // BLOCK
    first = slot * n_blocks // n_slots * BLOCK
    end = min((slot + 1) * n_blocks // n_slots * BLOCK, n_cells)
    return first, end


@nb.njit(inline="always")
def _advance_slot(element_block, slot, factors, mesh, material, history, outputs, controls):
    """The cells of one slot, block by block: their forces are added into the slot's nodal
    array; returns their (internal, hourglass, bulk) work [J]."""
    dt, hg_coefficient, q1, q2 = controls
    points, velocities, cells = mesh
    nodal_forces, cell_volume, cell_dt = outputs[0], outputs[1], outputs[2]
    first, end = slot_cells(slot, nodal_forces.shape[0], cells.shape[0])
    # the block scratch, in the precision of the history: its rows end with the material factors
    w = np.zeros((R_MAT + factors.shape[1]) * BLOCK, dtype=history.dtype)
    # flat views of the nodal arrays for the gather and the scatter
    xs, vs, slot_forces = points.reshape(-1), velocities.reshape(-1), nodal_forces[slot].reshape(-1)
    internal = 0.0
    hourglass = 0.0
    bulk = 0.0
    held = -1  # the material whose factors fill w's rows (none yet)
    for start in range(first, end, BLOCK):
        n = min(BLOCK, end - start)
        block = history[start // BLOCK]
        gather_nodes(w, start, n, xs, vs, cells)
        held = gather_material(w, start, n, material[0], factors, held)
        a, b, c = element_block(w, block, n, dt, q1, q2, hg_coefficient)
        scatter_outputs(w, start, n, cell_volume, cell_dt)
        scatter_forces(w, start, n, cells, slot_forces)
        internal += a
        hourglass += b
        bulk += c
    return internal, hourglass, bulk


@nb.njit(inline="always")
def _advance_all(element_block, mesh, material, history, outputs, controls):
    """All cells, in the equal contiguous slots of ``nodal_forces``, one slot per parallel
    iteration (so each slot's nodal array has one writer and the sums do not depend on how the
    iterations are scheduled)."""
    energy_increments = outputs[3]
    factors = material_factors(material[1], material[2], controls[0])
    for slot in nb.prange(energy_increments.shape[0]):
        internal, hourglass, bulk = _advance_slot(
            element_block, slot, factors, mesh, material, history, outputs, controls
        )
        energy_increments[slot, ENERGY_INTERNAL] = internal
        energy_increments[slot, ENERGY_HOURGLASS] = hourglass
        energy_increments[slot, ENERGY_BULK_VISCOSITY] = bulk


# One compiled kernel per hourglass form, so that a run compiles (and caches) only its own.
# Numba's cache is keyed on this file alone: after editing the modules it inlines, change
# INLINED below, so that a cache compiled from the old code is not loaded (a checkout leaves
# this file's time stamp as it was unless its text changes).
INLINED = "hex8_block: blocks of 64 cells on every host"


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_viscous(mesh, material, history, outputs, controls):
    """IHQ 1."""
    _advance_all(element_block_viscous, mesh, material, history, outputs, controls)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_fb_viscous(mesh, material, history, outputs, controls):
    """IHQ 2 and 3."""
    _advance_all(element_block_fb_viscous, mesh, material, history, outputs, controls)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_fb_stiffness(mesh, material, history, outputs, controls):
    """IHQ 4 and 5."""
    _advance_all(element_block_fb_stiffness, mesh, material, history, outputs, controls)


# The same for materials of 2 and 3 Prony terms (batball.materials.prony).


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_viscous_2(mesh, material, history, outputs, controls):
    """IHQ 1, two Prony terms."""
    _advance_all(element_block_viscous_2, mesh, material, history, outputs, controls)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_fb_viscous_2(mesh, material, history, outputs, controls):
    """IHQ 2 and 3, two Prony terms."""
    _advance_all(element_block_fb_viscous_2, mesh, material, history, outputs, controls)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_fb_stiffness_2(mesh, material, history, outputs, controls):
    """IHQ 4 and 5, two Prony terms."""
    _advance_all(element_block_fb_stiffness_2, mesh, material, history, outputs, controls)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_viscous_3(mesh, material, history, outputs, controls):
    """IHQ 1, three Prony terms."""
    _advance_all(element_block_viscous_3, mesh, material, history, outputs, controls)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_fb_viscous_3(mesh, material, history, outputs, controls):
    """IHQ 2 and 3, three Prony terms."""
    _advance_all(element_block_fb_viscous_3, mesh, material, history, outputs, controls)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def _forces_fb_stiffness_3(mesh, material, history, outputs, controls):
    """IHQ 4 and 5, three Prony terms."""
    _advance_all(element_block_fb_stiffness_3, mesh, material, history, outputs, controls)


#: Kernels keyed by (IHQ, Prony terms).
_KERNELS = {
    (1, 1): _forces_viscous,
    (2, 1): _forces_fb_viscous,
    (3, 1): _forces_fb_viscous,
    (4, 1): _forces_fb_stiffness,
    (5, 1): _forces_fb_stiffness,
    (1, 2): _forces_viscous_2,
    (2, 2): _forces_fb_viscous_2,
    (3, 2): _forces_fb_viscous_2,
    (4, 2): _forces_fb_stiffness_2,
    (5, 2): _forces_fb_stiffness_2,
    (1, 3): _forces_viscous_3,
    (2, 3): _forces_fb_viscous_3,
    (3, 3): _forces_fb_viscous_3,
    (4, 3): _forces_fb_stiffness_3,
    (5, 3): _forces_fb_stiffness_3,
}


def compute_hex8_forces(
    points: np.ndarray,
    velocities: np.ndarray,
    cells: np.ndarray,
    dt: float,
    cell_material: np.ndarray,
    material_constants: np.ndarray,
    densities: np.ndarray,
    history: np.ndarray,
    hg_type: int,
    hg_coefficient: float,
    q1: float,
    q2: float,
    nodal_forces: np.ndarray,
    cell_volume: np.ndarray,
    cell_dt: np.ndarray,
    energy_increments: np.ndarray,
) -> None:
    """Element forces, stress update and stable steps of all hexes for one explicit cycle.

    Args:
        points: (n_points, 3) coordinates x^n [m]; velocities: (n_points, 3) v^(n-1/2) [m/s].
        cells: (n_cells, 8) node ids (:func:`kernel_ids`); dt: the step dt^(n-1/2) [s] that
            led to x^n.
        cell_material: (n_cells,) (:func:`kernel_ids`) row of ``material_constants``
            (n_materials, 2 N + 2: K, G0, G_inf [Pa], beta_1 [1/s], then (G_i [Pa],
            beta_i [1/s]) for Prony terms i = 2..N; N = 1 is MAT_006's K, G0, G_inf, beta) and
            ``densities`` (n_materials,) [kg/m^3].
        history: (n_blocks, rows * BLOCK) in/out, the element history in the kernel's block
            layout (:func:`batball.elements.hex8_block.pack_history` builds it from element-wise
            arrays and ``unpack_history`` reads it): initial volume [m^3], long-time deviatoric
            stress s_inf and the N Prony terms' relaxing stresses h [Pa], pressure [Pa] and the
            stiffness-form hourglass forces [N].
        hg_type, hg_coefficient: LS-DYNA IHQ (a key of ``HOURGLASS_TYPES``) and QH/QM.
        q1, q2: bulk viscosity (0, 0 = off).
        nodal_forces: (n_slots, n_points, 3) in/out: the element forces [N] are ADDED here, the
            cells split into n_slots contiguous slots of whole blocks (:func:`slot_cells`), slot
            k adding into ``nodal_forces[k]`` (the caller sums the slots and zeroes them; see
            :func:`batball.solvers.explicit_kernels.assemble_and_update`). One slot per thread
            makes the assembly parallel without atomics and without per-element force arrays.
        cell_volume: (n_cells,) out [m^3];
        cell_dt: (n_cells,) out, stable steps [s] (0 where the volume is not positive; such an
            element keeps its pressure and hourglass forces and gets no forces or work).
        energy_increments: (n_slots, 3) out: internal, hourglass, bulk-viscosity work [J] of
            each slot.
    """
    kernel, arguments, controls = hex8_kernel_call(
        points, velocities, cells, cell_material, material_constants, densities, history,
        hg_type, hg_coefficient, q1, q2, nodal_forces, cell_volume, cell_dt, energy_increments,
    )  # fmt: skip
    kernel(*arguments, (float(dt), *controls))


def hex8_kernel_call(
    points: np.ndarray,
    velocities: np.ndarray,
    cells: np.ndarray,
    cell_material: np.ndarray,
    material_constants: np.ndarray,
    densities: np.ndarray,
    history: np.ndarray,
    hg_type: int,
    hg_coefficient: float,
    q1: float,
    q2: float,
    nodal_forces: np.ndarray,
    cell_volume: np.ndarray,
    cell_dt: np.ndarray,
    energy_increments: np.ndarray,
) -> tuple[Callable, tuple, tuple]:
    """The compiled kernel :func:`compute_hex8_forces` calls on these arrays (its arguments but
    the step), checked: (kernel, arguments, controls), called as ``kernel(*arguments, (dt,
    *controls))`` with the step dt [s]; a compiled loop over cycles makes the same call."""
    n_terms = history_terms(history)
    if material_constants.shape[1] != 2 * n_terms + 2:
        raise ValueError(
            f"the history holds {n_terms} Prony terms and material_constants has "
            f"{material_constants.shape[1]} columns; expected 2 N + 2 for N terms"
        )
    n_blocks = -(-len(cells) // BLOCK)
    if history.shape != (n_blocks, history_rows(n_terms) * BLOCK):
        raise ValueError(
            f"history has shape {history.shape}; {len(cells)} cells need {n_blocks} blocks"
        )
    if nodal_forces.shape[1:] != points.shape or nodal_forces.shape[0] != len(energy_increments):
        raise ValueError(
            f"nodal_forces has shape {nodal_forces.shape}; expected (n_slots, n_points, 3) with "
            f"n_slots = {len(energy_increments)}, the rows of energy_increments"
        )
    arguments = (
        (points, velocities, kernel_ids(cells)),
        (kernel_ids(cell_material), material_constants, densities),
        history,
        (nodal_forces, cell_volume, cell_dt, energy_increments),
    )
    return _KERNELS[hg_type, n_terms], arguments, (float(hg_coefficient), float(q1), float(q2))
