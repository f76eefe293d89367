"""The DMA route: a Prony shear relaxation fitted to storage and loss moduli.

A DMA (dynamic mechanical analysis) CSV gives, per row, a frequency and the storage and loss
moduli (or the storage modulus and tan delta), units in the column names::

    frequency_hz,storage_psi,loss_psi
    10,14210.5,1203.7
    ...

Accepted column names (case-insensitive): ``frequency_<hz|khz|rad_s>``,
``storage_<pa|kpa|mpa|gpa|psi|ksi>`` and either ``loss_<same units>`` or ``tan_delta``.
Whether the moduli are shear (G', G'') or tensile (E', E'') is said by the caller
(``modulus="shear"`` or ``"tensile"``); tensile moduli are converted to shear before the fit
(:func:`tensile_to_shear`).

Time-frequency conversion. The Prony relaxation G(t) = G_inf + sum_i G_i exp(-t / tau_i),
tau_i = 1 / beta_i, has the complex modulus G*(w) = i w int_0^inf G(t) exp(-i w t) dt, i.e.

    G'(w)  = G_inf + sum_i G_i w^2 tau_i^2 / (1 + w^2 tau_i^2)
    G''(w) =         sum_i G_i w tau_i     / (1 + w^2 tau_i^2),       w = 2 pi f [rad/s],

(J. Bergström, "Calculation of Prony series parameters from dynamic frequency data",
PolymerFEM 2005, eqs. 5-6; the ABAQUS theory manual's frequency-domain viscoelasticity). Both
are linear in (G_inf, G_1..G_N) for fixed tau_i: with the tau_i on a log-spaced grid over the
data's 1/w range the moduli follow in closed form from a non-negative linear least-squares
problem (``scipy.optimize.nnls``: every G >= 0, as the material's passivity needs); the tau_i are
then refined by a bounded nonlinear least-squares search over log tau with the moduli solved by
NNLS at each step (variable projection). Residuals are relative (each divided by the measured
|G*|), so that storage and loss weigh alike over the decades of frequency.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from batball.errors import SpecError
from batball.specs import BallSpec, MaterialSpec
from batball.units import PSI

#: Unit suffixes of the CSV columns (lower case) and their SI factors.
PRESSURE_UNITS: dict[str, float] = {
    "pa": 1.0,
    "kpa": 1e3,
    "mpa": 1e6,
    "gpa": 1e9,
    "psi": PSI,
    "ksi": 6894757.293168361,  # 1000 psi to the nearest double (1e3 * PSI is one ulp low)
}
#: Frequency suffixes -> factor to angular frequency [rad/s].
FREQUENCY_UNITS: dict[str, float] = {"hz": 2.0 * math.pi, "khz": 2e3 * math.pi, "rad_s": 1.0}

MODULUS_KINDS = ("shear", "tensile")


@dataclass(frozen=True)
class DmaData:
    """Complex shear modulus measurements.

    Attributes:
        omega: angular frequencies [rad/s], (n,), increasing.
        storage: G'(omega) [Pa], (n,); loss: G''(omega) [Pa], (n,).
    """

    omega: np.ndarray
    storage: np.ndarray
    loss: np.ndarray

    @property
    def frequency_hz(self) -> np.ndarray:
        """f = omega / 2 pi [Hz]."""
        return self.omega / (2.0 * math.pi)


def _column_unit(header: Sequence[str], stem: str, units: Mapping[str, float]) -> tuple[str, float]:
    """The column named ``<stem>_<unit>`` and its unit's factor; SpecError naming the column."""
    for name in header:
        key = name.strip().lower()
        if key.startswith(stem + "_") and key != "tan_delta":
            suffix = key[len(stem) + 1 :]
            if suffix not in units:
                raise SpecError(f"dma.{name.strip()}", suffix, f"a unit among {', '.join(units)}")
            return name, units[suffix]
    raise SpecError(f"dma.{stem}", "missing", f"a column {stem}_<unit> ({', '.join(units)})")


def _number(text: str | None, field: str) -> float:
    """A finite number from a CSV cell."""
    try:
        value = float(text if text is not None else "")
    except ValueError:
        raise SpecError(field, text, "a number") from None
    if not math.isfinite(value):
        raise SpecError(field, text, "a finite number")
    return value


def load_dma_csv(
    path: str | Path,
    *,
    modulus: str,
    poisson_ratio: float | None = None,
    bulk_modulus: float | None = None,
) -> DmaData:
    """Read a DMA CSV (see the module docstring) as shear moduli.

    Args:
        modulus: ``"shear"`` (G', G'') or ``"tensile"`` (E', E''); tensile needs
            ``poisson_ratio`` or ``bulk_modulus`` [Pa] for :func:`tensile_to_shear`.

    Raises:
        SpecError: a missing file, a missing column or one without a known unit (naming it), a
            non-numeric cell, a non-positive frequency or storage modulus, a negative loss.
    """
    if modulus not in MODULUS_KINDS:
        raise SpecError("dma-modulus", modulus, "shear or tensile")
    path = Path(path)
    if not path.is_file():
        raise SpecError("dma", str(path), "an existing CSV file")
    with path.open(newline="", encoding="utf-8") as handle:
        reader = csv.DictReader(handle)
        header = list(reader.fieldnames or [])
        rows = list(reader)
    f_col, f_factor = _column_unit(header, "frequency", FREQUENCY_UNITS)
    s_col, s_factor = _column_unit(header, "storage", PRESSURE_UNITS)
    tan_col = next((h for h in header if h.strip().lower() == "tan_delta"), None)
    loss_col, l_factor = (
        (tan_col, 1.0) if tan_col is not None else _column_unit(header, "loss", PRESSURE_UNITS)
    )
    if len(rows) < 2:
        raise SpecError("dma", str(path), "at least two rows of data")
    table = np.array(
        [
            [_number(row.get(c), f"dma[{i}].{c.strip()}") for c in (f_col, s_col, loss_col)]
            for i, row in enumerate(rows)
        ]
    )
    omega, storage = table[:, 0] * f_factor, table[:, 1] * s_factor
    loss = table[:, 2] * storage if tan_col is not None else table[:, 2] * l_factor
    for column, ok in ((f_col, omega > 0), (s_col, storage > 0), (loss_col, loss >= 0)):
        if not ok.all():
            bad = int(np.flatnonzero(~ok)[0])
            raise SpecError(f"dma[{bad}].{column.strip()}", rows[bad][column], "a positive value")
    order = np.argsort(omega)
    data = DmaData(omega[order], storage[order], loss[order])
    if modulus == "tensile":
        return tensile_to_shear(data, poisson_ratio=poisson_ratio, bulk_modulus=bulk_modulus)
    return data


def tensile_to_shear(
    data: DmaData, *, poisson_ratio: float | None = None, bulk_modulus: float | None = None
) -> DmaData:
    """E*(w) -> G*(w) for an isotropic material.

    With an elastic bulk modulus K (the model's own assumption: MAT_006/MAT_076 relax in shear
    only), E = 9 K G / (3 K + G) inverts exactly in complex arithmetic to
    G* = 3 K E* / (9 K - E*). With a Poisson's ratio instead, G* = E* / (2 (1 + nu)) (a constant,
    real nu: the usual approximation when K is not known). K wins when both are given.

    Raises:
        SpecError: neither given, nu outside (-1, 0.5), K <= 0 or K not above E'/9 at some
            frequency (no positive G).
    """
    e_star = data.storage + 1j * data.loss
    if bulk_modulus is not None:
        if not bulk_modulus > 0.0:
            raise SpecError("bulk-modulus", bulk_modulus, "a positive bulk modulus")
        g_star = 3.0 * bulk_modulus * e_star / (9.0 * bulk_modulus - e_star)
        if not (g_star.real > 0).all():
            raise SpecError("bulk-modulus", bulk_modulus, "K > E'/9 at every frequency")
    elif poisson_ratio is not None:
        if not -1.0 < poisson_ratio < 0.5:
            raise SpecError("poisson-ratio", poisson_ratio, "-1 < nu < 0.5")
        g_star = e_star / (2.0 * (1.0 + poisson_ratio))
    else:
        raise SpecError("dma-modulus", "tensile", "a Poisson's ratio or a bulk modulus with it")
    return DmaData(data.omega, g_star.real, g_star.imag)


def prony_moduli(omega: np.ndarray, g_inf: float, moduli: np.ndarray, tau: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """(G'(w), G''(w)) [Pa] of a Prony series (module docstring; Bergström 2005 eqs. 5-6)."""
    wt = np.outer(np.asarray(omega, dtype=np.float64), np.asarray(tau, dtype=np.float64))
    storage = g_inf + (moduli * wt**2 / (1.0 + wt**2)).sum(axis=1)
    loss = (moduli * wt / (1.0 + wt**2)).sum(axis=1)
    return storage, loss


def _design(data: DmaData, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The relative-residual linear system A x = b for x = (G_inf, G_1..G_N)."""
    wt = np.outer(data.omega, tau)
    scale = np.hypot(data.storage, data.loss)
    storage_rows = np.column_stack([np.ones_like(data.omega), wt**2 / (1.0 + wt**2)])
    loss_rows = np.column_stack([np.zeros_like(data.omega), wt / (1.0 + wt**2)])
    a = np.vstack([storage_rows / scale[:, None], loss_rows / scale[:, None]])
    b = np.concatenate([data.storage / scale, data.loss / scale])
    return a, b


def solve_moduli(data: DmaData, tau: np.ndarray) -> tuple[np.ndarray, float]:
    """Closed-form step: (G_inf, G_1..G_N) >= 0 for fixed tau by NNLS, and the residual norm."""
    from scipy.optimize import nnls

    a, b = _design(data, tau)
    column = np.linalg.norm(a, axis=0)
    column[column == 0.0] = 1.0
    x, norm = nnls(a / column, b)
    return x / column, float(norm)


@dataclass(frozen=True)
class PronyFit:
    """A fitted N-term Prony shear relaxation.

    Attributes:
        g_inf: G_inf [Pa]; moduli: G_i [Pa] (N,); tau: tau_i [s] (N,), increasing.
        rms_relative: root-mean-square of the relative residuals (storage and loss rows).
    """

    g_inf: float
    moduli: np.ndarray
    tau: np.ndarray
    rms_relative: float

    @property
    def betas(self) -> np.ndarray:
        """beta_i = 1 / tau_i [1/s] (LS-DYNA's BETAI)."""
        return 1.0 / self.tau

    def values(self, bulk_modulus: float) -> dict[str, float]:
        """The ``prony<N>`` law's parameter values (SI) with the given bulk modulus."""
        out = {"bulk_modulus": bulk_modulus, "g_inf": self.g_inf}
        for i, (g, tau) in enumerate(zip(self.moduli, self.tau, strict=True), start=1):
            out[f"g{i}"] = float(g)
            out[f"beta{i}"] = float(1.0 / tau)
        return out


def fit_prony(data: DmaData, n_terms: int = 3, *, refine: bool = True) -> PronyFit:
    """Fit G_inf and N Prony terms to ``data`` (module docstring).

    The tau_i start log-spaced between 1/w_max and 1/w_min of the data (one term: their
    geometric mean); NNLS gives the moduli in closed form; with ``refine`` the log tau_i are
    then searched (bounds: one decade beyond the data's range each side) with NNLS inside.

    Raises:
        SpecError: n_terms outside 1..3 or fewer data rows than 2 N + 1 unknowns need.
    """
    from scipy.optimize import least_squares

    from batball.materials.prony import MAX_PRONY_TERMS

    if not 1 <= n_terms <= MAX_PRONY_TERMS:
        raise SpecError("prony-terms", n_terms, f"an integer 1..{MAX_PRONY_TERMS}")
    if 2 * data.omega.size < 2 * n_terms + 1:
        raise SpecError("dma", f"{data.omega.size} rows", f"at least {n_terms + 1} rows")
    lo, hi = -math.log(data.omega.max()), -math.log(data.omega.min())
    start = np.linspace(lo, hi, n_terms) if n_terms > 1 else np.array([0.5 * (lo + hi)])
    log_tau = start
    if refine:

        def residual(x: np.ndarray) -> np.ndarray:
            a, b = _design(data, np.exp(x))
            moduli, _ = solve_moduli(data, np.exp(x))
            return a @ moduli - b

        bounds = (np.full(n_terms, lo - math.log(10.0)), np.full(n_terms, hi + math.log(10.0)))
        solution = least_squares(residual, start, bounds=bounds, x_scale=1.0, xtol=1e-14,
                                 ftol=1e-14, gtol=1e-14, max_nfev=2000)  # fmt: skip
        log_tau = solution.x
    order = np.argsort(log_tau)
    tau = np.exp(log_tau[order])
    x, norm = solve_moduli(data, tau)
    rms = norm / math.sqrt(2 * data.omega.size)
    return PronyFit(g_inf=float(x[0]), moduli=x[1:], tau=tau, rms_relative=rms)


def dma_ball(
    base: BallSpec,
    data: DmaData,
    *,
    n_terms: int = 3,
    bulk_modulus: float | None = None,
    name: str | None = None,
) -> tuple[BallSpec, PronyFit]:
    """A ``prony<N>`` ball fitted to ``data``: the base ball's size and mass, and its bulk
    modulus unless ``bulk_modulus`` [Pa] is given (the DMA shear data say nothing of K; a
    MAT_006 or Prony base ball supplies its own).

    Returns:
        (the :class:`~batball.specs.BallSpec`, the :class:`PronyFit`).
    """
    import dataclasses

    fit = fit_prony(data, n_terms)
    k = bulk_modulus if bulk_modulus is not None else base.material.values.get("bulk_modulus")
    if k is None or not k > 0.0:
        raise SpecError("bulk-modulus", k, "a positive bulk modulus (the base ball has none)")
    material = MaterialSpec(law=f"prony{n_terms}", values=fit.values(float(k)))
    ball = dataclasses.replace(
        base, name=name or f"{base.name}-dma", material=material,
        description=f"Prony fit ({n_terms} terms) to DMA data, rms {fit.rms_relative:.2e}",
    )  # fmt: skip
    return ball, fit


__all__ = [
    "FREQUENCY_UNITS",
    "MODULUS_KINDS",
    "PRESSURE_UNITS",
    "DmaData",
    "PronyFit",
    "dma_ball",
    "fit_prony",
    "load_dma_csv",
    "prony_moduli",
    "solve_moduli",
    "tensile_to_shear",
    "write_dma_csv",
]


def write_dma_csv(path: str | Path, data: DmaData, *, unit: str = "psi") -> None:
    """Write ``data`` as ``frequency_hz,storage_<unit>,loss_<unit>`` (readable by
    :func:`load_dma_csv` with ``modulus="shear"``), atomically."""
    from batball.results.store import atomic_path

    factor = PRESSURE_UNITS[unit]
    with atomic_path(Path(path)) as tmp, tmp.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(["frequency_hz", f"storage_{unit}", f"loss_{unit}"])
        for f, s, loss in zip(data.frequency_hz, data.storage, data.loss, strict=True):
            writer.writerow([f"{f:.10g}", f"{s / factor:.10g}", f"{loss / factor:.10g}"])
