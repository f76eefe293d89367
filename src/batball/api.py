"""The Python API: the command line's virtual tests as functions, re-exported by ``batball``.

Each test of the lab registry is one function named as its subcommand, taking its options as
keyword arguments with the same names and defaults (``--axial-size`` is ``axial_size``)::

    import batball

    r = batball.ccor("type1", speed="95 mph", divisions=6)
    r.summary["ccor"], r.summary["ds_lbf_per_in"]   # what ``batball ccor --json`` prints
    r.history                                       # pandas DataFrame, units in column names
    r.plot()                                        # a matplotlib Figure

A dimensioned option takes text with its unit (``"95 mph"``) or a pint quantity; a bare number is
an error naming the option, as is an option the test does not have. Every option is checked
before anything runs. Runs go to the results store (``runs/`` unless ``runs_dir`` says otherwise)
and a run with the same inputs is reused unless ``reuse=False``. :func:`read_fields` reads a run's
field frames (what ParaView shows) back as meshio meshes.
"""

from __future__ import annotations

import html
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from batball.errors import SpecError
from batball.lab.protocol import LabTest
from batball.lab.registry import LAB_TESTS, SUBJECT_DEFAULTS, load_subject
from batball.results.fields import FieldSeries
from batball.results.fields import read_fields as read_field_files
from batball.specs import BallSpec, BatSpec


def load_ball(ball: str | Path | BallSpec) -> BallSpec:
    """A ball spec: an embedded ball by name (``"type1"``, ``"type2"``: the seed's;
    ``"type1-fit"``, ``"type2-fit"``: the model of record's; ``"foam057"``, ``"foam083"``), a
    ball TOML file by path, or a spec already loaded (returned as it is)."""
    return load_subject("ball", ball)


def load_bat(bat: str | Path | BatSpec) -> BatSpec:
    """A bat spec: an embedded bat (``"default"``: the reconstruction of the seed's;
    ``"fitted"``: the model of record's), a bat TOML file by path, or a spec already loaded
    (returned as it is)."""
    return load_subject("bat", bat)


@dataclass(frozen=True)
class Result:
    """A finished (or reused) virtual test.

    Attributes:
        test: the test's name (``"ccor"``).
        summary: what ``--json`` prints; each number's unit is in its key.
        run_dir: the run folder in the results store.
        history_file: the run folder's history or curve file, None for a test without one.
    """

    test: str
    summary: dict[str, Any]
    run_dir: Path
    history_file: str | None = None

    @property
    def history(self) -> Any:
        """The run's history (or measured curve) as a pandas DataFrame, units in the column
        names (``time_ms``, ``contact_force_lbf``); empty for a test that writes none."""
        import pandas as pd

        if self.history_file is None:
            return pd.DataFrame()
        return pd.read_csv(self.run_dir / self.history_file)

    def plot(self) -> Any:
        """The measured force against the history's first column, as a new matplotlib Figure.

        Made without pyplot, so the caller's backend is left as it was; in a notebook the
        Figure displays itself, elsewhere ``fig.savefig(path)`` writes it.
        """
        from batball.results.plots import new_figure

        history = self.history
        forces = [c for c in history.columns if "force" in c]
        if history.empty or not forces:
            raise ValueError(f"{self.test} writes no force history to plot")
        x = history.columns[0]
        fig, ax = new_figure(figsize=(6.4, 4.0))
        ax.plot(history[x], history[forces[0]], lw=1.2)
        ax.set_xlabel(_axis_label(x))
        ax.set_ylabel(_axis_label(forces[0]))
        ax.set_title(f"{self.test} of {self.summary.get('ball', self.summary.get('bat', ''))}")
        ax.grid(alpha=0.3)
        fig.tight_layout()
        return fig

    def __repr__(self) -> str:
        return f"Result(test={self.test!r}, run_dir={self.run_dir.as_posix()!r})"

    def _repr_html_(self) -> str:
        rows = "".join(
            f"<tr><td>{html.escape(str(k))}</td><td>{html.escape(_cell(v))}</td></tr>"
            for k, v in self.summary.items()
            if isinstance(v, str | int | float | bool) or v is None
        )
        folder = html.escape(self.run_dir.as_posix())
        return f"<b>batball {html.escape(self.test)}</b> <code>{folder}</code><table>{rows}</table>"


def read_fields(run: Result | str | Path, *, deformed: bool = False) -> dict[str, FieldSeries]:
    """The field time series of a run, read back with meshio: by name (the ``.pvd`` file's
    stem), a :class:`~batball.results.fields.FieldSeries` of the frame times [s] and one
    ``meshio.Mesh`` per frame, SI throughout.

    A ball test (ccor, cor, compression) has ``"fields"`` (the ball's hexes; point data
    ``displacement`` m, ``velocity`` m/s, ``contact_force`` N, ``contact_pressure`` Pa; cell data
    ``stress`` (xx, yy, zz, xy, yz, zx), ``von_mises``, ``pressure`` Pa and
    ``volumetric_strain`` ln(V/V0)) and ``"target"`` (the rigid target's surface); a bbs run
    has ``"ball"`` (the same fields) and ``"bat"`` (the shell mid-surface: ``displacement``,
    ``velocity``, ``angular_velocity``, ``contact_force``; with ``shell="bt"`` cell data
    ``von_mises``, the largest over the plies: the default MITC4 shells keep no ply stresses).
    :mod:`batball.solvers.frames` defines each field.

    Args:
        run: a :class:`Result`, a run folder or one ``.pvd`` file.
        deformed: points in the deformed place (reference plus displacement) rather than the
            reference.

    Example:
        >>> r = batball.ccor("type1", divisions=4)                   # doctest: +SKIP
        >>> series = batball.read_fields(r)["fields"]                 # doctest: +SKIP
        >>> series.cell_field("von_mises").shape       # (n_frames, n_cells)  # doctest: +SKIP
        >>> mesh = series.meshes[-1]                   # a meshio.Mesh  # doctest: +SKIP

    Raises:
        FileNotFoundError: no such run folder or file, or no field series in it.
    """
    source = run.run_dir if isinstance(run, Result) else Path(run)
    return read_field_files(source, deformed=deformed)


def _axis_label(column: str) -> str:
    """``contact_force_lbf`` -> ``contact force (lbf)``."""
    name, _, unit = column.rpartition("_")
    return f"{name.replace('_', ' ')} ({unit})" if name else column


def _cell(value: Any) -> str:
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def run_test(
    name: str,
    *,
    runs_dir: str | Path = "runs",
    reuse: bool = True,
    progress: Callable[[float], None] | None = None,
    **arguments: Any,
) -> Result:
    """Run (or reuse) the virtual test ``name`` of the lab registry.

    Args:
        name: ``"ccor"``, ``"cor"``, ``"compression"``, ``"props"``, ``"modal"``, ``"barrel"``
            or ``"bbs"``.
        runs_dir: the results store.
        reuse: reuse a stored run with the same inputs.
        progress: called with the simulated time [s] as the run goes (ccor, cor and
            compression; the other tests do not report it).
        arguments: the subjects (``ball``, ``bat``: names, paths or specs) and the test's
            options by name.

    Raises:
        SpecError: an unknown test or option, or a value that is not allowed (checked before
            anything runs).
        SimulationError: a numerical failure during the run.
    """
    if name not in LAB_TESTS:
        raise SpecError("test", name, "one of " + ", ".join(LAB_TESTS))
    test = LAB_TESTS[name]
    given = {kind: arguments.pop(kind, SUBJECT_DEFAULTS[kind]) for kind in test.subjects}
    setup = test.setup(**arguments)
    subjects = {kind: load_subject(kind, value) for kind, value in given.items()}
    summary, folder = test.execute(subjects, setup, runs_dir=Path(runs_dir), reuse=reuse,
                               progress=progress)  # fmt: skip
    return Result(test=name, summary=summary, run_dir=folder, history_file=test.history)


def _test_function(test: LabTest) -> Callable[..., Result]:
    """The API function of a registry entry: its subjects first, then its options."""
    subjects = test.subjects

    def run(*given: Any, **arguments: Any) -> Result:
        if len(given) > len(subjects):
            raise TypeError(f"{test.name}() takes the {' and '.join(subjects)} positionally, "
                            "its options by name")  # fmt: skip
        return run_test(test.name, **dict(zip(subjects, given, strict=False)), **arguments)

    options = "\n".join(f"        {o.name}: {o.help_line}" for o in test.options)
    named = ", ".join(f"{k}={SUBJECT_DEFAULTS[k]!r}" for k in subjects)
    run.__name__ = run.__qualname__ = test.name
    run.__doc__ = (f"{test.help[0].upper()}{test.help[1:]}.\n\n"
                   f"    ``batball.{test.name}({named}, **options)``; the subjects are names, "
                   "paths or loaded specs.\n\n"
                   f"    Options (as ``batball {test.name} --help``):\n{options}\n"
                   "        runs_dir, reuse, progress: as :func:`batball.api.run_test`.\n\n"
                   "    Returns:\n        A :class:`Result`.\n")  # fmt: skip
    return run


ccor = _test_function(LAB_TESTS["ccor"])
cor = _test_function(LAB_TESTS["cor"])
compression = _test_function(LAB_TESTS["compression"])
props = _test_function(LAB_TESTS["props"])
modal = _test_function(LAB_TESTS["modal"])
barrel = _test_function(LAB_TESTS["barrel"])
bbs = _test_function(LAB_TESTS["bbs"])
