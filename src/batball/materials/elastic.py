"""Isotropic elastic solid (LS-DYNA ``*MAT_ELASTIC``, MAT_001), for verification.

Hypoelastic deviatoric update in the Jaumann frame with shear modulus G = E / (2 (1 + nu)), and
the same logarithmic pressure p = K ln(V0/V) as MAT_006, with K = E / (3 (1 - 2 nu)). It runs
through the MAT_006 kernel with G0 = G_inf = G, so the two laws share one tested update.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from batball.materials.base import MaterialLaw
from batball.materials.parameters import Parameter

ELASTIC_PARAMETERS = (
    Parameter(
        "youngs_modulus", "pressure", "psi", 0.0, 1e13, "Young's modulus E", "E", log_scale=True
    ),
    Parameter("poissons_ratio", "dimensionless", "", -0.999, 0.4999, "Poisson's ratio nu", "PR"),
)


class ElasticLaw(MaterialLaw):
    """Isotropic elastic declaration mapped to the viscoelastic kernel's constants."""

    def kernel_constants(self, values: Mapping[str, float]) -> np.ndarray:
        """K, G, G (Pa) and beta = 0."""
        e, nu = values["youngs_modulus"], values["poissons_ratio"]
        bulk = e / (3.0 * (1.0 - 2.0 * nu))
        shear = e / (2.0 * (1.0 + nu))
        return np.array([bulk, shear, shear, 0.0], dtype=np.float64)


ELASTIC = ElasticLaw(
    name="elastic",
    title="isotropic elastic (LS-DYNA MAT_001)",
    lsdyna_keyword="*MAT_ELASTIC",
    parameters=ELASTIC_PARAMETERS,
)
