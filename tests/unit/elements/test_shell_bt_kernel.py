"""The blocked (SIMD) Belytschko-Tsay shell kernel against the scalar kernel it replaced.

``shell_bt.bt_force_kernel`` runs the cells in blocks of one laminate, structure-of-arrays and
vectorised across the cells; ``shell_bt_scalar.bt_force_kernel_scalar`` is the former kernel, one
cell at a time with small work arrays, kept unchanged as the reference. Both are run side by side
for several steps on a small, randomly perturbed, curved (tapered tube) mesh of three laminates
with different layer counts (so padding layers and blocks cut at laminate changes occur), with
random velocities and rotation rates and a random initial stress state, and must agree to
round-off in the nodal forces and in every state array. The kernel with the assembly fused in
(``bt_nodal_force_kernel``) must give the serial sum of the blocked kernel's cell forces, to
round-off as well.

Tolerance: 1e-10 of each array's largest magnitude. The two kernels evaluate the same
expressions in the same order (the blocked one drops the moments' zero drilling term and the
padding layers' zero terms, exact); they differ only in what LLVM's fast-math flags let it do
(contraction into fused multiply-adds) differently in vector and scalar code, a
few ulps per operation. The forces are sums of a few dozen such terms, partly cancelling
(sum B_I = 0), so they are compared against the array's scale rather than element-wise. Five
steps of a stable update do not amplify that (measured: ~3e-16 of scale); 1e-10 is far above
round-off and far below any error in the element (a wrong sign, index or layer gives O(1)
differences).

Different kernels are compared to round-off. The blocked and the scalar kernel are different
code. The fused and slot kernels gave the cell-force kernel's bits whenever both were compiled
in one state, but not when one was compiled and the other loaded from Numba's cache, until the
fast-math flags lost ``reassoc`` (``test_compile_state.py``; docs/notes/precision.md); they are
checked to RTOL since. The thread-count check below stays bitwise: it runs one compiled kernel
twice.
"""

from __future__ import annotations

import numba as nb
import numpy as np
import pytest

from batball.elements.shell_bt import (
    BLOCK,
    HOURGLASS_RATIO,
    bt_force_kernel,
    bt_nodal_force_kernel,
    bt_slot_force_kernel,
    pack_force_state,
    slot_node_ranges,
    sum_slots,
)
from batball.elements.shell_bt_scalar import bt_force_kernel_scalar
from batball.elements.shell_bt_section import LayeredSection, layered_section
from batball.materials.laminate import Laminate, Ply
from batball.materials.orthotropic import OrthotropicLamina, isotropic_lamina
from batball.mesh.bat import revolve_rings

RTOL = 1e-10
#: The shell state arrays, in the order ``run`` returns them.
STATE_NAMES = ("layer stress", "shear force", "hourglass")
CARBON = OrthotropicLamina(name="carbon", density=1550.0, ea=138e9, eb=9.0e9, ec=9.0e9,
                           prba=0.3 * 9.0 / 138.0, gab=7.1e9, gbc=3.5e9, gca=7.1e9)  # fmt: skip
STEEL = isotropic_lamina(name="steel", density=8000.0, youngs_modulus=200e9, poissons_ratio=0.3)
LAMINATES = (
    Laminate(tuple(Ply(CARBON, 0.3e-3, np.radians(a)) for a in (0, 30, 90, -60, 45, 10, -20))),
    Laminate(tuple(Ply(STEEL, 0.4e-3, 0.0) for _ in range(3))),
    Laminate(tuple(Ply(CARBON, 0.2e-3, np.radians(a)) for a in (15, -75))),
)


def curved_mesh(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, LayeredSection]:
    """A tapered tube of 8 x 13 quads, nodes moved at random by up to 0.5 mm, and its section:
    runs of random length of the three laminates (blocks of one laminate are cut there)."""
    points, cells = revolve_rings(np.linspace(0.0, 0.12, 9), np.linspace(0.03, 0.022, 9),
                                  circumferential=13)  # fmt: skip
    points = points + rng.uniform(-0.5e-3, 0.5e-3, points.shape)
    runs = rng.integers(1, 20, cells.shape[0])
    cell_laminate = np.repeat(rng.integers(0, 3, runs.size), runs)[: cells.shape[0]]
    return points, cells, layered_section(LAMINATES, cell_laminate)


def random_state(rng: np.random.Generator, section: LayeredSection) -> list[np.ndarray]:
    """Layer stresses (zero in the padding layers) [Pa], shear forces [N/m], hourglass."""
    n_cells, n_layers = section.n_cells, section.layer_z.shape[1]
    stress = rng.normal(0.0, 1e7, (n_cells, n_layers, 3))
    stress *= (section.layer_thickness[section.cell_laminate] > 0)[:, :, None]
    return [stress, rng.normal(0.0, 1e3, (n_cells, 2)), rng.normal(0.0, 1e-1, (n_cells, 5))]


def run(kernel, points, cells, section, velocities, dt, state, out_shape=None):  # noqa: ANN001, ANN201
    """Step ``kernel`` with each velocity field in turn (nodes moved by v dt between steps);
    returns its force output (``out_shape``, default (n_cells, 4, 6), NaN before the call) of
    every step and the final state, element-wise (the inputs are not changed). The blocked
    kernels get the state packed in their block layout (``pack_force_state``)."""
    points = points.copy()
    blocked = kernel is not bt_force_kernel_scalar
    if blocked:
        packed = pack_force_state(section.cell_laminate, *state)
        arrays = [packed.block_start, packed.history]
    else:
        arrays = [a.copy() for a in state]
    forces = []
    for velocity in velocities:
        f = np.full(out_shape or (cells.shape[0], 4, 6), np.nan)
        kernel(points, cells, velocity, dt, section.cell_laminate, section.layer_stiffness,
               section.layer_z, section.layer_thickness, section.shear,
               section.hourglass_moduli, HOURGLASS_RATIO, *arrays, f)  # fmt: skip
        forces.append(f)
        points += dt * velocity[:, :3]
    if blocked:
        arrays = [packed.layer_stress, packed.shear_force, packed.hourglass]
    return np.array(forces), arrays


def assert_close(actual: np.ndarray, expected: np.ndarray, name: str) -> None:
    """|actual - expected| <= RTOL max |expected|, and the arrays are not trivial."""
    scale = np.abs(expected).max()
    assert scale > 0.0 and np.all(np.isfinite(actual)), name
    error = np.abs(actual - expected).max() / scale
    assert error <= RTOL, f"{name}: {error:.2e} of its scale"


@pytest.mark.parametrize("seed", [0, 1])
def test_blocked_kernel_matches_the_scalar_kernel(seed: int) -> None:
    """Forces of five steps and the final stresses, shear forces and hourglass stresses."""
    rng = np.random.default_rng(seed)
    points, cells, section = curved_mesh(rng)
    assert np.count_nonzero(np.diff(section.cell_laminate)) > 5
    state = random_state(rng, section)
    base = rng.normal(0.0, 1.0, (points.shape[0], 6)) * [2.0, 2.0, 2.0, 80.0, 80.0, 80.0]
    velocities = [base * (1.0 + 0.3 * step) + rng.normal(0.0, 0.2, base.shape)
                  for step in range(5)]  # fmt: skip
    dt = 2e-7
    expected = run(bt_force_kernel_scalar, points, cells, section, velocities, dt, state)
    actual = run(bt_force_kernel, points, cells, section, velocities, dt, state)
    for step in range(len(velocities)):
        assert_close(actual[0][step], expected[0][step], f"forces of step {step}")
    for name, a, b in zip(STATE_NAMES, actual[1], expected[1], strict=True):
        assert_close(a, b, name)
    # the padding layers are left at zero
    padding = section.layer_thickness[section.cell_laminate] == 0.0
    assert np.all(actual[1][0][padding] == 0.0)


def test_blocked_kernel_does_not_depend_on_the_thread_count() -> None:
    """One thread and all of Numba's threads give the same bits."""
    rng = np.random.default_rng(7)
    points, cells, section = curved_mesh(rng)
    state = random_state(rng, section)
    velocities = [rng.normal(0.0, 1.0, (points.shape[0], 6)) for _ in range(2)]
    threads = nb.get_num_threads()
    nb.set_num_threads(1)
    try:
        serial = run(bt_force_kernel, points, cells, section, velocities, 1e-7, state)
    finally:
        nb.set_num_threads(threads)
    parallel = run(bt_force_kernel, points, cells, section, velocities, 1e-7, state)
    assert np.array_equal(serial[0], parallel[0])
    for a, b in zip(serial[1], parallel[1], strict=True):
        assert np.array_equal(a, b)


def test_fused_assembly_is_the_serial_sum_of_the_cell_forces() -> None:
    """The cell forces summed node by node in cell order (np.add.at), and the same state, to
    round-off (RTOL; not bit for bit, see the module's note)."""
    rng = np.random.default_rng(3)
    points, cells, section = curved_mesh(rng)
    state = random_state(rng, section)
    velocities = [rng.normal(0.0, 1.0, (points.shape[0], 6)) for _ in range(3)]
    cell_forces, cell_state = run(bt_force_kernel, points, cells, section, velocities, 1e-7,
                                  state)  # fmt: skip
    n_points = points.shape[0]
    # a 7th column, which the kernel must leave alone
    nodal_forces, nodal_state = run(bt_nodal_force_kernel, points, cells, section, velocities,
                                    1e-7, state, (n_points, 7))  # fmt: skip
    for step in range(len(velocities)):
        expected = np.zeros((n_points, 6))
        np.add.at(expected, cells.ravel(), cell_forces[step].reshape(-1, 6))
        assert_close(nodal_forces[step][:, :6], expected, f"forces of step {step}")
        assert np.all(np.isnan(nodal_forces[step][:, 6]))
    for name, a, b in zip(STATE_NAMES, nodal_state, cell_state, strict=True):
        assert_close(a, b, name)


@pytest.mark.parametrize("n_slots", [1, 3])
def test_slot_kernel_sums_to_the_serial_assembly(n_slots: int) -> None:
    """The parallel fused kernel (one nodal array per run of blocks, summed by sum_slots) gives
    the serial assembly to round-off (a node shared by two runs is summed in two parts: a few
    ulps of the largest force, RTOL as above) and the same state to round-off (not bit for bit,
    see the module's note); each run writes only inside its node range."""
    rng = np.random.default_rng(11)
    points, cells, section = curved_mesh(rng)
    state = random_state(rng, section)
    velocities = [rng.normal(0.0, 1.0, (points.shape[0], 6)) for _ in range(3)]
    n_points = points.shape[0]
    serial, serial_state = run(bt_nodal_force_kernel, points, cells, section, velocities, 1e-7,
                               state, (n_points, 6))  # fmt: skip
    packed = pack_force_state(section.cell_laminate, *state)
    ranges = slot_node_ranges(cells, packed.block_start, n_slots)
    slots = np.full((n_slots, n_points, 6), np.nan)  # outside its range a slot is never read
    moved = points.copy()
    for step, velocity in enumerate(velocities):
        bt_slot_force_kernel(moved, cells, velocity, 1e-7, section.cell_laminate,
                             section.layer_stiffness, section.layer_z, section.layer_thickness,
                             section.shear, section.hourglass_moduli, HOURGLASS_RATIO,
                             packed.block_start, packed.history, slots, ranges)  # fmt: skip
        total = np.full((n_points, 6), np.nan)
        sum_slots(slots, ranges, -1.0, total)
        assert_close(-total, serial[step], f"forces of step {step}")
        moved += 1e-7 * velocity[:, :3]
    slot_state = (packed.layer_stress, packed.shear_force, packed.hourglass)
    for name, a, b in zip(STATE_NAMES, slot_state, serial_state, strict=True):
        assert_close(a, b, name)
    assert ranges[0, 0] == 0 and ranges[-1, 1] == n_points
    assert np.all(ranges[:, 1] > ranges[:, 0])


def test_block_layout_of_the_state() -> None:
    """pack_force_state and the state's properties are inverse; blocks are runs of at most
    BLOCK cells of one laminate, in cell order."""
    rng = np.random.default_rng(5)
    _, _, section = curved_mesh(rng)
    stress, shear, hourglass = random_state(rng, section)
    state = pack_force_state(section.cell_laminate, stress, shear, hourglass)
    assert np.array_equal(state.layer_stress, stress)
    assert np.array_equal(state.shear_force, shear)
    assert np.array_equal(state.hourglass, hourglass)
    start = state.block_start
    assert start[0] == 0 and start[-1] == section.n_cells
    assert np.all((np.diff(start) >= 1) & (np.diff(start) <= BLOCK))
    for first, end in zip(start[:-1], start[1:], strict=True):
        assert np.all(section.cell_laminate[first:end] == section.cell_laminate[first])
        # a block stops short only at a laminate change
        if end - first < BLOCK and end < section.n_cells:
            assert section.cell_laminate[end] != section.cell_laminate[first]
