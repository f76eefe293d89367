"""batball fit-bat: free parameters by name, and a fit that recovers a known bat."""

from __future__ import annotations

import dataclasses
import math

import pytest

from batball.calibrate.bat_fit import (
    MATCH_TOLERANCE,
    BatFit,
    FreeParameter,
    MassTargets,
    MeshOptions,
    ModalTargets,
    fit_bat,
)
from batball.errors import SpecError
from batball.lab.props import bat_mass_properties
from batball.specs import load_bat_spec

IN, OZ = 0.0254, 0.028349523125
COARSE = {"circumferential": 16, "axial_size": 0.4 * IN}


def test_free_parameters_parse_and_read_the_spec() -> None:
    spec = load_bat_spec("default")
    assert FreeParameter.parse("lumped_mass:endcap").value(spec) == pytest.approx(1.39 * OZ)
    assert FreeParameter.parse("thickness:barrel-carbon").value(spec) == pytest.approx(0.0633 * IN)
    with pytest.raises(SpecError, match="free"):
        FreeParameter.parse("colour:red")
    with pytest.raises(SpecError, match="labels: barrel-carbon, handle-glass"):
        FreeParameter.parse("thickness:nothing").value(spec)


def test_thickness_parameter_changes_every_labelled_ply() -> None:
    spec = FreeParameter.parse("thickness:handle-glass").apply(load_bat_spec("default"), 1e-3)
    plies = [p for part in spec.parts for p in part.layup if p.label == "handle-glass"]
    assert len(plies) == 6 and all(p.thickness == 1e-3 for p in plies)


def test_fit_recovers_the_values_a_bat_was_built_with() -> None:
    truth = load_bat_spec("default")
    props, _ = bat_mass_properties(truth, **COARSE)
    targets = MassTargets(weight=props.mass, balance_point=props.balance_point,
                          moi_pivot=props.moi_pivot)  # fmt: skip
    free = tuple(
        FreeParameter.parse(t)
        for t in ("lumped_mass:endcap", "thickness:handle-glass", "thickness:barrel-carbon")
    )
    start = free[0].apply(truth, 2.0 * OZ)
    start = free[1].apply(start, 0.045 * IN)
    start = dataclasses.replace(free[2].apply(start, 0.035 * IN), name="start")
    fit = fit_bat(start, targets, free, **COARSE)
    assert fit.success
    assert max(abs(r) for r in fit.residuals) < 1e-9
    assert fit.values == pytest.approx([1.39 * OZ, 0.0472 * IN, 0.0633 * IN], rel=1e-6)


BARREL_BRAID = "angle:barrel-carbon@barrel-1+barrel-2+barrel-3+endcap"


def test_angle_parameter_sets_the_labelled_plies_of_the_named_parts_only() -> None:
    spec = load_bat_spec("default")
    braid = FreeParameter.parse(BARREL_BRAID)
    assert braid.parts == ("barrel-1", "barrel-2", "barrel-3", "endcap")
    assert str(braid) == BARREL_BRAID
    assert braid.value(spec) == pytest.approx(math.radians(30.0))
    changed = braid.apply(spec, math.radians(40.0))
    set_plies = [p for part in changed.parts if part.name in braid.parts for p in part.layup
                 if p.label == "barrel-carbon"]  # fmt: skip
    assert len(set_plies) == 4
    assert [math.degrees(p.angle) for p in set_plies] == pytest.approx([40.0] * 4)
    untouched = [p for p in changed.parts if p.name not in braid.parts]
    assert untouched == [p for p in spec.parts if p.name not in braid.parts]
    assert changed.insert == spec.insert
    # every labelled ply, the taper's included, without the restriction
    everywhere = FreeParameter.parse("angle:barrel-carbon").apply(spec, math.radians(40.0))
    angles = {round(math.degrees(p.angle), 9) for part in everywhere.parts for p in part.layup
              if p.label == "barrel-carbon"}  # fmt: skip
    assert angles == {40.0}


def test_part_restrictions_are_checked() -> None:
    spec = load_bat_spec("default")
    with pytest.raises(SpecError, match="parts of the bat"):
        FreeParameter.parse("angle:barrel-carbon@barrel-9").value(spec)
    with pytest.raises(SpecError, match="free"):
        FreeParameter.parse("lumped_mass:endcap@barrel-1")
    with pytest.raises(SpecError, match="free"):
        FreeParameter.parse("angle:barrel-carbon@")
    # the handle glass is braided at 15, 22.5 and 30 deg: no common angle
    with pytest.raises(SpecError, match="one angle"):
        FreeParameter.parse("angle:handle-glass").value(spec)


def test_hoop_fit_recovers_the_braid_a_bat_was_built_with(tmp_path, monkeypatch) -> None:
    """Coarse bat (16 x 0.5 in, ~3.5 s per modal analysis): the hoop frequencies of a bat with a
    40-deg barrel braid, fitted from 30 deg, give back 40 deg to 0.01 deg (the fit stops at
    steps of 0.003 deg, ModalTargets) and both frequencies to 1e-4 (0.15 Hz; 0.01 deg moves them
    by about 0.1 Hz). Run again with the same store, the fit replays the stored evaluations: no
    modal analysis at all."""
    import batball.calibrate.bat_fit as bat_fit

    coarse = {"circumferential": 16, "axial_size": 0.5 * IN}
    braid = FreeParameter.parse(BARREL_BRAID)
    truth = braid.apply(load_bat_spec("default"), math.radians(40.0))
    wanted = ModalTargets().achieved(truth, MeshOptions(**coarse))
    targets = ModalTargets(hoop_hz=wanted, runs_dir=tmp_path)
    start = load_bat_spec("default")
    fit = fit_bat(start, targets, (braid,), **coarse)
    assert fit.success and fit.least_squares and fit.matched
    assert math.degrees(fit.values[0]) == pytest.approx(40.0, abs=0.01)
    assert max(abs(r) for r in fit.residuals) < 1e-4

    def no_modal_analysis(*args, **kwargs):
        raise AssertionError("a stored evaluation was recomputed")

    monkeypatch.setattr(bat_fit, "bat_modes", no_modal_analysis)
    again = fit_bat(start, targets, (braid,), **coarse)
    assert again.values == fit.values


def test_the_shipped_fitted_bat_is_the_default_with_a_wider_barrel_braid() -> None:
    """The embedded bat "fitted" (the output of `batball fit-bat --to hoop`) differs from the
    embedded default only in the freed parameter, so its mass properties are the default's."""
    fitted, default = load_bat_spec("fitted"), load_bat_spec("default")
    braid = FreeParameter.parse(BARREL_BRAID)
    assert math.degrees(braid.value(fitted)) == pytest.approx(39.4843, abs=1e-4)
    restored = braid.apply(fitted, braid.value(default))
    same = dataclasses.replace(restored, name="default", description=default.description)
    assert same == default


def test_an_exact_fit_is_met_within_its_targets_match_tolerance() -> None:
    """One hoop frequency, one braid: met when within ModalTargets.match (1e-4, 0.15 Hz), which
    a mass-property fit's 1e-6 would refuse; a least-squares fit is met unless a bound stops it."""
    spec = load_bat_spec("default")
    braid = FreeParameter.parse(BARREL_BRAID)

    def outcome(residuals: tuple[float, ...], match: float, value: float = 0.6) -> BatFit:
        return BatFit(spec=spec, parameters=(braid,), initial=(0.5,), values=(value,),
                      achieved=residuals, residuals=residuals, n_evaluations=3, success=True,
                      match=match)  # fmt: skip

    assert ModalTargets().match == 1e-4 and MassTargets(1.0, 1.0, 1.0).match == 1e-6
    assert outcome((5e-5,), ModalTargets().match).matched
    assert not outcome((5e-5,), MATCH_TOLERANCE).matched
    assert outcome((5e-3, -4e-3), ModalTargets().match).matched  # least squares
    at_90 = outcome((5e-3, -4e-3), ModalTargets().match, value=0.5 * math.pi)
    assert at_90.at_bound == (braid,) and not at_90.matched


@dataclasses.dataclass(frozen=True)
class WeightOnly:
    """A one-target set: the bat's weight, with a relative resolution (linear in any lumped
    mass, so the regularised fit and the sensitivity have closed forms)."""

    weight: float
    resolution: tuple[float, ...] = (0.01,)
    names = ("weight_oz",)
    description = "weight"
    diff_step = 1e-7
    tolerance = 1e-12
    match = MATCH_TOLERANCE

    @property
    def wanted(self) -> tuple[float, ...]:
        return (self.weight / OZ,)

    def achieved(self, spec, mesh) -> tuple[float, ...]:
        props, _ = bat_mass_properties(spec, circumferential=mesh.circumferential,
                                       axial_size=mesh.axial_size)  # fmt: skip
        return (props.mass / OZ,)


def test_a_regularised_fit_lands_where_the_prior_and_the_resolution_put_it() -> None:
    """Weight W0 + dm against a measured Wt of resolution r (relative), the end cap's mass with
    a prior spread sd: the most probable dm = (Wt - W0) sd^2 / (sd^2 + (r Wt)^2), the product of
    two Gaussians. Three cases: a loose prior (the data win), equal spreads (halfway), a tight
    prior (the start wins)."""
    spec = load_bat_spec("default")
    props, _ = bat_mass_properties(spec, **COARSE)
    endcap = (FreeParameter.parse("lumped_mass:endcap"),)
    wt = props.mass + 0.4 * OZ
    targets = WeightOnly(weight=wt)
    sigma = 0.01 * wt
    for sd in (10.0 * sigma, sigma, 0.1 * sigma):
        fit = fit_bat(spec, targets, endcap, **COARSE, prior_sd=(sd,))
        expected = 0.4 * OZ * sd**2 / (sd**2 + sigma**2)
        assert fit.values[0] - endcap[0].value(spec) == pytest.approx(expected, rel=1e-6)
        assert fit.least_squares and fit.regularised


def test_the_sensitivity_of_a_linear_target_is_its_closed_form() -> None:
    """The weight moves 1 oz per oz of end cap: one spread sd moves it sd / (r Wt) resolutions;
    a braid angle moves no mass, so its column is zero, its singular value 0 and its posterior
    spread its prior one; the end cap's posterior ratio is 1 / sqrt(1 + J^2)."""
    from batball.calibrate.bat_sensitivity import bat_sensitivity

    spec = load_bat_spec("default")
    props, _ = bat_mass_properties(spec, **COARSE)
    targets = WeightOnly(weight=props.mass)
    free = (FreeParameter.parse("lumped_mass:endcap"), FreeParameter.parse(BARREL_BRAID))
    sd = 0.5 * OZ
    found = bat_sensitivity(spec, targets, free, spread=(sd, math.radians(5.0)),
                            mesh=MeshOptions(**COARSE))  # fmt: skip
    j = sd / (0.01 * props.mass)
    assert found.jacobian[0, 0] == pytest.approx(j, rel=1e-9)
    assert found.jacobian[0, 1] == 0.0
    assert found.singular_values == pytest.approx([j, 0.0], abs=1e-9)
    assert found.posterior_ratio == pytest.approx([1.0 / math.sqrt(1.0 + j * j), 1.0], rel=1e-9)
    # a quantity j resolutions per spread of end cap: posterior sd j / sqrt(1 + j^2); one moved
    # only by the unseen angle keeps its prior spread
    assert found.propagated_spread([j, 0.0]) == pytest.approx(j / math.sqrt(1 + j * j), rel=1e-9)
    assert found.propagated_spread([0.0, 2.0]) == pytest.approx(2.0, rel=1e-12)
    summary = found.summary()
    assert summary["spread"]["lumped_mass:endcap"] == "0.5 oz"
    assert summary["combinations"][0]["parameters"] == {"lumped_mass:endcap": 1.0,
                                                        BARREL_BRAID: 0.0}  # fmt: skip


def test_joint_targets_weigh_table_1_and_table_3_by_their_resolutions(tmp_path) -> None:
    """The joint set is Table 1 then Table 3's bending and hoop frequencies; the modal part's
    hoop frequencies are the hoop-only set's, and a stored evaluation is replayed."""
    from batball.calibrate.bat_fit import JointTargets, seed_bending_hz

    spec = load_bat_spec("fitted")
    mesh = MeshOptions(16, 0.5 * IN)
    modal = ModalTargets(bending_hz=seed_bending_hz(), runs_dir=tmp_path)
    joint = JointTargets((MassTargets(22.1 * OZ, 21.0 * IN, 1.0), modal))
    assert joint.names == ("weight_oz", "balance_point_in", "moi_pivot_oz_in2", "bending_1_hz",
                           "bending_2_hz", "hoop_1_hz", "hoop_2_hz")  # fmt: skip
    assert joint.wanted[3:] == (146.0, 555.0, 1450.0, 1950.0)  # seed Table 3
    # 0.1 oz of 22.1 oz, 0.1 in of 21 in, then 1 % for the MOI and each frequency
    assert joint.resolution == pytest.approx((0.1 / 22.1, 0.1 / 21.0) + (0.01,) * 5, rel=1e-12)
    both = modal.achieved(spec, mesh)
    assert both[2:] == ModalTargets().achieved(spec, mesh)
    assert both[0] < both[1] < both[2]  # bending 1 < bending 2 < hoop 1 here
    assert modal.achieved(spec, mesh) == both  # replayed from the store
    with pytest.raises(SpecError, match="resolution"):
        JointTargets((modal,), resolution=(0.01,))


def test_joint_resolutions_follow_the_targets_not_the_seed(tmp_path) -> None:
    """Weight and balance point resolutions are absolute (0.1 oz, 0.1 in), so they scale with the
    measured value; any number of frequencies gets 1 % each; a target with no assumed resolution
    and a balance point off the bat are refused by name."""
    from batball.calibrate.bat_fit import JointTargets, joint_resolution

    mass = MassTargets(25.0 * OZ, 20.0 * IN, 7000.0 * OZ * IN**2)
    three = ModalTargets(hoop_hz=(1400.0, 1900.0, 2500.0), runs_dir=tmp_path)
    joint = JointTargets((mass, three))
    assert joint.resolution == pytest.approx((0.1 / 25.0, 0.1 / 20.0) + (0.01,) * 4, rel=1e-12)
    with pytest.raises(SpecError, match="resolution.*torsion_hz_peak"):
        joint_resolution("torsion_hz_peak", 1.0)
    off = JointTargets((MassTargets(22.1 * OZ, 40.0 * IN, 6920.0 * OZ * IN**2),))
    free = (FreeParameter("lumped_mass", "endcap"),)
    with pytest.raises(SpecError, match="balance-point"):
        fit_bat(load_bat_spec("fitted"), off, free)


def test_posterior_draws_have_the_posterior_covariance_and_cover_each_stratum() -> None:
    """A two-parameter Jacobian J = [[2, 0], [1, 1]]: the draws' covariance is (J^T J + I)^-1
    (sampling error of a covariance with 20,000 draws about 1 %, so 4 % is four of them), and,
    mapped back to standard normals, each parameter has one draw in each of the n equal-
    probability strata (the Latin hypercube's property, exact for any n)."""
    import numpy as np
    from scipy.stats import norm

    from batball.calibrate.bat_sensitivity import Sensitivity

    jac = np.array([[2.0, 0.0], [1.0, 1.0]])
    free = (FreeParameter.parse("lumped_mass:endcap"), FreeParameter.parse(BARREL_BRAID))
    found = Sensitivity(free, (1.0, 1.0), ("a", "b"), (1.0, 1.0), (0.01, 0.01), (1.0, 1.0), jac)
    expected = np.linalg.inv(jac.T @ jac + np.eye(2))
    draws = found.posterior_offsets(20_000, seed=3)
    assert np.cov(draws.T) == pytest.approx(expected, rel=0.04, abs=0.04 * expected.max())
    few = found.posterior_offsets(7, seed=3)
    normal = few @ np.linalg.inv(np.linalg.cholesky(expected)).T
    for column in norm.cdf(normal).T:
        assert sorted(np.floor(column * 7).astype(int)) == list(range(7))
    assert np.array_equal(few, found.posterior_offsets(7, seed=3))  # reproducible
    with pytest.raises(SpecError, match="samples"):
        found.posterior_offsets(0, seed=3)
