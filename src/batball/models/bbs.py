"""The batted-ball-speed fixture (ASTM F2219 as the seed ran it): the bat on its pivot, the ball
about to hit it, and the contacts between them (the test itself, its run and its measurements, is
:mod:`batball.lab.bbs`).

The bat, at rest, may turn about a pivot axis 6 in from the knob (z; the bat's axis is x); the ball
is fired along -y at the barrel 6 in from the end cap. Contact stiffness, LS-DYNA SOFT = 0 style:
every ball surface node keeps the stiffness the ball tests give it (SLSFAC K A^2 / V of its faces,
the ball being the softer side); a bat node against the ball gets the ball faces' stiffness per
area, SLSFAC K A / V, times its own tributary area. The insert touches the barrel's bore through a
node-to-column contact (:mod:`batball.contact.columns`; shell thicknesses as offsets, stiffness
SLSFAC E A / diagonal of the barrel's segments). Selective mass scaling of the bat's shells is
LS-DYNA's DT2MS < 0.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from batball.contact.columns import ColumnContact
from batball.contact.segments import SegmentContact
from batball.contact.shell_contact import nodal_areas
from batball.elements.hex8 import kernel_ids
from batball.elements.hex8_block import check_precision
from batball.elements.hex8_foam import foam_reference_gradients
from batball.elements.shell_bt import HOURGLASS_RATIO, ShellForceState, initial_force_state
from batball.elements.shell_bt_section import HG_THICKNESS, LayeredSection, layered_section
from batball.elements.shell_corotational import SHELLS, CorotationalState, initial_rotations
from batball.elements.shell_explicit import (
    cell_stable_steps,
    lumped_shell_mass,
    selective_mass_scaling,
)
from batball.elements.shell_stiffness import ShellSection, shell_section
from batball.errors import SpecError
from batball.mesh import boundary_faces, hex_volumes
from batball.mesh.bat import make_bat_mesh, outer_rings
from batball.mesh.shell import ShellMesh, quad_areas
from batball.models.ball import (
    BallBody,
    ContactOptions,
    ball_body,
    ball_hourglass,
    estimate_first_step,
    with_ball_hourglass,
)
from batball.models.bat import bat_areal_mass, bat_laminates
from batball.solvers.ball_bat import (
    BallPart,
    BatPart,
    CoupledModel,
    moment_of_inertia_z,
)
from batball.solvers.explicit import BulkViscosity, HourglassControl
from batball.specs import BallSpec, BatSpec
from batball.units import IN, MPH


@dataclass(frozen=True)
class BbsSetup:
    """One batted-ball-speed run (SI).

    Attributes:
        speed: inbound ball speed [m/s] (95 or 110 mph in the seed).
        pitch_speed, swing_speed: the BBS constants v_p, v_b [m/s] (ASA 25 and 85 mph).
        impact_from_cap: impact point from the end cap [m] (6 in).
        pivot_from_knob: pivot axis from the knob end [m] (6 in).
        pivot_band: half width of the rigid band of handle rings at the pivot [m].
        ball_divisions: ball mesh (12 = the seed's 12,096 hexes).
        circumferential, axial_size: bat mesh (48 x 0.1 in = the seed's about 20,000 shells).
        gap: initial clearance between ball and bat [m].
        end_time: longest run [s]; separation_time: run on this long after the ball leaves [s].
        rigid_bat: the whole bat a rigid body on the pivot (verification).
        fixed_bat: the bat held still (k = 0: the ball's COR on this target).
        insert_contact: the insert touches the barrel (else it floats free, for tests).
        search_interval: cycles between contact searches.
        prestress: press the insert in by dynamic relaxation before the impact (else its
            initial overlap is ignored and it just touches the barrel).
        relax_time: (ramp, settle) duration of that relaxation [s]; the cycles are these over
            the stable step, so a finer mesh gets the same physical time (docs/notes/bbs.md);
            relax_steps: the fewest (ramp, settle) cycles, whatever the step.
        contact_reach: the ball-bat contact includes only the bat's outer shells and nodes
            within this distance of the impact station along the bat [m] (None: the whole
            bat); the 3-in default is the ball's radius plus about an inch, so no part of the
            ball can reach beyond it during the impact (docs/notes/bbs.md).
        mass_scaling: selective mass scaling of the bat's shells (LS-DYNA DT2MS < 0,
            docs/notes/bbs.md):
            "barrel" (default) adds mass only to the shells whose step is below the smaller of
            the barrel's (its parts and the insert) and the ball's, so that those set the step;
            a float is the target step itself [s] (TSSFAC |DT2MS|); None: no mass added.
        precision: the ball's hex kernel, "single" (default, as the impact lab and LS-DYNA's
            default executable) or "double" (docs/notes/precision.md).
        insert_friction: Coulomb coefficient between insert and barrel during the impact (the
            fit is pressed frictionless); None, the default: the bat's own
            (``InsertSpec.friction``, 0 on the embedded bats as in the seed), settled by
            :func:`with_bat_friction`.
        shell_hourglass_ratio: r of the bat shells' hourglass constants (LS-DYNA's default
            0.01; the barrel test's squeeze needs 1, docs/notes/barrel.md).
        bat_damping: damping of the bat's deformation relative to its own rigid turn about
            the pivot, c [1/s] (the form of LS-DYNA's ``*DAMPING_RELATIVE``,
            :func:`batball.solvers.ball_bat.advance_bat`; fraction of critical c / (4 pi f) at
            frequency f); 0, the default, as the seed (docs/notes/bbs.md, "(b) tested").
        bat_shell: the bat's shell element, "bt" (the one-point Belytschko-Tsay shells, as
            the seed's LS-DYNA model; this class's default, which a deck read from LS-DYNA and
            the verification cases rely on) or "mitc4" (the statics' MITC4 made
            co-rotational, :mod:`batball.elements.shell_corotational`; no hourglass modes; the
            default of the test protocol, ``batball bbs`` and the registry, since its limit
            does not hang on an hourglass ratio: docs/decisions.md).
    """

    speed: float = 110.0 * MPH
    pitch_speed: float = 25.0 * MPH
    swing_speed: float = 85.0 * MPH
    impact_from_cap: float = 6.0 * IN
    pivot_from_knob: float = 6.0 * IN
    pivot_band: float = 0.5 * IN
    ball_divisions: int = 12
    circumferential: int = 48
    axial_size: float = 0.1 * IN
    gap: float = 0.01 * IN
    end_time: float = 2e-3
    separation_time: float = 0.2e-3
    time_step_scale: float = 0.9
    hourglass: HourglassControl | None = None  # None: the ball's own (models.ball)
    bulk_viscosity: BulkViscosity = field(default_factory=BulkViscosity)
    contact: ContactOptions = field(default_factory=ContactOptions)
    rigid_bat: bool = False
    fixed_bat: bool = False
    insert_contact: bool = True
    search_interval: int = 10
    prestress: bool = True
    relax_time: tuple[float, float] = (0.16e-3, 0.64e-3)
    relax_steps: tuple[int, int] = (400, 1600)
    mass_scaling: float | str | None = "barrel"
    contact_reach: float | None = 3.0 * IN
    precision: str = "single"
    insert_friction: float | None = None
    shell_hourglass_ratio: float = HOURGLASS_RATIO
    bat_damping: float = 0.0
    bat_shell: str = "bt"

    def __post_init__(self) -> None:
        if not (np.isfinite(self.speed) and 0 < self.speed <= 100.0):
            raise SpecError("speed", f"{self.speed / MPH:.4g} mph", "0 mph < speed <= 223 mph")
        for name in ("pitch_speed", "swing_speed"):
            value = getattr(self, name)
            if not (np.isfinite(value) and 0 <= value <= 100.0):
                raise SpecError(name, f"{value / MPH:.4g} mph", "0 mph <= speed <= 223 mph")
        if not 2 <= self.ball_divisions <= 40:
            raise SpecError("ball_divisions", self.ball_divisions, "an integer 2..40 (12 = seed)")
        if not 8 <= self.circumferential <= 256:
            raise SpecError("circumferential", self.circumferential, "an integer 8..256")
        check_precision(self.precision)
        mu = self.insert_friction
        if mu is not None and not (np.isfinite(mu) and 0.0 <= mu <= 10.0):
            raise SpecError("insert_friction", mu, "a coefficient 0 .. 10")
        check_hourglass_ratio("shell_hourglass_ratio", self.shell_hourglass_ratio)
        if self.bat_shell not in SHELLS:
            raise SpecError("bat_shell", self.bat_shell, " or ".join(SHELLS))
        if not (np.isfinite(self.bat_damping) and 0.0 <= self.bat_damping <= 1e5):
            raise SpecError("bat_damping", f"{self.bat_damping:.4g} 1/s", "0 1/s .. 1e5 1/s")
        if not 0.01 * IN <= self.axial_size <= 2.0 * IN:
            raise SpecError("axial_size", f"{self.axial_size / IN:.4g} in", "0.01 in .. 2 in")
        if not 0.0 < self.pivot_band <= 3.0 * IN:
            raise SpecError("pivot_band", f"{self.pivot_band / IN:.4g} in", "0 in < band <= 3 in")
        if not 0.0 < self.end_time <= 0.02:
            raise SpecError("end_time", self.end_time, "0 s < end_time <= 0.02 s")
        if not all(0 <= n <= 100_000 for n in self.relax_steps) or self.relax_steps[0] < 1:
            raise SpecError("relax_steps", self.relax_steps, "(ramp >= 1, settle >= 0) cycles")
        if not all(0.0 <= t <= 0.01 for t in self.relax_time):
            raise SpecError("relax_time", self.relax_time, "(ramp, settle) each 0 s .. 0.01 s")
        if not 1 <= self.search_interval <= 100:
            raise SpecError("search_interval", self.search_interval, "an integer 1..100")
        if self.contact_reach is not None and not 0.5 * IN <= self.contact_reach <= 100 * IN:
            raise SpecError("contact_reach", self.contact_reach, "0.5 in .. 100 in, or None")
        scaling = self.mass_scaling
        if scaling not in (None, "barrel") and (
            isinstance(scaling, str) or not 0.0 < float(scaling) <= 1e-5
        ):
            allowed = '"barrel", a target step 0 s < dt <= 1e-5 s, or None (off)'
            raise SpecError("mass_scaling", scaling, allowed)


@dataclass(frozen=True)
class BbsModel:
    """The coupled model with what the measurements need.

    Attributes:
        coupled: the solver's model; bat_mesh: the bat's shells; ball_cells: (n, 8) ball hexes
            (local ids); impact_x, pivot_x: stations along the bat [m]; z: their distance [m].
        interference: the insert's radial interference [m]; added_mass: (n_cells,) mass that
            selective mass scaling added to each shell [kg]; pivot_inertia: the bat's MOI about
            the pivot without that mass [kg m^2] (the k of the BBCOR is the real bat's);
            mass_scaling_step: the step below which that mass was added [s, TSSFAC applied],
            None when none was (:func:`mass_scaling_target`); insert_friction: the Coulomb
            coefficient of the insert's contact during the impact (the setup's, else the bat's).
    """

    coupled: CoupledModel
    bat_mesh: ShellMesh
    ball_cells: np.ndarray
    impact_x: float
    pivot_x: float
    interference: float = 0.0
    added_mass: np.ndarray = field(default_factory=lambda: np.zeros(0))
    pivot_inertia: float = 0.0
    mass_scaling_step: float | None = None
    insert_friction: float = 0.0

    @property
    def z(self) -> float:
        """Pivot-to-impact distance [m]."""
        return self.impact_x - self.pivot_x


def with_bat_friction(setup: BbsSetup, bat: BatSpec) -> BbsSetup:
    """``setup`` with the insert's friction settled: the bat's own where the setup gives none,
    so that a run's key, summary and model name the coefficient it ran with."""
    if setup.insert_friction is not None:
        return setup
    return replace(setup, insert_friction=bat.insert.friction if bat.insert else 0.0)


def check_hourglass_ratio(field: str, ratio: float) -> None:
    """The shells' hourglass ratio r must lie in (0, 1]: 1 is the largest tried; 10 made the
    barrel test's squeeze unstable at the shells' step (docs/notes/barrel.md)."""
    if not (np.isfinite(ratio) and 0.0 < ratio <= 1.0):
        raise SpecError(field, ratio, "a ratio 0 < r <= 1")


def bat_part(spec: BatSpec, setup: BbsSetup, ball_step: float = np.inf
             ) -> tuple[BatPart, ShellMesh, np.ndarray]:  # fmt: skip
    """The bat's shells, layered section, lumped mass, stable step and pivot band, and the mass
    that selective mass scaling added to each cell, (n_cells,) [kg] (``ball_step``: the ball's
    stable step [s], TSSFAC applied, which caps the scaling's target)."""
    mesh = make_bat_mesh(spec, circumferential=setup.circumferential,
                         axial_size=setup.axial_size)  # fmt: skip
    section = layered_section(*bat_laminates(spec, mesh))
    areal = bat_areal_mass(spec, mesh)
    added = scaled_areal_mass(mesh, section, setup, ball_step)
    mass = lumped_shell_mass(mesh.points, mesh.cells, section, areal_mass=areal + added)
    steps = setup.time_step_scale * cell_stable_steps(mesh.points, mesh.cells, section)
    m0 = section.areal_mass[section.cell_laminate]
    step = float(np.min(steps * np.sqrt((m0 + added) / m0)))  # dt ~ sqrt(density)
    pivot = np.array([setup.pivot_from_knob, 0.0, 0.0])
    whole = setup.rigid_bat or setup.fixed_bat
    band = np.flatnonzero(whole | (np.abs(mesh.points[:, 0] - pivot[0]) <= setup.pivot_band))
    if band.size == 0:
        raise SpecError("pivot_band", f"{setup.pivot_band / IN:.3g} in",
                        "a band wide enough to hold a ring of bat nodes")  # fmt: skip
    part = BatPart(mesh.cells.astype(np.int64), section, mass, step, band, pivot, rigid=whole,
                   fixed=setup.fixed_bat)  # fmt: skip
    return part, mesh, added * quad_areas(mesh.points, mesh.cells)


def bat_shell_state(
    spec: BatSpec, bat: BatPart, mesh: ShellMesh, setup: BbsSetup
) -> tuple[ShellForceState | CorotationalState, ShellSection | None]:
    """The shells' initial state and, for the co-rotational MITC4 shells, their section (the
    solver builds those shells and checks the step against them); (BT stresses, None) else."""
    if setup.bat_shell == "bt" or bat.rigid:
        return initial_force_state(bat.section), None
    return initial_rotations(mesh.n_points), shell_section(*bat_laminates(spec, mesh))


def mass_scaling_target(mesh: ShellMesh, section: LayeredSection, setup: BbsSetup,
                        ball_step: float) -> float | None:  # fmt: skip
    """The step [s, TSSFAC applied] below which ``setup.mass_scaling`` adds mass to a shell
    (LS-DYNA's TSSFAC |DT2MS|), or None when it adds none: "barrel" targets the smallest step
    among the barrel's parts and the insert (where the ball hits, left untouched) or the ball's
    step if smaller; a float is the target itself."""
    if setup.mass_scaling is None or setup.rigid_bat or setup.fixed_bat:
        return None
    if setup.mass_scaling != "barrel":
        return float(setup.mass_scaling)
    steps = setup.time_step_scale * cell_stable_steps(mesh.points, mesh.cells, section)
    names = [n for n in mesh.cell_sets if n.startswith("barrel") or n == "insert"]
    if not names:
        raise SpecError("mass_scaling", "barrel", "a bat with parts named barrel*")
    barrel = np.concatenate([mesh.cell_sets[n] for n in names])
    return min(float(steps[barrel].min()), ball_step)


def scaled_areal_mass(mesh: ShellMesh, section: LayeredSection, setup: BbsSetup,
                      ball_step: float) -> np.ndarray:  # fmt: skip
    """Areal mass that ``setup.mass_scaling`` adds to each cell, (n_cells,) [kg/m^2]
    (:func:`mass_scaling_target`)."""
    target = mass_scaling_target(mesh, section, setup, ball_step)
    if target is None:
        return np.zeros(mesh.n_cells)
    return selective_mass_scaling(mesh.points, mesh.cells, section, target,
                                  time_step_factor=setup.time_step_scale)  # fmt: skip


def place_ball(
    body: BallBody, ball: BallSpec, spec: BatSpec, setup: BbsSetup, n_bat: int
) -> tuple[BallPart, np.ndarray, float]:
    """The ball's nodes placed over the impact point, moving along -y."""
    impact_x = spec.length - setup.impact_from_cap
    centre = np.array([impact_x, float(spec.outer_radius(impact_x)) + ball.radius + setup.gap,
                       0.0])  # fmt: skip
    points = body.mesh.points + centre
    volume0 = hex_volumes(body.mesh.points, body.mesh.cells)
    mass = np.zeros(body.mesh.n_points)
    np.add.at(mass, body.mesh.cells.ravel(), np.repeat(body.density * volume0 / 8.0, 8))
    bv = setup.bulk_viscosity
    cells = kernel_ids(body.mesh.cells)
    part = BallPart(
        cells,
        n_bat,
        body.constants[None, :],
        body.density,
        volume0,
        mass,
        ball_hourglass(setup.hourglass, ball).type,
        ball_hourglass(setup.hourglass, ball).coefficient,
        *((bv.q1, bv.q2) if bv.enabled else (0.0, 0.0)),
        foam=body.foam,
        reference=None if body.foam is None else foam_reference_gradients(cells, points),
    )
    return part, points, impact_x


def ball_bat_contacts(
    body: BallBody,
    ball_part: BallPart,
    bat: BatPart,
    mesh: ShellMesh,
    setup: BbsSetup,
    impact_x: float,
) -> tuple[SegmentContact, ...]:
    """Ball surface nodes on the bat's outer shells, and the bat's outer nodes on the ball's
    surface quads (module docs for the stiffness), the bat's side within
    ``setup.contact_reach`` of the impact station ``impact_x`` [m]."""
    offset = ball_part.first_node
    outer_cells = np.setdiff1d(np.arange(mesh.n_cells), mesh.cell_sets.get("insert", []))
    outer = mesh.point_sets["outer"]
    if setup.contact_reach is not None:
        near = np.abs(mesh.points[:, 0] - impact_x) <= setup.contact_reach
        outer_cells = outer_cells[near[bat.cells[outer_cells]].any(axis=1)]
        outer = outer[near[outer]]
    half = 0.5 * bat.section.hourglass_moduli[bat.section.cell_laminate, HG_THICKNESS]
    margin = 0.05 * IN
    ball_on_bat = SegmentContact(
        "ball on bat",
        body.nodes + offset,
        np.zeros(body.nodes.size),
        body.stiffness,
        bat.cells[outer_cells],
        half[outer_cells],
        two_sided=True,
        depth=0.0,
        margin=margin,
    )
    faces, owner = boundary_faces(body.mesh.cells)
    face_area = quad_areas(body.mesh.points, faces)
    c = setup.contact
    per_area = (
        c.slsfac
        * c.sfs
        * float(ball_part.material_constants[0, 0])
        * np.mean(face_area / ball_part.volume0[owner])
    )
    node_half = np.zeros(mesh.n_points)
    np.maximum.at(node_half, bat.cells[outer_cells].ravel(), np.repeat(half[outer_cells], 4))
    areas = nodal_areas(mesh.points, bat.cells[outer_cells])
    depth = 2.0 * float(np.mean(ball_part.volume0[owner] / face_area))
    bat_on_ball = SegmentContact(
        "bat on ball",
        outer,
        node_half[outer],
        per_area * areas[outer],
        faces + offset,
        np.zeros(len(faces)),
        two_sided=False,
        depth=depth,
        margin=margin,
    )
    return ball_on_bat, bat_on_ball


def insert_barrel_contact(spec: BatSpec, bat: BatPart, mesh: ShellMesh,
                          setup: BbsSetup) -> ColumnContact:  # fmt: skip
    """The insert's nodes on the barrel's columns of nodes at their angles, the initial overlap
    (the interference the pre-stress would remove) ignored; stiffness SLSFAC E A / diagonal of
    the barrel's segments beside the insert (module docs).

    The pair is a central force between each insert node and the closest point of its column
    (:mod:`batball.contact.columns`), as the statics of the barrel test pair them: against the
    barrel's facets the insert's nodes sat on the facets' corners, the push turned or jumped as
    round-off moved a node across one, and the full-size bat's pre-stress grew a local mode
    instead of settling (docs/notes/bbs.md, "Pre-stress length")."""
    assert spec.insert is not None
    sec = bat.section
    insert = mesh.point_sets["insert"]
    insert_cells = mesh.cell_sets["insert"]
    outer_cells = np.setdiff1d(np.arange(mesh.n_cells), insert_cells)
    centre_x = mesh.points[bat.cells[outer_cells], 0].mean(axis=1)
    beside = outer_cells[(centre_x > spec.insert.start - 0.5 * IN)
                         & (centre_x < spec.insert.end + 0.5 * IN)]  # fmt: skip
    thickness = sec.hourglass_moduli[sec.cell_laminate, HG_THICKNESS]
    modulus = sec.hourglass_moduli[sec.cell_laminate[beside], 0] / thickness[beside]
    corners = mesh.points[bat.cells[beside]]
    diagonal = np.maximum(np.linalg.norm(corners[:, 2] - corners[:, 0], axis=1),
                          np.linalg.norm(corners[:, 3] - corners[:, 1], axis=1))  # fmt: skip
    per_area = setup.contact.slsfac * float(np.mean(modulus / diagonal))
    areas = nodal_areas(mesh.points, bat.cells[insert_cells])[insert]
    cells = bat.cells[outer_cells].ravel()
    count = np.bincount(cells, minlength=mesh.n_points)
    half = np.bincount(cells, weights=np.repeat(0.5 * thickness[outer_cells], 4),
                       minlength=mesh.n_points) / np.maximum(count, 1)  # fmt: skip
    pair = ColumnContact(
        "insert on barrel",
        insert,
        0.5 * thickness[insert_cells[0]] * np.ones(insert.size),
        per_area * areas,
        outer_rings(mesh),
        half,
        mesh.points,
    )
    pair.gap_offset = pair.initial_overlap(mesh.points)
    return pair


def build_bbs_model(spec: BatSpec, ball: BallSpec, setup: BbsSetup) -> BbsModel:
    """The bat on its pivot and the ball about to hit it (module docs)."""
    setup = with_ball_hourglass(setup, ball)
    body = ball_body(ball, setup.ball_divisions, setup.contact, setup.time_step_scale)
    ball_step = setup.time_step_scale * estimate_first_step(body.mesh, body.constants,
                                                            body.density)  # fmt: skip
    bat, mesh, added_mass = bat_part(spec, setup, ball_step)
    ball_part, ball_points, impact_x = place_ball(body, ball, spec, setup, mesh.n_points)
    points = np.vstack([mesh.points, ball_points])
    velocity = np.zeros_like(points)
    velocity[mesh.n_points :, 1] = -setup.speed
    contacts: tuple[SegmentContact | ColumnContact, ...]
    contacts = ball_bat_contacts(body, ball_part, bat, mesh, setup, impact_x)
    if spec.insert is not None and setup.insert_contact and not bat.rigid:
        contacts = (*contacts, insert_barrel_contact(spec, bat, mesh, setup))
    coupled = CoupledModel(points, velocity, ball_part, bat, contacts, 2,
                           *bat_shell_state(spec, bat, mesh, setup))  # fmt: skip
    interference = spec.insert.interference if spec.insert is not None else 0.0
    unscaled = lumped_shell_mass(mesh.points, mesh.cells, bat.section,
                                 areal_mass=bat_areal_mass(spec, mesh))  # fmt: skip
    moi = moment_of_inertia_z(mesh.points, unscaled, bat.pivot)
    target = mass_scaling_target(mesh, bat.section, setup, ball_step)
    friction = with_bat_friction(setup, spec).insert_friction
    return BbsModel(coupled, mesh, body.mesh.cells, impact_x, setup.pivot_from_knob, interference,
                    added_mass, moi, target, friction or 0.0)  # fmt: skip


def relaxation_cycles(setup: BbsSetup, step: float) -> tuple[int, int]:
    """(ramp, settle) cycles of the pre-stress: ``setup.relax_time`` over the bat's ``step``
    [s], at least ``setup.relax_steps``. The fit settles in physical time (the full-size mesh
    reached 76 psi of 92 in 1,200 cycles at 1.2e-7 s, 92.5 psi in 2,400 at 2.1e-7 s; with the
    column contact the table's mesh needs 0.64 ms of settling to come within 1 % of the
    penalty-compliant thin ring: docs/notes/bbs.md), so a finer mesh needs proportionally more
    cycles."""
    return (max(setup.relax_steps[0], int(np.ceil(setup.relax_time[0] / step))),
            max(setup.relax_steps[1], int(np.ceil(setup.relax_time[1] / step))))  # fmt: skip


def insert_pressure(model: BbsModel, points: np.ndarray) -> float:
    """Mean contact pressure between insert and barrel [Pa]: the insert contact's total normal
    force over the insert's outer area (as lab/barrel's mean interference pressure)."""
    pair = model.coupled.contacts[model.coupled.ball_contacts]
    mesh = model.bat_mesh
    return fit_pressure(pair, points, mesh.points, mesh.cells[mesh.cell_sets["insert"]])


def fit_pressure(pair: SegmentContact | ColumnContact, points: np.ndarray, reference: np.ndarray,
                 insert_cells: np.ndarray) -> float:  # fmt: skip
    """The insert pair's total normal force at ``points`` over the insert's outer area (from
    the undeformed ``reference`` nodes and the insert's (n, 4) cells) [Pa]."""
    pair.search(points)
    pair.add_forces(points, np.zeros_like(points))
    radius = np.hypot(reference[pair.slave_nodes, 1], reference[pair.slave_nodes, 2])
    areas = nodal_areas(reference, insert_cells)[pair.slave_nodes]
    outer_area = np.sum(areas * (radius + pair.slave_thickness) / radius)
    return float(np.linalg.norm(pair.slave_force, axis=1).sum() / outer_area)
