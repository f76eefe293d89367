"""The explicit, geometrically nonlinear barrel compression (issue 8) against the static solver,
symmetry, and an independent code's nonlinearity.

Coarse bat (16 quads around, 0.4-in rings) so that a squeeze costs seconds. Expectations:

* **Small travel = the linear static test.** At 0.005 in geometric nonlinearity is negligible
  (CalculiX's NLGEOM moves the double-wall tube's force by 1.1 % at 0.01 in, docs/notes/barrel.md),
  so
  the explicit squeeze, relaxed, must give the static MITC4 force on the same mesh (42.7 lbf):
  - with the co-rotational MITC4 shells (the default) the element is the statics' own, and
    what is left are the contacts: the insert's penalty contact (SLSFAC 0.1) in series with the
    walls, against the statics' stiff one (about 0.5 %, docs/notes/barrel.md), and the reading's
    settling (force drift up to 0.3 % over the window): 4 % allowed, measured -3.2 %;
  - with the one-point Belytschko-Tsay shells, up to the two elements' discretisation
    difference as well: 3.4 % for a smooth bending field on an 8 x 8 plate (test_shell_bt), so
    6 % on these 0.4 x 0.44-in cells with the platen's concentrated load. Measured: -4.2 % with
    hourglass ratio 1; with LS-DYNA's 0.01 the hourglass patterns under the platen take 17 %
    off (docs/notes/barrel.md).
* **Geometric nonlinearity, sized by CalculiX.** CalculiX's NLGEOM / linear force on the
  double-wall tube falls from 0.989 at 0.01 in to 0.932 at 0.07 in (docs/notes/barrel.md,
  benchmarks/ccx_barrel_nlgeom.py): 5.8 % of softening over the test's travel. The explicit
  force over the static one must fall between 0.005 and 0.07 in by 2-10 % (a different model:
  the tube is 10 in of solids with its walls tied; measured 4.0 % with the MITC4 shells).
  A linear solver gives 0.
* **Symmetry.** The bat is axisymmetric and 16 around puts nodes under the platens at 0 and
  45 deg with the same mesh rotated by two cells: the same forces (measured 2e-12; 1e-6 allowed
  for round-off in the rotated geometry).
"""

from __future__ import annotations

import numpy as np
import pytest

from batball.errors import SpecError
from batball.lab.barrel import compress_barrel
from batball.lab.barrel_explicit import (
    ExplicitBarrelOptions,
    build_explicit_bat,
    make_platens,
    platen_friction_forces,
    press_fit,
    squeeze,
)
from batball.models.barrel import BarrelTestOptions, build_barrel_model, compute_prestress
from batball.specs import load_bat_spec

IN = 0.0254
AROUND, AXIAL = 16, 0.4 * IN
TRAVELS = (0.005 * IN, 0.07 * IN)


@pytest.fixture(scope="module")
def spec():  # noqa: ANN201
    return load_bat_spec("default")


@pytest.fixture(scope="module")
def protocol() -> BarrelTestOptions:
    """Two levels only: 0.005 in (the linear limit) and 0.07 in (the final travel)."""
    return BarrelTestOptions(orientations_deg=(0.0,), preload_travel=TRAVELS[0],
                             final_travel=TRAVELS[1] - TRAVELS[0])  # fmt: skip


@pytest.fixture(scope="module")
def static_forces(spec, protocol) -> np.ndarray:  # noqa: ANN001
    model = build_barrel_model(spec, circumferential=AROUND, axial_size=AXIAL)
    curve = compress_barrel(model, compute_prestress(model), protocol, 0.0, curve=False)
    return curve.force


def explicit_forces(spec, protocol: BarrelTestOptions, angle: float,  # noqa: ANN001
                    **changes: float | str) -> np.ndarray:  # fmt: skip
    options = ExplicitBarrelOptions(circumferential=AROUND, axial_size=AXIAL, **changes)
    state = build_explicit_bat(spec, options)
    press_fit(state, options)
    run = squeeze(state, protocol, options, angle, curve=False)
    assert run.kinetic_ratio.max() < 1e-3 and np.abs(run.drift).max() < 1e-2  # settled
    assert np.abs(run.travel_error).max() < 1e-3 * TRAVELS[0]  # penalty compliance removed
    return run.curve.force


@pytest.fixture(scope="module")
def explicit_0deg(spec, protocol) -> np.ndarray:  # noqa: ANN001
    return explicit_forces(spec, protocol, 0.0)


def test_small_travel_gives_the_static_force(explicit_0deg, static_forces) -> None:  # noqa: ANN001
    assert explicit_0deg[0] == pytest.approx(static_forces[0], rel=0.04)


def test_small_travel_on_the_bt_shells_gives_the_static_force(spec, protocol,  # noqa: ANN001
                                                              static_forces) -> None:  # noqa: ANN001  # fmt: skip
    one_point = explicit_forces(spec, protocol, 0.0, shell="bt", hourglass_ratio=1.0)
    assert one_point[0] == pytest.approx(static_forces[0], rel=0.06)


def test_large_travel_softens_as_calculix_nlgeom_says(explicit_0deg,  # noqa: ANN001
                                                      static_forces) -> None:  # noqa: ANN001  # fmt: skip
    ratio = explicit_0deg / static_forces
    softening = 1.0 - ratio[1] / ratio[0]
    assert 0.02 < softening < 0.10


def test_orientations_give_the_same_forces(spec, protocol, explicit_0deg) -> None:  # noqa: ANN001
    turned = explicit_forces(spec, protocol, 45.0)
    np.testing.assert_allclose(turned, explicit_0deg, rtol=1e-6)


def test_bad_options_name_the_field() -> None:
    with pytest.raises(SpecError, match="hold_time"):
        ExplicitBarrelOptions(hold_time=0.0)
    with pytest.raises(SpecError, match="circumferential"):
        ExplicitBarrelOptions(circumferential=20)
    with pytest.raises(SpecError, match="shell"):
        ExplicitBarrelOptions(shell="hughes-liu")


def test_platen_friction_resists_the_surface_not_the_mid_surface(spec, protocol) -> None:  # noqa: ANN001
    """The explicit squeeze's platen friction (barrel_explicit.platen_friction_forces) on a bat
    turning rigidly about its axis at omega under pressed platens: each pressed node's outer
    surface, o off its mid-surface p along the radial r, moves by omega x (p + o r) dt, so
    the friction is k_t times minus the tangential part of that (stick), its moment about the
    node (o r) x f, and the platens take the opposite force."""
    options = ExplicitBarrelOptions(circumferential=AROUND, axial_size=AXIAL)
    state = build_explicit_bat(spec, options)
    platens = make_platens(state, protocol, 0.0, options.contact_scale)
    omega, n = 50.0, platens.nodes.size  # rad/s
    p = state.points[platens.nodes]
    radial = p * np.array([0.0, 1.0, 1.0]) / np.hypot(p[:, 1], p[:, 2])[:, None]
    arm = state.surface_offset[platens.nodes, None] * radial
    state.velocity[platens.nodes, :3] = np.cross([omega, 0.0, 0.0], p)
    state.velocity[platens.nodes, 3] = omega
    normal = -1e3 * radial  # pressed towards the axis
    normal[::2] = 0.0  # half of them free
    platen_forces, forces = normal.copy(), np.zeros_like(state.velocity)
    reaction = np.zeros((2, 3))
    platen_friction_forces(state, platens, 0.3, 0.0, np.zeros((n, 3)), platen_forces, forces,
                           reaction)  # fmt: skip
    slip = -state.bat.stable_step * np.cross([omega, 0.0, 0.0], p + arm)
    tangential = slip - np.einsum("ij,ij->i", slip, radial)[:, None] * radial
    expected = platens.stiffness[:, None] * tangential
    expected[::2] = 0.0
    size = np.linalg.norm(expected[1::2], axis=1)
    assert size.max() < 0.3e3 and size.min() > 1.0  # sticking, as assumed, and not nothing
    np.testing.assert_allclose(platen_forces - normal, expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(forces[platens.nodes, 3:], np.cross(arm, expected), atol=1e-15)
    np.testing.assert_allclose(reaction.sum(axis=0), -expected.sum(axis=0), atol=1e-12)
