"""Write the bat's virtual tests (free-free modal, barrel compression, batted-ball speed) as
complete LS-DYNA keyword decks, built from the objects the direct runs use (the bat spec, its
mesh :func:`~batball.mesh.bat.make_bat_mesh`, its laminates, the tests' setups).

The bat (seed, "Construction of the Composite Bat Finite Element Model"): one ``*PART_COMPOSITE``
per part of the spec and one for the insert (title = the part's name), each integration point a
layer of the laminate with braids expanded into their five [+/-/+/-/+] layers (MID, THICK, B =
the layer angle in degrees); one ``*MAT_COMPOSITE_DAMAGE`` (MAT_022) per lamina material, AOPT =
0 (the a-axis along element edge 1-2, which batball's mesh lays along the bat's meridian, the
axis the seed's AOPT = 3 gave it), strengths at 1e20 (elastic, as batball's laminae: no
Chang-Chang failure). A part's lumped mass (knob, end cap) is MAREA, the non-structural mass per
area that batball spreads over the part. Nodes are numbered from 200,001 and shells from 200,001
in batball's order (outer rings first, then the insert), so a deck read back is the same mesh.
"""

from __future__ import annotations

import math

import numpy as np

from batball.contact.rigid import RigidCylinder
from batball.elements.shell_stiffness import SHEAR_FACTOR
from batball.errors import SpecError
from batball.lsdyna.cards import UnitSystem, unit_system
from batball.lsdyna.export import (
    _LONG,
    BALL_PART,
    card,
    control_cards,
    database_cards,
    head,
    keyword,
    material_cards,
    mesh_lines,
    part_cards,
    target_cards,
    target_element_lines,
    target_node_lines,
    target_shells,
)
from batball.materials.laminate import Ply
from batball.materials.orthotropic import MAT022_PARAMETERS
from batball.mesh.bat import make_bat_mesh
from batball.mesh.shell import ShellMesh, quad_areas
from batball.models.ball import ball_body, with_ball_hourglass
from batball.models.barrel import (
    BarrelTestOptions,
    build_barrel_model,
    compression_supports,
    load_axes,
)
from batball.models.bbs import BbsSetup, build_bbs_model
from batball.specs import BallSpec
from batball.specs.bat import BatSpec, PlySpec
from batball.units import IN, MPH
from batball.version import __version__

BAT_NODE_START = 200_001
BAT_ELEMENT_START = 200_001
#: Part ids of the bat: 101 + k for spec part k, then the insert; lamina materials likewise.
BAT_PART_START = 101
LAMINA_MID_START = 101
#: *SET_PART_LIST of the outer wall's parts (the barrel side of the insert's contact).
OUTER_PART_SET = 1
#: MAT_022 strengths written: out of reach, so LS-DYNA stays elastic as batball does.
NO_FAILURE = 1e20
#: Shell formulations: fully integrated (16) for the implicit tests, Belytschko-Tsay (2) explicit.
ELFORM_IMPLICIT, ELFORM_EXPLICIT = 16, 2


def bat_part_names(spec: BatSpec) -> list[str]:
    """The bat's part names in part-id order (spec parts, then ``"insert"`` for a double wall)."""
    return [p.name for p in spec.parts] + (["insert"] if spec.insert is not None else [])


def bat_part_ids(spec: BatSpec) -> dict[str, int]:
    """Part id of each part name (:func:`bat_part_names`)."""
    return {name: BAT_PART_START + k for k, name in enumerate(bat_part_names(spec))}


def lamina_ids(spec: BatSpec) -> dict[str, int]:
    """MID of each lamina material, in the spec's order."""
    return {name: LAMINA_MID_START + k for k, name in enumerate(spec.materials)}


def lamina_cards(spec: BatSpec, u: UnitSystem) -> list[str]:
    """One *MAT_COMPOSITE_DAMAGE per lamina material, its fields named by the law's declaration
    (each parameter's ``lsdyna_field``); an isotropic layer is the same card with EA = EB = EC."""
    lines: list[str] = []
    for name, mid in lamina_ids(spec).items():
        lamina = spec.materials[name]
        values = {p.lsdyna_field.lower(): getattr(lamina, p.name) / u.size(p.dimension)
                  for p in MAT022_PARAMETERS}  # fmt: skip
        values["mid"], values["prca"], values["prcb"] = mid, lamina.prba, lamina.prba
        first = {k: values[k] for k in ("mid", "ro", "ea", "eb", "ec", "prba", "prca", "prcb")}
        shear = {k: values[k] for k in ("gab", "gbc", "gca")}
        strengths = {k: NO_FAILURE for k in ("sc", "xt", "yt", "yc", "sn", "syz", "szx")}
        lines += [f"$ lamina material '{name}'"]
        lines += keyword("MAT_COMPOSITE_DAMAGE", first, {**shear, "aopt": 0.0, "macf": 1}, {},
                         {"beta": 0.0}, strengths)  # fmt: skip
    return lines


def part_extra_mass(spec: BatSpec, mesh: ShellMesh) -> dict[str, float]:
    """Non-structural mass per area of each part, kg/m^2: its lumped mass over its mesh area
    (what :func:`batball.models.bat.bat_areal_mass` spreads); 0 for the insert."""
    areas = quad_areas(mesh.points, mesh.cells)
    extra = {p.name: p.lumped_mass / float(areas[mesh.cell_sets[p.name]].sum())
             for p in spec.parts}  # fmt: skip
    if spec.insert is not None:
        extra["insert"] = 0.0
    return extra


def composite_part_cards(spec: BatSpec, mesh: ShellMesh, elform: int, u: UnitSystem) -> list[str]:
    """One *PART_COMPOSITE per part: its layers inner surface first, braids expanded."""
    mids = lamina_ids(spec)
    extra = part_extra_mass(spec, mesh)
    layups = {p.name: p.layup for p in spec.parts}
    if spec.insert is not None:
        layups["insert"] = spec.insert.layup
    lines: list[str] = []
    for name, pid in bat_part_ids(spec).items():
        plies = [layer for ply in layups[name] for layer in ply_layers(ply, spec)]
        head_card = {"pid": pid, "elform": elform, "shrf": SHEAR_FACTOR, "nloc": 0.0,
                     "marea": extra[name] / (u.density * u.length), "hgid": 0}  # fmt: skip
        lines += keyword("PART_COMPOSITE", {"title": name}, head_card)
        lines.append(head("PART_COMPOSITE", 2))
        for k in range(0, len(plies), 2):
            values: dict[str, object] = {}
            for j, (material, thickness, angle) in enumerate(plies[k : k + 2], start=1):
                values |= {f"mid{j}": mids[material], f"thick{j}": thickness / u.length,
                           f"b{j}": math.degrees(angle)}  # fmt: skip
            lines.append(card("PART_COMPOSITE", 2, values))
    return lines


def ply_layers(ply: PlySpec, spec: BatSpec) -> list[tuple[str, float, float]]:
    """(material name, thickness m, angle rad) of each single-angle layer of a spec ply."""
    lamina = Ply(spec.materials[ply.material], ply.thickness, ply.angle, braided=ply.braided)
    return [(ply.material, layer.thickness, layer.angle) for layer in lamina.layers()]


def bat_mesh_lines(spec: BatSpec, mesh: ShellMesh, u: UnitSystem) -> list[str]:
    """*NODE and *ELEMENT_SHELL of the bat, numbered from 200,001 in the mesh's order."""
    pids = np.zeros(mesh.n_cells, dtype=np.int64)
    for name, pid in bat_part_ids(spec).items():
        pids[mesh.cell_sets[name]] = pid
    lines = ["*NODE", head("NODE", 0)]
    for i, (x, y, z) in enumerate(mesh.points / u.length):
        lines.append(card("NODE", 0, {"nid": BAT_NODE_START + i, "x": x, "y": y, "z": z}))
    lines += ["*ELEMENT_SHELL", head("ELEMENT_SHELL", 0)]
    for i, cell in enumerate(mesh.cells):
        nodes = {f"n{k + 1}": int(n) + BAT_NODE_START for k, n in enumerate(cell)}
        values = {"eid": BAT_ELEMENT_START + i, "pid": int(pids[i]), **nodes}
        lines.append(card("ELEMENT_SHELL", 0, values))
    return lines


def part_set_lines(sid: int, pids: list[int]) -> list[str]:
    """A *SET_PART_LIST of ``pids`` (eight a card)."""
    lines = keyword("SET_PART_LIST", {"sid": sid})
    lines.append(head("SET_PART_LIST", 1))
    for k in range(0, len(pids), 8):
        lines.append(card("SET_PART_LIST", 1,
                          {f"pid{j + 1}": p for j, p in enumerate(pids[k : k + 8])}))  # fmt: skip
    return lines


def node_set_lines(sid: int, node_ids: np.ndarray) -> list[str]:
    """A *SET_NODE_LIST of ``node_ids`` (deck ids, eight a card)."""
    lines = keyword("SET_NODE_LIST", {"sid": sid})
    lines.append(head("SET_NODE_LIST", 1))
    for k in range(0, len(node_ids), 8):
        chunk = node_ids[k : k + 8]
        lines.append(card("SET_NODE_LIST", 1, {f"nid{j + 1}": int(n) for j, n in enumerate(chunk)}))
    return lines


def bat_lines(spec: BatSpec, mesh: ShellMesh, elform: int, u: UnitSystem) -> list[str]:
    """The whole bat: composite parts, lamina materials, the outer parts' set, nodes, shells."""
    outer = [pid for name, pid in bat_part_ids(spec).items() if name != "insert"]
    return [
        *composite_part_cards(spec, mesh, elform, u),
        *lamina_cards(spec, u),
        *part_set_lines(OUTER_PART_SET, outer),
        *bat_mesh_lines(spec, mesh, u),
    ]


def bat_header(spec: BatSpec, what: str, u: UnitSystem, mesh: ShellMesh, long: bool) -> list[str]:
    """Comment lines (what, units, parts) and *KEYWORD."""
    parts = ", ".join(f"{pid} = {name}" for name, pid in bat_part_ids(spec).items())
    return [
        f"$ batball {__version__}: {what} of bat '{spec.name}', {mesh.n_cells} shells",
        f"$ units {u.name}: {u.description}",
        f"$ bat parts (*PART_COMPOSITE): {parts}",
        "*KEYWORD LONG=Y" if long else "*KEYWORD",
    ]


def modal_deck(
    spec: BatSpec,
    *,
    circumferential: int,
    axial_size: float,
    n_modes: int = 30,
    units: str = "in-lbf-s",
    long: bool = False,
) -> str:
    """The free-free modal test as a keyword deck: an implicit eigenvalue analysis
    (*CONTROL_IMPLICIT_GENERAL IMFLAG 1, *CONTROL_IMPLICIT_EIGENVALUE NEIG = ``n_modes``, the six
    rigid-body modes included, ENDTIM 0) of the bat with no supports; the insert bonded to the
    barrel as batball's modal test bonds it, by *CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET
    (the insert's nodes tied, with their rotations and the offset between the mid-surfaces, to
    the outer wall's shells)."""
    token = _LONG.set(long)
    try:
        u = unit_system(units)
        mesh = make_bat_mesh(spec, circumferential=circumferential, axial_size=axial_size)
        lines = bat_header(spec, f"free-free modal test, {n_modes} modes", u, mesh, long)
        lines += keyword("TITLE", {"title": f"batball modal bat {spec.name} ({u.name})"})
        lines += keyword("CONTROL_IMPLICIT_GENERAL", {"imflag": 1, "dt0": 1.0})
        lines += keyword("CONTROL_IMPLICIT_EIGENVALUE", {"neig": n_modes})
        lines += keyword("CONTROL_TERMINATION", {"endtim": 0.0})
        lines += bat_lines(spec, mesh, ELFORM_IMPLICIT, u)
        if spec.insert is not None:
            lines += keyword("CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET",
                             {"surfa": bat_part_ids(spec)["insert"], "surfb": OUTER_PART_SET,
                              "surfatyp": 3, "surfbtyp": 2}, {}, {})  # fmt: skip
        lines.append("*END")
        return "\n".join(lines) + "\n"
    finally:
        _LONG.reset(token)


#: Curve ids of the interference fit: the contact stiffness ramp during dynamic relaxation
#: (SIDR 1) and its full value during the transient (SIDR 0); the top platen's travel.
RAMP_CURVE, FULL_CURVE, TRAVEL_CURVE = 1, 2, 3
#: Pseudo-time of the dynamic relaxation ramp (LS-DYNA scales the contact from 0 to 1 over it).
RAMP_TIME = 1.0


def interference_lines(spec: BatSpec, end_time: float, u: UnitSystem) -> list[str]:
    """The insert pressed into the barrel as the seed did it: the overlap of the insert's
    outer surface with the barrel's bore (the spec's interference, in the mesh) removed by
    *CONTACT_SURFACE_TO_SURFACE_INTERFERENCE in a dynamic relaxation phase whose LCID1 curve
    (SIDR 1) ramps the contact stiffness 0 -> 1, LCID2 holding it at 1 in the transient."""
    if spec.insert is None:
        return []
    return [
        *keyword("CONTROL_DYNAMIC_RELAXATION", {"nrcyck": 250, "drtol": 0.001,
                                                "drfctr": 0.995, "tssfdr": 0.0}),
        *keyword("DEFINE_CURVE", {"lcid": RAMP_CURVE, "sidr": 1}),
        card("DEFINE_CURVE", 1, {"a1": 0.0, "o1": 0.0}),
        card("DEFINE_CURVE", 1, {"a1": RAMP_TIME / u.time, "o1": 1.0}),
        *keyword("DEFINE_CURVE", {"lcid": FULL_CURVE, "sidr": 0}),
        card("DEFINE_CURVE", 1, {"a1": 0.0, "o1": 1.0}),
        card("DEFINE_CURVE", 1, {"a1": 2.0 * end_time / u.time, "o1": 1.0}),
        *keyword("CONTACT_SURFACE_TO_SURFACE_INTERFERENCE",
                 {"surfa": bat_part_ids(spec)["insert"], "surfb": OUTER_PART_SET,
                  "surfatyp": 3, "surfbtyp": 2}, {}, {},
                 {"lcid1": RAMP_CURVE, "lcid2": FULL_CURVE}),
    ]  # fmt: skip


def rigid_part_lines(names: tuple[str, ...]) -> list[str]:
    """*PART 2, 3, .. for rigid shells (section 2, material = part id)."""
    return [line for i, name in enumerate(names)
            for line in keyword("PART", {"heading": name},
                                {"pid": 2 + i, "secid": 2, "mid": 2 + i})]  # fmt: skip


def barrel_platens(
    spec: BatSpec, options: BarrelTestOptions, orientation_deg: float
) -> tuple[RigidCylinder, RigidCylinder]:
    """The top and bottom platens of the barrel test touching the bat's undeformed outer
    surface: half-cylinders of the protocol's diameter, axes along x cross e (the sideways
    direction), centred ``distance_from_cap`` from the cap, 2.5 bat diameters long."""
    load, sideways = load_axes(orientation_deg)
    radius = 0.5 * options.platen_diameter
    centre_x = spec.length - options.distance_from_cap
    outer = float(spec.outer_radius(centre_x))
    centre = np.array([centre_x, 0.0, 0.0])
    return tuple(  # type: ignore[return-value]
        RigidCylinder(axis_point=centre + side * (outer + radius) * load, axis=sideways,
                      front=-side * load, radius=radius, length=5.0 * outer)
        for side in (1.0, -1.0)
    )  # fmt: skip


def barrel_support_nodes(
    spec: BatSpec, options: BarrelTestOptions, orientation_deg: float, *, circumferential: int,
    axial_size: float,
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The seed's supports as batball's barrel test places them: the ring nodes held axially
    (:func:`~batball.models.barrel.compression_supports`) and, of those, the four on the load axis
    held sideways (mesh indices)."""
    model = build_barrel_model(spec, circumferential=circumferential, axial_size=axial_size)
    dofs, _ = compression_supports(model, options, orientation_deg)
    rings = dofs // 6
    load, _ = load_axes(orientation_deg)
    points = model.mesh.points[rings]
    on_axis = rings[np.abs(np.abs(points @ load / np.hypot(points[:, 1], points[:, 2])) - 1) < 1e-9]
    return rings, on_axis


def barrel_deck(
    spec: BatSpec,
    options: BarrelTestOptions,
    *,
    circumferential: int,
    axial_size: float,
    orientation_deg: float = 0.0,
    units: str = "in-lbf-s",
    long: bool = False,
) -> str:
    """The barrel compression test (seed "Bat Barrel Compression", Table 2) as a keyword deck,
    one orientation: the insert pressed in (:func:`interference_lines`), then an implicit static
    run (pseudo-time 0..1, ten steps) in which the top platen (part 2, *MAT_RIGID free in the
    load direction only) moves ``preload_travel + final_travel`` toward the bat by
    *BOUNDARY_PRESCRIBED_MOTION_RIGID (VAD 2, displacement), the bottom one (part 3) fixed;
    frictionless contacts of the outer wall with each; the supports as *BOUNDARY_SPC_SET (axial
    on the rings under the platens, sideways on the four load-axis nodes); RCFORC histories."""
    sideways = load_axes(orientation_deg)[1]
    axis = int(np.argmax(np.abs(sideways)))
    if abs(abs(sideways[axis]) - 1.0) > 1e-12:
        raise SpecError("orientation", orientation_deg, "0 or 90 deg (supports along y or z)")
    token = _LONG.set(long)
    try:
        u = unit_system(units)
        mesh = make_bat_mesh(spec, circumferential=circumferential, axial_size=axial_size)
        rings, on_axis = barrel_support_nodes(spec, options, orientation_deg,
                                              circumferential=circumferential,
                                              axial_size=axial_size)  # fmt: skip
        top, bottom = barrel_platens(spec, options, orientation_deg)
        travel = options.preload_travel + options.final_travel
        load_dof = 1 + int(np.argmax(np.abs(load_axes(orientation_deg)[0])))
        free = {2: 6.0, 3: 4.0}[load_dof]  # CON1: x and the other lateral axis held
        lines = bat_header(spec, f"barrel compression at {orientation_deg:g} deg", u, mesh, long)
        lines += [
            f"$ platens {options.platen_diameter / IN:.6g} in, centre "
            f"{options.distance_from_cap / IN:.6g} in from the cap; preload = F at "
            f"{options.preload_travel / IN:.6g} in, final = F(total) - preload "
            "(RCFORC of part 2); batball zeroes the travel at first touch after the fit"
        ]
        lines += keyword("TITLE", {"title": f"batball barrel bat {spec.name} ({u.name})"})
        lines += keyword("CONTROL_IMPLICIT_GENERAL", {"imflag": 1, "dt0": 0.1 / u.time})
        lines += keyword("CONTROL_TERMINATION", {"endtim": 1.0 / u.time})
        lines += database_cards(u, 0.1, 0.1, 0.1)
        lines += interference_lines(spec, 1.0, u)
        lines += bat_lines(spec, mesh, ELFORM_IMPLICIT, u)
        lines += rigid_part_lines(("top platen", "bottom platen"))
        lines += target_cards(u, con1=(free, 7.0))
        lines += platen_mesh_lines((top, bottom), spec, u)
        lines += keyword("DEFINE_CURVE", {"lcid": TRAVEL_CURVE})
        # the preload's travel is a point of its own: where the protocol zeroes the force
        preload = options.preload_travel
        lines += [
            card("DEFINE_CURVE", 1, {"a1": t / u.time, "o1": d / u.length})
            for t, d in ((0.0, 0.0), (preload / travel, preload), (1.0, travel))
        ]
        lines += keyword(
            "BOUNDARY_PRESCRIBED_MOTION_RIGID",
            {
                "pid": 2,
                "dof": load_dof,
                "vad": 2,
                "lcid": TRAVEL_CURVE,
                "sf": -float(np.sign(top.axis_point @ load_axes(orientation_deg)[0])),
            },
        )
        lines += support_lines(rings, on_axis, axis)
        for pid in (2, 3):
            lines += keyword(
                "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE",
                {"surfa": OUTER_PART_SET, "surfb": pid, "surfatyp": 2, "surfbtyp": 3},
                {"fs": 0.0, "fd": 0.0},
                {},
                {"soft": 0},
            )
        lines.append("*END")
        return "\n".join(lines) + "\n"
    finally:
        _LONG.reset(token)


def platen_mesh_lines(
    platens: tuple[RigidCylinder, ...], spec: BatSpec, u: UnitSystem
) -> list[str]:
    """*NODE and *ELEMENT_SHELL of rigid half-cylinders (parts 2, 3, ..; ids from 1,000,001 +
    100,000 i), meshed as the ball tests' targets are (:func:`~batball.lsdyna.export.
    target_shells`)."""
    shells = [target_shells(p, float(spec.outer_radius(spec.length))) for p in platens]
    return ["*NODE", head("NODE", 0), *target_node_lines(shells, u), *target_element_lines(shells)]


def support_lines(rings: np.ndarray, on_axis: np.ndarray, sideways_axis: int) -> list[str]:
    """Node sets 1 (rings, held axially: DOFX) and 2 (load-axis nodes, held sideways)."""
    dof = {0: "dofx", 1: "dofy", 2: "dofz"}[sideways_axis]
    return [
        *node_set_lines(1, rings + BAT_NODE_START),
        *keyword("BOUNDARY_SPC_SET", {"nsid": 1, "dofx": 1}),
        *node_set_lines(2, on_axis + BAT_NODE_START),
        *keyword("BOUNDARY_SPC_SET", {"nsid": 2, dof: 1}),
    ]


#: Ids of the bbs deck's pivot: the band's node set and the nodal rigid body's part id.
PIVOT_NODE_SET, PIVOT_BODY = 3, 900


def bbs_deck(
    spec: BatSpec, ball: BallSpec, setup: BbsSetup, *, units: str = "in-lbf-s", long: bool = False
) -> str:
    """The batted-ball-speed test (seed "Batted-Ball Speed", ASTM F2219 as the seed ran it) as a
    keyword deck, built from :func:`batball.models.bbs.build_bbs_model`: the ball (part 1, hexes,
    its *MAT card) placed ``gap`` over the barrel ``impact_from_cap`` from the cap and fired
    along -y; the bat's Belytschko-Tsay composite shells; the insert pressed in by dynamic
    relaxation (:func:`interference_lines`); ball and outer wall in
    *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE (SOFT, SFSA, SLSFAC of the setup); the pivot as
    batball's rigid band (the bat nodes within ``pivot_band`` of the pivot) made a
    *CONSTRAINED_NODAL_RIGID_BODY_SPC free to turn about z only (CMO 1, CON1 7, CON2 4)."""
    token = _LONG.set(long)
    try:
        return "\n".join(_bbs_lines(spec, ball, setup, unit_system(units))) + "\n"
    finally:
        _LONG.reset(token)


def _bbs_lines(spec: BatSpec, ball: BallSpec, setup: BbsSetup, u: UnitSystem) -> list[str]:
    """The bbs deck's lines."""
    setup = with_ball_hourglass(setup, ball)
    model = build_bbs_model(spec, ball, setup)
    mesh, coupled = model.bat_mesh, model.coupled
    ball_points = coupled.points[mesh.n_points :]
    band = coupled.bat.band
    band_mass = coupled.bat.mass[band, 0]  # translational lumped mass
    offset = float(band_mass @ mesh.points[band, 0] / band_mass.sum()) - setup.pivot_from_knob
    lines = bat_header(spec, f"batted-ball speed with ball '{ball.name}' at "
                       f"{setup.speed / MPH:.6g} mph", u, mesh, _LONG.get())  # fmt: skip
    lines += [
        f"$ part 1 = ball (moving along -y); BBS from MATSUM part 1 y-velocity; pivot band "
        f"= node set {PIVOT_NODE_SET}; its centre of mass (LS-DYNA's rotation centre) is "
        f"{offset / IN:.4g} in from batball's pivot axis"
    ]
    lines += keyword("TITLE", {"title": f"batball bbs bat {spec.name} ball {ball.name} ({u.name})"})
    lines += control_cards(setup, setup.end_time, u, model.mass_scaling_step)
    lines += database_cards(u, 1e-6, 1e-5, 1e-4)
    if setup.prestress:
        lines += interference_lines(spec, setup.end_time, u)
    elif spec.insert is not None:
        raise SpecError("prestress", False, "true (the deck presses the insert in)")
    body = ball_body(ball, setup.ball_divisions, setup.contact, setup.time_step_scale)
    lines += part_cards(setup, ()) + material_cards(ball, body.density, u)
    lines += mesh_lines(ball_points, model.ball_cells, [], u)
    lines += bat_lines(spec, mesh, ELFORM_EXPLICIT, u)
    lines += keyword("INITIAL_VELOCITY_GENERATION",
                     {"id": BALL_PART, "styp": 2, "omega": 0.0, "vx": 0.0,
                      "vy": -setup.speed / u.velocity, "vz": 0.0}, {"xc": 0.0})  # fmt: skip
    c = setup.contact
    lines += keyword("CONTACT_AUTOMATIC_SURFACE_TO_SURFACE",
                     {"surfa": BALL_PART, "surfb": OUTER_PART_SET, "surfatyp": 3, "surfbtyp": 2},
                     {"fs": 0.0, "fd": 0.0}, {"sfsa": c.sfs, "sfsb": 1.0},
                     {"soft": c.soft, "sofscl": c.sofscl})  # fmt: skip
    lines += node_set_lines(PIVOT_NODE_SET, band + BAT_NODE_START)
    lines += keyword("CONSTRAINED_NODAL_RIGID_BODY_SPC",
                     {"pid": PIVOT_BODY, "nsid": PIVOT_NODE_SET},
                     {"cmo": 1.0, "con1": 7.0, "con2": 4.0})  # fmt: skip
    lines.append("*END")
    return lines
