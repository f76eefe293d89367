"""The seed's Tables 5-8 (CCOR, DS, peak load, contact time) on the full 12,096-hex ball.

Targets against the seed's LS-DYNA ("FE") column, from the issue: CCOR within 0.01, DS and peak
load within 5 %, contact time within 10 %.

* Default model (LS-DYNA's default hourglass control, IHQ 1, QH 0.1): peak load, DS and contact
  time meet their targets; CCOR comes out 0.02-0.06 low. That miss is documented, with its study,
  in docs/notes/ball-impact.md (the viscous hourglass control absorbs ~2-4 % of the impact energy,
  which
  is 20-40 % of the little energy a CCOR ball gives back); it is marked as an expected failure,
  strict, so the day it passes the mark must go.
* The study's configuration with a light stiffness hourglass (IHQ 4, QM 0.01) meets all targets.
"""

import pytest

from batball.lab.impact import run_impact
from batball.models.impact import ImpactSetup
from batball.solvers.explicit import HourglassControl
from batball.specs import load_ball_spec
from batball.specs.seed import load_seed_tables

MPH = 0.44704
CASES = [("type1", 95), ("type1", 110), ("type2", 95), ("type2", 110)]
HOURGLASS = {
    "ihq1": HourglassControl(type=1, coefficient=0.1),
    "ihq4": HourglassControl(type=4, coefficient=0.01),
}
_RUNS: dict[tuple[str, int, str], object] = {}


def impact(ball: str, mph: int, hourglass: str):
    """Run each case once per session (the runs are the slow part)."""
    key = (ball, mph, hourglass)
    if key not in _RUNS:
        setup = ImpactSetup(
            test="ccor", speed=mph * MPH, divisions=12, hourglass=HOURGLASS[hourglass]
        )
        _RUNS[key] = run_impact(load_ball_spec(ball), setup).measures
    return _RUNS[key]


@pytest.mark.parametrize("hourglass", ["ihq1", "ihq4"])
@pytest.mark.parametrize(("ball", "mph"), CASES)
def test_peak_load_ds_and_contact_time_match_the_seed_ls_dyna(ball, mph, hourglass) -> None:
    seed = load_seed_tables().ball_impact(ball, mph)
    m = impact(ball, mph, hourglass)
    assert m.peak_force == pytest.approx(seed.peak_fe, rel=0.05)
    assert m.dynamic_stiffness == pytest.approx(seed.ds_fe, rel=0.05)
    assert m.contact_time == pytest.approx(seed.contact_fe, rel=0.10)


@pytest.mark.parametrize(("ball", "mph"), CASES)
def test_ccor_matches_the_seed_ls_dyna_with_light_stiffness_hourglass(ball, mph) -> None:
    seed = load_seed_tables().ball_impact(ball, mph)
    assert impact(ball, mph, "ihq4").restitution == pytest.approx(seed.ccor_fe, abs=0.01)


@pytest.mark.xfail(
    strict=True,
    reason="CCOR with viscous hourglass control is 0.02-0.06 below "
    "the seed's LS-DYNA; studied in docs/notes/ball-impact.md",
)
@pytest.mark.parametrize(("ball", "mph"), CASES)
def test_ccor_matches_the_seed_ls_dyna_with_default_hourglass(ball, mph) -> None:
    seed = load_seed_tables().ball_impact(ball, mph)
    assert impact(ball, mph, "ihq1").restitution == pytest.approx(seed.ccor_fe, abs=0.01)
