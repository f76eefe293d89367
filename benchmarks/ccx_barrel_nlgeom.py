"""Barrel compression of the default bat's double wall in CalculiX: geometrically linear vs NLGEOM.

An independent check of two questions in docs/notes/barrel.md (issue 8): (1) does geometric
nonlinearity (ovalisation, local flattening under the platen) make the force-travel curve soften
from 0.02 in to 0.07 in, as the experiment's Table 2 pair (186 / 368 lbf, ratio 1.98 against the
linear 2.5) does; (2) is batball's linear force the right size for such a wall.

Model (inch, lbf, psi; one eighth by symmetry): the barrel-3 wall (glass 0.012 in at 60 deg,
carbon 0.0633 in at 30 deg, glass 0.015 in at 45 deg, inner to outer, outer radius 1.125 in) over
the insert (glass 0.015 / carbon 0.030 / glass 0.015 in at 60 / 45 / 60 deg), 10 in long (the
insert's length; the bat's barrel continues beyond it, so this tube is somewhat softer than the
bat), one C3D8I layer per ply. Each braided ply is the homogenised balanced +-theta laminate
(classical lamination theory in the ply's plane, the through-thickness moduli rotated), in
CalculiX's cylindrical orientation (1 radial, 2 hoop, 3 axial). The insert's outer and the
barrel's inner surfaces share their radius and are tied radially only (*EQUATION on the radial
dofs), free to slide: batball's finding that the fit gaps never open, without the 0.001-in
pre-stress. The 3.3-in platen is a rigid body (node-to-surface penalty contact, frictionless);
top-bottom symmetry means each platen moves half the travel. Materials: docs/physics.md section
7.1 as in src/batball/specs/data/default_bat.toml.

Run: ``python benchmarks/ccx_barrel_nlgeom.py [folder]`` (needs ``ccx``); prints the force at
each 0.01 in of travel for the linear and the NLGEOM run, and the Table 2 pair of each.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

PSI_PER_GPA = 1e9 / 6894.757293168
#: (E1, E2, G12, G23 in GPa; nu12) of docs/physics.md section 7.1 (as default_bat.toml).
LAMINAE = {"carbon": (147.0, 10.3, 7.0, 3.5, 0.27), "glass": (41.0, 10.4, 4.3, 3.5, 0.28)}
#: Inner to outer: (material, thickness in, braid angle deg).
INSERT = [("glass", 0.015, 60.0), ("carbon", 0.030, 45.0), ("glass", 0.015, 60.0)]
BARREL = [("glass", 0.012, 60.0), ("carbon", 0.0633, 30.0), ("glass", 0.015, 45.0)]
OUTER_RADIUS, HALF_LENGTH, PLATEN_RADIUS = 1.125, 5.0, 1.65  # in
N_AROUND = 16  # per quarter (64 around)
TRAVEL, N_INCREMENTS = 0.07, 7  # in, total platen travel (each platen moves half)


def braid_constants(material: str, angle_deg: float) -> list[float]:
    """CalculiX engineering constants (1 radial, 2 hoop, 3 axial) of a balanced +-angle braid:
    E1 E2 E3 nu12 nu13 nu23 G12 G13 G23, psi."""
    e1, e2, g12, g23, nu12 = LAMINAE[material]
    nu21 = nu12 * e2 / e1
    q11, q22, q12, q66 = (e1 / (1 - nu12 * nu21), e2 / (1 - nu12 * nu21),
                          nu12 * e2 / (1 - nu12 * nu21), g12)  # fmt: skip
    c, s = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    qxx = q11 * c**4 + 2 * (q12 + 2 * q66) * s**2 * c**2 + q22 * s**4
    qyy = q11 * s**4 + 2 * (q12 + 2 * q66) * s**2 * c**2 + q22 * c**4
    qxy = (q11 + q22 - 4 * q66) * s**2 * c**2 + q12 * (s**4 + c**4)
    qss = (q11 + q22 - 2 * q12 - 2 * q66) * s**2 * c**2 + q66 * (s**4 + c**4)
    compliance = np.linalg.inv(np.array([[qxx, qxy], [qxy, qyy]]))
    ex, ey, nu_xy = 1 / compliance[0, 0], 1 / compliance[1, 1], -compliance[0, 1] / compliance[0, 0]
    g_xr, g_yr = g12 * c**2 + g23 * s**2, g12 * s**2 + g23 * c**2
    # Through-thickness Poisson ratios nu_r,hoop and nu_r,axial: a typical 0.3 of the in-plane
    # direction, scaled to the radial modulus (they barely touch a thin wall's bending).
    values = [e2, ey, ex, 0.3 * e2 / ey, 0.3 * e2 / ex, nu_xy * ey / ex, g_yr, g_xr, qss]
    return [v * PSI_PER_GPA if k not in (3, 4, 5) else v for k, v in enumerate(values)]


def axial_stations() -> np.ndarray:
    """x of the node rings, in: 0.05 in to 1 in, then growing to the tube's end."""
    fine = np.linspace(0.0, 1.0, 21)
    coarse = 1.0 + (HALF_LENGTH - 1.0) * (np.geomspace(1.0, 9.0, 12) - 1.0) / 8.0
    return np.concatenate([fine, coarse[1:]])


def tube_nodes(radii: np.ndarray, first_id: int) -> tuple[np.ndarray, np.ndarray]:
    """Node ids (n_x, n_theta, n_r) and coordinates (n, 3) of a tube's grid."""
    x, theta = axial_stations(), np.linspace(0.0, 0.5 * np.pi, N_AROUND + 1)
    grid_x, grid_t, grid_r = np.meshgrid(x, theta, radii, indexing="ij")
    coords = np.stack([grid_x, grid_r * np.cos(grid_t), grid_r * np.sin(grid_t)], -1)
    ids = first_id + np.arange(grid_x.size).reshape(grid_x.shape)
    return ids, coords.reshape(-1, 3)


def hexes(ids: np.ndarray) -> np.ndarray:
    """C3D8 connectivity of a structured (i, j, k) grid with positive volume, (n, 8)."""
    a = ids[:-1, :-1, :-1]
    b, c, d = ids[1:, :-1, :-1], ids[1:, 1:, :-1], ids[:-1, 1:, :-1]
    e, f, g, h = ids[:-1, :-1, 1:], ids[1:, :-1, 1:], ids[1:, 1:, 1:], ids[:-1, 1:, 1:]
    return np.stack([a, d, c, b, e, h, g, f], -1).reshape(-1, 8)


def positive(cells: np.ndarray, coords: dict[int, np.ndarray]) -> np.ndarray:
    """Reorder hexes whose corner triad is left-handed (negative Jacobian)."""
    p = np.array([[coords[n] for n in cell] for cell in cells])
    volume = np.einsum("ci,ci->c", p[:, 1] - p[:, 0],
                       np.cross(p[:, 3] - p[:, 0], p[:, 4] - p[:, 0]))  # fmt: skip
    flipped = cells.copy()
    flipped[volume < 0] = cells[volume < 0][:, [0, 3, 2, 1, 4, 7, 6, 5]]
    return flipped


def platen(first_id: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The platen's rigid block: ids (n_phi, n_z, 2), coordinates, and its surface nodes (the
    cylinder of radius PLATEN_RADIUS about z at y = OUTER_RADIUS + PLATEN_RADIUS)."""
    phi = np.radians(np.linspace(0.0, 40.0, 21))
    z = np.linspace(0.0, 0.9, 10)
    radius = np.array([PLATEN_RADIUS, PLATEN_RADIUS - 0.1])
    gp, gz, gr = np.meshgrid(phi, z, radius, indexing="ij")
    coords = np.stack([gr * np.sin(gp), OUTER_RADIUS + PLATEN_RADIUS - gr * np.cos(gp), gz], -1)
    ids = first_id + np.arange(gp.size).reshape(gp.shape)
    return ids, coords.reshape(-1, 3), ids[:, :, 0].ravel()


def id_lines(label: str, ids: np.ndarray) -> list[str]:
    """A *NSET or *ELSET card with 16 ids a line."""
    flat = [str(int(i)) for i in np.ravel(ids)]
    return [label] + [", ".join(flat[k:k + 16]) for k in range(0, len(flat), 16)]


def wall_radii(plies: list[tuple[str, float, float]], outer: float) -> np.ndarray:
    """Node radii through a wall whose outer surface is at ``outer``, inner to outer."""
    thickness = np.array([t for _, t, _ in plies])
    return outer - thickness.sum() + np.concatenate([[0.0], np.cumsum(thickness)])


def tube_and_platen_cards(
    interference: float = 0.0, clearance: float = 0.0
) -> tuple[list[str], np.ndarray, np.ndarray, dict[int, np.ndarray], int, int]:
    """The nodes, ply elements and materials of the two walls (the insert's outer radius
    ``interference`` above the barrel's inner one) and the rigid platen ``clearance`` above the
    barrel; returns the cards, the insert's and barrel's node ids, the coordinates, and the
    platen's reference and rotation nodes."""
    barrel_r = wall_radii(BARREL, OUTER_RADIUS)
    insert_r = wall_radii(INSERT, barrel_r[0] + interference)
    insert_ids, insert_xyz = tube_nodes(insert_r, 1)
    barrel_ids, barrel_xyz = tube_nodes(barrel_r, int(insert_ids.max()) + 1)
    platen_ids, platen_xyz, platen_surface = platen(int(barrel_ids.max()) + 1)
    platen_xyz = platen_xyz + np.array([0.0, clearance, 0.0])
    ref, rot = int(platen_ids.max()) + 1, int(platen_ids.max()) + 2
    ref_xyz = np.array([[0.0, OUTER_RADIUS + PLATEN_RADIUS + clearance, 0.0]] * 2)
    all_ids = np.concatenate([insert_ids.ravel(), barrel_ids.ravel(), platen_ids.ravel(),
                              [ref, rot]])  # fmt: skip
    all_xyz = np.concatenate([insert_xyz, barrel_xyz, platen_xyz, ref_xyz])
    coords = dict(zip(all_ids.tolist(), all_xyz, strict=True))
    lines = ["*NODE"] + [f"{i}, {p[0]:.10f}, {p[1]:.10f}, {p[2]:.10f}" for i, p in coords.items()]
    lines += material_and_section_cards(insert_ids, barrel_ids, coords)
    cells = positive(hexes(platen_ids), coords)
    first = int(insert_ids.size + barrel_ids.size) * 2
    lines += ["*ELEMENT, TYPE=C3D8, ELSET=PLATEN"]
    lines += [f"{first + k}, " + ", ".join(map(str, c)) for k, c in enumerate(cells)]
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "3.0e7, 0.3",
              "*SOLID SECTION, ELSET=PLATEN, MATERIAL=STEEL"]  # rigid; ccx still wants one
    lines += platen_surface_cards(cells, first, set(platen_surface.tolist()))
    lines += id_lines("*NSET, NSET=NPLATEN", platen_ids)
    lines += [f"*RIGID BODY, ELSET=PLATEN, REF NODE={ref}, ROT NODE={rot}"]
    return lines, insert_ids, barrel_ids, coords, ref, rot


def deck(nlgeom: bool) -> str:
    """The whole .inp."""
    lines, insert_ids, barrel_ids, _, ref, rot = tube_and_platen_cards()
    lines += tie_and_symmetry_cards(insert_ids, barrel_ids)
    outer = barrel_ids[:, :, -1]
    near = outer[: np.searchsorted(axial_stations(), 1.3), : N_AROUND // 2 + 1]
    lines += id_lines("*NSET, NSET=SLAVE", near)
    lines += ["*SURFACE, NAME=SSLAVE, TYPE=NODE", "SLAVE",
              "*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
              "1.0e9, 1.0", "*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE",
              "SSLAVE, SPLATEN", "*NSET, NSET=NREF", f"{ref}",
              "*STEP" + (", NLGEOM" if nlgeom else "") + ", INC=200",
              "*STATIC, DIRECT", f"{1.0 / N_INCREMENTS:.12f}, 1.0",
              "*BOUNDARY", f"{ref}, 1, 1, 0.0", f"{ref}, 3, 3, 0.0", f"{rot}, 1, 3, 0.0",
              f"{ref}, 2, 2, {-0.5 * TRAVEL:.10f}",
              "*NODE PRINT, NSET=NREF", "RF", "*END STEP"]  # fmt: skip
    return "\n".join(lines) + "\n"


def material_and_section_cards(insert_ids: np.ndarray, barrel_ids: np.ndarray,
                               coords: dict[int, np.ndarray]) -> list[str]:  # fmt: skip
    """C3D8I elements of each ply with its braid's orthotropic material (cylindrical axes)."""
    lines = ["*ORIENTATION, NAME=CYL, SYSTEM=CYLINDRICAL", "0., 0., 0., 1., 0., 0."]
    element = 1
    for wall, ids, plies in (("I", insert_ids, INSERT), ("B", barrel_ids, BARREL)):
        for k, (material, _, angle) in enumerate(plies):
            cells = positive(hexes(ids[:, :, k:k + 2]), coords)
            name = f"{wall}{k}"
            lines += [f"*ELEMENT, TYPE=C3D8I, ELSET=E{name}"]
            lines += [f"{element + j}, " + ", ".join(map(str, c)) for j, c in enumerate(cells)]
            element += len(cells)
            constants = braid_constants(material, angle)
            lines += [f"*MATERIAL, NAME=M{name}", "*ELASTIC, TYPE=ENGINEERING CONSTANTS",
                      ", ".join(f"{v:.6e}" for v in constants[:8]), f"{constants[8]:.6e}, 0.0",
                      f"*SOLID SECTION, ELSET=E{name}, MATERIAL=M{name}, ORIENTATION=CYL"]
    return lines


def platen_surface_cards(cells: np.ndarray, first: int, surface: set[int]) -> list[str]:
    """*SURFACE of the platen faces whose four nodes lie on the cylinder (C3D8 face numbers)."""
    faces = {1: [0, 1, 2, 3], 2: [4, 5, 6, 7], 3: [0, 1, 5, 4], 4: [1, 2, 6, 5], 5: [2, 3, 7, 6],
             6: [3, 0, 4, 7]}  # fmt: skip
    lines = ["*SURFACE, NAME=SPLATEN, TYPE=ELEMENT"]
    for k, cell in enumerate(cells):
        for face, corners in faces.items():
            if all(int(cell[c]) in surface for c in corners):
                lines.append(f"{first + k}, S{face}")
    return lines


def tie_and_symmetry_cards(insert_ids: np.ndarray, barrel_ids: np.ndarray) -> list[str]:
    """Radial tie of the insert's outer to the barrel's inner nodes; symmetry planes x = 0,
    z = 0 (theta = 0) and y = 0 (theta = 90 deg). Tied nodes carry the cylindrical transform
    (local 1 radial, 2 hoop, 3 axial), so their symmetry conditions name local dofs."""
    outer_insert, inner_barrel = insert_ids[:, :, -1], barrel_ids[:, :, 0]
    tied = np.concatenate([outer_insert.ravel(), inner_barrel.ravel()])
    lines = id_lines("*NSET, NSET=TIED", tied)
    lines += ["*TRANSFORM, NSET=TIED, TYPE=C", "0., 0., 0., 1., 0., 0.", "*EQUATION"]
    for a, b in zip(inner_barrel.ravel(), outer_insert.ravel(), strict=True):
        lines += ["2", f"{a}, 1, 1.0, {b}, 1, -1.0"]
    tied_set = set(tied.tolist())
    lines.append("*BOUNDARY")
    for ids in (insert_ids, barrel_ids):
        for node in ids[0].ravel():  # x = 0
            lines.append(f"{node}, 3, 3, 0.0" if node in tied_set else f"{node}, 1, 1, 0.0")
        for node in np.concatenate([ids[:, 0].ravel(), ids[:, -1].ravel()]):
            if node in tied_set:
                lines.append(f"{node}, 2, 2, 0.0")  # hoop = z at theta 0, -y at theta 90 deg
        lines += [f"{n}, 3, 3, 0.0" for n in ids[:, 0].ravel() if n not in tied_set]
        lines += [f"{n}, 2, 2, 0.0" for n in ids[:, -1].ravel() if n not in tied_set]
    return lines


def platen_forces(dat: str) -> np.ndarray:
    """The reference node's y reaction at each increment, times 4 (the symmetry), lbf."""
    pattern = r"forces \(fx,fy,fz\) for set NREF and time\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)"
    blocks = re.findall(pattern, dat)
    return np.array([4.0 * abs(float(b[3])) for b in blocks])


def run(folder: Path, nlgeom: bool) -> np.ndarray:
    """Write and run one deck; the platen force at each increment, lbf."""
    name = "nlgeom" if nlgeom else "linear"
    (folder / f"{name}.inp").write_text(deck(nlgeom))
    ccx = shutil.which("ccx")
    if ccx is None:
        raise SystemExit("ccx is not on PATH")
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    subprocess.run([ccx, "-i", name], cwd=folder, env=env, check=True, capture_output=True)
    return platen_forces((folder / f"{name}.dat").read_text())


def main() -> None:
    """Both runs; the curves and Table 2's pair (F(0.02), F(0.07) - F(0.02)) of each."""
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else "ccx_barrel")
    folder.mkdir(parents=True, exist_ok=True)
    travel = TRAVEL * np.arange(1, N_INCREMENTS + 1) / N_INCREMENTS
    for nlgeom in (False, True):
        force = run(folder, nlgeom)
        at = {t: float(np.interp(t, travel, force)) for t in (0.02, 0.07)}
        print(("NLGEOM" if nlgeom else "linear") + " force (lbf) at " +
              ", ".join(f"{t:.2f}: {f:.1f}" for t, f in zip(travel, force, strict=False)))
        preload, final = at[0.02], at[0.07] - at[0.02]
        print(f"  preload {preload:.1f} lbf, final {final:.1f} lbf, ratio {final / preload:.3f}")


if __name__ == "__main__":
    main()
