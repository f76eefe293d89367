"""One-point hex element forces for the foam laws (MAT_057, MAT_083): the foam's own kernel.

It produces exactly what :func:`batball.elements.hex8.compute_hex8_forces` produces (nodal forces
added into per-slot nodal arrays, volumes, stable steps, per-slot energy increments) and shares
its geometry, hourglass control, bulk viscosity, nodal forces and stable step (``hex8_geometry``,
``hex8_kinematics``, ``hex8_response``). What differs is the stress: a foam is a total
(hyperelastic-like) law of the deformation gradient, not a rate law, so each step

1. F at the element centre from the current and reference nodal coordinates,
   F = sum_a x_a (x) dV0/dX_a / V0 (the mean-gradient form of the one-point hex, exact for a
   homogeneous deformation; Flanagan & Belytschko 1981), which on the corner-sign modes is
   F = sum_k X_k (x) G0_k / V0, the same contraction as the velocity gradient;
2. the foam stress from F (as :func:`batball.materials.foam_update.foam_stress` forms it);
   objective by construction, since b = F F^T rotates with the body. The eigen-decompositions
   of b, a third of a cell's time when done one at a time (a chain of dependent divisions and
   square roots), run for a block of cells at once, SIMD across the cells, after a first pass
   over the block's cells (kinematics, b; SIMD); so does the law, its branches as selects and
   its curve look-ups one curve point at a time across the block; steps 3-5 are again one pass
   over the block (scalar code, :func:`foam_response`): the same bits as one cell at a time;
3. MAT_057's rate stress (ED, BETA1), a Maxwell stress E_d int exp(-beta_1 (t - s)) D ds
   rotated by the step's Hughes-Winget rotation like MAT_006's deviator;
4. the DAMP stress DAMP rho c L_e D with L_e = V / A_max, the time step's length (so that the
   step's reduction below is exact however flat a crushed element gets) and c the wave speed;
5. ``element_response`` with a zero bulk modulus (no separate pressure: the foam's stress is
   complete) and the effective modulus E_eff for c (time step, hourglass, bulk viscosity), or
   the element's current unloading tangent where that is stiffer (the HU/SHAPE damage makes
   unloading up to 1 + 2 SHAPE (1 - HU) times stiffer than loading, which would otherwise
   break the stable step); the
   step is divided by DAMP + sqrt(1 + DAMP^2), the reduction a linear viscosity DAMP c causes
   (the same form as LS-DYNA's Q in the solid time step).

The internal work is the midpoint rule 0.5 (sigma^(n-1) + sigma^n) : D dt V^(n-1/2), as for
MAT_006, so the energy balance checks the foam's hysteresis as dissipated internal work.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numba as nb
import numpy as np

from batball.elements.hex8 import kernel_ids, slot_cells
from batball.elements.hex8_block import add_pair, node_offset
from batball.elements.hex8_geometry import (
    modal_largest_face_area,
    modal_sums,
    modal_volume_gradient,
    modes_of_components,
)
from batball.elements.hex8_kinematics import (
    advance_prony_term,
    cayley_rotation,
    half_stress_work,
    midstep_velocity_gradient,
    velocity_gradient,
)
from batball.elements.hex8_response import element_response, stable_step
from batball.materials.foam import P_BETA1, P_DAMP, P_ED, P_MODULUS, P_RATE_FILTER
from batball.materials.foam_update import (
    EIGEN_LANES,
    H_RATE,
    H_RATE_STRESS,
    H_STRESS,
    H_WMAX,
    LAW_D,
    LAW_RATE,
    LAW_SIGMA,
    LAW_TANGENT,
    LAW_WMAX,
    N_HISTORY,
    block_principal_stress,
    block_symmetric_eigen,
    eigen_block,
    law_block,
    left_cauchy_green,
    rate_filter_weight,
)
from batball.materials.viscoelastic import viscoelastic_step_factors

ENERGY_INTERNAL, ENERGY_HOURGLASS, ENERGY_BULK_VISCOSITY = 0, 1, 2
_ZERO6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@nb.njit(inline="always")
def _node(cell: np.ndarray, a: int, i: int) -> np.uint64:
    """Unsigned offset of component i of the cell's node a in a flat (n_points * 3) array: no
    negative-index wraparound for Numba to add (as in ``hex8_block``)."""
    return np.uint64(3) * np.uint64(cell[a]) + np.uint64(i)


@nb.njit(inline="always")
def _component_sums(flat: np.ndarray, cell: np.ndarray, i: int) -> tuple:
    """Modal sums of component i of the cell's eight node vectors (7-tuple)."""
    return modal_sums(
        flat[_node(cell, 0, i)],
        flat[_node(cell, 1, i)],
        flat[_node(cell, 2, i)],
        flat[_node(cell, 3, i)],
        flat[_node(cell, 4, i)],
        flat[_node(cell, 5, i)],
        flat[_node(cell, 6, i)],
        flat[_node(cell, 7, i)],
    )


@nb.njit(inline="always")
def cell_modal_sums(flat: np.ndarray, cell: np.ndarray) -> tuple:
    """Modal sums X_1..X_7 (3-tuples) of the cell's node vectors in ``flat``, a flat view
    (n_points * 3) of an (n_points, 3) nodal array."""
    sx = _component_sums(flat, cell, 0)
    sy = _component_sums(flat, cell, 1)
    sz = _component_sums(flat, cell, 2)
    return modes_of_components(sx, sy, sz)


#: Columns of a cell's row of :func:`foam_reference_gradients`: G0_1..G0_6 (3 each), then V0.
N_REFERENCE = 19
REFERENCE_VOLUME = 18


@nb.njit(cache=True)
def foam_reference_gradients(cells: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Each cell's reference volume gradient on its modes, G0_k = dV0/dX0_k (k = 1..6) [m^2],
    and its reference volume V0 [m^3] from the undeformed coordinates ``reference``
    (n_points, 3): (n_cells, N_REFERENCE). Constant over a run; the foam kernel takes them
    instead of forming them from the reference nodes every cycle."""
    out = np.empty((cells.shape[0], N_REFERENCE))
    flat = reference.reshape(-1)
    for e in range(cells.shape[0]):
        x0 = cell_modal_sums(flat, cells[e])
        g1, g2, g3, g4, g5, g6, v0 = modal_volume_gradient(x0[0], x0[1], x0[2], x0[3], x0[4], x0[5])
        for k, g in enumerate((g1, g2, g3, g4, g5, g6)):
            out[e, 3 * k : 3 * k + 3] = g
        out[e, REFERENCE_VOLUME] = v0
    return out


@nb.njit(inline="always")
def deformation_gradient(x: tuple, g0: tuple, v0: float) -> tuple:
    """F (9-tuple, row-major) from the modal sums of x^n, the cell's reference gradients G0_k
    (six 3-tuples) and its reference volume V0, from :func:`foam_reference_gradients`:
    sum_k X_k (x) G0_k / V0 (module docstring, step 1)."""
    return velocity_gradient(x, g0, v0)


@nb.njit(inline="always")
def _axpy6(a: tuple, b: tuple, s: float) -> tuple:
    """a + s b for Voigt 6-tuples."""
    return (a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2],
            a[3] + s * b[3], a[4] + s * b[4], a[5] + s * b[5])  # fmt: skip


@nb.njit(inline="always")
def _at(row: int, lane: int) -> int:
    """Lane ``lane`` of row ``row`` of a block array (rows EIGEN_LANES wide, as ``eig``)."""
    return row * EIGEN_LANES + lane


@nb.njit(inline="always")
def _lane_vector(block: np.ndarray, row: int, lane: int) -> tuple:
    """The 3-tuple in rows row..row+2 of lane ``lane`` of a block array."""
    return (block[_at(row, lane)], block[_at(row + 1, lane)], block[_at(row + 2, lane)])


@nb.njit(inline="always")
def _store_lane_vector(block: np.ndarray, row: int, lane: int, x: tuple) -> None:
    """Write the 3-tuple x to rows row..row+2 of lane ``lane`` of a block array."""
    block[_at(row, lane)] = x[0]
    block[_at(row + 1, lane)] = x[1]
    block[_at(row + 2, lane)] = x[2]


@nb.njit(inline="always")
def _lane_nine(block: np.ndarray, row: int, lane: int) -> tuple:
    """The 9-tuple (a 3x3 tensor, row-major) in rows row..row+8 of a lane."""
    return (
        _lane_vector(block, row, lane)
        + _lane_vector(block, row + 3, lane)
        + _lane_vector(block, row + 6, lane)
    )


@nb.njit(inline="always")
def _store_lane_nine(block: np.ndarray, row: int, lane: int, t: tuple) -> None:
    """Write the 9-tuple t to rows row..row+8 of a lane."""
    _store_lane_vector(block, row, lane, (t[0], t[1], t[2]))
    _store_lane_vector(block, row + 3, lane, (t[3], t[4], t[5]))
    _store_lane_vector(block, row + 6, lane, (t[6], t[7], t[8]))


@nb.njit(inline="always")
def _store_modes(keep: np.ndarray, first: int, lane: int, x: tuple) -> None:
    """Write the 7 modal sums (3-tuples) ``x`` to rows first..first + 20 of ``keep``'s lane."""
    _store_lane_vector(keep, first, lane, x[0])
    _store_lane_vector(keep, first + 3, lane, x[1])
    _store_lane_vector(keep, first + 6, lane, x[2])
    _store_lane_vector(keep, first + 9, lane, x[3])
    _store_lane_vector(keep, first + 12, lane, x[4])
    _store_lane_vector(keep, first + 15, lane, x[5])
    _store_lane_vector(keep, first + 18, lane, x[6])


@nb.njit(inline="always")
def _load_modes(keep: np.ndarray, first: int, lane: int) -> tuple:
    """The 7 modal sums (3-tuples) in rows first..first + 20 of ``keep``'s lane."""
    return (_lane_vector(keep, first, lane), _lane_vector(keep, first + 3, lane),
            _lane_vector(keep, first + 6, lane), _lane_vector(keep, first + 9, lane),
            _lane_vector(keep, first + 12, lane), _lane_vector(keep, first + 15, lane),
            _lane_vector(keep, first + 18, lane))  # fmt: skip


# What the first pass over a block keeps of each cell for the second (rows of ``keep``, each
# EIGEN_LANES wide): the modal sums of x^n and v^(n-1/2), the mid-step velocity gradient L and
# that geometry's volume.
K_X, K_V, K_L, K_VMID = 0, 21, 42, 51
N_KEEP = 52

# What the first pass gathers of a block's cells (rows of ``gathered``, each EIGEN_LANES wide):
# component i of node a of x^n at row G_X + 8 i + a, of v^(n-1/2) at G_V + 8 i + a, then the
# cell's row of foam_reference_gradients.
G_X, G_V, G_REF = 0, 24, 48
N_GATHER = G_REF + N_REFERENCE


@nb.njit(inline="always")
def _gathered_sums(gathered: np.ndarray, first: int, lane: int) -> tuple:
    """Modal sums (7-tuple) of the eight node values in rows first..first + 7 of a lane."""
    return modal_sums(
        gathered[_at(first, lane)],
        gathered[_at(first + 1, lane)],
        gathered[_at(first + 2, lane)],
        gathered[_at(first + 3, lane)],
        gathered[_at(first + 4, lane)],
        gathered[_at(first + 5, lane)],
        gathered[_at(first + 6, lane)],
        gathered[_at(first + 7, lane)],
    )


@nb.njit(error_model="numpy")
def foam_kinematics(start, n, mesh, dt, keep, eig, gathered):
    """The first pass over cells start..start+n-1 (module docstring, step 1), n <= EIGEN_LANES:
    their modal sums, L and mid-step volume into ``keep``, and b = F F^T into the eigen block
    ``eig``, cell start + lane in lane ``lane``.

    The nodes and reference gradients are gathered into ``gathered`` (rows EIGEN_LANES wide),
    then the arithmetic runs as one loop over the lanes, which LLVM vectorises: the same
    operations in the same order as for one cell (no fast-math, so no contraction either way),
    the same bits. NumPy's error model: a division by a zero volume gives inf, not an exception,
    and the cycle's checks stop the run on it."""
    points, velocities, cells, reference = mesh
    for lane in range(n):
        cell = cells[start + lane]
        for i in range(3):
            for a in range(8):
                gathered[_at(G_X + 8 * i + a, lane)] = points[_node(cell, a, i)]
                gathered[_at(G_V + 8 * i + a, lane)] = velocities[_node(cell, a, i)]
        for k in range(N_REFERENCE):
            gathered[_at(G_REF + k, lane)] = reference[start + lane, k]
    for lane in range(n):
        x = modes_of_components(_gathered_sums(gathered, G_X, lane),
                                _gathered_sums(gathered, G_X + 8, lane),
                                _gathered_sums(gathered, G_X + 16, lane))  # fmt: skip
        v = modes_of_components(_gathered_sums(gathered, G_V, lane),
                                _gathered_sums(gathered, G_V + 8, lane),
                                _gathered_sums(gathered, G_V + 16, lane))  # fmt: skip
        lg, vmid = midstep_velocity_gradient(x, v, dt)
        g0 = (_lane_vector(gathered, G_REF, lane), _lane_vector(gathered, G_REF + 3, lane),
              _lane_vector(gathered, G_REF + 6, lane), _lane_vector(gathered, G_REF + 9, lane),
              _lane_vector(gathered, G_REF + 12, lane),
              _lane_vector(gathered, G_REF + 15, lane))  # fmt: skip
        b = left_cauchy_green(
            deformation_gradient(x, g0, gathered[_at(G_REF + REFERENCE_VOLUME, lane)])
        )
        _store_lane_nine(eig, 0, lane, b)
        _store_modes(keep, K_X, lane, x)
        _store_modes(keep, K_V, lane, v)
        _store_lane_nine(keep, K_L, lane, lg)
        keep[_at(K_VMID, lane)] = vmid


# Rows of a block's ``response`` array (each EIGEN_LANES wide), between the second pass (the
# law) and the third (the element response, SIMD across the block). In:
# the law's sigma (Voigt) and wave-speed modulus, the stored hourglass forces and the initial
# volume (the stored rate stress and stress are read from the rows of ``saved``, which the law
# does not change). Out: the new rate stress and total stress, hourglass forces, nodal forces
# (component i of node a at R_FORCES + 8 i + a), volume, stable step and the work (internal,
# hourglass, bulk viscosity).
R_SIGMA, R_MODULUS, R_HG_OLD, R_V0 = 0, 6, 7, 19
R_RATE, R_TOTAL, R_HG, R_FORCES, R_VOL, R_DT, R_WORK = 20, 26, 32, 44, 68, 69, 70
N_RESPONSE = 73


@nb.njit(inline="always")
def _lane_six(block: np.ndarray, row: int, lane: int) -> tuple:
    """The 6-tuple in rows row..row+5 of a lane."""
    return _lane_vector(block, row, lane) + _lane_vector(block, row + 3, lane)


@nb.njit(inline="always")
def _store_lane_six(block: np.ndarray, row: int, lane: int, s: tuple) -> None:
    """Write the 6-tuple s to rows row..row+5 of a lane."""
    _store_lane_vector(block, row, lane, (s[0], s[1], s[2]))
    _store_lane_vector(block, row + 3, lane, (s[3], s[4], s[5]))


@nb.njit(inline="always")
def _store_lane_eight(block: np.ndarray, row: int, lane: int, t: tuple) -> None:
    """Write the 8-tuple t to rows row..row+7 of a lane."""
    _store_lane_vector(block, row, lane, (t[0], t[1], t[2]))
    _store_lane_vector(block, row + 3, lane, (t[3], t[4], t[5]))
    block[_at(row + 6, lane)] = t[6]
    block[_at(row + 7, lane)] = t[7]


@nb.njit(inline="always")
def _strain_rate(lg: tuple) -> tuple:
    """D (Voigt, tensor shear components) of L (9-tuple)."""
    return (lg[0], lg[4], lg[8], 0.5 * (lg[1] + lg[3]), 0.5 * (lg[5] + lg[7]),
            0.5 * (lg[6] + lg[2]))  # fmt: skip


@nb.njit(inline="always")
def foam_law(start, n, table, state, volume0, work_space, weight):
    """The second pass over cells start..start+n-1 (module docstring, step 2): the foam law from
    the block's decomposition of b, for the block at once
    (:func:`batball.materials.foam_update.block_principal_stress`). Updates the cells' history
    rows and writes the law's sigma and modulus, the stored hourglass forces and V0 into the
    lanes of the ``response`` rows; each row as it was goes to the lane of ``saved`` (the
    stored stresses for :func:`foam_response`, and the row :func:`foam_store` restores for a
    cell without volume)."""
    history, hg_state = state
    law, saved, keep, eig, response = (work_space[0], work_space[1], work_space[2],
                                       work_space[3], work_space[5])  # fmt: skip
    params = table[0]
    for lane in range(n):
        e = start + lane
        for k in range(N_HISTORY):
            saved[_at(k, lane)] = history[e, k]
        law[_at(LAW_RATE, lane)] = history[e, H_RATE]
        law[_at(LAW_WMAX, lane)] = history[e, H_WMAX]
        _store_lane_six(law, LAW_D, lane, _strain_rate(_lane_nine(keep, K_L, lane)))
        for mode in range(4):
            hg = (hg_state[e, mode, 0], hg_state[e, mode, 1], hg_state[e, mode, 2])
            _store_lane_vector(response, R_HG_OLD + 3 * mode, lane, hg)
        response[_at(R_V0, lane)] = volume0[e]
    block_principal_stress(law, eig, n, weight, table)
    for lane in range(n):
        e = start + lane
        history[e, H_RATE] = law[_at(LAW_RATE, lane)]
        history[e, H_WMAX] = law[_at(LAW_WMAX, lane)]
        # the wave speed's modulus: E_eff, or the unloading tangent where that is stiffer
        tangent = law[_at(LAW_TANGENT, lane)]
        response[_at(R_MODULUS, lane)] = max(params[P_MODULUS], tangent + params[P_ED])
        sigma = _lane_nine(law, LAW_SIGMA, lane)
        voigt = (sigma[0], sigma[4], sigma[8], 0.5 * (sigma[1] + sigma[3]),
                 0.5 * (sigma[5] + sigma[7]), 0.5 * (sigma[6] + sigma[2]))  # fmt: skip
        _store_lane_six(response, R_SIGMA, lane, voigt)


@nb.njit(error_model="numpy")
def foam_response(n, keep, saved, response, rho0, damp, controls, step_factors):
    """The third pass over a block's n cells (module docstring, steps 3-5), one loop over the
    lanes: the rate stress, the DAMP stress, the element response (pressure none, bulk
    viscosity, hourglass forces, nodal forces, stable step) from the ``keep``, ``saved`` and
    ``response`` rows, into the ``response`` rows. ``damp`` is the foam's DAMP, ``controls``
    (dt, q1, q2, QH/QM, fb, stiff) and ``step_factors`` (decay, scale) of the rate stress. The
    same operations in the same order as one cell at a time (no fast-math), the same bits;
    NumPy's error model, so a degenerate cell gives inf or NaN, not an exception.

    With the hourglass form (fb, stiff) a run-time flag, LLVM compiles this loop to scalar
    code. Compiled per form, the IHQ 1 loop vectorised and the kernel ran about 4 % faster,
    but a kernel per form took 87-110 s each to compile (benchmarks/RESULTS.md)."""
    dt, q1, q2, hg_coefficient, fb, stiff = controls
    decay, scale = step_factors
    for lane in range(n):
        x = _load_modes(keep, K_X, lane)
        v = _load_modes(keep, K_V, lane)
        lg = _lane_nine(keep, K_L, lane)
        vmid = keep[_at(K_VMID, lane)]
        dd = _strain_rate(lg)
        trd = lg[0] + lg[4] + lg[8]
        modulus = response[_at(R_MODULUS, lane)]
        v0 = response[_at(R_V0, lane)]
        # 3: MAT_057's Maxwell rate stress, rotated with the step (Jaumann) and advanced
        q = cayley_rotation(0.5 * (lg[1] - lg[3]), 0.5 * (lg[5] - lg[7]), 0.5 * (lg[6] - lg[2]),
                            dt)  # fmt: skip
        de = (dd[0] * dt, dd[1] * dt, dd[2] * dt, dd[3] * dt, dd[4] * dt, dd[5] * dt)
        rate_stress, _ = advance_prony_term(_lane_six(saved, H_RATE_STRESS, lane), q, de, decay,
                                            scale)  # fmt: skip
        # 4: the DAMP stress, with the current density and the effective wave speed
        g1, g2, g3, g4, g5, g6, vol = modal_volume_gradient(x[0], x[1], x[2], x[3], x[4], x[5])
        rho = rho0 * v0 / vol if vol > 0.0 else rho0
        c = np.sqrt(modulus / rho)
        area = modal_largest_face_area(x[0], x[1], x[2], x[3], x[4], x[5])
        length = vol / area  # as dt's
        damping = damp * rho * c * abs(length)
        total = _axpy6(_axpy6(_lane_six(response, R_SIGMA, lane), rate_stress, 1.0), dd, damping)
        dev_work = half_stress_work(_lane_six(saved, H_STRESS, lane), total, de)
        hg_old = (
            _lane_vector(response, R_HG_OLD, lane),
            _lane_vector(response, R_HG_OLD + 3, lane),
            _lane_vector(response, R_HG_OLD + 6, lane),
            _lane_vector(response, R_HG_OLD + 9, lane),
        )
        # 5: the element response on x^n
        _, hg, forces, wave_speed, work = element_response(
            x, v, (g1, g2, g3, g4, g5, g6), total, _ZERO6, hg_old,
            (vol, v0, trd, vmid, dev_work, 0.0), (rho0, 0.0, modulus),
            (dt, q1, q2, hg_coefficient), fb, stiff,
        )  # fmt: skip
        step = stable_step(area, vol, trd, wave_speed, q1, q2)
        _store_lane_six(response, R_RATE, lane, rate_stress)
        _store_lane_six(response, R_TOTAL, lane, total)
        _store_lane_vector(response, R_HG, lane, hg[0])
        _store_lane_vector(response, R_HG + 3, lane, hg[1])
        _store_lane_vector(response, R_HG + 6, lane, hg[2])
        _store_lane_vector(response, R_HG + 9, lane, hg[3])
        _store_lane_eight(response, R_FORCES, lane, forces[0])
        _store_lane_eight(response, R_FORCES + 8, lane, forces[1])
        _store_lane_eight(response, R_FORCES + 16, lane, forces[2])
        response[_at(R_VOL, lane)] = vol
        response[_at(R_DT, lane)] = step / (damp + np.sqrt(1.0 + damp * damp))
        _store_lane_vector(response, R_WORK, lane, work)


@nb.njit(inline="always")
def _row(row: int, lane: np.uint64) -> np.uint64:
    """Unsigned offset of lane ``lane`` of row ``row`` of a block array (as :func:`_at`, with
    no negative-index wraparound for Numba to add to the per-cell passes)."""
    return np.uint64(row) * np.uint64(EIGEN_LANES) + lane


@nb.njit(inline="always")
def foam_store(start, n, cells, state, outputs, work_space, sums):
    """The last pass over cells start..start+n-1: their history (the new rate stress and
    stress, or the row as it was for a cell without volume), hourglass forces, volumes and
    stable steps, then their nodal forces added into the slot's flat array, from the
    ``response`` rows; returns ``sums``, the running (internal, hourglass, bulk viscosity) work
    [J], with theirs added in cell order.

    One loop a kind of output, with unsigned offsets (no negative-index wraparound): a cell at
    a time, with every output in one loop body, this pass took four times as long. The forces
    go in cell order and each node's pair of x and y as one update (``add_pair``): the same
    sums as one cell at a time."""
    history, hg_state = state
    nodal, cell_volume, cell_dt = outputs
    saved, response = work_space[1], work_space[5]
    lanes = np.uint64(n)
    first = np.uint64(start)
    for lane in range(lanes):
        e = first + lane
        if response[_row(R_VOL, lane)] > 0.0:
            for k in range(6):
                history[e, H_RATE_STRESS + k] = response[_row(R_RATE + k, lane)]
                history[e, H_STRESS + k] = response[_row(R_TOTAL + k, lane)]
        else:
            for k in range(N_HISTORY):
                history[e, k] = saved[_row(k, lane)]
        for mode in range(4):
            for i in range(3):
                hg_state[e, mode, i] = response[_row(R_HG + 3 * mode + i, lane)]
    for lane in range(lanes):
        cell_volume[first + lane] = response[_row(R_VOL, lane)]
        cell_dt[first + lane] = response[_row(R_DT, lane)]
    for lane in range(lanes):
        e = first + lane
        for a in range(8):
            node = node_offset(cells, e, a)
            x, y = response[_row(R_FORCES + a, lane)], response[_row(R_FORCES + 8 + a, lane)]
            add_pair(nodal, node, x, y)
            nodal[node + np.uint64(2)] += response[_row(R_FORCES + 16 + a, lane)]
    internal, hourglass, bulk = sums
    for lane in range(lanes):
        internal += response[_row(R_WORK, lane)]
        hourglass += response[_row(R_WORK + 1, lane)]
        bulk += response[_row(R_WORK + 2, lane)]
    return internal, hourglass, bulk


@nb.njit
def _foam_cells(first, end, mesh, material, state, outputs, controls):
    """Cells first..end-1 of one slot (``mesh``'s points and velocities and ``outputs``' nodal
    array, the slot's, as flat views (n_points * 3)); their (internal, hourglass, bulk
    viscosity) work [J]. The cells go in blocks of EIGEN_LANES: a first pass forms each
    cell's b = F F^T (:func:`foam_kinematics`, SIMD across the block), the block's
    eigen-decompositions and the law run for the block at once (:func:`foam_law`), the
    element response across the block again
    (:func:`foam_response`), and a last pass stores the cells' history and adds their forces
    in cell order (:func:`foam_store`). Each SIMD pass does what one cell at a time did, in the
    same order and without fast-math: the same bits. The passes are inlined: called per cell,
    their arguments (some twenty arrays) were copied at every call."""
    work_space = (law_block(), np.empty(N_HISTORY * EIGEN_LANES),
                  np.empty(N_KEEP * EIGEN_LANES), eigen_block(), np.empty(N_GATHER * EIGEN_LANES),
                  np.empty(N_RESPONSE * EIGEN_LANES))  # fmt: skip
    params, dt = material[2][0], controls[0]
    decay, scale = viscoelastic_step_factors(0.5 * params[P_ED], 0.0, params[P_BETA1], dt)
    weight = rate_filter_weight(params[P_RATE_FILTER], dt)
    sums = (0.0, 0.0, 0.0)
    for start in range(first, end, EIGEN_LANES):
        n = min(EIGEN_LANES, end - start)
        foam_kinematics(start, n, mesh, controls[0], work_space[2], work_space[3], work_space[4])
        block_symmetric_eigen(work_space[3], n)
        foam_law(start, n, material[2], state, material[1], work_space, weight)
        foam_response(n, work_space[2], work_space[1], work_space[5], material[0],
                      params[P_DAMP], controls, (decay, scale))  # fmt: skip
        sums = foam_store(start, n, mesh[2], state, outputs, work_space, sums)
    return sums


# Numba's cache is keyed on this file alone: after editing what the cached kernels here inline
# from hex8 and hex8_block (slot_cells and its BLOCK, node_offset, add_pair), change INLINED, so
# that a cache compiled from the old code is not loaded.
INLINED = "hex8.slot_cells: blocks of 64 cells on every host"


@nb.njit(parallel=True, cache=True)
def _foam_forces(mesh, material, state, outputs, energy_increments, controls):
    """All cells in the slots of ``nodal_forces`` (rows of ``energy_increments``), in parallel, as
    :func:`batball.elements.hex8.compute_hex8_forces` splits them."""
    # the parallel loop takes plain arrays: tuples of arrays are rebuilt inside its body
    points, velocities, cells, reference = mesh
    rho0, volume0, table = material
    params, rates, strains, stresses, counts, energies = table
    history, hg_state = state
    nodal_forces, cell_volume, cell_dt = outputs
    n_cells = cells.shape[0]
    n_chunks = energy_increments.shape[0]
    for chunk in nb.prange(n_chunks):
        first, end = slot_cells(chunk, n_chunks, n_cells)
        # flat views of the nodal arrays, made once a slot (reshape is a call)
        internal, hourglass, bulk = _foam_cells(
            first, end, (points.reshape(-1), velocities.reshape(-1), cells, reference),
            (rho0, volume0, (params, rates, strains, stresses, counts, energies)),
            (history, hg_state), (nodal_forces[chunk].reshape(-1), cell_volume, cell_dt),
            controls,
        )  # fmt: skip
        energy_increments[chunk, ENERGY_INTERNAL] = internal
        energy_increments[chunk, ENERGY_HOURGLASS] = hourglass
        energy_increments[chunk, ENERGY_BULK_VISCOSITY] = bulk


def compute_foam_forces(
    points: np.ndarray,
    velocities: np.ndarray,
    cells: np.ndarray,
    reference: np.ndarray,
    dt: float,
    density: float,
    volume0: np.ndarray,
    table: tuple[np.ndarray, ...],
    history: np.ndarray,
    hg_state: np.ndarray,
    hg_type: int,
    hg_coefficient: float,
    q1: float,
    q2: float,
    nodal_forces: np.ndarray,
    cell_volume: np.ndarray,
    cell_dt: np.ndarray,
    energy_increments: np.ndarray,
) -> None:
    """Element forces, foam stress update and stable steps of all hexes for one explicit cycle.

    Args:
        points: (n_points, 3) x^n [m]; velocities: (n_points, 3) v^(n-1/2) [m/s];
        cells: (n_cells, 8) node ids (:func:`batball.elements.hex8.kernel_ids`);
        reference: (n_cells, N_REFERENCE) the cells' reference gradients and volumes
            (:func:`foam_reference_gradients` of the undeformed coordinates);
        dt: the step dt^(n-1/2) that led to x^n [s].
        density: the foam's initial density [kg/m^3]; volume0: (n_cells,) initial volumes [m^3].
        table: :meth:`batball.materials.foam.FoamTable.arrays` of the (one) foam material.
        history: (n_cells, N_HISTORY) the foam history (``foam_update.H_*``), updated in place;
        hg_state: (n_cells, 4, 3) stiffness-form hourglass forces [N], updated in place.
        hg_type, hg_coefficient, q1, q2: as in :func:`batball.elements.hex8.compute_hex8_forces`.
        nodal_forces, cell_volume, cell_dt, energy_increments: outputs, as there (the forces
            are added into the slots of ``nodal_forces``).
    """
    kernel, arguments, controls = foam_kernel_call(
        points, velocities, cells, reference, density, volume0, table, history, hg_state,
        hg_type, hg_coefficient, q1, q2, nodal_forces, cell_volume, cell_dt, energy_increments,
    )  # fmt: skip
    kernel(*arguments, (float(dt), *controls))


def foam_kernel_call(
    points: np.ndarray,
    velocities: np.ndarray,
    cells: np.ndarray,
    reference: np.ndarray,
    density: float,
    volume0: np.ndarray,
    table: tuple[np.ndarray, ...],
    history: np.ndarray,
    hg_state: np.ndarray,
    hg_type: int,
    hg_coefficient: float,
    q1: float,
    q2: float,
    nodal_forces: np.ndarray,
    cell_volume: np.ndarray,
    cell_dt: np.ndarray,
    energy_increments: np.ndarray,
) -> tuple[Callable, tuple, tuple]:
    """The compiled kernel :func:`compute_foam_forces` calls on these arrays (its arguments but
    the step), checked: (kernel, arguments, controls), called as ``kernel(*arguments, (dt,
    *controls))`` with the step dt [s] (as :func:`batball.elements.hex8.hex8_kernel_call`)."""
    if history.shape != (cells.shape[0], N_HISTORY):
        raise ValueError(f"history has shape {history.shape}; expected ({cells.shape[0]}, 14)")
    if reference.shape != (cells.shape[0], N_REFERENCE):
        raise ValueError(
            f"reference has shape {reference.shape}; expected ({cells.shape[0]}, "
            f"{N_REFERENCE}) from foam_reference_gradients"
        )
    fb, stiff = hg_type >= 2, hg_type >= 4
    arguments = (
        (points, velocities, kernel_ids(cells), reference),
        (float(density), volume0, table),
        (history, hg_state),
        (nodal_forces, cell_volume, cell_dt),
        energy_increments,
    )
    return _foam_forces, arguments, (float(q1), float(q2), float(hg_coefficient), fb, stiff)


#: Columns of a foam body's per-cell history (solver state ``foam_history``).
N_FOAM_HISTORY = N_HISTORY


def foam_solver_call(
    model: Any,
    points: np.ndarray,
    velocities: np.ndarray,
    work: Any,
    history: np.ndarray,
    hg_state: np.ndarray,
    hourglass: Any,
) -> tuple[Callable, tuple, tuple]:
    """The solver's call into this kernel (``ExplicitSolver.kernel_call``): :func:`foam_kernel_call`
    for the foam body of ``model`` (``model.foam``) with the solver's workspace ``work``
    (volume0, the reference gradients ``foam_reference``, q1, q2 and the output arrays) and
    hourglass control."""
    return foam_kernel_call(
        points, velocities, work.cells, work.foam_reference, float(model.densities[0]),
        work.volume0, model.foam.arrays(), history, hg_state, hourglass.type,
        hourglass.coefficient, work.q1, work.q2, work.nodal_forces, work.cell_volume,
        work.cell_dt, work.energy_increments,
    )  # fmt: skip
