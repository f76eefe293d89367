"""Explicit use of the layered Belytschko-Tsay shell: lumped mass, stable step, dynamic relaxation.

* Lumped mass (docs/physics.md section 6.1): each node gets a quarter of every attached cell's
  m0 A on its three translations, and on its three rotations the larger of the physical rotary
  inertia (I2 A / 4) and (m0 A / 4) (A + t^2) / 12. The second term is LS-DYNA's practice of
  scaling the shells' rotary inertia so that the membrane, not the rotations, set the stable step:
  a node's rotational stiffness grows as kappa G t A (shear) + E t^3 (bending), and with the
  (A + t^2) inertia its frequency stays below the membrane one, about 2 c / h, even for t ~ h
  (A alone was not enough there: a 10-mm plate on 10-mm quads went unstable). It slows rotations,
  so it is for explicit dynamics and relaxation, not for modal analysis (which uses
  :mod:`batball.elements.shell_stiffness`).
* Stable step (docs/physics.md section 6.2): dt_e = L_s / c, L_s = area / longest side, c the
  stiffest layer's plate wave speed; dt = time_step_factor * min dt_e (TSSFAC 0.9). Selective mass
  scaling (LS-DYNA DT2MS < 0) adds mass to the few cells whose step is below a target.
* Dynamic relaxation: central differences with mass-proportional damping c = 2 omega_1 (critical
  for the lowest mode), omega_1 from the Rayleigh quotient of the current displacement
  (Underwood 1983), for static answers of the explicit element.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from batball.elements.shell_bt import bt_internal_forces, initial_force_state
from batball.elements.shell_bt_section import HG_THICKNESS, LayeredSection
from batball.mesh.shell import quad_areas

#: LS-DYNA TSSFAC default.
TIME_STEP_FACTOR = 0.9


def lumped_shell_mass(
    points: np.ndarray,
    cells: np.ndarray,
    section: LayeredSection,
    *,
    areal_mass: np.ndarray | None = None,
    scale_rotary_inertia: bool = True,
) -> np.ndarray:
    """Diagonal mass of the shells, (n_points, 6): kg on translations, kg m^2 on rotations.

    Args:
        points: (n_points, 3), m.
        cells: (n_cells, 4).
        section: layer data (areal mass and rotary inertia of each cell's laminate).
        areal_mass: per-cell m0 replacing the laminate's (structural plus non-structural mass),
            (n_cells,), kg/m^2.
        scale_rotary_inertia: raise the rotary inertia to m (A + t^2) / 12 (module docs).
    """
    area = quad_areas(points, cells)
    m0 = section.areal_mass[section.cell_laminate] if areal_mass is None else areal_mass
    node_mass = 0.25 * m0 * area
    rotary = 0.25 * section.rotary_inertia[section.cell_laminate] * area
    if scale_rotary_inertia:
        thickness = section.hourglass_moduli[section.cell_laminate, HG_THICKNESS]
        rotary = np.maximum(rotary, node_mass * (area + thickness**2) / 12.0)
    mass = np.zeros((points.shape[0], 6))
    for k, per_cell in ((0, node_mass), (3, rotary)):
        summed = np.bincount(cells.ravel(), weights=np.repeat(per_cell, 4),
                             minlength=points.shape[0])  # fmt: skip
        mass[:, k : k + 3] = summed[:, None]
    return mass


def cell_stable_steps(points: np.ndarray, cells: np.ndarray, section: LayeredSection) -> np.ndarray:
    """Each shell's critical step area / longest side / c, (n_cells,) [s] (no TSSFAC)."""
    x = points[cells]
    sides = np.linalg.norm(x - np.roll(x, -1, axis=1), axis=2).max(axis=1)
    speed = section.wave_speed[section.cell_laminate]
    return np.asarray(quad_areas(points, cells) / sides / speed)


def stable_time_step(
    points: np.ndarray, cells: np.ndarray, section: LayeredSection, *,
    time_step_factor: float = TIME_STEP_FACTOR,
) -> float:  # fmt: skip
    """Explicit stable step of the shells, s: factor * min(area / longest side / c)."""
    return float(time_step_factor * np.min(cell_stable_steps(points, cells, section)))


def selective_mass_scaling(
    points: np.ndarray, cells: np.ndarray, section: LayeredSection, target_step: float, *,
    time_step_factor: float = TIME_STEP_FACTOR,
) -> np.ndarray:  # fmt: skip
    """Areal mass to add to the shells whose step is below ``target_step``, (n_cells,) [kg/m^2].

    LS-DYNA ``*CONTROL_TIMESTEP`` with DT2MS < 0 (selective mass scaling): mass is added only
    to the elements whose step, TSSFAC dt_e, would be less than TSSFAC |DT2MS| (here
    ``target_step``, the step wanted), so that their step becomes equal to it; the others are
    untouched (LS-DYNA support, "Mass scaling", https://lsdyna.ansys.com/mass-scaling/). The
    plate wave speed goes as 1 / sqrt(density), so a cell whose step is short by the ratio
    r = target / (TSSFAC dt_e) < 1 gets its laminate's areal mass m0 multiplied by 1 / r^2:
    added m0 (1 / r^2 - 1). m0 is the laminate's own areal mass (the one its wave speed
    belongs to), so the lumped non-structural mass a cell may carry is extra inertia on top.

    Args:
        points: (n_points, 3) [m]; cells: (n_cells, 4); section: layer data.
        target_step: the step to reach [s] (TSSFAC already applied, like the returned steps of
            :func:`stable_time_step`).
        time_step_factor: TSSFAC.
    """
    steps = time_step_factor * cell_stable_steps(points, cells, section)
    ratio = np.minimum(steps / target_step, 1.0)
    return np.asarray(section.areal_mass[section.cell_laminate] * (1.0 / ratio**2 - 1.0))


@dataclass(frozen=True)
class RelaxationResult:
    """A static answer by dynamic relaxation.

    Attributes:
        displacement: (u, theta) per node, (n_points, 6), m and rad.
        n_steps: central-difference steps taken.
        residual: final |f_ext - f_int| on the free dofs over |f_ext|.
    """

    displacement: np.ndarray
    n_steps: int
    residual: float


def dynamic_relaxation(
    points: np.ndarray,
    cells: np.ndarray,
    section: LayeredSection,
    load: np.ndarray,
    fixed: np.ndarray,
    *,
    tolerance: float = 1e-6,
    max_steps: int = 200_000,
) -> RelaxationResult:
    """Static equilibrium of the BT shells under a dead load by damped central differences.

    Args:
        points: reference coordinates, (n_points, 3), m.
        cells: (n_cells, 4).
        section: layer data.
        load: external forces and moments, (n_points, 6), N and N m.
        fixed: dofs held at zero, (n_points, 6), bool.
        tolerance: stop when the free-dof residual norm falls below tolerance * |load|.
        max_steps: give up after this many steps (the result says how far it got).
    """
    mass = lumped_shell_mass(points, cells, section)
    dt = stable_time_step(points, cells, section)
    state = initial_force_state(section)
    u, v = np.zeros_like(load), np.zeros_like(load)
    free = ~fixed
    scale = np.linalg.norm(load[free])
    internal, residual = np.zeros_like(load), np.inf
    for step in range(1, max_steps + 1):
        residual_force = np.where(free, load - internal, 0.0)
        residual = float(np.linalg.norm(residual_force) / scale)
        if residual < tolerance and step > 1:
            return RelaxationResult(u, step - 1, residual)
        damping = 2.0 * lowest_frequency_estimate(u, internal, mass)
        v = ((2.0 - damping * dt) * v + 2.0 * dt * residual_force / mass) / (2.0 + damping * dt)
        u += dt * v
        internal = bt_internal_forces(points + u[:, :3], cells, section, v, dt, state)
    return RelaxationResult(u, max_steps, residual)


def lowest_frequency_estimate(u: np.ndarray, internal: np.ndarray, mass: np.ndarray) -> float:
    """omega_1 ~ sqrt(u . f_int / u . M u), rad/s (0 before anything moves)."""
    work, inertia = float(np.sum(u * internal)), float(np.sum(mass * u * u))
    return float(np.sqrt(max(work, 0.0) / inertia)) if inertia > 0.0 else 0.0
