"""Mass properties (ASTM F2398) against closed forms: a flat plate, a thin uniform tube."""

from __future__ import annotations

import math

import numpy as np
import pytest

from batball.lab.props import bat_mass_properties, shell_mass_properties
from batball.materials import isotropic_lamina
from batball.mesh import ShellMesh
from batball.specs import BatSpec, PartSpec, PlySpec

RHO, T = 1800.0, 0.003  # kg/m^3, m
L, D = 0.84, 0.057  # tube length and outer diameter, m
R = 0.5 * D - 0.5 * T  # mid-surface radius, m
PIVOT = 6 * 0.0254


def tube(lumped_mass: float = 0.0) -> BatSpec:
    """A uniform tube: one isotropic ply; the last 20 mm a part carrying ``lumped_mass``."""
    material = isotropic_lamina(name="resin", density=RHO, youngs_modulus=3e9, poissons_ratio=0.35)
    layup = (PlySpec(material="resin", thickness=T, angle=0.0),)
    parts = (
        PartSpec(name="tube", start=0.0, end=L - 0.02, layup=layup),
        PartSpec(name="cap", start=L - 0.02, end=L, layup=layup, lumped_mass=lumped_mass),
    )
    return BatSpec(name="tube", length=L, stations=((0.0, D), (L, D)), parts=parts, insert=None,
                   materials={"resin": material})  # fmt: skip


def test_uniform_tube_matches_the_closed_form() -> None:
    props, _ = bat_mass_properties(tube(), circumferential=96, axial_size=0.005, pivot=PIVOT)
    mass = RHO * 2 * math.pi * R * T * L
    d = L / 2 - PIVOT
    moi_cm = mass * (L**2 / 12 + R**2 / 2)  # rod about its centre + thin ring about a diameter
    assert props.mass == pytest.approx(mass, rel=1e-3)
    assert props.balance_point == pytest.approx(L / 2, rel=1e-9)
    assert props.moi_pivot == pytest.approx(moi_cm + mass * d**2, rel=1e-3)
    assert props.moi_cm == pytest.approx(moi_cm, rel=1e-3)


def test_lumped_mass_is_spread_over_its_part() -> None:
    extra = 0.05  # kg on the last 20 mm
    bare, _ = bat_mass_properties(tube(), circumferential=96, axial_size=0.005, pivot=PIVOT)
    loaded, _ = bat_mass_properties(tube(extra), circumferential=96, axial_size=0.005, pivot=PIVOT)
    x_cap = L - 0.01
    assert loaded.mass - bare.mass == pytest.approx(extra, rel=1e-12)
    expected_bp = (bare.mass * bare.balance_point + extra * x_cap) / (bare.mass + extra)
    assert loaded.balance_point == pytest.approx(expected_bp, rel=1e-9)
    # a 20-mm band of radius R: m ((x - p)^2 + 0.02^2 / 12 + R^2 / 2), faceting within 1e-3
    band = extra * ((x_cap - PIVOT) ** 2 + 0.02**2 / 12 + R**2 / 2)
    assert loaded.moi_pivot - bare.moi_pivot == pytest.approx(band, rel=1e-3)


def test_flat_rectangle_is_integrated_exactly() -> None:
    a, b = 0.3, 0.1  # m along x and y
    points = np.array([[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, b, 0.0], [0.0, b, 0.0]])
    mesh = ShellMesh(points=points + [0.2, -0.05, 0.0], cells=np.array([[0, 1, 2, 3]]))
    props = shell_mass_properties(mesh, np.array([4.0]), pivot=0.0)
    mass = 4.0 * a * b
    assert props.mass == pytest.approx(mass, rel=1e-12)
    assert props.balance_point == pytest.approx(0.35, rel=1e-12)
    assert props.moi_cm == pytest.approx(mass * (a**2 + b**2) / 12, rel=1e-12)
    assert props.moi_pivot == pytest.approx(mass * ((a**2 + b**2) / 12 + 0.35**2), rel=1e-12)


def test_trapezoid_mass_and_centroid_are_exact() -> None:
    # trapezoid with parallel sides 0.2 (at x = 0) and 0.1 (at x = 0.3), symmetric about y = 0
    points = np.array([[0.0, -0.1, 0.0], [0.3, -0.05, 0.0], [0.3, 0.05, 0.0], [0.0, 0.1, 0.0]])
    mesh = ShellMesh(points=points, cells=np.array([[0, 1, 2, 3]]))
    props = shell_mass_properties(mesh, np.array([1.0]), pivot=0.0)
    assert props.mass == pytest.approx(0.5 * (0.2 + 0.1) * 0.3, rel=1e-12)
    # centroid from the wide side: h (a + 2b) / (3 (a + b)) with a = 0.2, b = 0.1
    assert props.balance_point == pytest.approx(0.3 * (0.2 + 0.2) / (3 * 0.3), rel=1e-12)
