"""Section data of the explicit layered Belytschko-Tsay shell: one integration point per layer.

As LS-DYNA's ``*PART_COMPOSITE`` (docs/physics.md section 6.5): each single-angle layer k (braids
expanded) has one through-thickness point at its mid-surface z_k with weight t_k, so

    N = sum_k t_k sigma_k,  M = sum_k z_k t_k sigma_k,  sigma_k = Qbar_k (eps0 + z_k kappa).

This midpoint rule gives A and B exactly and D short by sum_k Qbar_k t_k^3 / 12 (a homogeneous
shell split into n equal layers has D (1 - 1/n^2); a single layer has no bending stiffness at all,
as in LS-DYNA): :func:`midpoint_abd` returns the [[A, B], [B, D]] actually integrated.

Arrays are per laminate (a bat has a handful) and padded to the largest layer count with
zero-thickness layers; ``cell_laminate`` maps cells to laminates.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from batball.elements.shell_stiffness import (
    SHEAR_FACTOR,
    laminate_rotary_inertia,
    transverse_shear_stiffness,
)
from batball.materials.laminate import Laminate
from batball.materials.orthotropic import rotated_stiffness

#: Columns of ``LayeredSection.hourglass_moduli``.
HG_MEMBRANE, HG_BENDING, HG_SHEAR, HG_THICKNESS = 0, 1, 2, 3


@dataclass(frozen=True)
class LayeredSection:
    """Per-laminate layer data of a layered explicit shell (laminate x axis = element edge 1-2).

    Attributes:
        layer_stiffness: Qbar_k in laminate axes, Voigt (xx, yy, xy), (n_laminates, n_layers, 3,
            3), Pa (zero for padding layers).
        layer_z: layer mid-surface heights from the mid-plane, (n_laminates, n_layers), m.
        layer_thickness: t_k, (n_laminates, n_layers), m (0 for padding).
        shear: transverse shear stiffness H (5/6 included), (n_laminates, 2, 2), N/m.
        hourglass_moduli: max(A11, A22) N/m, max(D11, D22) N m, max(H11, H22) N/m and the
            thickness m, the moduli of the hourglass constants, (n_laminates, 4).
        areal_mass: sum rho_k t_k, (n_laminates,), kg/m^2.
        rotary_inertia: integral of rho z^2 dz, (n_laminates,), kg.
        wave_speed: max over layers of sqrt(E_max / (rho (1 - nu_ab nu_ba))), (n_laminates,), m/s.
        cell_laminate: laminate of each cell, (n_cells,), int.
    """

    layer_stiffness: np.ndarray
    layer_z: np.ndarray
    layer_thickness: np.ndarray
    shear: np.ndarray
    hourglass_moduli: np.ndarray
    areal_mass: np.ndarray
    rotary_inertia: np.ndarray
    wave_speed: np.ndarray
    cell_laminate: np.ndarray

    @property
    def n_cells(self) -> int:
        """Number of cells the section covers."""
        return int(self.cell_laminate.size)


def layer_wave_speed(laminate: Laminate) -> float:
    """Plate wave speed of the stiffest layer, sqrt(E_max / (rho (1 - nu_ab nu_ba))), m/s.

    docs/physics.md section 6.2 (LS-DYNA shell time step for orthotropic layers).
    """
    speeds = [np.sqrt(max(ly.material.ea, ly.material.eb)
                      / (ly.material.density * (1.0 - ly.material.nu_ab * ly.material.prba)))
              for ly in laminate.layers()]  # fmt: skip
    return float(max(speeds))


def layered_section(
    laminates: Sequence[Laminate],
    cell_laminate: np.ndarray,
    *,
    shear_factor: float = SHEAR_FACTOR,
) -> LayeredSection:
    """Layer data of every laminate, padded to the largest layer count.

    Args:
        laminates: the distinct layups.
        cell_laminate: index into ``laminates`` of each cell, (n_cells,), int.
        shear_factor: kappa_s (LS-DYNA SHRF, 5/6).
    """
    n_layers = max(len(lam.layers()) for lam in laminates)
    stiffness = np.zeros((len(laminates), n_layers, 3, 3))
    z = np.zeros((len(laminates), n_layers))
    thickness = np.zeros((len(laminates), n_layers))
    for i, lam in enumerate(laminates):
        layers = lam.layers()
        interfaces = lam.interfaces()
        stiffness[i, : len(layers)] = np.stack(
            [rotated_stiffness(ly.material.reduced_stiffness(), ly.angle) for ly in layers]
        )
        z[i, : len(layers)] = 0.5 * (interfaces[1:] + interfaces[:-1])
        thickness[i, : len(layers)] = np.diff(interfaces)
    shear = np.stack([transverse_shear_stiffness(lam, shear_factor=shear_factor)
                      for lam in laminates])  # fmt: skip
    abd = np.stack([lam.abd().matrix() for lam in laminates])
    moduli = np.column_stack([
        np.maximum(abd[:, 0, 0], abd[:, 1, 1]), np.maximum(abd[:, 3, 3], abd[:, 4, 4]),
        np.maximum(shear[:, 0, 0], shear[:, 1, 1]), [lam.thickness for lam in laminates],
    ])  # fmt: skip
    return LayeredSection(
        layer_stiffness=stiffness,
        layer_z=z,
        layer_thickness=thickness,
        shear=shear,
        hourglass_moduli=moduli,
        areal_mass=np.array([lam.areal_mass for lam in laminates]),
        rotary_inertia=np.array([laminate_rotary_inertia(lam) for lam in laminates]),
        wave_speed=np.array([layer_wave_speed(lam) for lam in laminates]),
        cell_laminate=np.asarray(cell_laminate, dtype=np.int64),
    )


def midpoint_abd(section: LayeredSection) -> np.ndarray:
    """[[A, B], [B, D]] integrated by one point per layer, (n_laminates, 6, 6); N/m, N, N m."""
    t, z, q = section.layer_thickness, section.layer_z, section.layer_stiffness
    a = np.einsum("lk,lkij->lij", t, q)
    b = np.einsum("lk,lkij->lij", t * z, q)
    d = np.einsum("lk,lkij->lij", t * z * z, q)
    return np.block([[a, b], [b, d]])
