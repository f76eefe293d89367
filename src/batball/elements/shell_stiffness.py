"""Four-node flat layered shell for implicit statics and eigenvalues: stiffness and mass.

Formulation (a flat MITC4 shell with drilling stabilisation):

* Element frame as the Belytschko-Tsay shell (docs/physics.md section 6.4): e3 along (x3 - x1) x
  (x4 - x2), e1 along edge 1-2 projected onto the plane, e2 = e3 x e1. The nodes are projected onto
  the plane through their centroid (exact for the planar quads of the bat and tube meshes).
* Six degrees of freedom per node, global (u_x, u_y, u_z, theta_x, theta_y, theta_z); the rotations
  are rotation-vector components, so a point at height z along e3 moves by theta x (z e3):
  u = u0 + z theta_2, v = v0 - z theta_1.
* Membrane strains and curvatures (kappa_x = theta_2,x, kappa_y = -theta_1,y, 2 kappa_xy =
  theta_2,y - theta_1,x) by 2 x 2 Gauss quadrature with the laminate's full [[A, B], [B, D]]
  (classical lamination theory, :meth:`batball.materials.laminate.Laminate.abd`); the membrane
  shear strain is sampled at the centre (a B-bar that removes the parasitic shear of in-plane
  bending without adding zero-energy modes).
* Transverse shear by the MITC4 assumed covariant strains tied at the edge midpoints (Dvorkin &
  Bathe 1984; Bathe, Finite Element Procedures, section 5.4.2), with stiffness H = kappa_s
  sum_k t_k R_k^T diag(G_ca, G_bc) R_k, kappa_s = 5/6 (LS-DYNA SHRF; docs/physics.md section 6.5).
* Drilling: a penalty k_d (theta_3,i - omega)^2 at each node, omega = (v,x - u,y)/2 the in-plane
  rotation at the centre, k_d = alpha * A66 * area with alpha = 1e-3 by default: rigid rotations
  cost nothing, and the drilling freedom no longer makes K singular.
* Mass: consistent (2 x 2 Gauss, exact for flat quads) or row-sum lumped, with the translational
  areal mass m0 = sum rho_k t_k and the rotary inertia I2 = sum rho_k (z_k+1^3 - z_k^3)/3 on all
  three rotations (so the rotational mass is frame-invariant); the first moment sum rho_k z t_k
  (a mass offset of unsymmetric layups) is neglected.

Layer angles are measured from element edge 1-2 (the laminate x axis = e1), as LS-DYNA's
AOPT = 0; on the bat meshes edge 1-2 runs along the bat axis.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from batball.materials.laminate import Laminate
from batball.mesh.shell import ShellMesh

#: LS-DYNA SHRF default, the Reissner-Mindlin shear correction factor.
SHEAR_FACTOR = 5.0 / 6.0
#: Drilling penalty relative to A66 times the element area.
DRILLING_FACTOR = 1e-3

_G = 1.0 / np.sqrt(3.0)
_GAUSS = np.array([[-_G, -_G], [_G, -_G], [_G, _G], [-_G, _G]])  # (xi, eta), unit weights
_CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
#: MITC4 tying points: A, C for gamma_xi (eta = -1, +1); D, B for gamma_eta (xi = -1, +1).
_TYING_XI = np.array([[0.0, -1.0], [0.0, 1.0]])
_TYING_ETA = np.array([[-1.0, 0.0], [1.0, 0.0]])


@dataclass(frozen=True)
class ShellSection:
    """Per-cell section constants of a layered shell, in each element's frame (x = edge 1-2).

    Attributes:
        abd: [[A, B], [B, D]], shape (n_cells, 6, 6); A N/m, B N, D N m.
        shear: transverse shear stiffness H (gamma_xz, gamma_yz), shape (n_cells, 2, 2), N/m.
        areal_mass: m0 = sum rho_k t_k, shape (n_cells,), kg/m^2.
        rotary_inertia: I2 = integral of rho z^2 dz, shape (n_cells,), kg.
    """

    abd: np.ndarray
    shear: np.ndarray
    areal_mass: np.ndarray
    rotary_inertia: np.ndarray


def transverse_shear_stiffness(
    laminate: Laminate, *, shear_factor: float = SHEAR_FACTOR
) -> np.ndarray:
    """H = kappa_s sum_k t_k R_k^T diag(G_ca, G_bc) R_k in laminate axes, shape (2, 2), N/m.

    Args:
        laminate: the layup (layer angles from the laminate x axis).
        shear_factor: kappa_s (5/6).
    """
    layers = laminate.layers()
    theta = np.array([ly.angle for ly in layers])
    c, s = np.cos(theta), np.sin(theta)
    rotation = np.stack([np.stack([c, s], -1), np.stack([-s, c], -1)], -2)  # (k, 2, 2)
    moduli = np.array([[ly.material.gca, ly.material.gbc] for ly in layers])
    thickness = np.array([ly.thickness for ly in layers])
    per_layer = np.einsum("kai,ka,kaj->kij", rotation, moduli, rotation)
    return shear_factor * np.einsum("k,kij->ij", thickness, per_layer)


def laminate_rotary_inertia(laminate: Laminate) -> float:
    """I2 = sum_k rho_k (z_k+1^3 - z_k^3) / 3 about the mid-surface, kg."""
    z = laminate.interfaces()
    density = np.array([ly.material.density for ly in laminate.layers()])
    return float(np.sum(density * np.diff(z**3)) / 3.0)


def shell_section(
    laminates: Sequence[Laminate],
    cell_laminate: np.ndarray,
    *,
    extra_areal_mass: np.ndarray | None = None,
    shear_factor: float = SHEAR_FACTOR,
) -> ShellSection:
    """Section constants of every cell from a short list of laminates.

    Args:
        laminates: the distinct layups.
        cell_laminate: index into ``laminates`` of each cell, shape (n_cells,), int.
        extra_areal_mass: non-structural mass per area added to m0, shape (n_cells,), kg/m^2.
        shear_factor: kappa_s (5/6).
    """
    abd = np.stack([lam.abd().matrix() for lam in laminates])
    shear = np.stack([transverse_shear_stiffness(lam, shear_factor=shear_factor)
                      for lam in laminates])  # fmt: skip
    mass = np.array([lam.areal_mass for lam in laminates])
    inertia = np.array([laminate_rotary_inertia(lam) for lam in laminates])
    index = np.asarray(cell_laminate, dtype=np.int64)
    areal = mass[index] if extra_areal_mass is None else mass[index] + extra_areal_mass
    return ShellSection(abd[index], shear[index], areal, inertia[index])


def element_frames(points: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Element frames and flat local coordinates of the nodes.

    Args:
        points: (n_points, 3), m.
        cells: (n_cells, 4) node indices.

    Returns:
        frames (n_cells, 3, 3) with rows e1, e2, e3; local (n_cells, 4, 2) node coordinates in
        (e1, e2) about the centroid, m.
    """
    x = points[cells]
    e3 = np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])
    e3 /= np.linalg.norm(e3, axis=1, keepdims=True)
    edge = x[:, 1] - x[:, 0]
    e1 = edge - np.einsum("ci,ci->c", edge, e3)[:, None] * e3
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    frames = np.stack([e1, np.cross(e3, e1), e3], axis=1)
    relative = x - x.mean(axis=1, keepdims=True)
    local = np.einsum("cnk,cak->cna", relative, frames[:, :2])
    return frames, local


def shape_functions(xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bilinear shape functions and their natural derivatives at points ``xi`` (n_pts, 2).

    Returns:
        N (n_pts, 4); dN (n_pts, 2, 4) with rows d/dxi, d/deta.
    """
    a = 1.0 + xi[:, None, 0] * _CORNERS[None, :, 0]
    b = 1.0 + xi[:, None, 1] * _CORNERS[None, :, 1]
    derivative = np.stack([0.25 * _CORNERS[None, :, 0] * b, 0.25 * _CORNERS[None, :, 1] * a], 1)
    return 0.25 * a * b, derivative


def jacobians(local: np.ndarray, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Jacobians J = [[x_xi, y_xi], [x_eta, y_eta]] and Cartesian derivatives at points ``xi``.

    Returns:
        J (n_cells, n_pts, 2, 2); det J (n_cells, n_pts); dN/dx (n_cells, n_pts, 2, 4).
    """
    _, derivative = shape_functions(xi)
    jac = np.einsum("pan,cnb->cpab", derivative, local)
    inverse = np.linalg.inv(jac)
    return jac, np.linalg.det(jac), np.einsum("cpab,pbn->cpan", inverse, derivative)


def membrane_bending_matrix(dndx: np.ndarray, dndx_centre: np.ndarray) -> np.ndarray:
    """B of (eps_x, eps_y, gamma_xy, kappa_x, kappa_y, 2 kappa_xy) on the 24 local dofs.

    Args:
        dndx: Cartesian derivatives at the Gauss points, (n_cells, n_pts, 2, 4), 1/m.
        dndx_centre: the same at the centre, (n_cells, 2, 4), 1/m (membrane shear B-bar).

    Returns:
        (n_cells, n_pts, 6, 24), 1/m for strains and 1/m (per rad) for curvatures.
    """
    n_cells, n_pts = dndx.shape[:2]
    b = np.zeros((n_cells, n_pts, 6, 4, 6))
    nx, ny = dndx[:, :, 0], dndx[:, :, 1]
    b[:, :, 0, :, 0] = nx
    b[:, :, 1, :, 1] = ny
    b[:, :, 2, :, 0] = dndx_centre[:, None, 1]
    b[:, :, 2, :, 1] = dndx_centre[:, None, 0]
    b[:, :, 3, :, 4] = nx
    b[:, :, 4, :, 3] = -ny
    b[:, :, 5, :, 4] = ny
    b[:, :, 5, :, 3] = -nx
    return b.reshape(n_cells, n_pts, 6, 24)


def covariant_shear_rows(local: np.ndarray, tying: np.ndarray, direction: int) -> np.ndarray:
    """Rows of gamma_xi (direction 0) or gamma_eta (1) at tying points, on the 24 local dofs.

    gamma_r = w,r + theta_2 x,r - theta_1 y,r (r = xi or eta).

    Returns:
        (n_cells, n_tying, 24), dimensionless per m of w, per rad of rotation times m.
    """
    shape, derivative = shape_functions(tying)
    tangent = np.einsum("pn,cnb->cpb", derivative[:, direction], local)  # (c, p, 2)
    rows = np.zeros((local.shape[0], tying.shape[0], 4, 6))
    rows[..., 2] = derivative[None, :, direction]
    rows[..., 4] = shape[None] * tangent[..., 0:1]
    rows[..., 3] = -shape[None] * tangent[..., 1:2]
    return rows.reshape(local.shape[0], tying.shape[0], 24)


def transverse_shear_matrix(local: np.ndarray, jac: np.ndarray) -> np.ndarray:
    """MITC4 B of (gamma_xz, gamma_yz) at the Gauss points, (n_cells, n_pts, 2, 24)."""
    at_xi = covariant_shear_rows(local, _TYING_XI, 0)  # A (eta=-1), C (eta=+1)
    at_eta = covariant_shear_rows(local, _TYING_ETA, 1)  # D (xi=-1), B (xi=+1)
    eta, xi = _GAUSS[:, 1], _GAUSS[:, 0]
    gamma_xi = 0.5 * ((1 - eta)[None, :, None] * at_xi[:, None, 0]
                      + (1 + eta)[None, :, None] * at_xi[:, None, 1])  # fmt: skip
    gamma_eta = 0.5 * ((1 - xi)[None, :, None] * at_eta[:, None, 0]
                       + (1 + xi)[None, :, None] * at_eta[:, None, 1])  # fmt: skip
    natural = np.stack([gamma_xi, gamma_eta], axis=2)  # (c, p, 2, 24)
    return np.einsum("cpab,cpbk->cpak", np.linalg.inv(jac), natural)


def drilling_matrix(dndx_centre: np.ndarray, area: np.ndarray, a66: np.ndarray,
                    factor: float) -> np.ndarray:  # fmt: skip
    """Drilling penalty sum_i k_d (theta_3,i - omega)^2, (n_cells, 24, 24), N m.

    Args:
        dndx_centre: (n_cells, 2, 4), 1/m.
        area: (n_cells,), m^2.
        a66: membrane shear stiffness A66, (n_cells,), N/m.
        factor: alpha in k_d = alpha A66 area.
    """
    n_cells = area.shape[0]
    omega = np.zeros((n_cells, 4, 6))
    omega[..., 0] = -0.5 * dndx_centre[:, 1]
    omega[..., 1] = 0.5 * dndx_centre[:, 0]
    rows = np.repeat(-omega.reshape(n_cells, 1, 24), 4, axis=1)
    rows[:, np.arange(4), 6 * np.arange(4) + 5] += 1.0
    return (factor * a66 * area)[:, None, None] * np.einsum("cik,cil->ckl", rows, rows)


def local_stiffness(local: np.ndarray, section: ShellSection,
                    drilling_factor: float = DRILLING_FACTOR) -> np.ndarray:  # fmt: skip
    """Element stiffness in element frames, (n_cells, 24, 24), SI (N/m, N, N m per rad)."""
    jac, det, dndx = jacobians(local, _GAUSS)
    _, det_centre, dndx_centre = jacobians(local, np.zeros((1, 2)))
    b_mb = membrane_bending_matrix(dndx, dndx_centre[:, 0])
    b_s = transverse_shear_matrix(local, jac)
    stiffness = np.einsum("cp,cpik,cij,cpjl->ckl", det, b_mb, section.abd, b_mb)
    stiffness += np.einsum("cp,cpik,cij,cpjl->ckl", det, b_s, section.shear, b_s)
    area = 4.0 * det_centre[:, 0]
    stiffness += drilling_matrix(dndx_centre[:, 0], area, section.abd[:, 2, 2], drilling_factor)
    return stiffness


def to_global(k: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """(T^T k T) for k of shape (n_cells, 8, 3, 8, 3) and frames (n_cells, 3, 3) (rows e_a)."""
    # two stacked 3 x 3 products, each frame on one index of every 3 x 3 block (five times the
    # speed of the two einsum contractions they replace)
    n_cells = k.shape[0]
    left = np.matmul(frames.transpose(0, 2, 1)[:, None], k.reshape(n_cells, 8, 3, 24))
    return np.matmul(left.reshape(n_cells, 24, 8, 3), frames[:, None]).reshape(n_cells, 24, 24)


def element_dofs(cells: np.ndarray) -> np.ndarray:
    """Global dof numbers 6 * node + component of each quad, (n_cells, 24)."""
    return (6 * cells[:, :, None] + np.arange(6)[None, None, :]).reshape(cells.shape[0], 24)


def assemble(matrices: np.ndarray, cells: np.ndarray, n_points: int) -> sp.csr_matrix:
    """Scatter element matrices (n_cells, 24, 24) into a (6 n_points)^2 CSR matrix."""
    size = 6 * n_points
    # 32-bit indices where they fit: the sort into rows takes a third of the time of 64-bit
    dofs = element_dofs(cells).astype(np.int32 if size < 2**31 else np.int64)
    rows = np.broadcast_to(dofs[:, :, None], matrices.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], matrices.shape).ravel()
    return sp.coo_matrix((matrices.ravel(), (rows, cols)), shape=(size, size)).tocsr()


def assemble_shell_stiffness(
    mesh: ShellMesh, section: ShellSection, *, drilling_factor: float = DRILLING_FACTOR
) -> sp.csr_matrix:
    """Global stiffness K of a layered MITC4 shell mesh, (6 n_points)^2, SI.

    Args:
        mesh: the quads; layer angles are taken from each quad's edge 1-2.
        section: per-cell constants (:func:`shell_section`).
        drilling_factor: alpha of the drilling penalty alpha A66 area.
    """
    frames, local = element_frames(mesh.points, mesh.cells)
    stiffness = local_stiffness(local, section, drilling_factor)
    return assemble(to_global(stiffness.reshape(-1, 8, 3, 8, 3), frames), mesh.cells,
                    mesh.n_points)  # fmt: skip


def element_mass(local: np.ndarray, section: ShellSection, *, lumped: bool) -> np.ndarray:
    """Element mass (frame-invariant), (n_cells, 24, 24), kg and kg m^2.

    The consistent matrix m0 int N_i N_j dA on translations and I2 int N_i N_j dA on rotations;
    ``lumped`` takes row sums.
    """
    shape, _ = shape_functions(_GAUSS)
    _, det, _ = jacobians(local, _GAUSS)
    scalar = np.einsum("cp,pi,pj->cij", det, shape, shape)
    if lumped:
        scalar = scalar.sum(axis=2)[:, :, None] * np.eye(4)[None]
    density = np.concatenate([np.repeat(section.areal_mass[:, None], 3, 1),
                              np.repeat(section.rotary_inertia[:, None], 3, 1)], 1)  # fmt: skip
    mass = np.einsum("cij,ck,kl->cikjl", scalar, density, np.eye(6))
    return mass.reshape(-1, 24, 24)


def assemble_shell_mass(
    mesh: ShellMesh, section: ShellSection, *, lumped: bool = False
) -> sp.csr_matrix:
    """Global mass M, (6 n_points)^2: consistent (default) or row-sum lumped, with rotary inertia.

    Args:
        mesh: the quads.
        section: per-cell areal mass and rotary inertia.
        lumped: row-sum lumping (diagonal M).
    """
    _, local = element_frames(mesh.points, mesh.cells)
    return assemble(element_mass(local, section, lumped=lumped), mesh.cells, mesh.n_points)
