"""Hertz impact of an elastic sphere on a rigid wall (docs/physics.md section 8, case 1) and energy
balance.

R = 48.5 mm, m = 0.185 kg, E = 50 MPa, nu = 0.3, 3 m/s: Hertz gives F_max = 1186.0 N and a contact
time of 1.7216 ms (delta_max / R = 3.6 %, quasi-static). Two model choices make the FE comparable
with Hertz's rigid, impenetrable wall and elastic ball:

* penalty scale SFS = 10: with the default SOFT = 0 stiffness (0.1 K A^2 / V) the penalty
  penetration of this ball (K ~ E) is as large as the Hertz approach itself (about 2 mm against
  1.75 mm), which stretches the contact time by a third; ten times stiffer leaves it near 0.2 mm;
* hourglass IHQ 4 (stiffness form), which stores rather than dissipates energy.

Tolerances: contact time 3 % (docs/physics.md section 8). Peak force 8 %: the contact radius
a = sqrt(R delta) = 9.2 mm spans only about 1.5 surface elements of the 12-division ball (6.3 mm),
so the force rises in ring-by-ring steps and its sampled peak overshoots the smooth Hertz curve;
the error falls with refinement (+5.8 % at 12 divisions, +4.3 % at 16, measured when this test was
written), so 8 % is the 12-division band, not a licence.
"""

import numpy as np
import pytest

from batball.lab.impact import run_impact
from batball.models.ball import ContactOptions
from batball.models.impact import ImpactSetup
from batball.solvers.explicit import BALANCE, HourglassControl
from batball.specs import ball_spec_from_dict

RADIUS, MASS, E_MOD, NU, SPEED = 0.0485, 0.185, 50e6, 0.3, 3.0


def hertz_peak_and_duration(speed: float) -> tuple[float, float]:
    """Hertz (Johnson 1985): k = 4/3 E* sqrt(R), d = (5 m v^2 / 4k)^(2/5), tc = 2.9432 d / v."""
    k = 4.0 / 3.0 * E_MOD / (1 - NU**2) * np.sqrt(RADIUS)
    approach = (5 * MASS * speed**2 / (4 * k)) ** 0.4
    return k * approach**1.5, 2.9432 * approach / speed


@pytest.fixture(scope="module")
def hertz_run():
    ball = ball_spec_from_dict(
        {
            "name": "hertz",
            "circumference": f"{2 * np.pi * RADIUS} m",
            "mass": f"{MASS} kg",
            "material": {"law": "elastic", "youngs_modulus": "50 MPa", "poissons_ratio": "0.3"},
        },
        source="verification case 1",
    )
    setup = ImpactSetup(
        test="cor",
        speed=SPEED,
        divisions=12,
        end_time=6e-3,
        gap=1e-6,
        hourglass=HourglassControl(type=4, coefficient=0.1),
        contact=ContactOptions(sfs=10.0),
        contact_threshold=0.0,
    )
    return run_impact(ball, setup)


def test_closed_form_matches_the_tabulated_hertz_numbers() -> None:
    peak, duration = hertz_peak_and_duration(SPEED)
    assert peak == pytest.approx(1186.0, rel=1e-3)
    assert duration == pytest.approx(1.7216e-3, rel=1e-3)


def test_contact_time_and_peak_force_agree_with_hertz(hertz_run) -> None:
    peak, duration = hertz_peak_and_duration(SPEED)
    assert hertz_run.measures.contact_time == pytest.approx(duration, rel=0.03)
    assert hertz_run.measures.peak_force == pytest.approx(peak, rel=0.08)


def test_elastic_impact_conserves_energy(hertz_run) -> None:
    energies = hertz_run.run.energies
    kinetic0 = 0.5 * hertz_run.run.mass * SPEED**2
    assert np.abs(energies[:, BALANCE]).max() < 0.005 * kinetic0  # balance: KE+IE+HG+BV+CE = KE0
    assert hertz_run.measures.restitution >= 0.98  # docs/physics.md section 8: COR >= 0.98
