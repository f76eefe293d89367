"""Laminates: CLT moduli of braids against docs/physics.md section 7.1, balance and symmetry of the
seed's braid, a hand-computed ply stiffness, and the PRBA (minor Poisson's ratio) convention."""

from __future__ import annotations

import math

import numpy as np
import pytest

from batball.errors import SpecError
from batball.materials import Laminate, OrthotropicLamina, Ply, rotated_stiffness

GPA = 1e9


def carbon(**changes: float) -> OrthotropicLamina:
    """AS4/3501-6 (docs/physics.md section 7.1): E1 147, E2 10.3, G12 7.0 GPa, nu12 0.27, PRBA =
    minor."""
    values = dict(density=1600.0, ea=147 * GPA, eb=10.3 * GPA, ec=10.3 * GPA,
                  prba=0.27 * 10.3 / 147, gab=7.0 * GPA, gbc=3.5 * GPA, gca=7.0 * GPA)  # fmt: skip
    values.update(changes)
    return OrthotropicLamina(name="carbon", **values)


def braid(angle_deg: float, thickness: float = 1e-3) -> Laminate:
    return Laminate((Ply(carbon(), thickness, math.radians(angle_deg), braided=True),))


@pytest.mark.parametrize(
    ("angle_deg", "axial_gpa", "hoop_gpa"),
    [(15.0, 121.0, 10.9), (22.5, 89.5, 11.9), (30.0, 58.1, 13.8), (45.0, 23.9, 23.9)],
)
def test_carbon_braid_moduli_match_the_physics_table(angle_deg, axial_gpa, hoop_gpa) -> None:
    laminate = braid(angle_deg)
    assert laminate.axial_modulus / GPA == pytest.approx(axial_gpa, rel=0.01)
    assert laminate.hoop_modulus / GPA == pytest.approx(hoop_gpa, rel=0.01)


def test_plus_minus_30_braid_shear_modulus_matches_the_physics_table() -> None:
    assert braid(30.0).shear_modulus / GPA == pytest.approx(30.3, rel=0.01)


def test_braided_ply_is_balanced_and_symmetric() -> None:
    abd = braid(30.0, thickness=2e-3).abd()
    scale = abd.a[0, 0]
    assert abs(abd.a[0, 2]) < 1e-12 * scale and abs(abd.a[1, 2]) < 1e-12 * scale
    assert np.abs(abd.b).max() < 1e-12 * scale * 2e-3
    assert abs(abd.d[0, 2]) > 1e-3 * abd.d[0, 0]  # bending-twist coupling remains (physics 6.5)


def test_braid_expands_to_five_layers_with_the_seed_thickness_fractions() -> None:
    layers = Ply(carbon(), 0.012, math.radians(30), braided=True).layers()
    assert [ly.thickness / 0.012 for ly in layers] == pytest.approx(
        [1 / 6, 1 / 4, 1 / 6, 1 / 4, 1 / 6]
    )
    assert [math.degrees(ly.angle) for ly in layers] == pytest.approx([30, -30, 30, -30, 30])


def test_layer_midplanes_of_a_lone_braid_match_physics_6_5() -> None:
    z = braid(30.0, thickness=1.0).interfaces()
    midplanes = 0.5 * (z[1:] + z[:-1])
    assert midplanes == pytest.approx([-0.4167, -0.2083, 0.0, 0.2083, 0.4167], abs=1e-4)


def test_zero_degree_ply_reduced_stiffness_by_hand() -> None:
    # nu21 = 0.27 * 10.3 / 147 = 0.0189184; D = 1 - 0.27 * 0.0189184 = 0.9948920
    # Q11 = 147 / D = 147.7547, Q22 = 10.3 / D = 10.35288, Q12 = 0.27 * 10.3 / D = 2.795277 GPa
    q = carbon().reduced_stiffness() / GPA
    expected = [[147.7547, 2.795277, 0.0], [2.795277, 10.35288, 0.0], [0.0, 0.0, 7.0]]
    assert q == pytest.approx(np.array(expected), rel=1e-5, abs=1e-9)
    a = Laminate((Ply(carbon(), 2e-3, 0.0),)).abd().a
    assert a / GPA == pytest.approx(2e-3 * np.array(expected), rel=1e-5, abs=1e-12)


def test_major_poissons_ratio_is_prba_times_ea_over_eb() -> None:
    assert carbon().nu_ab == pytest.approx(0.27)


def test_prba_given_as_the_major_ratio_is_refused_naming_the_field() -> None:
    with pytest.raises(SpecError, match=r"materials\.carbon\.prba.*MINOR"):
        carbon(prba=0.27)


def test_rotating_a_ply_by_90_degrees_swaps_axial_and_hoop() -> None:
    q = carbon().reduced_stiffness()
    turned = rotated_stiffness(q, math.pi / 2)
    assert turned[0, 0] == pytest.approx(q[1, 1]) and turned[1, 1] == pytest.approx(q[0, 0])
    assert turned[2, 2] == pytest.approx(q[2, 2])
    assert abs(turned[0, 2]) < 1e-6 * q[0, 0]


def test_isotropic_plate_a_matrix_is_e_t_over_one_minus_nu_squared() -> None:
    from batball.materials import isotropic_lamina

    steel = isotropic_lamina(name="steel", density=7850.0, youngs_modulus=200 * GPA,
                             poissons_ratio=0.3)  # fmt: skip
    laminate = Laminate((Ply(steel, 2e-3, 0.3),))
    a = laminate.abd().a
    assert a[0, 0] == pytest.approx(200 * GPA * 2e-3 / (1 - 0.09))
    assert a[0, 1] == pytest.approx(0.3 * 200 * GPA * 2e-3 / (1 - 0.09))
    assert laminate.axial_modulus == pytest.approx(200 * GPA)
    assert laminate.abd().d[0, 0] == pytest.approx(200 * GPA * 8e-9 / 12 / 0.91)


def test_areal_mass_is_the_sum_of_density_times_thickness() -> None:
    laminate = Laminate((Ply(carbon(), 1e-3, 0.0), Ply(carbon(density=2000.0), 2e-3, 0.5, True)))
    assert laminate.areal_mass == pytest.approx(1600 * 1e-3 + 2000 * 2e-3)
    assert laminate.thickness == pytest.approx(3e-3)


def test_mat022_is_registered_as_a_lamina_law_with_the_card_fields() -> None:
    from batball.materials import LAMINA_LAWS, MATERIAL_LAWS

    law = LAMINA_LAWS["mat022"]
    assert "mat022" not in MATERIAL_LAWS  # solid laws give hex-kernel constants; laminae do not
    assert law.lsdyna_keyword == "*MAT_COMPOSITE_DAMAGE"
    fields = [p.lsdyna_field for p in law.parameters]
    assert fields == ["RO", "EA", "EB", "EC", "PRBA", "GAB", "GBC", "GCA"]
