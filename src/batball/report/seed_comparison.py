"""The seed study's Tables 1-9 laid out for comparison: experiment, the seed's LS-DYNA, batball.

Each table is a list of rows; a row names one measured quantity (``"ccor/type1/95mph"``) with its
display unit, the seed's two published values and its role:

* ``fitted``: a target of a fit the model of record used (Table 1 and the hoop modes for the bat,
  Tables 5-8 for the balls). Agreement shows the fit worked; it predicts nothing.
* ``predicted``: used by no fit (Table 2, the bending modes, Table 9). Only these say how well
  batball predicts the lab.
* ``check``: the seed's own constants run through batball (section ``"check"``, keys
  ``"check/..."``), compared with the seed's LS-DYNA column: solver against solver.

batball's values are looked up by the same key in what the reproduction's runs measured; a key
nobody measured stays empty and the report says why. Percent differences are signed,
``100 (value - experiment) / experiment``; the seed prints unsigned ones. A verdict (closer to the
experiment than the seed's LS-DYNA, as close, farther) is given only to fitted and predicted rows
on the converged meshes: a coarse mesh's value is indicative.

Source: the seed study ("Batted-Ball Performance of a Composite Softball Bat as a Function of
Ball Type"), Tables 1-9 (values in ``specs/data``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from batball.specs.seed import SeedTables
from batball.units import to_unit

#: How batball's value compares with the seed's LS-DYNA value, both against the experiment.
Verdict = Literal["closer", "tie", "farther"]

#: What a compared number is (module docstring).
Role = Literal["fitted", "predicted", "check"]

#: Where a table stands on the page: the model of record, the solver check, or a refit of the
#: balls that ``batball reproduce --calibrate`` adds.
Section = Literal["record", "check", "refit"]

#: The ball-impact cases of Tables 5-9: (ball, inbound speed in mph).
BALL_CASES: tuple[tuple[str, int], ...] = (
    ("type1", 95),
    ("type1", 110),
    ("type2", 95),
    ("type2", 110),
)

#: The balls ``batball reproduce --calibrate`` refits (one table each, in the refit section).
CALIBRATED_BALLS: tuple[str, ...] = ("type1", "type2")

#: Table 4's MAT_006 parameters: (name, display unit, label).
MATERIAL_PARAMETERS: tuple[tuple[str, str, str], ...] = (
    ("bulk_modulus", "psi", "bulk modulus K"),
    ("g0", "psi", "short-time shear modulus G0"),
    ("g_inf", "psi", "long-time shear modulus G∞"),
    ("beta", "1/s", "decay constant β"),
)


@dataclass(frozen=True)
class ComparisonRow:
    """One quantity of a seed table, in display units.

    Attributes:
        key: what batball's runs report it under, e.g. ``"ds/type2/110mph"``.
        label: the row's name on the page.
        unit: display unit (``"lbf/in"``; ``""`` for a bare number).
        experiment: the seed's measurement, or None where the seed has none.
        seed_fe: the seed's LS-DYNA value, or None.
        digits: decimals shown.
        role: ``"fitted"``, ``"predicted"`` or ``"check"`` (module docstring).
    """

    key: str
    label: str
    unit: str
    experiment: float | None
    seed_fe: float | None
    digits: int
    role: Role = "predicted"


@dataclass(frozen=True)
class ComparisonTable:
    """A seed table (or batball's extra table) and the registry test that fills it."""

    id: str
    title: str
    test: str
    rows: tuple[ComparisonRow, ...]
    note: str = ""
    section: Section = "record"


def percent_difference(value: float | None, experiment: float | None) -> float | None:
    """``100 (value - experiment) / experiment``, or None when either is missing or exp is 0."""
    if value is None or experiment is None or experiment == 0.0:
        return None
    return 100.0 * (value - experiment) / experiment


def verdict(
    row: ComparisonRow, batball: float | None, *, indicative: bool = False
) -> Verdict | None:
    """Whether batball is closer to the experiment than the seed's LS-DYNA, at shown precision.

    Both values are rounded to the row's shown decimals first, so a difference the page cannot
    show is a tie. None when the experiment, the LS-DYNA value or batball's value is missing, for
    a solver-check row (it is compared with LS-DYNA, not with the experiment) and for an
    ``indicative`` value (a mesh coarser than the converged one).
    """
    if batball is None or row.experiment is None or row.seed_fe is None:
        return None
    if indicative or row.role == "check":
        return None
    ours = abs(round(batball, row.digits) - round(row.experiment, row.digits))
    theirs = abs(round(row.seed_fe, row.digits) - round(row.experiment, row.digits))
    if round(ours - theirs, row.digits + 3) == 0.0:
        return "tie"
    return "closer" if ours < theirs else "farther"


def _pair_row(key: str, label: str, unit: str, exp: float, fe: float, digits: int,
              role: Role = "predicted") -> ComparisonRow:  # fmt: skip
    """A row from two SI values, converted to ``unit``."""
    return ComparisonRow(
        key,
        label,
        unit,
        to_unit(exp, unit) if unit else exp,
        to_unit(fe, unit) if unit else fe,
        digits,
        role,
    )


def table1(seed: SeedTables) -> ComparisonTable:
    """Table 1: weight, MOI about the 6-in pivot, balance point from the knob end."""
    bat = seed.bat
    rows = (
        _pair_row("props/weight", "weight", "oz", bat.weight_exp, bat.weight_fe, 2, "fitted"),
        _pair_row("props/moi", "MOI about the 6-in pivot", "oz*in**2", bat.moi_exp, bat.moi_fe, 0,
                  "fitted"),  # fmt: skip
        _pair_row(
            "props/balance_point",
            "balance point from the knob end",
            "in",
            bat.balance_point_exp,
            bat.balance_point_fe,
            2,
            "fitted",
        ),
    )
    note = (
        "Fitted: the bat's end-cap mass and two ply thicknesses were fitted to these three "
        "values (batball fit-bat); the shell mesh's discretisation is all that can move them."
    )
    return ComparisonTable(
        "table1", "Table 1. Bat physical properties (ASTM F2398)", "props", rows, note
    )


def table2(seed: SeedTables) -> ComparisonTable:
    """Table 2: barrel compression preload and final load."""
    b = seed.barrel
    rows = (
        _pair_row(
            "barrel/preload", "preload (first 0.02 in)", "lbf", b.preload_exp, b.preload_fe, 0
        ),
        _pair_row(
            "barrel/final_load",
            "final load (additional 0.05 in)",
            "lbf",
            b.final_load_exp,
            b.final_load_fe,
            0,
        ),
    )
    return ComparisonTable(
        "table2", "Table 2. Barrel compression with the insert (ASTM F2844)", "barrel", rows
    )


def table3(seed: SeedTables) -> ComparisonTable:
    """Table 3: the first two free-free bending and hoop frequencies."""
    m = seed.modal
    pairs = (
        ("bending_1", "first bending", m.bending_1_exp, m.bending_1_fe),
        ("bending_2", "second bending", m.bending_2_exp, m.bending_2_fe),
        ("hoop_1", "first hoop", m.hoop_1_exp, m.hoop_1_fe),
        ("hoop_2", "second hoop", m.hoop_2_exp, m.hoop_2_fe),
    )
    rows = tuple(
        _pair_row(f"modal/{k}", label, "Hz", exp, fe, 0, "fitted" if k.startswith("hoop") else
                  "predicted")
        for k, label, exp, fe in pairs
    )  # fmt: skip
    note = (
        "The hoop frequencies are fitted (the barrel's carbon braid angle, batball fit-bat --to "
        "hoop); the bending frequencies are predicted."
    )
    return ComparisonTable(
        "table3", "Table 3. Free-free modal analysis of the bat", "modal", rows, note
    )


def table4(seed: SeedTables) -> ComparisonTable:
    """Table 4: the seed's MAT_006 constants; batball's column is what its check runs used."""
    rows = []
    for ball, material in seed.ball_materials:
        for name, unit, label in MATERIAL_PARAMETERS:
            value = to_unit(material.values[name], unit)
            rows.append(ComparisonRow(f"check/material/{ball}/{name}", f"{ball}: {label}", unit,
                                      None, value, 0, "check"))  # fmt: skip
    note = (
        "Hand-tuned constants, not measurements: the seed's MAT_006 balls, which the solver "
        "check runs as given (batball's column is what its runs used)."
    )
    return ComparisonTable(
        "table4",
        "Table 4. MAT_006 parameters of ball types 1 and 2 (the seed's)",
        "ccor-check",
        tuple(rows),
        note,
        "check",
    )


def ball_impact_table(seed: SeedTables, number: int) -> ComparisonTable:
    """Tables 5-8: CCOR, dynamic stiffness, peak force, contact time for the four cases."""
    quantity, label, unit, digits, title = {
        5: ("ccor", "CCOR", "", 3, "CCOR"),
        6: ("ds", "dynamic stiffness", "lbf/in", 0, "Dynamic stiffness (DS)"),
        7: ("peak", "peak force", "lbf", 0, "Peak load"),
        8: ("contact", "contact time", "ms", 2, "Contact time"),
    }[number]
    rows = []
    for ball, mph in BALL_CASES:
        s = seed.ball_impact(ball, mph)
        exp, fe = getattr(s, f"{quantity}_exp"), getattr(s, f"{quantity}_fe")
        rows.append(
            _pair_row(
                f"{quantity}/{ball}/{mph}mph",
                f"{ball} at {mph} mph ({label})",
                unit,
                exp,
                fe,
                digits,
                "fitted",
            )
        )
    full_title = f"Table {number}. {title} against the rigid half-cylinder (ASTM F2845)"
    note = "Fitted: the model of record's balls were fitted to these experiment values."
    return ComparisonTable(f"table{number}", full_title, "ccor", tuple(rows), note)


#: The ball-impact quantities of Tables 5-8: (key prefix, label, display unit, decimals).
IMPACT_QUANTITIES: tuple[tuple[str, str, str, int], ...] = (
    ("ccor", "CCOR", "", 3),
    ("ds", "dynamic stiffness", "lbf/in", 0),
    ("peak", "peak force", "lbf", 0),
    ("contact", "contact time", "ms", 2),
)


def calibrated_ball_table(seed: SeedTables, ball: str) -> ComparisonTable:
    """The calibrated ``ball``'s own CCOR, DS, peak and contact time at 95 and 110 mph.

    batball's column is what ``batball calibrate`` reports per target: the fitted ball run on
    the calibration's last mesh; experiment and LS-DYNA are the seed's Tables 5-8.
    """
    material = dict(seed.ball_materials)[ball]
    rows = [
        ComparisonRow(f"calibrated/material/{ball}/{name}", f"fitted {label}", unit, None,
                      to_unit(material.values[name], unit), 0, "fitted")
        for name, unit, label in MATERIAL_PARAMETERS
    ]  # fmt: skip
    for quantity, label, unit, digits in IMPACT_QUANTITIES:
        for name, mph in BALL_CASES:
            if name != ball:
                continue
            s = seed.ball_impact(ball, mph)
            exp, fe = getattr(s, f"{quantity}_exp"), getattr(s, f"{quantity}_fe")
            key = f"calibrated/{quantity}/{ball}/{mph}mph"
            rows.append(_pair_row(key, f"{label} at {mph} mph", unit, exp, fe, digits, "fitted"))
    note = (
        f"batball: {ball} refitted here by batball calibrate (MAT_006, all eight targets), run "
        "on the calibration's last mesh; the seed's LS-DYNA column is its hand-tuned ball "
        "(Table 4 for the constants, Tables 5-8 for the measurements)."
    )
    return ComparisonTable(
        f"calibrated_{ball}",
        f"Refitted ball {ball}: CCOR, DS, peak load, contact time against the seed",
        "calibrate",
        tuple(rows),
        note,
        "refit",
    )


def table9(seed: SeedTables) -> ComparisonTable:
    """Table 9: batted-ball speed at the 6-in location of the bat."""
    rows = []
    for ball, mph in BALL_CASES:
        s = seed.batted_ball_speed(ball, mph)
        rows.append(
            _pair_row(f"bbs/{ball}/{mph}mph", f"{ball} at {mph} mph", "mph", s.bbs_exp, s.bbs_fe, 1)
        )
    note = "Predicted: no fit of the model of record saw these values."
    return ComparisonTable(
        "table9",
        "Table 9. Batted-ball speed, 6-in impact location (ASTM F2219)",
        "bbs",
        tuple(rows),
        note,
    )


def check_impact_table(seed: SeedTables) -> ComparisonTable:
    """Tables 5-8 with the seed's Table 4 balls: batball's solver against the seed's LS-DYNA."""
    rows = []
    for quantity, label, unit, digits in IMPACT_QUANTITIES:
        for ball, mph in BALL_CASES:
            s = seed.ball_impact(ball, mph)
            exp, fe = getattr(s, f"{quantity}_exp"), getattr(s, f"{quantity}_fe")
            rows.append(_pair_row(f"check/{quantity}/{ball}/{mph}mph",
                                  f"{ball} at {mph} mph ({label})", unit, exp, fe, digits,
                                  "check"))  # fmt: skip
    note = (
        "The seed's Table 4 balls with the hourglass control that reproduces its LS-DYNA "
        "(IHQ 4, QM 0.01): compare batball with the LS-DYNA column."
    )
    return ComparisonTable("check_impact", "Tables 5-8 with the seed's balls (solver check)",
                           "ccor-check", tuple(rows), note, "check")  # fmt: skip


def check_table9(seed: SeedTables) -> ComparisonTable:
    """Table 9 with the seed's Table 4 balls on the reconstructed bat, against LS-DYNA."""
    rows = []
    for ball, mph in BALL_CASES:
        s = seed.batted_ball_speed(ball, mph)
        rows.append(_pair_row(f"check/bbs/{ball}/{mph}mph", f"{ball} at {mph} mph", "mph",
                              s.bbs_exp, s.bbs_fe, 1, "check"))  # fmt: skip
    note = (
        "The seed's Table 4 balls (IHQ 4, QM 0.01) on the reconstructed bat (the embedded "
        "default bat, fitted to Table 1 only): compare batball with the LS-DYNA column."
    )
    return ComparisonTable("check_table9", "Table 9 with the seed's balls (solver check)",
                           "bbs-check", tuple(rows), note, "check")  # fmt: skip


def compression_table() -> ComparisonTable:
    """batball's ball compression (ASTM F1888); the seed publishes no compression values."""
    rows = tuple(
        ComparisonRow(f"compression/{ball}", f"{ball}: compression force", "lbf", None, None, 0)
        for ball in ("type1", "type2")
    )  # predicted: no fit saw them (and nothing to compare them with)
    note = "The seed reports no compression measurements: batball's values stand alone."
    return ComparisonTable(
        "compression", "Ball compression (ASTM F1888; not in the seed)", "compression", rows, note
    )


def comparison_tables(seed: SeedTables, *, refit: bool = False) -> tuple[ComparisonTable, ...]:
    """All tables of the report in page order: the model of record's Tables 1-3, 5-9 and ball
    compression; the solver check's Table 4, Tables 5-8 and Table 9; with ``refit``, the
    refitted balls."""
    return (
        table1(seed),
        table2(seed),
        table3(seed),
        *(ball_impact_table(seed, n) for n in (5, 6, 7, 8)),
        table9(seed),
        compression_table(),
        table4(seed),
        check_impact_table(seed),
        check_table9(seed),
        *((calibrated_ball_table(seed, ball) for ball in CALIBRATED_BALLS) if refit else ()),
    )


def table_records(
    table: ComparisonTable, values: Mapping[str, float], *, indicative: bool = False
) -> list[dict[str, float | str | bool | None]]:
    """One dict per row (for CSV and JSON): the role, the seed's values, batball's, the
    differences and the verdict (None where :func:`verdict` gives none)."""
    records: list[dict[str, float | str | bool | None]] = []
    for row in table.rows:
        ours = values.get(row.key)
        records.append(
            {
                "key": row.key,
                "quantity": row.label,
                "unit": row.unit,
                "role": row.role,
                "indicative": indicative,
                "experiment": row.experiment,
                "seed_lsdyna": row.seed_fe,
                "batball": ours,
                "batball_vs_experiment_pct": percent_difference(ours, row.experiment),
                "lsdyna_vs_experiment_pct": percent_difference(row.seed_fe, row.experiment),
                "batball_vs_lsdyna_pct": percent_difference(ours, row.seed_fe),
                "verdict": verdict(row, ours, indicative=indicative),
            }
        )
    return records
