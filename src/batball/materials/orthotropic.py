"""Orthotropic elastic laminae for layered shells: LS-DYNA ``*MAT_COMPOSITE_DAMAGE`` (MAT_022).

Only the elastic part of MAT_022 is declared (the seed's bat analyses are elastic; the Chang-Chang
strengths are left out). Axes: ``a`` is the fibre direction, ``b`` the in-plane transverse
direction, ``c`` the shell normal. Source: LS-DYNA Keyword Manual, MAT_022 (fields as in
``ansys/pydyna:.../auto/mat/mat_composite_damage.py``); ``docs/physics.md`` section 6.5.

**PRBA is the minor Poisson's ratio** nu_ba (contraction along ``a`` under stress along ``b``);
the major ratio is nu_ab = PRBA * EA / EB. Entering the major ratio (0.27 for carbon) as PRBA gives
nu_ab near 4 and a stiffness that is not positive definite; :class:`OrthotropicLamina` refuses it.

A lamina is not a solid-kernel :class:`~batball.materials.base.MaterialLaw` (whose
``kernel_constants`` are the hex kernel's K, G0, G_inf, beta), so laminae have their own registry,
:data:`batball.materials.LAMINA_LAWS`: ``"mat022"`` (orthotropic) and ``"elastic"`` (isotropic,
for metal or polymer parts of a layup, LS-DYNA MAT_001 on a shell).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields

import numpy as np

from batball.errors import SpecError
from batball.materials.base import check_bounds
from batball.materials.parameters import Parameter

GPA = 1e9

_DENSITY = Parameter(
    "density", "density", "g/cm**3", 0.0, 25000.0, "mass density", "RO"
)  # fmt: skip

MAT022_PARAMETERS: tuple[Parameter, ...] = (
    _DENSITY,
    Parameter("ea", "pressure", "GPa", 0.0, 1e12, "Young's modulus along a (fibre)", "EA"),
    Parameter("eb", "pressure", "GPa", 0.0, 1e12, "Young's modulus along b (transverse)", "EB"),
    Parameter("ec", "pressure", "GPa", 0.0, 1e12, "Young's modulus along c (normal)", "EC"),
    Parameter(
        "prba", "dimensionless", "", -1.0, 0.5,
        "minor Poisson's ratio nu_ba = nu_ab EB/EA (not the major nu_ab)", "PRBA",
    ),
    Parameter("gab", "pressure", "GPa", 0.0, 1e12, "in-plane shear modulus G_ab", "GAB"),
    Parameter("gbc", "pressure", "GPa", 0.0, 1e12, "transverse shear modulus G_bc", "GBC"),
    Parameter("gca", "pressure", "GPa", 0.0, 1e12, "transverse shear modulus G_ca", "GCA"),
)  # fmt: skip

ISOTROPIC_PARAMETERS: tuple[Parameter, ...] = (
    _DENSITY,
    Parameter("youngs_modulus", "pressure", "GPa", 0.0, 1e13, "Young's modulus E", "E"),
    Parameter("poissons_ratio", "dimensionless", "", -0.999, 0.4999, "Poisson's ratio nu", "PR"),
)


@dataclass(frozen=True)
class OrthotropicLamina:
    """The elastic constants of one MAT_022 lamina, SI.

    Attributes:
        name: the user's material name (``"carbon"``); error fields are ``materials.<name>.<key>``.
        density: kg/m^3.
        ea, eb, ec: Young's moduli along a (fibre), b (transverse), c (normal), Pa.
        prba: minor Poisson's ratio nu_ba, dimensionless.
        gab, gbc, gca: shear moduli, Pa.

    Raises:
        SpecError: a value outside its declared bounds, or PRBA^2 EA/EB >= 1 (the plane-stress
            stiffness would not be positive definite: most often the major ratio given as PRBA).
    """

    name: str
    density: float
    ea: float
    eb: float
    ec: float
    prba: float
    gab: float
    gbc: float
    gca: float

    def __post_init__(self) -> None:
        prefix = f"materials.{self.name}"
        for p in MAT022_PARAMETERS:
            check_bounds(p, getattr(self, p.name), prefix=prefix)
        if self.prba * self.nu_ab >= 1.0:
            allowed = (
                f"the MINOR Poisson's ratio nu_ba, with PRBA^2 EA/EB < 1 "
                f"(|PRBA| < {math.sqrt(self.eb / self.ea):.3f}); nu_ba = nu_ab EB/EA"
            )
            raise SpecError(f"{prefix}.prba", self.prba, allowed)

    @property
    def nu_ab(self) -> float:
        """Major Poisson's ratio nu_ab = PRBA * EA / EB (0.27 for AS4 carbon/epoxy)."""
        return self.prba * self.ea / self.eb

    def values(self) -> dict[str, float]:
        """``{parameter name: SI value}`` in declaration order (for TOML and keyword export)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name != "name"}

    def reduced_stiffness(self) -> np.ndarray:
        """Plane-stress reduced stiffness Q in material axes, shape (3, 3), Pa.

        Voigt order (11, 22, 12) with engineering shear strain:
        Q11 = EA/D, Q22 = EB/D, Q12 = nu_ba EA/D, Q66 = GAB, D = 1 - nu_ab nu_ba
        (docs/physics.md section 6.5; Jones, Mechanics of Composite Materials, eq. 2.61).
        """
        denominator = 1.0 - self.nu_ab * self.prba
        q12 = self.prba * self.ea / denominator
        return np.array(
            [
                [self.ea / denominator, q12, 0.0],
                [q12, self.eb / denominator, 0.0],
                [0.0, 0.0, self.gab],
            ]
        )


def rotated_stiffness(q: np.ndarray, angles: np.ndarray | float) -> np.ndarray:
    """Transformed reduced stiffness Qbar of plies rotated by ``angles`` about the normal.

    A positive angle turns the fibre (a) axis from the laminate x axis toward its y axis
    (Jones eq. 2.85; Daniel & Ishai eq. 4.56).

    Args:
        q: reduced stiffness in material axes, shape (3, 3), Pa.
        angles: ply angles, shape (n_plies,) or scalar, rad.

    Returns:
        Qbar in laminate axes, shape (n_plies, 3, 3) (or (3, 3) for a scalar angle), Pa.
    """
    theta = np.asarray(angles, dtype=np.float64)
    m, n = np.cos(theta), np.sin(theta)
    m2n2, m4, n4 = m * m * n * n, m**4, n**4
    q11, q12, q22, q66 = q[0, 0], q[0, 1], q[1, 1], q[2, 2]
    qbar = np.empty((*theta.shape, 3, 3))
    qbar[..., 0, 0] = q11 * m4 + 2.0 * (q12 + 2.0 * q66) * m2n2 + q22 * n4
    qbar[..., 1, 1] = q11 * n4 + 2.0 * (q12 + 2.0 * q66) * m2n2 + q22 * m4
    qbar[..., 0, 1] = qbar[..., 1, 0] = (q11 + q22 - 4.0 * q66) * m2n2 + q12 * (m4 + n4)
    qbar[..., 2, 2] = (q11 + q22 - 2.0 * q12 - 2.0 * q66) * m2n2 + q66 * (m4 + n4)
    a, b = q11 - q12 - 2.0 * q66, q12 - q22 + 2.0 * q66
    qbar[..., 0, 2] = qbar[..., 2, 0] = a * m**3 * n + b * m * n**3
    qbar[..., 1, 2] = qbar[..., 2, 1] = a * m * n**3 + b * m**3 * n
    return qbar


@dataclass(frozen=True)
class LaminaLaw:
    """A lamina law: its declared parameters and how they make an :class:`OrthotropicLamina`.

    Attributes:
        name: the key users type (``"mat022"``, ``"elastic"``).
        title: one line for listings.
        lsdyna_keyword: the keyword card it exports to.
        parameters: the declared parameters, in card order.
    """

    name: str
    title: str
    lsdyna_keyword: str
    parameters: tuple[Parameter, ...]

    def lamina(self, values: Mapping[str, float], *, name: str) -> OrthotropicLamina:
        """The lamina of ``values`` (SI, one per declared parameter), validated.

        Raises:
            SpecError: a missing or out-of-bounds value, naming ``materials.<name>.<parameter>``.
        """
        for p in self.parameters:
            if p.name not in values:
                raise SpecError(f"materials.{name}.{p.name}", "missing", f"a {p.dimension}")
            check_bounds(p, values[p.name], prefix=f"materials.{name}")
        if self.name == "elastic":
            return isotropic_lamina(name=name, **values)
        return OrthotropicLamina(name=name, **values)


def isotropic_lamina(
    *, name: str, density: float, youngs_modulus: float, poissons_ratio: float
) -> OrthotropicLamina:
    """An isotropic layer (metal, polymer) as a lamina: EA = EB = EC = E, PRBA = nu, G = E/2(1+nu).

    Args:
        name: material name.
        density: kg/m^3.
        youngs_modulus: Pa.
        poissons_ratio: dimensionless.
    """
    shear = youngs_modulus / (2.0 * (1.0 + poissons_ratio))
    return OrthotropicLamina(
        name=name, density=density, ea=youngs_modulus, eb=youngs_modulus, ec=youngs_modulus,
        prba=poissons_ratio, gab=shear, gbc=shear, gca=shear,
    )  # fmt: skip


MAT022 = LaminaLaw(
    name="mat022",
    title="orthotropic elastic lamina (LS-DYNA MAT_022, elastic part)",
    lsdyna_keyword="*MAT_COMPOSITE_DAMAGE",
    parameters=MAT022_PARAMETERS,
)

ISOTROPIC_LAMINA = LaminaLaw(
    name="elastic",
    title="isotropic elastic layer (LS-DYNA MAT_001 on a shell)",
    lsdyna_keyword="*MAT_ELASTIC",
    parameters=ISOTROPIC_PARAMETERS,
)
