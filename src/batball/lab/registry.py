"""The registry of virtual tests: every test on the protocol of :mod:`batball.lab.protocol`.

:data:`LAB_TESTS` maps the name users type to its :class:`~batball.lab.protocol.LabTest`. The
command line makes one subcommand of each entry and the Python API one function; a new test is one
entry here. Options shared by several tests are declared once below and reused, with a test's own
default where it differs (the inbound speed).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from batball.errors import SpecError
from batball.lab import describe
from batball.lab.protocol import LabTest, Option

# --- ball options -------------------------------------------------------------------------------

SPEED = Option("speed", "95 mph", "inbound speed with its unit", dimension="velocity",
               check=lambda v: v > 0, allowed="a positive speed, e.g. '95 mph'")  # fmt: skip
DIVISIONS = Option("divisions", 12, "ball mesh size: 12 gives the seed's 12,096 hexes",
                   kind="int")  # fmt: skip
HOURGLASS_TYPE = Option("hourglass_type", None, "LS-DYNA IHQ 1-5, replacing the ball's own "
                        "(the ball file's [hourglass], else viscous IHQ 1)",
                        kind="int")  # fmt: skip
HOURGLASS_COEFFICIENT = Option("hourglass_coefficient", None, "QH/QM, replacing the ball's own "
                               "(the ball file's, else 0.1)", kind="float")  # fmt: skip
BULK_VISCOSITY = Option("bulk_viscosity", True, "bulk viscosity (Q1 = 1.5, Q2 = 0.06)",
                        kind="flag")  # fmt: skip
SOFT = Option("soft", 0, "contact SOFT option, 0 or 1", kind="int")
SFS = Option("sfs", 1.0, "contact penalty scale SFS on the ball's side, as LS-DYNA's (a foam "
             "ball's compression needs about 5)", kind="float", check=lambda v: v > 0,
             allowed="a positive scale", aliases=("--penalty-scale",))  # fmt: skip
CONTACT_THRESHOLD = Option("contact_threshold", 0.01,
                           "contact-time level as a fraction of the peak force",
                           kind="float", check=lambda v: 0.0 <= v < 1.0,
                           allowed="0 <= threshold < 1 (a fraction of the peak force)")  # fmt: skip
PRECISION = Option("precision", "single",
                   "element arithmetic of the ball: single, as LS-DYNA's default executable, or "
                   "double (they agree to about 1e-6 in CCOR, docs/notes/precision.md)",
                   kind="choice", choices=("single", "double"))  # fmt: skip

DISPLACEMENT = Option("displacement", "0.25 in", "plate travel: where the compression is read",
                      dimension="length")  # fmt: skip

# --- bat options --------------------------------------------------------------------------------

CIRCUMFERENTIAL = Option("circumferential", 48,
                         "shells around the circumference (with 0.1 in: 20,928 shells)",
                         kind="int", check=lambda n: n >= 3, allowed="an integer >= 3")  # fmt: skip
AXIAL_SIZE = Option("axial_size", "0.1 in", "largest shell length along the bat",
                    dimension="length", check=lambda v: v > 0,
                    allowed="a positive length, e.g. '0.1 in'")  # fmt: skip
PIVOT = Option("pivot", "6 in", "pivot distance from the knob end", dimension="length")
SHELL = Option("shell", "mitc4", "the bat's explicit shells: mitc4, the statics' MITC4 made "
               "co-rotational (no hourglass modes; the element whose limit batball believes, "
               "docs/decisions.md), or bt, the one-point Belytschko-Tsay shells of the seed's "
               "LS-DYNA model", kind="choice", choices=("bt", "mitc4"))  # fmt: skip
HOURGLASS_RATIO = Option("hourglass_ratio", None,
                         "hourglass ratio r of the bat's one-point shells, 0 < r <= 1 "
                         "(default LS-DYNA's 0.01)", kind="float")  # fmt: skip
MODES = Option("modes", 30, "modes to compute, the six rigid-body modes included", kind="int",
               check=lambda n: n >= 8,
               allowed="an integer >= 8 (six rigid-body modes come first)")  # fmt: skip
PIVOT_BAND = Option("pivot_band", "0.5 in", "half width of the rigid handle band at the pivot",
                    dimension="length")  # fmt: skip
BAT_MESH = (CIRCUMFERENTIAL, AXIAL_SIZE)


# --- the Setups of the bat tests (the ball tests' live with their models) ------------------------
# No defaults of their own: those are the options'; a Setup is made by its test's ``setup()``.


@dataclass(frozen=True)
class PropsSetup:
    """Mass properties (ASTM F2398): the shell mesh [count, m] and the pivot from the knob [m]."""

    circumferential: int
    axial_size: float
    pivot: float


@dataclass(frozen=True)
class ModalSetup:
    """Free-free modes: the shell mesh, how many modes (six rigid ones first) and the insert's
    fit ("contact": the pre-stressed fit, sliding; "bonded": tied)."""

    circumferential: int
    axial_size: float
    modes: int
    insert: str


@dataclass(frozen=True)
class BarrelSetup:
    """Barrel compression (seed Table 2): the shell mesh, the static ramp of the fit, the
    protocol (platens, travels, orientations, Coulomb friction insert-barrel and
    platens-barrel), and for the explicit solver its options (None: the static solver)."""

    circumferential: int
    axial_size: float
    ramp_steps: int
    protocol: Any
    explicit: Any = None


def _build_barrel(values: Mapping[str, Any]) -> BarrelSetup:
    """The barrel Setup, every value checked by the options it becomes."""
    from batball.lab.barrel_explicit import ExplicitBarrelOptions
    from batball.models.barrel import BarrelTestOptions

    shell, ratio = values["shell"], values["hourglass_ratio"]
    explicit = None
    if values["solver"] == "explicit":
        if ratio is not None and shell != "bt":
            raise SpecError("hourglass-ratio", ratio,
                            "only with --shell bt (MITC4 shells have none)")  # fmt: skip
        explicit = ExplicitBarrelOptions(
            circumferential=values["circumferential"], axial_size=values["axial_size"],
            shell=shell or "mitc4", **({} if ratio is None else {"hourglass_ratio": ratio}),
        )  # fmt: skip
    elif shell is not None or ratio is not None:
        name, value = ("shell", shell) if shell is not None else ("hourglass-ratio", ratio)
        raise SpecError(name, value, "only with --solver explicit")
    protocol = BarrelTestOptions(friction=values["friction"],
                                 platen_friction=values["platen_friction"])  # fmt: skip
    return BarrelSetup(circumferential=values["circumferential"],
                       axial_size=values["axial_size"], ramp_steps=values["ramp_steps"],
                       protocol=protocol, explicit=explicit)  # fmt: skip


# --- build: parsed option values -> Setup --------------------------------------------------------


def ball_numerics(values: Mapping[str, Any]) -> dict[str, Any]:
    """The ``hourglass``, ``bulk_viscosity`` and ``contact`` settings of a ball's parsed options
    (those not given keep their own defaults), for any Setup that holds a ball."""
    from batball.models.ball import ContactOptions
    from batball.solvers.explicit import BulkViscosity, HourglassControl

    hourglass = {k: values[f"hourglass_{k}"] for k in ("type", "coefficient")}
    given = {k: v for k, v in hourglass.items() if v is not None}
    return {
        # none given: the ball's own; one given: the other at the solver default (both replace
        # the ball's, so that an option never mixes with a ball file's value)
        "hourglass": HourglassControl(**given) if given else None,
        "bulk_viscosity": BulkViscosity(
            **({} if "bulk_viscosity" not in values else {"enabled": values["bulk_viscosity"]})
        ),
        # each test declares the contact options it lets a user set; the rest keep their own
        "contact": ContactOptions(**{k: values[k] for k in ("soft", "sfs") if k in values}),
    }


def _impact_builder(test: str) -> Any:
    def build(values: Mapping[str, Any]) -> Any:
        from batball.models.impact import ImpactSetup

        return ImpactSetup(test=test, speed=values["speed"], divisions=values["divisions"],
                           contact_threshold=values["contact_threshold"],
                           precision=values["precision"], **ball_numerics(values))  # fmt: skip

    return build


def _build_compression(values: Mapping[str, Any]) -> Any:
    from batball.models.compression import CompressionSetup

    numerics = ball_numerics(values)
    return CompressionSetup(displacement=values["displacement"], rate=values["rate"],
                            divisions=values["divisions"], hourglass=numerics["hourglass"],
                            quasi_static_ratio=values["quasi_static_ratio"],
                            contact=numerics["contact"])  # fmt: skip


def _build_bbs(values: Mapping[str, Any]) -> Any:
    from batball.models.bbs import BbsSetup

    ratio = values["hourglass_ratio"]
    if ratio is not None and values["shell"] != "bt":
        raise SpecError("hourglass-ratio", ratio, "only with --shell bt (MITC4 shells have none)")
    return BbsSetup(
        speed=values["speed"], pitch_speed=values["pitch_speed"],
        swing_speed=values["swing_speed"], impact_from_cap=values["impact"],
        pivot_from_knob=values["pivot"], pivot_band=values["pivot_band"],
        ball_divisions=values["divisions"], circumferential=values["circumferential"],
        axial_size=values["axial_size"], rigid_bat=values["rigid_bat"],
        end_time=values["end_time"], mass_scaling=values["mass_scaling"],
        precision=values["precision"], insert_friction=values["insert_friction"],
        bat_damping=values["bat_damping"], bat_shell=values["shell"],
        hourglass=ball_numerics(values)["hourglass"], contact=ball_numerics(values)["contact"],
        **({} if ratio is None else {"shell_hourglass_ratio": ratio}),
    )  # fmt: skip


# --- run: subjects and Setup -> (summary, run folder) --------------------------------------------


def _run_impact(subjects: Mapping[str, Any], setup: Any, **store: Any) -> tuple[dict, Path]:
    from batball.lab.impact_run import run_impact_test

    return run_impact_test(subjects["ball"], setup, **store)


def _run_compression(subjects: Mapping[str, Any], setup: Any, **store: Any) -> tuple[dict, Path]:
    from batball.lab.compression_run import run_compression_test

    return run_compression_test(subjects["ball"], setup, **store)


def _run_props(subjects: Mapping[str, Any], setup: PropsSetup, *, runs_dir: Path, reuse: bool,
               progress: Any = None) -> tuple[dict, Path]:  # fmt: skip
    from batball.lab.props_run import run_props_test

    return run_props_test(subjects["bat"], runs_dir=runs_dir, reuse=reuse,
                          circumferential=setup.circumferential, axial_size=setup.axial_size,
                          pivot=setup.pivot)  # fmt: skip


def _run_modal(subjects: Mapping[str, Any], setup: ModalSetup, *, runs_dir: Path, reuse: bool,
               progress: Any = None) -> tuple[dict, Path]:  # fmt: skip
    from batball.lab.modal_run import run_modal_test

    return run_modal_test(subjects["bat"], runs_dir=runs_dir, reuse=reuse, n_modes=setup.modes,
                          circumferential=setup.circumferential, axial_size=setup.axial_size,
                          insert=setup.insert)  # fmt: skip


def _run_barrel(subjects: Mapping[str, Any], setup: BarrelSetup, *, runs_dir: Path, reuse: bool,
                progress: Any = None) -> tuple[dict, Path]:  # fmt: skip
    from batball.lab.barrel_run import run_barrel_test, run_explicit_barrel_test

    if setup.explicit is None:
        return run_barrel_test(subjects["bat"], runs_dir=runs_dir, reuse=reuse,
                               options=setup.protocol, ramp_steps=setup.ramp_steps,
                               circumferential=setup.circumferential,
                               axial_size=setup.axial_size)  # fmt: skip
    return run_explicit_barrel_test(subjects["bat"], runs_dir=runs_dir, options=setup.protocol,
                                    explicit=setup.explicit, reuse=reuse)  # fmt: skip


def _run_bbs(subjects: Mapping[str, Any], setup: Any, *, runs_dir: Path, reuse: bool,
             progress: Any = None) -> tuple[dict, Path]:  # fmt: skip
    from batball.lab.bbs_run import run_bbs_test

    return run_bbs_test(subjects["bat"], subjects["ball"], setup, runs_dir=runs_dir, reuse=reuse)


# --- the entries ----------------------------------------------------------------------------------

_BALL_NUMERICS = (HOURGLASS_TYPE, HOURGLASS_COEFFICIENT, BULK_VISCOSITY, SOFT, SFS)


def _impact_test(name: str, help: str, speed: str) -> LabTest:
    return LabTest(
        name=name, help=help, subjects=("ball",),
        options=(SPEED.with_default(speed), DIVISIONS, *_BALL_NUMERICS, CONTACT_THRESHOLD,
                 PRECISION),
        build=_impact_builder(name), run=_run_impact, describe=describe.describe_impact,
        history="history.csv", span=lambda setup: (setup.end_time, "ms"),
    )  # fmt: skip


COMPRESSION = LabTest(
    name="compression",
    help="ball compression: force at 0.25 in between flat plates at 1 in/min (ASTM F1888)",
    subjects=("ball",),
    options=(
        DISPLACEMENT,
        Option("rate", "1 in/min", "plate speed", dimension="velocity"),
        DIVISIONS, HOURGLASS_TYPE, HOURGLASS_COEFFICIENT,
        Option("quasi_static_ratio", 60.0,
               "loading time in radians of the mass-scaled squash mode", kind="float"),
        SFS,
    ),
    build=_build_compression, run=_run_compression, describe=describe.describe_compression,
    history="curve.csv", span=lambda setup: (setup.displacement / setup.rate, "s"),
)  # fmt: skip

PROPS = LabTest(
    name="props",
    help="weight, balance point and MOI about the 6-in pivot of a bat (ASTM F2398)",
    subjects=("bat",), options=(*BAT_MESH, PIVOT),
    build=lambda v: PropsSetup(**v), run=_run_props, describe=describe.describe_props,
)  # fmt: skip

MODAL = LabTest(
    name="modal",
    help="free-free modes of a bat: first two bending and hoop frequencies (seed Table 3)",
    subjects=("bat",),
    options=(
        *BAT_MESH,
        MODES,
        Option("insert", "contact", "the insert: contact, its pre-stressed fit sliding "
               "frictionless (docs/notes/modal.md), or bonded, tied to the barrel", kind="choice",
               choices=("contact", "bonded")),
    ),
    build=lambda v: ModalSetup(**v), run=_run_modal, describe=describe.describe_modal,
)  # fmt: skip

BARREL = LabTest(
    name="barrel",
    help="interference-fit pre-stress and barrel compression of a bat (seed Table 2)",
    subjects=("bat",),
    options=(
        *BAT_MESH,
        Option("ramp_steps", 1, "static steps removing the insert's overlap (1: the fit is "
               "linear and frictionless, so its end state does not depend on the path)",
               kind="int", check=lambda n: n >= 1, allowed="an integer >= 1"),
        Option("friction", None, "Coulomb coefficient between insert and barrel during the "
               "squeeze (default: the bat's insert friction, 0 on the embedded bats as in the "
               "seed; the fit itself stays frictionless)", kind="float"),
        Option("platen_friction", 0.0, "Coulomb coefficient between the platens and the "
               "barrel (0, as the seed)", kind="float"),
        Option("solver", "static", "static: linear MITC4 shells, penalty contact, small "
               "displacements; explicit: shells relaxed at each travel, geometrically "
               "nonlinear (docs/notes/barrel.md)", kind="choice", choices=("static", "explicit")),
        SHELL.with_default(None, "with solver explicit: mitc4 (default), the statics' MITC4 "
                           "shells made co-rotational, or bt, the one-point Belytschko-Tsay "
                           "shells of the seed's LS-DYNA model"),
        HOURGLASS_RATIO.with_default(None, "with shell bt: hourglass ratio r of the one-point "
                                     "shells, 0 < r <= 1 (default 1)"),
    ),
    build=_build_barrel, run=_run_barrel, describe=describe.describe_barrel,
    history="force_travel.csv",
)  # fmt: skip

BBS = LabTest(
    name="bbs",
    help="batted-ball speed: a ball fired at the bat pivoting 6 in from the knob (Table 9)",
    subjects=("bat", "ball"),
    options=(
        *BAT_MESH, PIVOT,
        SPEED.with_default("110 mph", "inbound ball speed"),
        Option("pitch_speed", "25 mph", "BBS pitch speed v_p (ASA: 25 mph)",
               dimension="velocity"),
        Option("swing_speed", "85 mph", "BBS bat speed v_b (ASA: 85 mph)",
               dimension="velocity"),
        replace(DIVISIONS, aliases=("--ball-divisions",)),
        Option("impact", "6 in", "impact point from the end cap", dimension="length"),
        PIVOT_BAND,
        Option("end_time", "2 ms", "longest run (2 ms, as the seed)", dimension="time"),
        Option("rigid_bat", False, "the bat as a rigid body on the pivot (verification)",
               kind="flag"),
        Option("mass_scaling", "barrel", "selective mass scaling of the shells below a target "
               "step (LS-DYNA DT2MS < 0): barrel (the barrel's or the ball's step), off, or the "
               "target step, e.g. '2e-7 s'", dimension="time",
               words={"barrel": "barrel", "off": None}),
        Option("insert_friction", None, "Coulomb coefficient between insert and barrel during "
               "the impact (default: the bat's insert friction, 0 on the embedded bats as in "
               "the seed; the fit is pressed frictionless)", kind="float"),
        Option("bat_damping", "0 1/s", "damping c of the bat's deformation relative to its "
               "rigid turn, e.g. '1000 1/s' (as LS-DYNA *DAMPING_RELATIVE; 0: none, as the "
               "seed)", dimension="frequency"),
        HOURGLASS_RATIO.with_default(None, "with --shell bt: hourglass ratio r of the one-point "
                                     "shells, 0 < r <= 1 (default LS-DYNA's 0.01)"),
        SHELL,
        replace(HOURGLASS_TYPE, help="the ball's hourglass control, LS-DYNA IHQ 1-5, replacing "
                "the ball's own (its file's [hourglass], else viscous IHQ 1)"),
        replace(HOURGLASS_COEFFICIENT, help="the ball's QH/QM, replacing its own (its file's, "
                "else 0.1)"),
        SFS,
        PRECISION,
    ),
    build=_build_bbs, run=_run_bbs, describe=describe.describe_bbs, history="history.csv",
)  # fmt: skip

#: Every virtual test on the protocol, keyed by the name users type.
LAB_TESTS: dict[str, LabTest] = {
    test.name: test
    for test in (
        _impact_test("ccor", "CCOR and dynamic stiffness against the 2.63-in half-cylinder "
                     "(ASTM F2845)", "95 mph"),
        _impact_test("cor", "COR against a rigid flat wall (ASTM F1887)", "60 mph"),
        COMPRESSION, PROPS, MODAL, BARREL, BBS,
    )
}  # fmt: skip


# --- the subjects ---------------------------------------------------------------------------------

#: What each subject is when none is named: the embedded ball and bat of the seed study.
SUBJECT_DEFAULTS = {"ball": "type1", "bat": "default"}

#: One line for each subject's option.
SUBJECT_HELP = {
    "ball": "embedded ball (type1, type2: the seed's; type1-fit, type2-fit: the model of "
    "record's; foam057, foam083) or a ball TOML file",
    "bat": "embedded bat (default: the reconstruction; fitted: the model of record's) or a bat "
    "TOML file",
}


def load_subject(kind: str, given: Any) -> Any:
    """A ball or bat spec from a name, a path or an already loaded spec."""
    from batball.specs import BallSpec, BatSpec, load_ball_spec, load_bat_spec

    spec_type, load = {"ball": (BallSpec, load_ball_spec), "bat": (BatSpec, load_bat_spec)}[kind]
    if isinstance(given, spec_type):
        return given
    if not isinstance(given, str | Path):
        raise SpecError(kind, given, f"an embedded {kind}'s name, a TOML file's path or a "
                        f"{spec_type.__name__}")  # fmt: skip
    return load(given)


def parse_options(options: tuple[Option, ...], values: Any) -> dict[str, Any]:
    """The parsed values (SI) of ``options`` read by name from ``values`` (an argparse
    namespace or any object with those attributes); a missing one takes its default."""
    return {o.name: o.parse(getattr(values, o.name, o.default)) for o in options}
