"""One protocol for every virtual test: declared options -> a frozen Setup -> a run -> a summary.

Each test is a :class:`LabTest`: the subjects it needs (a ball, a bat or both), its options, each
declared once as an :class:`Option` (name, default as a person writes it, unit dimension, what is
allowed, help), a ``build`` that turns the parsed option values into the test's frozen Setup, and a
``run`` that runs (or reuses) it in the results store. The command line, the Python API
(:mod:`batball.api`) and anything else that drives tests read these declarations, so an option and
its default exist in one place and one name means one thing in every test.

Values are parsed at this edge: a dimensioned option takes ``"95 mph"`` or a pint quantity and is
stored in SI; a bare number for it is an error naming the option.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from batball.errors import SpecError
from batball.units import parse_quantity

#: The kinds of option value: a quantity with a unit, an integer, a real number, one word of a
#: fixed set, an on/off flag.
OPTION_KINDS = ("quantity", "int", "float", "choice", "flag")


@dataclass(frozen=True)
class Option:
    """One option of a virtual test, declared once for the CLI, the API and the store.

    Attributes:
        name: the Python keyword (``axial_size``); the command line spells it ``--axial-size``
            (an on-by-default flag ``--no-<name>``) and errors name it that way.
        default: the default as a person writes it (``"95 mph"``, ``12``, ``False``); None where
            the test's own default applies.
        help: one line for ``--help`` and the API's docstrings.
        kind: one of :data:`OPTION_KINDS`.
        dimension: for a quantity, a dimension name of :data:`batball.units.DIMENSIONS`.
        choices: for a choice, the allowed words.
        words: for a quantity, words accepted in place of a value and what each stands for
            (``mass_scaling``: ``{"barrel": "barrel", "off": None}``).
        check: a predicate on the parsed value (SI), with ``allowed`` saying it in words.
        aliases: older command-line spellings that still work (``--ball-divisions``).
    """

    name: str
    default: Any
    help: str
    kind: str = "quantity"
    dimension: str | None = None
    choices: tuple[str, ...] = ()
    words: Mapping[str, Any] | None = None
    check: Callable[[Any], bool] | None = None
    allowed: str = ""
    aliases: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in OPTION_KINDS:
            raise ValueError(f"option {self.name}: kind {self.kind!r} not in {OPTION_KINDS}")
        if (self.kind == "quantity") != (self.dimension is not None):
            raise ValueError(f"option {self.name}: a quantity, and only it, has a dimension")

    @property
    def field(self) -> str:
        """The option as errors and the command line name it: ``axial-size``."""
        return self.name.replace("_", "-")

    @property
    def flags(self) -> tuple[str, ...]:
        """The command-line spellings: ``--axial-size`` (``--no-bulk-viscosity`` for a flag
        that is on by default), then the aliases."""
        if self.kind == "flag" and self.default:
            return (f"--no-{self.field}", *self.aliases)
        return (f"--{self.field}", *self.aliases)

    @property
    def help_line(self) -> str:
        """The help with the default, as ``--help`` and the API's docstrings show it."""
        if self.kind == "flag":
            return self.help + (" (on by default)" if self.default else " (off by default)")
        return self.help + ("" if self.default is None else f" (default {self.default!r})")

    @property
    def default_value(self) -> Any:
        """The default, parsed (SI for a quantity)."""
        return self.parse(self.default)

    def with_default(self, default: Any, help: str | None = None) -> Option:
        """The same option with another default (a test's own speed, say)."""
        return replace(self, default=default, help=self.help if help is None else help)

    def parse(self, value: Any) -> Any:
        """``value`` checked and converted: SI float for a quantity, int, float, str or bool.

        Raises:
            SpecError: naming the option, the value and what is allowed.
        """
        if value is None and self.default is None:
            return None
        parsed = self._convert(value)
        if self.check is not None and parsed is not None and not self.check(parsed):
            raise SpecError(self.field, value, self.allowed)
        return parsed

    def _convert(self, value: Any) -> Any:
        if self.kind == "quantity":
            assert self.dimension is not None
            if not self.words:
                return parse_quantity(value, self.dimension, field=self.field)
            if isinstance(value, str) and value.strip().lower() in self.words:
                return self.words[value.strip().lower()]
            try:
                return parse_quantity(value, self.dimension, field=self.field)
            except SpecError as error:
                words = " or ".join(repr(w) for w in self.words)
                raise SpecError(self.field, value, f"{words}, or {error.allowed}") from None
        if self.kind == "flag":
            if not isinstance(value, bool | np.bool_):
                raise SpecError(self.field, value, "True or False")
            return bool(value)
        if self.kind == "choice":
            if value not in self.choices:
                raise SpecError(self.field, value, "one of " + ", ".join(self.choices))
            return value
        return _number(value, integer=self.kind == "int", field=self.field)


def _number(value: Any, *, integer: bool, field: str) -> int | float:
    """An int (``integer``) or a finite float from a number or its text; bools are refused."""
    allowed = "an integer" if integer else "a finite number"
    if isinstance(value, bool | np.bool_):
        raise SpecError(field, value, allowed)
    if isinstance(value, np.integer | np.floating):
        value = value.item()
    if not isinstance(value, int | float | str):
        raise SpecError(field, value, allowed)
    try:
        number = int(value) if integer and not isinstance(value, float) else float(value)
    except ValueError:
        raise SpecError(field, value, allowed) from None
    if integer and isinstance(value, float):
        raise SpecError(field, value, allowed)
    if not math.isfinite(number):
        raise SpecError(field, value, allowed)
    return number


#: The share of the impact's kinetic energy that hourglass control may take before a run is
#: flagged, and the largest energy balance error (LS-DYNA practice: hourglass energy under 10 %,
#: the balance within 1 %).
HOURGLASS_LIMIT = 0.10
BALANCE_LIMIT = 0.01
#: The largest contact penetration, as a fraction of the ball's deflection, before a run is
#: flagged: beyond it the penalty's compliance is a visible part of the measured deformation.
PENETRATION_LIMIT = 0.05


def run_warnings(summary: Mapping[str, Any]) -> list[str]:
    """What a careful analyst would be told about a finished run: hourglass energy over
    :data:`HOURGLASS_LIMIT` of the initial kinetic energy, an energy balance error over
    :data:`BALANCE_LIMIT`, a contact penetration over :data:`PENETRATION_LIMIT` of the ball's
    deflection. Each a sentence with its number and what to do."""
    warnings = []
    hourglass = summary.get("hourglass_energy_fraction")
    if isinstance(hourglass, float) and hourglass > HOURGLASS_LIMIT:
        warnings.append(
            f"hourglass energy is {100 * hourglass:.1f} % of the initial kinetic energy (over "
            f"{100 * HOURGLASS_LIMIT:g} %): refine the mesh or use a stiffness hourglass control"
        )
    balance = summary.get("energy_balance_error")
    if isinstance(balance, float) and balance > BALANCE_LIMIT:
        warnings.append(
            f"the energy balance error is {100 * balance:.2f} % (over {100 * BALANCE_LIMIT:g} %): "
            "lower the time-step scale or check the contact"
        )
    penetration = summary.get("max_penetration_in")
    deflection = summary.get("max_deflection_in")
    if (
        isinstance(penetration, float)
        and isinstance(deflection, float)
        and penetration > PENETRATION_LIMIT * deflection
    ):
        share = f"{100 * penetration / deflection:.1f} %" if deflection > 0 else "more than all"
        warnings.append(
            f"the ball sank {penetration:.4f} in into the target, {share} of its "
            f"{deflection:.4f}-in deflection (over {100 * PENETRATION_LIMIT:g} %): the contact "
            "penalty is too soft; raise the penalty scale (--sfs)"
        )
    return warnings


#: What a test's ``run`` gets: the loaded subjects by name ("ball", "bat"), the Setup, the
#: results store, whether a stored run may be reused and a progress callback over simulated time.
RunFunction = Callable[..., tuple[dict[str, Any], Path]]


@dataclass(frozen=True)
class LabTest:
    """A virtual test on the protocol.

    Attributes:
        name: the name users type (``"ccor"``): the CLI subcommand and the API function.
        help: one line: what the test measures, and its standard.
        subjects: what it tests, in order: ``("ball",)``, ``("bat",)`` or ``("bat", "ball")``.
        options: its options, in the order ``--help`` lists them.
        build: parsed option values (by name, SI) -> the test's frozen Setup.
        run: ``run(subjects, setup, *, runs_dir, reuse, progress)`` -> (summary, run folder).
        describe: a summary -> a short report for a person, every number with its unit.
        history: the run folder's time-history (or curve) file, if the test writes one.
        span: the Setup -> (simulated time the run may reach, "ms" or "s") for a progress bar;
            None for a test without a time loop.
    """

    name: str
    help: str
    subjects: tuple[str, ...]
    options: tuple[Option, ...]
    build: Callable[[Mapping[str, Any]], Any]
    run: RunFunction
    describe: Callable[[dict[str, Any]], str]
    history: str | None = None
    span: Callable[[Any], tuple[float, str]] | None = None

    def option(self, name: str) -> Option:
        """The option called ``name``; a SpecError listing the test's options otherwise."""
        for option in self.options:
            if option.name == name:
                return option
        names = ", ".join(o.name for o in self.options)
        raise SpecError("option", name, f"an option of {self.name}: {names}")

    def execute(self, subjects: Mapping[str, Any], setup: Any,
                **store: Any) -> tuple[dict[str, Any], Path]:  # fmt: skip
        """``run``, with the run's :func:`run_warnings` under ``"warnings"`` in the summary (a
        list, empty when there is nothing to say)."""
        summary, folder = self.run(subjects, setup, **store)
        return {**summary, "warnings": run_warnings(summary)}, folder

    def setup(self, **values: Any) -> Any:
        """The frozen Setup of ``values`` (option name -> value as a person gives it; a missing
        option takes its declared default); every value checked before anything runs."""
        for name in values:
            self.option(name)
        parsed = {o.name: o.parse(values.get(o.name, o.default)) for o in self.options}
        return self.build(parsed)
