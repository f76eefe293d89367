"""A virtual DMA of a foam ball's material (MAT_057, MAT_083): E'(w), E''(w).

A foam truth ball (docs/notes/calibration-routes.md, "A foam truth") has no closed-form complex
modulus: its loading curve is nonlinear, it unloads on a damaged curve (HU, SHAPE) and MAT_057
adds a Maxwell rate stress (ED, BETA1). Its DMA data are therefore *measured*, as a lab would:
one material point, the foam's own update (:func:`batball.materials.foam_update.foam_stress`
and the element kernel's Maxwell recursion), driven in compression DMA

    e(t) = e_0 r(t)                       ramp to the static pre-strain e_0 (compression > 0),
    e(t) = e_0 + a sin(w t)               then ``cycles`` cycles of amplitude a,

with e the nominal compressive strain (F = diag(1 - e, 1, 1)). The foams have no lateral
coupling (zero Poisson's ratio), so this uniaxial strain is also a uniaxial stress state and
the compressive stress s(t) = -sigma_11 is what a compression DMA's load cell reads over the
specimen's area. The storage and loss moduli are the first harmonic of the last two cycles, by
least squares on s = c_0 + c_1 t + a (E' sin wt + E'' cos wt) (the linear term absorbs what is
left of the ramp's decaying rate stress; ASTM D4065's definitions of E', E'').

Not modelled: DAMP (LS-DYNA's viscous coefficient sigma_d = DAMP rho c L D scales with the
element length L: a mesh quantity a DMA specimen cannot measure; a foam with DAMP > 0 is a
``SpecError``), inertia of the specimen (a DMA runs far below its resonance).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numba as nb
import numpy as np

from batball.calibrate.dma import DmaData
from batball.errors import SpecError
from batball.materials.foam import P_BETA1, P_ED, FoamLaw
from batball.materials.foam_update import N_HISTORY, foam_stress
from batball.materials.viscoelastic import viscoelastic_step_factors
from batball.specs import MaterialSpec


@dataclass(frozen=True)
class DmaProtocol:
    """The virtual DMA's loading.

    Attributes:
        prestrain: static compressive nominal strain e_0 [-] (a compression DMA's preload).
        amplitude: dynamic strain amplitude a [-], < prestrain (the specimen stays in contact).
        cycles: cycles at each frequency (the last two are analysed), >= 3.
        steps_per_cycle: time steps per cycle, >= 32.
        ramp_time: duration of the smooth ramp to e_0 [s], long against the rate stress's
            1 / BETA1 so that it has relaxed before the cycles.
        ramp_steps: time steps of the ramp.
    """

    prestrain: float = 0.02
    amplitude: float = 0.002
    cycles: int = 6
    steps_per_cycle: int = 256
    ramp_time: float = 0.1
    ramp_steps: int = 4000

    def __post_init__(self) -> None:
        if not 0.0 < self.prestrain < 0.5:
            raise SpecError("dma.prestrain", self.prestrain, "a compressive strain 0 < e_0 < 0.5")
        if not 0.0 < self.amplitude < self.prestrain:
            raise SpecError("dma.amplitude", self.amplitude, f"0 < a < e_0 = {self.prestrain}")
        if self.cycles < 3 or self.steps_per_cycle < 32 or self.ramp_steps < 10:
            raise SpecError(
                "dma.cycles", (self.cycles, self.steps_per_cycle, self.ramp_steps),
                "cycles >= 3, steps_per_cycle >= 32, ramp_steps >= 10",
            )  # fmt: skip
        if not self.ramp_time > 0.0:
            raise SpecError("dma.ramp_time", self.ramp_time, "a ramp time > 0 s")


@nb.njit(cache=True)
def uniaxial_foam_response(
    strain: np.ndarray, times: np.ndarray, table: tuple[np.ndarray, ...]
) -> np.ndarray:
    """Compressive stress s = -sigma_11 [Pa], (n,), of one foam point driven along the
    compressive nominal strain history ``strain`` (n,) at ``times`` (n,) [s], strain[0] = 0:
    F = diag(1 - e, 1, 1); the foam stress plus MAT_057's Maxwell rate stress, advanced as the
    element kernel does (h <- exp(-beta dt) h + E_d (1 - exp(-beta dt)) / (beta dt) D dt)."""
    params = table[0]
    history = np.zeros(N_HISTORY)
    scratch = np.zeros((4, 3, 3))
    f = np.eye(3)
    d = np.zeros((3, 3))
    stress = np.zeros(strain.size)
    rate_stress = 0.0
    for n in range(1, strain.size):
        dt = times[n] - times[n - 1]
        stretch = 1.0 - strain[n]
        f[0, 0] = stretch
        # D_11 = d ln(lambda) / dt over the step (the midpoint rate of the element kernel)
        d[0, 0] = math.log(stretch / (1.0 - strain[n - 1])) / dt
        foam_stress(f, d, dt, history, table, scratch)
        decay, scale = viscoelastic_step_factors(0.5 * params[P_ED], 0.0, params[P_BETA1], dt)
        rate_stress = decay * rate_stress + scale * d[0, 0] * dt
        stress[n] = -(scratch[3][0, 0] + rate_stress)
    return stress


def _foam_table(material: MaterialSpec) -> tuple[np.ndarray, ...]:
    """The packed foam table of ``material``; SpecError for a non-foam or a DAMP > 0."""
    law = material.material_law
    if not isinstance(law, FoamLaw):
        raise SpecError("truth.material.law", material.law, "a foam (mat057, mat083) for a DMA")
    if material.values["damp"] != 0.0:
        raise SpecError(
            "truth.material.damp", material.values["damp"],
            "0 for a virtual DMA (DAMP scales with the element length, not a material property)",
        )  # fmt: skip
    return law.foam_table(material.values, material.curves).arrays()


def first_harmonic(
    times: np.ndarray, stress: np.ndarray, omega: float, amplitude: float
) -> tuple[float, float]:
    """(E', E'') [Pa] of s = c_0 + c_1 t + a (E' sin wt + E'' cos wt) by least squares over
    ``times`` (n,) [s], counted from the start of the oscillation e_0 + a sin(wt), and
    ``stress`` (n,) [Pa]."""
    t = times
    basis = np.column_stack([np.ones_like(t), t, np.sin(omega * t), np.cos(omega * t)])
    coefficients = np.linalg.lstsq(basis, stress, rcond=None)[0]
    return float(coefficients[2] / amplitude), float(coefficients[3] / amplitude)


def measure_foam_dma(
    material: MaterialSpec,
    frequencies_hz: Sequence[float],
    protocol: DmaProtocol | None = None,
) -> DmaData:
    """The compression (tensile-type) storage and loss moduli E', E'' [Pa] of a foam material at
    ``frequencies_hz`` by the virtual DMA of the module docstring; a fresh specimen per
    frequency. Returns them as :class:`DmaData` (read ``storage``/``loss`` as E', E''); a loss
    below zero by round-off (an elastic foam) is returned as 0."""
    p = protocol or DmaProtocol()
    table = _foam_table(material)
    n_ramp = p.ramp_steps
    ramp_t = np.linspace(0.0, p.ramp_time, n_ramp + 1)
    ramp_e = p.prestrain * 0.5 * (1.0 - np.cos(np.pi * ramp_t / p.ramp_time))
    storage, loss = [], []
    for f_hz in frequencies_hz:
        if not (np.isfinite(f_hz) and f_hz > 0.0):
            raise SpecError("dma.frequency", f_hz, "a frequency > 0 Hz")
        omega = 2.0 * math.pi * f_hz
        n_cycle = p.cycles * p.steps_per_cycle
        cycle_t = np.arange(1, n_cycle + 1) * (2.0 * math.pi / omega / p.steps_per_cycle)
        times = np.concatenate([ramp_t, p.ramp_time + cycle_t])
        strain = np.concatenate([ramp_e, p.prestrain + p.amplitude * np.sin(omega * cycle_t)])
        stress = uniaxial_foam_response(strain, times, table)
        last = slice(times.size - 2 * p.steps_per_cycle, times.size)
        e1, e2 = first_harmonic(times[last] - p.ramp_time, stress[last], omega, p.amplitude)
        storage.append(e1)
        loss.append(e2)
    omega_all = 2.0 * math.pi * np.asarray(frequencies_hz, dtype=np.float64)
    return DmaData(omega_all, np.array(storage), np.maximum(np.array(loss), 0.0))


__all__ = ["DmaProtocol", "first_harmonic", "measure_foam_dma", "uniaxial_foam_response"]
