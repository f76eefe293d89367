"""The modal solver gives the same modes for the same model, bit for bit (a seeded Lanczos start;
ARPACK's own random start moved the hoop frequencies by ~5e-7 between runs, which a fit that replays
stored evaluations cannot tell from a change of the bat)."""

from __future__ import annotations

import numpy as np

from batball.lab.modal import bat_modes
from batball.specs import load_bat_spec

IN = 0.0254


def test_the_same_bat_gives_the_same_modes_bit_for_bit() -> None:
    spec = load_bat_spec("default")
    runs = [bat_modes(spec, circumferential=8, axial_size=1.0 * IN, n_modes=14, insert="contact")
            for _ in range(3)]  # fmt: skip
    for again in runs[1:]:
        assert np.array_equal(again.frequencies, runs[0].frequencies)
