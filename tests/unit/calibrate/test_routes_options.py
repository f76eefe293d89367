"""Options of compare-calibrations and synthetic-data added for the noise and foam studies."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from batball.calibrate.routes_command import _bbs_setup, measured_bbs
from batball.errors import SpecError


def _args(**overrides: object) -> argparse.Namespace:
    defaults: dict[str, object] = {
        "measured_bbs": None, "divisions": 8, "time_step_scale": 0.9, "circumferential": 16,
        "axial_size": "0.4 in", "pivot": "6 in", "end_time": "2 ms",
    }  # fmt: skip
    return argparse.Namespace(**{**defaults, **overrides})


def test_measured_bbs_none_drops_the_seed_table() -> None:
    """Without the option a seed ball is compared with Table 9 (96.5 and 97.0 mph for type 1);
    'none' compares with nothing (a synthetic truth whose BBS is not known)."""
    table9 = measured_bbs(_args(), "type1", [95.0, 110.0])
    assert table9 == {95.0: pytest.approx(96.5), 110.0: pytest.approx(97.0)}
    assert measured_bbs(_args(measured_bbs=Path("none")), "type1", [95.0, 110.0]) == {}


def test_time_step_scale_reaches_the_bbs_setup_and_is_checked() -> None:
    assert _bbs_setup(_args(time_step_scale=0.6)).time_step_scale == 0.6
    with pytest.raises(SpecError, match="time-step-scale"):
        _bbs_setup(_args(time_step_scale=1.5))
