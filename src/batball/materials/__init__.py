"""Material laws, registered by the names users type in spec files."""

from __future__ import annotations

from batball.materials.base import MaterialLaw
from batball.materials.elastic import ELASTIC
from batball.materials.foam import FOAM_LAWS, FoamCurve, FoamLaw
from batball.materials.laminate import ABD, Laminate, Ply
from batball.materials.orthotropic import (
    ISOTROPIC_LAMINA,
    MAT022,
    LaminaLaw,
    OrthotropicLamina,
    isotropic_lamina,
    rotated_stiffness,
)
from batball.materials.parameters import Parameter
from batball.materials.prony import PRONY_LAWS, PronyLaw
from batball.materials.viscoelastic import MAT006

#: The registry read by spec validation and by the CLI's listings.
MATERIAL_LAWS: dict[str, MaterialLaw] = {
    law.name: law for law in (MAT006, ELASTIC, *PRONY_LAWS, *FOAM_LAWS)
}

#: Shell-layer (lamina) laws, kept apart from MATERIAL_LAWS: a lamina gives a plane-stress
#: stiffness for layered shells, not the hex kernel's constants (MaterialLaw.kernel_constants).
LAMINA_LAWS: dict[str, LaminaLaw] = {law.name: law for law in (MAT022, ISOTROPIC_LAMINA)}

__all__ = [
    "ABD",
    "FoamCurve",
    "FoamLaw",
    "LAMINA_LAWS",
    "MATERIAL_LAWS",
    "LaminaLaw",
    "Laminate",
    "MaterialLaw",
    "OrthotropicLamina",
    "Parameter",
    "Ply",
    "PronyLaw",
    "isotropic_lamina",
    "rotated_stiffness",
]
