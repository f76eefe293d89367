"""CCOR and dynamic stiffness of the seed study's two balls at both lab speeds, with a plot of
the force-time curves (ASTM F2845: the ball fired at the 2.63-in rigid half-cylinder).

    python examples/ccor_and_plot.py          # 8-division balls: about a minute
    BATBALL_EXAMPLE_TINY=1 python examples/ccor_and_plot.py   # the test suite's coarse run

Writes ``ccor_force_time.png`` in the current folder; the runs are stored in ``runs/``.
"""

import os

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt

import batball

divisions = 2 if os.environ.get("BATBALL_EXAMPLE_TINY") else 8  # 12 is the seed's full mesh

fig, ax = plt.subplots(figsize=(7, 4))
for ball in ("type1", "type2"):
    for speed in ("95 mph", "110 mph"):
        r = batball.ccor(ball, speed=speed, divisions=divisions)
        s = r.summary
        print(f"{ball} at {speed}: CCOR {s['ccor']:.3f}, DS {s['ds_lbf_per_in']:.0f} lbf/in, "
              f"peak {s['peak_force_lbf']:.0f} lbf, contact {s['contact_time_ms']:.2f} ms")
        h = r.history
        ax.plot(h["time_ms"], h["contact_force_lbf"], label=f"{ball}, {speed}")
ax.set_xlabel("time (ms)")
ax.set_ylabel("contact force (lbf)")
ax.set_title(f"CCOR test, {divisions}-division balls")
ax.legend()
fig.savefig("ccor_force_time.png", dpi=120, bbox_inches="tight")
print("wrote ccor_force_time.png")
