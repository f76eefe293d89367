"""What ``batball reproduce`` runs on: the mesh sizes, the options, the inputs every runner
shares, and how a runner runs a lab test through the registry (:func:`lab_run`).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from batball.errors import SpecError
from batball.report.runs import ReportFigure, TestRun
from batball.results.store import check_output_folder, load_cached_summary
from batball.specs import BallSpec, BatSpec
from batball.units import IN


@dataclass(frozen=True)
class MeshSizes:
    """Mesh density of every test: ball divisions (12 = the seed's 12,096 hexes), bat shells."""

    ball_divisions: int
    bat_circumferential: int
    bat_axial_size: float  # m
    #: the barrel compression's static contact solve is the costliest bat test: its own mesh
    barrel_circumferential: int = 16
    barrel_axial_size: float = 0.4 * IN  # m
    #: batted-ball speed (coupled runs): ball divisions, bat shells around, axial size [m]
    bbs: tuple[int, int, float] = (4, 16, 0.5 * IN)
    #: the meshes the model of record was fitted and checked on: only these get verdicts
    converged: bool = False


#: The full-size meshes: the seed's 12,096-hex ball (the mesh the balls were fitted on); the bat
#: mesh of ``batball props``/``modal``/``barrel``, 48 x 0.1 in (on 32 x 0.2 in the barrel test's
#: loads are 6-10 % stiff, docs/notes/barrel.md), also for the batted-ball speed (on 32 x 0.2 in
#: the seed's type-1 ball's BBS is 0.7 mph lower, docs/fidelity.md).
FULL_MESHES = MeshSizes(
    ball_divisions=12,
    bat_circumferential=48,
    bat_axial_size=0.1 * IN,
    barrel_circumferential=48,
    barrel_axial_size=0.1 * IN,
    bbs=(12, 48, 0.1 * IN),
    converged=True,
)


#: ``--quick``: coarse meshes for CI and a first look (1,512 hexes per ball, 2,832 bat shells;
#: 1,512 hexes on 16 x 0.5 in shells for the batted-ball speed). Its values are indicative.
QUICK_MESHES = MeshSizes(ball_divisions=6, bat_circumferential=16, bat_axial_size=0.25 * IN,
                         bbs=(6, 16, 0.5 * IN))  # fmt: skip


#: The solver check's ball numerics: the hourglass control with which the seed's Table 4 balls
#: reproduce its LS-DYNA Tables 5-8 (docs/notes/ball-impact.md).
CHECK_NUMERICS: dict[str, Any] = {"hourglass_type": 4, "hourglass_coefficient": 0.01}

#: The solver check's bat element in the batted-ball speed: the seed's LS-DYNA model's
#: one-point Belytschko-Tsay shells (ELFORM 2), so that the check compares like with like; the
#: model of record runs the test's default, the MITC4 shells.
CHECK_BAT_SHELL = "bt"


#: The compression test's contact scale SFS for a foam ball (``batball compression --sfs``).
FOAM_SFS = 5.0


def log_to_stderr(message: str) -> None:
    """Progress line on stderr."""
    print(f"[reproduce] {message}", file=sys.stderr, flush=True)


@dataclass(frozen=True)
class ReproduceOptions:
    """What to run and where.

    Attributes:
        out_dir: the report folder (created).
        runs_dir: the run store; runs with unchanged inputs are reused from it.
        meshes: mesh sizes (:data:`FULL_MESHES` or :data:`QUICK_MESHES`).
        reuse: reuse stored runs (False reruns everything).
        balls, bat: the model of record (embedded names or spec files; each ball's spec names
            the seed ball type it models).
        check_balls, check_bat: the solver check's (the seed's Table 4 balls, the reconstructed
            bat).
        log: progress sink.
        command: the command line, as the report states it.
        calibrate: also refit both seed balls with MAT_006 (``--calibrate``; a refit section).
        workers: the calibration's local process pool (None: CPU cores; 0: this process).
        ensemble: the folder of a ``batball ensemble`` run whose Table 9 intervals the report
            shows beside the tables (None: no interval section).
    """

    out_dir: Path
    runs_dir: Path
    meshes: MeshSizes = FULL_MESHES
    reuse: bool = True
    balls: tuple[str, ...] = ("type1-fit", "type2-fit")
    bat: str = "fitted"
    check_balls: tuple[str, ...] = ("type1", "type2")
    check_bat: str = "default"
    log: Callable[[str], None] = log_to_stderr
    command: str = "batball reproduce"
    calibrate: bool = False
    workers: int | None = None
    ensemble: Path | None = None

    def __post_init__(self) -> None:
        """The output folders checked before anything runs (a file in their place is named),
        and the ensemble's summary."""
        check_output_folder("out", self.out_dir)
        check_output_folder("runs-dir", self.runs_dir)
        if self.ensemble is not None:
            check_ensemble_folder(Path(self.ensemble))


def check_ensemble_folder(folder: Path) -> None:
    """Refuse a folder without a finished ``batball ensemble`` run's ``summary.json``."""
    import json

    allowed = "the folder of a finished batball ensemble run (its summary.json with study, "
    try:
        summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        raise SpecError("ensemble", str(folder), allowed + "cells and trends)") from None
    missing = [k for k in ("study", "cells", "trends", "bats", "balls", "members")
               if not isinstance(summary, dict) or k not in summary]  # fmt: skip
    if missing:
        raise SpecError("ensemble", str(folder), allowed + f"cells and trends; it lacks "
                        f"{', '.join(missing)})")  # fmt: skip


@dataclass(frozen=True)
class RunnerOutput:
    """What a runner returns: its runs and any figures drawn from several of them."""

    runs: tuple[TestRun, ...]
    figures: tuple[ReportFigure, ...] = ()


@dataclass(frozen=True)
class Inputs:
    """The specs every runner shares (loaded once) and the options."""

    options: ReproduceOptions
    balls: tuple[BallSpec, ...]
    bat: BatSpec
    check_balls: tuple[BallSpec, ...] = ()
    check_bat: BatSpec | None = None

    @property
    def figures_dir(self) -> Path:
        return self.options.out_dir / "figures"


class NotYetAvailableError(Exception):
    """A registered test whose code is not in this installation yet; the message says why."""


class SkippedError(NotYetAvailableError):
    """A test left out of this invocation by its options; the message says how to include it."""


Runner = Callable[[Inputs], RunnerOutput]


def timed_run(
    inputs: Inputs, label: str, call: Callable[[], tuple[dict[str, Any], Path]]
) -> tuple[dict[str, Any], Path, bool, float]:
    """Call a ``run_*_test``; returns its summary, folder, whether it was reused and the seconds.

    A run counts as reused when its folder held a complete summary before the call.
    """
    runs_dir = inputs.options.runs_dir
    stored = (
        {p.parent.name for p in runs_dir.glob("*/summary.json")} if runs_dir.is_dir() else set()
    )
    inputs.options.log(f"{label} ...")
    start = time.perf_counter()
    summary, folder = call()
    seconds = time.perf_counter() - start
    reused = (
        inputs.options.reuse and folder.name in stored and load_cached_summary(folder) is not None
    )
    inputs.options.log(f"{label}: {'reused' if reused else 'ran'} in {seconds:.1f} s ({folder})")
    return summary, folder, reused, seconds


def lab_run(
    inputs: Inputs, label: str, name: str, subjects: dict[str, Any], **options: Any
) -> tuple[dict[str, Any], Path, bool, float]:
    """Run (or reuse) the registry's test ``name`` with ``options`` (SI lengths as metres,
    :func:`metres`), timed as :func:`timed_run` times it: the same run ``batball <name>`` makes
    with those options. A test whose modules are not in this installation is not yet available.
    """
    from batball.lab.registry import LAB_TESTS

    test = LAB_TESTS[name]
    setup = test.setup(**options)
    try:
        return timed_run(
            inputs, label,
            lambda: test.execute(subjects, setup, runs_dir=inputs.options.runs_dir,
                             reuse=inputs.options.reuse, progress=None),
        )  # fmt: skip
    except ModuleNotFoundError as exc:
        reason = f"the {name} test is not in this installation ({exc})"
        raise NotYetAvailableError(reason) from exc


def metres(value: float) -> Any:
    """A length in metres as a quantity, for a registry option (which takes no bare number)."""
    from batball.units import unit_registry

    return unit_registry().Quantity(value, "m")
