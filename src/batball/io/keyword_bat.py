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

from batball import __version__
from batball.elements.shell_stiffness import SHEAR_FACTOR
from batball.io.keyword_cards import UnitSystem, unit_system
from batball.io.keyword_export import _LONG, card, head, keyword
from batball.materials.laminate import Ply
from batball.materials.orthotropic import MAT022_PARAMETERS
from batball.mesh.bat import make_bat_mesh
from batball.mesh.shell import ShellMesh, quad_areas
from batball.specs.bat import BatSpec, PlySpec

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
    (what :func:`batball.lab.props.bat_areal_mass` spreads); 0 for the insert."""
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
        plies = [ply for ply in layups[name] for ply in ply_layers(ply, spec)]
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
        lines.append(card("ELEMENT_SHELL", 0,
                          {"eid": BAT_ELEMENT_START + i, "pid": int(pids[i]), **nodes}))  # fmt: skip
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
