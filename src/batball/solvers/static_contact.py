"""Linear statics with penalty contact: an active-set iteration on K + sum G^T k G.

For each gap set (:class:`batball.contact.shell_contact.PenaltyGaps`) the closed gaps add the
penalty energy k g^2 / 2 with g = g0 + G u. With the active set A fixed the problem is linear:

    (K + sum_A G^T k G) u = f - sum_A G^T k g0,

solved on the free degrees of freedom by a sparse LU factorisation (SuperLU, symmetric mode,
no pivoting: the matrix is symmetric positive definite).
The active set is then updated (closed where g < 0, open where g >= 0, optionally with a small
hysteresis) and the solve repeated until it no longer changes: the frictionless penalty solution,
which for a linear-elastic structure does not depend on the loading path. Bilateral springs are
always active.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from batball.contact.shell_contact import PenaltyGaps
from batball.errors import SimulationError


@dataclass(frozen=True)
class StaticContactSolution:
    """The converged state.

    Attributes:
        u: nodal displacements and rotations, (6 n_points,), m and rad.
        gaps: g of each gap set, list of (n_gaps,), m.
        forces: compressive force of each gap, list of (n_gaps,), N.
        active: closed gaps of each set, list of (n_gaps,) bool.
        iterations: linear solves done.
    """

    u: np.ndarray
    gaps: list[np.ndarray]
    forces: list[np.ndarray]
    active: list[np.ndarray]
    iterations: int


def penalty_system(
    stiffness: sp.spmatrix, gap_sets: Sequence[PenaltyGaps], active: Sequence[np.ndarray]
) -> tuple[sp.csr_matrix, np.ndarray]:
    """K + sum G^T k_A G and the right-hand side -sum G^T k_A g0 of the active gaps."""
    matrix = sp.csr_matrix(stiffness)
    rhs = np.zeros(stiffness.shape[0])
    for gaps, closed in zip(gap_sets, active, strict=True):
        k = np.where(closed, gaps.stiffness, 0.0)
        matrix = matrix + gaps.matrix.T @ sp.diags(k) @ gaps.matrix
        rhs -= gaps.matrix.T @ (k * gaps.initial)
    return sp.csr_matrix(matrix), rhs


def solve_free(matrix: sp.csr_matrix, rhs: np.ndarray, free: np.ndarray, where: str) -> np.ndarray:
    """Solve matrix u = rhs with u = 0 on the dofs not in ``free``; SimulationError if singular."""
    u = np.zeros(rhs.size)
    reduced = matrix[free][:, free].tocsc()
    try:
        # The system is symmetric positive definite: no pivoting (with SuperLU's default partial
        # pivoting the penalty rows made a 2,000-node bat take minutes instead of a second).
        factor = spla.splu(reduced, permc_spec="MMD_AT_PLUS_A",
                           options={"SymmetricMode": True, "DiagPivotThresh": 0.0})  # fmt: skip
    except RuntimeError as exc:
        raise SimulationError(f"{where}: the stiffness with the closed contacts is singular "
                              f"({exc}); a rigid-body motion is unrestrained") from exc  # fmt: skip
    u[free] = factor.solve(rhs[free])
    if not np.all(np.isfinite(u)):
        raise SimulationError(f"{where}: the linear solve returned non-finite displacements")
    return u


def solve_static_contact(
    stiffness: sp.spmatrix,
    gap_sets: Sequence[PenaltyGaps],
    *,
    fixed_dofs: np.ndarray,
    loads: np.ndarray | None = None,
    initial_active: Sequence[np.ndarray] | None = None,
    closed_within: float = 0.0,
    hysteresis: float = 0.0,
    max_iterations: int = 30,
    where: str = "static contact",
) -> StaticContactSolution:
    """Frictionless penalty contact statics by active-set iteration (module docs).

    Args:
        stiffness: K, (n_dofs, n_dofs), SI.
        gap_sets: the gaps; bilateral sets are always active.
        fixed_dofs: dofs held at zero, (n_fixed,) int.
        loads: external nodal loads, (n_dofs,), N and N m; zero if None.
        initial_active: a first guess of the closed gaps (e.g. the previous load level's);
            default: the gaps with g0 <= ``closed_within``.
        closed_within: m; gaps this close start closed (surfaces that just touch at u = 0).
        hysteresis: m; a closed gap opens only when g > hysteresis, an open one closes only when
            g < -hysteresis. It stops pairs of neighbouring gaps from switching each other on and
            off for ever; the error it allows is a force of at most k * hysteresis per gap.
        max_iterations: linear solves allowed before giving up.
        where: names the analysis in error messages.

    Raises:
        SimulationError: singular system, or an active set that does not settle.
    """
    n_dofs = stiffness.shape[0]
    free = np.setdiff1d(np.arange(n_dofs), np.asarray(fixed_dofs, dtype=np.int64))
    f = np.zeros(n_dofs) if loads is None else np.asarray(loads, dtype=float)
    if initial_active is None:
        initial_active = [gaps.initial <= closed_within for gaps in gap_sets]
    active = [np.asarray(a, dtype=bool) | gaps.bilateral
              for a, gaps in zip(initial_active, gap_sets, strict=True)]  # fmt: skip
    for iteration in range(1, max_iterations + 1):
        matrix, rhs = penalty_system(stiffness, gap_sets, active)
        u = solve_free(matrix, rhs + f, free, where)
        gaps = [g.gaps(u) for g in gap_sets]
        updated = [np.where(a, g < hysteresis, g < -hysteresis) | s.bilateral
                   for g, a, s in zip(gaps, active, gap_sets, strict=True)]  # fmt: skip
        if all(np.array_equal(a, b) for a, b in zip(active, updated, strict=True)):
            forces = [s.forces(u) for s in gap_sets]
            return StaticContactSolution(u, gaps, forces, active, iteration)
        switching = sum(int(np.sum(a != b)) for a, b in zip(active, updated, strict=True))
        active = updated
    raise SimulationError(f"{where}: the contact active set did not settle in {max_iterations} "
                          f"solves ({switching} gaps still switching)")  # fmt: skip
