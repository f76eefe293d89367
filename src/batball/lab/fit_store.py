"""The explicit tests' stored interference fit (LS-DYNA's ``drdisp.sif``).

The BBS test and the explicit barrel test press the insert into the barrel by dynamic
relaxation (:func:`batball.solvers.ball_bat.relax_fit`) before they start; on the full-size bat
that is about a third of a BBS run (16 of 46 s, docs/notes/bbs.md "Runtime"). As LS-DYNA writes the
relaxed state to ``drdisp.sif`` and later runs start from it, the relaxed state is stored in
``<runs>/fit-<hash>/`` (``fit.npz``, then ``summary.json``, both atomic) and reused by every
later run of the same bat model: the eight runs of Table 9 relax the fit once.

The key is a digest of what the relaxation does, taken from the arrays themselves (nodes,
cells, lumped masses, laminate, held nodes, the pairs' stiffnesses and overlaps) and its
controls (interference, cycles, damping factor, step, hourglass ratio), so a change anywhere
in the bat's model (a mass-scaling target set by a different ball, a mesh option, a ply)
relaxes anew; the ball itself is not in the key, since the relaxation never moves it.

What is stored is the bat's whole state after the relaxation: its nodes, the shells' state
(the BT kernel's stress history, hourglass resultants included, or the co-rotational MITC4
shells' nodal rotations) and each insert pair's offsets and
walking state. Velocities are zero after a relaxation. A restored run reproduces a fresh one to
the last digit (tests/unit/lab/test_fit_store.py).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from batball.contact.columns import ColumnContact
from batball.contact.segments import SegmentContact
from batball.elements.shell_bt import ShellForceState
from batball.elements.shell_corotational import CorotationalState
from batball.results.store import (
    arrays_digest,
    load_stored_arrays,
    run_folder,
    write_arrays_atomic,
    write_summary,
)
from batball.solvers.ball_bat import BatPart
from batball.version import __version__

FIT_FILE = "fit.npz"
Pair = SegmentContact | ColumnContact
#: The shells' state: the BT stresses, or the co-rotational MITC4 shells' nodal rotations.
ShellState = ShellForceState | CorotationalState


@dataclass(frozen=True)
class FitRelaxation:
    """How the fit is relaxed (the controls of :func:`~batball.solvers.ball_bat.relax_fit`)."""

    interference: float  # [m]
    ramp_steps: int
    settle_steps: int
    search_interval: int
    dt: float  # [s]
    factor: float
    hourglass_ratio: float
    shell: str = "bt"  # the shell element ("bt" or "mitc4", lab.barrel_explicit.SHELLS)


def fit_inputs(bat: BatPart, reference: np.ndarray, pairs: Sequence[Pair], moving: np.ndarray,
               relaxation: FitRelaxation) -> dict[str, object]:  # fmt: skip
    """The store key of a relaxation of ``pairs`` on ``bat`` (undeformed nodes ``reference``,
    ``moving`` the nodes it may move): a digest of the arrays and the controls."""
    sec = bat.section
    arrays = [reference, bat.cells, bat.mass, moving, sec.cell_laminate, sec.layer_stiffness,
              sec.layer_z, sec.layer_thickness, sec.shear, sec.hourglass_moduli]  # fmt: skip
    for pair in pairs:
        arrays += [pair.slave_nodes, pair.slave_stiffness, pair.slave_thickness, pair.gap_offset]
    return {"model": arrays_digest(*arrays), "relaxation": relaxation.__dict__,
            "batball": __version__}  # fmt: skip


def pair_state(pair: Pair) -> dict[str, np.ndarray]:
    """What a relaxation changes in ``pair``: its ignored overlap and, for a column pair, where
    each slave has walked to along its column."""
    state = {"gap_offset": pair.gap_offset}
    if isinstance(pair, ColumnContact):
        state |= {"ring": pair.ring, "weight_b": pair.weight_b}
    return state


def live_fit_arrays(points: np.ndarray, shell_state: ShellState,
                    pairs: Sequence[Pair]) -> dict[str, np.ndarray]:  # fmt: skip
    """The arrays that hold the relaxed state, by name (the arrays themselves, not copies):
    ``points`` are the bat's nodes (n_bat, 3)."""
    arrays = {"points": points, "shell_history": shell_state.history}
    for i, pair in enumerate(pairs):
        arrays |= {f"pair{i}_{name}": a for name, a in pair_state(pair).items()}
    return arrays


def capture_fit(points: np.ndarray, shell_state: ShellState,
                pairs: Sequence[Pair]) -> dict[str, np.ndarray]:  # fmt: skip
    """The relaxed state as named arrays (copies of :func:`live_fit_arrays`)."""
    return {k: a.copy() for k, a in live_fit_arrays(points, shell_state, pairs).items()}


def restore_fit(arrays: dict[str, np.ndarray], points: np.ndarray,
                shell_state: ShellState, pairs: Sequence[Pair]) -> bool:  # fmt: skip
    """Put a captured state back in place; False (nothing changed) if it does not fit."""
    wanted = live_fit_arrays(points, shell_state, pairs)
    if set(arrays) != set(wanted) or any(arrays[k].shape != a.shape or arrays[k].dtype != a.dtype
                                         for k, a in wanted.items()):  # fmt: skip
        return False
    for key, target in wanted.items():
        target[...] = arrays[key]
    return True


def obtain_fit(store: Path | None, inputs: dict[str, object], relax: Callable[[], float],
               points: np.ndarray, shell_state: ShellState, pairs: Sequence[Pair], *,
               reuse: bool = True) -> tuple[float, bool]:  # fmt: skip
    """The relaxed fit in place: restored from ``store``'s folder for ``inputs`` when ``reuse``
    and it is there and fits, else ``relax()`` (which relaxes in place and returns the kinetic
    energy ratio) and stored. ``store`` None: relax, store nothing.

    Returns:
        (the relaxation's final over peak kinetic energy, whether it was restored).
    """
    folder = run_folder(store, "fit", inputs) if store is not None else None
    if folder is not None and reuse:
        arrays = load_stored_arrays(folder, FIT_FILE)
        if arrays is not None:
            stored = arrays.pop("kinetic_ratio", None)
            if stored is not None and restore_fit(arrays, points, shell_state, pairs):
                return float(stored), True
    start = time.perf_counter()
    ratio = relax()
    if folder is not None:
        arrays = capture_fit(points, shell_state, pairs)
        arrays["kinetic_ratio"] = np.array(ratio)
        write_arrays_atomic(folder / FIT_FILE, arrays)
        write_summary(folder, {"test": "fit", "kinetic_ratio": ratio,
                               "wall_seconds": time.perf_counter() - start})  # fmt: skip
    return ratio, False
