"""A league ball from its stamp: a MAT_006 ball fitted to a stamped COR and compression.

Softballs are sold stamped with two numbers, e.g. ``.44 / 375``: the COR on a rigid flat wall at
60 mph (ASTM F1887) and the force at 0.25 in between flat plates (ASTM F1888), 375 lbf. Two
numbers fix two material constants, so each league ball starts from a *prior* MAT_006 ball (the
seed's type 1 or type 2): its size, mass, bulk modulus and the constant not fitted are the
prior's, and :func:`batball.calibrate.command.run_calibration` fits :data:`LEAGUE_FREE` to the
stamp. The priors give different balls that all meet the stamp; their spread is what the stamp
leaves open, and a bat design study carries it into its BBS responses.

Which two constants (:data:`LEAGUE_FREE`): the compression is quasi-static (15 s to 0.25 in
at 1 in/min against relaxation times 1/beta of some 15 us), so it sees only the relaxed moduli,
the bulk modulus K (the prior's) and the long-time shear modulus G_inf (relaxed Hertz, E* of K and
G_inf): G_inf carries the compression. The 60-mph COR is set by the Maxwell branch in a ~1 ms
contact, whose loss grows with its viscosity (G0 - G_inf) / beta while 1/beta is short against
the contact. With G_inf fitted, that branch is best moved by ``g0``: G0 reaches down to the
elastic ball (G0 -> G_inf, the least loss) and up to a stiff lossy branch, whereas beta's effect
peaks where 1/beta nears the contact time and is bounded on either side, and raising G_inf for
the compression shrinks the branch beta has to work with. Measured on the 4-division mesh
(stamp .44 / 375, the default budget, runs counted as COR + compression runs until one
candidate met both to 1 %): (``g_inf``, ``g0``) met it for type 1 after 40 runs and for type 2
after 38; (``g_inf``, ``beta``) met it for type 1 after 28 but not for type 2 in 64 (COR
+1.6 %, compression -27 %, beta pinned low). On the 2-division mesh (56 hexes) neither pair
meets the stamp: even an elastic ball (G0 = G_inf) rebounds at COR 0.36-0.39 there, its energy
lost to the coarse mesh's vibration.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from batball.calibrate.optimise import OptimiserOptions
from batball.calibrate.targets import Target
from batball.errors import SimulationError, SpecError
from batball.specs import BallSpec
from batball.specs.ball import load_ball_spec
from batball.specs.document import check_name
from batball.units import LBF, MPH, format_quantity, parse_quantity

#: The MAT_006 constants fitted to a stamp (the others are the prior's); see the module docstring.
LEAGUE_FREE: tuple[str, str] = ("g_inf", "g0")

#: The stamp's COR speed: ASTM F1887, a rigid flat wall at 60 mph [m/s].
STAMP_SPEED = 60.0 * MPH

_STAMP = re.compile(r"^\s*(\d*\.\d+|\d+)\s*/\s*(\S.*?)\s*$")
_STAMP_TEXT = 'COR / compression as stamped on the ball, e.g. ".44 / 375" or "0.44/375 lbf"'


@dataclass(frozen=True)
class LeagueBall:
    """One prior's ball that meets a stamp.

    Attributes:
        ball: the calibrated ball, named ``f"{name}-{prior}"``.
        prior: the prior ball's name (``"type1"``).
        cor: the COR on the flat wall at 60 mph the fit achieved (on the fit's mesh).
        compression: the ASTM F1888 force at 0.25 in the fit achieved [N] (the calibration's
            reading: the power law fitted over 0.15-0.25 in, on at most 8 divisions).
        residuals: ``{"cor": r, "compression": r}``, each (achieved - stamp) / (stamp * goal),
            the goals of :data:`batball.calibrate.targets.QUANTITIES` (COR 1 %, compression 5 %).
        study: the calibration's SQLite study file (a second call resumes it).
        spec_file: the ball written as a spec TOML (``load_ball_spec`` reads it back).
        runs: virtual-test runs the study holds (every candidate's COR and compression run).
    """

    ball: BallSpec
    prior: str
    cor: float
    compression: float
    residuals: Mapping[str, float]
    study: Path
    spec_file: Path
    runs: int


def parse_stamp(text: str) -> tuple[float, float]:
    """``".44 / 375"`` or ``"0.44/375 lbf"`` -> (COR, compression [N]).

    The compression is in lbf when bare, as stamped on the ball; with a unit it is any force.

    Raises:
        SpecError: naming ``stamp``, for text of another form, 0 >= COR >= 1 or a compression
            that is not a positive force.
    """
    match = _STAMP.match(text) if isinstance(text, str) else None
    if match is None:
        raise SpecError("stamp", text, _STAMP_TEXT)
    cor = float(match.group(1))
    force = match.group(2)
    if re.fullmatch(r"\d*\.?\d+", force):  # the stamp's bare number is lbf
        force += " lbf"
    compression = parse_quantity(force, "force", field="stamp")
    if not (0.0 < cor < 1.0 and compression > 0.0):
        raise SpecError("stamp", text, _STAMP_TEXT + ", 0 < COR < 1, a positive compression")
    return cor, compression


def league_targets(cor: float, compression: float) -> tuple[Target, Target]:
    """The stamp as calibration targets: the COR at 60 mph and the compression [N]."""
    return Target("cor", STAMP_SPEED, cor), Target("compression", 0.0, compression)


def default_budget(divisions: int) -> OptimiserOptions:
    """The optimiser's budget of a league fit on ``divisions``: a start and 4 Latin-hypercube
    points, then at most 12 least-squares evaluations, one mesh."""
    return OptimiserOptions(
        global_points=4, coarse_divisions=divisions, coarse_evaluations=12, fine_divisions=None
    )


def league_balls(
    name: str,
    cor: float,
    compression: float,
    *,
    priors: Sequence[str] = ("type1", "type2"),
    divisions: int,
    runs_dir: Path,
    workers: int | None = 0,
    budget: OptimiserOptions | None = None,
) -> list[LeagueBall]:
    """The balls, one per prior, that meet the stamp ``cor`` / ``compression``.

    Args:
        name: the league ball's name (the balls are ``f"{name}-{prior}"``).
        cor: the stamped COR, flat wall at 60 mph (ASTM F1887), 0 < cor < 1.
        compression: the stamped compression, force at 0.25 in (ASTM F1888) [N].
        priors: MAT_006 balls (embedded names or TOML files) whose size, mass, bulk modulus and
            unfitted constants the league balls keep.
        divisions: the ball mesh of the fit (:func:`batball.mesh.make_ball_mesh`; the
            compression runs on at most 8). Even, or 8 and above: an odd mesh below 8 puts a flat
            face at each pole, below the sphere (0.12 in at 3 divisions), and the plates' travel
            closes that gap before they squeeze the ball.
        runs_dir: where the study files ``league-{name}-{prior}.db`` and the balls'
            ``league-{name}-{prior}.toml`` are written; a second call resumes the studies.
        workers: local pool size (0: this process; None: the CPU cores).
        budget: the optimiser's options (default :func:`default_budget`); its last mesh must be
            ``divisions``.

    Raises:
        SpecError: naming the field, before anything runs: ``name``, ``cor``, ``compression``,
            ``priors``, ``divisions``, ``workers`` or ``budget``.
    """
    budget = check_league_inputs(name, cor, compression, divisions, workers, budget)
    balls = load_priors(priors)
    runs_dir = Path(runs_dir)
    return [
        fit_league_ball(name, prior, league_targets(cor, compression), budget=budget,
                        runs_dir=runs_dir, workers=workers)
        for prior in balls
    ]  # fmt: skip


def check_league_inputs(
    name: str,
    cor: float,
    compression: float,
    divisions: int,
    workers: int | None,
    budget: OptimiserOptions | None,
) -> OptimiserOptions:
    """The budget of a league fit, after every scalar input is checked (SpecError naming it)."""
    check_name("name", name)
    if not (_is_number(cor) and 0.0 < cor < 1.0):
        raise SpecError("cor", cor, "a COR 0 < cor < 1 (flat wall at 60 mph, ASTM F1887)")
    if not (_is_number(compression) and compression > 0.0):
        raise SpecError("compression", compression, "a positive force in N (375 lbf = 1668 N)")
    if isinstance(divisions, bool) or not isinstance(divisions, int) or not 2 <= divisions <= 40:
        raise SpecError("divisions", divisions, "an integer 2..40")
    if divisions < 8 and divisions % 2:
        raise SpecError("divisions", divisions, "an even mesh or 8 and above (an odd one "
                        "below 8 leaves a gap at the plates: faceted poles)")  # fmt: skip
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 0
    ):
        raise SpecError("workers", workers, "0 (this process), a positive pool size or None")
    if budget is None:
        return default_budget(divisions)
    if not isinstance(budget, OptimiserOptions):
        raise SpecError("budget", budget, "an OptimiserOptions or None")
    final = budget.fine_divisions if budget.fine_divisions is not None else budget.coarse_divisions
    if final != divisions:
        raise SpecError("budget", f"last mesh {final} divisions",
                        f"the league balls' mesh, {divisions} divisions")  # fmt: skip
    return budget


def _is_number(value: object) -> bool:
    """A finite int or float (not a bool)."""
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def load_priors(priors: Sequence[str]) -> list[BallSpec]:
    """The prior balls, each a MAT_006 ball with a distinct name (SpecError naming ``priors``)."""
    if isinstance(priors, str) or not priors:
        raise SpecError("priors", priors, "a non-empty sequence of MAT_006 balls (type1, type2)")
    balls: list[BallSpec] = []
    for prior in priors:
        try:
            ball = load_ball_spec(prior)
        except SpecError as exc:
            raise SpecError("priors", prior, f"a MAT_006 ball: type1, type2 or a TOML file "
                            f"({exc.field}: {exc.allowed})") from None  # fmt: skip
        if ball.material.law != "mat006":
            raise SpecError("priors", prior, f"a MAT_006 ball (type1, type2), not "
                            f"{ball.material.law}")  # fmt: skip
        if any(b.name == ball.name for b in balls):
            raise SpecError("priors", prior, "distinct balls (a name given twice)")
        balls.append(ball)
    return balls


def fit_league_ball(
    name: str,
    prior: BallSpec,
    targets: Sequence[Target],
    *,
    budget: OptimiserOptions,
    runs_dir: Path,
    workers: int | None,
    free: Sequence[str] = LEAGUE_FREE,
) -> LeagueBall:
    """Fit ``free`` constants of ``prior`` to the stamp's ``targets``; write the ball's spec."""
    from batball.calibrate.command import run_calibration

    league_name = check_name("name", f"{name}-{prior.name}")
    study = runs_dir / f"league-{league_name}.db"
    fitted, summary = run_calibration(
        dataclasses.replace(prior, name=league_name), budget, study=study, targets=targets,
        free=free, workers=workers,
    )  # fmt: skip
    achieved = _achieved(summary["targets"])
    stamp = {t.quantity: t for t in targets}
    cor_text = f"{stamp['cor'].value:.3g}"
    ball = dataclasses.replace(
        fitted,
        description=(
            f"league ball {name} (COR {cor_text} at 60 mph, "
            f"{format_quantity(stamp['compression'].value, 'lbf')} at 0.25 in): prior "
            f"{prior.name}, {' and '.join(free)} fitted on {summary['divisions']} divisions"
        ),
    )
    spec_file = runs_dir / f"league-{league_name}.toml"
    write_ball(ball, spec_file)
    return LeagueBall(
        ball=ball, prior=prior.name, cor=achieved["cor"], compression=achieved["compression"],
        residuals={q: stamp[q].residual(v) for q, v in achieved.items()}, study=study,
        spec_file=spec_file, runs=int(summary["runs_stored"]),
    )  # fmt: skip


def _achieved(rows: Sequence[Mapping[str, Any]]) -> dict[str, float]:
    """``{"cor": value, "compression": value [N]}`` from a calibration summary's target rows."""
    values = {}
    for row in rows:
        fitted = row["fitted"]
        if fitted is None:  # the best candidate never rebounded: nothing meets the stamp
            raise SimulationError(f"{row['target']}: no candidate of the fit could be run")
        values[row["quantity"]] = fitted * LBF if row["unit"] == "lbf" else fitted
    return values


def write_ball(ball: BallSpec, path: Path) -> None:
    """Write ``ball`` as a spec TOML (read back by :func:`batball.specs.load_ball_spec`)."""
    import tomli_w

    from batball.results.store import write_text_atomic
    from batball.specs.ball import ball_spec_to_toml_dict

    write_text_atomic(path, tomli_w.dumps(ball_spec_to_toml_dict(ball)))


__all__ = ["LEAGUE_FREE", "LeagueBall", "league_balls", "league_targets", "parse_stamp"]
