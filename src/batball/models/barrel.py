"""The double-wall bat as a static shell model, its insert's interference fit, and the barrel
compression fixture (the test itself is :mod:`batball.lab.barrel`, whose docstring gives the
protocol and the seed's figures it follows).

The bat's MITC4 shells (:mod:`batball.elements.shell_stiffness`), linear elastic, small
displacements; the insert touches the barrel's bore (the spec's outer radius minus the part's wall)
through node-to-surface penalty gaps from its outer surface (mid-surface + t/2). The fit is a static
frictionless penalty solve in place of LS-DYNA's dynamic relaxation: for a linear-elastic,
frictionless fit the end state does not depend on the path, so removing the overlap in
``ramp_steps`` static steps gives the state dynamic relaxation converges to. The fixture: two rigid
half-cylinder platens across the bat, with the seed's supports (the rings under the platens held
axially, the four nodes on the load axis held sideways).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from batball.contact.shell_contact import (
    PenaltyGaps,
    coaxial_ring_gaps,
    gap_matrix,
    nodal_areas,
    rigid_cylinder_gaps,
)
from batball.elements.shell_stiffness import (
    ShellSection,
    assemble_shell_stiffness,
)
from batball.errors import SimulationError, SpecError
from batball.mesh.bat import (
    DEFAULT_AXIAL_SIZE,
    DEFAULT_CIRCUMFERENTIAL,
    make_bat_mesh,
    outer_rings,
)
from batball.mesh.shell import ShellMesh
from batball.models.bat import bat_section
from batball.solvers.static_contact import (
    FactorReuse,
    solve_static_contact,
)
from batball.specs.bat import BatSpec
from batball.units import IN


@dataclass(frozen=True)
class BarrelTestOptions:
    """The barrel compression protocol (seed "Bat Barrel Compression"), SI.

    Attributes:
        platen_diameter: m (the seed's FE platens: 3.3 in; its fixture: 3.86 in).
        distance_from_cap: platen centre from the end-cap end of the bat, m (6 in).
        preload_travel: first platen travel, m (0.02 in).
        final_travel: further travel after zeroing, m (0.05 in).
        orientations_deg: bat rotations about its axis, deg (0, 90, 45, -45).
        preload_steps: travel levels up to the preload (force-displacement curve).
        final_steps: travel levels from the preload to the final travel.
        curve_orientations: how many of the orientations (first ones) get all levels; the rest are
            solved at the preload and final travel only.
        penalty_factor: contact penalty per area over the stiffest hoop membrane stiffness
            A22 / R^2 of the barrel or insert (dimensionless).
        friction: Coulomb coefficient between insert and barrel during the compression (None,
            the default: the bat's own, ``InsertSpec.friction``, resolved by :meth:`for_bat`;
            0: frictionless, the seed's; > 0 solves every orientation in load steps over the
            curve levels, :func:`compress_barrel_with_friction`).
        platen_friction: Coulomb coefficient between the platens and the barrel's outer surface
            (0: frictionless, the seed's; > 0 solves as ``friction`` does).
    """

    platen_diameter: float = 3.3 * IN
    distance_from_cap: float = 6.0 * IN
    preload_travel: float = 0.02 * IN
    final_travel: float = 0.05 * IN
    orientations_deg: tuple[float, ...] = (0.0, 90.0, 45.0, -45.0)
    preload_steps: int = 4
    final_steps: int = 5
    curve_orientations: int = 1
    penalty_factor: float = 1e3
    friction: float | None = None
    platen_friction: float = 0.0

    def __post_init__(self) -> None:
        for name in ("friction", "platen_friction"):
            mu = getattr(self, name)
            if mu is not None and not (np.isfinite(mu) and 0.0 <= mu <= 10.0):
                raise SpecError(name, mu, "a coefficient 0 .. 10")

    def for_bat(self, spec: BatSpec) -> BarrelTestOptions:
        """These options with the insert's friction settled: the bat's own where not given."""
        if self.friction is not None:
            return self
        return replace(self, friction=spec.insert.friction if spec.insert else 0.0)

    @property
    def insert_friction(self) -> float:
        """The insert's Coulomb coefficient (the options settled by :meth:`for_bat`).

        Raises:
            SimulationError: options not yet settled for a bat.
        """
        if self.friction is None:
            raise SimulationError("barrel compression: the insert's friction is the bat's; "
                                  "settle the options with for_bat(spec) first")  # fmt: skip
        return self.friction

    @property
    def frictional(self) -> bool:
        """Whether any contact of the squeeze has friction."""
        return self.insert_friction > 0.0 or self.platen_friction > 0.0

    def travels(self, *, curve: bool) -> np.ndarray:
        """Platen travels solved, m: all curve levels or just (preload, preload + final)."""
        if not curve:
            return np.array([self.preload_travel, self.preload_travel + self.final_travel])
        first = np.linspace(0.0, self.preload_travel, self.preload_steps + 1)[1:]
        second = self.preload_travel + np.linspace(0.0, self.final_travel, self.final_steps + 1)
        return np.concatenate([first, second[1:]])


@dataclass(frozen=True)
class BarrelModel:
    """The bat's shells with the insert's contact (a static Model; states live elsewhere).

    Attributes:
        spec: the bat.
        mesh: its shells (outer wall nodes first, then the insert's).
        section: per-cell section constants.
        stiffness: K, (6 n_points)^2, SI.
        interference: the insert-barrel gaps, one per insert node.
        outer_rings: outer-wall nodes ring by ring, (n_rings, circumferential).
        outer_offsets: outer surface minus mid-surface radius of every node, (n_points,), m.
        contact_stiffness_per_area: penalty per contact area, N/m^3.
    """

    spec: BatSpec
    mesh: ShellMesh
    section: ShellSection
    stiffness: sp.csr_matrix
    interference: PenaltyGaps
    outer_rings: np.ndarray
    outer_offsets: np.ndarray
    contact_stiffness_per_area: float

    @property
    def insert_nodes(self) -> np.ndarray:
        """The insert's nodes, (n_insert,)."""
        return self.mesh.point_sets["insert"]


def cell_thickness(spec: BatSpec, mesh: ShellMesh) -> np.ndarray:
    """Wall of every cell, (n_cells,), m."""
    thickness = np.zeros(mesh.n_cells)
    for part in spec.parts:
        thickness[mesh.cell_sets[part.name]] = spec.laminate(part.layup).thickness
    if spec.insert is not None:
        thickness[mesh.cell_sets["insert"]] = spec.laminate(spec.insert.layup).thickness
    return thickness


def wall_at(spec: BatSpec, x: np.ndarray) -> np.ndarray:
    """Wall of the part that starts at or before x (the later part at a boundary), (n,), m."""
    starts = np.array([part.start for part in spec.parts])
    walls = np.array([spec.laminate(part.layup).thickness for part in spec.parts])
    return walls[np.clip(np.searchsorted(starts, x, side="right") - 1, 0, len(walls) - 1)]


def bore_offsets(spec: BatSpec, points: np.ndarray) -> np.ndarray:
    """Each node's mid-surface radius minus the bore's (the outer wall's inner surface) at its
    x, (n_points,), m: how far inside its mid-surface the barrel's contact surface lies."""
    x, radius = points[:, 0], np.hypot(points[:, 1], points[:, 2])
    return radius - (np.asarray(spec.outer_radius(x)) - wall_at(spec, x))


def insert_half_wall(spec: BatSpec) -> float:
    """Half the insert's wall, m: its contact surface lies this far outside its mid-surface."""
    assert spec.insert is not None
    return 0.5 * spec.laminate(spec.insert.layup).thickness


def contact_stiffness_per_area(spec: BatSpec, mesh: ShellMesh, section: ShellSection,
                               factor: float) -> float:  # fmt: skip
    """factor * max(A22) / R_bore^2 over the insert and the barrel cells beside it, N/m^3."""
    assert spec.insert is not None
    centre_x = mesh.points[mesh.cells, 0].mean(axis=1)
    beside = (centre_x > spec.insert.start) & (centre_x < spec.insert.end)
    hoop = section.abd[beside, 1, 1].max()
    bore = spec.insert_outer_radius() - spec.insert.interference
    return factor * float(hoop) / bore**2


def build_barrel_model(
    spec: BatSpec,
    *,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
    penalty_factor: float = 1e3,
) -> BarrelModel:
    """The bat's stiffness and its insert-barrel gaps (module docs).

    Raises:
        SpecError: a bat without an insert, or ``circumferential`` not a multiple of 8 (the
            platens at 0, 45, 90 and -45 deg must meet nodes).
    """
    if spec.insert is None:
        raise SpecError("insert", None, "a double-wall bat with an [insert] table")
    if circumferential % 8:
        raise SpecError("circumferential", circumferential,
                        "a multiple of 8 (platens at 0, 45, 90, -45 deg meet nodes)")  # fmt: skip
    mesh = make_bat_mesh(spec, circumferential=circumferential, axial_size=axial_size)
    section = bat_section(spec, mesh)
    rings = outer_rings(mesh)
    x, radius = mesh.points[:, 0], np.hypot(mesh.points[:, 1], mesh.points[:, 2])
    outer_offsets = np.asarray(spec.outer_radius(x)) - radius
    insert = mesh.point_sets["insert"]
    k_area = contact_stiffness_per_area(spec, mesh, section, penalty_factor)
    interference = coaxial_ring_gaps(
        mesh.points, slave_nodes=insert, master_rings=rings,
        slave_offsets=np.full(insert.size, insert_half_wall(spec)),
        master_offsets=bore_offsets(spec, mesh.points),
        slave_areas=nodal_areas(mesh.points, mesh.cells)[insert], stiffness_per_area=k_area,
    )  # fmt: skip
    stiffness = assemble_shell_stiffness(mesh, section)
    return BarrelModel(spec, mesh, section, stiffness, interference, rings, outer_offsets,
                       k_area)  # fmt: skip


@dataclass(frozen=True)
class Prestress:
    """The interference-fit state (the drdisp of the seed's LS-DYNA runs).

    Attributes:
        u: displacements and rotations, (6 n_points,), m and rad.
        contact_force: compressive force of each insert node's gap, (n_insert,), N.
        contact_pressure: that force over the node's tributary area, (n_insert,), Pa.
        active: closed gaps, (n_insert,) bool.
        ramp_pressure: mean contact pressure after each ramp step, (ramp_steps,), Pa.
    """

    u: np.ndarray
    contact_force: np.ndarray
    contact_pressure: np.ndarray
    active: np.ndarray
    ramp_pressure: np.ndarray = field(default_factory=lambda: np.zeros(0))


def prestress_supports(model: BarrelModel) -> np.ndarray:
    """Fixed dofs of the free bat during the fit: one outer node (all six), and the insert's
    axial and spin freedoms at its first node (phi = 0: tangent = z). The load is
    self-equilibrated, so the reactions vanish."""
    first = model.insert_nodes[0]
    return np.concatenate([np.arange(6), 6 * first + np.array([0, 2])])


def contact_areas(model: BarrelModel) -> np.ndarray:
    """Each insert node's share of the contact surface (its outer surface), (n_insert,), m^2."""
    insert = model.insert_nodes
    radius = np.hypot(model.mesh.points[insert, 1], model.mesh.points[insert, 2])
    half_wall = insert_half_wall(model.spec)
    mid_areas = model.interference.stiffness / model.contact_stiffness_per_area
    return mid_areas * (radius + half_wall) / radius


def compute_prestress(model: BarrelModel, *, ramp_steps: int = 1) -> Prestress:
    """Remove the insert's overlap in ``ramp_steps`` static steps (module docs).

    Step s of n solves with the overlap scaled by s / n: g0 + (1 - s/n) * interference.
    """
    if ramp_steps < 1:
        raise SpecError("ramp_steps", ramp_steps, "an integer >= 1")
    interference = model.spec.insert.interference if model.spec.insert else 0.0
    fixed = prestress_supports(model)
    areas = contact_areas(model)
    active, pressures, reuse = None, [], FactorReuse()
    for step in range(1, ramp_steps + 1):
        gaps = model.interference.shifted((1.0 - step / ramp_steps) * interference)
        solution = solve_static_contact(model.stiffness, [gaps], fixed_dofs=fixed,
                                        initial_active=active, where="interference pre-stress",
                                        reuse=reuse)  # fmt: skip
        active = solution.active
        pressures.append(solution.forces[0].sum() / areas.sum())
    force = solution.forces[0]
    return Prestress(solution.u, force, force / areas, solution.active[0], np.array(pressures))


def load_axes(orientation_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit load direction e (towards the top platen) and the sideways direction p = x cross e."""
    angle = np.radians(orientation_deg)
    load = np.array([0.0, np.cos(angle), np.sin(angle)])
    return load, np.cross([1.0, 0.0, 0.0], load)


def platen_gaps(model: BarrelModel, options: BarrelTestOptions, orientation_deg: float,
                travel: float, prestress_u: np.ndarray) -> list[PenaltyGaps]:  # fmt: skip
    """Top (moved ``travel`` towards the bat) and bottom (fixed) platen gaps; at zero travel each
    platen just touches the pre-stressed outer surface (displacements ``prestress_u``, the fit
    swells the barrel by about 0.0005 in): the gauges are zeroed at first contact."""
    load, sideways = load_axes(orientation_deg)
    radius = 0.5 * options.platen_diameter
    points = model.mesh.points
    gap_sets = []
    for (nodes, axis_point), shift in zip(platen_sides(model, options, orientation_deg),
                                          (travel, 0.0), strict=True):  # fmt: skip
        stiffness = model.contact_stiffness_per_area * nodal_areas(points, model.mesh.cells)[nodes]
        at_zero, moved = (rigid_cylinder_gaps(
            points, nodes=nodes, offsets=model.outer_offsets[nodes], radius=radius,
            axis_point=axis_point - s * load, axis_direction=sideways, stiffness=stiffness,
        ) for s in (0.0, shift))  # fmt: skip
        # Zero travel = first touch: no ring need lie under the platen's apex. The normals stay
        # those at first touch (small displacements), so a level's matrix depends on its closed
        # gaps only and a kept factorisation serves the next level exactly.
        first_touch = at_zero.gaps(prestress_u).min()
        gap_sets.append(replace(at_zero, initial=moved.initial - first_touch))
    return gap_sets


def platen_sides(model: BarrelModel, options: BarrelTestOptions,
                 orientation_deg: float) -> list[tuple[np.ndarray, np.ndarray]]:  # fmt: skip
    """The top and the bottom platen: each one's candidate outer-wall nodes (within its radius
    of its centre, on its side of the bat) and a point of its axis at zero travel (m)."""
    load, _ = load_axes(orientation_deg)
    radius = 0.5 * options.platen_diameter
    centre_x = model.spec.length - options.distance_from_cap
    outer = model.outer_rings.ravel()
    points = model.mesh.points
    near = np.abs(points[outer, 0] - centre_x) < radius
    reach = float(model.spec.outer_radius(centre_x)) + radius
    centre = np.array([centre_x, 0.0, 0.0])
    return [(outer[near & (side * (points[outer] @ load) > 0.0)], centre + side * reach * load)
            for side in (1.0, -1.0)]  # fmt: skip


def support_nodes(points: np.ndarray, outer: np.ndarray, insert: np.ndarray, centre_x: float,
                  load: np.ndarray, orientation_deg: float,
                  ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The seed's supports (Figures 11-12): the barrel's (``outer`` nodes) and the insert's ring
    nearest the platen centre ``centre_x`` (held axially), and their four nodes on the load axis
    ``load`` (held sideways); (ring nodes, load-axis nodes)."""
    rings = []
    for nodes in (outer, insert):
        ring_x = points[nodes, 0]
        nearest = np.abs(ring_x - ring_x[np.argmin(np.abs(ring_x - centre_x))]) < 1e-9
        rings.append(nodes[nearest])
    ring_nodes = np.concatenate(rings)
    direction = points[ring_nodes] @ load / np.hypot(points[ring_nodes, 1], points[ring_nodes, 2])
    on_axis = ring_nodes[np.abs(np.abs(direction) - 1.0) < 1e-9]
    if on_axis.size != 4:
        raise SpecError("orientation", orientation_deg, "an angle at which nodes lie on the axis")
    return ring_nodes, on_axis


def compression_supports(model: BarrelModel, options: BarrelTestOptions,
                         orientation_deg: float) -> tuple[np.ndarray, PenaltyGaps]:  # fmt: skip
    """The seed's supports (Figures 11-12): axial dofs of the barrel and insert rings nearest the
    platen centre (fixed dofs), and bilateral sideways springs on their four load-axis nodes."""
    load, sideways = load_axes(orientation_deg)
    points = model.mesh.points
    ring_nodes, on_axis = support_nodes(points, model.outer_rings.ravel(), model.insert_nodes,
                                        model.spec.length - options.distance_from_cap, load,
                                        orientation_deg)  # fmt: skip
    springs = PenaltyGaps(
        gap_matrix(on_axis[:, None], np.ones((4, 1)), np.tile(sideways, (4, 1)), len(points)),
        np.zeros(4), np.full(4, model.interference.stiffness.max()), bilateral=True,
    )  # fmt: skip
    return 6 * ring_nodes, springs


def thin_ring_interference_pressure(spec: BatSpec) -> float:
    """docs/physics.md section 6.7: p = delta / (R_o^2/(E_theta,o t_o) + R_i^2/(E_theta,i t_i)), Pa,
    with the barrel part at the insert's middle and mid-surface radii."""
    assert spec.insert is not None
    middle = 0.5 * (spec.insert.start + spec.insert.end)
    barrel = spec.laminate(next(p for p in spec.parts if p.start <= middle < p.end).layup)
    insert = spec.laminate(spec.insert.layup)
    r_outer = float(spec.outer_radius(middle)) - 0.5 * barrel.thickness
    r_inner = spec.insert_outer_radius() - 0.5 * insert.thickness
    compliance = (r_outer**2 / (barrel.hoop_modulus * barrel.thickness)
                  + r_inner**2 / (insert.hoop_modulus * insert.thickness))  # fmt: skip
    return spec.insert.interference / compliance
