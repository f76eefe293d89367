"""A foam ball (MAT_057, issue 5) in the batted-ball-speed test runs on the foam kernel.

Before this, the ball-bat solver fed a foam ball's contact stand-in constants (G0 = 0) to the
MAT_006 kernel, and every foam BBS run blew up (energy balance +500 % and more, issue 12's
report). Checked here on coarse meshes:

* the energy balance closes to 1 % of the initial kinetic energy, bat held still or on a rigid
  pivot (the same bound as the viscoelastic ball's, tests/verification/test_bbs_pivot.py), and the
  ball leaves at a steady speed;
* a rigid bat on the seed's pivot conserves the angular momentum about the pivot through the
  impact to the viscoelastic ball's bound (1e-5, tests/verification/test_bbs_pivot.py; measured
  1.9e-6 for the foam, 2.3e-7 for MAT_006), and a spinning, squashed foam ball in free flight
  keeps its angular momentum to round-off (the foam kernel's forces have no net moment).

Open (docs/notes/bbs.md): at a pivot 24 in from the knob the foam ball changes the angular momentum
by 7.4e-5 of itself (MAT_006: 3.3e-7). The lever is 4 in there against 22 in at the seed's
pivot, which makes a given absolute error 5.5 times larger relative to L; the rest is not
explained. The free-flight check points at the contact on the strongly deformed ball surface
rather than the foam kernel.

Measured beside these (docs/notes/bbs.md), not asserted: the held bat gives e_A 0.715 where the
impact
lab's CCOR of the same ball and mesh is 0.723 (for the MAT_006 balls the two differ by -0.025 and
-0.098 on these meshes, so no tolerance for it follows from them); at the 24-in pivot
(k = 0.03) e_A is 0.656 against (e - k) / (1 + k) = 0.663, where the viscoelastic ball meets the
relation to 0.005 (this foam stays in contact 2.2 ms, twice as long).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from batball.lab.bbs import BbsResult, run_bbs
from batball.models.bbs import BbsSetup
from batball.models.impact import ImpactSetup, build_impact_model
from batball.solvers.explicit import ExplicitControls, ExplicitSolver, HourglassControl
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
        "rigid": BbsSetup(rigid_bat=True, **COARSE),
    }
    return {name: run_bbs(bat, ball, setup) for name, setup in setups.items()}


@pytest.mark.parametrize("name", ["fixed", "rigid"])
def test_energy_balance_closes_and_the_ball_rebounds(
    runs: dict[str, BbsResult], name: str
) -> None:
    m = runs[name].measures
    assert m.energy_balance_error < 0.01
    assert m.rebound_drift < 1e-6 * m.inbound_speed
    assert 0.0 < m.collision_efficiency < 1.0


def test_rigid_bat_conserves_angular_momentum_about_the_pivot(
    runs: dict[str, BbsResult],
) -> None:
    assert runs["rigid"].measures.angular_momentum_change < 1e-5


def test_spinning_foam_ball_keeps_its_angular_momentum_in_free_flight() -> None:
    setup = ImpactSetup(test="ccor", speed=1.0, divisions=4)  # the ball only: no contact below
    model = build_impact_model(load_ball_spec("foam057"), setup)
    x = model.mesh.points - model.mesh.points.mean(axis=0)
    squash = 30.0 * x / np.linalg.norm(x, axis=1).max() * np.array([1.0, -1.0, 0.5])  # [m/s]
    v = np.cross([0.0, 0.0, 300.0], x) + squash
    model = dataclasses.replace(model, contacts=(), initial_velocity=v)
    solver = ExplicitSolver(model, ExplicitControls(end_time=1.0, hourglass=HourglassControl(5)))
    m = solver.work.mass[:, None]
    l0 = (m * np.cross(model.mesh.points, v)).sum(axis=0)
    for _ in range(1500):
        solver.cycle()
    s = solver.state
    # leapfrog: L at n - 1/2 is m (x^n - dt/2 v^(n-1/2)) x v^(n-1/2)
    l1 = (m * np.cross(s.points - 0.5 * s.dt * s.velocities, s.velocities)).sum(axis=0)
    assert np.linalg.norm(l1 - l0) < 1e-12 * np.linalg.norm(l0)
