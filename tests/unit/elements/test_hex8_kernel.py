"""The blocked SIMD hex8 kernel against a plain per-element NumPy reference of the same steps.

The reference follows the docstring of ``batball.elements.hex8`` literally, one element at a time:
B from 2x2x2 Gauss quadrature of dV/dx (exact for the trilinear hex), the Cayley rotation by a
matrix inverse, tensors as 3x3 matrices, hourglass vectors from the corner signs. It shares no
code with the kernel.
"""

from __future__ import annotations

import platform
import re
from dataclasses import dataclass

import numba as nb
import numpy as np
import pytest

from batball.elements.hex8 import _KERNELS, compute_hex8_forces
from batball.elements.hex8_block import (
    AXIS_PAIRS,
    BLOCK,
    GATHER_LANES,
    N_ROWS,
    R_V,
    R_X,
    RUN,
    element_block_types,
    element_block_viscous,
    gather_nodes,
    history_rows,
    pack_history,
    scatter_forces,
    unpack_history,
)

CORNERS = np.array(
    [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
     [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float,
)  # fmt: skip
XI, ETA, ZETA = CORNERS.T
GAMMA = np.array([ETA * ZETA, ZETA * XI, XI * ETA, XI * ETA * ZETA])  # (4, 8)
FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
GAUSS = np.array(np.meshgrid(*[[-1.0, 1.0]] * 3)).reshape(3, -1).T / np.sqrt(3.0)


def shape_gradients(xi: np.ndarray) -> np.ndarray:
    """dN_a/dxi_k at one point of the reference cube, (8, 3)."""
    dn = np.empty((8, 3))
    for k in range(3):
        factors = 1.0 + CORNERS * xi
        factors[:, k] = CORNERS[:, k]
        dn[:, k] = np.prod(factors, axis=1) / 8.0
    return dn


def volume_and_b(x: np.ndarray) -> tuple[float, np.ndarray]:
    """V = integral of det J and B_a = dV/dx_a = integral of det J dN_a/dx, (8, 3)."""
    volume, b = 0.0, np.zeros((8, 3))
    for xi in GAUSS:
        dn = shape_gradients(xi)
        jac = x.T @ dn  # dx_i / dxi_k
        det = np.linalg.det(jac)
        volume += det
        b += det * dn @ np.linalg.inv(jac)
    return volume, b


def voigt_to_matrix(v: np.ndarray) -> np.ndarray:
    return np.array([[v[0], v[3], v[5]], [v[3], v[1], v[4]], [v[5], v[4], v[2]]])


def matrix_to_voigt(m: np.ndarray) -> np.ndarray:
    return np.array([m[0, 0], m[1, 1], m[2, 2], m[0, 1], m[1, 2], m[2, 0]])


def largest_face_area(x: np.ndarray) -> float:
    return max(0.5 * np.linalg.norm(np.cross(x[c] - x[a], x[d] - x[b])) for a, b, c, d in FACES)


@dataclass
class Material:
    bulk: float
    g0: float
    g_inf: float
    beta: float
    density: float


def deviatoric_update(lg, s_inf, h, mat, dt):  # type: ignore[no-untyped-def]
    """Rotated and advanced (S_inf, H) as matrices, tr D and the stress power per volume."""
    d, w = 0.5 * (lg + lg.T), 0.5 * (lg - lg.T)
    eye = np.eye(3)
    q = np.linalg.inv(eye - 0.5 * dt * w) @ (eye + 0.5 * dt * w)
    s_inf, h = q @ voigt_to_matrix(s_inf) @ q.T, q @ voigt_to_matrix(h) @ q.T
    trd = np.trace(d)
    de = (d - trd / 3.0 * eye) * dt
    work = 0.5 * np.sum((s_inf + h) * de)
    x = mat.beta * dt
    s_inf = s_inf + 2.0 * mat.g_inf * de
    h = np.exp(-x) * h + 2.0 * (mat.g0 - mat.g_inf) * (-np.expm1(-x) / x) * de
    return s_inf, h, trd, work + 0.5 * np.sum((s_inf + h) * de)


def hourglass(x, v, b, volume, rho, c, hg_old, hg_type, coefficient, dt):  # type: ignore[no-untyped-def]
    """Hourglass forces (8, 3), new stored forces (4, 3) and work of one element."""
    gam = GAMMA if hg_type == 1 else GAMMA - (GAMMA @ x) @ b.T / volume
    rate = gam @ v  # (4, 3)
    if hg_type >= 4:
        kappa = coefficient * rho * c * c * np.sum(b * b) / (3.0 * volume)
        q = hg_old + kappa * dt * rate
        return -gam.T @ q, q, np.sum(0.5 * (hg_old + q) * rate) * dt
    q = coefficient * rho * np.cbrt(volume) ** 2 * c / 4.0 * rate
    return -gam.T @ q, hg_old, np.sum(q * rate) * dt


def reference_element(x, v, dt, mat, v0, s_inf, h, p_old, hg_old, hg_type, qh, q1, q2):  # type: ignore[no-untyped-def]
    """Everything the kernel computes for one element, as a dict."""
    vmid, bmid = volume_and_b(x - 0.5 * dt * v)
    s_new, h_new, trd, dev_work = deviatoric_update(v.T @ bmid / vmid, s_inf, h, mat, dt)
    volume, b = volume_and_b(x)
    out = {"s_inf": matrix_to_voigt(s_new), "h": matrix_to_voigt(h_new), "volume": volume}
    if not volume > 0:
        return out | {"forces": np.zeros((8, 3)), "dt": 0.0, "pressure": p_old, "hg": hg_old,
                      "energy": np.zeros(3)}  # fmt: skip
    rho = mat.density * v0 / volume
    c = np.sqrt((mat.bulk + 4.0 / 3.0 * mat.g0) / rho)
    p = mat.bulk * np.log(v0 / volume)
    length = np.cbrt(volume)
    q = rho * length * (q1 * length * trd**2 - q2 * c * trd) if trd < 0 else 0.0
    sigma = s_new + h_new - (p + q) * np.eye(3)
    f_hg, hg_new, hg_work = hourglass(x, v, b, volume, rho, c, hg_old, hg_type, qh, dt)
    le = volume / largest_face_area(x)
    qv = q2 * c + q1 * le * abs(trd) if trd < 0 else 0.0
    internal = (dev_work - 0.5 * (p_old + p) * trd * dt) * vmid
    return out | {
        "forces": -b @ sigma.T + f_hg,
        "dt": le / (qv + np.sqrt(qv**2 + c**2)),
        "pressure": p,
        "hg": hg_new,
        "energy": np.array([internal, hg_work, -q * trd * dt * vmid]),
    }


MATERIALS = [Material(5e8, 1.5e8, 5e6, 7.5e4, 1100.0), Material(2e9, 4e8, 1e8, 2e4, 900.0)]


def distorted_model(seed: int, n: tuple[int, int, int] = (3, 4, 5)) -> dict:
    """An n[0] x n[1] x n[2] box of 1 cm hexes with shaken nodes, two materials and one inverted
    cell."""
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.arange(k + 1.0) for k in n], indexing="ij"), -1)
    ids = np.arange(grid[..., 0].size).reshape(grid.shape[:3])
    i, j, k = (a.ravel() for a in np.meshgrid(*[np.arange(m) for m in n], indexing="ij"))
    cells = np.stack([ids[i + di, j + dj, k + dk] for di, dj, dk in (CORNERS > 0).astype(int)], 1)
    points = 0.01 * (grid.reshape(-1, 3) + 0.15 * rng.standard_normal((ids.size, 3)))
    spin = np.array([[0.0, -300.0, 100.0], [300.0, 0.0, -200.0], [-100.0, 200.0, 0.0]])
    velocities = 40.0 * rng.standard_normal((ids.size, 3)) + points @ spin.T + [0, 0, -42.0]
    cells[7] = cells[7][[4, 5, 6, 7, 0, 1, 2, 3]]  # upside down: negative volume
    n_cells = cells.shape[0]
    return {
        "points": points, "velocities": velocities, "cells": cells, "dt": 2e-7,
        "cell_material": rng.integers(0, 2, n_cells),
        "volume0": np.abs(np.array([volume_and_b(points[c])[0] for c in cells])) * 1.02,
        "s_inf": 1e5 * rng.standard_normal((n_cells, 6)),
        "h": 1e5 * rng.standard_normal((n_cells, 6)),
        "pressure": 1e5 * rng.standard_normal(n_cells),
        "hg_state": 0.1 * rng.standard_normal((n_cells, 4, 3)),
    }  # fmt: skip


def run_kernel(
    model: dict, hg_type: int, qh: float, q1: float, q2: float, n_chunks: int,
    dtype: type = np.float64,
) -> dict:  # fmt: skip
    m = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in model.items()}
    n_cells = m["cells"].shape[0]
    n_points = m["points"].shape[0]
    out = {"slots": np.zeros((n_chunks, n_points, 3)), "volume": np.zeros(n_cells),
           "dt": np.zeros(n_cells), "energy": np.zeros((n_chunks, 3))}  # fmt: skip
    constants = np.array([[x.bulk, x.g0, x.g_inf, x.beta] for x in MATERIALS])
    densities = np.array([x.density for x in MATERIALS])
    history = pack_history(
        m["volume0"], m["s_inf"], m["h"], m["pressure"], m["hg_state"], dtype=dtype
    )
    compute_hex8_forces(
        m["points"], m["velocities"], m["cells"], m["dt"], m["cell_material"], constants,
        densities, history, hg_type, qh, q1, q2, out["slots"], out["volume"], out["dt"],
        out["energy"],
    )  # fmt: skip
    h = unpack_history(history, n_cells)
    assert np.all(h["volume0"] == m["volume0"].astype(dtype))
    return out | {"forces": out["slots"].sum(axis=0), "s_inf": h["s_inf"], "h": h["h"],
                  "pressure": h["pressure"], "hg": h["hg_state"],
                  "energy": out["energy"].sum(axis=0)}  # fmt: skip


def run_reference(model: dict, hg_type: int, qh: float, q1: float, q2: float) -> dict:
    rows = []
    for e, c in enumerate(model["cells"]):
        rows.append(reference_element(
            model["points"][c], model["velocities"][c], model["dt"],
            MATERIALS[model["cell_material"][e]], model["volume0"][e], model["s_inf"][e],
            model["h"][e], model["pressure"][e], model["hg_state"][e], hg_type, qh, q1, q2,
        ))  # fmt: skip
    out = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    out["cell_forces"] = out.pop("forces").reshape(len(rows), 8, 3)
    out["forces"] = assembled(out["cell_forces"], model)
    out["energy"] = out["energy"].sum(axis=0)
    return out


def assembled(cell_forces: np.ndarray, model: dict) -> np.ndarray:
    """Element forces (n_cells, 8, 3) summed to the nodes, (n_points, 3)."""
    nodal = np.zeros_like(model["points"])
    np.add.at(nodal, model["cells"], cell_forces)
    return nodal


def assert_close(actual: np.ndarray, expected: np.ndarray, rel: float = 1e-10) -> None:
    """Equal to within ``rel`` of the array's largest magnitude (round-off, not physics)."""
    scale = np.abs(expected).max()
    assert np.abs(actual - expected).max() <= rel * scale


@pytest.mark.parametrize("hg_type", [1, 2, 3, 4, 5])
def test_kernel_matches_the_per_element_reference(hg_type: int) -> None:
    # 264 cells: several blocks of the kernel's layout (BLOCK cells), the last one partial,
    # split over three slots
    model = distorted_model(seed=hg_type, n=(4, 6, 11))
    got = run_kernel(model, hg_type, qh=0.1, q1=1.5, q2=0.06, n_chunks=3)
    want = run_reference(model, 4 if hg_type == 5 else (2 if hg_type == 3 else hg_type), 0.1,
                         1.5, 0.06)  # fmt: skip
    for key in ("forces", "volume", "dt", "s_inf", "h", "pressure", "hg"):
        assert_close(got[key], want[key])
    np.testing.assert_allclose(got["energy"], want["energy"], rtol=1e-9)
    assert np.all(want["energy"] != 0.0)


def test_kernel_matches_the_reference_with_materials_in_runs_of_blocks() -> None:
    # whole blocks of one material, repeated and then switched (the kernel keeps a block's
    # material factors for the next block of the same material), then one mixed block
    model = distorted_model(seed=7, n=(4, 6, 11))
    material = (np.arange(len(model["cells"])) // (2 * BLOCK)) % 2
    material[5 * BLOCK : 6 * BLOCK : 7] = 1
    model["cell_material"] = material
    got = run_kernel(model, 1, qh=0.1, q1=1.5, q2=0.06, n_chunks=2)
    want = run_reference(model, 1, 0.1, 1.5, 0.06)
    for key in ("forces", "volume", "dt", "s_inf", "h", "pressure"):
        assert_close(got[key], want[key])


@pytest.mark.parametrize("hg_type", [1, 2, 4])
def test_single_precision_kernel_matches_the_reference_to_float32_round_off(hg_type: int) -> None:
    # float32 has eps = 2**-24 = 6e-8. Volumes, steps and the rotated stresses come from a few
    # dozen operations on relative coordinates: 1e-6 (16 ulp). The pressure K ln(V0/V) divides
    # the volume's relative error by |ln(V0/V)| = ln 1.02 here (the model's V0 = 1.02 |V|), and
    # the forces carry it: 1e-6 / ln 1.02 = 5e-5. The internal work sums terms of both signs:
    # rtol 1e-4. Measured over seeds 1-6: 2e-7, 1.1e-5, 7e-6 and 1.5e-5.
    model = distorted_model(seed=hg_type)
    got = run_kernel(model, hg_type, qh=0.1, q1=1.5, q2=0.06, n_chunks=3, dtype=np.float32)
    want = run_reference(model, hg_type, 0.1, 1.5, 0.06)
    for key in ("volume", "dt", "s_inf", "h", "hg"):
        assert_close(got[key], want[key], rel=1e-6)
    for key in ("pressure", "forces"):
        assert_close(got[key], want[key], rel=1e-6 / np.log(1.02))
    np.testing.assert_allclose(got["energy"], want["energy"], rtol=1e-4)
    assert got["volume"][7] < 0.0 and got["dt"][7] == 0.0  # the inverted cell, as in double


def test_any_integer_ids_reach_the_one_int32_kernel() -> None:
    # A form compiles once (about 30 s) whatever integer type its callers hold: the solvers keep
    # int32 ids, the test models here are int64, and the wrapper converts, so both give the same
    # forces and the compiled kernel has no int64 signature.
    model = distorted_model(seed=3)
    assert model["cells"].dtype == np.int64
    wide = run_kernel(model, 1, qh=0.1, q1=1.5, q2=0.06, n_chunks=2)
    narrow_model = model | {"cells": model["cells"].astype(np.int32),
                            "cell_material": model["cell_material"].astype(np.int32)}  # fmt: skip
    narrow = run_kernel(narrow_model, 1, qh=0.1, q1=1.5, q2=0.06, n_chunks=2)
    assert np.array_equal(wide["forces"], narrow["forces"])
    for signature in _KERNELS[1, 1].signatures:
        (_, _, cells), (cell_material, _, _) = signature[0], signature[1]
        assert cells.dtype == cell_material.dtype == nb.int32


def test_inverted_element_gets_no_forces_step_or_work() -> None:
    model = distorted_model(seed=9)
    got = run_kernel(model, 4, qh=0.1, q1=1.5, q2=0.06, n_chunks=2)
    want = run_reference(model, 4, 0.1, 1.5, 0.06)
    want["cell_forces"][7] = 0.0
    assert got["volume"][7] < 0.0
    assert got["dt"][7] == 0.0
    assert_close(got["forces"], assembled(want["cell_forces"], model))  # nothing from cell 7
    assert got["pressure"][7] == model["pressure"][7]
    assert np.all(got["hg"][7] == model["hg_state"][7])
    assert np.all(got["dt"][np.arange(60) != 7] > 0.0)


def test_energies_do_not_depend_on_the_number_of_chunks() -> None:
    # 264 cells: more than four blocks of BLOCK (64) cells, the last one partial, so that the
    # seven slots hold different runs of whole blocks (and some none)
    model = distorted_model(seed=4, n=(4, 6, 11))
    one = run_kernel(model, 1, qh=0.1, q1=1.5, q2=0.06, n_chunks=1)
    many = run_kernel(model, 1, qh=0.1, q1=1.5, q2=0.06, n_chunks=7)
    np.testing.assert_allclose(many["energy"], one["energy"], rtol=1e-12)
    assert_close(many["forces"], one["forces"], rel=1e-13)  # vector or scalar remainder path
    # each slot adds into its own cells' nodes only
    assert np.all(np.abs(many["slots"]).sum(axis=2).min(axis=1) == 0.0)


def test_bulk_viscosity_off_and_uniform_material() -> None:
    model = distorted_model(seed=6)
    model["cell_material"] = np.ones_like(model["cell_material"])
    got = run_kernel(model, 2, qh=0.05, q1=0.0, q2=0.0, n_chunks=2)
    want = run_reference(model, 2, 0.05, 0.0, 0.0)
    assert got["energy"][2] == 0.0
    for key in ("forces", "dt", "s_inf", "pressure"):
        assert_close(got[key], want[key])


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="reads x86 assembly")
def test_element_loop_is_simd_across_elements() -> None:
    # the speed rests on LLVM vectorising the element loop: packed-double arithmetic (..pd)
    w = np.ones(N_ROWS * BLOCK)
    element_block_viscous(w, np.ones(history_rows(1) * BLOCK), BLOCK, 1e-7, 1.5, 0.06, 0.1)
    # the double signature by name: a float32 one may have been compiled first in this process
    signature = next(s for s in element_block_viscous.signatures if str(s[0].dtype) == "float64")
    asm = element_block_viscous.inspect_asm(signature)
    packed = re.findall(r"\tv?(?:add|sub|mul|div|f[n]?m(?:add|sub)\d*)pd\s", asm)
    assert len(packed) > 400


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="reads x86 assembly")
def test_single_precision_element_loop_is_packed_single() -> None:
    # single precision pays only if the loop is packed-single and as wide as double's in lanes
    # x 2: one double load, store or sum in the loop would make LLVM choose the double width
    w = np.ones(N_ROWS * BLOCK, dtype=np.float32)
    history = np.ones(history_rows(1) * BLOCK, dtype=np.float32)
    element_block_viscous(w, history, BLOCK, 1e-7, 1.5, 0.06, 0.1)
    signature = next(s for s in element_block_viscous.signatures if str(s[0].dtype) == "float32")
    assert signature == element_block_types(np.float32)  # what reads the loop alone compiles
    asm = element_block_viscous.inspect_asm(signature)
    single = re.findall(r"\tv?(?:add|sub|mul|div|f[n]?m(?:add|sub)\d*)ps\s", asm)
    double = re.findall(r"\tv?(?:add|sub|mul|div|f[n]?m(?:add|sub)\d*)pd\s", asm)
    assert len(single) > 400
    assert not double  # ln and the cube root run in float32 too (vector_math.log32, cbrt32)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("n", [BLOCK, GATHER_LANES + 5, 3])
def test_node_gather_matches_numpy(dtype: type, n: int) -> None:
    # whole groups of GATHER_LANES cells go through the vector gather, the rest one by one;
    # both must store x (and v) of each cell's nodes less its first node's, the difference
    # taken in double and rounded once to the scratch's precision (double: the values as they
    # are), as NumPy computes it here
    rng = np.random.default_rng(7)
    n_points, start = 200, 5
    points = 0.05 + 0.01 * rng.standard_normal((n_points, 3))  # a ball away from the origin
    velocities = 42.0 + rng.standard_normal((n_points, 3))  # flying at 42 m/s
    cells = rng.integers(0, n_points, size=(start + n + 4, 8)).astype(np.int32)
    w = np.full(N_ROWS * BLOCK, np.nan, dtype=dtype)
    gather_nodes(w, start, n, points.reshape(-1), velocities.reshape(-1), cells)
    own = cells[start : start + n]
    for row, values in ((R_X, points), (R_V, velocities)):
        nodal = values[own]  # (n, 8, 3)
        if dtype == np.float32:
            nodal = nodal - nodal[:, :1, :]
        want = nodal.reshape(n, 24).T.astype(dtype)  # rows 3 a + i, one column a cell
        got = w[row * BLOCK : (row + 24) * BLOCK].reshape(24, BLOCK)
        assert np.array_equal(got[:, :n], want)
        assert np.isnan(got[:, n:]).all()  # nothing beyond the n cells


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_force_scatter_adds_in_cell_order(dtype: type) -> None:
    # cells without runs of consecutive nodes (random ids): each node's sum must run over its
    # cells in cell order, each float32 force widened exactly, as before the scatter by runs
    # (test_force_scatter_adds_runs_of_nodes_pair_by_pair); np.add.at applies repeated
    # indices one after another in the order given
    rng = np.random.default_rng(11)
    n_points, start, n = 30, 3, BLOCK  # few nodes: each is shared by many cells
    cells = rng.integers(0, n_points, size=(start + n, 8)).astype(np.int32)
    w = rng.standard_normal(N_ROWS * BLOCK).astype(dtype)
    # forces from 1 to 1e9: sums that are not exact, so that another order would show (it
    # changes 5 of the 90 sums in single precision, 11 in double)
    forces = rng.standard_normal(n_points * 3) * 10.0 ** rng.uniform(0.0, 9.0, n_points * 3)
    want = forces.copy()
    own = cells[start : start + n]
    values = w[R_X * BLOCK : (R_X + 24) * BLOCK].reshape(24, BLOCK)[:, :n].T  # (n, 3 a + i)
    index = (3 * own[:, :, None] + np.arange(3)).reshape(n, 24)
    np.add.at(want, index.reshape(-1), values.reshape(-1).astype(np.float64))
    scatter_forces(w, start, n, cells, forces)
    assert np.array_equal(forces, want)


def cells_in_lines(n_lines: int, length: int, broken: tuple[int, ...]) -> np.ndarray:
    """Cells along lines of ``length`` in a (length + 1) x 2 x 2 grid of nodes a line, numbered
    along the lines (node ids rising by one along each line), so that RUN consecutive cells of
    a line reach consecutive nodes in every corner; the lines in ``broken`` get their first
    node swapped with a far node, so that their first cells' corners do not."""
    per_line = 4 * (length + 1)
    ids = np.arange(n_lines * per_line).reshape(n_lines, 2, 2, length + 1)  # (line, j, k, i)
    for line in broken:
        ids[line, 0, 0, 0], ids[-1, 1, 1, -1] = ids[-1, 1, 1, -1], ids[line, 0, 0, 0]
    i = np.arange(length)
    cells = []
    for grid in ids:
        corner = {
            (di, dj, dk): grid[dj, dk, i + di] for di in (0, 1) for dj in (0, 1) for dk in (0, 1)
        }
        order = [
            (0, 0, 0),
            (1, 0, 0),
            (1, 1, 0),
            (0, 1, 0),
            (0, 0, 1),
            (1, 0, 1),
            (1, 1, 1),
            (0, 1, 1),
        ]
        cells.append(np.stack([corner[c] for c in order], axis=1))
    return np.concatenate(cells).astype(np.int32)


@pytest.mark.parametrize("ids", [np.int32, np.int64])
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_node_gather_moves_runs_of_nodes_as_spans(dtype: type, ids: type) -> None:
    # lines of 12 cells, two of them with a first node from elsewhere: the gather loads a
    # corner's nodes of RUN cells as one span where they are consecutive, else node by node;
    # the rows must be what NumPy takes from each cell's nodes either way
    cells = cells_in_lines(n_lines=6, length=12, broken=(1, 4)).astype(ids)
    rng = np.random.default_rng(5)
    n_points = cells.max() + 1
    points = 0.05 + 0.01 * rng.standard_normal((n_points, 3))
    velocities = 42.0 + rng.standard_normal((n_points, 3))
    for start in range(0, cells.shape[0] - BLOCK + 1, 4):
        w = np.full(N_ROWS * BLOCK, np.nan, dtype=dtype)
        gather_nodes(w, start, BLOCK, points.reshape(-1), velocities.reshape(-1), cells)
        own = cells[start : start + BLOCK]
        for row, values in ((R_X, points), (R_V, velocities)):
            nodal = values[own]
            if dtype == np.float32:
                nodal = nodal - nodal[:, :1, :]
            want = nodal.reshape(BLOCK, 24).T.astype(dtype)
            assert np.array_equal(w[row * BLOCK : (row + 24) * BLOCK].reshape(24, BLOCK), want)


@pytest.mark.parametrize("ids", [np.int32, np.int64])
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_force_scatter_adds_runs_of_nodes_pair_by_pair(dtype: type, ids: type) -> None:
    # RUN cells whose four pairs of corners along the first axis all run along lines of nodes:
    # each pair's two forces are summed in double first (the second corner's one node on),
    # then added to the RUN + 1 nodes; RUN cells with any other corner, four cells whose
    # corners all rise but not as pairs one node apart, and the last n % RUN cells go in cell by
    # cell (np.add.at, in the order given). Forces from 1 to 1e9, so another order would show.
    lines = cells_in_lines(n_lines=4, length=12, broken=(2,))
    base = lines.max() + 1
    unjoined = base + 100 * np.arange(8)[None, :] + np.arange(RUN)[:, None]  # ids 100 a + e
    rest = np.random.default_rng(4).integers(0, base, size=(3, 8))
    cells = np.concatenate([lines, unjoined, rest]).astype(ids)
    rng = np.random.default_rng(3)
    n_points = cells.max() + 1
    w = rng.standard_normal(N_ROWS * BLOCK).astype(dtype)
    forces = rng.standard_normal(n_points * 3) * 10.0 ** rng.uniform(0.0, 9.0, n_points * 3)
    want = forces.copy()
    start = 24
    n = len(cells) - start  # 31: a broken line's first group, runs, the unjoined group, 3 more
    assert n % RUN == 3 and n < BLOCK
    values = w[R_X * BLOCK : (R_X + 24) * BLOCK].reshape(24, BLOCK).astype(np.float64)

    def cell_by_cell(e0: int, count: int) -> None:
        own = cells[start + e0 : start + e0 + count].astype(np.int64)
        index = (3 * own[:, :, None] + np.arange(3)).reshape(count, 24)
        np.add.at(want, index.reshape(-1), values[:, e0 : e0 + count].T.reshape(-1))

    whole = n - n % RUN
    spans = 0
    for e0 in range(0, whole, RUN):
        own = cells[start + e0 : start + e0 + RUN].astype(np.int64)
        rising = np.all(np.diff(own, axis=0) == 1, axis=0)  # each corner, cell to cell
        if all(rising[a] and rising[b] and own[0, b] == own[0, a] + 1 for a, b in AXIS_PAIRS):
            spans += 1
            for a, b in AXIS_PAIRS:
                first = values[3 * a : 3 * a + 3, e0 : e0 + RUN].T  # (RUN, 3)
                second = values[3 * b : 3 * b + 3, e0 : e0 + RUN].T
                span = np.zeros((RUN + 1, 3))
                span[:RUN] += first
                span[1:] += second
                nodes = 3 * own[0, a] + np.arange(3 * (RUN + 1))
                want[nodes] += span.reshape(-1)
        else:
            cell_by_cell(e0, RUN)
    cell_by_cell(whole, n - whole)
    # of the 7 groups, cell by cell: the broken line's first, the last line's last (the node it
    # swapped with) and the unjoined one
    assert spans == 4
    scatter_forces(w, start, n, cells, forces)
    assert np.array_equal(forces, want)
