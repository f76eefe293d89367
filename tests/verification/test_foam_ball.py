"""Foam balls (MAT_057, MAT_083) end to end on coarse meshes: CCOR, COR and compression run,
the energy balance closes and the measures are physical."""

from __future__ import annotations

import numpy as np
import pytest

from batball.lab.compression import run_compression
from batball.lab.impact import run_impact
from batball.models.ball import ContactOptions
from batball.models.compression import CompressionSetup
from batball.models.impact import ImpactSetup
from batball.solvers.explicit import BALANCE, ENERGY_COLUMNS
from batball.specs import load_ball_spec

MPH = 0.44704


@pytest.mark.parametrize("name", ["foam057", "foam083"])
def test_foam_ball_ccor_closes_its_energy_balance(name: str) -> None:
    result = run_impact(load_ball_spec(name), ImpactSetup(test="ccor", speed=95 * MPH, divisions=4))
    energies = result.run.energies
    kinetic0 = energies[0, 0]
    # the solver's own run-away guard is 10 %; a healthy run stays within 2 %
    assert np.abs(energies[:, BALANCE]).max() < 0.02 * kinetic0
    ccor = result.measures.restitution
    assert 0.0 < ccor < 1.0
    # what the ball lost is what the internal (hysteresis, DAMP), hourglass and bulk-viscosity
    # work kept: 1 - e^2 of the inbound kinetic energy, up to the vibration left in the ball
    end = energies[-1]
    lost = kinetic0 * (1.0 - ccor**2)
    kept = sum(end[ENERGY_COLUMNS.index(k)] for k in ("internal", "hourglass", "bulk_viscosity"))
    assert kept == pytest.approx(lost, rel=0.15)


def test_foam_ball_cor_against_a_wall() -> None:
    result = run_impact(
        load_ball_spec("foam057"), ImpactSetup(test="cor", speed=60 * MPH, divisions=3)
    )
    assert 0.0 < result.measures.restitution < 1.0
    assert np.abs(result.run.energies[:, BALANCE]).max() < 0.02 * result.run.energies[0, 0]


def test_foam_ball_compression_is_quasi_static() -> None:
    # a foam's contact modulus is its E_eff (~1e8 Pa, not MAT_006's K ~ 5e9 Pa): SFS = 5 keeps
    # the plates' penetration small (LS-DYNA users raise SFS for soft foams the same way)
    setup = CompressionSetup(divisions=4, contact=ContactOptions(sfs=5.0))
    result = run_compression(load_ball_spec("foam057"), setup)
    assert result.compression > 0.0
    assert result.penetration < 0.05 * setup.displacement
    assert result.kinetic_to_internal < 0.01
    assert result.energy_balance_error < 0.01
