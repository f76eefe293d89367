"""The two kinds of failure a user meets: bad input, and a simulation that cannot go on."""

from __future__ import annotations


class SpecError(ValueError):
    """Invalid input: names the field, the value given and what is allowed.

    Args:
        field: dotted path of the offending field, e.g. ``"material.g_inf"``.
        value: the value as the user gave it (or as displayed with its unit).
        allowed: the allowed range or kinds, in words, e.g. ``"0 < g_inf <= g0 (22500 psi)"``.
    """

    def __init__(self, field: str, value: object, allowed: str) -> None:
        self.field = field
        self.value = value
        self.allowed = allowed
        super().__init__(f"{field}: {value!r} is not allowed; expected {allowed}")


class SimulationError(RuntimeError):
    """A numerical failure that stops a run: says where (element, node) and when."""
