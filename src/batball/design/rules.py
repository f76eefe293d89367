"""Certification rules a design study can hold a bat to, from the standards' published numbers
(docs/physics.md section 4.5). Each rule becomes one constraint per ball it applies to; its
margin is reported per design.

- ``asa-2004-bbs``: the batted-ball speed at the 110-mph lab speed (25-mph pitch plus 85-mph
  swing, ASTM F2219 with the ASA 2004 constants) at most 98 mph.
- ``usssa-bpf-1.20``: the bat performance factor BPF = BBCOR / ball COR (ASTM F1890's ratio; the
  ball's COR on the flat wall of ASTM F1887 at 60 mph) at most 1.20, at every speed the ball is
  fired at.

The numbers are the ones these bodies published for the standards named; a league's current
rule book is what certifies a bat, so check it before relying on a margin.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from batball.errors import SpecError
from batball.units import MPH

#: The ASA 2004 lab speed and BBS limit, mph.
ASA_2004_SPEED_MPH = 110.0
ASA_2004_BBS_LIMIT_MPH = 98.0
#: The USSSA bat performance factor limit (BBCOR over the ball's COR).
USSSA_BPF_LIMIT = 1.20
#: The flat-wall COR speed of ASTM F1887.
BALL_COR_SPEED = 60.0 * MPH


@dataclass(frozen=True)
class BallChoice:
    """A ball the BBS responses use, and the inbound speeds it is fired at (m/s)."""

    name: str
    source: str
    speeds: tuple[float, ...]
    #: A league ball's stamp, (COR at 60 mph, compression at 0.25 in [N]); None for a spec.
    stamp: tuple[float, float] | None = None
    #: A league ball's priors as given (embedded names or TOML paths) and their ball names.
    priors: tuple[str, ...] = ()
    prior_names: tuple[str, ...] = ()
    #: A league ball's fit budget: Latin-hypercube points, then least-squares evaluations.
    fit_points: int = 4
    fit_evaluations: int = 12

    def columns(self, speed: float) -> tuple[str, str, str]:
        """The BBS, BBCOR and e_A columns of this ball at ``speed`` (a league ball's: the
        largest over its priors)."""
        tag = f"{self.name}_{speed / MPH:g}mph".replace(".", "p")
        return f"bbs_{tag}", f"bbcor_{tag}", f"e_a_{tag}"

    def spread_columns(self, speed: float) -> tuple[str, ...]:
        """A league ball's BBS column per prior, then the spread (largest minus smallest) over
        them; none for a ball given by its spec."""
        if self.stamp is None:
            return ()
        bbs = self.columns(speed)[0]
        return (*(f"{bbs}_{prior}" for prior in self.prior_names), f"{bbs}_spread")


@dataclass(frozen=True)
class Constraint:
    """``response`` within ``[lower, upper]`` (in the response's own unit); from a rule, its
    name and source."""

    response: str
    lower: float | None = None
    upper: float | None = None
    rule: str = ""

    def margin(self, value: float) -> float:
        """How far ``value`` is inside the limit (negative: outside), in the response's unit."""
        margins = []
        if self.upper is not None:
            margins.append(self.upper - value)
        if self.lower is not None:
            margins.append(value - self.lower)
        return min(margins)

    @property
    def label(self) -> str:
        """How the study's outputs name it: ``margin_<response>`` or the rule's name."""
        return f"margin_{self.rule.replace('-', '_')}" if self.rule else f"margin_{self.response}"


@dataclass(frozen=True)
class Rule:
    """A named certification rule: its title, its source, and the constraints it makes for the
    study's balls."""

    name: str
    title: str
    source: str
    make: Callable[[Sequence[BallChoice], str], list[Constraint]]
    needs_ball_cor: bool = False

    def constraints(self, balls: Sequence[BallChoice], *, field: str) -> list[Constraint]:
        return self.make(balls, field)


def _asa_2004(balls: Sequence[BallChoice], field: str) -> list[Constraint]:
    out = [
        Constraint(ball.columns(speed)[0], upper=ASA_2004_BBS_LIMIT_MPH, rule="asa-2004-bbs")
        for ball in balls
        for speed in ball.speeds
        if abs(speed / MPH - ASA_2004_SPEED_MPH) < 1e-6
    ]
    if not out:
        raise SpecError(field, "asa-2004-bbs", "a [[ball]] fired at 110 mph (the ASA 2004 speed)")
    return out


def _usssa_bpf(balls: Sequence[BallChoice], field: str) -> list[Constraint]:
    if not balls:
        raise SpecError(field, "usssa-bpf-1.20", "a [[ball]]: the BPF is BBCOR over its COR")
    return [
        Constraint(bpf_column(ball, speed), upper=USSSA_BPF_LIMIT, rule="usssa-bpf-1.20")
        for ball in balls
        for speed in ball.speeds
    ]


def bpf_column(ball: BallChoice, speed: float) -> str:
    """The BPF column of ``ball`` at ``speed``: ``bpf_type1_110mph``."""
    return "bpf_" + ball.columns(speed)[1].removeprefix("bbcor_")


RULES: dict[str, Rule] = {
    "asa-2004-bbs": Rule(
        "asa-2004-bbs",
        "ASA 2004: BBS at most 98 mph at the 110-mph lab speed",
        "ASTM F2219 with the ASA 2004 constants (25-mph pitch, 85-mph swing); limit 98 mph "
        "(NCAA News, 3 January 2005)",
        _asa_2004,
    ),
    "usssa-bpf-1.20": Rule(
        "usssa-bpf-1.20",
        "USSSA: bat performance factor BBCOR / ball COR at most 1.20",
        "ASTM F1890 (BPF), ball COR by ASTM F1887 at 60 mph; the USSSA 1.20 BPF stamp",
        _usssa_bpf,
        needs_ball_cor=True,
    ),
}
