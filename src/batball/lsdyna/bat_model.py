"""Read a bat test's LS-DYNA keyword deck (the modal, barrel or bbs deck of
:mod:`batball.lsdyna.bat`, or one written like it) back into batball's bat model.

The bat: every ``*PART_COMPOSITE`` is a part (its title names the cell set), its layers a
:class:`~batball.materials.laminate.Laminate` of ``*MAT_COMPOSITE_DAMAGE`` laminae (MAT_022's
elastic constants; a strength must be blank or >= 1e19, i.e. no failure, since batball's laminae
are elastic), MAREA the non-structural mass per area, SHRF the transverse shear factor (blank =
LS-DYNA's 1.0; one value for all parts). The insert is the SURFA part of the tied or interference
contact. batball's modal labels and insert tie need its ring-numbered mesh (outer rings of equal
node count first, then the insert's), which the exported decks keep; another numbering is a
:class:`~batball.errors.SpecError`.

What batball runs from a deck: the modal test (:func:`run_modal_deck`, the same
:func:`~batball.lab.modal.shell_modes` as ``batball modal``). The barrel and bbs decks are read
(bat, platens, supports, ball, velocities, contacts, pivot) into :class:`BatDeck` here and run by
:mod:`batball.lsdyna.bat_barrel` and :mod:`batball.lsdyna.bat_bbs`, which turn the deck
back into the specs those tests build their contacts from.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from batball.contact.rigid import RigidCylinder, RigidPlane
from batball.elements.shell_stiffness import ShellSection, shell_section
from batball.errors import SpecError
from batball.lsdyna.cards import UnitSystem, unit_system
from batball.lsdyna.model import (
    Deck,
    _initial_velocity,
    _materials,
    _solid_mesh,
    fit_target,
    parse_deck,
)
from batball.materials import LAMINA_LAWS
from batball.materials.laminate import Laminate, Ply
from batball.materials.orthotropic import OrthotropicLamina
from batball.mesh import Mesh
from batball.mesh.shell import ShellMesh

#: A MAT_022 strength at or above this (deck units) means "never fails".
NO_FAILURE_FROM = 1e19
STRENGTHS = ("sc", "xt", "yt", "yc", "sn", "syz", "szx")
INSERT_CONTACTS = ("CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET",
                   "CONTACT_SURFACE_TO_SURFACE_INTERFERENCE")  # fmt: skip


@dataclass(frozen=True)
class BatDeck:
    """A bat deck read back (SI).

    Attributes:
        test: "modal" (*CONTROL_IMPLICIT_EIGENVALUE), "bbs" (hexes: a ball) or "barrel".
        mesh: the bat's shells; ``cell_sets`` by part title (the insert's as ``"insert"``),
            ``point_sets`` ``"outer"`` and ``"insert"``.
        laminates: each part's laminate, by cell-set name.
        extra_areal_mass: non-structural mass per area of each cell, (n_cells,), kg/m^2.
        shear_factor: SHRF of the parts.
        elform: the parts' shell formulation.
        circumferential: nodes around each ring.
        node_ids: deck id of each mesh point, (n_points,).
        n_modes: NEIG of a modal deck (0 otherwise).
        deck: the parsed deck (deck units), for the rest of a barrel or bbs deck.
        units: the unit system it was read in; title: its *TITLE.
    """

    test: str
    mesh: ShellMesh
    laminates: dict[str, Laminate]
    extra_areal_mass: np.ndarray
    shear_factor: float
    elform: int
    circumferential: int
    node_ids: np.ndarray
    n_modes: int
    deck: Deck
    units: str
    title: str

    def section(self) -> ShellSection:
        """Per-cell section constants, as :func:`batball.models.bat.bat_section` makes them."""
        names = list(self.laminates)
        cell_laminate = np.full(self.mesh.n_cells, -1, dtype=np.int64)
        for k, name in enumerate(names):
            cell_laminate[self.mesh.cell_sets[name]] = k
        return shell_section([self.laminates[n] for n in names], cell_laminate,
                             extra_areal_mass=self.extra_areal_mass,
                             shear_factor=self.shear_factor)  # fmt: skip


def is_bat_deck(deck: Deck) -> bool:
    """Whether a parsed deck is a bat deck (it has *PART_COMPOSITE parts)."""
    return bool(deck.composites)


def read_bat_deck(
    path: str | Path, *, units: str = "in-lbf-s", include_root: str | Path | None = None
) -> BatDeck:
    """Read the bat deck at ``path`` (numbers in ``units``; includes inside ``include_root`` if
    named, else the deck's folder) into a :class:`BatDeck`."""
    u = unit_system(units)
    deck = parse_deck(path, include_root=include_root)
    if not deck.composites:
        raise SpecError(f"deck {path}", "no *PART_COMPOSITE", "a bat deck (composite shells)")
    laminae = read_laminae(deck, u)
    insert_pid = insert_part(deck)
    mesh, node_ids = bat_mesh(deck, insert_pid, u)
    laminates, extra, shear, elform = read_parts(deck, mesh, laminae, insert_pid, u)
    circumferential = ring_count(mesh)
    eigen = deck.controls.get("CONTROL_IMPLICIT_EIGENVALUE")
    test = "modal" if eigen else ("bbs" if deck.solids else "barrel")
    n_modes = int(eigen.get("neig") or 0) if eigen else 0
    if eigen and not 6 < n_modes <= 500:
        raise SpecError(f"*CONTROL_IMPLICIT_EIGENVALUE.NEIG at {eigen['where']}", n_modes,
                        "7 to 500 modes (the six rigid-body modes count)")  # fmt: skip
    if test == "modal":
        check_modal_deck(deck, insert_pid, path)
        check_one_piece(mesh)
    return BatDeck(test, mesh, laminates, extra, shear, elform, circumferential, node_ids,
                   n_modes, deck, u.name, deck.title)  # fmt: skip


def check_modal_deck(deck: Deck, insert_pid: int | None, path: str | Path) -> None:
    """What a modal deck must be for batball's modal test: free-free (no supports, no ball, no
    rigid parts, no motion), an eigenvalue run only (IMFLAG 1, ENDTIM 0), and the insert, if
    any, tied to every outer part (batball bonds it; an interference fit is not modelled)."""
    c = deck.controls
    extras = [
        name
        for name, present in (
            ("*BOUNDARY_SPC_SET", deck.spcs),
            ("*CONSTRAINED_NODAL_RIGID_BODY_SPC", deck.nodal_rigid_bodies),
            ("*ELEMENT_SOLID", deck.solids),
            ("*INITIAL_VELOCITY_GENERATION", deck.velocities),
            ("*BOUNDARY_PRESCRIBED_MOTION_RIGID", deck.motions),
            ("*DEFINE_CURVE", deck.curves),
            ("*MAT_RIGID", [m for m in deck.materials.values() if m["kind"] == "MAT_RIGID"]),
            ("*CONTROL_DYNAMIC_RELAXATION", "CONTROL_DYNAMIC_RELAXATION" in c),
        )
        if present
    ]
    if extras:
        raise SpecError(f"modal deck {path}", extras, "a free-free bat only")
    general = c.get("CONTROL_IMPLICIT_GENERAL", {})
    end = c.get("CONTROL_TERMINATION", {}).get("endtim")
    if general.get("imflag") != 1 or end not in (None, 0.0):
        raise SpecError(f"modal deck {path}", f"IMFLAG {general.get('imflag')}, ENDTIM {end}",
                        "IMFLAG 1 and ENDTIM 0 (an eigenvalue analysis only)")  # fmt: skip
    contacts = deck.contacts
    outer = sorted(pid for pid in deck.composites if pid != insert_pid)
    tie = "CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET"
    if insert_pid is None and contacts or insert_pid is not None and not (
        len(contacts) == 1 and contacts[0]["kind"] == tie
        and sorted(contact_side(deck, contacts[0], "b")) == outer
    ):  # fmt: skip
        raise SpecError(
            f"modal deck {path}",
            [c["kind"] for c in contacts],
            f"none, or one *{tie} of the insert (SURFA) on all outer parts (SURFB)",
        )


def check_one_piece(mesh: ShellMesh) -> None:
    """The outer wall in one piece, and so the insert the only part held by a tie: a free
    floating part would add rigid-body modes that batball's labels do not expect."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    inserted = mesh.cell_sets.get("insert", np.zeros(0, dtype=np.int64))
    cells = mesh.cells[np.setdiff1d(np.arange(mesh.n_cells), inserted)]
    outer = mesh.point_sets["outer"]
    rows = np.repeat(cells[:, 0], 4)
    graph = coo_matrix((np.ones(rows.size), (rows, cells.ravel())), shape=(mesh.n_points,) * 2)
    _, labels = connected_components(graph, directed=False)
    if np.unique(labels[outer]).size != 1:
        raise SpecError("bat shells", "in more than one piece",
                        "one outer wall (a separate insert must be tied to it)")  # fmt: skip


def contact_side(deck: Deck, contact: dict[str, Any], side: str) -> list[int]:
    """The part ids of one side (``"a"`` or ``"b"``) of a contact: a part or a part set."""
    surf, kind = contact.get(f"surf{side}"), contact.get(f"surf{side}typ")
    if kind == 3:
        return [int(surf)] if surf is not None else []
    if kind == 2 and surf in deck.part_sets:
        return list(deck.part_sets[surf])
    raise SpecError(f"*{contact['kind']} at {contact['where']} SURF{side.upper()}", surf,
                    "a part (type 3) or a *SET_PART_LIST (type 2)")  # fmt: skip


def read_laminae(deck: Deck, u: UnitSystem) -> dict[int, OrthotropicLamina]:
    """Every *MAT_COMPOSITE_DAMAGE as a lamina (SI), by MID."""
    law = LAMINA_LAWS["mat022"]
    out = {}
    for mid, mat in deck.materials.items():
        if mat["kind"] != "MAT_COMPOSITE_DAMAGE":
            continue
        where = f"*MAT_COMPOSITE_DAMAGE at {mat['where']}"
        for name in STRENGTHS:
            if mat.get(name) is not None and not mat[name] >= NO_FAILURE_FROM:
                raise SpecError(
                    f"{where} {name.upper()}",
                    mat[name],
                    f"blank or >= {NO_FAILURE_FROM:g} (batball's laminae are elastic)",
                )
        if mat.get("macf") not in (None, 1) or mat.get("atrack") not in (None, 0):
            raise SpecError(f"{where} MACF/ATRACK", (mat.get("macf"), mat.get("atrack")),
                            "MACF 1, ATRACK 0 (shells, a-axis along edge 1-2)")  # fmt: skip
        values = {p.name: (mat.get(p.lsdyna_field.lower()) or 0.0) * u.size(p.dimension)
                  for p in law.parameters}  # fmt: skip
        out[mid] = law.lamina(values, name=f"mid{mid}")
    return out


def insert_part(deck: Deck) -> int | None:
    """The part id of the insert: SURFA of the tied or interference contact (None if none)."""
    found = [c for c in deck.contacts if c["kind"] in INSERT_CONTACTS]
    if not found:
        return None
    if len(found) > 1 or found[0].get("surfatyp") != 3 or found[0]["surfa"] not in deck.composites:
        raise SpecError(
            f"*{found[0]['kind']} at {found[0]['where']}",
            found[0].get("surfa"),
            "one insert contact whose SURFA is a composite part (SURFATYP 3)",
        )
    return int(found[0]["surfa"])


def bat_mesh(deck: Deck, insert_pid: int | None, u: UnitSystem) -> tuple[ShellMesh, np.ndarray]:
    """The composite parts' shells [m], nodes in deck order; sets by part title."""
    shells = [(pid, nodes, where) for _, pid, nodes, where in deck.shells if pid in deck.composites]
    used = {n for _, nodes, _ in shells for n in nodes}
    missing = sorted(used - set(deck.nodes))
    if missing:
        raise SpecError("*ELEMENT_SHELL", f"node {missing[0]}", "a node defined by *NODE")
    order = np.array([n for n in deck.nodes if n in used], dtype=np.int64)
    index = {int(n): i for i, n in enumerate(order)}
    points = np.array([deck.nodes[int(n)] for n in order], dtype=np.float64) * u.length
    cells = np.array([[index[n] for n in nodes] for _, nodes, _ in shells], dtype=np.int64)
    pids = np.array([pid for pid, _, _ in shells])
    cell_sets, point_sets = {}, {}
    for pid, part in deck.composites.items():
        name = "insert" if pid == insert_pid else part["title"]
        if not name or name in cell_sets or (name == "insert" and pid != insert_pid):
            raise SpecError(f"*PART_COMPOSITE at {part['where']}", name,
                            "a unique title ('insert' only for the SURFA part of the insert's "
                            "tied or interference contact)")  # fmt: skip
        cell_sets[name] = np.flatnonzero(pids == pid)
    inserted = cell_sets.get("insert", np.zeros(0, dtype=np.int64))
    outer = np.setdiff1d(np.arange(len(pids)), inserted)
    point_sets["outer"] = np.unique(cells[outer])
    if inserted.size:
        point_sets["insert"] = np.unique(cells[inserted])
    mesh = ShellMesh(points=points, cells=cells, point_sets=point_sets, cell_sets=cell_sets)
    return mesh, order


def read_parts(
    deck: Deck, mesh: ShellMesh, laminae: dict[int, OrthotropicLamina], insert_pid: int | None,
    u: UnitSystem,
) -> tuple[dict[str, Laminate], np.ndarray, float, int]:  # fmt: skip
    """Each part's laminate, the cells' non-structural mass [kg/m^2], SHRF and ELFORM."""
    laminates, extra = {}, np.zeros(mesh.n_cells)
    shear, elform = set(), set()
    for pid, part in deck.composites.items():
        name = "insert" if pid == insert_pid else part["title"]
        plies = []
        for mid, thickness, angle, where in part["layers"]:
            if mid not in laminae:
                raise SpecError(f"*PART_COMPOSITE MID at {where}", mid,
                                "the MID of a *MAT_COMPOSITE_DAMAGE")  # fmt: skip
            if not thickness > 0:
                raise SpecError(f"*PART_COMPOSITE THICK at {where}", thickness, "> 0")
            plies.append(Ply(laminae[mid], thickness * u.length, math.radians(angle)))
        laminates[name] = Laminate(tuple(plies))
        extra[mesh.cell_sets[name]] = (part.get("marea") or 0.0) * u.density * u.length
        shear.add(1.0 if part.get("shrf") is None else float(part["shrf"]))
        elform.add(part.get("elform") or 2)
    if len(shear) != 1 or len(elform) != 1 or not elform <= {2, 16}:
        raise SpecError("*PART_COMPOSITE SHRF/ELFORM", (sorted(shear), sorted(elform)),
                        "one SHRF and one ELFORM (2 or 16) for every bat part")  # fmt: skip
    return laminates, extra, shear.pop(), elform.pop()


def ring_count(mesh: ShellMesh) -> int:
    """Nodes per ring of batball's ring-numbered bat mesh; SpecError for another numbering."""
    outer = mesh.point_sets["outer"]
    x = mesh.points[:, 0]
    circumferential = int(np.count_nonzero(np.abs(x[outer] - x[0]) < 1e-12))
    ok = outer.size == outer[-1] + 1 and circumferential >= 3
    for nodes in (outer, mesh.point_sets.get("insert", np.zeros(0, dtype=np.int64))):
        ok = ok and nodes.size % max(circumferential, 1) == 0
        if ok and nodes.size:
            ok = float(np.ptp(x[nodes].reshape(-1, circumferential), axis=1).max()) < 1e-9
    if not ok:
        raise SpecError("bat shells", "not numbered ring by ring",
                        "batball's bat mesh: outer rings of equal node count first, then the "
                        "insert's (the modal labels and the insert tie need it)")  # fmt: skip
    return circumferential


def node_set(bat: BatDeck, sid: int) -> np.ndarray:
    """Mesh indices of the bat nodes in *SET_NODE_LIST ``sid``."""
    if sid not in bat.deck.node_sets:
        raise SpecError("*SET_NODE_LIST", sid, "the SID of a node set in the deck")
    index = {int(n): i for i, n in enumerate(bat.node_ids)}
    missing = [n for n in bat.deck.node_sets[sid] if n not in index]
    if missing:
        raise SpecError(f"*SET_NODE_LIST {sid}", f"node {missing[0]}", "a node of the bat")
    return np.array([index[n] for n in bat.deck.node_sets[sid]], dtype=np.int64)


def supports(bat: BatDeck) -> list[tuple[np.ndarray, tuple[int, ...]]]:
    """Each *BOUNDARY_SPC_SET: the bat nodes it holds and its DOF flags (x y z rx ry rz)."""
    out = []
    for spc in bat.deck.spcs:
        dofs = tuple(int(spc.get(k) or 0) for k in ("dofx", "dofy", "dofz", "dofrx", "dofry",
                                                    "dofrz"))  # fmt: skip
        if any(d not in (0, 1) for d in dofs):
            raise SpecError(f"*BOUNDARY_SPC_SET at {spc['where']}", dofs, "flags 0 or 1")
        out.append((node_set(bat, int(spc["nsid"])), dofs))
    return out


def rigid_shells(bat: BatDeck, u: UnitSystem) -> dict[int, RigidPlane | RigidCylinder]:
    """The fixed or moving *MAT_RIGID shell parts (barrel platens) as batball's analytic
    surfaces (:func:`batball.lsdyna.model.fit_target`), by part id; the contact face is
    offset half the shell thickness toward the bat."""
    out = {}
    centre = bat.mesh.points.mean(axis=0)
    for pid, part in bat.deck.parts.items():
        mat = bat.deck.materials.get(int(part.get("mid") or 0), {})
        if mat.get("kind") != "MAT_RIGID":
            continue
        section = bat.deck.sections.get(int(part.get("secid") or 0), {})
        quads = [nodes for _, p, nodes, _ in bat.deck.shells if p == pid]
        if section.get("kind") != "SECTION_SHELL" or not quads:
            raise SpecError(f"rigid part {pid}", "no shells or no *SECTION_SHELL", "rigid shells")
        xyz = np.array([[bat.deck.nodes[n] for n in q] for q in quads]) * u.length
        thickness = float(section.get("t1") or 0.0) * u.length
        out[pid] = fit_target(xyz, thickness, centre, where=f"rigid part {pid}")
    return out


def pivot_band(bat: BatDeck) -> np.ndarray:
    """The bat nodes of the pivot's *CONSTRAINED_NODAL_RIGID_BODY_SPC, which must turn about z
    only (CMO 1, CON1 7, CON2 4: batball's pivot)."""
    if len(bat.deck.nodal_rigid_bodies) != 1:
        raise SpecError("*CONSTRAINED_NODAL_RIGID_BODY_SPC", len(bat.deck.nodal_rigid_bodies),
                        "one: the pivot band")  # fmt: skip
    body = bat.deck.nodal_rigid_bodies[0]
    if (body.get("cmo"), body.get("con1"), body.get("con2")) != (1.0, 7.0, 4.0):
        raise SpecError(
            f"*CONSTRAINED_NODAL_RIGID_BODY_SPC at {body['where']}",
            (body.get("cmo"), body.get("con1"), body.get("con2")),
            "CMO 1, CON1 7, CON2 4 (turning about z only: batball's pivot)",
        )
    return node_set(bat, int(body["nsid"]))


def ball_of(bat: BatDeck, u: UnitSystem) -> tuple[Mesh, np.ndarray, np.ndarray]:
    """The bbs deck's ball: its hex mesh [m], kernel constants and initial velocities [m/s]."""
    solid_parts = sorted({pid for _, pid, _, _ in bat.deck.solids})
    mesh, node_ids = _solid_mesh(bat.deck, u)
    constants, _, _ = _materials(bat.deck, solid_parts, u)
    return mesh, constants, _initial_velocity(bat.deck, mesh, node_ids, u)
