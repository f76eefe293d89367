"""The DMA route's Prony fit (issue 12): recovery of a known model from its exact moduli, the
unit handling of the CSV, and the tensile-to-shear conversion."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from batball.calibrate.dma import (
    DmaData,
    dma_ball,
    fit_prony,
    load_dma_csv,
    prony_moduli,
    solve_moduli,
    tensile_to_shear,
    write_dma_csv,
)
from batball.errors import SpecError
from batball.specs import load_ball_spec

PSI = 6894.757293168361
# A 3-term truth: the type-1 ball's prony3 calibration (benchmarks/calibration/type1-prony3.toml)
G_INF = 1006.30592039 * PSI
MODULI = np.array([1695.39560021, 13186.6221867, 1787.2504889]) * PSI
BETAS = np.array([718456.726241, 58302.3928116, 24757.13337])  # 1/s
TAU = 1.0 / BETAS


def exact(omega: np.ndarray) -> DmaData:
    """The truth's G', G'' from the closed form written out here, independently of the code."""
    wt = omega[:, None] * TAU[None, :]
    storage = G_INF + (MODULI * wt**2 / (1 + wt**2)).sum(axis=1)
    loss = (MODULI * wt / (1 + wt**2)).sum(axis=1)
    return DmaData(omega, storage, loss)


def test_closed_form_moduli_match_a_single_maxwell_branch() -> None:
    """One term at w = 1/tau: G' = G_inf + G/2 and G'' = G/2 (the loss peak of a Maxwell
    branch, Bergström 2005 eqs. 5-6); exact to round-off."""
    storage, loss = prony_moduli(np.array([1e4]), 2.0, np.array([6.0]), np.array([1e-4]))
    assert storage[0] == pytest.approx(5.0, rel=1e-14)
    assert loss[0] == pytest.approx(3.0, rel=1e-14)


def test_nnls_recovers_the_moduli_when_the_relaxation_times_are_known() -> None:
    """The closed-form (linear) step alone: exact data, the truth's tau -> the truth's G_inf,
    G_i. Tolerance 1e-9: a least-squares solve of exact data loses only the conditioning of
    the scaled 62 x 4 design matrix (about 1e3 here) times round-off."""
    data = exact(np.logspace(2, 7, 31))
    order = np.argsort(TAU)
    x, norm = solve_moduli(data, TAU[order])
    assert x[0] == pytest.approx(G_INF, rel=1e-9)
    np.testing.assert_allclose(x[1:], MODULI[order], rtol=1e-9)
    assert norm < 1e-12


@pytest.mark.parametrize("decades", [(2, 7), (1, 5)])
def test_fit_recovers_a_known_three_term_model(decades: tuple[int, int]) -> None:
    """From log-spaced starting tau (not the truth's), the refined fit recovers all 7
    parameters. Tolerance 1e-6 relative: the data are exact, so the truth is the global minimum
    with a zero residual; what is left is the search's stopping tolerance (1e-14 on the steps)
    amplified by the ill-conditioning of two terms only 2.4x apart in beta; 1e-13 is seen. The
    second range, 1-1e5 rad/s, puts the fastest term (beta 7.2e5 1/s) above every frequency
    measured: still found, because the data are exact (with noise it would not be)."""
    data = exact(np.logspace(*decades, 31))
    fit = fit_prony(data, 3)
    order = np.argsort(TAU)
    assert fit.g_inf == pytest.approx(G_INF, rel=1e-6)
    np.testing.assert_allclose(fit.moduli, MODULI[order], rtol=1e-6)
    np.testing.assert_allclose(fit.betas, BETAS[order], rtol=1e-6)
    assert fit.rms_relative < 1e-9


def test_one_term_fit_of_three_term_data_is_the_best_single_term_not_exact() -> None:
    """A 1-term fit cannot be exact: its residual is finite, and its G0 = G_inf + G_1 lies
    between the truth's G_inf and G0 (storage rises monotonically between them)."""
    fit = fit_prony(exact(np.logspace(2, 7, 31)), 1)
    assert fit.rms_relative > 1e-3
    assert G_INF < fit.g_inf + fit.moduli[0] < G_INF + MODULI.sum()


def test_csv_round_trip_with_units_and_ball(tmp_path: Path) -> None:
    """psi in the file, Pa in the data; the ball keeps the base ball's size, mass and K."""
    data = exact(np.logspace(2, 7, 21))
    path = tmp_path / "dma.csv"
    write_dma_csv(path, data, unit="psi")
    assert path.read_text().splitlines()[0] == "frequency_hz,storage_psi,loss_psi"
    back = load_dma_csv(path, modulus="shear")
    np.testing.assert_allclose(back.omega, data.omega, rtol=1e-9)
    np.testing.assert_allclose(back.storage, data.storage, rtol=1e-9)
    base = load_ball_spec("type1")
    ball, fit = dma_ball(base, back)
    assert ball.material.law == "prony3"
    assert ball.mass == base.mass
    assert ball.material.values["bulk_modulus"] == base.material.values["bulk_modulus"]
    assert ball.material.values["g_inf"] == pytest.approx(G_INF, rel=1e-6)


def test_tan_delta_and_mpa_columns(tmp_path: Path) -> None:
    """tan delta = G''/G' and MPa / rad/s units give the same shear data."""
    data = exact(np.logspace(3, 6, 5))
    path = tmp_path / "dma.csv"
    lines = ["Frequency_rad_s,Storage_MPa,tan_delta"]
    lines += [f"{w:.17g},{s / 1e6:.17g},{g2 / s:.17g}" for w, s, g2 in
              zip(data.omega, data.storage, data.loss, strict=True)]  # fmt: skip
    path.write_text("\n".join(lines) + "\n")
    back = load_dma_csv(path, modulus="shear")
    np.testing.assert_allclose(back.loss, data.loss, rtol=1e-12)
    np.testing.assert_allclose(back.omega, data.omega, rtol=1e-12)


@pytest.mark.parametrize(
    ("header", "field"),
    [
        ("frequency_hz,storage_psx,loss_psi", "dma.storage_psx"),
        ("frequency_rpm,storage_psi,loss_psi", "dma.frequency_rpm"),
        ("frequency_hz,storage_psi,loss_N", "dma.loss_N"),
        ("frequency_hz,storage_psi", "dma.loss"),
    ],
)
def test_bad_units_are_rejected_naming_the_column(tmp_path: Path, header: str, field: str
                                                  ) -> None:  # fmt: skip
    path = tmp_path / "dma.csv"
    path.write_text(header + "\n1,2,3\n10,20,3\n")
    with pytest.raises(SpecError) as info:
        load_dma_csv(path, modulus="shear")
    assert info.value.field == field


def test_negative_storage_and_unknown_kind_rejected(tmp_path: Path) -> None:
    path = tmp_path / "dma.csv"
    path.write_text("frequency_hz,storage_psi,loss_psi\n1,2,3\n10,-20,3\n")
    with pytest.raises(SpecError) as info:
        load_dma_csv(path, modulus="shear")
    assert info.value.field == "dma[1].storage_psi"
    with pytest.raises(SpecError, match="dma-modulus"):
        load_dma_csv(path, modulus="bulk")


def test_tensile_to_shear_inverts_the_elastic_bulk_relation() -> None:
    """E* = 9 K G* / (3 K + G*) (isotropic, elastic K) built here, converted back: G* to
    round-off. With nu instead, G = E / (2 (1 + nu)) for an elastic solid (E 2.6, nu 0.3 ->
    G 1)."""
    shear = exact(np.logspace(2, 7, 9))
    k = 243461.269523 * PSI
    g_star = shear.storage + 1j * shear.loss
    e_star = 9 * k * g_star / (3 * k + g_star)
    back = tensile_to_shear(DmaData(shear.omega, e_star.real, e_star.imag), bulk_modulus=k)
    np.testing.assert_allclose(back.storage, shear.storage, rtol=1e-12)
    np.testing.assert_allclose(back.loss, shear.loss, rtol=1e-10)
    elastic = tensile_to_shear(DmaData(np.ones(1), np.array([2.6]), np.zeros(1)),
                               poisson_ratio=0.3)  # fmt: skip
    assert elastic.storage[0] == pytest.approx(1.0, rel=1e-14)
    with pytest.raises(SpecError, match="poisson-ratio"):
        tensile_to_shear(shear, poisson_ratio=0.5)
    assert math.isfinite(back.storage.sum())
