"""batball: a virtual bat-and-ball laboratory.

Finite-element models of softballs and composite bats, the lab tests that certify them (CCOR and
dynamic stiffness, COR, compression, barrel compression, mass properties, modes, batted-ball
speed), and the measurements defined as the ASTM standards define them. SI float64 inside; units
only at the edges (see :mod:`batball.units`). The functions below are :mod:`batball.api`.
"""

from typing import Any

from batball.version import __version__

__all__ = [
    "FieldSeries",
    "Result",
    "__version__",
    "barrel",
    "bbs",
    "ccor",
    "compression",
    "cor",
    "load_ball",
    "load_bat",
    "modal",
    "props",
    "read_fields",
    "run_test",
]


def __getattr__(name: str) -> Any:
    """The API's names, imported on first use: ``import batball.errors`` (or the command line's
    ``--version``) does not pay for NumPy, SciPy and Numba."""
    if name in __all__:
        from batball import api

        return getattr(api, name)
    raise AttributeError(f"module 'batball' has no attribute {name!r}")
