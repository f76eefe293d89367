"""A foam ball (MAT_057, issue 5) in the batted-ball-speed test runs on the foam kernel.

Before this, the ball-bat solver fed a foam ball's contact stand-in constants (G0 = 0) to the
MAT_006 kernel, and every foam BBS run blew up (energy balance +500 % and more, issue 12's
report). Checked here on coarse meshes:

* the energy balance closes to 1 % of the initial kinetic energy, bat held still or on a rigid
  pivot (the same bound as the viscoelastic ball's, tests/verification/test_bbs_pivot.py), and the
  ball leaves at a steady speed;
* a rigid bat on its pivot should conserve the angular momentum about the pivot through the
  impact as for the viscoelastic ball (1e-5 there); the foam ball misses it (7.4e-5), a strict
  xfail until explained.

Measured beside these (docs/bbs.md), not asserted: the held bat gives e_A 0.715 where the impact
lab's CCOR of the same ball and mesh is 0.723 (for the MAT_006 balls the two differ by -0.025 and
-0.098 on these meshes, so no tolerance for it follows from them); at the 24-in pivot
(k = 0.03) e_A is 0.656 against (e - k) / (1 + k) = 0.663, where the viscoelastic ball meets the
relation to 0.005 (this foam stays in contact 2.2 ms, twice as long).
"""

from __future__ import annotations

import pytest

from batball.lab.bbs import BbsResult, BbsSetup, run_bbs
from batball.solvers.explicit import HourglassControl
from batball.specs import load_ball_spec, load_bat_spec

IN = 0.0254
#: As test_bbs_pivot's coarse runs; the soft foam stays in contact about 2.2 ms at 110 mph.
COARSE = {"ball_divisions": 4, "circumferential": 12, "axial_size": 0.75 * IN,
          "separation_time": 0.05e-3, "hourglass": HourglassControl(type=5),
          "end_time": 3e-3}  # fmt: skip


@pytest.fixture(scope="module")
def runs() -> dict[str, BbsResult]:
    bat, ball = load_bat_spec("default"), load_ball_spec("foam057")
    setups = {
        "fixed": BbsSetup(fixed_bat=True, **COARSE),
        "rigid_24in": BbsSetup(rigid_bat=True, pivot_from_knob=24.0 * IN, **COARSE),
    }
    return {name: run_bbs(bat, ball, setup) for name, setup in setups.items()}


@pytest.mark.parametrize("name", ["fixed", "rigid_24in"])
def test_energy_balance_closes_and_the_ball_rebounds(
    runs: dict[str, BbsResult], name: str
) -> None:
    m = runs[name].measures
    assert m.energy_balance_error < 0.01
    assert m.rebound_drift < 1e-6 * m.inbound_speed
    assert 0.0 < m.collision_efficiency < 1.0


@pytest.mark.xfail(
    strict=True,
    reason="known, not yet explained: the foam ball on a rigid pivoted bat changes the angular "
    "momentum about the pivot by 7.4e-5 of itself (the MAT_006 ball: 2e-7); docs/bbs.md",
)
def test_rigid_bat_conserves_angular_momentum_about_the_pivot(
    runs: dict[str, BbsResult],
) -> None:
    assert runs["rigid_24in"].measures.angular_momentum_change < 1e-5
