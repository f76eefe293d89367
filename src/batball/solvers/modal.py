"""Free-free modal analysis: K phi = omega^2 M phi by shift-invert Lanczos (ARPACK via SciPy).

With no supports K is singular (six rigid-body modes), so the shift sigma is negative: K - sigma M
is then positive definite and factorisable, and the modes nearest sigma (the rigid ones and the
lowest flexible ones) converge first (docs/physics.md section 5.3; SciPy ``eigsh`` shift-invert).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

#: Rigid-body modes of an unsupported body in space.
N_RIGID_BODY_MODES = 6


@dataclass(frozen=True)
class ModalResult:
    """Modes of a free-free structure, ascending.

    Attributes:
        frequencies: f = sign(lambda) sqrt(|lambda|) / 2 pi, shape (n_modes,), Hz (rigid-body
            modes near zero, possibly slightly negative from round-off).
        shapes: mass-normalised mode shapes, shape (n_dofs, n_modes).
        rigid: which modes are rigid-body modes, shape (n_modes,), bool.
    """

    frequencies: np.ndarray
    shapes: np.ndarray
    rigid: np.ndarray

    @property
    def n_rigid(self) -> int:
        """Number of rigid-body modes found."""
        return int(self.rigid.sum())

    @property
    def flexible_frequencies(self) -> np.ndarray:
        """Frequencies of the flexible modes, ascending, Hz."""
        return self.frequencies[~self.rigid]


def free_free_modes(
    stiffness: sp.spmatrix,
    mass: sp.spmatrix,
    *,
    n_modes: int = 30,
    shift_hz: float = 1.0,
    rigid_fraction: float = 0.01,
    n_zero_modes: int = N_RIGID_BODY_MODES,
) -> ModalResult:
    """The lowest ``n_modes`` modes of an unsupported structure.

    Args:
        stiffness: K, symmetric positive semi-definite, (n_dofs, n_dofs), SI.
        mass: M, symmetric positive definite, same shape, SI.
        n_modes: modes to compute (rigid-body modes included).
        shift_hz: |sigma| = (2 pi shift_hz)^2 with sigma < 0; a fraction of the first flexible
            frequency is a good value.
        rigid_fraction: a mode is rigid when |f| < rigid_fraction times the lowest frequency
            above the first ``n_zero_modes`` (the first flexible one when that many zero modes
            are present).
        n_zero_modes: zero-frequency modes expected: six rigid-body modes, plus any mechanism
            the model has on purpose (a frictionless insert sliding and spinning in its barrel).

    Returns:
        The modes, ascending.
    """
    sigma = -((2.0 * np.pi * shift_hz) ** 2)
    # A seeded start rather than ARPACK's random one: the same model gives the same modes, bit
    # for bit, run after run (fits replay stored evaluations; ARPACK's own start moved the hoop
    # frequencies by about 5e-7). Random, not ones: a symmetric start is slow to find
    # antisymmetric modes.
    start = np.random.default_rng(0).standard_normal(stiffness.shape[0])
    values, vectors = eigsh(
        sp.csc_matrix(stiffness), k=n_modes, M=sp.csc_matrix(mass), sigma=sigma, which="LM",
        v0=start,
    )
    order = np.argsort(values)
    values, vectors = values[order], vectors[:, order]
    frequencies = np.sign(values) * np.sqrt(np.abs(values)) / (2.0 * np.pi)
    reference = abs(frequencies[min(n_zero_modes, n_modes - 1)])
    rigid = np.abs(frequencies) < rigid_fraction * reference
    return ModalResult(frequencies=frequencies, shapes=vectors, rigid=rigid)
