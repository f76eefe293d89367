"""A bat design study, read from TOML: the base bat, the design space, the balls, the responses,
the constraints (certification rules among them) and the objectives.

A study file (units in the strings, as in every spec)::

    name = "barrel-layup"
    bat = "default"                   # embedded bat or a bat TOML file

    [mesh]                            # the screening mesh
    circumferential = 16
    axial_size = "0.5 in"
    ball_divisions = 4

    [confirm]                         # optional: the best designs rerun on a finer mesh
    top = 3
    circumferential = 48
    axial_size = "0.1 in"
    ball_divisions = 12

    [sampling]
    method = "sobol"                  # sobol or lhs
    designs = 16
    seed = 1

    [optimise]                        # optional: a local search from the best sampled design
    evaluations = 12

    [[parameter]]
    name = "carbon_angle"
    set = "angle:barrel-carbon"       # as batball fit-bat --free; or insert_interference
    range = ["15 deg", "45 deg"]

    [[ball]]
    name = "type1"                    # embedded ball or a ball TOML file
    speeds = ["110 mph"]

    [[ball]]                          # a league ball: fitted to its stamp per prior
    name = "league"
    stamp = ".44 / 375"               # COR at 60 mph / compression at 0.25 in (bare: lbf)
    priors = ["type1", "type2"]       # optional

    [[constraint]]
    rule = "asa-2004-bbs"             # a certification rule (batball.design.rules)

    [[constraint]]
    response = "weight_oz"
    max = "24 oz"

    [[objective]]
    maximize = "bbs_type1_110mph"     # or minimize = ..., or response = ... with target = ...

Responses are the columns of ``designs.csv``: ``weight_oz``, ``balance_point_in``,
``moi_pivot_oz_in2`` (always), ``bending1_hz``, ``bending2_hz``, ``hoop1_hz``, ``hoop2_hz`` (the
modal test, run when a constraint or objective names one, or ``modal = true``),
``barrel_preload_lbf``, ``barrel_final_load_lbf`` (the barrel test, likewise or ``barrel =
true``), and per ball and speed ``bbs_<ball>_<speed>mph``, ``bbcor_<ball>_<speed>mph`` and
``e_a_<ball>_<speed>mph`` (a league ball's: the largest over its priors, with
``bbs_<ball>_<speed>mph_<prior>`` per prior and ``bbs_<ball>_<speed>mph_spread``).
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from batball.calibrate.bat_fit import FreeParameter
from batball.design.rules import RULES, BallChoice, Constraint, Rule, bpf_column
from batball.errors import SpecError
from batball.specs.bat import BatSpec, parse_angle
from batball.specs.document import check_name
from batball.units import IN, MPH, OZ, parse_quantity

STUDY_KEYS = ("name", "description", "bat", "mesh", "confirm", "sampling", "optimise",
              "parameter", "ball", "constraint", "objective", "modal", "barrel")  # fmt: skip

#: What ``set`` may say besides fit-bat's ``kind:target[@parts]``.
INSERT_INTERFERENCE = "insert_interference"
_SET_TEXT = ("lumped_mass:<part>, thickness:<ply label>[@<part>+...], "
             "angle:<ply label>[@<part>+...] or insert_interference")  # fmt: skip

#: SI per unit of the units parameters are written in.
UNIT_FACTORS = {"oz": OZ, "in": IN, "deg": math.pi / 180.0}

#: The unit each kind of parameter is written and reported in, and its dimension.
PARAMETER_UNITS = {
    "lumped_mass": ("oz", "mass"),
    "thickness": ("in", "length"),
    "angle": ("deg", "angle"),
    INSERT_INTERFERENCE: ("in", "length"),
}


@dataclass(frozen=True)
class DesignParameter:
    """One dimension of the design space: what it sets and its range (SI: kg, m or rad)."""

    name: str
    setting: str
    lower: float
    upper: float

    @property
    def unit(self) -> str:
        """The unit it is written in (``"deg"``)."""
        return PARAMETER_UNITS[self.kind][0]

    @property
    def kind(self) -> str:
        return self.setting.partition(":")[0]

    @property
    def column(self) -> str:
        """Its column in ``designs.csv``: ``carbon_angle_deg``."""
        return f"{self.name}_{self.unit}"

    def to_unit(self, value: float) -> float:
        """``value`` (SI) in :attr:`unit`."""
        return value / UNIT_FACTORS[self.unit]

    def value_at(self, u: float) -> float:
        """The value at ``u`` in [0, 1] of the range (SI)."""
        return self.lower + u * (self.upper - self.lower)

    def apply(self, spec: BatSpec, value: float) -> BatSpec:
        """``spec`` with this parameter set to ``value`` (SI)."""
        import dataclasses

        if self.setting == INSERT_INTERFERENCE:
            if spec.insert is None:
                raise SpecError(f"parameter {self.name}", self.setting, "a bat with an insert")
            return dataclasses.replace(
                spec, insert=dataclasses.replace(spec.insert, interference=value)
            )
        return FreeParameter.parse(self.setting, field=f"parameter {self.name}").apply(spec, value)


@dataclass(frozen=True)
class Objective:
    """Minimise, maximise, or bring ``response`` to ``target`` (in the response's unit)."""

    response: str
    sense: str  # "min", "max" or "target"
    target: float | None = None

    def score(self, value: float) -> float:
        """Smaller is better."""
        if self.sense == "max":
            return -value
        if self.sense == "target":
            assert self.target is not None
            return abs(value - self.target)
        return value


@dataclass(frozen=True)
class Mesh:
    """The bat shells around, the largest shell length along the bat (m), the ball's divisions."""

    circumferential: int
    axial_size: float
    ball_divisions: int

    @property
    def label(self) -> str:
        return (f"{self.circumferential} x {self.axial_size / 0.0254:g} in shells, "
                f"{self.ball_divisions}-division ball")  # fmt: skip


@dataclass(frozen=True)
class DesignStudy:
    """A parsed study file (module docs)."""

    name: str
    description: str
    bat: str
    parameters: tuple[DesignParameter, ...]
    balls: tuple[BallChoice, ...]
    constraints: tuple[Constraint, ...]
    objectives: tuple[Objective, ...]
    mesh: Mesh
    confirm: Mesh | None = None
    confirm_top: int = 0
    confirm_rounds: int = 1
    method: str = "sobol"
    designs: int = 16
    seed: int = 1
    optimise_evaluations: int = 0
    modal: bool = False
    barrel: bool = False
    rules: tuple[Rule, ...] = field(default=())

    @property
    def responses(self) -> tuple[str, ...]:
        """Every response column the study computes, in ``designs.csv`` order."""
        out = ["weight_oz", "balance_point_in", "moi_pivot_oz_in2"]
        if self.needs_modal:
            out += ["bending1_hz", "bending2_hz", "hoop1_hz", "hoop2_hz"]
        if self.needs_barrel:
            out += ["barrel_preload_lbf", "barrel_final_load_lbf"]
        for ball in self.balls:
            for speed in ball.speeds:
                out += list(ball.columns(speed))
                out += list(ball.spread_columns(speed))
                if self.needs_ball_cor:
                    out.append(bpf_column(ball, speed))
        return tuple(out)

    @property
    def needs_ball_cor(self) -> bool:
        """Whether a rule needs each ball's flat-wall COR (the BPF's denominator)."""
        return any(rule.needs_ball_cor for rule in self.rules)

    @property
    def named(self) -> set[str]:
        return {c.response for c in self.constraints} | {o.response for o in self.objectives}

    @property
    def needs_modal(self) -> bool:
        return self.modal or any(n.endswith("_hz") for n in self.named)

    @property
    def needs_barrel(self) -> bool:
        return self.barrel or any(n.startswith("barrel_") for n in self.named)


def load_design_study(path: str | Path) -> DesignStudy:
    """Read and check the study file at ``path``.

    Raises:
        SpecError: a missing or invalid value, naming its field (``parameter[1].range``).
    """
    path = Path(path)
    if not path.is_file():
        raise SpecError("study", str(path), "an existing study TOML file")
    try:
        document = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise SpecError("study", str(path), f"valid TOML ({exc})") from None
    return design_study_from_dict(document, base=path.parent)


def design_study_from_dict(document: Mapping[str, Any], *, base: Path = Path(".")) -> DesignStudy:
    """A :class:`DesignStudy` from a parsed study document; relative spec paths are read from
    ``base`` (the study file's folder)."""
    from batball.specs import load_bat_spec

    unknown = sorted(set(document) - set(STUDY_KEYS))
    if unknown:
        raise SpecError(unknown[0], document[unknown[0]], f"a study key: {', '.join(STUDY_KEYS)}")
    name = check_name("name", document.get("name"))
    from batball.specs.bat import EMBEDDED_BATS, FITTED_BATS

    bat = _spec_path(document.get("bat", "default"), base, embedded=EMBEDDED_BATS + FITTED_BATS)
    spec = load_bat_spec(bat)
    parameters = tuple(
        _parameter(item, f"parameter[{i}]", spec)
        for i, item in enumerate(_tables(document, "parameter", required=True))
    )
    names = [p.name for p in parameters]
    if len(set(names)) != len(names):
        raise SpecError("parameter", names, "parameters of distinct names")
    balls = tuple(_ball(item, f"ball[{i}]", base)
                  for i, item in enumerate(_tables(document, "ball")))  # fmt: skip
    mesh = _mesh(document.get("mesh", {}), "mesh", default=(16, 0.5 * 0.0254, 4))
    confirm_table = document.get("confirm")
    confirm, top, rounds = None, 0, 1
    if confirm_table is not None:
        confirm = _mesh(confirm_table, "confirm", default=(48, 0.1 * 0.0254, 12))
        top = _integer(confirm_table.get("top", 3), "confirm.top", 1, 20)
        rounds = _integer(confirm_table.get("rounds", 1), "confirm.rounds", 1, 10)
    sampling = document.get("sampling", {})
    _known(sampling, "sampling", ("method", "designs", "seed"))
    method = sampling.get("method", "sobol")
    if method not in ("sobol", "lhs"):
        raise SpecError("sampling.method", method, "sobol or lhs")
    designs = _integer(sampling.get("designs", 16), "sampling.designs", 1, 10000)
    seed = _integer(sampling.get("seed", 1), "sampling.seed", 0, 2**31 - 1)
    optimise = document.get("optimise", {})
    _known(optimise, "optimise", ("evaluations",))
    evaluations = _integer(optimise.get("evaluations", 0), "optimise.evaluations", 0, 1000)
    constraints: list[Constraint] = []
    rules: list[Rule] = []
    for i, item in enumerate(_tables(document, "constraint")):
        made, rule = _constraint(item, f"constraint[{i}]", balls)
        constraints += made
        rules += [rule] if rule is not None else []
    objectives = tuple(_objective(item, f"objective[{i}]")
                       for i, item in enumerate(_tables(document, "objective")))  # fmt: skip
    study = DesignStudy(
        name=name, description=str(document.get("description", "")), bat=str(bat),
        parameters=parameters, balls=balls, constraints=tuple(constraints),
        objectives=objectives, mesh=mesh, confirm=confirm, confirm_top=top, confirm_rounds=rounds,
        method=method,
        designs=designs, seed=seed, optimise_evaluations=evaluations,
        modal=_flag(document, "modal"), barrel=_flag(document, "barrel"), rules=tuple(rules),
    )  # fmt: skip
    known = set(study.responses)
    for where, response in [*(("constraint", c.response) for c in study.constraints),
                            *(("objective", o.response) for o in study.objectives)]:  # fmt: skip
        if response not in known:
            raise SpecError(where, response, f"a response of the study: {', '.join(sorted(known))}")
    if evaluations and not objectives:
        raise SpecError("optimise.evaluations", evaluations, "0 when the study has no objective")
    return study


def _tables(document: Mapping[str, Any], key: str, required: bool = False) -> list[Any]:
    items = document.get(key, [])
    if not isinstance(items, list) or (required and not items):
        raise SpecError(key, items, f"one or more [[{key}]] tables")
    for i, item in enumerate(items):
        if not isinstance(item, Mapping):
            raise SpecError(f"{key}[{i}]", item, "a table")
    return items


def _known(table: Any, field: str, keys: Sequence[str]) -> None:
    if not isinstance(table, Mapping):
        raise SpecError(field, table, "a table")
    unknown = sorted(set(table) - set(keys))
    if unknown:
        raise SpecError(f"{field}.{unknown[0]}", table[unknown[0]], f"a key: {', '.join(keys)}")


def _integer(value: Any, field: str, lower: int, upper: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not lower <= value <= upper:
        raise SpecError(field, value, f"an integer {lower}..{upper}")
    return value


def _flag(document: Mapping[str, Any], key: str) -> bool:
    value = document.get(key, False)
    if not isinstance(value, bool):
        raise SpecError(key, value, "true or false")
    return value


def _spec_path(value: Any, base: Path, *, embedded: Sequence[str]) -> str:
    """An embedded name as it is; a file path relative to the study's folder."""
    if not isinstance(value, str) or not value:
        raise SpecError("spec", value, "an embedded name or the path of a TOML file")
    if value in embedded or Path(value).is_absolute():
        return value
    return str(base / value)


def _quantity(value: Any, dimension: str, field: str) -> float:
    if dimension == "angle":
        return parse_angle(value, field=field)
    return parse_quantity(value, dimension, field=field)


def _parameter(item: Mapping[str, Any], field: str, spec: BatSpec) -> DesignParameter:
    _known(item, field, ("name", "set", "range"))
    name = check_name(f"{field}.name", item.get("name"))
    setting = item.get("set")
    if not isinstance(setting, str):
        raise SpecError(f"{field}.set", setting, _SET_TEXT)
    if setting != INSERT_INTERFERENCE:
        free = FreeParameter.parse(setting, field=f"{field}.set")
        try:  # the part or label exists and is one value on the base bat
            free.value(spec)
        except SpecError as error:
            raise SpecError(f"{field}.set", setting, error.allowed) from None
    elif spec.insert is None:
        raise SpecError(f"{field}.set", setting, "a bat with an insert")
    kind = setting.partition(":")[0]
    dimension = PARAMETER_UNITS[kind][1]
    bounds = item.get("range")
    if not isinstance(bounds, list) or len(bounds) != 2:
        raise SpecError(f"{field}.range", bounds, "[lower, upper], each with its unit")
    lower, upper = (_quantity(b, dimension, f"{field}.range") for b in bounds)
    limits = {"angle": (0.0, 0.5 * math.pi), "lumped_mass": (0.0, math.inf),
              "thickness": (0.001 * 0.0254, math.inf),
              INSERT_INTERFERENCE: (0.0, 0.01 * 0.0254)}[kind]  # fmt: skip
    if not (limits[0] <= lower < upper <= limits[1]):
        unit = PARAMETER_UNITS[kind][0]
        raise SpecError(f"{field}.range", bounds, f"lower < upper within the {kind}'s limits "
                        f"({_text(limits[0], unit)} to {_text(limits[1], unit)})")  # fmt: skip
    return DesignParameter(name, setting, lower, upper)


def _text(value: float, unit: str) -> str:
    if math.isinf(value):
        return "no limit"
    factor = UNIT_FACTORS[unit]
    return f"{value / factor:g} {unit}"


def _ball(item: Mapping[str, Any], field: str, base: Path) -> BallChoice:
    from batball.specs.ball import EMBEDDED_BALLS, EXAMPLE_BALLS, FITTED_BALLS, load_ball_spec

    speeds = item.get("speeds", ["110 mph"])
    if not isinstance(speeds, list) or not speeds:
        raise SpecError(f"{field}.speeds", speeds, "a list of speeds with units")
    values = tuple(parse_quantity(s, "velocity", field=f"{field}.speeds") for s in speeds)
    if any(not 10 * MPH <= v <= 200 * MPH for v in values):
        raise SpecError(f"{field}.speeds", speeds, "inbound speeds 10 to 200 mph")
    if "stamp" in item:
        return _league_ball(item, field, base, values)
    _known(item, field, ("name", "speeds"))
    source = _spec_path(item.get("name"), base,
                        embedded=EMBEDDED_BALLS + FITTED_BALLS + EXAMPLE_BALLS)  # fmt: skip
    ball = load_ball_spec(source)
    return BallChoice(check_name(f"{field}.name", ball.name), source, values)


def _league_ball(item: Mapping[str, Any], field: str, base: Path,
                 speeds: tuple[float, ...]) -> BallChoice:  # fmt: skip
    """A ``[[ball]]`` given by its stamp: fitted per prior when the study runs
    (:mod:`batball.design.league`)."""
    from batball.design.league import load_priors, parse_stamp
    from batball.specs.ball import EMBEDDED_BALLS, FITTED_BALLS

    _known(item, field, ("name", "stamp", "priors", "speeds", "fit_points", "fit_evaluations"))
    name = check_name(f"{field}.name", item.get("name"))
    try:
        stamp = parse_stamp(item["stamp"])
    except SpecError as exc:
        raise SpecError(f"{field}.stamp", exc.value, exc.allowed) from None
    given = item.get("priors", ["type1", "type2"])
    if not isinstance(given, list) or not all(isinstance(p, str) for p in given):
        raise SpecError(f"{field}.priors", given, "a list of MAT_006 balls (type1, type2)")
    sources = tuple(_spec_path(p, base, embedded=EMBEDDED_BALLS + FITTED_BALLS) for p in given)
    try:
        priors = load_priors(sources)
    except SpecError as exc:
        raise SpecError(f"{field}.priors", exc.value, exc.allowed) from None
    return BallChoice(
        name, "", speeds, stamp=stamp, priors=sources, prior_names=tuple(b.name for b in priors),
        fit_points=_integer(item.get("fit_points", 4), f"{field}.fit_points", 0, 100),
        fit_evaluations=_integer(item.get("fit_evaluations", 12), f"{field}.fit_evaluations",
                                 1, 200),
    )  # fmt: skip


def _constraint(item: Mapping[str, Any], field: str,
                balls: Sequence[BallChoice]) -> tuple[list[Constraint], Rule | None]:  # fmt: skip
    if "rule" in item:
        _known(item, field, ("rule",))
        rule = RULES.get(item["rule"])
        if rule is None:
            raise SpecError(f"{field}.rule", item["rule"], f"one of {', '.join(RULES)}")
        return rule.constraints(balls, field=f"{field}.rule"), rule
    _known(item, field, ("response", "min", "max"))
    response = item.get("response")
    if not isinstance(response, str):
        raise SpecError(f"{field}.response", response, "a response column of designs.csv")
    if "min" not in item and "max" not in item:
        raise SpecError(field, dict(item), "a min, a max or both")
    lower = _limit(item.get("min"), response, f"{field}.min")
    upper = _limit(item.get("max"), response, f"{field}.max")
    return [Constraint(response, lower, upper)], None


#: A response column's unit suffix -> the dimension its limits are given in.
SUFFIX_DIMENSIONS = {"_oz": "mass", "_in": "length", "_oz_in2": "moment_of_inertia",
                     "_hz": "frequency", "_lbf": "force", "mph": "velocity"}  # fmt: skip
_SUFFIX_UNITS = {"_oz": "oz", "_in": "in", "_oz_in2": "oz*in**2", "_hz": "Hz", "_lbf": "lbf",
                 "mph": "mph"}  # fmt: skip


def response_unit(response: str) -> str:
    """The unit of a response column (``"oz"``), or ``""`` for a pure number (BBCOR, e_A)."""
    for suffix in ("_oz_in2", "_oz", "_in", "_hz", "_lbf"):
        if response.endswith(suffix):
            return _SUFFIX_UNITS[suffix]
    return "mph" if response.startswith("bbs_") else ""


def _limit(value: Any, response: str, field: str) -> float | None:
    """A constraint's limit in the response's own unit (a bare number for BBCOR and e_A)."""
    if value is None:
        return None
    unit = response_unit(response)
    if not unit:
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(
            value
        ):
            raise SpecError(field, value, "a number (the response has no unit)")
        return float(value)
    suffix = next(s for s, u in _SUFFIX_UNITS.items() if u == unit)
    si = parse_quantity(value, SUFFIX_DIMENSIONS[suffix], field=field)
    from batball.units import to_unit

    return to_unit(si, unit)


def _objective(item: Mapping[str, Any], field: str) -> Objective:
    _known(item, field, ("minimize", "maximize", "response", "target"))
    if "minimize" in item or "maximize" in item:
        if len(item) != 1:
            raise SpecError(field, dict(item), "one of minimize = ..., maximize = ...")
        sense = "min" if "minimize" in item else "max"
        response = item.get("minimize", item.get("maximize"))
        if not isinstance(response, str):
            raise SpecError(field, response, "a response column of designs.csv")
        return Objective(response, sense)
    response = item.get("response")
    if not isinstance(response, str) or "target" not in item:
        raise SpecError(field, dict(item), "minimize = R, maximize = R, or response = R with "
                        "target = value")  # fmt: skip
    target = _limit(item["target"], response, f"{field}.target")
    return Objective(response, "target", target)


def _mesh(table: Any, field: str, default: tuple[int, float, int]) -> Mesh:
    _known(table, field, ("circumferential", "axial_size", "ball_divisions", "top", "rounds"))
    circumferential = _integer(table.get("circumferential", default[0]),
                               f"{field}.circumferential", 8, 256)  # fmt: skip
    axial = table.get("axial_size")
    axial_size = default[1] if axial is None else parse_quantity(
        axial, "length", field=f"{field}.axial_size")  # fmt: skip
    if not 0.01 * 0.0254 <= axial_size <= 4 * 0.0254:
        raise SpecError(f"{field}.axial_size", axial, "0.01 in to 4 in")
    divisions = _integer(table.get("ball_divisions", default[2]), f"{field}.ball_divisions", 2, 40)
    return Mesh(circumferential, axial_size, divisions)
