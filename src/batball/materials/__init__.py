"""Material laws, registered by the names users type in spec files."""

from __future__ import annotations

from batball.materials.base import MaterialLaw
from batball.materials.elastic import ELASTIC
from batball.materials.parameters import Parameter
from batball.materials.viscoelastic import MAT006

#: The registry read by spec validation and by the CLI's listings.
MATERIAL_LAWS: dict[str, MaterialLaw] = {law.name: law for law in (MAT006, ELASTIC)}

__all__ = ["MATERIAL_LAWS", "MaterialLaw", "Parameter"]
