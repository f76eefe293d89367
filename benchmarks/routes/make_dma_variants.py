"""Less ideal DMA data of the synthetic true ball (docs/notes/calibration-routes.md, issue 12).

Writes, next to the exact ``synthetic/dma.csv``:

* ``synthetic/dma-noisy-10hz-10khz.csv``: 13 frequencies, 10 Hz to 10 kHz (three decades, what
  a DMA reaches without time-temperature superposition), storage and loss each with 2 %
  Gaussian relative noise (seed 12). The impact's time scale (contact ~1 ms, the truth's fast
  term beta 7.2e5 1/s) lies above that window.

Run: ``PYTHONPATH=src python benchmarks/routes/make_dma_variants.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from batball.calibrate.dma import DmaData, write_dma_csv
from batball.calibrate.routes import exact_dma
from batball.specs import load_ball_spec

HERE = Path(__file__).resolve().parent / "synthetic"


def main() -> None:
    truth = load_ball_spec(HERE / "true-ball.toml")
    exact = exact_dma(truth, np.logspace(1.0, 4.0, 13))
    rng = np.random.default_rng(12)
    noisy = DmaData(
        exact.omega,
        exact.storage * (1.0 + 0.02 * rng.standard_normal(exact.omega.size)),
        exact.loss * (1.0 + 0.02 * rng.standard_normal(exact.omega.size)),
    )
    write_dma_csv(HERE / "dma-noisy-10hz-10khz.csv", noisy, unit="psi")


if __name__ == "__main__":
    main()
