"""Penalty gaps for implicit statics: shell-to-shell node-to-surface pairs and rigid cylinders.

A set of gaps is linear in the nodal displacements (small-displacement contact):

    g = g0 + G u,   G of shape (n_gaps, 6 n_points),

with g < 0 a penetration. A penalty k per gap adds the energy k g^2 / 2 while the gap is closed
(unilateral contact) or always (a bilateral spring). The compressive contact force of a closed gap
is lambda = k max(-g, 0), N.

Shell thickness offsets: a shell's contact surface lies half its wall (or any given offset) from
its mid-surface along the contact normal. The normals are fixed (the undeformed geometry), and a
rotation theta moves an offset point by theta x (o n), which is perpendicular to n, so the offsets
enter g0 only, to first order.

Shell-to-shell pairs (:func:`coaxial_ring_gaps`) tie each node of the inner surface (the slave,
e.g. the bat's insert) to the outer surface (the master, the barrel) at the same angle, the master
point interpolated linearly between the master's two neighbouring rings, with the radial normal;
the penalty per pair is a stiffness per area times the slave node's tributary area, so that a
uniform overlap gives a uniform pressure (LS-DYNA's segment-based penalty, docs/physics.md
section 6.6, in the form an implicit solve needs). Rigid cylinders (:func:`rigid_cylinder_gaps`)
model the barrel-compression platens.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from batball.contact.columns import column_pairs
from batball.mesh.shell import quad_areas


@dataclass(frozen=True)
class PenaltyGaps:
    """Gaps g = initial + matrix @ u with a penalty per gap.

    Attributes:
        matrix: G, shape (n_gaps, 6 n_points), dimensionless (m of gap per m of displacement).
        initial: g0, shape (n_gaps,), m; negative = overlap.
        stiffness: penalty k, shape (n_gaps,), N/m.
        bilateral: True for springs that act in tension too (always active).
    """

    matrix: sp.csr_matrix
    initial: np.ndarray
    stiffness: np.ndarray
    bilateral: bool = False

    @property
    def n_gaps(self) -> int:
        """Number of gaps."""
        return int(self.initial.size)

    def shifted(self, offset: float | np.ndarray) -> PenaltyGaps:
        """The same gaps with g0 + offset (m): a rigid surface moved by -offset along its normal."""
        return replace(self, initial=self.initial + offset)

    def gaps(self, u: np.ndarray) -> np.ndarray:
        """g for displacements u (6 n_points,), m, shape (n_gaps,)."""
        return self.initial + self.matrix @ u

    def forces(self, u: np.ndarray) -> np.ndarray:
        """Compressive force k max(-g, 0) of each gap (k (-g) for bilateral springs), N."""
        g = self.gaps(u)
        return self.stiffness * (-g if self.bilateral else np.maximum(-g, 0.0))


def gap_matrix(nodes: np.ndarray, weights: np.ndarray, normals: np.ndarray,
               n_points: int, *, first_dof: int = 0) -> sp.csr_matrix:  # fmt: skip
    """G with row p = sum_k weights[p, k] normals[p] . u(nodes[p, k]).

    Args:
        nodes: (n_gaps, n_terms) node indices.
        weights: (n_gaps, n_terms), dimensionless (+w_a, +w_b for a master, -1 for a slave).
        normals: (n_gaps, 3) unit normals.
        n_points: nodes of the mesh (6 dofs each).
        first_dof: 0 for the translations u, 3 for the rotations theta.

    Returns:
        (n_gaps, 6 n_points) CSR.
    """
    n_gaps, n_terms = nodes.shape
    rows = np.broadcast_to(np.arange(n_gaps)[:, None, None], (n_gaps, n_terms, 3))
    cols = 6 * nodes[:, :, None] + first_dof + np.arange(3)[None, None, :]
    values = weights[:, :, None] * normals[:, None, :]
    return sp.coo_matrix((values.ravel(), (rows.ravel(), cols.ravel())),
                         shape=(n_gaps, 6 * n_points)).tocsr()  # fmt: skip


def nodal_areas(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Tributary area of each node: a quarter of each attached quad's area, (n_points,), m^2."""
    share = np.repeat(0.25 * quad_areas(points, cells), 4)
    return np.bincount(cells.ravel(), weights=share, minlength=points.shape[0])


def coaxial_ring_gaps(
    points: np.ndarray,
    *,
    slave_nodes: np.ndarray,
    master_rings: np.ndarray,
    slave_offsets: np.ndarray,
    master_offsets: np.ndarray,
    slave_areas: np.ndarray,
    stiffness_per_area: float,
) -> PenaltyGaps:
    """Node-to-surface gaps from an inner shell of revolution (slave) to an outer one (master).

    Both surfaces are revolved about the x axis with the same angles: slave node j of a ring and
    master column j share the angle phi_j. The contact normal is the radial unit vector at phi_j
    (from the slave towards the master). The slave's contact surface lies ``slave_offsets``
    outside its mid-surface, the master's ``master_offsets`` inside its own (half the walls).

    Args:
        points: all nodes, (n_points, 3), m.
        slave_nodes: the slave's nodes, (n_slave,).
        master_rings: the master's nodes ring by ring, (n_rings, n_around), x increasing along
            axis 0, angles 2 pi j / n_around along axis 1.
        slave_offsets: (n_slave,), m.
        master_offsets: (n_points,) indexed by node, m.
        slave_areas: tributary area of each slave node, (n_slave,), m^2.
        stiffness_per_area: penalty per contact area, N/m^3.

    Returns:
        One gap per slave node; g0 < 0 where the two contact surfaces overlap.
    """
    nodes, weights, phi = coaxial_pairs(points, slave_nodes, master_rings)
    normals = np.stack([np.zeros_like(phi), np.cos(phi), np.sin(phi)], axis=1)
    master_a, master_b = nodes[:, 0], nodes[:, 1]
    position = np.einsum("gk,gki->gi", weights, points[nodes])  # x_master - x_slave
    offset = weights[:, 0] * master_offsets[master_a] + weights[:, 1] * master_offsets[master_b]
    initial = np.einsum("gi,gi->g", position, normals) - offset - slave_offsets
    return PenaltyGaps(gap_matrix(nodes, weights, normals, points.shape[0]), initial,
                       stiffness_per_area * slave_areas)  # fmt: skip


def coaxial_pairs(
    points: np.ndarray, slave_nodes: np.ndarray, master_rings: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each slave node's pair in :func:`coaxial_ring_gaps`: nodes (master a, master b, slave),
    weights (1 - w, w, -1) whose sum over the nodes is x_master - x_slave, and the pair's angle
    phi [rad]; (n_slave, 3), (n_slave, 3), (n_slave,)."""
    column, ring, weight_b = column_pairs(points, slave_nodes, master_rings)
    nodes = np.stack([master_rings[ring, column], master_rings[ring + 1, column], slave_nodes],
                     axis=1)  # fmt: skip
    weights = np.stack([1.0 - weight_b, weight_b, -np.ones_like(weight_b)], axis=1)
    return nodes, weights, 2.0 * np.pi * column / master_rings.shape[1]


def coaxial_ring_slips(
    points: np.ndarray,
    *,
    slave_nodes: np.ndarray,
    master_rings: np.ndarray,
    slave_offsets: np.ndarray,
    master_offsets: np.ndarray,
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The tangential relative displacements at the contact surfaces of :func:`coaxial_ring_gaps`'
    pairs (the master's surface point minus the slave's), along the axis and around it (the hoop
    direction at the pair's angle): two (n_slave, 6 n_points) matrices.

    A shell's contact surface lies o along the radial normal n from its mid-surface (the slave's
    ``slave_offsets`` outward, the master's ``master_offsets`` inward), and a point there moves
    by u + theta x (o n): along a tangent t that is u . t + o (n x t) . theta. So the rows carry
    the walls' rotations too: two walls bent alike slide on each other by their curvature times
    the offsets, which is what the surfaces' friction or a glue resists. Small displacements:
    fixed directions.
    """
    nodes, weights, phi = coaxial_pairs(points, slave_nodes, master_rings)
    normals = np.stack([np.zeros_like(phi), np.cos(phi), np.sin(phi)], axis=1)
    offsets = np.column_stack([-master_offsets[nodes[:, 0]], -master_offsets[nodes[:, 1]],
                               slave_offsets])  # fmt: skip
    axial = np.zeros_like(normals)
    axial[:, 0] = 1.0
    hoop = np.cross(axial, normals)
    return surface_slips(nodes, weights, offsets, normals, (axial, hoop), points.shape[0])


def surface_slips(nodes: np.ndarray, weights: np.ndarray, offsets: np.ndarray,
                  normals: np.ndarray, tangents: Sequence[np.ndarray],
                  n_points: int) -> tuple[sp.csr_matrix, ...]:  # fmt: skip
    """Rows of the weighted tangential motion of shell surface points: the point o n off the
    node's mid-surface moves by u + theta x (o n), so along t by u . t + o (n x t) . theta.

    Args:
        nodes, weights: (n_rows, n_terms) as :func:`gap_matrix`'s.
        offsets: (n_rows, n_terms) signed offset o of each term's surface along ``normals``, m.
        normals: (n_rows, 3) the walls' unit normal at each row (the offsets' direction).
        tangents: the slip directions, each (n_rows, 3) unit vectors.
        n_points: number of nodes (6 dofs each).
    """
    return tuple(
        gap_matrix(nodes, weights, t, n_points)
        + gap_matrix(nodes, weights * offsets, np.cross(normals, t), n_points, first_dof=3)
        for t in tangents
    )


def rigid_cylinder_slips(
    points: np.ndarray,
    *,
    nodes: np.ndarray,
    offsets: np.ndarray,
    axis_point: np.ndarray,
    axis_direction: np.ndarray,
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The tangential motion of a fixed rigid cylinder against the shell nodes' offset surfaces
    of :func:`rigid_cylinder_gaps` (the cylinder's point minus the surface's: minus the
    surface's motion), along the cylinder's axis and around it (the normal crossed with the
    axis): two (n_gaps, 6 n_points) matrices, the directions fixed at the undeformed geometry.

    The surface lies ``offsets`` out along the radial direction r about the bat's x axis, so
    its motion carries the node's rotation as o (r x t) . theta (:func:`surface_slips`); a
    cylinder moved along its normals slides nothing, so a moving platen has the same rows.
    """
    radial, normals, _ = cylinder_contact_frame(points, nodes, offsets, axis_point,
                                                axis_direction)  # fmt: skip
    along = np.tile(np.asarray(axis_direction, dtype=float), (nodes.size, 1))
    around = np.cross(normals, along)
    ones = -np.ones((nodes.size, 1))
    return surface_slips(nodes[:, None], ones, offsets[:, None], radial, (along, around),
                         points.shape[0])


def rigid_cylinder_gaps(
    points: np.ndarray,
    *,
    nodes: np.ndarray,
    offsets: np.ndarray,
    axis_point: np.ndarray,
    axis_direction: np.ndarray,
    radius: float,
    stiffness: np.ndarray,
) -> PenaltyGaps:
    """Gaps between shell nodes' offset surfaces and the outside of a rigid circular cylinder.

    g0 = (distance of the offset point from the cylinder's axis) - radius; the normal is the unit
    vector from the axis to the point (fixed at the undeformed geometry). Moving the cylinder by
    s along a direction d changes g by about -(d . n) s; :meth:`PenaltyGaps.shifted` applies it.

    Args:
        points: all nodes, (n_points, 3), m.
        nodes: candidate nodes, (n_gaps,).
        offsets: outward offset of each node's contact surface along its shell normal, taken as
            the radial direction about the bat's x axis, (n_gaps,), m.
        axis_point: a point on the cylinder's axis, (3,), m.
        axis_direction: unit vector along the axis, (3,).
        radius: cylinder radius, m.
        stiffness: penalty per gap, (n_gaps,), N/m.
    """
    _, normals, distance = cylinder_contact_frame(points, nodes, offsets, axis_point,
                                                  axis_direction)  # fmt: skip
    matrix = gap_matrix(nodes[:, None], np.ones((nodes.size, 1)), normals, points.shape[0])
    return PenaltyGaps(matrix, distance - radius, np.asarray(stiffness, dtype=float))


def cylinder_contact_frame(points: np.ndarray, nodes: np.ndarray, offsets: np.ndarray,
                           axis_point: np.ndarray, axis_direction: np.ndarray,
                           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """For shell nodes whose surface lies ``offsets`` out along the radial direction about the
    x axis: that radial direction, the unit normal from a cylinder's axis to the surface point
    and the point's distance from the axis (m), each per node."""
    radial = points[nodes].copy()
    radial[:, 0] = 0.0
    radial /= np.linalg.norm(radial, axis=1, keepdims=True)
    relative = points[nodes] + offsets[:, None] * radial - axis_point
    relative -= np.outer(relative @ axis_direction, axis_direction)
    distance = np.linalg.norm(relative, axis=1)
    return radial, relative / distance[:, None], distance
