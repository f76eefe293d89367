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

One module (about 620 lines) because the frictionless active-set solve, the condensed contact
and the Coulomb iteration share the penalty-gap assembly and the factorisation reuse.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import nnls

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


@dataclass
class FactorReuse:
    """A factorisation the caller keeps between solves (nothing is cached behind its back).

    A later system that differs from the factorised one by at most ``max_changed`` gaps changing
    state (plus small changes of the gaps' normals, as a moved platen gives) is a low-rank update
    of it: conjugate gradients preconditioned by the old factor solve it in about
    ``max_changed`` iterations, each costing one pair of triangular solves instead of a new
    factorisation. If CG does not reach ``rtol`` the system is factorised afresh.

    Attributes:
        max_changed: most gaps whose state may differ from the factorised system's.
        rtol: CG relative residual.
        factor: the SuperLU factor of the last factorised reduced matrix.
        active: that system's closed gaps.
        free: that system's free dofs.
        factorisations: factorisations done so far.
        cg_solves: systems solved by CG so far.
    """

    max_changed: int = 40
    rtol: float = 1e-13
    factor: Any = None
    active: list[np.ndarray] | None = None
    free: np.ndarray | None = None
    factorisations: int = 0
    cg_solves: int = 0

    def changed(self, active: Sequence[np.ndarray], free: np.ndarray) -> int | None:
        """Gaps whose state differs from the factorised system's; None if not comparable."""
        if self.factor is None or self.active is None or self.free is None:
            return None
        if len(self.active) != len(active) or not np.array_equal(self.free, free):
            return None
        if any(a.shape != b.shape for a, b in zip(self.active, active, strict=True)):
            return None
        return sum(int(np.sum(a != b)) for a, b in zip(self.active, active, strict=True))


def factorise(reduced: sp.csc_matrix, where: str) -> Any:
    """SuperLU of a symmetric positive definite matrix; SimulationError if singular."""
    try:
        # The system is symmetric positive definite: no pivoting (with SuperLU's default partial
        # pivoting the penalty rows made a 2,000-node bat take minutes instead of a second).
        return spla.splu(reduced, permc_spec="MMD_AT_PLUS_A",
                         options={"SymmetricMode": True, "DiagPivotThresh": 0.0})  # fmt: skip
    except RuntimeError as exc:
        raise SimulationError(f"{where}: the stiffness with the closed contacts is singular "
                              f"({exc}); a rigid-body motion is unrestrained") from exc  # fmt: skip


def solve_by_reuse(reduced: sp.csc_matrix, rhs: np.ndarray, reuse: FactorReuse,
                   changed: int) -> np.ndarray | None:  # fmt: skip
    """CG preconditioned by the kept factor; None when it does not converge."""
    preconditioner = spla.LinearOperator(reduced.shape, matvec=reuse.factor.solve)
    x, info = spla.cg(reduced, rhs, rtol=reuse.rtol, atol=0.0, M=preconditioner,
                      maxiter=2 * changed + 10)  # fmt: skip
    if info != 0:
        return None
    reuse.cg_solves += 1
    return np.asarray(x)


def solve_free(matrix: sp.csr_matrix, rhs: np.ndarray, free: np.ndarray, where: str, *,
               active: Sequence[np.ndarray] | None = None,
               reuse: FactorReuse | None = None) -> np.ndarray:  # fmt: skip
    """Solve matrix u = rhs with u = 0 on the dofs not in ``free``; SimulationError if singular.

    With ``reuse`` (and the ``active`` gaps that made ``matrix``) a kept factor is tried first.
    """
    u = np.zeros(rhs.size)
    reduced = matrix[free][:, free].tocsc()
    solved = None
    if reuse is not None and active is not None:
        changed = reuse.changed(active, free)
        if changed is not None and changed <= reuse.max_changed:
            solved = solve_by_reuse(reduced, rhs[free], reuse, changed)
    if solved is None:
        factor = factorise(reduced, where)
        solved = factor.solve(rhs[free])
        if reuse is not None and active is not None:
            reuse.factor, reuse.active, reuse.free = factor, [a.copy() for a in active], free
            reuse.factorisations += 1
    u[free] = solved
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
    reuse: FactorReuse | None = None,
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
        max_iterations: linear solves allowed before giving up; after half of them every solve
            factorises afresh (no CG on a kept factor).
        where: names the analysis in error messages.
        reuse: a factorisation kept across calls (e.g. the load levels of one test).

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
        # Past half the allowed solves, factorise every time (a cycle may come from CG's error).
        kept = reuse if iteration <= max_iterations // 2 else None
        u = solve_free(matrix, rhs + f, free, where, active=active, reuse=kept)
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


def solve_small_lcp(matrix: np.ndarray, offset: np.ndarray, where: str) -> np.ndarray:
    """lambda >= 0 with w = offset + matrix lambda >= 0 and w . lambda = 0, matrix SPD (n, n).

    The LCP is the optimality condition of min lambda^T M lambda / 2 + q^T lambda over
    lambda >= 0; with M = L L^T that is the non-negative least-squares problem
    min |L^T lambda + L^-1 q| (Lawson and Hanson's active-set NNLS, scipy.optimize.nnls), solved
    after scaling M to a unit diagonal. Exact in finitely many steps: no cycling.
    """
    if offset.size == 0:
        return np.zeros(0)
    scale = 1.0 / np.sqrt(np.diag(matrix))
    scaled = matrix * np.outer(scale, scale)
    try:
        lower = np.linalg.cholesky(scaled)
    except np.linalg.LinAlgError as exc:
        raise SimulationError(f"{where}: the condensed contact compliance is not positive "
                              f"definite ({exc})") from exc  # fmt: skip
    target = -np.linalg.solve(lower, scale * offset)
    try:
        mu, _ = nnls(lower.T, target, maxiter=50 * offset.size)
    except RuntimeError as exc:
        raise SimulationError(f"{where}: the condensed contact problem did not converge "
                              f"({exc})") from exc  # fmt: skip
    return np.asarray(scale * mu)


class CondensedContact:
    """Penalty contact statics with a few unilateral gaps condensed onto a kept factorisation.

    For problems where most gaps have a known state (the barrel test: the insert's fit gaps stay
    closed, the platen gaps far from the patch stay open), K_s = K + sum G^T k G over the gaps
    assumed ``closed`` is factorised once. The ``candidate`` gaps (those that may switch) are
    condensed: with q = g0_c + G_c K_s^-1 r and the compliance C = G_c K_s^-1 G_c^T, their
    compressive forces solve the linear complementarity problem

        w = q + (C + diag(1/k)) lambda >= 0,  lambda >= 0,  w . lambda = 0

    (closed: g = -lambda / k; open: lambda = 0, g >= 0), a small dense SPD problem solved
    exactly (:func:`solve_small_lcp`). Each solve then checks the assumptions on the full
    solution: a gap assumed open that penetrates is added to the candidates (C extended); a gap
    assumed closed that opens is made a candidate and K_s factorised afresh. The result is the
    frictionless penalty solution :func:`solve_static_contact` iterates to, usually in one
    factorisation and n_candidates + 2 triangular solves, for any number of loads or offsets.
    """

    def __init__(self, stiffness: sp.spmatrix, gap_sets: Sequence[PenaltyGaps], *,
                 fixed_dofs: np.ndarray, closed: Sequence[np.ndarray],
                 candidates: Sequence[np.ndarray], where: str) -> None:  # fmt: skip
        self.gap_sets = list(gap_sets)
        self.where = where
        self.closed = [np.asarray(c, dtype=bool) | s.bilateral
                       for c, s in zip(closed, gap_sets, strict=True)]  # fmt: skip
        self.candidates = [np.asarray(c, dtype=bool) & ~a
                           for c, a in zip(candidates, self.closed, strict=True)]  # fmt: skip
        self.n_dofs = int(stiffness.shape[0])
        self.free = np.setdiff1d(np.arange(stiffness.shape[0]),
                                 np.asarray(fixed_dofs, dtype=np.int64))  # fmt: skip
        self.stiffness = stiffness
        self.factorisations = self.solves = 0
        self._factorise()

    def _factorise(self) -> None:
        """Factorise K_s with the gaps assumed closed, then condense the candidates."""
        matrix, _ = penalty_system(self.stiffness, self.gap_sets, self.closed)
        self.factor = factorise(matrix[self.free][:, self.free].tocsc(), self.where)
        self.factorisations += 1
        self._condense()

    def _candidate_rows(self) -> tuple[sp.csr_matrix, np.ndarray]:
        """G_c restricted to the free dofs, (n_c, n_free), and the candidates' penalties."""
        rows = sp.vstack([s.matrix[c] for s, c in zip(self.gap_sets, self.candidates,
                                                       strict=True)]).tocsc()  # fmt: skip
        penalties = np.concatenate([s.stiffness[c] for s, c in zip(self.gap_sets,
                                                                  self.candidates, strict=True)])
        return sp.csr_matrix(rows[:, self.free]), penalties

    def _condense(self, chunk: int = 32) -> None:
        """C = G_c K_s^-1 G_c^T, a block of right-hand sides at a time (bounded memory)."""
        rows, _ = self._candidate_rows()
        n_c = rows.shape[0]
        self.compliance = np.zeros((n_c, n_c))
        for start in range(0, n_c, chunk):
            block = rows[start:start + chunk].T.toarray()
            self.compliance[:, start:start + chunk] = rows @ self.factor.solve(block)
            self.solves += block.shape[1]
        self.compliance = 0.5 * (self.compliance + self.compliance.T)

    def _on_all_dofs(self, free_values: np.ndarray) -> np.ndarray:
        full = np.zeros(self.n_dofs)
        full[self.free] = free_values
        return full

    def _extend(self, sets: Sequence[PenaltyGaps], u: np.ndarray, tolerance: float) -> bool:
        """Check the assumed states on ``u``; True if any was wrong. A gap assumed open that
        penetrates becomes a candidate (C is extended); a unilateral gap assumed closed that opens
        becomes a candidate too, which changes K_s (factorised afresh)."""
        added = refactor = False
        for k, (gaps, closed) in enumerate(zip(sets, self.closed, strict=True)):
            g = gaps.gaps(u)
            opened = closed & (g > tolerance) & (not gaps.bilateral)
            missed = ~closed & ~self.candidates[k] & (g < -tolerance)
            if opened.any():
                self.closed[k] = closed & ~opened
                refactor = True
            if opened.any() or missed.any():
                self.candidates[k] = self.candidates[k] | opened | missed
                added = True
        if refactor:
            self._factorise()
        elif added:
            self._condense()
        return added

    def _solve(self, rhs: np.ndarray) -> np.ndarray:
        """K_s^-1 rhs with zeros on the fixed dofs, (n_dofs,)."""
        u = np.zeros(rhs.size)
        u[self.free] = self.factor.solve(rhs[self.free])
        self.solves += 1
        if not np.all(np.isfinite(u)):
            raise SimulationError(f"{self.where}: the linear solve returned non-finite values")
        return u

    def solve(self, initial: Sequence[np.ndarray], *, loads: np.ndarray | None = None,
              tolerance: float = 1e-12, max_rounds: int = 5) -> StaticContactSolution:  # fmt: skip
        """The contact state for the gap offsets ``initial`` (g0 of each set, m) and ``loads``.

        Args:
            initial: g0 of each gap set, list of (n_gaps,), m (the sets' G and k are kept).
            loads: external nodal loads, (n_dofs,), N and N m; zero if None.
            tolerance: m; a gap assumed open may penetrate this much, one assumed closed may
                open this much, before the assumption counts as broken.
            max_rounds: corrections of the assumed states allowed.
        """
        sets = [replace(s, initial=np.asarray(g0, dtype=float))
                for s, g0 in zip(self.gap_sets, initial, strict=True)]  # fmt: skip
        for _ in range(max_rounds + 1):
            rhs = np.zeros(self.n_dofs) if loads is None else np.array(loads, dtype=float)
            for gaps, closed in zip(sets, self.closed, strict=True):
                rhs -= gaps.matrix.T @ (np.where(closed, gaps.stiffness, 0.0) * gaps.initial)
            u = self._solve(rhs)
            rows, penalties = self._candidate_rows()
            start = np.concatenate([g.initial[c] for g, c in zip(sets, self.candidates,
                                                                 strict=True)])  # fmt: skip
            offset = start + rows @ u[self.free]
            lam = solve_small_lcp(self.compliance + np.diag(1.0 / penalties), offset, self.where)
            # The candidates' contact forces G_c^T lambda on the free dofs.
            u = self._solve(rhs + self._on_all_dofs(rows.T @ lam))
            if not self._extend(sets, u, tolerance):
                values = [g.gaps(u) for g in sets]
                active = [a | (c & (gap < 0.0))
                          for a, c, gap in zip(self.closed, self.candidates, values, strict=True)]
                forces = [g.forces(u) for g in sets]
                return StaticContactSolution(u, values, forces, active, self.solves)
        raise SimulationError(f"{self.where}: the assumed contact states were corrected "
                              f"{max_rounds} times and are still wrong")


def solve_with_kept_factor(
    matrix: sp.csr_matrix, rhs: np.ndarray, free: np.ndarray, kept: FactorReuse, where: str,
    *, max_cg: int = 40,
) -> np.ndarray:
    """matrix u = rhs with u = 0 off ``free``, by CG preconditioned by ``kept``'s factor of a
    nearby matrix (at most ``max_cg`` iterations to ``kept.rtol``), else a new factorisation
    that ``kept`` then holds."""
    u = np.zeros(rhs.size)
    reduced = matrix[free][:, free].tocsc()
    solved = None
    if kept.factor is not None and kept.free is not None and np.array_equal(kept.free, free):
        preconditioner = spla.LinearOperator(reduced.shape, matvec=kept.factor.solve)
        x, info = spla.cg(reduced, rhs[free], rtol=kept.rtol, atol=0.0, M=preconditioner,
                          maxiter=max_cg)  # fmt: skip
        if info == 0:
            solved, kept.cg_solves = np.asarray(x), kept.cg_solves + 1
    if solved is None:
        kept.factor, kept.free = factorise(reduced, where), free
        kept.factorisations += 1
        solved = kept.factor.solve(rhs[free])
    u[free] = solved
    if not np.all(np.isfinite(u)):
        raise SimulationError(f"{where}: the linear solve returned non-finite displacements")
    return u


#: Halvings of a Newton step allowed while the out-of-balance force grows.
MAX_HALVINGS = 8
#: Newton iterations of a frictional step before it turns to the secant tangent.
NEWTON_ITERATIONS = 12


@dataclass(frozen=True)
class CoulombFriction:
    """Coulomb friction on the pairs of one normal gap set (small displacements).

    Each pair's slips s = T_d u along fixed tangent directions d (the rows of ``slips``, the
    master's point minus the slave's, as the normal gap's G) carry a traction tau (n_pairs, 2)
    [N]: while the pair sticks, tau = k_t (s - xi) with xi the slip so far (the anchor), a
    spring; when |k_t (s - xi)| would exceed mu times the normal gap's compressive force, the
    pair slips and tau is that limit along the trial direction (a radial return, exact for a
    load step whose slip keeps its direction). The traction's work is tau . s, so it enters the
    equilibrium as the forces T_d^T tau_d.

    Attributes:
        slips: the tangent rows T_d, each (n_pairs, n_dofs).
        normal_sets: where each pair's normal force comes from, in blocks of pairs: block b's
            pairs take the summed forces of the gap sets listed in ``normal_sets[b]`` (indices
            among the solve's gap sets, of equal sizes; a contact split into sets with
            complementary penalties is listed whole), the blocks' pairs in order.
        stiffness: stick penalty k_t per pair, (n_pairs,), N/m.
        mu: friction coefficient (>= 0), one for all pairs or one per pair (n_pairs,).
        initial: s0, the slips at u = 0 (n_pairs, n_directions) [m], or None for none: a
            prescribed motion of a rigid master (a platen moved along the load slides over a
            point whose normal is tilted from the load).
    """

    slips: tuple[sp.csr_matrix, ...]
    normal_sets: tuple[tuple[int, ...], ...]
    stiffness: np.ndarray
    mu: float | np.ndarray
    initial: np.ndarray | None = None

    def slip(self, u: np.ndarray) -> np.ndarray:
        """s = s0 + T u of each pair and direction, (n_pairs, n_directions), m."""
        s = np.column_stack([t @ u for t in self.slips])
        return s if self.initial is None else s + self.initial

    def normal_forces(self, gap_sets: Sequence[PenaltyGaps], u: np.ndarray) -> np.ndarray:
        """Each pair's compressive normal force, (n_pairs,), N (tension counts as 0)."""
        blocks = [sum(gap_sets[i].forces(u) for i in block) for block in self.normal_sets]
        return np.maximum(np.concatenate(blocks), 0.0)


@dataclass(frozen=True)
class FrictionState:
    """The converged frictional step.

    Attributes:
        solution: the normal contact state and displacements.
        traction: tau, (n_pairs, n_directions), N.
        anchor: xi after the step, (n_pairs, n_directions), m (the next step's start).
        stick: pairs sticking, (n_pairs,) bool.
    """

    solution: StaticContactSolution
    traction: np.ndarray
    anchor: np.ndarray
    stick: np.ndarray


@dataclass(frozen=True)
class FrictionIterate:
    """One iterate of :func:`solve_frictional_step` at displacements u.

    Attributes:
        gaps, closed: each normal set's gaps [m] and closed flags.
        stick: pairs within the Coulomb limit; traction: (n_pairs, n_dir) [N].
        tangent, secant: (n_pairs, n_dir, n_dir) pair stiffnesses [N/m], Newton's and the
            secant's.
        out: the out-of-balance force on the free dofs, (n_dofs,) [N]; norm: its 2-norm [N];
        scale: the largest load or penalty force, for the tolerance [N].
    """

    gaps: list[np.ndarray]
    closed: list[np.ndarray]
    stick: np.ndarray
    traction: np.ndarray
    tangent: np.ndarray
    secant: np.ndarray
    out: np.ndarray
    norm: float
    scale: float


@dataclass(frozen=True)
class FrictionProblem:
    """One frictional load step's data (:func:`solve_frictional_step`): K, the normal gap sets,
    the friction, the step's anchor xi (n_pairs, n_dir) [m], the loads f (n_dofs,) [N], the
    free dofs and the gaps' hysteresis [m]."""

    stiffness: sp.spmatrix
    gap_sets: list[PenaltyGaps]
    friction: CoulombFriction
    anchor: np.ndarray
    loads: np.ndarray
    free: np.ndarray
    hysteresis: float

    def iterate(self, u: np.ndarray, before: Sequence[np.ndarray]) -> FrictionIterate:
        """The contact state, tractions, tangents and out-of-balance force at ``u``, the gaps
        closed ``before`` opening only past the hysteresis (and the open ones closing only
        below minus it: a gap at the kink of its penalty would flip for ever)."""
        h, friction, k_t = self.hysteresis, self.friction, self.friction.stiffness
        n_dir = len(friction.slips)
        gaps = [g.gaps(u) for g in self.gap_sets]
        closed = [np.where(b, g < h, g < -h) | s.bilateral
                  for g, b, s in zip(gaps, before, self.gap_sets, strict=True)]  # fmt: skip
        limit = friction.mu * friction.normal_forces(self.gap_sets, u)
        trial = k_t[:, None] * (friction.slip(u) - self.anchor)
        size = np.linalg.norm(trial, axis=1)
        sticks = size <= limit
        direction = trial / np.maximum(size, 1e-300)[:, None]
        traction = np.where(sticks[:, None], trial, limit[:, None] * direction)
        secant = np.where(sticks, k_t, k_t * limit / np.maximum(size, 1e-300))
        slipping = np.where(sticks, 0.0, 1.0)[:, None, None]
        tangent = secant[:, None, None] * (
            np.eye(n_dir)[None] - slipping * direction[:, :, None] * direction[:, None, :])
        force = self.stiffness @ u - self.loads  # K u + penalties + T^T tau - f
        scale = float(np.abs(self.loads).max(initial=0.0))
        for g, s, c in zip(gaps, self.gap_sets, closed, strict=True):
            k = np.where(c, s.stiffness, 0.0)
            force += s.matrix.T @ (k * g)
            scale = max(scale, float(np.abs(k * g).max(initial=0.0)))
        for d, rows in enumerate(friction.slips):
            force += rows.T @ traction[:, d]
        out = np.zeros(u.size)
        out[self.free] = force[self.free]
        return FrictionIterate(gaps, closed, sticks, traction, tangent,
                               secant[:, None, None] * np.eye(n_dir)[None], out,
                               float(np.linalg.norm(out)), scale)  # fmt: skip

    def tangent_matrix(self, now: FrictionIterate, newton: bool) -> sp.csr_matrix:
        """K, the closed gaps' penalties and the pairs' Newton (or secant) stiffnesses."""
        matrix, _ = penalty_system(self.stiffness, self.gap_sets, now.closed)
        pairs = now.tangent if newton else now.secant
        for d, rows_d in enumerate(self.friction.slips):
            for e, rows_e in enumerate(self.friction.slips):
                matrix = matrix + rows_d.T @ sp.diags(pairs[:, d, e]) @ rows_e
        return sp.csr_matrix(matrix)


def solve_frictional_step(
    stiffness: sp.spmatrix,
    gap_sets: Sequence[PenaltyGaps],
    friction: CoulombFriction,
    anchor: np.ndarray,
    *,
    fixed_dofs: np.ndarray,
    loads: np.ndarray | None = None,
    initial_active: Sequence[np.ndarray] | None = None,
    hysteresis: float = 1e-10,
    rtol: float = 1e-9,
    max_iterations: int = 150,
    where: str = "frictional contact",
    reuse: FactorReuse | None = None,
) -> FrictionState:
    """One load step of penalty contact with Coulomb friction (:class:`CoulombFriction`), by
    Newton's method on the out-of-balance forces.

    Each iteration takes the normal active set and every pair's state from the current
    displacements: the trial traction k_t (s - xi) from the anchor ``anchor`` of the step's
    start; a pair sticks if it is within mu f_n, else it slips with the traction returned to
    the limit along the trial's direction d (radial return). The tangent is the stick spring
    k_t for a sticking pair and (mu f_n / |s - xi|)(I - d d^T) for a slipping one (no stiffness
    along its slip; the change of the limit with the normal force is left out of the tangent,
    not of the residual). The step is halved while the out-of-balance force grows, and after
    ``NEWTON_ITERATIONS`` the slipping pairs take their secant mu f_n / |s - xi| in every
    direction instead (a pair on the stick-slip boundary can make Newton cycle). A normal gap
    opens or closes only past ``hysteresis`` (m) from its state. Converged when the sets no
    longer change and the out-of-balance force is below ``rtol`` of the largest of the loads
    and the penalty forces; the step's slips are then the next anchor. Solves: CG on the last
    factor (``reuse``), a new factorisation when CG stalls. Other schemes tried:
    docs/notes/barrel.md.

    Raises:
        SimulationError: singular system, or no convergence in ``max_iterations`` solves.
    """
    n_dofs = stiffness.shape[0]
    free = np.setdiff1d(np.arange(n_dofs), np.asarray(fixed_dofs, dtype=np.int64))
    f = np.zeros(n_dofs) if loads is None else np.asarray(loads, dtype=float)
    if initial_active is None:
        initial_active = [gaps.initial <= 0.0 for gaps in gap_sets]
    active = [np.asarray(a, dtype=bool) | gaps.bilateral
              for a, gaps in zip(initial_active, gap_sets, strict=True)]  # fmt: skip
    k_t = friction.stiffness
    residual = np.inf
    kept = FactorReuse() if reuse is None else reuse
    problem = FrictionProblem(stiffness, list(gap_sets), friction, anchor, f, free, hysteresis)

    # the elastic predictor: every pair sticks at its anchor, the active set from the guess
    matrix, rhs = penalty_system(stiffness, gap_sets, active)
    held = anchor if friction.initial is None else anchor - friction.initial
    for d, rows in enumerate(friction.slips):
        matrix = matrix + rows.T @ sp.diags(k_t) @ rows
        rhs += rows.T @ (k_t * held[:, d])
    u = solve_with_kept_factor(sp.csr_matrix(matrix), rhs + f, free, kept, where)
    now = problem.iterate(u, active)
    for iteration in range(1, max_iterations + 1):
        newton = iteration <= NEWTON_ITERATIONS  # then the secant, which does not cycle
        du = solve_with_kept_factor(problem.tangent_matrix(now, newton), -now.out, free, kept,
                                    where)  # fmt: skip
        step = 1.0
        for _ in range(MAX_HALVINGS):  # backtrack while the out-of-balance force grows
            trial_state = problem.iterate(u + step * du, now.closed)
            if trial_state.norm < now.norm:
                break
            step *= 0.5
        previous, u, now = now, u + step * du, trial_state
        settled = (all(np.array_equal(a, b)
                       for a, b in zip(previous.closed, now.closed, strict=True))
                   and np.array_equal(previous.stick, now.stick))  # fmt: skip
        residual = float(np.abs(now.out).max())
        if settled and residual <= rtol * max(now.scale, 1e-300):
            forces = [s.forces(u) for s in gap_sets]
            traction, stick = now.traction, now.stick
            slipped = friction.slip(u) - traction / k_t[:, None]
            anchor_out = np.where(stick[:, None], anchor, slipped)
            solution = StaticContactSolution(u, now.gaps, forces, now.closed, iteration)
            return FrictionState(solution, traction, anchor_out, stick)
    raise SimulationError(f"{where}: friction did not converge in {max_iterations} solves "
                          f"(out-of-balance force {residual:.3g} N)")  # fmt: skip
