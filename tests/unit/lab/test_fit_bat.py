"""batball fit-bat: free parameters by name, and a fit that recovers a known bat."""

from __future__ import annotations

import dataclasses

import pytest

from batball.errors import SpecError
from batball.lab.fit_bat import FreeParameter, MassTargets, fit_bat
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
