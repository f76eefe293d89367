"""The double-wall bat: interference-fit pre-stress and the barrel compression test.

Seed: "Construction of the Composite Bat Finite Element Model" (the 10-in insert pressed in with a
0.001-in interference, pre-stressed by dynamic relaxation, Figures 10 and 13), "Bat Barrel
Compression" and "Barrel Compression" (Table 2); physics.md sections 5.1 and 6.7.

Model: the bat's MITC4 shells (:mod:`batball.elements.shell_stiffness`), linear elastic, small
displacements. The insert touches the barrel through node-to-surface penalty gaps
(:func:`batball.contact.shell_contact.coaxial_ring_gaps`) between the insert's outer surface
(mid-surface + t/2) and the barrel's bore (the spec's outer radius minus the part's wall, so
that the averaged mid-surface at a wall step does not invent overlap). The pre-stress is a
static frictionless penalty solve (:mod:`batball.solvers.static_contact`) in place of LS-DYNA's
dynamic relaxation: for a linear-elastic, frictionless fit the end state does not depend on the
path, so removing the overlap in ``ramp_steps`` static steps (scaling it as LS-DYNA scales the
contact thickness) gives the state DR converges to, without the thousands of explicit cycles.

The compression test: two rigid half-cylinder platens (3.3-in diameter as in the seed's model,
axes across the bat) centred ``distance_from_cap`` from the end cap; the bottom one fixed, the
top one moved towards the bat; the outer wall's outer surface contacts them through penalty
gaps. Supports as the seed's Figures 11-12: the barrel and insert rings under the platens held
axially, and the four nodes on the load axis held sideways. Forces at each travel come from one
penalty-contact problem with the interference gaps still in place (so the pre-stress is the
initial state), factorised once per orientation with the platen gaps condensed
(:class:`batball.solvers.static_contact.CondensedContact`). Preload = F(0.02 in); final load =
F(0.07 in) - F(0.02 in) (the seed's "zeroed" force: its FE pair 155 / 386 lbf is in the linear
ratio 2.5 that this definition gives; docs/barrel.md weighs the other readings).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from batball.contact.shell_contact import (
    PenaltyGaps,
    coaxial_ring_gaps,
    coaxial_ring_slips,
    gap_matrix,
    nodal_areas,
    rigid_cylinder_gaps,
    rigid_cylinder_slips,
)
from batball.elements.shell_stiffness import (
    ShellSection,
    assemble_shell_stiffness,
    element_frames,
    jacobians,
    membrane_bending_matrix,
)
from batball.errors import SpecError
from batball.mesh.bat import (
    DEFAULT_AXIAL_SIZE,
    DEFAULT_CIRCUMFERENTIAL,
    make_bat_mesh,
    outer_rings,
)
from batball.mesh.shell import ShellMesh
from batball.models.bat import bat_section
from batball.solvers.static_contact import (
    CondensedContact,
    CoulombFriction,
    FactorReuse,
    solve_frictional_step,
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
        friction: Coulomb coefficient between insert and barrel during the compression (0:
            frictionless, the seed's; > 0 solves every orientation in load steps over the curve
            levels, :func:`compress_barrel_with_friction`).
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
    friction: float = 0.0
    platen_friction: float = 0.0

    def __post_init__(self) -> None:
        for name in ("friction", "platen_friction"):
            mu = getattr(self, name)
            if not (np.isfinite(mu) and 0.0 <= mu <= 10.0):
                raise SpecError(name, mu, "a coefficient 0 .. 10")

    @property
    def frictional(self) -> bool:
        """Whether any contact of the squeeze has friction."""
        return self.friction > 0.0 or self.platen_friction > 0.0

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


@dataclass(frozen=True)
class CompressionCurve:
    """One orientation's force-travel record.

    Attributes:
        orientation_deg: rotation of the bat about its axis, deg.
        travel: platen travel of each level, (n_levels,), m.
        force: platen force along the load axis, (n_levels,), N.
        insert_top, insert_bottom: sum of the insert-barrel contact forces on the top and bottom
            halves of the insert (seed Figure 13; nodes on the dividing plane count half to each),
            (n_levels,), N.
        iterations: triangular solves (pairs of forward and back substitutions) used.
        factorisations: factorisations used.
    """

    orientation_deg: float
    travel: np.ndarray
    force: np.ndarray
    insert_top: np.ndarray
    insert_bottom: np.ndarray
    iterations: int
    factorisations: int = 0

    def force_at(self, travel: float) -> float:
        """Force at a solved travel, N."""
        return float(self.force[np.argmin(np.abs(self.travel - travel))])


def along(gaps: PenaltyGaps | sp.spmatrix, direction: np.ndarray, n_points: int) -> np.ndarray:
    """n . direction of each gap's normal, (n_gaps,) (G applied to a rigid translation; or any
    rows of that form, as friction's slips)."""
    translation = np.zeros((n_points, 6))
    translation[:, :3] = direction
    matrix = gaps.matrix if isinstance(gaps, PenaltyGaps) else gaps
    return matrix @ translation.ravel()


def radial_cosines(points: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Radial unit vector (from the bat's x axis) of each of ``points`` (n, 3) dotted with
    ``direction`` (3,), (n,): which side of the load axis a node lies on."""
    return (points[:, 1:] @ direction[1:]) / np.hypot(points[:, 1], points[:, 2])


def insert_cosines(model: BarrelModel, direction: np.ndarray) -> np.ndarray:
    """Radial unit vector of each insert node dotted with ``direction``, (n_insert,).

    (Not :func:`along` of the fit gaps: a gap between two bodies does not change under a common
    translation, so that is zero for every gap.)"""
    return radial_cosines(model.mesh.points[model.insert_nodes], direction)


def halves(forces: np.ndarray, cosine: np.ndarray) -> tuple[float, float]:
    """Sums of ``forces`` on the top (cosine > 0) and bottom halves, the plane split evenly."""
    on_plane = np.abs(cosine) < 1e-9
    top = forces[(cosine > 0) & ~on_plane].sum() + 0.5 * forces[on_plane].sum()
    bottom = forces[(cosine < 0) & ~on_plane].sum() + 0.5 * forces[on_plane].sum()
    return float(top), float(bottom)


def condensed_compression(model: BarrelModel, prestress: Prestress, options: BarrelTestOptions,
                          orientation_deg: float, *, insert_may_open: bool = False,
                          ) -> tuple[CondensedContact, list[PenaltyGaps]]:  # fmt: skip
    """The compression's contact problem, factorised once for every travel of one orientation.

    Assumed closed (and checked at every level): the insert's fit gaps closed after the
    pre-stress, the sideways springs, and the bottom platen's first-touch gap (it holds the bat
    against rigid motion along the load). Condensed: the platen gaps within the largest travel of
    the platens at first touch. With ``insert_may_open`` (a weak fit) the insert's gaps are
    condensed too, but for those on the load axis nearest the platens (they hold the insert).
    The platen gap sets returned are those at zero travel."""
    fixed, springs = compression_supports(model, options, orientation_deg)
    top, bottom = platen_gaps(model, options, orientation_deg, 0.0, prestress.u)
    reach = options.preload_travel + options.final_travel
    anchor = bottom.initial <= bottom.initial.min() + 1e-12
    insert_closed, insert_candidates = prestress.active, np.zeros(prestress.active.size, bool)
    if insert_may_open:
        insert_candidates = prestress.active.copy()
        insert_closed = prestress.active & np.isin(model.insert_nodes, fixed // 6)
        on_axis = np.abs(insert_cosines(model, load_axes(orientation_deg)[0])) > 1.0 - 1e-9
        insert_closed &= on_axis
    condensed = CondensedContact(
        model.stiffness, [model.interference, top, bottom, springs], fixed_dofs=fixed,
        closed=[insert_closed, np.zeros(top.n_gaps, bool), anchor, np.ones(4, bool)],
        candidates=[insert_candidates, top.initial < reach, bottom.initial < reach,
                    np.zeros(4, bool)],
        where=f"barrel compression at {orientation_deg:g} deg",
    )  # fmt: skip
    return condensed, [top, bottom, springs]


def compress_barrel(model: BarrelModel, prestress: Prestress, options: BarrelTestOptions,
                    orientation_deg: float, *, curve: bool,
                    insert_may_open: bool = False) -> CompressionCurve:  # fmt: skip
    """Platen travel levels from the pre-stressed state: one factorisation with the platen gaps
    condensed (:class:`batball.solvers.static_contact.CondensedContact`), an exact small contact
    problem per level (module docs). The largest travel is solved first: the few fit gaps that
    open (by nanometres, at the insert's ends) then open at once, costing one more
    factorisation, and stay candidates for the smaller travels."""
    load, _ = load_axes(orientation_deg)
    n_points = model.mesh.n_points
    insert_cosine = insert_cosines(model, load)
    condensed, (top, bottom, springs) = condensed_compression(
        model, prestress, options, orientation_deg, insert_may_open=insert_may_open)
    top_cosine = along(top, load, n_points)
    travels = options.travels(curve=curve)
    force, upper, lower = np.zeros(travels.size), np.zeros(travels.size), np.zeros(travels.size)
    for level in np.argsort(-travels):
        moved, _ = platen_gaps(model, options, orientation_deg, travels[level], prestress.u)
        solution = condensed.solve([model.interference.initial, moved.initial, bottom.initial,
                                    springs.initial])  # fmt: skip
        force[level] = -(solution.forces[1] * top_cosine).sum()
        upper[level], lower[level] = halves(solution.forces[0], insert_cosine)
    return CompressionCurve(orientation_deg, travels, force, upper, lower, condensed.solves,
                            condensed.factorisations)  # fmt: skip


#: The stick spring of a frictional insert pair over its normal penalty: 0.01 and 0.03 give the
#: same loads to 0.01 lbf (docs/barrel.md); from 0.1 up the stick-slip iteration cycles.
STICK_FACTOR = 0.01


def insert_friction(model: BarrelModel, mu: float, *,
                    stick_factor: float = STICK_FACTOR) -> CoulombFriction:  # fmt: skip
    """Coulomb friction ``mu`` on the insert's fit pairs, axial and around; the stick spring of
    each pair is ``stick_factor`` times its normal penalty."""
    if not (np.isfinite(mu) and mu >= 0.0):
        raise SpecError("friction", mu, "a coefficient >= 0")
    slips = coaxial_ring_slips(
        model.mesh.points, slave_nodes=model.insert_nodes, master_rings=model.outer_rings,
        slave_offsets=np.full(model.insert_nodes.size, insert_half_wall(model.spec)),
        master_offsets=bore_offsets(model.spec, model.mesh.points),
    )  # fmt: skip
    return CoulombFriction(slips, ((0,),), stick_factor * model.interference.stiffness, mu)


def with_platen_friction(model: BarrelModel, options: BarrelTestOptions, orientation_deg: float,
                         insert: CoulombFriction, mu: float, *,
                         stick_factor: float = STICK_FACTOR) -> CoulombFriction:  # fmt: skip
    """``insert``'s friction (on the gap set 0) and Coulomb friction ``mu`` between the platens
    and the barrel's outer surface, along the platens' axes and around them, on the gap sets
    of :func:`compress_barrel_with_friction` (1: the top platen; 2 and 3: the bottom one, split
    in two); the stick spring of each pair is ``stick_factor`` times its normal penalty. The
    rows are minus the barrel surface's tangential motion, rotations times the wall's offset
    included; the platens' own sliding over the points beside the apex (they move along the
    load, not along those points' normals) is the prescribed slip that
    :func:`compress_barrel_with_friction` adds at each travel."""
    if not (np.isfinite(mu) and mu >= 0.0):
        raise SpecError("platen_friction", mu, "a coefficient >= 0")
    _, sideways = load_axes(orientation_deg)
    points = model.mesh.points
    rows, stiffness = [list(insert.slips)], [insert.stiffness]
    for nodes, axis_point in platen_sides(model, options, orientation_deg):
        rows.append(list(rigid_cylinder_slips(
            points, nodes=nodes, offsets=model.outer_offsets[nodes], axis_point=axis_point,
            axis_direction=sideways)))  # fmt: skip
        areas = nodal_areas(points, model.mesh.cells)[nodes]
        stiffness.append(stick_factor * model.contact_stiffness_per_area * areas)
    slips = tuple(sp.vstack([r[d] for r in rows]).tocsr() for d in range(2))
    mus = np.concatenate([np.broadcast_to(insert.mu, insert.stiffness.shape),
                          np.full(stiffness[1].size + stiffness[2].size, mu)])  # fmt: skip
    return CoulombFriction(slips, ((0,), (1,), (2, 3)), np.concatenate(stiffness), mus)


def compress_barrel_with_friction(
    model: BarrelModel,
    prestress: Prestress,
    options: BarrelTestOptions,
    orientation_deg: float,
    mu: float,
    *,
    platen_mu: float = 0.0,
    stick_factor: float = STICK_FACTOR,
) -> CompressionCurve:
    """The compression of :func:`compress_barrel` with Coulomb friction ``mu`` between insert
    and barrel, and ``platen_mu`` between the platens and the barrel
    (:func:`with_platen_friction`), by load steps over every curve level (friction makes the
    path count).

    The fit is the frictionless pre-stress (the insert is pressed in axially, so its radial fit
    is taken to have slid to the frictionless state; docs/barrel.md): at zero travel every pair
    sticks with no traction, and the platens' travel then loads the interface. The bottom
    platen's first-touch gap is a two-sided spring (it holds the bat against rigid motion
    along the load, as the frictionless solve's assumed-closed gap; it stays compressed). The
    force read is the top platen's along the load, its friction's share included."""
    load, _ = load_axes(orientation_deg)
    n_points = model.mesh.n_points
    fixed, springs = compression_supports(model, options, orientation_deg)
    friction = insert_friction(model, mu, stick_factor=stick_factor)
    if platen_mu > 0.0:
        friction = with_platen_friction(model, options, orientation_deg, friction, platen_mu,
                                        stick_factor=stick_factor)  # fmt: skip
    insert_cosine = insert_cosines(model, load)
    travels = options.travels(curve=True)
    force, upper, lower = np.zeros(travels.size), np.zeros(travels.size), np.zeros(travels.size)
    reuse, kept, solves = FactorReuse(), FactorReuse(rtol=1e-12), 0
    where = (f"barrel compression with friction {mu:g} (platens {platen_mu:g}) "
             f"at {orientation_deg:g} deg")

    fit = replace(model.interference, bilateral=True)

    def gap_sets(travel: float) -> list[PenaltyGaps]:
        top, bottom = platen_gaps(model, options, orientation_deg, travel, prestress.u)
        held = bottom.initial <= bottom.initial.min() + 1e-12
        rest = replace(bottom, stiffness=np.where(held, 0.0, bottom.stiffness))
        holder = replace(bottom, stiffness=np.where(held, bottom.stiffness, 0.0), bilateral=True)
        return [fit, top, rest, holder, springs]

    # the fit under the compression's supports (they hold insert and barrel axially at the
    # platen's ring, where the pre-stress's held other points): the stick's zero
    start = gap_sets(0.0)
    active = [prestress.active, start[1].initial <= 0.0, start[2].initial <= 0.0,
              start[3].stiffness > 0.0, np.ones(springs.n_gaps, bool)]  # fmt: skip
    fitted = solve_static_contact(model.stiffness, start, fixed_dofs=fixed,
                                  initial_active=active, where=where, reuse=reuse)  # fmt: skip
    anchor, active = friction.slip(fitted.u), fitted.active
    # the top platen's pairs (after the insert's; none without platen friction) and their
    # slips' load components: the platen moved by -travel along the load slides by travel
    # times them
    first = model.insert_nodes.size
    on_top = slice(first, min(friction.stiffness.size, first + start[1].n_gaps))
    top_cosine = along(start[1], load, n_points)
    slip_cosines = np.column_stack([along(rows[on_top], load, n_points)
                                    for rows in friction.slips])  # fmt: skip
    for level, travel in enumerate(travels):
        sets = gap_sets(travel)
        moved = np.zeros_like(anchor)
        moved[on_top] = travel * slip_cosines
        state = solve_frictional_step(model.stiffness, sets, replace(friction, initial=moved),
                                      anchor, fixed_dofs=fixed, initial_active=active,
                                      where=where, reuse=kept)  # fmt: skip
        anchor, active = state.anchor, state.solution.active
        solves += state.solution.iterations
        force[level] = (-(state.solution.forces[1] * top_cosine).sum()
                        + (state.traction[on_top] * slip_cosines).sum())  # fmt: skip
        upper[level], lower[level] = halves(state.solution.forces[0], insert_cosine)
    return CompressionCurve(orientation_deg, travels, force, upper, lower, solves,
                            kept.factorisations + reuse.factorisations)  # fmt: skip


@dataclass(frozen=True)
class BarrelResult:
    """The pre-stress and the compression at every orientation, with Table 2's numbers.

    Attributes:
        model: the bat's model.
        prestress: the interference-fit state.
        curves: one per orientation, in the options' order.
        options: the protocol.
    """

    model: BarrelModel
    prestress: Prestress
    curves: tuple[CompressionCurve, ...]
    options: BarrelTestOptions

    def preloads(self) -> np.ndarray:
        """F(preload travel) per orientation, (n_orientations,), N."""
        return table2_loads(self.curves, self.options)[0]

    def final_loads(self) -> np.ndarray:
        """F(preload + final travel) - F(preload travel) per orientation, N (the zeroed force)."""
        return table2_loads(self.curves, self.options)[1]


def table2_loads(curves: Sequence[CompressionCurve],
                 options: BarrelTestOptions) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Table 2's pair per orientation, N: the preload F(preload travel) and the final load
    F(preload + final travel) - F(preload travel) (the zeroed force), (n_orientations,) each."""
    end = options.preload_travel + options.final_travel
    preloads = np.array([c.force_at(options.preload_travel) for c in curves])
    return preloads, np.array([c.force_at(end) for c in curves]) - preloads


def run_barrel_compression(model: BarrelModel, prestress: Prestress,
                           options: BarrelTestOptions) -> BarrelResult:  # fmt: skip
    """The compression at every orientation of ``options`` from the pre-stressed state."""
    if options.frictional:
        curves = tuple(compress_barrel_with_friction(model, prestress, options, angle,
                                                     options.friction,
                                                     platen_mu=options.platen_friction)
                       for angle in options.orientations_deg)  # fmt: skip
    else:
        curves = tuple(
            compress_barrel(model, prestress, options, angle, curve=k < options.curve_orientations)
            for k, angle in enumerate(options.orientations_deg)
        )
    return BarrelResult(model, prestress, curves, options)


def thin_ring_interference_pressure(spec: BatSpec) -> float:
    """physics.md section 6.7: p = delta / (R_o^2/(E_theta,o t_o) + R_i^2/(E_theta,i t_i)), Pa,
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


def membrane_stress(model: BarrelModel, u: np.ndarray) -> np.ndarray:
    """Through-thickness mean stress N / t at each cell's centre, (n_cells, 3): sigma_axial,
    sigma_hoop, tau, Pa, in the element frame (e1 along the bat axis, e2 around)."""
    frames, local = element_frames(model.mesh.points, model.mesh.cells)
    _, _, dndx = jacobians(local, np.zeros((1, 2)))
    b = membrane_bending_matrix(dndx, dndx[:, 0])[:, 0]  # (n_cells, 6, 24)
    nodal = u.reshape(-1, 6)[model.mesh.cells].reshape(-1, 4, 2, 3)  # (c, node, u/theta, xyz)
    local_dofs = np.einsum("cai,cnki->cnka", frames, nodal).reshape(-1, 24)
    strains = np.einsum("cij,cj->ci", b, local_dofs)
    resultants = np.einsum("cij,cj->ci", model.section.abd, strains)
    return resultants[:, :3] / cell_thickness(model.spec, model.mesh)[:, None]


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Plane-stress von Mises of (sigma_x, sigma_y, tau), (n,), Pa."""
    sx, sy, txy = stress.T
    return np.sqrt(sx**2 - sx * sy + sy**2 + 3.0 * txy**2)
