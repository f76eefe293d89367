"""The double-wall bat: interference-fit pre-stress and the barrel compression test.

Seed: "Construction of the Composite Bat Finite Element Model" (the 10-in insert pressed in with a
0.001-in interference, pre-stressed by dynamic relaxation, Figures 10 and 13), "Bat Barrel
Compression" and "Barrel Compression" (Table 2); docs/physics.md sections 5.1 and 6.7.

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
ratio 2.5 that this definition gives; docs/notes/barrel.md weighs the other readings).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from batball.contact.shell_contact import (
    PenaltyGaps,
    coaxial_ring_slips,
    nodal_areas,
    rigid_cylinder_slips,
)
from batball.elements.shell_stiffness import (
    element_frames,
    jacobians,
    membrane_bending_matrix,
)
from batball.errors import SpecError
from batball.models.barrel import (
    BarrelModel,
    BarrelTestOptions,
    Prestress,
    bore_offsets,
    cell_thickness,
    compression_supports,
    insert_half_wall,
    load_axes,
    platen_gaps,
    platen_sides,
)
from batball.solvers.static_contact import (
    CondensedContact,
    CoulombFriction,
    FactorReuse,
    solve_frictional_step,
    solve_static_contact,
)


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
#: same loads to 0.01 lbf (docs/notes/barrel.md); from 0.1 up the stick-slip iteration cycles.
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
    is taken to have slid to the frictionless state; docs/notes/barrel.md): at zero travel every
    pair sticks with no traction, and the platens' travel then loads the interface. The bottom
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
    """The compression at every orientation of ``options`` from the pre-stressed state (the
    insert's friction the bat's unless ``options`` give one)."""
    options = options.for_bat(model.spec)
    if options.frictional:
        curves = tuple(compress_barrel_with_friction(model, prestress, options, angle,
                                                     options.insert_friction,
                                                     platen_mu=options.platen_friction)
                       for angle in options.orientations_deg)  # fmt: skip
    else:
        curves = tuple(
            compress_barrel(model, prestress, options, angle, curve=k < options.curve_orientations)
            for k, angle in enumerate(options.orientations_deg)
        )
    return BarrelResult(model, prestress, curves, options)


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
