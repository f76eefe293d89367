"""The condensed penalty-contact solve against an exhaustive search over active sets.

A chain of nodes on springs (axial dof only) is pushed by a rigid flat moved towards it. The
frictionless penalty solution is the one active set A whose solve has g < 0 exactly on A: found
here by trying all 2^n sets (an independent, brute-force route to the same equations), and by
:class:`CondensedContact` with one factorisation and a small LCP.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp

from batball.contact.shell_contact import PenaltyGaps, gap_matrix
from batball.errors import SimulationError
from batball.solvers.static_contact import CondensedContact, solve_small_lcp

N_NODES = 7
#: Ground springs and chain springs, N/m; penalty per gap, N/m.
GROUND, CHAIN, PENALTY = 2.0e5, 5.0e5, 1.0e8


def chain_stiffness() -> tuple[sp.csr_matrix, np.ndarray]:
    """K over 6 dofs per node (only the x dof is elastic) and the fixed dofs (all others)."""
    k = np.diag(np.full(N_NODES, GROUND))
    for a in range(N_NODES - 1):
        k[a:a + 2, a:a + 2] += CHAIN * np.array([[1.0, -1.0], [-1.0, 1.0]])
    dofs = 6 * np.arange(N_NODES)
    full = sp.lil_matrix((6 * N_NODES, 6 * N_NODES))
    full[np.ix_(dofs, dofs)] = k
    fixed = np.setdiff1d(np.arange(6 * N_NODES), dofs)
    return sp.csr_matrix(full), fixed


def flat_gaps(initial: np.ndarray) -> PenaltyGaps:
    """A rigid flat beyond each node along +x: g = g0 - u_x (a node moving +x closes its gap;
    g0 - travel is the flat moved ``travel`` towards the nodes)."""
    normals = np.tile([-1.0, 0.0, 0.0], (N_NODES, 1))
    matrix = gap_matrix(np.arange(N_NODES)[:, None], np.ones((N_NODES, 1)), normals, N_NODES)
    return PenaltyGaps(matrix, initial, np.full(N_NODES, PENALTY))


def brute_force(stiffness: sp.csr_matrix, fixed: np.ndarray, gaps: PenaltyGaps) -> np.ndarray:
    """Displacements of the one consistent active set among all 2^n."""
    free = np.setdiff1d(np.arange(stiffness.shape[0]), fixed)
    g_matrix = gaps.matrix.toarray()[:, free]
    k_free = stiffness.toarray()[np.ix_(free, free)]
    found = []
    for pattern in itertools.product((False, True), repeat=gaps.n_gaps):
        closed = np.array(pattern)
        k = np.where(closed, gaps.stiffness, 0.0)
        u = np.linalg.solve(k_free + g_matrix.T @ (k[:, None] * g_matrix),
                            -g_matrix.T @ (k * gaps.initial))  # fmt: skip
        g = gaps.initial + g_matrix @ u
        if np.array_equal(g < 0.0, closed):
            found.append(u)
    assert len(found) == 1  # the penalty problem is strictly convex: one solution
    full = np.zeros(stiffness.shape[0])
    full[free] = found[0]
    return full


@pytest.mark.parametrize("travel", [0.5e-3, 2.0e-3, 6.0e-3])
def test_condensed_contact_matches_the_exhaustive_active_set(travel: float) -> None:
    """A curved flat (gaps 0 to 4.5 mm along the chain) pushed ``travel``: same displacements
    to 1e-9 relative, and one factorisation serves every travel."""
    stiffness, fixed = chain_stiffness()
    shape = 1e-3 * np.array([0.0, 0.2, 0.8, 1.8, 3.2, 4.0, 4.5])
    base = flat_gaps(shape)
    # Only the first three gaps are candidates: the solve must find the others itself.
    condensed = CondensedContact(stiffness, [base], fixed_dofs=fixed,
                                 closed=[np.zeros(N_NODES, bool)],
                                 candidates=[np.arange(N_NODES) < 3], where="chain")  # fmt: skip
    solution = condensed.solve([shape - travel])
    expected = brute_force(stiffness, fixed, base.shifted(-travel))
    np.testing.assert_allclose(solution.u, expected, rtol=1e-9, atol=1e-15)
    assert np.array_equal(solution.active[0], solution.gaps[0] < 0.0)


def test_small_lcp_solution_is_complementary() -> None:
    """w = q + M lambda >= 0, lambda >= 0, w . lambda = 0 for an SPD M (1e-12 of the scale)."""
    rng = np.random.default_rng(3)
    a = rng.normal(size=(12, 12))
    matrix = a @ a.T + 12 * np.eye(12)
    offset = rng.normal(size=12)
    lam = solve_small_lcp(matrix, offset, "test")
    w = offset + matrix @ lam
    assert lam.min() >= 0.0 and w.min() >= -1e-12
    assert abs(w @ lam) < 1e-10


def test_an_assumed_closed_gap_that_opens_is_released() -> None:
    """A gap assumed closed but not pressed must not act as a tension spring: it is made a
    candidate, K_s is factorised again, and the answer is the exhaustive one (all open: u = 0
    except what the one touching gap does)."""
    stiffness, fixed = chain_stiffness()
    shape = np.array([-0.2e-3, 1e-3, 1e-3, 2e-3, 2e-3, 3e-3, 3e-3])
    gaps = flat_gaps(shape)
    closed = np.arange(N_NODES) < 2  # gap 1 is 1 mm open: the assumption is wrong
    condensed = CondensedContact(stiffness, [gaps], fixed_dofs=fixed, closed=[closed],
                                 candidates=[np.zeros(N_NODES, bool)], where="chain")  # fmt: skip
    solution = condensed.solve([shape])
    np.testing.assert_allclose(solution.u, brute_force(stiffness, fixed, gaps), rtol=1e-9,
                               atol=1e-15)  # fmt: skip
    assert condensed.factorisations == 2
    assert solution.active[0].tolist() == [True] + [False] * (N_NODES - 1)


def test_a_lost_anchor_is_a_simulation_error() -> None:
    """Free nodes held only by gaps assumed closed, pulled off the flat by a load: once the gaps
    open the system left is singular, and the solve says so instead of returning NaNs."""
    _, fixed = chain_stiffness()
    floating = sp.csr_matrix((6 * N_NODES, 6 * N_NODES))  # no springs at all
    gaps = flat_gaps(np.full(N_NODES, 1e-3))
    condensed = CondensedContact(floating, [gaps], fixed_dofs=fixed,
                                 closed=[np.ones(N_NODES, bool)],
                                 candidates=[np.zeros(N_NODES, bool)], where="chain")  # fmt: skip
    pull = np.zeros(6 * N_NODES)
    pull[0::6] = -1.0  # N, away from the flat
    with pytest.raises(SimulationError, match="singular"):
        condensed.solve([np.full(N_NODES, 1e-3)], loads=pull)
