"""Laminates: plies, braid expansion, classical lamination theory (ABD) and effective moduli.

Conventions (``docs/physics.md`` sections 6.5 and 7.1):

* Plies are listed from the inner surface outward; z runs along the outward shell normal from
  -t/2 (inner surface) to +t/2 (outer surface), measured from the laminate mid-plane.
* Laminate axes: x along the bat axis (the material a-axis of a 0-degree ply, element edge 1-2),
  y in the hoop direction. A ply at angle theta has its fibres turned by theta from x toward y.
* A braided ply of thickness t at angle theta is five layers [+theta/-theta/+theta/-theta/+theta]
  with thicknesses t/6, t/4, t/6, t/4, t/6 (the seed, "Construction of the Composite Bat Finite
  Element Model"): balanced (A16 = A26 = 0) and symmetric about its own mid-plane (B = 0).
* A, B, D are the exact CLT integrals (Jones, Mechanics of Composite Materials, eqs. 4.22-4.24).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from batball.materials.orthotropic import OrthotropicLamina, rotated_stiffness

#: Thickness fractions and angle signs of the seed's five-layer braid [+/-/+/-/+].
BRAID_FRACTIONS: tuple[float, ...] = (1 / 6, 1 / 4, 1 / 6, 1 / 4, 1 / 6)
BRAID_SIGNS: tuple[float, ...] = (1.0, -1.0, 1.0, -1.0, 1.0)


@dataclass(frozen=True)
class Ply:
    """One ply of a layup.

    Attributes:
        material: the lamina.
        thickness: m (> 0).
        angle: fibre angle from the bat axis toward the hoop direction, rad; for a braided ply
            the braid half-angle (the layers are at +angle and -angle).
        braided: expand into the five-layer [+/-/+/-/+] braid.
    """

    material: OrthotropicLamina
    thickness: float
    angle: float
    braided: bool = False

    def __post_init__(self) -> None:
        if not (np.isfinite(self.thickness) and self.thickness > 0.0):
            raise ValueError(f"ply thickness must be positive, got {self.thickness!r} m")

    def layers(self) -> tuple[Ply, ...]:
        """The layers this ply stands for: itself, or the five braid layers (none braided)."""
        if not self.braided:
            return (self,)
        return tuple(
            Ply(material=self.material, thickness=f * self.thickness, angle=s * self.angle)
            for f, s in zip(BRAID_FRACTIONS, BRAID_SIGNS, strict=True)
        )


@dataclass(frozen=True)
class ABD:
    """Laminate stiffness matrices in laminate axes (x axial, y hoop), Voigt (xx, yy, xy).

    Attributes:
        a: extensional stiffness A, shape (3, 3), N/m.
        b: coupling stiffness B, shape (3, 3), N.
        d: bending stiffness D, shape (3, 3), N m.
    """

    a: np.ndarray
    b: np.ndarray
    d: np.ndarray

    def matrix(self) -> np.ndarray:
        """The 6x6 [[A, B], [B, D]] relating (N, M) to (mid-plane strain, curvature)."""
        return np.block([[self.a, self.b], [self.b, self.d]])


@dataclass(frozen=True)
class Laminate:
    """An ordered stack of plies, inner surface first.

    Attributes:
        plies: the plies as specified (braids not yet expanded).
    """

    plies: tuple[Ply, ...]

    def layers(self) -> tuple[Ply, ...]:
        """The single-angle layers, braids expanded, inner surface first."""
        return tuple(layer for ply in self.plies for layer in ply.layers())

    @property
    def thickness(self) -> float:
        """Total thickness t, m (0 for an empty laminate)."""
        return float(sum(ply.thickness for ply in self.plies))

    @property
    def areal_mass(self) -> float:
        """Mass per unit mid-surface area, sum(rho_k t_k), kg/m^2."""
        return float(sum(ply.material.density * ply.thickness for ply in self.plies))

    def interfaces(self) -> np.ndarray:
        """z of the layer boundaries from the mid-plane, shape (n_layers + 1,), m."""
        thicknesses = np.array([layer.thickness for layer in self.layers()])
        return np.concatenate(([0.0], np.cumsum(thicknesses))) - 0.5 * self.thickness

    def abd(self) -> ABD:
        """A, B, D by classical lamination theory (exact integrals over each layer)."""
        layers = self.layers()
        if not layers:
            raise ValueError("an empty laminate has no stiffness")
        qbar = np.stack(
            [rotated_stiffness(ly.material.reduced_stiffness(), ly.angle) for ly in layers]
        )
        z = self.interfaces()
        dz1, dz2, dz3 = np.diff(z), np.diff(z**2) / 2.0, np.diff(z**3) / 3.0
        return ABD(
            a=np.einsum("k,kij->ij", dz1, qbar),
            b=np.einsum("k,kij->ij", dz2, qbar),
            d=np.einsum("k,kij->ij", dz3, qbar),
        )

    def membrane_compliance(self) -> np.ndarray:
        """a = A^-1, shape (3, 3), m/N (membrane strains per unit force resultant)."""
        return np.linalg.inv(self.abd().a)

    @property
    def axial_modulus(self) -> float:
        """Effective membrane modulus along the bat axis, E_x = 1 / (t a11), Pa."""
        return 1.0 / (self.thickness * self.membrane_compliance()[0, 0])

    @property
    def hoop_modulus(self) -> float:
        """Effective membrane modulus in the hoop direction, E_y = 1 / (t a22), Pa."""
        return 1.0 / (self.thickness * self.membrane_compliance()[1, 1])

    @property
    def shear_modulus(self) -> float:
        """Effective in-plane shear modulus, G_xy = 1 / (t a66), Pa."""
        return 1.0 / (self.thickness * self.membrane_compliance()[2, 2])
