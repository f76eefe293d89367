"""The virtual DMA of a foam truth (batball.calibrate.foam_dma, issue 12)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from batball.calibrate.dma import load_dma_csv, write_dma_csv
from batball.calibrate.foam_dma import DmaProtocol, first_harmonic, measure_foam_dma
from batball.errors import SpecError
from batball.specs import MaterialSpec, load_ball_spec

FOAM_TRUTH = (
    Path(__file__).resolve().parents[3]
    / "benchmarks" / "routes" / "synthetic-foam" / "true-ball.toml"
)  # fmt: skip
PSI = 6894.757293168361
# a short protocol: the ramp only has to outlast the rate stress (1 / BETA1 = 0.2 ms)
FAST = DmaProtocol(ramp_time=0.01, ramp_steps=1000, cycles=4, steps_per_cycle=128)


def _foam(**changes: float) -> MaterialSpec:
    material = load_ball_spec(FOAM_TRUTH).material
    return dataclasses.replace(material, values={**material.values, **changes})


def test_linear_foam_with_a_maxwell_term_has_the_standard_solid_moduli() -> None:
    """HU = 1 (no damage) and e_0 + a inside the curve's first, linear segment (slope
    E_0 = 3000 psi to 5 %): E' = E_0 + E_d' w^2 tau^2 / (1 + w^2 tau^2), E'' = E_d' w tau /
    (1 + w^2 tau^2), tau = 1 / BETA1, with E_d' = E_d / (1 - e_0) because the rate stress
    follows the true strain rate (first order in a). Tolerance 0.5 %: 1e-3 seen (128 steps a
    cycle, the O(a) variation of 1 / (1 - e))."""
    material = _foam(hu=1.0)
    f_hz = np.array([100.0, 800.0, 5000.0])
    data = measure_foam_dma(material, f_hz, FAST)
    wt = 2.0 * np.pi * f_hz / material.values["rate_decay"]
    e_d = material.values["rate_modulus"] / (1.0 - FAST.prestrain)
    np.testing.assert_allclose(data.storage, 3000.0 * PSI + e_d * wt**2 / (1 + wt**2), rtol=5e-3)
    np.testing.assert_allclose(data.loss, e_d * wt / (1 + wt**2), rtol=5e-3)


def _damaged_path_moduli(hu: float, shape: float, protocol: DmaProtocol) -> tuple[float, float]:
    """First harmonic of the steady cycle s(e) = (1 - D) f(e), D = (1 - HU)(1 - (W/W_max)^SHAPE),
    W = int_0^e f, W_max = W(e_0 + a), written from docs/notes/foams.md with np.interp (independent
    of the kernel)."""
    strain = np.array([0.0, 0.05, 0.1, 0.2]) * 1.0
    stress = np.array([0.0, 150.0, 240.0, 330.0]) * PSI
    e_fine = np.linspace(0.0, 0.2, 200_001)
    f_fine = np.interp(e_fine, strain, stress)
    w_fine = np.concatenate([[0.0], np.cumsum(0.5 * (f_fine[1:] + f_fine[:-1]) * np.diff(e_fine))])
    t = np.linspace(0.0, 1.0, 4096, endpoint=False)
    e = protocol.prestrain + protocol.amplitude * np.sin(2.0 * np.pi * t)
    w = np.interp(e, e_fine, w_fine)
    w_max = np.interp(protocol.prestrain + protocol.amplitude, e_fine, w_fine)
    s = (1.0 - (1.0 - hu) * (1.0 - (w / w_max) ** shape)) * np.interp(e, strain, stress)
    return first_harmonic(t, s, 2.0 * np.pi, protocol.amplitude)


def test_hysteretic_foam_without_rate_term_cycles_on_its_damaged_curve() -> None:
    """After the first cycle a MAT_057 point runs up and down the same damaged curve: no loop
    (E'' ~ 0) and a storage modulus several times the loading slope, as the closed-form path
    gives. Tolerance 0.5 % on E' (discretisation), E'' below 0.2 % of E'."""
    material = _foam(rate_modulus=0.0)
    data = measure_foam_dma(material, [50.0, 5000.0], FAST)
    expected, _ = _damaged_path_moduli(0.05, 2.0, FAST)
    np.testing.assert_allclose(data.storage, expected, rtol=5e-3)
    assert expected > 3.0 * 3000.0 * PSI
    assert np.all(data.loss < 2e-3 * data.storage)


def test_foam_dma_file_reads_back_as_shear_with_zero_poisson_ratio(tmp_path: Path) -> None:
    """The foam truth's compression moduli written as ``dma-tensile.csv`` and read with
    ``modulus="tensile", poisson_ratio=0`` give G* = E* / 2 (the foam's zero lateral coupling)."""
    data = measure_foam_dma(load_ball_spec(FOAM_TRUTH).material, [10.0, 1e3, 1e5], FAST)
    write_dma_csv(tmp_path / "dma-tensile.csv", data)
    shear = load_dma_csv(tmp_path / "dma-tensile.csv", modulus="tensile", poisson_ratio=0.0)
    np.testing.assert_allclose(shear.storage, data.storage / 2.0, rtol=1e-9)
    np.testing.assert_allclose(shear.loss, data.loss / 2.0, rtol=1e-9)
    assert np.all(np.diff(data.storage) > 0.0)  # the Maxwell term stiffens with frequency


def test_bad_dma_inputs_are_spec_errors() -> None:
    with pytest.raises(SpecError, match="truth.material.damp"):
        measure_foam_dma(_foam(damp=0.1), [10.0], FAST)
    with pytest.raises(SpecError, match="truth.material.law"):
        measure_foam_dma(load_ball_spec("type1").material, [10.0], FAST)
    with pytest.raises(SpecError, match="dma.amplitude"):
        DmaProtocol(prestrain=0.02, amplitude=0.03)
    with pytest.raises(SpecError, match="dma.frequency"):
        measure_foam_dma(load_ball_spec(FOAM_TRUTH).material, [-1.0], FAST)


def test_foam_truth_round_trips_through_the_synthetic_data_files(tmp_path: Path) -> None:
    """measure_synthetic on the foam truth (4-division ball): the impact targets load, the DMA
    is written as ``dma-tensile.csv`` and reads back; its storage modulus rises from 10 Hz to
    1 MHz by the Maxwell term's E_d / (1 - e_0) less its share already present at 10 Hz
    (E_d' (w tau)^2 / (1 + (w tau)^2)): the hysteresis adds the same to both ends. 0.1 %."""
    from batball.calibrate import load_targets
    from batball.calibrate.routes import DMA_TENSILE, SYNTHETIC_DMA_HZ, measure_synthetic

    truth = load_ball_spec(FOAM_TRUTH)
    paths = measure_synthetic(truth, tmp_path, divisions=4)
    assert paths["dma"].name == DMA_TENSILE
    assert {t.quantity for t in load_targets(paths["ccor"])} == {
        "ccor", "dynamic_stiffness", "peak_force", "contact_time"
    }  # fmt: skip
    assert all(0.1 < t.value < 0.7 for t in load_targets(paths["cor"]) if t.quantity == "cor")
    data = load_dma_csv(paths["dma"], modulus="tensile", poisson_ratio=0.0)
    e_d = truth.material.values["rate_modulus"] / (1.0 - DmaProtocol().prestrain)
    wt = 2.0 * np.pi * SYNTHETIC_DMA_HZ[0] / truth.material.values["rate_decay"]
    rise = 2.0 * (data.storage[-1] - data.storage[0])  # back from G = E / 2
    assert rise == pytest.approx(e_d / (1.0 + wt**2), rel=1e-3)
    assert "[[bbs]]" not in paths["bbs"].read_text()
