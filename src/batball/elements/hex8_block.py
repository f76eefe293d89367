"""Stages of the hex8 force kernel over a block of ``BLOCK`` elements, SIMD across the elements.

Each block's data lives in one scratch vector ``w`` in structure-of-arrays form: row r (of
``N_ROWS``) holds a quantity for the block's elements at ``w[r * BLOCK + e]``. A block is gathered
from the mesh and state arrays, advanced by one loop over its elements ``e`` whose body is
straight-line arithmetic on scalars and tuples (``hex8_kinematics``, ``hex8_response``), which
LLVM vectorises, and scattered back. Keeping all rows in one array, a constant ``BLOCK`` apart,
lets LLVM prove that the rows do not overlap. The element history is kept between cycles in
the same layout, one row of the history array a block, and the loop reads and writes it in
place (a second array; the loop still vectorises, which tests of its assembly check).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

import numba as nb
import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from batball.elements.hex8_geometry import (
    Vector,
    modal_largest_face_area,
    modal_sums,
    modes_of_components,
)
from batball.elements.hex8_kinematics import (
    Modes,
    Voigt,
    advance_prony_term,
    element_kinematics,
)
from batball.elements.hex8_response import element_response, stable_step
from batball.elements.vector_math import component_rows, like, shuffle_mask, transposed_lanes
from batball.errors import SpecError
from batball.materials.viscoelastic import viscoelastic_step_factors
from batball.numerics import FASTMATH

#: Elements per block: a multiple of the SIMD width whose scratch (N_ROWS rows) stays in L1, the
#: same on every host (the history's layout follows it). 64: on an AVX2 EPYC (Zen 3) the
#: single-precision kernel ran 12-19 % faster with 64 than with 16 (IHQ 1 and 4), double
#: precision 2-10 %, and 32 and 128 fell between; on an AVX-512 EPYC (Zen 5) the full-size
#: single-precision CCOR solver ran 1-14 % faster on one thread with 64 than with 32 (median
#: 4 %, 7 of 7 alternated rounds), and 128 was no faster than 64. On a Sapphire Rapids Xeon,
#: with the kernel of 2026-12-05 (before the gather by runs of nodes), 32 had been 2-6 % faster
#: than 64 (benchmarks/RESULTS.md).
BLOCK = 64

# Rows of the block scratch (each BLOCK wide).
R_X = 0  # 24 node coordinates x^n [m] (node-major), then the 24 nodal forces [N]
R_V = 24  # 24 node velocities v^(n-1/2) [m/s]
R_VOL = 48  # volume [m^3]
R_DT = 49  # stable step [s]
R_WORK = 50  # 3 work increments (internal, hourglass, bulk viscosity) [J], summed after the
# element loop: without reassociation (numerics.FASTMATH) a sum carried through the loop
# would keep LLVM from vectorising it (IHQ 4 ran at a third of its speed)
R_MAT = 53  # the material factors, row R_MAT + k for column k of material_factors(): 6 rows,
# and for a material of N Prony terms (N > 1) 2 (N - 1) more after N_ROWS
N_ROWS = 59

# The element history (what a cycle carries to the next) is kept between cycles in the same
# layout, ``history[b, r * BLOCK + e]`` for cell b * BLOCK + e, and the element loop reads and
# writes a block's row of it in place. Its rows:
H_S = 0  # 6 s_inf [Pa]
H_H = 6  # 6 h [Pa]
H_P = 12  # pressure [Pa]
H_V0 = 13  # initial volume [m^3]
N_CORE_ROWS = 14
H_HG = 14  # 12 hourglass forces of the stiffness form [N] (mode-major)
N_HOURGLASS_ROWS = 12
H_PRONY = 26  # 6 (N - 1) rows of the further Prony terms' h (term-major)


#: The precisions of the element arithmetic, by name: the dtype of the kernel's history and
#: scratch. "single" is LS-DYNA's default executable; nodes, contact and energies stay double.
PRECISIONS = {"single": np.float32, "double": np.float64}


def check_precision(precision: str) -> None:
    """A SpecError naming the field and the choices unless ``precision`` is in PRECISIONS."""
    if precision not in PRECISIONS:
        raise SpecError("precision", precision, " or ".join(map(repr, PRECISIONS)))


def element_block_types(dtype: type) -> tuple[types.Type, ...]:
    """The Numba types the kernel calls an element loop (``element_block_*``) with, for a block
    scratch and history row of ``dtype`` (np.float32 or np.float64): (w, history, n, dt, q1,
    q2, hg_coefficient). What compiles the loop alone, as the kernel inlines it, for reading
    its machine code."""
    array = types.Array(nb.from_dtype(np.dtype(dtype)), 1, "C")
    return (array, array, types.int64, types.float64, types.float64, types.float64,
            types.float64)  # fmt: skip


def history_rows(n_terms: int) -> int:
    """Rows of one block's history for a material of ``n_terms`` Prony terms."""
    return N_CORE_ROWS + N_HOURGLASS_ROWS + 6 * (n_terms - 1)


@nb.njit(inline="always")
def constants_terms(constants: np.ndarray) -> int:
    """The number of Prony terms N of kernel constants (n_materials, 2 N + 2)."""
    return constants.shape[1] // 2 - 1


def history_terms(history: np.ndarray) -> int:
    """The number of Prony terms a history array (n_blocks, rows * BLOCK) is laid out for."""
    rows, extra = divmod(history.shape[1], BLOCK)
    n_terms = (rows - N_CORE_ROWS - N_HOURGLASS_ROWS) // 6 + 1
    if extra or n_terms < 1 or history_rows(n_terms) != rows:
        raise ValueError(f"history has {history.shape[1]} columns: not a hex8 block history")
    return n_terms


def pack_history(
    volume0: np.ndarray,
    s_inf: np.ndarray | None = None,
    h: np.ndarray | None = None,
    pressure: np.ndarray | None = None,
    hg_state: np.ndarray | None = None,
    n_terms: int = 1,
    dtype: type = np.float64,
) -> np.ndarray:
    """The block history (n_blocks, rows * BLOCK) of cells with initial volumes ``volume0``
    (n_cells,) [m^3] and the element-wise s_inf (n_cells, 6), h (n_cells, 6 N), pressure
    (n_cells,) [Pa] and hg_state (n_cells, 4, 3) [N] (zero where not given).

    ``dtype`` (np.float64 or np.float32) is the precision of the element arithmetic: the kernel
    computes each block in the precision of its history (:data:`PRECISIONS`)."""
    n_cells = len(volume0)
    n_blocks = -(-n_cells // BLOCK)
    columns = np.zeros((n_blocks * BLOCK, history_rows(n_terms)))
    columns[:n_cells, H_V0] = volume0
    if s_inf is not None:
        columns[:n_cells, H_S : H_S + 6] = s_inf
    if h is not None:
        columns[:n_cells, H_H : H_H + 6] = h[:, :6]
        columns[:n_cells, H_PRONY:] = h[:, 6:]
    if pressure is not None:
        columns[:n_cells, H_P] = pressure
    if hg_state is not None:
        columns[:n_cells, H_HG : H_HG + N_HOURGLASS_ROWS] = hg_state.reshape(-1, 12)
    blocks = columns.reshape(n_blocks, BLOCK, -1).transpose(0, 2, 1)
    return np.ascontiguousarray(blocks, dtype=dtype).reshape(n_blocks, -1)


def unpack_history(history: np.ndarray, n_cells: int) -> dict[str, np.ndarray]:
    """The element-wise arrays of a block history (double copies, whatever its precision):
    ``volume0`` (n_cells,) [m^3], ``s_inf`` (n_cells, 6), ``h`` (n_cells, 6 N), ``pressure``
    (n_cells,) [Pa] and ``hg_state`` (n_cells, 4, 3) [N]."""
    n_terms = history_terms(history)
    rows = history_rows(n_terms)
    history = history.astype(np.float64)
    columns = history.reshape(history.shape[0], rows, BLOCK).transpose(0, 2, 1)
    columns = columns.reshape(-1, rows)[:n_cells]
    return {
        "volume0": columns[:, H_V0].copy(),
        "s_inf": columns[:, H_S : H_S + 6].copy(),
        "h": np.concatenate([columns[:, H_H : H_H + 6], columns[:, H_PRONY:]], axis=1),
        "pressure": columns[:, H_P].copy(),
        "hg_state": columns[:, H_HG : H_HG + N_HOURGLASS_ROWS].reshape(n_cells, 4, 3).copy(),
    }


# Columns of material_factors(): density, K, K + 4/3 G0, 2 G_inf, exp(-beta_1 dt), the relaxing
# modulus of term 1, 2 G_1 (1 - exp(-beta_1 dt)) / (beta_1 dt) with
# G_1 = G0 - G_inf - sum_(i>1) G_i; then, for Prony terms i = 2..N, exp(-beta_i dt) and
# 2 G_i (1 - exp(-beta_i dt)) / (beta_i dt).
M_RHO, M_K, M_MODULUS, M_TWO_G_INF, M_DECAY, M_SCALE = 0, 1, 2, 3, 4, 5
N_FACTORS = 6


@nb.njit(fastmath=FASTMATH)
def material_factors(constants: np.ndarray, densities: np.ndarray, dt: float) -> np.ndarray:
    """Per-material factors of one step, (n_materials, 6 + 2 (N - 1)), columns ``M_*`` then the
    further terms' (decay, scale) (SI units); ``constants`` (n_materials, 2 N + 2) as in
    :mod:`batball.materials.prony` (N = 1: MAT_006's K, G0, G_inf, beta)."""
    n_extra = (constants.shape[1] - 4) // 2
    table = np.empty((constants.shape[0], N_FACTORS + 2 * n_extra))
    for m in range(constants.shape[0]):
        k, g0, g_inf, beta = constants[m, 0], constants[m, 1], constants[m, 2], constants[m, 3]
        g_first = g0
        for i in range(n_extra):
            g_i, beta_i = constants[m, 4 + 2 * i], constants[m, 5 + 2 * i]
            g_first -= g_i
            decay_i, scale_i = viscoelastic_step_factors(g_i, 0.0, beta_i, dt)
            table[m, N_FACTORS + 2 * i] = decay_i
            table[m, N_FACTORS + 2 * i + 1] = scale_i
        decay, scale = viscoelastic_step_factors(g_first, g_inf, beta, dt)
        table[m, M_RHO] = densities[m]
        table[m, M_K] = k
        table[m, M_MODULUS] = k + 4.0 / 3.0 * g0
        table[m, M_TWO_G_INF] = 2.0 * g_inf
        table[m, M_DECAY] = decay
        table[m, M_SCALE] = scale
    return table


@nb.njit(inline="always")
def at(row: int, e: int) -> int:
    """Index of row ``row``, element slot ``e`` in the block scratch."""
    return row * BLOCK + e


@nb.njit(inline="always", fastmath=FASTMATH)
def load3(w: np.ndarray, row: int, e: int) -> Vector:
    """The 3-tuple in rows row..row+2."""
    return (w[at(row, e)], w[at(row + 1, e)], w[at(row + 2, e)])


@nb.njit(inline="always", fastmath=FASTMATH)
def store3(w: np.ndarray, row: int, e: int, a: Vector) -> None:
    """Write the 3-tuple ``a`` to rows row..row+2."""
    w[at(row, e)] = a[0]
    w[at(row + 1, e)] = a[1]
    w[at(row + 2, e)] = a[2]


@nb.njit(inline="always", fastmath=FASTMATH)
def load6(w: np.ndarray, row: int, e: int) -> Voigt:
    """The 6-tuple (a Voigt tensor) in rows row..row+5."""
    a, b = load3(w, row, e), load3(w, row + 3, e)
    return (a[0], a[1], a[2], b[0], b[1], b[2])


@nb.njit(inline="always", fastmath=FASTMATH)
def store6(w: np.ndarray, row: int, e: int, s: Voigt) -> None:
    """Write the 6-tuple ``s`` to rows row..row+5."""
    store3(w, row, e, (s[0], s[1], s[2]))
    store3(w, row + 3, e, (s[3], s[4], s[5]))


@nb.njit(inline="always", fastmath=FASTMATH)
def _nodal_modal_sums(w, row, e, i):
    """Modal sums of component ``i`` of the 8 node vectors in rows row..row+23."""
    return modal_sums(
        w[at(row + i, e)],
        w[at(row + 3 + i, e)],
        w[at(row + 6 + i, e)],
        w[at(row + 9 + i, e)],
        w[at(row + 12 + i, e)],
        w[at(row + 15 + i, e)],
        w[at(row + 18 + i, e)],
        w[at(row + 21 + i, e)],
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def load_modal_sums(w: np.ndarray, row: int, e: int) -> Modes:
    """Modal sums X_1..X_7 (3-tuples) of the node vectors in rows row..row+23."""
    sx = _nodal_modal_sums(w, row, e, 0)
    sy = _nodal_modal_sums(w, row, e, 1)
    sz = _nodal_modal_sums(w, row, e, 2)
    return modes_of_components(sx, sy, sz)


# Helpers that take ``w`` are straight-line and every value is computed before the first store:
# a branch between Numba's reference counting of ``w`` in a call stops LLVM vectorising the loop.


@nb.njit(inline="always", fastmath=FASTMATH)
def _load_hourglass(history, e):
    """The four stored hourglass forces (3-tuples) [N] of slot e of a block's history."""
    return (load3(history, H_HG, e), load3(history, H_HG + 3, e),
            load3(history, H_HG + 6, e), load3(history, H_HG + 9, e))  # fmt: skip


@nb.njit(inline="always", fastmath=FASTMATH)
def _store_hourglass(history, e, hg):
    """Write the four hourglass forces (3-tuples) [N] to slot e of a block's history."""
    store3(history, H_HG, e, hg[0])
    store3(history, H_HG + 3, e, hg[1])
    store3(history, H_HG + 6, e, hg[2])
    store3(history, H_HG + 9, e, hg[3])


@nb.njit(inline="always", fastmath=FASTMATH)
def _store_nodal(w, e, i, f):
    """Write component i of 8 node vectors (an 8-tuple) to the rows R_X + 3 a + i."""
    w[at(R_X + i, e)] = f[0]
    w[at(R_X + 3 + i, e)] = f[1]
    w[at(R_X + 6 + i, e)] = f[2]
    w[at(R_X + 9 + i, e)] = f[3]
    w[at(R_X + 12 + i, e)] = f[4]
    w[at(R_X + 15 + i, e)] = f[5]
    w[at(R_X + 18 + i, e)] = f[6]
    w[at(R_X + 21 + i, e)] = f[7]


@nb.njit(inline="always", fastmath=FASTMATH)
def _store_element(w, history, e, pressure, forces, vol, step):
    """Write the pressure (to the history), nodal forces (three 8-tuples), volume and stable
    step."""
    history[at(H_P, e)] = pressure
    _store_nodal(w, e, 0, forces[0])
    _store_nodal(w, e, 1, forces[1])
    _store_nodal(w, e, 2, forces[2])
    w[at(R_VOL, e)] = vol
    w[at(R_DT, e)] = step


@nb.njit(inline="always", fastmath=FASTMATH)
def _load_factors(w, e, first):
    """Three consecutive material factors of slot e, from column ``first``."""
    return (
        w[at(R_MAT + first, e)],
        w[at(R_MAT + first + 1, e)],
        w[at(R_MAT + first + 2, e)],
    )


@nb.njit(inline="always", fastmath=FASTMATH)
def _add6(a: Voigt, b: Voigt) -> Voigt:
    """a + b for Voigt 6-tuples."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5])


def _make_prony_terms(n_extra: int):
    """Advance the further Prony terms 2..n_extra+1 (n_extra = 1 or 2) of slot e in place;
    returns h_sum plus their new h, and their work. Straight-line, every value computed before
    the first store, so that the element loop stays SIMD (see the note above)."""
    r_h = H_PRONY  # history row of term 2's h
    r_factors = R_MAT + N_FACTORS  # first row of term 2's (decay, scale)

    @nb.njit(inline="always", fastmath=FASTMATH)
    def advance_one(w, history, e, q, de, h_sum):
        f = (w[at(r_factors, e)], w[at(r_factors + 1, e)])
        h2, work2 = advance_prony_term(load6(history, r_h, e), q, de, f[0], f[1])
        store6(history, r_h, e, h2)
        return _add6(h_sum, h2), work2

    @nb.njit(inline="always", fastmath=FASTMATH)
    def advance_two(w, history, e, q, de, h_sum):
        f2 = (w[at(r_factors, e)], w[at(r_factors + 1, e)])
        f3 = (w[at(r_factors + 2, e)], w[at(r_factors + 3, e)])
        h2, work2 = advance_prony_term(load6(history, r_h, e), q, de, f2[0], f2[1])
        h3, work3 = advance_prony_term(load6(history, r_h + 6, e), q, de, f3[0], f3[1])
        store6(history, r_h, e, h2)
        store6(history, r_h + 6, e, h3)
        return _add6(_add6(h_sum, h2), h3), work2 + work3

    return advance_two if n_extra == 2 else advance_one


def _make_element_block(fb: bool, stiff: bool, n_terms: int = 1):
    """The element loop compiled for one hourglass form and number of Prony terms (the flags are
    compile-time constants; ``n_terms`` = 1 is MAT_006's loop, unchanged)."""
    prony = n_terms > 1
    advance_terms = _make_prony_terms(n_terms - 1)

    @nb.njit(fastmath=FASTMATH, error_model="numpy")
    def element_block(w, history, n, dt, q1, q2, hg_coefficient):
        """Advance slots 0..n-1 (SIMD across the slots) of the block scratch ``w`` and of the
        block's row ``history`` of the history array (in place), in the precision of both
        (float32 or float64; the controls are rounded to it); the (internal, hg, bulk) work [J].

        The sums are in the precision of ``w`` too: LLVM picks the vector width from the widest
        type the loop loads, stores or reduces, so one double accumulator would halve the
        single-precision width."""
        zero = like(w[0], 0.0)
        internal = zero
        hourglass = zero
        bulk = zero
        none = (zero, zero, zero)
        no_hourglass = (none, none, none, none)
        controls = (
            like(zero, dt), like(zero, q1), like(zero, q2), like(zero, hg_coefficient)
        )  # fmt: skip
        for e in range(n):
            x = load_modal_sums(w, R_X, e)
            v = load_modal_sums(w, R_V, e)
            hg_old = _load_hourglass(history, e) if stiff else no_hourglass
            p_old, v0 = history[at(H_P, e)], history[at(H_V0, e)]
            s_inf, h, trd, dev_work, vmid, g, vol, q, de = element_kinematics(
                x, v, load6(history, H_S, e), load6(history, H_H, e),
                _load_factors(w, e, M_TWO_G_INF), controls[0],
            )  # fmt: skip
            store6(history, H_S, e, s_inf)
            store6(history, H_H, e, h)
            h_all = h
            if prony:
                h_all, prony_work = advance_terms(w, history, e, q, de, h)
                dev_work += prony_work
            p, hg, forces, c, work = element_response(
                x, v, g, s_inf, h_all, hg_old, (vol, v0, trd, vmid, dev_work, p_old),
                _load_factors(w, e, M_RHO), controls, fb, stiff,
            )  # fmt: skip
            area = modal_largest_face_area(x[0], x[1], x[2], x[3], x[4], x[5])
            step = stable_step(area, vol, trd, c, controls[1], controls[2])
            _store_element(w, history, e, p, forces, vol, step)
            if stiff:
                _store_hourglass(history, e, hg)
            w[at(R_WORK, e)] = work[0]
            w[at(R_WORK + 1, e)] = work[1]
            w[at(R_WORK + 2, e)] = work[2]
        for e in range(n):
            internal += w[at(R_WORK, e)]
            hourglass += w[at(R_WORK + 1, e)]
            bulk += w[at(R_WORK + 2, e)]
        return internal, hourglass, bulk

    return element_block


#: The element loop for LS-DYNA IHQ 1, 2/3 and 4/5.
element_block_viscous = _make_element_block(False, False)
element_block_fb_viscous = _make_element_block(True, False)
element_block_fb_stiffness = _make_element_block(True, True)

#: The same for materials of 2 and 3 Prony terms (batball.materials.prony).
element_block_viscous_2 = _make_element_block(False, False, 2)
element_block_fb_viscous_2 = _make_element_block(True, False, 2)
element_block_fb_stiffness_2 = _make_element_block(True, True, 2)
element_block_viscous_3 = _make_element_block(False, False, 3)
element_block_fb_viscous_3 = _make_element_block(True, False, 3)
element_block_fb_stiffness_3 = _make_element_block(True, True, 3)


@nb.njit(inline="always")
def _unsigned_at(row: int, slot: np.uint64) -> np.uint64:
    """:func:`at` as an unsigned index (``slot`` unsigned): Numba wraps a signed index that may be
    negative, which costs the gather and scatter loops a third of their instructions."""
    return np.uint64(row * BLOCK) + slot


@nb.njit(inline="always")
def node_offset(cells: np.ndarray, cell: np.uint64, a: int) -> np.uint64:
    """Unsigned offset of node ``a`` of ``cell`` in a flat (n_points * 3) view of a nodal array."""
    return np.uint64(3) * np.uint64(cells[cell, a])


#: Cells the node gather moves at once (BLOCK is a multiple of it), RUN at a time.
GATHER_LANES = 8

#: Cells in a run: where a corner's nodes of RUN consecutive cells are consecutive nodes, the
#: gather and scatter move them as one span of memory (RUN nodes, 3 RUN doubles).
RUN = 4

#: The corners of a hex in pairs along its first axis (corner 0 to 1): in a run, the second
#: corner of each cell is the first corner of the next.
AXIS_PAIRS = ((0, 1), (3, 2), (4, 5), (7, 6))


def _id_pointers(
    context,
    builder: ir.IRBuilder,
    cells_type: types.Array,
    cells: ir.Value,
    cell: ir.Value,
    count: int,
) -> list[ir.Value]:  # noqa: ANN001
    """LLVM IR: pointers to the node ids of cells ``cell`` .. ``cell + count - 1`` of ``cells``
    (n_cells, 8, C order)."""
    ids = context.make_array(cells_type)(context, builder, value=cells)
    return [cgutils.get_item_pointer(context, builder, cells_type, ids,
                                     [builder.add(cell, ir.IntType(64)(e)), ir.IntType(64)(0)])
            for e in range(count)]  # fmt: skip


def _id_rows(builder: ir.IRBuilder, pointers: list[ir.Value]) -> list[ir.Value]:
    """LLVM IR: each cell's 8 node ids (from :func:`_id_pointers`) as one <8 x int> vector."""
    row_type = ir.VectorType(pointers[0].type.pointee, 8)
    return [builder.load(builder.bitcast(at, row_type.as_pointer()), align=4) for at in pointers]


def _rising(builder: ir.IRBuilder, rows: list[ir.Value], base: ir.Value) -> ir.Value:
    """LLVM IR: the corners (an i8 mask, bit a for corner a) whose ids in ``rows`` (<8 x int>
    each) are ``base``, ``base + 1``, ... cell after cell: their nodes a run of consecutive
    nodes."""
    id_type = base.type.element
    along = builder.icmp_signed("==", rows[0], base)
    for e in range(1, len(rows)):
        step = builder.add(base, ir.Constant(base.type, [id_type(e)] * 8))
        along = builder.and_(along, builder.icmp_signed("==", rows[e], step))
    return builder.bitcast(along, ir.IntType(8))


def _node_offset(builder: ir.IRBuilder, pointer: ir.Value, a: int) -> ir.Value:
    """LLVM IR: the flat offset (3 doubles a node) of corner ``a``'s node, its cell's ids at
    ``pointer`` (a scalar load: cheaper than taking it out of the cell's vector)."""
    node = builder.load(builder.gep(pointer, [ir.IntType(64)(a)]), align=4)
    return builder.mul(ir.IntType(64)(3), builder.sext(node, ir.IntType(64)))


def _node_rows(
    builder: ir.IRBuilder, arrays: list[ir.Value], offsets: list[ir.Value], flag: ir.Value
) -> list[list[ir.Value]]:
    """LLVM IR: the 3 component rows (<RUN x double>) of the nodes at ``offsets`` (RUN flat
    offsets) of each nodal array: one span each where they are consecutive nodes (``flag``),
    else each node's values gathered (:func:`transposed_lanes`). The same values either way."""
    packed = ir.Constant(ir.ArrayType(ir.IntType(64), RUN), ir.Undefined)
    for k, offset in enumerate(offsets):
        packed = builder.insert_value(packed, offset, k)
    with builder.if_else(flag) as (run, scattered):
        with run:
            from_run = [component_rows(builder, data, offsets[0], RUN) for data in arrays]
            run_block = builder.block
        with scattered:
            from_nodes = [transposed_lanes(builder, data, packed, 3) for data in arrays]
            scattered_block = builder.block
    rows: list[list[ir.Value]] = []
    for a_run, a_nodes in zip(from_run, from_nodes, strict=True):
        rows.append([])
        for r_run, r_nodes in zip(a_run, a_nodes, strict=True):
            row = builder.phi(r_run.type)
            row.add_incoming(r_run, run_block)
            row.add_incoming(r_nodes, scattered_block)
            rows[-1].append(row)
    return rows


def _scratch_and_ids(w: types.Type, cells: types.Type) -> bool:
    """Whether ``w`` is a float32 or float64 block scratch and ``cells`` a C-ordered 2-D array
    of int32 or int64 node ids (the types the run intrinsics compile for)."""
    return (
        isinstance(w, types.Array)
        and w.dtype in (types.float32, types.float64)
        and isinstance(cells, types.Array)
        and cells.dtype in (types.int32, types.int64)
        and cells.ndim == 2
        and cells.layout == "C"
    )


def _store_corner_rows(
    builder: ir.IRBuilder,
    scratch: ir.Value,
    row_type: ir.VectorType,
    indices: tuple[ir.Value, ir.Value],
    corner_halves: Callable[[int], list[list[list[ir.Value]]]],
) -> None:
    """LLVM IR: store the rows of the 8 corners into the block scratch (rows ``indices[array]
    + (3 a + i) BLOCK``), each corner's rows joined from its halves' (per half, per array, per
    component, from ``corner_halves``); in single precision less corner 0's, rounded once."""
    relative = row_type.element != ir.DoubleType()
    whole = shuffle_mask(list(range(GATHER_LANES)))
    first: list[list[ir.Value]] = []
    for a in range(8):
        rows = [[builder.shuffle_vector(low, high, whole)
                 for low, high in zip(*pair, strict=True)]
                for pair in zip(*corner_halves(a), strict=True)]  # fmt: skip
        first = rows if a == 0 else first
        for array, index in enumerate(indices):
            for i, values in enumerate(rows[array]):
                row = builder.fsub(values, first[array][i]) if relative else values
                if relative:
                    row = builder.fptrunc(row, row_type)
                at_row = builder.add(index, ir.IntType(64)((3 * a + i) * BLOCK))
                target = builder.bitcast(builder.gep(scratch, [at_row]), row_type.as_pointer())
                builder.store(row, target, align=4 if relative else 8)


@intrinsic
def _gather_cell_rows(typingctx, w, index_x, index_v, xs, vs, cells, cell):  # noqa: ANN001, ANN202
    """The 24 rows of the coordinates and of the velocities in the block scratch, for the
    GATHER_LANES cells from ``cell``: ``w[index + (3 a + i) BLOCK + k] = nodal[3 cells[cell +
    k, a] + i]`` for node a < 8, component i < 3 and cell k < GATHER_LANES (``index_x`` with
    ``xs``, ``index_v`` with ``vs``), less the same of node 0 (the cell's first node) where
    ``w`` is single precision; the difference taken in double and rounded once.

    What the scalar loop stores, moved RUN cells at a time: a corner's nodes of RUN cells as
    one span where they are consecutive nodes, else each node's values loaded as pairs
    (:func:`transposed_lanes`); each row rounded and stored as one vector, and the first
    node's rows, already in registers, serving as the origin (LLVM does none of this in the
    scalar loop)."""
    double = types.Array(types.float64, 1, "C")
    if (
        not _scratch_and_ids(w, cells)
        or xs != double
        or vs != double
        or index_x != types.uint64
        or index_v != types.uint64
        or cell != types.uint64
    ):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        scratch = context.make_array(signature.args[0])(context, builder, value=args[0]).data
        arrays = [context.make_array(double)(context, builder, value=args[k]).data
                  for k in (3, 4)]  # fmt: skip
        row_type = ir.VectorType(context.get_value_type(signature.args[0].dtype), GATHER_LANES)
        pointers = _id_pointers(context, builder, signature.args[5], args[5], args[6], GATHER_LANES)
        ids = _id_rows(builder, pointers)
        halves = range(0, GATHER_LANES, RUN)
        runs = [_rising(builder, ids[h : h + RUN], ids[h]) for h in halves]

        def spans(a: int) -> list[list[list[ir.Value]]]:
            return [[component_rows(builder, data, _node_offset(builder, pointers[h], a), RUN)
                     for data in arrays] for h in halves]  # fmt: skip

        def corner_by_corner(a: int) -> list[list[list[ir.Value]]]:
            offsets = [_node_offset(builder, at, a) for at in pointers]
            bit = ir.IntType(8)(1 << a)
            return [
                _node_rows(builder, arrays, offsets[h : h + RUN], builder.icmp_unsigned(
                    "!=", builder.and_(run, bit), ir.IntType(8)(0)))
                for h, run in zip(halves, runs, strict=True)
            ]  # fmt: skip

        # every corner of both halves a run: one straight block of spans, scheduled as a whole
        every = ir.IntType(8)(255)
        all_runs = builder.and_(builder.icmp_unsigned("==", runs[0], every),
                                builder.icmp_unsigned("==", runs[1], every))  # fmt: skip
        indices = (args[1], args[2])
        with builder.if_else(all_runs, likely=True) as (straight, mixed):
            with straight:
                _store_corner_rows(builder, scratch, row_type, indices, spans)
            with mixed:
                _store_corner_rows(builder, scratch, row_type, indices, corner_by_corner)
        return context.get_dummy_value()

    return types.none(w, index_x, index_v, xs, vs, cells, cell), codegen


#: Typed view of the intrinsic for mypy (the same object for Numba).
gather_cell_rows = cast(
    "Callable[[np.ndarray, np.uint64, np.uint64, np.ndarray, np.ndarray, np.ndarray, np.uint64],"
    " None]",
    _gather_cell_rows,
)


@nb.njit(fastmath=FASTMATH)
def gather_nodes(
    w: np.ndarray, start: int, n: int, xs: np.ndarray, vs: np.ndarray, cells: np.ndarray
) -> None:
    """Rows R_X..R_V+23 of cells start..start+n-1: their nodes' coordinates x^n [m] and
    velocities v^(n-1/2) [m/s] (``xs``, ``vs``: flat (n_points * 3) views), rounded to the
    precision of ``w``; in single precision less the first node's, subtracted in double before
    the rounding.

    The kernel uses only the modal sums of modes 1..7, which do not see a common translation or
    velocity; relative values keep the digits of the element's own shape and deformation rate
    (a ball at 0.05 m flying at 42 m/s would lose them to its position and speed in float32).
    Double precision takes the values as they are (the scalar path subtracts zero: the same
    bits).

    GATHER_LANES cells at a time (:func:`_gather_cell_rows`), the rest one by one; both store
    the same values."""
    relative = w.itemsize == 4
    whole = n - n % GATHER_LANES
    for e0 in range(0, whole, GATHER_LANES):
        cell = np.uint64(start + e0)
        slot = np.uint64(e0)
        gather_cell_rows(w, _unsigned_at(R_X, slot), _unsigned_at(R_V, slot), xs, vs, cells, cell)
    # unsigned indices into flat views: no negative-index wraparound, no row strides
    for e in range(whole, n):
        cell = np.uint64(start + e)
        slot = np.uint64(e)
        first = node_offset(cells, cell, 0)
        ox = xs[first] if relative else 0.0
        oy = xs[first + np.uint64(1)] if relative else 0.0
        oz = xs[first + np.uint64(2)] if relative else 0.0
        ou = vs[first] if relative else 0.0
        ov = vs[first + np.uint64(1)] if relative else 0.0
        ow = vs[first + np.uint64(2)] if relative else 0.0
        for a in range(8):
            node = node_offset(cells, cell, a)
            x0, x1, x2 = xs[node], xs[node + np.uint64(1)], xs[node + np.uint64(2)]
            v0, v1, v2 = vs[node], vs[node + np.uint64(1)], vs[node + np.uint64(2)]
            w[_unsigned_at(R_X + 3 * a, slot)] = x0 - ox
            w[_unsigned_at(R_X + 3 * a + 1, slot)] = x1 - oy
            w[_unsigned_at(R_X + 3 * a + 2, slot)] = x2 - oz
            w[_unsigned_at(R_V + 3 * a, slot)] = v0 - ou
            w[_unsigned_at(R_V + 3 * a + 1, slot)] = v1 - ov
            w[_unsigned_at(R_V + 3 * a + 2, slot)] = v2 - ow


@nb.njit(inline="always")
def gather_material(
    w: np.ndarray,
    start: int,
    n: int,
    cell_material: np.ndarray,
    factors: np.ndarray,
    held: int = -1,
) -> int:
    """The material factors of cells start..start+n-1 (a broadcast where they share one); returns
    the material whose factors now fill every slot of ``w`` (-1 if none does).

    ``held`` is what the previous call returned for this ``w`` (-1 at first): a block of that one
    material leaves the rows as they are, since the element loop only reads them."""
    first = cell_material[np.uint64(start)]
    shared = True
    for e in range(n):
        shared &= cell_material[np.uint64(start + e)] == first
    if shared and n == BLOCK and first == held:
        return held
    for k in range(factors.shape[1]):
        row = R_MAT + k
        if shared:
            value = factors[np.uint64(first), k]
            for e in range(n):
                w[_unsigned_at(row, np.uint64(e))] = value
        else:
            for e in range(n):
                material = np.uint64(cell_material[np.uint64(start + e)])
                w[_unsigned_at(row, np.uint64(e))] = factors[material, k]
    return first if shared and n == BLOCK else -1


@nb.njit(inline="always")
def scatter_outputs(
    w: np.ndarray, start: int, n: int, cell_volume: np.ndarray, cell_dt: np.ndarray
) -> None:
    """The volumes [m^3] and stable steps [s] of cells start..start+n-1 (unsigned indices: no
    negative-index wraparound, so the copies vectorise)."""
    for e in range(n):
        slot = np.uint64(e)
        cell = np.uint64(start) + slot
        cell_volume[cell] = w[_unsigned_at(R_VOL, slot)]
        cell_dt[cell] = w[_unsigned_at(R_DT, slot)]


def _add_span(builder: ir.IRBuilder, data: ir.Value, offset: ir.Value, values: ir.Value) -> None:
    """LLVM IR: ``data[offset + j] += values[j]`` for each element j of the vector ``values``."""
    target = builder.bitcast(builder.gep(data, [offset]), values.type.as_pointer())
    builder.store(builder.fadd(builder.load(target, align=8), values), target, align=8)


@intrinsic
def _add_pair(typingctx, flat, offset, first, second):  # noqa: ANN001, ANN202
    """``flat[offset] += first`` and ``flat[offset + 1] += second`` (a float64 array; the values
    float32 or float64, widened exactly) as one load, add and store of a pair: the same sums as
    two scalar updates, with a third fewer memory operations (LLVM does not pair them)."""
    if (
        flat != types.Array(types.float64, 1, "C")
        or offset != types.uint64
        or first not in (types.float32, types.float64)
        or second != first
    ):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        data = context.make_array(signature.args[0])(context, builder, value=args[0]).data
        values = ir.Constant(ir.VectorType(args[2].type, 2), ir.Undefined)
        values = builder.insert_element(values, args[2], ir.Constant(ir.IntType(32), 0))
        values = builder.insert_element(values, args[3], ir.Constant(ir.IntType(32), 1))
        if args[2].type != ir.DoubleType():
            values = builder.fpext(values, ir.VectorType(ir.DoubleType(), 2))
        _add_span(builder, data, args[1], values)
        return context.get_dummy_value()

    return types.none(flat, offset, first, second), codegen


#: Typed view of the intrinsic for mypy (the same object for Numba).
add_pair = cast("Callable[[np.ndarray, np.uint64, float, float], None]", _add_pair)


def _interleaved_forces(
    builder: ir.IRBuilder, scratch: ir.Value, element: ir.Type, index: ir.Value
) -> ir.Value:
    """LLVM IR: one corner's forces of RUN cells from the block scratch (rows ``index + i
    BLOCK``, i < 3), widened to double and interleaved node by node: <3 RUN x double>."""
    double = ir.DoubleType()
    row_type = ir.VectorType(element, RUN)
    rows = []
    for i in range(3):
        at = builder.add(index, ir.IntType(64)(i * BLOCK))
        row = builder.load(builder.bitcast(builder.gep(scratch, [at]), row_type.as_pointer()),
                           align=4)  # fmt: skip
        rows.append(row if element == double else builder.fpext(row, ir.VectorType(double, RUN)))
    xy = builder.shuffle_vector(
        rows[0], rows[1], shuffle_mask([k + RUN * c for k in range(RUN) for c in (0, 1)])
    )
    z = builder.shuffle_vector(rows[2], rows[2], shuffle_mask(list(range(RUN)) * 2))
    return builder.shuffle_vector(xy, z, shuffle_mask(
        [j for k in range(RUN) for j in (2 * k, 2 * k + 1, 2 * RUN + k)]))  # fmt: skip


def _add_corner_force(
    builder: ir.IRBuilder,
    scratch: ir.Value,
    element: ir.Type,
    index: ir.Value,
    data: ir.Value,
    node: ir.Value,
) -> None:
    """LLVM IR: add one cell's corner force (rows ``index + i BLOCK`` of the block scratch,
    widened exactly to double) into the node at flat offset ``node``: x and y as one pair, z
    alone."""
    values = []
    for i in range(3):
        value = builder.load(builder.gep(scratch, [builder.add(index, ir.IntType(64)(i * BLOCK))]))
        values.append(
            value if element == ir.DoubleType() else builder.fpext(value, ir.DoubleType())
        )
    pair = ir.Constant(ir.VectorType(ir.DoubleType(), 2), ir.Undefined)
    pair = builder.insert_element(pair, values[0], ir.IntType(32)(0))
    pair = builder.insert_element(pair, values[1], ir.IntType(32)(1))
    _add_span(builder, data, node, pair)
    z_at = builder.gep(data, [builder.add(node, ir.IntType(64)(2))])
    builder.store(builder.fadd(builder.load(z_at, align=8), values[2]), z_at, align=8)


def _pairs_along_lines(builder: ir.IRBuilder, rows: list[ir.Value]) -> ir.Value:
    """LLVM IR: whether every pair of :data:`AXIS_PAIRS` of the cells with these id rows runs
    along a line of nodes: each corner's id rising by one from cell to cell, the pair's second
    corner one on from its first (integer vector compares, reduced once)."""
    pair_of, one_on = [0] * 8, [0] * 8
    for a, b in AXIS_PAIRS:
        pair_of[a] = pair_of[b] = a
        one_on[b] = 1
    id_type = rows[0].type.element
    base = builder.add(builder.shuffle_vector(rows[0], rows[0], shuffle_mask(pair_of)),
                       ir.Constant(rows[0].type, [id_type(k) for k in one_on]))  # fmt: skip
    return builder.icmp_unsigned("==", _rising(builder, rows, base), ir.IntType(8)(255))


@intrinsic
def _scatter_run_cells(typingctx, w, slot, cells, cell, flat):  # noqa: ANN001, ANN202
    """Add the nodal forces of the RUN cells from ``cell`` (in the block scratch ``w`` from
    ``slot``) into ``flat`` (n_points * 3 doubles) [N].

    Where all four pairs of corners along the cells' first axis (:data:`AXIS_PAIRS`) run along
    lines of nodes (each corner's nodes consecutive, the second corner's one on from the
    first's), each pair goes in as one span of 3 (RUN + 1) doubles: at the nodes both corners
    reach, their two forces summed first, then added to the node (one load, add and store
    instead of 2 RUN). Otherwise the cells go in cell by cell, corner by corner, a node's x and
    y as one pair and z alone, as :func:`scatter_forces` adds the rest: the sums of the code
    before runs, and their bits."""
    if (
        not _scratch_and_ids(w, cells)
        or slot != types.uint64
        or cell != types.uint64
        or flat != types.Array(types.float64, 1, "C")
    ):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        w_type, _, cells_type, _, flat_type = signature.args
        scratch = context.make_array(w_type)(context, builder, value=args[0]).data
        data = context.make_array(flat_type)(context, builder, value=args[4]).data
        element = context.get_value_type(w_type.dtype)
        i64 = ir.IntType(64)
        pointers = _id_pointers(context, builder, cells_type, args[2], args[3], RUN)
        rows = _id_rows(builder, pointers)

        def offset(e: int, a: int) -> ir.Value:  # flat offset of corner a of cell ``cell + e``
            return _node_offset(builder, pointers[e], a)

        def add_corner(e: int, a: int) -> None:
            index = builder.add(args[1], i64((R_X + 3 * a) * BLOCK + e))
            _add_corner_force(builder, scratch, element, index, data, offset(e, a))

        every_run = _pairs_along_lines(builder, rows)
        zero = ir.Constant(ir.VectorType(ir.DoubleType(), 3 * RUN), None)
        low = shuffle_mask(list(range(3 * RUN)) + [3 * RUN] * 3)
        high = shuffle_mask([3 * RUN] * 3 + list(range(3 * RUN)))
        with builder.if_else(every_run, likely=True) as (by_pairs, by_cells):
            with by_pairs:
                for a, b in AXIS_PAIRS:
                    first = _interleaved_forces(
                        builder, scratch, element, builder.add(args[1], i64((R_X + 3 * a) * BLOCK))
                    )
                    second = _interleaved_forces(
                        builder, scratch, element, builder.add(args[1], i64((R_X + 3 * b) * BLOCK))
                    )
                    both = builder.fadd(builder.shuffle_vector(first, zero, low),
                                        builder.shuffle_vector(second, zero, high))  # fmt: skip
                    _add_span(builder, data, offset(0, a), both)
            with by_cells:
                for e in range(RUN):
                    for a in range(8):
                        add_corner(e, a)
        return context.get_dummy_value()

    return types.none(w, slot, cells, cell, flat), codegen


#: Typed view of the intrinsic for mypy (the same object for Numba).
scatter_run_cells = cast(
    "Callable[[np.ndarray, np.uint64, np.ndarray, np.uint64, np.ndarray], None]",
    _scatter_run_cells,
)


@nb.njit
def scatter_forces(
    w: np.ndarray, start: int, n: int, cells: np.ndarray, forces: np.ndarray
) -> None:
    """Add the nodal forces of cells start..start+n-1 into ``forces`` (a flat n_points * 3
    view) [N]: RUN cells at a time (:func:`_scatter_run_cells`), the last n % RUN cell by cell,
    a node's x and y as one pair and z alone. Where the cells' nodes run along lines, the
    order of the sums at a node differs from cell by cell (round-off).

    ``forces`` belongs to one slot of the parallel loop, so no other thread writes it; the nodes
    of consecutive cells are neighbours, so the writes stay in cache.
    """
    whole = n - n % RUN
    for e0 in range(0, whole, RUN):
        scatter_run_cells(w, np.uint64(e0), cells, np.uint64(start + e0), forces)
    for e in range(whole, n):
        cell = np.uint64(start + e)
        slot = np.uint64(e)
        for a in range(8):
            node = node_offset(cells, cell, a)
            x, y = w[_unsigned_at(R_X + 3 * a, slot)], w[_unsigned_at(R_X + 3 * a + 1, slot)]
            add_pair(forces, node, x, y)
            forces[node + np.uint64(2)] += w[_unsigned_at(R_X + 3 * a + 2, slot)]
