"""A bat spec on its shell mesh: each quad's laminate, areal mass and section.

The mesh (:func:`batball.mesh.bat.make_bat_mesh`) has one cell set per part of the spec and one
for the insert; the laminates are the parts' layups (the insert's last), the areal mass is the
layup's sum(rho_k t_k) plus the part's lumped (non-structural) mass spread uniformly over its area.
"""

from __future__ import annotations

import numpy as np

from batball.elements.shell_stiffness import ShellSection, shell_section
from batball.materials.laminate import Laminate
from batball.mesh.shell import ShellMesh, quad_areas
from batball.specs.bat import BatSpec


def bat_laminates(spec: BatSpec, mesh: ShellMesh) -> tuple[list[Laminate], np.ndarray]:
    """Each part's (and the insert's) laminate and the laminate of each quad of a bat mesh:
    (laminates, cell_laminate (n_cells,) indices into them)."""
    layups = [part.layup for part in spec.parts]
    cell_laminate = np.full(mesh.n_cells, -1, dtype=np.int64)
    for k, part in enumerate(spec.parts):
        cell_laminate[mesh.cell_sets[part.name]] = k
    if spec.insert is not None:
        layups.append(spec.insert.layup)
        cell_laminate[mesh.cell_sets["insert"]] = len(layups) - 1
    return [spec.laminate(layup) for layup in layups], cell_laminate


def bat_areal_mass(spec: BatSpec, mesh: ShellMesh) -> np.ndarray:
    """Areal mass of each quad of a bat mesh: layup sum(rho_k t_k) + lumped mass / part area.

    Args:
        spec: the bat the mesh was made from.
        mesh: its mesh (:func:`batball.mesh.bat.make_bat_mesh`), one cell set per part.

    Returns:
        (n_cells,) kg/m^2.
    """
    areal = np.full(mesh.n_cells, np.nan)
    areas = quad_areas(mesh.points, mesh.cells)
    for part in spec.parts:
        cells = mesh.cell_sets[part.name]
        spread = part.lumped_mass / areas[cells].sum()
        areal[cells] = spec.laminate(part.layup).areal_mass + spread
    if spec.insert is not None:
        areal[mesh.cell_sets["insert"]] = spec.laminate(spec.insert.layup).areal_mass
    if np.isnan(areal).any():
        raise ValueError("the mesh has cells in no part of the bat")
    return areal


def bat_section(spec: BatSpec, mesh: ShellMesh) -> ShellSection:
    """Per-cell section of a bat mesh: each part's (and the insert's) laminate plus lumped mass."""
    laminates, cell_laminate = bat_laminates(spec, mesh)
    structural = np.array([lam.areal_mass for lam in laminates])[cell_laminate]
    extra = bat_areal_mass(spec, mesh) - structural
    return shell_section(laminates, cell_laminate, extra_areal_mass=extra)
