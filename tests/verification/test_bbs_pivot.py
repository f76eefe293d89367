"""The batted-ball-speed test against rigid-body mechanics (docs/physics.md section 4.1).

A bat that is a rigid body on the pivot recoils with V = k (v_in + v_out) (angular momentum about
the pivot), so e_A = (e - k) / (1 + k) with e the ball's COR on that target held still (k = 0:
the same ball, mesh, contact and bat surface, the bat fixed). The relation holds exactly for a
ball whose COR does not depend on the collision; a real (viscoelastic, vibrating) ball's COR
does depend on how long the contact lasts, and the contact on a recoiling bat is shorter. So:

* with the pivot moved to 24 in from the knob (k = 0.03) the relation must hold to 0.005 (there
  the recoil hardly changes the contact);
* at the seed's pivot (k = 0.45 on this coarse ball) the measured BBCOR e_A (1 + k) + k lies
  below the held-still COR by the duration effect, measured at 0.02-0.05 on these meshes for
  an elastic and a viscoelastic ball alike and shrinking with k (docs/notes/bbs.md), so the bound is
  0.06, and it is checked against the independent route through the bat's angular velocity.

Angular momentum about the pivot axis is conserved through the impact for the rigid and the
deformable bat (the joint's reactions pass through the axis), and the lumped bat's MOI about the
pivot is the F2398 MOI of lab/props on the same mesh.
"""

from __future__ import annotations

import numpy as np
import pytest

from batball.contact.shell_contact import nodal_areas
from batball.elements.shell_explicit import cell_stable_steps
from batball.lab.bbs import BbsResult, run_bbs
from batball.lab.props import bat_mass_properties
from batball.models.barrel import thin_ring_interference_pressure
from batball.models.bbs import BbsSetup
from batball.solvers.explicit import HourglassControl
from batball.specs import load_ball_spec, load_bat_spec

IN = 0.0254
#: Coarse meshes; the ball's hourglass control is Flanagan-Belytschko stiffness (IHQ 5), whose
#: forces have no moment: LS-DYNA's default IHQ 1 (the seed's) uses the raw hourglass vectors,
#: which are not orthogonal to rotations, and changes the angular momentum by about 7e-4 here.
COARSE = {"ball_divisions": 4, "circumferential": 12, "axial_size": 0.75 * IN,
          "separation_time": 0.05e-3, "hourglass": HourglassControl(type=5)}  # fmt: skip
#: The deformable bat, with the default selective mass scaling (to the barrel's step).
DEFORMABLE = {**COARSE, "circumferential": 16, "axial_size": 0.5 * IN}


@pytest.fixture(scope="module")
def runs() -> dict[str, BbsResult]:
    bat, ball = load_bat_spec("default"), load_ball_spec("type1")
    setups = {
        "fixed": BbsSetup(fixed_bat=True, **COARSE),
        "rigid": BbsSetup(rigid_bat=True, **COARSE),
        "rigid_24in": BbsSetup(rigid_bat=True, pivot_from_knob=24.0 * IN, **COARSE),
        "deformable": BbsSetup(**DEFORMABLE),
        "whole_contact": BbsSetup(**DEFORMABLE, contact_reach=None),
        "deformable_mitc4": BbsSetup(**DEFORMABLE, bat_shell="mitc4"),
    }
    return {name: run_bbs(bat, ball, setup) for name, setup in setups.items()}


def test_rigid_bat_with_small_k_follows_the_closed_form(runs: dict[str, BbsResult]) -> None:
    e = runs["fixed"].measures.collision_efficiency  # k = 0: e_A is the COR
    m = runs["rigid_24in"].measures
    assert m.k == pytest.approx(0.031, abs=0.005)
    assert m.collision_efficiency == pytest.approx((e - m.k) / (1 + m.k), abs=0.005)


def test_rigid_bat_at_the_seed_pivot(runs: dict[str, BbsResult]) -> None:
    e = runs["fixed"].measures.collision_efficiency
    m = runs["rigid"].measures
    assert m.k == pytest.approx(0.448, abs=0.01)  # docs/physics.md 4.3: 0.434 x 6.93 / 6.75 oz
    assert e - 0.06 < m.bbcor < e
    # the routes differ by the ball's sideways momentum (lever y v_x), largest on this coarse
    # faceted bat (0.002 here; 0.0004 on 32 x 0.2 in with an 8-division ball)
    assert m.bbcor_from_bat == pytest.approx(m.bbcor, abs=0.005)


@pytest.mark.parametrize("name", ["rigid", "deformable", "deformable_mitc4"])
def test_angular_momentum_about_the_pivot_is_conserved(
    runs: dict[str, BbsResult], name: str
) -> None:
    m = runs[name].measures
    # rigid: exact up to round-off (2e-7 measured); deformable: the one-point Belytschko-Tsay
    # element's forces balance moments only on flat quads (its known warping defect), and the
    # pre-stressed barrel's stresses act on slightly warped taper quads (2e-5 measured); the
    # co-rotational MITC4 shells' forces are balanced about each cell's current centroid
    # (elements/shell_corotational), so only round-off and the ball's contact remain
    assert m.angular_momentum_change < (5e-5 if name == "deformable" else 1e-5)
    assert m.energy_balance_error < 0.01
    assert m.rebound_drift < 1e-6 * m.inbound_speed  # the ball's speed is steady at the end


def test_pivot_moi_is_the_f2398_moi(runs: dict[str, BbsResult]) -> None:
    props, _ = bat_mass_properties(
        load_bat_spec("default"), circumferential=16, axial_size=0.5 * IN
    )
    # lumping each quad's mass to its corners adds about m h^2 / 6 (lab/props docs): < 0.1 %
    assert runs["deformable"].measures.pivot_inertia == pytest.approx(props.moi_pivot, rel=1e-3)


@pytest.mark.parametrize("name", ["deformable", "deformable_mitc4"])
def test_dynamic_relaxation_presses_the_insert_to_the_thin_ring_pressure(
    runs: dict[str, BbsResult], name: str
) -> None:
    """docs/physics.md section 6.7: p = delta / (R_o^2 / (E_o t_o) + R_i^2 / (E_i t_i)), 92.9 psi
    for the default bat, with the explicit contact's penalty k (per area) in series: p = delta /
    (the rings' compliance + 1 / k), 87.5 psi on this coarse mesh (SLSFAC E / diagonal is soft on
    0.5-in elements). 2 %: the static solve of the same 16-sided mesh with a stiff penalty
    gives the thin ring to 0.03 % (lab/barrel), and the relaxation leaves 0.5-0.9 % unsettled on
    three meshes (16 x 0.5, 32 x 0.2, 48 x 0.1 in; docs/notes/bbs.md)."""
    spec = load_bat_spec("default")
    model = runs[name].model
    pair = model.coupled.contacts[model.coupled.ball_contacts]
    mesh = model.bat_mesh
    areas = nodal_areas(mesh.points, mesh.cells[mesh.cell_sets["insert"]])[pair.slave_nodes]
    per_area = pair.slave_stiffness / areas
    assert np.ptp(per_area) < 1e-9 * per_area.max()  # one penalty per area
    ring = thin_ring_interference_pressure(spec)
    delta = spec.insert.interference
    expected = delta / (delta / ring + 1.0 / per_area[0])
    assert runs[name].run.interference_pressure == pytest.approx(expected, rel=0.02)


def test_deformable_run_is_mass_scaled_to_the_barrel_step(runs: dict[str, BbsResult]) -> None:
    """The momentum and energy checks above hold with the mass that selective mass scaling adds
    (to taper-1 and the handle on this mesh): the step is the barrel's, and the model's MOI
    carries the added mass while the BBCOR's k uses the real bat's."""
    model, m = runs["deformable"].model, runs["deformable"].measures
    bat = model.coupled.bat
    steps = 0.9 * cell_stable_steps(model.bat_mesh.points, bat.cells, bat.section)
    barrel = np.concatenate([c for n, c in model.bat_mesh.cell_sets.items()
                             if n.startswith("barrel") or n == "insert"])  # fmt: skip
    assert bat.stable_step == pytest.approx(steps[barrel].min(), rel=1e-12)
    assert bat.stable_step > 2.0 * steps.min()  # taper-1's step was less than half of it
    assert model.added_mass[barrel].sum() == 0.0
    assert m.model_pivot_inertia > m.pivot_inertia


def test_contact_limited_to_the_impact_region_changes_nothing(
    runs: dict[str, BbsResult],
) -> None:
    """The bat's side of the ball-bat contact within 3 in of the impact (the ball's radius is
    1.9 in) against the whole bat: the same contact force history, to round-off."""
    near, whole = runs["deformable"].run, runs["whole_contact"].run
    assert near.n_steps == whole.n_steps
    force = whole.column("contact_force_n")
    np.testing.assert_allclose(near.column("contact_force_n"), force, atol=1e-9 * force.max())
