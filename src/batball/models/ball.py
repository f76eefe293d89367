"""The meshed ball every ball test and the ball-bat collision start from: its hexes, material
constants, density (the FE ball weighs exactly its spec mass), and the penalty stiffness of its
surface nodes (LS-DYNA SOFT = 0 or 1, :mod:`batball.contact.rigid`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from batball.contact.rigid import (
    nodal_stiffness,
    segment_stiffness,
)
from batball.errors import SpecError
from batball.materials.base import BULK, G0
from batball.materials.foam import FoamTable
from batball.mesh import Mesh, boundary_faces, hex_volumes, make_ball_mesh
from batball.solvers.explicit import HourglassControl
from batball.specs import BallSpec

SetupT = TypeVar("SetupT")


def ball_hourglass(test: HourglassControl | None, ball: BallSpec) -> HourglassControl:
    """The hourglass control a run of ``ball`` uses: the test's when it sets one, else the one
    the ball's model names, else the solver default (viscous IHQ 1, QH 0.1)."""
    if test is not None:
        return test
    if ball.hourglass is not None:
        return HourglassControl(type=ball.hourglass.type, coefficient=ball.hourglass.coefficient)
    return HourglassControl()


def with_ball_hourglass(setup: SetupT, ball: BallSpec) -> SetupT:
    """``setup`` (any setup dataclass with an ``hourglass`` field) with the hourglass control
    of :func:`ball_hourglass` filled in, so that its run key, summary and deck name it."""
    current: Any = getattr(setup, "hourglass")  # noqa: B009 (typed by the setup dataclasses)
    return dataclasses.replace(setup, hourglass=ball_hourglass(current, ball))  # type: ignore[type-var]


@dataclass(frozen=True)
class ContactOptions:
    """Penalty contact settings (LS-DYNA names): SOFT (0 or 1), SLSFAC, SFS and SOFSCL."""

    soft: int = 0
    slsfac: float = 0.1
    sfs: float = 1.0
    sofscl: float = 0.1

    def __post_init__(self) -> None:
        if self.soft not in (0, 1):
            raise SpecError("contact.soft", self.soft, "0 (bulk-modulus penalty) or 1 (stability)")
        for name in ("slsfac", "sfs", "sofscl"):
            if not getattr(self, name) > 0:
                raise SpecError(f"contact.{name}", getattr(self, name), "a positive factor")


def ball_contact_stiffness(
    mesh: Mesh, bulk_modulus: float, density: float, options: ContactOptions, first_dt: float
) -> tuple[np.ndarray, np.ndarray]:
    """Surface node ids and their penalty stiffness [N/m] (SOFT = 0 or 1, see contact.rigid)."""
    faces, owner = boundary_faces(mesh.cells)
    volumes = hex_volumes(mesh.points, mesh.cells)[owner]
    k_faces = segment_stiffness(
        mesh.points,
        faces,
        volumes,
        np.full(len(faces), bulk_modulus),
        scale=options.slsfac * options.sfs,
    )
    nodes = np.unique(faces)
    k0 = nodal_stiffness(faces, k_faces, nodes, mesh.n_points)
    if options.soft == 0:
        return nodes, k0
    from batball.solvers.explicit_kernels import lumped_masses

    node_mass = lumped_masses(
        mesh.cells, density * hex_volumes(mesh.points, mesh.cells), mesh.n_points
    )[nodes]
    k1 = 0.5 * node_mass / first_dt**2
    return nodes, np.maximum(k0, options.sofscl * k1)


@dataclass(frozen=True)
class BallBody:
    """The meshed ball every ball test starts from: mesh, kernel constants, density and the
    penalty stiffness of its surface nodes [N/m]."""

    mesh: Mesh
    constants: np.ndarray
    density: float
    nodes: np.ndarray
    stiffness: np.ndarray
    foam: FoamTable | None = None  # a foam ball's packed material


def ball_body(
    ball: BallSpec,
    divisions: int,
    contact: ContactOptions,
    time_step_scale: float,
    mass_scale: float = 1.0,
) -> BallBody:
    """Mesh the ball, take its material constants, and size its contact penalty.

    ``mass_scale`` multiplies the density the SOFT = 1 stiffness sees (quasi-static tests).
    """
    mesh = make_ball_mesh(ball.radius, divisions=divisions)
    constants = ball.material.kernel_constants()
    # the FE ball weighs exactly the spec mass: density on the faceted mesh volume
    density = ball.mass / float(hex_volumes(mesh.points, mesh.cells).sum())
    scaled = density * mass_scale
    first_dt = estimate_first_step(mesh, constants, scaled) * time_step_scale
    bulk = float(constants[BULK])
    nodes, stiffness = ball_contact_stiffness(mesh, bulk, scaled, contact, first_dt)
    return BallBody(mesh, constants, density, nodes, stiffness, ball.material.foam_table())


def estimate_first_step(mesh: Mesh, constants: np.ndarray, density: float) -> float:
    """Stable element step of the undeformed mesh, min L_e / c [s] (before TSSFAC)."""
    from batball.mesh import characteristic_lengths

    c = np.sqrt((constants[BULK] + 4.0 / 3.0 * constants[G0]) / density)
    return float(characteristic_lengths(mesh.points, mesh.cells).min() / c)
