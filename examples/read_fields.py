"""Read a CCOR run's fields back in Python: the ball's von Mises stress at the instant of peak
contact force, as a plot over the ball's cross-section, and the contact pressure under it.

    python examples/read_fields.py                 # 8-division ball
    BATBALL_EXAMPLE_TINY=1 python examples/read_fields.py   # the test suite's coarse run

Writes ``ball_stress.png``. The same series open in ParaView (``fields.pvd`` and ``target.pvd``
in the run folder, *Warp By Vector* with ``displacement``) or in PyVista
(``pyvista.get_reader("fields.pvd")``).
"""

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import batball

divisions = 3 if os.environ.get("BATBALL_EXAMPLE_TINY") else 8
r = batball.ccor("type1", speed="110 mph", divisions=divisions)
ball = batball.read_fields(r, deformed=True)["fields"]

force = ball.point_field("contact_force")[:, :, 2].sum(axis=1)  # N, along the flight line
peak = int(np.abs(force).argmax())
mesh = ball.meshes[peak]
von_mises = ball.cell_field("von_mises")[peak]  # Pa, one per hex
pressure = ball.point_field("contact_pressure")[peak]  # Pa, one per surface node
print(f"frame {peak} at {ball.times[peak] * 1e3:.3f} ms: contact force {abs(force[peak]):.0f} N,"
      f" largest von Mises {von_mises.max() / 1e6:.2f} MPa,"
      f" largest contact pressure {pressure.max() / 1e6:.2f} MPa")

# the hexes' centres in the deformed place, the slice through the ball's middle (|x| small)
cells = mesh.cells_dict["hexahedron"]
centres = mesh.points[cells].mean(axis=1)
middle = np.abs(centres[:, 0]) < 0.5 * np.ptp(centres[:, 0]) / divisions
fig, ax = plt.subplots(figsize=(5, 5))
shown = ax.scatter(centres[middle, 1] * 1e3, centres[middle, 2] * 1e3,
                   c=von_mises[middle] / 1e6, s=40, cmap="viridis")
fig.colorbar(shown, ax=ax, label="von Mises stress (MPa)")
ax.set_xlabel("y (mm)")
ax.set_ylabel("z (mm), the flight line")
ax.set_aspect("equal")
ax.set_title(f"type1 at 110 mph, {ball.times[peak] * 1e3:.2f} ms")
fig.savefig("ball_stress.png", dpi=120, bbox_inches="tight")
print("wrote ball_stress.png")
