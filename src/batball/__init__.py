"""batball: a virtual bat-and-ball laboratory.

Finite-element models of softballs (and, later, composite bats), the lab tests that certify them
(CCOR, COR, dynamic stiffness, ...), and the measurements defined as the ASTM standards define them.
SI float64 inside; units only at the edges (see :mod:`batball.units`).
"""

__version__ = "0.1.2"
