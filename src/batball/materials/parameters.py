"""Material parameters declared once: unit, bounds, meaning and LS-DYNA field name.

A declaration drives validation of spec files, reports, keyword export and calibration bounds.
Values inside the code are SI floats; ``display_unit`` is what a person reads and writes.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Parameter:
    """One declared material parameter.

    Attributes:
        name: the key users type in spec files (``"g0"``).
        dimension: a pint dimension name understood by :func:`batball.units.parse_quantity`
            (``"pressure"``, ``"frequency"``, ``"density"``, ``"dimensionless"``).
        display_unit: unit for reports and error messages (``"psi"``, ``"1/s"``).
        lower: smallest allowed value, SI.
        upper: largest allowed value, SI.
        lower_inclusive: whether ``lower`` itself is allowed.
        meaning: one line for reports.
        lsdyna_field: the keyword-card field name (``"G0"``).
        log_scale: calibration should search this parameter in log space.
        default: the value (SI) a spec that omits the parameter gets; None: it is required.
            Only parameters added after spec files existed have one, so that those files
            still read as they did.
    """

    name: str
    dimension: str
    display_unit: str
    lower: float
    upper: float
    meaning: str
    lsdyna_field: str
    lower_inclusive: bool = False
    log_scale: bool = False
    default: float | None = None
