"""The BBS test's ball-bat contact against the impact lab's analytic cylinder.

Held still and rigid (``fixed_bat``), the bat is a target like the F2845 cylinder, only faceted
and 2.25 in across at the impact point instead of 2.63 in. So the ball's restitution off it must
be the impact lab's CCOR run with a 2.25-in rigid cylinder: the same ball mesh, material,
hourglass and contact stiffness, but an analytic surface instead of the bat's shells with their
thickness offsets and the segment contact both ways.

Measured (docs/notes/bbs.md, "Held bat against the cylinder"): 8-division ball, 110 mph, 32 x 0.2-in
bat: type 2 0.4250 against 0.4261 (type 1 0.3075 against 0.3083); 48 x 0.1 in: 0.4248. The
32-gon's flats lie 0.005 in inside the circle and the contact patch spans a few facets, so
0.005 is allowed (the 2.63-in cylinder's CCOR is 0.007 lower, so the test also tells the two
diameters apart).
"""

from __future__ import annotations

import pytest

from batball.lab.bbs import run_bbs
from batball.lab.impact import run_impact
from batball.models.bbs import BbsSetup
from batball.models.impact import ImpactSetup
from batball.specs import load_ball_spec, load_bat_spec

IN = 0.0254
MPH = 0.44704


def test_held_bat_restitution_is_the_cylinder_ccor_of_its_diameter() -> None:
    bat, ball = load_bat_spec("default"), load_ball_spec("type2")
    impact_x = bat.length - 6.0 * IN
    diameter = 2.0 * float(bat.outer_radius(impact_x))
    assert diameter == pytest.approx(2.25 * IN)
    cylinder = run_impact(ball, ImpactSetup(test="ccor", speed=110 * MPH, divisions=8,
                                            cylinder_diameter=diameter))  # fmt: skip
    held = run_bbs(bat, ball, BbsSetup(speed=110 * MPH, ball_divisions=8, circumferential=32,
                                       axial_size=0.2 * IN, fixed_bat=True))  # fmt: skip
    assert not held.run.column("bat_omega_rad_s").any()  # held still
    assert held.measures.collision_efficiency == pytest.approx(cylinder.measures.restitution,
                                                               abs=0.005)  # fmt: skip
