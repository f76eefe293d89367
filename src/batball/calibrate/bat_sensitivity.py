"""What a bat's measurements pin: the sensitivity of fitted targets to free parameters.

Each free parameter of a bat (:class:`~batball.calibrate.bat_fit.FreeParameter`) has a plausible
spread (one standard deviation: how far the real bat may lie from the reconstruction), each
target a measurement resolution (one relative standard deviation). The Jacobian

    J_ij = (change of target i, in resolutions) / (change of parameter j, in spreads)

is the linearised map from what is uncertain to what is measured, in units where both are "one
standard deviation". Its singular value decomposition says what the measurements pin:

* a singular value s_k >> 1: the parameter combination V_k moves the targets by many
  resolutions over its plausible spread, so the data pin it;
* s_k < 1: the combination moves no target by more than its resolution, so the data leave it
  where the prior put it (unidentifiable from these targets);
* the linearised posterior spread of each parameter relative to its prior spread,
  sqrt(diag((J^T J + I)^-1)): near 1, the data say nothing about it; near 0, they fix it.

The derivatives are one-sided differences of ``step`` spreads (a quarter by default: large
against the modal analysis' 5e-6 noise, small against the curvature of the frequencies in the
angles), one target evaluation per parameter beside the base one.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from batball.calibrate.bat_fit import PARAMETER_KINDS, FitTargets, FreeParameter, MeshOptions
from batball.errors import SpecError
from batball.specs.bat import BatSpec
from batball.units import IN, OZ

#: Default plausible spread (one standard deviation) of a free parameter, by kind: a braid
#: angle 5 deg (a mandrel's braid angle varies with its diameter by more), a ply thickness 15 %
#: of its value (a reconstruction's plies are textbook thicknesses), a lumped mass 0.5 oz (an
#: end cap or knob plug nobody weighed), the insert's Coulomb coefficient 0.3 (from the seed's
#: frictionless start; carbon-epoxy laminates slide dry at 0.2-0.35 on fresh surfaces and up to
#: about 0.7 once worn in: docs/physics.md, "Friction at the insert").
DEFAULT_SPREAD = {"angle": math.radians(5.0), "thickness": 0.15, "lumped_mass": 0.5 * OZ,
                  "friction": 0.3}  # fmt: skip


def default_spread(parameter: FreeParameter, spec: BatSpec) -> float:
    """:data:`DEFAULT_SPREAD` of ``parameter`` at its value in ``spec`` (SI)."""
    spread = DEFAULT_SPREAD[parameter.kind]
    if parameter.kind == "thickness":
        return max(spread * parameter.value(spec), 0.001 * IN)
    return spread


@dataclass(frozen=True)
class Sensitivity:
    """The targets' sensitivity to the free parameters at one bat (module docs).

    Attributes:
        parameters, spread: the free parameters and their plausible spreads (SI).
        names, wanted, resolution: the targets, their measured values and relative resolutions.
        achieved: the targets' values at the bat.
        jacobian: (n_targets, n_parameters), resolutions per spread.
    """

    parameters: tuple[FreeParameter, ...]
    spread: tuple[float, ...]
    names: tuple[str, ...]
    wanted: tuple[float, ...]
    resolution: tuple[float, ...]
    achieved: tuple[float, ...]
    jacobian: np.ndarray

    @property
    def singular_values(self) -> np.ndarray:
        """One singular value per parameter combination, largest first (zeros for the
        combinations no target sees when there are fewer targets than parameters)."""
        return self._svd()[1]

    def _svd(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """U (n_targets, n_parameters), the n_parameters singular values (zero-padded) and
        V^T (n_parameters, n_parameters), its rows the parameter combinations."""
        u, sv, vt = np.linalg.svd(self.jacobian, full_matrices=True)
        n = self.jacobian.shape[1]
        padded_u = np.zeros((self.jacobian.shape[0], n))
        padded_u[:, : min(u.shape[1], n)] = u[:, :n]
        return padded_u, np.concatenate([sv, np.zeros(n - sv.size)]), vt

    @property
    def posterior_covariance(self) -> np.ndarray:
        """The parameters' linearised posterior covariance in units of their spreads,
        (J^T J + I)^-1: the Gaussian prior of unit spreads updated by the targets."""
        j = self.jacobian
        return np.linalg.inv(j.T @ j + np.eye(j.shape[1]))

    @property
    def posterior_ratio(self) -> np.ndarray:
        """Each parameter's linearised posterior spread over its prior spread."""
        return np.sqrt(np.diag(self.posterior_covariance))

    def propagated_spread(self, gradient: Sequence[float]) -> float:
        """The linearised posterior standard deviation of a quantity that moves by
        ``gradient[j]`` when parameter j moves by one spread: sqrt(g^T C g)."""
        g = np.asarray(gradient, dtype=float)
        if g.shape != (self.jacobian.shape[1],):
            raise SpecError("gradient", list(g), f"{self.jacobian.shape[1]} values")
        return float(np.sqrt(g @ self.posterior_covariance @ g))

    def posterior_offsets(self, n: int, seed: int) -> np.ndarray:
        """``n`` draws from the linearised posterior, as offsets from the bat in spreads,
        (n, n_parameters): a Latin hypercube in the unit cube (:mod:`scipy.stats.qmc`, so the
        marginals are covered evenly however small ``n``), mapped to standard normals and then
        through the Cholesky factor of :attr:`posterior_covariance`.

        Raises:
            SpecError: ``n`` below 1.
        """
        from scipy.stats import norm, qmc

        if n < 1:
            raise SpecError("samples", n, "at least 1")
        unit = qmc.LatinHypercube(d=len(self.parameters), seed=seed).random(n)
        factor = np.linalg.cholesky(self.posterior_covariance)
        return np.asarray(norm.ppf(unit) @ factor.T)

    def misfit(self) -> np.ndarray:
        """The targets' misfits at the bat, in resolutions."""
        return (np.asarray(self.achieved) / np.asarray(self.wanted) - 1.0) / np.asarray(
            self.resolution
        )

    def summary(self) -> dict[str, Any]:
        """JSON-able: the Jacobian by name, each combination with the targets it moves, and
        each parameter's posterior ratio."""
        u, sv, vt = self._svd()
        params = [str(p) for p in self.parameters]
        combinations = []
        for k, value in enumerate(sv):
            sign = 1.0 if vt[k, np.argmax(np.abs(vt[k]))] > 0 else -1.0  # largest weight > 0
            combinations.append({
                "singular_value": round(float(value), 4),
                "parameters": _named(params, (sign * vt[k]).round(4)),
                "moves_targets": _named(self.names, (sign * value * u[:, k]).round(3)),
            })  # fmt: skip
        spreads = [_display(p, s) for p, s in zip(self.parameters, self.spread, strict=True)]
        return {
            "spread": _named(params, spreads),
            "resolution_percent": _named(self.names, [100.0 * r for r in self.resolution]),
            "misfit_resolutions": _named(self.names, self.misfit().round(3)),
            "jacobian": _named(self.names, [_named(params, row.round(3)) for row in self.jacobian]),
            "combinations": combinations,
            "posterior_ratio": _named(params, self.posterior_ratio.round(3)),
        }


def _named(names: Sequence[str], values: Any) -> dict[str, Any]:
    """``{name: value}``, NumPy values as plain floats."""
    return {n: float(v) if isinstance(v, np.floating) else v
            for n, v in zip(names, values, strict=True)}  # fmt: skip


def _display(parameter: FreeParameter, value: float) -> str:
    from batball.units import format_quantity

    return format_quantity(value, PARAMETER_KINDS[parameter.kind].unit, digits=4)


def bat_sensitivity(
    spec: BatSpec,
    targets: FitTargets,
    parameters: Sequence[FreeParameter],
    *,
    spread: Sequence[float] | None = None,
    resolution: Sequence[float] | None = None,
    mesh: MeshOptions | None = None,
    step: float = 0.25,
) -> Sensitivity:
    """The sensitivity of ``targets`` to ``parameters`` at ``spec`` (module docs).

    Args:
        spread: plausible spreads, SI (default :func:`default_spread`).
        resolution: relative resolutions of the targets (default the targets' own
            ``resolution``, as :class:`~batball.calibrate.bat_fit.JointTargets` carries).
        step: the difference step, in spreads.

    Raises:
        SpecError: spreads or resolutions of the wrong count or not positive; a parameter
            the bat does not have.
    """
    parameters = tuple(parameters)
    spreads = tuple(spread) if spread is not None else tuple(
        default_spread(p, spec) for p in parameters)  # fmt: skip
    names = tuple(targets.names)
    resolutions = tuple(resolution if resolution is not None
                        else getattr(targets, "resolution", None) or ())  # fmt: skip
    if len(spreads) != len(parameters) or not all(s > 0.0 for s in spreads):
        raise SpecError("spread", list(spreads), f"{len(parameters)} positive spreads")
    if len(resolutions) != len(names) or not all(r > 0.0 for r in resolutions):
        raise SpecError("resolution", list(resolutions), f"{len(names)} positive resolutions")
    mesh = mesh or MeshOptions()
    wanted = np.asarray(targets.wanted, dtype=float)
    base = np.asarray(targets.achieved(spec, mesh), dtype=float)
    columns = []
    for p, s in zip(parameters, spreads, strict=True):
        moved = np.asarray(targets.achieved(p.apply(spec, p.value(spec) + step * s), mesh))
        columns.append((moved - base) / wanted / np.asarray(resolutions) / step)
    return Sensitivity(
        parameters=parameters, spread=spreads, names=names, wanted=tuple(wanted.tolist()),
        resolution=resolutions, achieved=tuple(base.tolist()), jacobian=np.column_stack(columns),
    )  # fmt: skip
