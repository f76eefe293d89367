"""batball: a virtual bat-and-ball laboratory.

Finite-element models of softballs and composite bats, the lab tests that certify them (CCOR and
dynamic stiffness, COR, compression, barrel compression, mass properties, modes, batted-ball
speed), and the measurements defined as the ASTM standards define them. SI float64 inside; units
only at the edges (see :mod:`batball.units`). The functions below are :mod:`batball.api`.
"""

from batball.api import (
    Result,
    barrel,
    bbs,
    ccor,
    compression,
    cor,
    load_ball,
    load_bat,
    modal,
    props,
    run_test,
)
from batball.version import __version__

__all__ = [
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
    "run_test",
]
