"""Node-level Numba kernels of the explicit cycle: assembly and the central-difference update."""

from __future__ import annotations

import numba as nb
import numpy as np

from batball.numerics import FASTMATH


def node_cell_map(cells: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR map from each node to the (cell * 8 + local node) slots that touch it.

    Returns:
        offsets (n_points + 1,) and entries (8 n_cells,), int64: node n's slots are
        ``entries[offsets[n]:offsets[n + 1]]``. Gathering through it needs no atomics.
    """
    flat = cells.ravel()
    order = np.argsort(flat, kind="stable")
    counts = np.bincount(flat, minlength=n_points)
    offsets = np.zeros(n_points + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    return offsets, order.astype(np.int64)


@nb.njit(parallel=True, fastmath=FASTMATH, cache=True)
def assemble_nodal_forces(
    cell_forces: np.ndarray, offsets: np.ndarray, entries: np.ndarray, forces: np.ndarray
) -> None:
    """forces[n] = sum of the element forces on node n (a race-free gather).

    Args:
        cell_forces: (n_cells, 24) [N], node-major; offsets, entries: from :func:`node_cell_map`.
        forces: (n_points, 3) out [N].
    """
    flat = cell_forces.reshape((-1, 3))
    for n in nb.prange(forces.shape[0]):
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[n], offsets[n + 1]):
            slot = entries[k]
            f0 += flat[slot, 0]
            f1 += flat[slot, 1]
            f2 += flat[slot, 2]
        forces[n, 0] = f0
        forces[n, 1] = f1
        forces[n, 2] = f2


@nb.njit(fastmath=FASTMATH, cache=True)
def central_difference_update(
    points: np.ndarray,
    velocities: np.ndarray,
    forces: np.ndarray,
    contact_forces: np.ndarray,
    mass: np.ndarray,
    dt_old: float,
    dt_new: float,
    momentum: np.ndarray,
) -> tuple[float, float]:
    """One central-difference update of velocities and positions, in place.

    v^(n+1/2) = v^(n-1/2) + a^n (dt_old + dt_new) / 2;  x^(n+1) = x^n + dt_new v^(n+1/2).

    Args:
        points, velocities: (n_points, 3) x^n and v^(n-1/2), advanced in place [m, m/s].
        forces: (n_points, 3) element forces [N]; contact_forces: (n_points, 3) [N].
        mass: (n_points,) lumped masses [kg]; momentum: (3,) out, total momentum [kg m/s].

    Returns:
        (kinetic energy at n+1/2 [J], work of the contact forces over the step [J]), the work
        taken with the mean displacement (dx^(n-1/2) + dx^(n+1/2)) / 2, consistent with the
        kinetic-energy change of the central-difference scheme.
    """
    kinetic = 0.0
    contact_work = 0.0
    momentum[:] = 0.0
    half = 0.5 * (dt_old + dt_new)
    for n in range(points.shape[0]):
        inv_m = 1.0 / mass[n]
        for i in range(3):
            v_old = velocities[n, i]
            v_new = v_old + (forces[n, i] + contact_forces[n, i]) * inv_m * half
            velocities[n, i] = v_new
            points[n, i] += dt_new * v_new
            contact_work += contact_forces[n, i] * 0.5 * (v_old * dt_old + v_new * dt_new)
            kinetic += 0.5 * mass[n] * v_new * v_new
            momentum[i] += mass[n] * v_new
    return kinetic, contact_work


def lumped_masses(cells: np.ndarray, cell_mass: np.ndarray, n_points: int) -> np.ndarray:
    """Row-sum lumped masses: each hex gives 1/8 of its mass to each node, (n_points,) [kg]."""
    mass = np.zeros(n_points)
    np.add.at(mass, cells.ravel(), np.repeat(cell_mass / 8.0, 8))
    return mass
