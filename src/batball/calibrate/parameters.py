"""Free parameters of a calibration and the unit box the optimiser searches.

Any declared parameter of a material law (:class:`batball.materials.Parameter`) may be freed.
Its search interval defaults to a decade either side of the starting value (log-scale
parameters) or to the declared bounds (the others), always inside the declaration; the
optimiser works on u in [0, 1] per parameter, mapped linearly or logarithmically.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from batball.errors import SpecError
from batball.materials import MaterialLaw, Parameter
from batball.units import format_quantity, parse_quantity

#: Default half-width of a log-scale search interval, as a factor on the starting value.
DEFAULT_SPAN = 10.0


@dataclass(frozen=True)
class FreeParameter:
    """One parameter the optimiser moves.

    Attributes:
        declaration: the law's declaration (name, unit, bounds).
        lower, upper: the search interval, SI, inside the declared bounds.
        log_scale: search log(value) rather than value.
    """

    declaration: Parameter
    lower: float
    upper: float
    log_scale: bool

    @property
    def name(self) -> str:
        """The parameter's name (``"g0"``)."""
        return self.declaration.name

    def from_unit(self, u: float) -> float:
        """The SI value at position ``u`` in [0, 1] of the interval."""
        u = min(max(float(u), 0.0), 1.0)
        if self.log_scale:
            return math.exp(math.log(self.lower) + u * math.log(self.upper / self.lower))
        return self.lower + u * (self.upper - self.lower)

    def to_unit(self, value: float) -> float:
        """The position in [0, 1] of the SI ``value`` (clipped to the interval)."""
        value = min(max(value, self.lower), self.upper)
        if self.log_scale:
            return math.log(value / self.lower) / math.log(self.upper / self.lower)
        return (value - self.lower) / (self.upper - self.lower)


@dataclass(frozen=True)
class ParameterSpace:
    """A law, the fixed values of its parameters and the free ones.

    Attributes:
        law: the material law.
        start: ``{name: SI value}`` for every declared parameter (the fixed ones keep theirs).
        free: the free parameters, in the order of the optimiser's vector.
    """

    law: MaterialLaw
    start: Mapping[str, float]
    free: tuple[FreeParameter, ...]

    def values(self, u: Sequence[float] | np.ndarray) -> dict[str, float]:
        """All parameter values (SI) at the unit-box point ``u``, shape (n_free,)."""
        values = dict(self.start)
        for parameter, position in zip(self.free, u, strict=True):
            values[parameter.name] = parameter.from_unit(position)
        return values

    def start_point(self) -> np.ndarray:
        """The starting values in the unit box, shape (n_free,)."""
        return np.array([p.to_unit(self.start[p.name]) for p in self.free])

    def describe(self, values: Mapping[str, float]) -> dict[str, str]:
        """``{name: value with its display unit}`` of the free parameters."""
        return {
            p.name: format_quantity(values[p.name], p.declaration.display_unit, digits=5)
            for p in self.free
        }


def _declared(law: MaterialLaw, name: str) -> Parameter:
    """The declaration of ``name`` in ``law``; SpecError listing the law's parameters if none."""
    names = [p.name for p in law.parameters]
    if name not in names:
        raise SpecError("free", name, f"a parameter of {law.name}: {', '.join(names)}")
    return law.parameter(name)


def _check_inside(p: Parameter, lower: float, upper: float) -> None:
    """SpecError unless the interval lies inside the declaration (and lower > 0 in log scale)."""
    low_ok = lower >= p.lower if p.lower_inclusive else lower > p.lower
    positive = lower > 0.0 or not p.log_scale
    if not (low_ok and lower < upper <= p.upper and positive):
        unit = p.display_unit
        shown = f"{format_quantity(lower, unit)} .. {format_quantity(upper, unit)}"
        allowed = (
            f"lower < upper within the declaration {format_quantity(p.lower, unit)} .. "
            f"{format_quantity(p.upper, unit)}" + (" and lower > 0 (log scale)" * p.log_scale)
        )
        raise SpecError(f"bounds.{p.name}", shown, allowed)


def default_interval(
    p: Parameter, start: float, *, span: float = DEFAULT_SPAN
) -> tuple[float, float]:
    """A decade (``span``) either side of ``start`` for log-scale parameters, else the declared
    bounds (an excluded lower bound moved in by 1 % of the range, e.g. MAT_057's HU in (0, 1]);
    clipped to the declaration."""
    if not p.log_scale:
        inset = 0.0 if p.lower_inclusive else 0.01 * (p.upper - p.lower)
        return p.lower + inset, p.upper
    if not start > 0.0:
        raise SpecError(
            f"bounds.{p.name}", format_quantity(start, p.display_unit),
            "explicit bounds for a log-scale parameter whose starting value is 0",
        )  # fmt: skip
    return max(start / span, p.lower), min(start * span, p.upper)


def make_parameter_space(
    law: MaterialLaw,
    start: Mapping[str, float],
    free: Sequence[str],
    *,
    bounds: Mapping[str, tuple[float, float]] | None = None,
) -> ParameterSpace:
    """The search space of ``free`` parameters of ``law`` around ``start``.

    Args:
        law: the material law; start: ``{name: SI value}`` of every declared parameter.
        free: names of the parameters to fit (declared by ``law``).
        bounds: optional ``{name: (lower, upper)}`` SI, inside the declared bounds.

    Raises:
        SpecError: an unknown name (``free``), bounds outside the declaration or for a parameter
            that is not free (``bounds.<name>``), or an empty ``free``.
    """
    bounds = dict(bounds or {})
    if not free:
        raise SpecError("free", "none", f"at least one parameter of {law.name}")
    for name in bounds:
        if name not in free:
            raise SpecError(f"bounds.{name}", bounds[name], f"a free parameter: {', '.join(free)}")
    parameters = []
    for name in free:
        p = _declared(law, name)
        lower, upper = bounds.get(name) or default_interval(p, start[name])
        _check_inside(p, lower, upper)
        parameters.append(FreeParameter(p, lower, upper, p.log_scale))
    return ParameterSpace(law=law, start=dict(start), free=tuple(parameters))


def parse_bounds(texts: Sequence[str], law: MaterialLaw) -> dict[str, tuple[float, float]]:
    """``["g0=10000 psi:50000 psi", ...]`` -> ``{"g0": (lower, upper)}`` in SI.

    Raises:
        SpecError: malformed text, an unknown parameter, or a value without its unit.
    """
    bounds = {}
    for text in texts:
        name, _, interval = text.partition("=")
        low, _, high = interval.partition(":")
        if not (name and low and high):
            raise SpecError(
                "bounds", text, "NAME=LOWER:UPPER with units, e.g. g0=10000 psi:5e4 psi"
            )
        p = _declared(law, name.strip())
        field = f"bounds.{p.name}"
        bounds[p.name] = (
            parse_quantity(low.strip(), p.dimension, field=field),
            parse_quantity(high.strip(), p.dimension, field=field),
        )
    return bounds
