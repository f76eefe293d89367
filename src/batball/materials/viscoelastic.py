"""LS-DYNA ``*MAT_VISCOELASTIC`` (MAT_006): elastic bulk, one-term exponential shear relaxation.

G(t) = G_inf + (G0 - G_inf) exp(-beta t); deviatoric stress is the hereditary integral of the
deviatoric rate of deformation, integrated in a corotational (Jaumann) frame; the pressure is
p = K ln(V0/V). Sources: LS-DYNA Keyword Manual, MAT_006 (fields as in
``ansys/pydyna:.../auto/mat/mat_viscoelastic.py``); Herrmann & Peterson (1968); the recursion of
``docs/physics.md`` section 1.3 (Taylor-Pister-Goudreau / Simo-Hughes), exact for a
deviatoric rate that is constant over a step.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from batball.errors import SpecError
from batball.materials.base import MaterialLaw
from batball.materials.parameters import Parameter

MAT006_PARAMETERS = (
    Parameter(
        "bulk_modulus",
        "pressure",
        "psi",
        0.0,
        1e13,
        "elastic bulk modulus K",
        "BULK",
        log_scale=True,
    ),
    Parameter(
        "g0", "pressure", "psi", 0.0, 1e12, "short-time shear modulus G0", "G0", log_scale=True
    ),
    Parameter(
        "g_inf",
        "pressure",
        "psi",
        0.0,
        1e12,
        "long-time (infinite) shear modulus G_inf",
        "GI",
        lower_inclusive=True,
        log_scale=True,
    ),
    Parameter(
        "beta",
        "frequency",
        "1/s",
        0.0,
        1e9,
        "decay constant of the shear relaxation",
        "BETA",
        log_scale=True,
    ),
)


class Mat006Law(MaterialLaw):
    """MAT_006 declaration with its cross-field rule G_inf <= G0."""

    def check(self, values: Mapping[str, float], *, prefix: str = "material") -> None:
        """Bounds of each field, then G_inf <= G0."""
        super().check(values, prefix=prefix)
        if values["g_inf"] > values["g0"]:
            from batball.units import format_quantity

            raise SpecError(
                f"{prefix}.g_inf",
                format_quantity(values["g_inf"], "psi"),
                f"0 psi <= g_inf <= g0 ({format_quantity(values['g0'], 'psi')})",
            )

    def kernel_constants(self, values: Mapping[str, float]) -> np.ndarray:
        """K, G0, G_inf (Pa) and beta (1/s)."""
        return np.array(
            [values["bulk_modulus"], values["g0"], values["g_inf"], values["beta"]],
            dtype=np.float64,
        )


MAT006 = Mat006Law(
    name="mat006",
    title="viscoelastic (LS-DYNA MAT_006)",
    lsdyna_keyword="*MAT_VISCOELASTIC",
    parameters=MAT006_PARAMETERS,
)


# --- pointwise update (Numba) ---------------------------------------------------------------------

import numba as nb  # noqa: E402

from batball.numerics import FASTMATH  # noqa: E402


@nb.njit(inline="always", fastmath=FASTMATH)
def relaxation_factor(beta_dt: float) -> float:
    """(1 - exp(-x)) / x, with its series where x is tiny (docs/physics.md section 1.3)."""
    if beta_dt < 1e-6:
        return 1.0 - 0.5 * beta_dt + beta_dt * beta_dt / 6.0
    return (1.0 - np.exp(-beta_dt)) / beta_dt


@nb.njit(inline="always", fastmath=FASTMATH)
def viscoelastic_step_factors(
    g0: float, g_inf: float, beta: float, dt: float
) -> tuple[float, float]:
    """The per-step factors of the recursion: decay exp(-beta dt) and the relaxing-branch modulus
    2 (G0 - G_inf) (1 - exp(-beta dt)) / (beta dt) [Pa]; the same for every point of a material."""
    decay = np.exp(-beta * dt)
    scale = 2.0 * (g0 - g_inf) * relaxation_factor(beta * dt)
    return decay, scale


@nb.njit(inline="always", fastmath=FASTMATH)
def advance_viscoelastic_component(
    s_inf: float, h: float, de: float, two_g_inf: float, decay: float, scale: float
) -> tuple[float, float]:
    """One stress component's step: (s_inf + 2 G_inf de, decay h + scale de) [Pa]."""
    return s_inf + two_g_inf * de, decay * h + scale * de


@nb.njit(inline="always", fastmath=FASTMATH)
def update_viscoelastic_deviator(
    s_inf: np.ndarray,
    h: np.ndarray,
    de: np.ndarray,
    g0: float,
    g_inf: float,
    beta: float,
    dt: float,
) -> None:
    """Advance MAT_006's deviatoric stress by one step, in place.

    The stored stresses must already be rotated to the current configuration (Jaumann frame).

    Args:
        s_inf: (6,) long-time part 2 G_inf e' [Pa], Voigt order xx, yy, zz, xy, yz, zx.
        h: (6,) relaxing (Maxwell-branch) part [Pa], same order.
        de: (6,) deviatoric strain increment dev(D) dt, tensor shear components (not gamma).
        g0, g_inf: short- and long-time shear moduli [Pa]; beta: decay constant [1/s].
        dt: the step [s].
    """
    decay, scale = viscoelastic_step_factors(g0, g_inf, beta, dt)
    for c in range(6):
        s_inf[c], h[c] = advance_viscoelastic_component(
            s_inf[c], h[c], de[c], 2.0 * g_inf, decay, scale
        )


@nb.njit(cache=True)
def update_viscoelastic_points(
    s_inf: np.ndarray, h: np.ndarray, de: np.ndarray, constants: np.ndarray, dt: float
) -> None:
    """Batch form of :func:`update_viscoelastic_deviator` over points, for tests and tools.

    Args:
        s_inf, h: (n_points, 6) stresses [Pa], updated in place.
        de: (n_points, 6) deviatoric strain increments.
        constants: (4,) K, G0, G_inf [Pa], beta [1/s].
        dt: the step [s].
    """
    for i in range(s_inf.shape[0]):
        update_viscoelastic_deviator(
            s_inf[i], h[i], de[i], constants[1], constants[2], constants[3], dt
        )
