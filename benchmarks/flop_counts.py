"""Floating-point operations per element per cycle of the explicit element kernels, counted by hand.

What: the arithmetic one element does in one explicit cycle in

* the one-point hex of the ball (``batball.elements.hex8``, ``hex8_block``, ``hex8_kinematics``,
  ``hex8_response``, ``hex8_geometry``) on the path the full-size CCOR benchmark
  (``benchmarks/bench_ccor.py``) runs: ball "type1" is MAT_006 (``specs/data/type1.toml``,
  ``law = "mat006"``: constants K, G0, G_inf, beta, so n_terms = 1 Prony term), no hourglass card
  so the solver default IHQ 1 (viscous on Gamma, QH 0.1: not fb, not stiff), bulk viscosity on
  (Q1 1.5, Q2 0.06), precision "single" (the nodes are gathered in double and taken relative to
  the first node, ``gather_nodes``). ``hex8_foam`` (MAT_057/083) is not on this path;
* the layered Belytschko-Tsay shell of the bat (``batball.elements.shell_bt``, section data from
  ``shell_bt_section``) as ``benchmarks/bench_bbs_cycles.py --shell bt`` runs it on the default bat
  (``specs/data/default_bat.toml``, 48 x 0.1 in mesh): ``bt_nodal_force_kernel`` on one thread or
  ``bt_slot_force_kernel`` on several, both with the assembly fused in (``add_nodal_forces``).

* the co-rotational MITC4 shell of the bat (``batball.elements.shell_corotational``) as
  ``benchmarks/bench_bbs_cycles.py`` runs it by default (the batted-ball-speed test's shell):
  the nodal rotations, each cell's deformation, K0 d, the moment balance, the turn to global axes
  and the gather into the nodes (counted after the kernel was fused into chunks, the commit that
  added it to this file; K0 d recounted on 2026-11-30 when the product began to skip K0's
  blocks of zeros; the hex and BT counts are from 313b674).

When: 2026-11-29, hand counts from the source at commit 313b674 (``git rev-parse --short HEAD``;
the counted files had no uncommitted changes).

Convention:

* one flop per add, subtract and multiply; negation is free (``-a * b``, ``-x``); a fused
  multiply-add counts 2 (the source writes none: each ``a * b + c`` is counted as 1 mul + 1 add,
  which is what an FMA LLVM contracts it into is worth);
* divisions and square roots are not flops: they are listed separately (``*_DIVISIONS``,
  ``*_SQRTS``) because they are far slower;
* transcendental calls are listed by name (``HEX8_CALLS``); in this code ``log`` and ``cbrt`` are
  inline straight-line arithmetic (``vector_math.log64``, ``cbrt64`` in double precision,
  ``log32``, ``cbrt32`` in single), whose own cost is given in ``INLINE_CALL_COST`` and
  ``INLINE_CALL_COST_SINGLE`` for whoever wants to add it;
* comparisons, selects (``a if ok else b``, ``max``, ``abs``), integer index arithmetic, bit
  operations, int/float conversions and loads/stores are not flops;
* operations are counted as written in the Python source, what the code computes per element, not
  what LLVM may remove. Operations on constants only (``1.0 / 3.0``, ``like(x, 0.5)``) are folded
  literals and not counted.

How: phase by phase through the per-element loop bodies, following every inlined helper; then
checked by running the kernels' Python source (``NUMBA_DISABLE_JIT=1``) on a float type that counts
its operations, for one element: every phase below matched the hand count.

Things counted as written that the compiled code may not do (the uncertainty of these counts):

* hex IHQ 1: ``hex8_response.hourglass_forces`` computes ``lc = velocity_gradient(v, g, vol)``
  (108 flops, 1 division) that only the Flanagan-Belytschko forms use: dead code for IHQ 1
  (``HEX8_DEAD_IN_IHQ1``);
* hex: ``modal_largest_face_area`` multiplies by the literals +1 and -1 (72 of its 192 flops);
* hex: the compression-only terms (``bulk_q``, 8 flops; ``qv`` in the stable step, 4 flops) are
  counted always: the SIMD loop computes both sides of the select;
* hex, Prony terms 2..N: ``half_stress_work(zero, ...)`` adds a literal zero (12 adds per term);
* divisions by constants (``trd / 3``, ``c / 4``, ``bb / 8``, ``/ 16``, ``/ 12``) are listed as
  divisions; with the ``arcp`` fast-math flag (``numerics.FASTMATH``) LLVM may make them multiplies;
* the shells' ``zt = z * t`` is loop-invariant across the slots (counted per slot, as written).

Not per element, not in the totals: per block of cells (64 hexes, ``hex8_block.BLOCK``; 16 shells,
``shell_bt.BLOCK``), the hex's three work sums of ``hex8._advance_slot`` (3 adds) and the shell's
hourglass constants of ``advance_blocks`` (4 flops); per material and cycle,
``hex8_block.material_factors`` (exp etc.); per node after the shell kernel, the negation
``out *= -1.0`` (6 mul, one thread) or ``sum_slots`` (6 adds and 6 mul per node and slot). The
shells' layer loop always runs all 16 slots of a block and whole groups of 5 layers (zero layers
pad the rest); on the default bat every block is full (20,928 cells in 1,308 blocks) and every
laminate has a multiple of 5 layers, so neither adds work there.

Parameters the benchmarks use: bench_ccor's type-1 ball has n_terms = 1 (-> 1560 flops, 9
divisions, 3 square roots, 1 log, 1 cbrt per hex per cycle). The BBS benchmark's ball is type 1 too
but in double precision (``CoupledControls.precision``): 1512. The default bat's laminates have 15
layers (3 braided plies of 5 layers: knob, handles, barrel-2, barrel-3, end cap, insert; 16,320
cells) or 20 (4 braided plies: taper-1, taper-2, barrel-1; 4,608 cells): 1296 or 1496 flops, cell
mean 16.10 layers -> 1340.0 flops, with 10 divisions and 2 square roots, per shell per cycle.
"""

from __future__ import annotations

import math

# --- hex8, LS-DYNA ELFORM 1, as bench_ccor runs it (IHQ 1, MAT_006, n_terms = 1, single) -------

#: Flops per element-cycle by phase.
HEX8: dict[str, int] = {
    # hex8_block.gather_nodes: 48 subtractions (double, the first node's values), single
    # precision only; gather_material: loads and stores only (0)
    "gather: relative nodes": 48,
    # hex8_block.load_modal_sums -> hex8_geometry.modal_sums: 23 adds per component, x and v
    "modal sums of x^n and v": 138,
    # hex8_kinematics.midstep_velocity_gradient: s = -dt/2 and _step_back (6 modes)
    "mid-step geometry": 37,
    # hex8_geometry.modal_volume_gradient on x^(n-1/2): 12 cross, 4 dot, 6 _combine
    "mid-step volume gradient": 187,
    # hex8_kinematics.velocity_gradient: 9 six-term contractions times 1/V
    "velocity gradient L": 108,
    # hex8_kinematics.deviator_update (spin arguments) + cayley_rotation
    "Hughes-Winget rotation": 48,
    # hex8_kinematics.rotate_voigt, twice (s_inf and h)
    "rotate stored deviators": 150,
    # hex8_kinematics.deviatoric_increment
    "deviatoric increment": 17,
    # hex8_kinematics.advance_deviator -> viscoelastic.advance_viscoelastic_component (x6)
    "MAT_006 deviator update": 30,
    # hex8_kinematics.half_stress_work, twice, and their sum
    "deviatoric work": 37,
    # hex8_kinematics.element_kinematics -> hex8_geometry.modal_volume_gradient on x^n
    "volume gradient on x^n": 187,
    # hex8_response.pressure_and_viscosity (rho, p = K log, bulk q; log and cbrt in HEX8_CALLS)
    "pressure and bulk viscosity": 10,
    # hex8_response._hourglass_coefficient (viscous), _mode_force (x4), work sum
    "hourglass forces (IHQ 1)": 43,
    # hex8_response.hourglass_forces: lc = velocity_gradient(v, g, vol), unused for IHQ 1
    "hourglass lc (dead for IHQ 1)": 108,
    # hex8_response.element_response (p + q) + element_stress (not fb)
    "element stress": 10,
    # hex8_response.nodal_forces (x3): _modal_force (x6) + hourglass + nodal_sums
    "nodal forces": 165,
    # hex8_response.element_response: internal and bulk-viscosity work
    "energies": 9,
    # hex8_response.stable_step -> hex8_geometry.modal_largest_face_area (192 + 1)
    "stable step": 201,
    # hex8_block element_block: the second loop's three work sums
    "work sums": 3,
    # hex8_block.scatter_forces: 24 adds into the slot's nodal forces (double)
    "scatter forces": 24,
}

#: Divisions per element-cycle by phase (not in the flops).
HEX8_DIVISIONS: dict[str, int] = {
    "velocity gradient L": 1,  # 1 / V
    "Hughes-Winget rotation": 1,  # 2 / (1 + theta^2)
    "deviatoric increment": 1,  # tr D / 3
    "pressure and bulk viscosity": 2,  # V0 / V, modulus / rho
    "hourglass forces (IHQ 1)": 1,  # ... / 4
    "hourglass lc (dead for IHQ 1)": 1,  # 1 / V
    "stable step": 2,  # V / A_max, L_e / (Q + sqrt(...))
}

#: Square roots per element-cycle by phase (not in the flops).
HEX8_SQRTS: dict[str, int] = {
    "pressure and bulk viscosity": 1,  # wave speed c
    "stable step": 2,  # largest face area, sqrt(Q^2 + c^2)
}

#: Transcendental calls per element-cycle (hex8_response.pressure_and_viscosity).
HEX8_CALLS: dict[str, int] = {"log": 1, "cbrt": 1}

#: Inline cost of those calls (vector_math.log64, vector_math.cbrt64), same convention.
INLINE_CALL_COST: dict[str, dict[str, int]] = {
    "log": {"flops": 29, "divisions": 1},
    "cbrt": {"flops": 37, "divisions": 0},
}

#: The same for the single-precision kernel (vector_math.log32, vector_math.cbrt32).
INLINE_CALL_COST_SINGLE: dict[str, dict[str, int]] = {
    "log": {"flops": 25, "divisions": 1},
    "cbrt": {"flops": 35, "divisions": 0},
}

#: Flops of each further Prony term (n_terms > 1): hex8_block._make_prony_terms ->
#: hex8_kinematics.advance_prony_term (rotate 75, update 18, work 37), _add6 (6), work sum (1).
HEX8_PRONY_TERM = 137

#: Flops counted in HEX8 that LLVM drops for IHQ 1 ("hourglass lc (dead for IHQ 1)").
HEX8_DEAD_IN_IHQ1 = 108

#: The Prony terms of the ball bench_ccor runs (type1: MAT_006).
CCOR_N_TERMS = 1


def hex8_flops(n_terms: int = CCOR_N_TERMS, *, single: bool = True) -> int:
    """Flops per hex per cycle (IHQ 1) for a material of ``n_terms`` Prony terms (1..3);
    ``single=False`` for the double-precision kernel (no relative nodes)."""
    if not 1 <= n_terms <= 3:
        raise ValueError(f"the kernel has 1..3 Prony terms, got {n_terms}")
    total = sum(HEX8.values()) + HEX8_PRONY_TERM * (n_terms - 1)
    return total if single else total - HEX8["gather: relative nodes"]


# --- Belytschko-Tsay shell, LS-DYNA ELFORM 2, as bench_bbs_cycles --shell bt runs it ------------

#: Flops per element-cycle by phase, without the layers (BT_PER_LAYER).
BT_SHELL: dict[str, int] = {
    # shell_bt.gather_nodes and the state copies of advance_blocks: loads and stores only (0);
    # shell_bt.local_geometry: element_frame 48, centroid 12, local_xy (x4) 52, area 8, B 16
    "local geometry": 136,
    # shell_bt.local_velocity (x4): five dot3 each
    "local velocities": 100,
    # shell_bt.strain_rates
    "strain rates": 88,
    # shell_bt.block_kinematics: transverse shear forces Q += H gamma dt
    "transverse shear update": 10,
    # shell_bt.hourglass_vector: gamma and sum B.B
    "hourglass vector": 37,
    # shell_bt.block_kinematics: c_m, c_b, c_w (5) and t = gamma dt (4)
    "hourglass constants": 9,
    # shell_bt.hourglass_increment (x5)
    "hourglass stresses": 60,
    # shell_bt.block_forces -> node_forces (x4): local forces 34, to_global 15, moment 9
    "nodal forces": 232,
    # shell_bt.add_nodal_forces: 24 adds into the nodal array
    "scatter forces": 24,
}

#: Divisions per element-cycle by phase (not in the flops).
BT_DIVISIONS: dict[str, int] = {
    "local geometry": 7,  # normalising e3 and e1 (3 + 3), 0.5 / area
    "hourglass constants": 3,  # / 8, / 16, / 12
}

#: Square roots per element-cycle by phase (not in the flops).
BT_SQRTS: dict[str, int] = {"local geometry": 2}  # |e3|, |e1|

#: Flops per layer (and slot) of shell_bt.block_layer_group -> add_layer: d + z kappa 6,
#: stress update 21, z t 1, N and M shares 12.
BT_PER_LAYER = 40

#: Layers the kernel runs in groups of (shell_bt.GROUP): a laminate runs whole groups.
BT_GROUP = 5

#: The default bat's shells (48 x 0.1 in mesh) by layers of their laminate: cells.
BT_DEFAULT_BAT_CELLS: dict[int, int] = {15: 16320, 20: 4608}


def bt_flops(n_layers: int) -> int:
    """Flops per BT shell per cycle for a laminate of ``n_layers`` layers (braids expanded), the
    layers padded to whole groups of BT_GROUP as the kernel runs them."""
    if n_layers < 1:
        raise ValueError(f"a laminate has at least one layer, got {n_layers}")
    padded = math.ceil(n_layers / BT_GROUP) * BT_GROUP
    return sum(BT_SHELL.values()) + BT_PER_LAYER * padded


def bt_default_bat_mean_flops() -> float:
    """Flops per BT shell per cycle on the default bat, the mean over its cells (about 1340.0)."""
    cells = sum(BT_DEFAULT_BAT_CELLS.values())
    return sum(bt_flops(n) * count for n, count in BT_DEFAULT_BAT_CELLS.items()) / cells


# --- co-rotational MITC4 shell, as bench_bbs_cycles (--shell mitc4, the default) runs it ---------

#: Flops per element-cycle by phase (batball.elements.shell_corotational, one cell; the SIMD
#: loops also run the padding columns of a chunk's last cells, not counted here).
MITC4_SHELL: dict[str, int] = {
    # advance_rotations, per node (about one per cell: 21,024 nodes for 20,928 cells on the
    # default bat): dt omega 3, angle^2 5, 1 - cos 1, Q 36, Q R 45 (the large-angle branch, the
    # one the batted-ball-speed run takes: the small one is 91)
    "nodal rotations (per node)": 90,
    # deformation: element_frame 48, centroid 12, per corner (x4): p 3, local displacements
    # 18, E R_a (frame_row_times x3) 45, six off-diagonal entries of E R_a E0^T (dot3) 30,
    # sine vector 6, cosine 19
    "deformation": 544,
    # rotation_vectors, per corner (x4): |s|^2 5, the series 6, s times it 3
    "rotation vectors": 56,
    # local_product: f = K0 d, the 26 of 36 4 x 4 blocks of K0 that are not all zero (w
    # couples with neither u, v nor theta_z, theta_z with neither w nor theta_x, theta_y: the
    # same 26 in every kind of cell of the default bat), 26 x 16 multiply-adds
    "local forces K0 d": 832,
    # balance_moment: moment and J (x4) 38, adjugate 18, determinant 5, couple 15, w x p (x4) 15
    "moment balance": 250,
    # chunk_forces: E^T g for the 8 triples of a cell
    "to global axes": 120,
    # gather_node: 24 subtractions per cell into its nodes
    "gather forces": 24,
}

#: Divisions, square roots and transcendental calls per element-cycle (not in the flops).
MITC4_DIVISIONS: dict[str, int] = {"nodal rotations (per node)": 2, "deformation": 6,
                                   "moment balance": 3}  # fmt: skip
MITC4_SQRTS: dict[str, int] = {"nodal rotations (per node)": 1, "deformation": 2}
MITC4_CALLS: dict[str, int] = {"sin (per node)": 1, "cos (per node)": 1}


def mitc4_flops(nodes_per_cell: float = 1.0) -> float:
    """Flops per co-rotational MITC4 shell per cycle, the nodal rotations' share at
    ``nodes_per_cell`` nodes a cell (1.0046 on the default bat's 48 x 0.1 in mesh)."""
    per_node = MITC4_SHELL["nodal rotations (per node)"]
    return sum(MITC4_SHELL.values()) - per_node + per_node * nodes_per_cell
