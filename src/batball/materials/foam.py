"""Foam laws LS-DYNA ``*MAT_LOW_DENSITY_FOAM`` (MAT_057) and ``*MAT_FU_CHANG_FOAM`` (MAT_083).

Both are uniaxial in each principal direction with no lateral coupling (zero Poisson's ratio):
the principal stretches lambda_i of V (F = V R) give nominal strains e_i = lambda_i - 1; in
compression the nominal stress is minus the loading curve at -e_i (MAT_083: interpolated in strain
rate between a table of curves), in tension it is E e_i up to the cut-off TC; the Cauchy stress is
sigma_i = tau_i / (lambda_j lambda_k) along the principal directions. Unloading is hysteretic:
tau = (1 - D) tau_load with D = (1 - HU) (1 - (W / W_max)^SHAPE), W the energy density on the
(first) loading curve and W_max its largest value so far.

Sources followed (docs/physics.md section 2, verified with the stored copies below):

* card fields and defaults: ``ansys/pydyna`` keyword classes ``mat_low_density_foam.py`` and
  ``mat_fu_chang_foam.py``;
* no lateral coupling, hysteresis with HU and SHAPE, tension linear up to TC, the viscous
  coefficient DAMP: Ansys LS-DYNA User's Guide, "6.8.1 Rate Independent Low Density Foam"
  (https://ansyshelp.ansys.com/public/Views/Secured/corp/v251/en/lsdyna_ug/exd_ag_lsd_mat_foams.html);
* the damage form of the unloading and MAT_083's unloading on the first curve (HU = 0: along the
  first loading curve; HU > 0: the first curve with the damage): Altair's LS-DYNA input pages for
  MAT_057 and MAT_083, which map both to Radioss /MAT/LAW90
  (https://help.altair.com/hwsolvers/rad/topics/solvers/rad/mat_083_fu_chang_foam_lsdyna_r.htm);
* the DAMP stress, whose LS-DYNA formula we could not find in a stored copy: the form
  sigma_d = DAMP rho c L D of IMPETUS's MAT_FOAM damping coefficient
  (https://impetus.no/support/manual/?command=MAT_FOAM), the usual one for such a coefficient
  (a fraction of the element's critical damping, like LS-DYNA's linear bulk viscosity);
* MAT_057's rate term (ED, BETA1): a one-term Maxwell stress sigma_r = int E_d exp(-beta_1 (t -
  s)) D ds added to the foam stress (docs/physics.md section 2.1, an assumed form); updated with
  MAT_006's exact recursion in the Jaumann frame.

What is not implemented, and why: MAT_057's BETA (creep recovery of the unloading curve; LS-DYNA's
default 0 is what the model does), FAIL (tension is held at TC), KCON (the effective modulus is
always LS-DYNA's default max(E, largest curve slope)), MAT_083's analytic constants (D0..C5; only
the table route TBID, docs/physics.md section 2.2), PVID, TFLAG = 1 and the running
average of the rate (SRAF): the scalar rate is the true strain rate along the most compressed
principal direction (RFLAG = 0, SFLAG = 0) through a first-order filter of cut-off
``rate_filter``, like LAW90's.

A curve scale factor (``curve_scale``, LS-DYNA's SFO of the curve) multiplies every loading curve's
stress so that a calibration can move the curve's level without changing its shape; a strain scale
factor (``curve_strain_scale``, the curve's SFA, *DEFINE_CURVE's abscissa scale) multiplies every
curve's strain, so that, with the level, a calibration can move where the curve densifies: the
curve used is curve_scale * f(e / curve_strain_scale). The scaled strains must stay at or below
MAX_CURVE_STRAIN (a stretch must stay positive).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from batball.errors import SpecError
from batball.materials.base import MaterialLaw
from batball.materials.parameters import Parameter
from batball.units import PSI

#: Kinds of foam law, as the kernel sees them (params[P_KIND]).
KIND_MAT057, KIND_MAT083 = 57.0, 83.0

# Columns of FoamTable.params.
P_KIND, P_E, P_TC, P_HU, P_SHAPE, P_DAMP, P_ED, P_BETA1, P_MODULUS, P_RATE_FILTER = range(10)
N_FOAM_PARAMS = 10

#: Largest compressive nominal strain a curve point may have (a stretch must stay positive).
MAX_CURVE_STRAIN = 0.99


def _common_parameters(*, hu_lower: float, hu_inclusive: bool) -> list[Parameter]:
    """E, TC, HU, SHAPE, DAMP and the curve scale, shared by both laws."""
    return [
        Parameter(
            "youngs_modulus", "pressure", "psi", 0.0, 1e12,
            "Young's modulus E: tension, and the time step if above the curves' slopes", "E",
            log_scale=True,
        ),
        Parameter(
            "tension_cutoff", "pressure", "psi", 0.0, 1e15, "tension cut-off stress TC", "TC",
            log_scale=True,
        ),
        Parameter(
            "hu", "dimensionless", "", hu_lower, 1.0,
            "hysteretic unloading factor HU: the stress ratio after full unloading", "HU",
            lower_inclusive=hu_inclusive,
        ),
        Parameter(
            "shape", "dimensionless", "", 0.0, 100.0,
            "unloading shape factor SHAPE (< 1 less, > 1 more dissipation)", "SHAPE",
            log_scale=True,
        ),
        Parameter(
            "damp", "dimensionless", "", 0.0, 1.0,
            "viscous coefficient DAMP: sigma_d = DAMP rho c L D (LS-DYNA suggests 0.05-0.5)",
            "DAMP", lower_inclusive=True,
        ),
        Parameter(
            "curve_scale", "dimensionless", "", 0.0, 100.0,
            "scale factor on the stress of every loading curve (the curve's SFO)", "SFO",
            log_scale=True,
        ),
        Parameter(
            "curve_strain_scale", "dimensionless", "", 0.0, 100.0,
            "scale factor on the strain of every loading curve (the curve's SFA): below 1 the "
            "curve densifies earlier", "SFA", log_scale=True, default=1.0,
        ),
    ]  # fmt: skip


MAT057_PARAMETERS = (
    *_common_parameters(hu_lower=0.0, hu_inclusive=False),
    Parameter(
        "rate_modulus", "pressure", "psi", 0.0, 1e12,
        "relaxation modulus E_d of the optional rate (Maxwell) term; 0 = off", "ED",
        lower_inclusive=True, log_scale=True,
    ),
    Parameter(
        "rate_decay", "frequency", "1/s", 0.0, 1e9, "decay constant beta_1 of the rate term",
        "BETA1", log_scale=True,
    ),
)  # fmt: skip

MAT083_PARAMETERS = (
    *_common_parameters(hu_lower=0.0, hu_inclusive=True),
    Parameter(
        "rate_filter", "frequency", "1/s", 0.0, 1e9,
        "cut-off frequency of the strain-rate filter (LAW90's Fcut)", "(SRAF)", log_scale=True,
    ),
)  # fmt: skip


@dataclass(frozen=True)
class FoamCurve:
    """One loading curve: compressive nominal stress against compressive nominal strain.

    Attributes:
        strain: (n,) nominal strains, compression positive, starting at 0, increasing.
        stress: (n,) nominal stresses [Pa], compression positive, starting at 0, non-decreasing.
        strain_rate: the curve's strain rate [1/s] (MAT_083's table; 0 for MAT_057).
    """

    strain: tuple[float, ...]
    stress: tuple[float, ...]
    strain_rate: float = 0.0

    def check(self, *, prefix: str) -> None:
        """SpecError naming ``prefix.strain`` / ``prefix.stress`` for a curve the law cannot use."""
        strain, stress = np.asarray(self.strain), np.asarray(self.stress)
        if strain.ndim != 1 or len(strain) < 2 or len(strain) != len(stress):
            raise SpecError(
                f"{prefix}.strain", list(self.strain), "at least 2 points, as many as stresses"
            )
        if not (np.all(np.isfinite(strain)) and strain[0] == 0.0 and np.all(np.diff(strain) > 0)):
            raise SpecError(f"{prefix}.strain", list(self.strain), "0 first, then increasing")
        if strain[-1] > MAX_CURVE_STRAIN:
            raise SpecError(
                f"{prefix}.strain", float(strain[-1]), f"nominal strains <= {MAX_CURVE_STRAIN}"
            )
        if not (np.all(np.isfinite(stress)) and stress[0] == 0.0):
            raise SpecError(f"{prefix}.stress", list(self.stress), "0 at zero strain")
        if not (np.all(np.diff(stress) >= 0.0) and stress[-1] > 0.0):
            raise SpecError(
                f"{prefix}.stress", [s / PSI for s in self.stress],
                "a monotonic (non-decreasing) loading curve, in psi as shown, ending above 0",
            )  # fmt: skip
        if not (np.isfinite(self.strain_rate) and self.strain_rate >= 0.0):
            raise SpecError(f"{prefix}.strain_rate", self.strain_rate, "a rate >= 0 1/s")

    def max_slope(self) -> float:
        """The steepest segment of the curve [Pa]."""
        return float(np.max(np.diff(self.stress) / np.diff(self.strain)))


@dataclass(frozen=True)
class FoamTable:
    """The packed constants of one foam material for the element kernel.

    Attributes:
        params: (N_FOAM_PARAMS,) the columns ``P_*`` (SI).
        rates: (n_curves,) strain rates of the curves [1/s], increasing.
        strains, stresses: (n_curves, n_max) the scaled curves [-], [Pa], padded with their
            last point; counts: (n_curves,) points of each.
        energies: (n_max,) energy density of the first curve at its points [J/m^3].
    """

    params: np.ndarray
    rates: np.ndarray
    strains: np.ndarray
    stresses: np.ndarray
    counts: np.ndarray
    energies: np.ndarray

    def arrays(self) -> tuple[np.ndarray, ...]:
        """The kernel's tuple (params, rates, strains, stresses, counts, energies)."""
        return (self.params, self.rates, self.strains, self.stresses, self.counts, self.energies)


@dataclass(frozen=True)
class FoamLaw(MaterialLaw):
    """A tabulated foam: declared parameters plus loading curves (``MaterialSpec.curves``)."""

    kind: float = KIND_MAT057
    max_curves: int = 1

    def check_curves(
        self, curves: Sequence[FoamCurve], values: Mapping[str, float], *, prefix: str = "material"
    ) -> None:
        """SpecError naming ``<prefix>.curves[i]...`` unless the curves suit the law, or
        ``<prefix>.curve_strain_scale`` if ``values``' strain scale takes a curve's last strain
        past MAX_CURVE_STRAIN."""
        if not 1 <= len(curves) <= self.max_curves:
            allowed = "one loading curve" if self.max_curves == 1 else "one curve per strain rate"
            raise SpecError(f"{prefix}.curves", f"{len(curves)} curves", allowed)
        for i, curve in enumerate(curves):
            curve.check(prefix=f"{prefix}.curves[{i}]")
        rates = [c.strain_rate for c in curves]
        if any(b <= a for a, b in zip(rates, rates[1:], strict=False)):
            raise SpecError(f"{prefix}.curves.strain_rate", rates, "increasing strain rates")
        largest = max(c.strain[-1] for c in curves)
        scale = values["curve_strain_scale"]
        if scale * largest > MAX_CURVE_STRAIN:
            raise SpecError(
                f"{prefix}.curve_strain_scale", scale,
                f"at most {MAX_CURVE_STRAIN / largest:.6g}, so that the largest curve "
                f"strain, {largest:g}, scaled stays <= {MAX_CURVE_STRAIN}",
            )  # fmt: skip

    def effective_modulus(self, values: Mapping[str, float], curves: Sequence[FoamCurve]) -> float:
        """LS-DYNA's default contact and time-step modulus max(E, largest slope) (+ E_d) [Pa]."""
        slope = (values["curve_scale"] / values["curve_strain_scale"]) * max(
            c.max_slope() for c in curves
        )
        return max(values["youngs_modulus"], slope) + values.get("rate_modulus", 0.0)

    def kernel_constants(
        self, values: Mapping[str, float], curves: Sequence[FoamCurve] = ()
    ) -> np.ndarray:
        """The stand-ins the rest of the code reads from a law's constants, (4,):
        K = E_eff, the modulus LS-DYNA's foams use for contact (KCON, "stiffness for contact
        and time step"; the penalty formula takes it in place of the bulk modulus); G0 = 0, so
        that K + 4/3 G0 = E_eff sets the wave speed; G_inf = E_0 / 3 with E_0 the scaled first
        slope of the first curve, so that the relaxed Young's modulus 9 K G_inf / (3 K + G_inf)
        is about E_0 (the compression test's Hertz estimate); beta = 0."""
        if not curves:
            raise SpecError("material.curves", "none", f"the loading curve(s) of {self.name}")
        e_eff = self.effective_modulus(values, curves)
        first = curves[0]
        e_0 = (
            values["curve_scale"] * first.stress[1]
            / (values["curve_strain_scale"] * first.strain[1])
        )  # fmt: skip
        return np.array([e_eff, 0.0, e_0 / 3.0, 0.0], dtype=np.float64)

    def foam_table(self, values: Mapping[str, float], curves: Sequence[FoamCurve]) -> FoamTable:
        """Pack ``values`` and ``curves`` for :mod:`batball.elements.hex8_foam`."""
        self.check_curves(curves, values)
        params = np.zeros(N_FOAM_PARAMS)
        params[P_KIND] = self.kind
        params[P_E] = values["youngs_modulus"]
        params[P_TC] = values["tension_cutoff"]
        # MAT_083's HU = 0 means no damage: unloading on the first curve (Altair, MAT_083 page)
        params[P_HU] = values["hu"] if values["hu"] > 0.0 else 1.0
        params[P_SHAPE] = values["shape"]
        params[P_DAMP] = values["damp"]
        params[P_ED] = values.get("rate_modulus", 0.0)
        params[P_BETA1] = values.get("rate_decay", 0.0)
        params[P_MODULUS] = self.effective_modulus(values, curves)
        params[P_RATE_FILTER] = values.get("rate_filter", 0.0)
        n_max = max(len(c.strain) for c in curves)
        strains = np.empty((len(curves), n_max))
        stresses = np.empty((len(curves), n_max))
        for i, c in enumerate(curves):
            n = len(c.strain)
            strains[i, :n] = values["curve_strain_scale"] * np.asarray(c.strain)
            strains[i, n:] = strains[i, n - 1]
            stresses[i, :n] = values["curve_scale"] * np.asarray(c.stress)
            stresses[i, n:] = stresses[i, n - 1]
        energies = np.zeros(n_max)
        energies[1:] = np.cumsum(0.5 * (stresses[0, 1:] + stresses[0, :-1]) * np.diff(strains[0]))
        counts = np.array([len(c.strain) for c in curves], dtype=np.int64)
        rates = np.array([c.strain_rate for c in curves])
        return FoamTable(params, rates, strains, stresses, counts, energies)


MAT057 = FoamLaw(
    name="mat057",
    title="low-density urethane foam (LS-DYNA MAT_057)",
    lsdyna_keyword="*MAT_LOW_DENSITY_FOAM",
    parameters=MAT057_PARAMETERS,
    kind=KIND_MAT057,
    max_curves=1,
)

MAT083 = FoamLaw(
    name="mat083",
    title="Fu-Chang foam with rate effects, tabulated (LS-DYNA MAT_083, TBID)",
    lsdyna_keyword="*MAT_FU_CHANG_FOAM",
    parameters=MAT083_PARAMETERS,
    kind=KIND_MAT083,
    max_curves=16,
)

FOAM_LAWS: tuple[FoamLaw, ...] = (MAT057, MAT083)
