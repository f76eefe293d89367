"""What every material law declares, and the constants its update kernel receives."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from batball.errors import SpecError
from batball.materials.parameters import Parameter

#: Integer ids the element kernels dispatch on (one per pointwise update function).
LAW_ID_VISCOELASTIC = 1

#: Where the kernel constants (:meth:`MaterialLaw.kernel_constants`) hold the bulk modulus K, the
#: instantaneous and long-term shear moduli G0 and G_inf (Pa) and the first decay rate (1/s).
BULK, G0, G_INF, BETA = 0, 1, 2, 3


@dataclass(frozen=True)
class MaterialLaw(ABC):
    """A material law: its declared parameters and how to turn values into kernel constants.

    Subclasses add cross-field checks (``check``) and the mapping to kernel constants.
    """

    name: str
    title: str
    lsdyna_keyword: str
    parameters: tuple[Parameter, ...]

    def parameter(self, name: str) -> Parameter:
        """The declaration of parameter ``name``."""
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    def check(self, values: Mapping[str, float], *, prefix: str = "material") -> None:
        """Check each value against its bounds; raise :class:`SpecError` naming the field."""
        for p in self.parameters:
            if p.name not in values:
                raise SpecError(
                    f"{prefix}.{p.name}", "missing", f"a {p.dimension} in {p.display_unit}"
                )
            check_bounds(p, values[p.name], prefix=prefix)

    @abstractmethod
    def kernel_constants(self, values: Mapping[str, float]) -> np.ndarray:
        """Kernel constants, shape ``(2 N + 2,)``: K, G0, G_inf (Pa), beta_1 (1/s), then the
        pairs (G_i (Pa), beta_i (1/s)) of Prony terms 2..N; N = 1 (MAT_006) gives ``(4,)``."""

    def wave_speed(self, values: Mapping[str, float], density: float) -> float:
        """Dilatational wave speed (m/s) from the stiffest (instantaneous) moduli."""
        constants = self.kernel_constants(values)
        bulk, g0 = constants[BULK], constants[G0]
        return float(np.sqrt((bulk + 4.0 * g0 / 3.0) / density))


def check_bounds(p: Parameter, value: float, *, prefix: str) -> None:
    """Raise :class:`SpecError` unless ``value`` (SI) lies within the declared bounds of ``p``."""
    from batball.units import format_quantity

    low_ok = value >= p.lower if p.lower_inclusive else value > p.lower
    if not (np.isfinite(value) and low_ok and value <= p.upper):
        lo = "<=" if p.lower_inclusive else "<"
        allowed = (
            f"{format_quantity(p.lower, p.display_unit)} {lo} {p.name} "
            f"<= {format_quantity(p.upper, p.display_unit)}"
        )
        raise SpecError(f"{prefix}.{p.name}", format_quantity(value, p.display_unit), allowed)
