"""batball fit-bat: free parameters by name, and a fit that recovers a known bat."""

from __future__ import annotations

import dataclasses
import math

import pytest

from batball.calibrate.bat_fit import (
    MATCH_TOLERANCE,
    BatFit,
    FreeParameter,
    HoopTargets,
    MassTargets,
    MeshOptions,
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
    steps of 0.003 deg, HoopTargets) and both frequencies to 1e-4 (0.15 Hz; 0.01 deg moves them
    by about 0.1 Hz). Run again with the same store, the fit replays the stored evaluations: no
    modal analysis at all."""
    import batball.calibrate.bat_fit as bat_fit

    coarse = {"circumferential": 16, "axial_size": 0.5 * IN}
    braid = FreeParameter.parse(BARREL_BRAID)
    truth = braid.apply(load_bat_spec("default"), math.radians(40.0))
    wanted = HoopTargets().achieved(truth, MeshOptions(**coarse))
    targets = HoopTargets(hoop_hz=wanted, runs_dir=tmp_path)
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
    """One hoop frequency, one braid: met when within HoopTargets.match (1e-4, 0.15 Hz), which
    a mass-property fit's 1e-6 would refuse; a least-squares fit is met unless a bound stops it."""
    spec = load_bat_spec("default")
    braid = FreeParameter.parse(BARREL_BRAID)

    def outcome(residuals: tuple[float, ...], match: float, value: float = 0.6) -> BatFit:
        return BatFit(spec=spec, parameters=(braid,), initial=(0.5,), values=(value,),
                      achieved=residuals, residuals=residuals, n_evaluations=3, success=True,
                      match=match)  # fmt: skip

    assert HoopTargets().match == 1e-4 and MassTargets(1.0, 1.0, 1.0).match == 1e-6
    assert outcome((5e-5,), HoopTargets().match).matched
    assert not outcome((5e-5,), MATCH_TOLERANCE).matched
    assert outcome((5e-3, -4e-3), HoopTargets().match).matched  # least squares
    at_90 = outcome((5e-3, -4e-3), HoopTargets().match, value=0.5 * math.pi)
    assert at_90.at_bound == (braid,) and not at_90.matched
