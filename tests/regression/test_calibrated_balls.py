"""The calibrated balls (benchmarks/calibration/<ball>-<model>.toml, written by
``batball calibrate --save``) against the seed's Tables 5-8 on the full 12,096-hex ball.

Issue 4: every cell at least as close to the experiment as the seed's LS-DYNA column, except the
ones docs/calibration.md lists as not reached (type 1's CCOR at 95 mph with MAT_006: the one-term
model cannot follow CCOR's fall with speed; see the trade-off there). The same for the MAT_057
foam balls fitted on this mesh (``<ball>-mat057-12div``, docs/notes/foams.md "The fine stage for
MAT_057"): type 1's CCOR at 95 mph for the same reason, and type 2's CCORs, which the seed's
LS-DYNA had within 0.9 % and the foam within 1.1 %. And the type-2 foam refitted with its curve
densifying later (``type2-mat057-sfa14``, docs/notes/foams.md "The loading curve's shape"): every
cell
within the calibration goal (CCOR 1 %, peak force 3 %, DS and contact time 5 %), its CCORs
(-0.9 / +0.9 %) still a little farther than the seed's LS-DYNA (-0.9 / -0.7 %).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from batball.calibrate.targets import QUANTITIES as TARGET_QUANTITIES
from batball.lab.impact import run_impact
from batball.models.impact import ImpactSetup
from batball.specs import load_ball_spec
from batball.specs.seed import load_seed_tables

MPH = 0.44704
FITTED = Path(__file__).resolve().parents[2] / "benchmarks" / "calibration"
QUANTITIES = {
    "ccor": ("restitution", "ccor"),
    "dynamic_stiffness": ("dynamic_stiffness", "ds"),
    "peak_force": ("peak_force", "peak"),
    "contact_time": ("contact_time", "contact"),
}
#: (fit, ball, speed, quantity) cells the fit does not bring closer than the seed's LS-DYNA.
NOT_REACHED = {
    ("type1-mat006", 95, "ccor"),
    ("type1-mat057-12div", 95, "ccor"),
    ("type2-mat057-12div", 95, "ccor"),
    ("type2-mat057-12div", 110, "ccor"),
    ("type2-mat057-sfa14", 95, "ccor"),
    ("type2-mat057-sfa14", 110, "ccor"),
}
_RUNS: dict[tuple[str, int], object] = {}


def measures(fit: str, mph: int):
    if (fit, mph) not in _RUNS:
        setup = ImpactSetup(test="ccor", speed=mph * MPH, divisions=12)
        _RUNS[fit, mph] = run_impact(load_ball_spec(FITTED / f"{fit}.toml"), setup).measures
    return _RUNS[fit, mph]


@pytest.mark.slow
@pytest.mark.parametrize("quantity", list(QUANTITIES))
@pytest.mark.parametrize("mph", [95, 110])
@pytest.mark.parametrize(
    "fit",
    [
        "type1-mat006",
        "type2-mat006",
        "type1-mat057-12div",
        "type2-mat057-12div",
        "type2-mat057-sfa14",
    ],
)
def test_calibrated_ball_is_as_close_to_the_experiment_as_the_seed(fit, mph, quantity) -> None:
    attribute, column = QUANTITIES[quantity]
    row = load_seed_tables().ball_impact(fit.split("-")[0], mph)
    experiment, seed = getattr(row, f"{column}_exp"), getattr(row, f"{column}_fe")
    batball = getattr(measures(fit, mph), attribute)
    closer = abs(batball - experiment) <= abs(seed - experiment)
    if (fit, mph, quantity) in NOT_REACHED:
        assert not closer, "reached now: remove it from NOT_REACHED and docs/calibration.md"
    else:
        assert closer, f"{batball:.5g} vs experiment {experiment:.5g}, seed {seed:.5g}"


@pytest.mark.slow
@pytest.mark.parametrize("quantity", list(QUANTITIES))
@pytest.mark.parametrize("mph", [95, 110])
def test_type2_foam_with_later_densification_meets_every_goal(mph, quantity) -> None:
    attribute, column = QUANTITIES[quantity]
    experiment = getattr(load_seed_tables().ball_impact("type2", mph), f"{column}_exp")
    batball = getattr(measures("type2-mat057-sfa14", mph), attribute)
    error = (batball - experiment) / experiment
    # the calibration goals of issues 4 and 5 (CCOR 1 %, peak 3 %, DS and contact time 5 %)
    goal = TARGET_QUANTITIES[quantity].tolerance
    assert abs(error) <= goal, f"{100 * error:+.2f} % of {experiment:.5g}"
