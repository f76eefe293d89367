"""Fit chosen bat parameters to measured mass properties (weight, balance point, MOI).

A free parameter is named as the user types it:

* ``lumped_mass:<part>``: the lumped (non-structural) mass of a part, e.g. ``lumped_mass:endcap``;
* ``thickness:<label>``: the common thickness of every ply labelled ``<label>`` in the layups,
  e.g. ``thickness:handle-glass``.

The residuals are the relative misfits of weight, balance point and MOI about the pivot;
:func:`scipy.optimize.least_squares` (trust-region reflective, bounds keep masses >= 0 and plies
thicker than 0.001 in) drives them to zero when as many parameters as targets are free. Each
evaluation remeshes the bat, so a thickness moves the mid-surface exactly as the final mesh does.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from batball.errors import SpecError
from batball.lab.props import DEFAULT_PIVOT, MassProperties, bat_mass_properties
from batball.mesh.bat import DEFAULT_AXIAL_SIZE, DEFAULT_CIRCUMFERENTIAL
from batball.specs.bat import BatSpec, PartSpec, PlySpec

#: The kinds of free parameter, with their lower bound (SI) and a typical size for scaling.
PARAMETER_KINDS: dict[str, tuple[float, float]] = {
    "lumped_mass": (0.0, 0.028349523125),  # kg; 1 oz
    "thickness": (0.001 * 0.0254, 0.01 * 0.0254),  # m; 0.001 in, 0.01 in
}

#: Relative misfit below which a target counts as met.
MATCH_TOLERANCE = 1e-6

#: The parameters ``batball fit-bat`` frees by default on the embedded bat.
DEFAULT_FREE = ("lumped_mass:endcap", "thickness:handle-glass", "thickness:barrel-carbon")


@dataclass(frozen=True)
class FreeParameter:
    """One adjustable quantity of a :class:`BatSpec`.

    Attributes:
        kind: a key of :data:`PARAMETER_KINDS`.
        target: the part name (``lumped_mass``) or the ply label (``thickness``).
    """

    kind: str
    target: str

    @classmethod
    def parse(cls, text: str, *, field: str = "free") -> FreeParameter:
        """``"lumped_mass:endcap"`` -> FreeParameter("lumped_mass", "endcap")."""
        kind, _, target = text.partition(":")
        if kind not in PARAMETER_KINDS or not target:
            raise SpecError(field, text, "lumped_mass:<part> or thickness:<ply label>")
        return cls(kind, target)

    def __str__(self) -> str:
        return f"{self.kind}:{self.target}"

    def value(self, spec: BatSpec) -> float:
        """The current value in ``spec`` (kg or m).

        Raises:
            SpecError: no such part or label, or labelled plies of unequal thickness.
        """
        if self.kind == "lumped_mass":
            return spec.part(self.target).lumped_mass
        thicknesses = {p.thickness for p in _all_plies(spec) if p.label == self.target}
        if len(thicknesses) != 1:
            labels = sorted({p.label for p in _all_plies(spec) if p.label})
            allowed = f"a label of plies of one thickness; labels: {', '.join(labels) or 'none'}"
            raise SpecError("free", str(self), allowed)
        return thicknesses.pop()

    def apply(self, spec: BatSpec, value: float) -> BatSpec:
        """A copy of ``spec`` with this parameter set to ``value`` (kg or m)."""
        if self.kind == "lumped_mass":
            parts = tuple(
                dataclasses.replace(p, lumped_mass=value) if p.name == self.target else p
                for p in spec.parts
            )
            return dataclasses.replace(spec, parts=parts)
        return _replace_layups(spec, lambda ply: (
            dataclasses.replace(ply, thickness=value) if ply.label == self.target else ply
        ))  # fmt: skip


def _all_plies(spec: BatSpec) -> list[PlySpec]:
    """Every ply of the parts and the insert."""
    plies = [ply for part in spec.parts for ply in part.layup]
    return plies + (list(spec.insert.layup) if spec.insert is not None else [])


def _replace_layups(spec: BatSpec, change: Callable[[PlySpec], PlySpec]) -> BatSpec:
    """``spec`` with ``change(ply)`` applied to every ply (parts and insert)."""

    def layup(part: PartSpec) -> PartSpec:
        return dataclasses.replace(part, layup=tuple(change(p) for p in part.layup))

    insert = spec.insert
    if insert is not None:
        insert = dataclasses.replace(insert, layup=tuple(change(p) for p in insert.layup))
    return dataclasses.replace(spec, parts=tuple(layup(p) for p in spec.parts), insert=insert)


@dataclass(frozen=True)
class MassTargets:
    """Measured mass properties to match, SI.

    Attributes:
        weight: kg.
        balance_point: m from the knob end.
        moi_pivot: kg m^2 about the pivot.
        pivot: m from the knob end.
    """

    weight: float
    balance_point: float
    moi_pivot: float
    pivot: float = DEFAULT_PIVOT

    def residuals(self, props: MassProperties) -> np.ndarray:
        """Relative misfits (weight, balance point, MOI), shape (3,)."""
        return np.array([
            props.mass / self.weight - 1.0,
            props.balance_point / self.balance_point - 1.0,
            props.moi_pivot / self.moi_pivot - 1.0,
        ])  # fmt: skip


@dataclass(frozen=True)
class BatFit:
    """The outcome of :func:`fit_bat`.

    Attributes:
        spec: the bat with the fitted values.
        parameters: the free parameters.
        initial: their starting values, kg or m.
        values: their fitted values, kg or m.
        properties: the fitted bat's mass properties.
        residuals: relative misfits (weight, balance point, MOI).
        n_evaluations: mass-property evaluations used.
        success: the optimiser's verdict.
    """

    spec: BatSpec
    parameters: tuple[FreeParameter, ...]
    initial: tuple[float, ...]
    values: tuple[float, ...]
    properties: MassProperties
    residuals: tuple[float, ...]
    n_evaluations: int
    success: bool

    @property
    def matched(self) -> bool:
        """Every target met to a relative 1e-6 (False when a bound stops the fit short)."""
        return self.success and max(abs(r) for r in self.residuals) < MATCH_TOLERANCE


def fit_bat(
    spec: BatSpec,
    targets: MassTargets,
    parameters: tuple[FreeParameter, ...],
    *,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
) -> BatFit:
    """Adjust ``parameters`` of ``spec`` so its mass properties match ``targets`` (least squares).

    Raises:
        SpecError: an unknown part or label, or a fit that leaves the bat invalid.
    """
    from scipy.optimize import least_squares

    initial = np.array([p.value(spec) for p in parameters])
    typical = np.array([PARAMETER_KINDS[p.kind][1] for p in parameters])
    scale = np.maximum(initial, typical)
    lower = np.array([PARAMETER_KINDS[p.kind][0] for p in parameters]) / scale

    def with_values(scaled: np.ndarray) -> BatSpec:
        fitted = spec
        for p, value in zip(parameters, scaled * scale, strict=True):
            fitted = p.apply(fitted, float(value))
        return fitted

    def misfit(scaled: np.ndarray) -> np.ndarray:
        props, _ = bat_mass_properties(with_values(scaled), circumferential=circumferential,
                                       axial_size=axial_size, pivot=targets.pivot)  # fmt: skip
        return targets.residuals(props)

    start = np.maximum(initial / scale, lower)
    result = least_squares(misfit, start, bounds=(lower, np.inf), x_scale=1.0, xtol=1e-12,
                           ftol=1e-12, gtol=1e-12, diff_step=1e-7)  # fmt: skip
    fitted = with_values(result.x)
    props, _ = bat_mass_properties(fitted, circumferential=circumferential,
                                   axial_size=axial_size, pivot=targets.pivot)  # fmt: skip
    return BatFit(
        spec=fitted, parameters=parameters, initial=tuple(initial.tolist()),
        values=tuple((result.x * scale).tolist()), properties=props,
        residuals=tuple(targets.residuals(props).tolist()), n_evaluations=int(result.nfev),
        success=bool(result.success),
    )  # fmt: skip


_OZ, _IN = 0.028349523125, 0.0254
_DISPLAY_UNITS = {"lumped_mass": "oz", "thickness": "in"}


def fit_summary(fit: BatFit, targets: MassTargets) -> dict[str, Any]:
    """A JSON-able summary of a fit: parameters with units, properties against targets."""
    from batball.units import format_quantity

    props = fit.properties
    achieved = (props.mass / _OZ, props.balance_point / _IN, props.moi_pivot / (_OZ * _IN**2))
    wanted = (targets.weight / _OZ, targets.balance_point / _IN,
              targets.moi_pivot / (_OZ * _IN**2))  # fmt: skip
    keys = ("weight_oz", "balance_point_in", "moi_pivot_oz_in2")
    return {
        "bat": fit.spec.name,
        "success": fit.success,
        "n_evaluations": fit.n_evaluations,
        "parameters": {
            str(p): {
                "initial": format_quantity(v0, _DISPLAY_UNITS[p.kind], digits=6),
                "fitted": format_quantity(v, _DISPLAY_UNITS[p.kind], digits=6),
            }
            for p, v0, v in zip(fit.parameters, fit.initial, fit.values, strict=True)
        },
        "properties": dict(zip(keys, achieved, strict=True)),
        "targets": dict(zip(keys, wanted, strict=True)),
        "error_percent": {k: 100.0 * r for k, r in zip(keys, fit.residuals, strict=True)},
        "matched": fit.matched,
        "at_lower_bound": [
            str(p)
            for p, v in zip(fit.parameters, fit.values, strict=True)
            if v <= PARAMETER_KINDS[p.kind][0] * (1.0 + 1e-6) + 1e-12
        ],
        "moi_cm_oz_in2": props.moi_cm / (_OZ * _IN**2),
    }


def write_fitted_bat(path: Path, fit: BatFit) -> None:
    """Write the fitted bat as a bat-spec TOML file (atomically)."""
    import tomli_w

    from batball.io.store import write_text_atomic
    from batball.specs.bat import bat_spec_to_toml_dict

    header = "# Written by batball fit-bat: " + ", ".join(str(p) for p in fit.parameters) + "\n"
    write_text_atomic(path, header + tomli_w.dumps(bat_spec_to_toml_dict(fit.spec)))
