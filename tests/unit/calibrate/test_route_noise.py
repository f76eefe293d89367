"""Seeded measurement noise on the synthetic route data (batball.calibrate.noise, issue 12)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from batball.calibrate.dma import DmaData, load_dma_csv
from batball.calibrate.noise import NoiseLevels, perturb_dma, perturb_targets, write_noisy_data
from batball.calibrate.targets import Target, load_targets
from batball.cli import main
from batball.errors import SpecError

SYNTHETIC = Path(__file__).resolve().parents[3] / "benchmarks" / "routes" / "synthetic"
MPH = 0.44704
N_DRAWS = 4000
# the sample sd of n normal draws has a relative sd of 1/sqrt(2 (n - 1)) = 1.1 % at n = 4000;
# 5 % is 4.5 of those; the sample mean's sd is sd/sqrt(n), held to 4 of those
SD_RTOL = 0.05


def _levels_seen(values: np.ndarray, centre: float, relative: bool) -> tuple[float, float]:
    """(mean offset, sd) of draws about ``centre``, relative to it if ``relative``."""
    offsets = (values - centre) / centre if relative else values - centre
    return float(offsets.mean()), float(offsets.std(ddof=1))


@pytest.mark.parametrize(
    ("quantity", "value", "relative", "expected_sd"),
    [
        ("ccor", 0.37, False, 0.005),  # absolute on a restitution
        ("cor", 0.33, False, 0.005),
        ("dynamic_stiffness", 1.2e6, True, 0.025),  # relative on forces and stiffness
        ("wall_peak_force", 2.4e4, True, 0.025),
        ("contact_time", 1.1e-3, True, 0.025),
    ],
)
def test_target_noise_has_the_stated_spread(
    quantity: str, value: float, relative: bool, expected_sd: float
) -> None:
    targets = [Target(quantity, 95.0 * MPH, value)] * N_DRAWS
    noisy = perturb_targets(targets, NoiseLevels(), np.random.default_rng(7))
    mean, sd = _levels_seen(np.array([t.value for t in noisy]), value, relative)
    assert sd == pytest.approx(expected_sd, rel=SD_RTOL)
    assert abs(mean) < 4.0 * expected_sd / np.sqrt(N_DRAWS)
    assert all(t.quantity == quantity and t.speed == 95.0 * MPH for t in noisy)


def test_dma_noise_is_relative_with_the_stated_spread() -> None:
    omega = np.full(N_DRAWS, 100.0)
    data = DmaData(omega, np.full(N_DRAWS, 7e7), np.full(N_DRAWS, 3e6))
    noisy = perturb_dma(data, 0.05, np.random.default_rng(3))
    for values, centre in ((noisy.storage, 7e7), (noisy.loss, 3e6)):
        mean, sd = _levels_seen(values, centre, relative=True)
        assert sd == pytest.approx(0.05, rel=SD_RTOL)
        assert abs(mean) < 4.0 * 0.05 / np.sqrt(N_DRAWS)
    np.testing.assert_array_equal(noisy.omega, omega)


def test_noisy_copies_are_reproducible_and_differ_by_seed(tmp_path: Path) -> None:
    """The same seed writes the same files; another seed other values; the BBS is copied as is
    and every noisy value lies within 5 sd of the exact one."""
    levels = NoiseLevels()
    a = write_noisy_data(SYNTHETIC, tmp_path / "a", seed=11, levels=levels)
    b = write_noisy_data(SYNTHETIC, tmp_path / "b", seed=11, levels=levels)
    c = write_noisy_data(SYNTHETIC, tmp_path / "c", seed=12, levels=levels)
    for name in ("cor", "ccor", "dma", "bbs"):
        assert a[name].read_bytes() == b[name].read_bytes()
    assert a["ccor"].read_bytes() != c["ccor"].read_bytes()
    assert a["bbs"].read_bytes() == (SYNTHETIC / "bbs.toml").read_bytes()
    for name in ("cor", "ccor"):
        exact = load_targets(SYNTHETIC / f"{name}-targets.toml")
        for t0, t1 in zip(exact, load_targets(a[name]), strict=True):
            sd = levels.standard_deviation(t0.quantity)
            scale = 1.0 if t0.quantity in ("cor", "ccor") else t0.value
            assert (t0.quantity, t0.speed) == (t1.quantity, t1.speed)
            assert 0.0 < abs(t1.value - t0.value) < 5.0 * sd * scale
    exact_dma = load_dma_csv(SYNTHETIC / "dma.csv", modulus="shear")
    noisy_dma = load_dma_csv(a["dma"], modulus="shear")
    assert np.all(np.abs(noisy_dma.storage / exact_dma.storage - 1.0) < 5.0 * levels.dma)
    assert "seed = 11" in a["noise"].read_text()


def test_noise_command_writes_one_folder_per_seed(tmp_path: Path) -> None:
    code = main(["synthetic-noise", "--source", str(SYNTHETIC), "--out", str(tmp_path),
                 "--seeds", "1", "2", "--dma-sd", "0.02"])  # fmt: skip
    assert code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["seed-1", "seed-2"]
    assert "dma = 0.02" in (tmp_path / "seed-2" / "noise.toml").read_text()


def test_bad_levels_and_source_are_spec_errors(tmp_path: Path) -> None:
    with pytest.raises(SpecError, match="noise.dma"):
        NoiseLevels(dma=-0.01)
    with pytest.raises(SpecError, match="noise.restitution"):
        NoiseLevels(restitution=float("nan"))
    with pytest.raises(SpecError, match="noise.source"):
        write_noisy_data(tmp_path / "missing", tmp_path / "out", seed=1, levels=NoiseLevels())
