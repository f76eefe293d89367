"""The bat's free-free modal test (docs/physics.md section 5.3; seed "Modal Analysis", Table 3).

The bat's shells (MITC4, :mod:`batball.elements.shell_stiffness`) with each part's laminate and
lumped mass; the 30 lowest modes by shift-invert Lanczos (:mod:`batball.solvers.modal`).

**The insert**, two models (``insert=``). ``"contact"`` (the default: every later test
starts from the bat's pre-stressed state) and ``"bonded"``. ``"bonded"``: each insert node is tied
rigidly to the barrel wall: its displacement is the barrel's (linearly interpolated between the
two nearest barrel rings at the same angle) plus the barrel rotation times the radial offset
between the two mid-surfaces, and its rotation the barrel's. This is the "bonded" bound of
docs/physics.md section 7.3: stiffer in hoop than the seed's fitted double wall. ``"contact"``: the
pre-stressed interference fit of :mod:`batball.lab.barrel` linearised: every closed fit gap is a
radial penalty spring and the walls slide freely (frictionless), the other bound; the insert's
free axial slide and spin are then two more zero-frequency modes.

Mode labels come from the shapes of the outer wall (the nodes sit on rings of ``circumferential``
nodes at angles phi_j = 2 pi j / circumferential):

* ``bending``: cross-sections translate rigidly; the share of the outer wall's translational
  "energy" sum |u|^2 carried by the ring-mean lateral translation (u_y, u_z) exceeds one half.
* ``hoop``: ovalling of the barrel; the share carried by the cos 2 phi and sin 2 phi content of the
  radial displacement on the barrel rings exceeds one third. Barrel rings are those of full
  diameter (radius >= 95 % of the largest) *within the insert's axial span*: the seed's hoop
  modes are ovalling of the barrel it hits, and without this restriction the lowest n = 2 mode
  was the ovalling of the open barrel end beyond the insert (32-33.1 in), which the real bat's
  end-cap plug stiffens but our model does not (the plug is non-structural mass here; its
  stiffness and geometry are not in the seed). A hoop mode must also have more of that ovalling
  on the barrel rings than on the full-diameter rings beyond them, so the end-ring mode (whose
  ovalling spills onto the last barrel rings) is labelled ``other`` with a margin.
* ``rigid`` for the six near-zero modes (eight with the contact insert); ``other`` for the rest
  (torsion, axial, n >= 3 shell).

Degenerate pairs (the same frequency in two planes) count once: "first" and "second" bending and
hoop are the first two distinct frequencies (more than 1 % apart), as the seed reports them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from batball.elements.shell_stiffness import (
    ShellSection,
    assemble_shell_mass,
    assemble_shell_stiffness,
)
from batball.errors import SpecError
from batball.mesh.bat import DEFAULT_AXIAL_SIZE, DEFAULT_CIRCUMFERENTIAL, make_bat_mesh
from batball.mesh.shell import ShellMesh
from batball.models.bat import bat_section
from batball.solvers.modal import N_RIGID_BODY_MODES, ModalResult, free_free_modes
from batball.solvers.static_contact import penalty_system
from batball.specs.bat import BatSpec

BENDING_SHARE = 0.5
HOOP_SHARE = 1.0 / 3.0
#: Frequencies closer than this (relative) are one degenerate pair.
DISTINCT = 0.01


@dataclass(frozen=True)
class BatModes:
    """The bat's free-free modes with labels.

    Attributes:
        frequencies: (n_modes,), Hz, ascending, rigid-body modes first.
        labels: (n_modes,) ``"rigid"``, ``"bending"``, ``"hoop"`` or ``"other"``.
        bending_share: share of the outer wall's sum |u|^2 in rigid section translation, (n_modes,).
        hoop_share: share in n = 2 radial ovalling of the barrel, (n_modes,).
        shapes: mode shapes on all nodes, (n_points, 6, n_modes): u (m) and theta (rad) per unit
            modal mass.
        mesh: the shells the modes live on.
    """

    frequencies: np.ndarray
    labels: tuple[str, ...]
    bending_share: np.ndarray
    hoop_share: np.ndarray
    shapes: np.ndarray
    mesh: ShellMesh

    def first(self, label: str, count: int = 2) -> list[int]:
        """Indices of the first ``count`` distinct-frequency modes with ``label``."""
        chosen: list[int] = []
        for index in np.flatnonzero(np.array(self.labels) == label):
            f = self.frequencies[index]
            if all(abs(f - self.frequencies[c]) > DISTINCT * f for c in chosen):
                chosen.append(int(index))
        return chosen[:count]


def skew(vectors: np.ndarray) -> np.ndarray:
    """Cross-product matrices [d]x with [d]x a = d x a, (n, 3, 3) from (n, 3)."""
    out = np.zeros((vectors.shape[0], 3, 3))
    out[:, 0, 1], out[:, 0, 2] = -vectors[:, 2], vectors[:, 1]
    out[:, 1, 0], out[:, 1, 2] = vectors[:, 2], -vectors[:, 0]
    out[:, 2, 0], out[:, 2, 1] = -vectors[:, 1], vectors[:, 0]
    return out


def insert_tie(mesh: ShellMesh, circumferential: int) -> sp.csr_matrix:
    """T with u_all = T u_outer: insert nodes rigidly tied to the barrel (see module docs).

    Returns:
        (6 n_points, 6 n_outer) sparse; the outer nodes are the first n_outer and map to themselves.
    """
    n_outer = mesh.point_sets["outer"].size
    inserted = mesh.point_sets["insert"]
    ring_x = mesh.points[:n_outer:circumferential, 0]
    x = mesh.points[inserted, 0]
    j = (inserted - n_outer) % circumferential
    ring = np.clip(np.searchsorted(ring_x, x, side="right") - 1, 0, ring_x.size - 2)
    weight = np.clip((x - ring_x[ring]) / (ring_x[ring + 1] - ring_x[ring]), 0.0, 1.0)
    rows, cols, values = [], [], []
    for anchor_ring, w in ((ring, 1.0 - weight), (ring + 1, weight)):
        anchor = anchor_ring * circumferential + j
        block = np.zeros((inserted.size, 6, 6))
        block[:, :3, :3] = block[:, 3:, 3:] = np.eye(3)
        block[:, :3, 3:] = -skew(mesh.points[inserted] - mesh.points[anchor])
        block *= w[:, None, None]
        row_dofs, col_dofs = (
            6 * inserted[:, None] + np.arange(6),
            6 * anchor[:, None] + np.arange(6),
        )
        rows.append(np.broadcast_to(row_dofs[:, :, None], block.shape))
        cols.append(np.broadcast_to(col_dofs[:, None, :], block.shape))
        values.append(block)
    n_dofs = 6 * n_outer
    identity = np.arange(n_dofs)
    tie = sp.coo_matrix(
        (np.concatenate([np.ones(n_dofs)] + [v.ravel() for v in values]),
         (np.concatenate([identity] + [r.ravel() for r in rows]),
          np.concatenate([identity] + [c.ravel() for c in cols]))),
        shape=(6 * mesh.n_points, n_dofs),
    )  # fmt: skip
    return tie.tocsr()


def shape_shares(
    mesh: ShellMesh, shapes: np.ndarray, circumferential: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Bending share, hoop share on the barrel rings and hoop share on the full-diameter rings
    beyond them (module docs), each (n_modes,)."""
    n_outer = mesh.point_sets["outer"].size
    n_rings = n_outer // circumferential
    u = shapes[:n_outer, :3].reshape(n_rings, circumferential, 3, -1)
    total = np.einsum("rjkm,rjkm->m", u, u)
    lateral = u[:, :, 1:].mean(axis=1)  # (rings, 2, modes)
    bending = circumferential * np.einsum("rkm,rkm->m", lateral, lateral) / total
    points = mesh.points[:n_outer].reshape(n_rings, circumferential, 3)
    phi = np.arctan2(points[0, :, 2], points[0, :, 1])
    radial = u[:, :, 1] * np.cos(phi)[None, :, None] + u[:, :, 2] * np.sin(phi)[None, :, None]
    c2 = 2.0 / circumferential * np.einsum("rjm,j->rm", radial, np.cos(2 * phi))
    s2 = 2.0 / circumferential * np.einsum("rjm,j->rm", radial, np.sin(2 * phi))
    ovalling = 0.5 * circumferential * (c2**2 + s2**2) / total  # (rings, modes)
    full_diameter, barrel = barrel_rings(mesh, points)
    return bending, ovalling[barrel].sum(axis=0), ovalling[full_diameter & ~barrel].sum(axis=0)


def barrel_rings(mesh: ShellMesh, rings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Full-diameter rings and barrel rings of the outer wall, each (n_rings,) bool.

    Full diameter: radius >= 95 % of the largest. Barrel: those within the insert's axial span
    (all of them when the bat has no insert).

    Args:
        mesh: the bat's shells.
        rings: outer-wall nodes ring by ring, (n_rings, circumferential, 3), m.
    """
    radius = np.hypot(rings[:, 0, 1], rings[:, 0, 2])
    full_diameter = radius >= 0.95 * radius.max()
    barrel = full_diameter.copy()
    if "insert" in mesh.point_sets:
        x_insert = mesh.points[mesh.point_sets["insert"], 0]
        barrel &= (rings[:, 0, 0] >= x_insert.min()) & (rings[:, 0, 0] <= x_insert.max())
    return full_diameter, barrel


def label_modes(
    result: ModalResult, bending: np.ndarray, hoop: np.ndarray, hoop_beyond: np.ndarray
) -> tuple[str, ...]:
    """``rigid``, ``bending``, ``hoop`` or ``other`` for each mode (shares from shape_shares)."""
    is_hoop = (hoop > HOOP_SHARE) & (hoop > hoop_beyond)
    labels = np.where(bending > BENDING_SHARE, "bending", np.where(is_hoop, "hoop", "other"))
    labels = np.where(result.rigid, "rigid", labels)
    return tuple(str(label) for label in labels)


#: How the insert meets the barrel in the modal model (module docs).
INSERT_MODELS = ("bonded", "contact")


def insert_contact_stiffness(spec: BatSpec, circumferential: int,
                             axial_size: float) -> sp.csr_matrix:  # fmt: skip
    """K plus the closed interference-fit gaps of the pre-stressed bat as radial springs, SI.

    The fit (:func:`batball.models.barrel.compute_prestress`) closes every insert node's gap on the
    default bat; linearised about that state, each closed frictionless gap is a radial penalty
    spring k G^T G: the walls share radial motion and slide freely along the axis and around.
    The pre-stress's geometric stiffness is left out (hoop stresses of about 1-1.6 ksi against
    moduli of 2-3 Msi)."""
    from batball.models.barrel import build_barrel_model, compute_prestress

    model = build_barrel_model(spec, circumferential=circumferential, axial_size=axial_size)
    active = compute_prestress(model).active
    stiffness, _ = penalty_system(model.stiffness, [model.interference], [active])
    return stiffness


def bat_modes(
    spec: BatSpec,
    *,
    circumferential: int = DEFAULT_CIRCUMFERENTIAL,
    axial_size: float = DEFAULT_AXIAL_SIZE,
    n_modes: int = 30,
    insert: str = "contact",
) -> BatModes:
    """Free-free modes of a bat, labelled.

    Args:
        spec: the bat.
        circumferential: shells around the circumference.
        axial_size: largest shell length along the bat, m.
        n_modes: modes to compute, the six rigid-body modes included.
        insert: ``"bonded"`` (tied rigidly to the barrel) or ``"contact"`` (the pre-stressed
            interference fit: radial springs of the closed gaps, frictionless sliding; the
            insert's free axial slide and spin are two more zero modes, labelled rigid).

    Raises:
        SpecError: an unknown ``insert``.
    """
    if insert not in INSERT_MODELS:
        raise SpecError("insert", insert, f"one of {', '.join(INSERT_MODELS)}")
    mesh = make_bat_mesh(spec, circumferential=circumferential, axial_size=axial_size)
    section = bat_section(spec, mesh)
    contact = None
    if "insert" in mesh.point_sets and insert == "contact":
        contact = insert_contact_stiffness(spec, circumferential, axial_size)
    return shell_modes(mesh, section, circumferential=circumferential, n_modes=n_modes,
                       contact_stiffness=contact)  # fmt: skip


def shell_modes(
    mesh: ShellMesh,
    section: ShellSection,
    *,
    circumferential: int,
    n_modes: int = 30,
    contact_stiffness: sp.spmatrix | None = None,
) -> BatModes:
    """Free-free modes of a ring-numbered bat mesh with its section, labelled:
    :func:`bat_modes` once the mesh and section exist (also the route of a keyword deck read
    by :mod:`batball.lsdyna.bat_model`).

    Args:
        mesh: the bat's shells, numbered as :func:`~batball.mesh.bat.make_bat_mesh` numbers them
            (outer rings of ``circumferential`` nodes first, then the insert's; point sets
            ``"outer"`` and, for a double wall, ``"insert"``).
        section: per-cell section constants.
        circumferential: nodes around each ring.
        n_modes: modes to compute, the six rigid-body modes included.
        contact_stiffness: the whole stiffness with the insert held by the pre-stressed fit's
            contact (:func:`insert_contact_stiffness`; two more zero modes); None ties the insert
            to the barrel (bonded).
    """
    mass = assemble_shell_mass(mesh, section)
    tie = sp.identity(6 * mesh.n_points, format="csr")
    n_zero = N_RIGID_BODY_MODES
    if contact_stiffness is not None:
        stiffness = contact_stiffness
        n_zero += 2
    else:
        stiffness = assemble_shell_stiffness(mesh, section)
        if "insert" in mesh.point_sets:
            tie = insert_tie(mesh, circumferential)
            stiffness, mass = tie.T @ stiffness @ tie, tie.T @ mass @ tie
    result = free_free_modes(stiffness, mass, n_modes=n_modes, shift_hz=10.0,
                             n_zero_modes=n_zero)  # fmt: skip
    shapes = np.asarray(tie @ result.shapes).reshape(mesh.n_points, 6, n_modes)
    bending, hoop, hoop_beyond = shape_shares(mesh, shapes, circumferential)
    labels = label_modes(result, bending, hoop, hoop_beyond)
    return BatModes(result.frequencies, labels, bending, hoop, shapes, mesh)
