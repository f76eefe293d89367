"""Figures a person reads: every axis names its unit."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from batball.io.store import atomic_path

LBF = 4.4482216152605  # N


def plot_force_time(
    path: Path, time: np.ndarray, force: np.ndarray, *, title: str, threshold: float | None = None
) -> None:
    """Load-cell force against time, in ms and lbf, written atomically as PNG.

    Args:
        time: (n,) [s]; force: (n,) [N]; threshold: the contact-time level [N], drawn if given.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=120)
    ax.plot(time * 1e3, force / LBF, lw=1.2, color="tab:blue", label="load cell")
    if threshold is not None:
        ax.axhline(threshold / LBF, color="0.6", lw=0.8, ls="--", label="contact-time level")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("force (lbf)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp)
    plt.close(fig)
