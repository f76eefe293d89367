"""Generalised viscoelastic solid with N Prony terms, LS-DYNA ``*MAT_GENERAL_VISCOELASTIC`` style
(MAT_076 with shear terms only, no temperature shift): elastic bulk K, long-time shear G_inf and
N pairs (G_i, beta_i):

    G(t) = G_inf + sum_i G_i exp(-beta_i t),   G0 = G(0) = G_inf + sum_i G_i.

Each term is a Maxwell branch updated with the exact-exponential recursion of MAT_006
(``docs/physics.md`` section 1.3), so N = 1 is MAT_006 with G0 - G_inf = G_1.
Source: LS-DYNA Keyword Manual, MAT_076 (fields GI, BETAI as in
``ansys/pydyna:.../auto/mat/mat_general_viscoelastic.py``); docs/physics.md section 1.1.

Kernel constants, shape (2 N + 2,): K, G0, G_inf, beta_1, then (G_i, beta_i) for i = 2..N.
For N = 1 that is MAT_006's (K, G0, G_inf, beta) exactly, and the hex kernel reads both the same
way; the history array ``h`` of a model with N-term materials has 6 N columns (term-major).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from batball.materials.base import MaterialLaw
from batball.materials.parameters import Parameter

#: Most Prony terms the hex kernel is compiled for (LS-DYNA's MAT_076 takes 6).
MAX_PRONY_TERMS = 3


def _prony_parameters(n_terms: int) -> tuple[Parameter, ...]:
    """K, G_inf and the N (G_i, beta_i) declarations."""
    parameters = [
        Parameter(
            "bulk_modulus", "pressure", "psi", 0.0, 1e13, "elastic bulk modulus K", "BULK",
            log_scale=True,
        ),
        Parameter(
            "g_inf", "pressure", "psi", 0.0, 1e12, "long-time (infinite) shear modulus G_inf",
            "GI(beta=0)", lower_inclusive=True, log_scale=True,
        ),
    ]  # fmt: skip
    for i in range(1, n_terms + 1):
        parameters += [
            Parameter(
                f"g{i}", "pressure", "psi", 0.0, 1e12, f"shear modulus of Prony term {i}",
                f"GI{i}", lower_inclusive=True, log_scale=True,
            ),
            Parameter(
                f"beta{i}", "frequency", "1/s", 0.0, 1e9, f"decay constant of Prony term {i}",
                f"BETAI{i}", log_scale=True,
            ),
        ]  # fmt: skip
    return tuple(parameters)


@dataclass(frozen=True)
class PronyLaw(MaterialLaw):
    """An N-term Prony-series shear relaxation with elastic bulk."""

    n_terms: int = 1

    def kernel_constants(self, values: Mapping[str, float]) -> np.ndarray:
        """(2 N + 2,): K, G0 = G_inf + sum G_i, G_inf [Pa], beta_1 [1/s], (G_i [Pa], beta_i)."""
        moduli = [values[f"g{i}"] for i in range(1, self.n_terms + 1)]
        rates = [values[f"beta{i}"] for i in range(1, self.n_terms + 1)]
        g0 = values["g_inf"] + sum(moduli)
        extra = [x for pair in zip(moduli[1:], rates[1:], strict=True) for x in pair]
        return np.array(
            [values["bulk_modulus"], g0, values["g_inf"], rates[0], *extra], dtype=np.float64
        )


def make_prony_law(n_terms: int) -> PronyLaw:
    """The registered ``prony<N>`` law."""
    if not 1 <= n_terms <= MAX_PRONY_TERMS:
        raise ValueError(f"n_terms must be 1..{MAX_PRONY_TERMS}, got {n_terms}")
    return PronyLaw(
        name=f"prony{n_terms}",
        title=f"generalised viscoelastic, {n_terms} Prony terms (LS-DYNA MAT_076 shear terms)",
        lsdyna_keyword="*MAT_GENERAL_VISCOELASTIC",
        parameters=_prony_parameters(n_terms),
        n_terms=n_terms,
    )


PRONY_LAWS: tuple[PronyLaw, ...] = tuple(make_prony_law(n) for n in range(1, MAX_PRONY_TERMS + 1))


def relaxation_modulus(values: Mapping[str, float], time: np.ndarray) -> np.ndarray:
    """G(t) = G_inf + sum_i G_i exp(-beta_i t) [Pa] at ``time`` (n,) [s]."""
    t = np.asarray(time, dtype=np.float64)
    g = np.full_like(t, values["g_inf"])
    i = 1
    while f"g{i}" in values:
        g += values[f"g{i}"] * np.exp(-values[f"beta{i}"] * t)
        i += 1
    return g


def prony_from_mat006(values: Mapping[str, float], *, n_terms: int) -> dict[str, float]:
    """A starting N-term set near a MAT_006 material: term 1 carries 80 % of G0 - G_inf at
    beta, terms 2 and 3 carry 10 % each at beta / 10 and 10 beta (so that each term starts
    with a non-zero modulus, which a log-scale search needs)."""
    relaxing = values["g0"] - values["g_inf"]
    shares = (1.0,) if n_terms == 1 else (0.8, 0.1, 0.1)[:n_terms]
    if n_terms == 2:
        shares = (0.9, 0.1)
    rates = (1.0, 0.1, 10.0)
    out = {"bulk_modulus": values["bulk_modulus"], "g_inf": values["g_inf"]}
    for i, (share, rate) in enumerate(zip(shares, rates, strict=False), start=1):
        out[f"g{i}"] = share * relaxing
        out[f"beta{i}"] = rate * values["beta"]
    return out
