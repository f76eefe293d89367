"""The seed study's Tables 1-9 laid out for comparison: experiment, the seed's LS-DYNA, batball.

Each table is a list of rows; a row names one measured quantity (``"ccor/type1/95mph"``) with its
display unit and the seed's two published values. batball's values are looked up by the same key in
what the reproduction's runs measured; a key nobody measured stays empty and the report says "not
yet available". Percent differences are signed, ``100 (value - experiment) / experiment``; the seed
prints unsigned ones.

Source: ``shared/seed/000_25d27d381ae2ff56.txt``, Tables 1-9 (values in ``specs/data``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from batball.specs.seed import SeedTables
from batball.units import to_unit

#: How batball's value compares with the seed's LS-DYNA value, both against the experiment.
Verdict = Literal["closer", "tie", "farther"]

#: The ball-impact cases of Tables 5-9: (ball, inbound speed in mph).
BALL_CASES: tuple[tuple[str, int], ...] = (
    ("type1", 95),
    ("type1", 110),
    ("type2", 95),
    ("type2", 110),
)

#: The balls ``batball reproduce`` calibrates (one table each after Table 8).
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
    """

    key: str
    label: str
    unit: str
    experiment: float | None
    seed_fe: float | None
    digits: int


@dataclass(frozen=True)
class ComparisonTable:
    """A seed table (or batball's extra table) and the registry test that fills it."""

    id: str
    title: str
    test: str
    rows: tuple[ComparisonRow, ...]
    note: str = ""


def percent_difference(value: float | None, experiment: float | None) -> float | None:
    """``100 (value - experiment) / experiment``, or None when either is missing or exp is 0."""
    if value is None or experiment is None or experiment == 0.0:
        return None
    return 100.0 * (value - experiment) / experiment


def verdict(row: ComparisonRow, batball: float | None) -> Verdict | None:
    """Whether batball is closer to the experiment than the seed's LS-DYNA, at shown precision.

    Both values are rounded to the row's shown decimals first, so a difference the page cannot
    show is a tie. None when the experiment, the LS-DYNA value or batball's value is missing.
    """
    if batball is None or row.experiment is None or row.seed_fe is None:
        return None
    ours = abs(round(batball, row.digits) - round(row.experiment, row.digits))
    theirs = abs(round(row.seed_fe, row.digits) - round(row.experiment, row.digits))
    if round(ours - theirs, row.digits + 3) == 0.0:
        return "tie"
    return "closer" if ours < theirs else "farther"


def _pair_row(key: str, label: str, unit: str, exp: float, fe: float, digits: int) -> ComparisonRow:
    """A row from two SI values, converted to ``unit``."""
    return ComparisonRow(
        key,
        label,
        unit,
        to_unit(exp, unit) if unit else exp,
        to_unit(fe, unit) if unit else fe,
        digits,
    )


def table1(seed: SeedTables) -> ComparisonTable:
    """Table 1: weight, MOI about the 6-in pivot, balance point from the knob end."""
    bat = seed.bat
    rows = (
        _pair_row("props/weight", "weight", "oz", bat.weight_exp, bat.weight_fe, 2),
        _pair_row("props/moi", "MOI about the 6-in pivot", "oz*in**2", bat.moi_exp, bat.moi_fe, 0),
        _pair_row(
            "props/balance_point",
            "balance point from the knob end",
            "in",
            bat.balance_point_exp,
            bat.balance_point_fe,
            2,
        ),
    )
    return ComparisonTable("table1", "Table 1. Bat physical properties (ASTM F2398)", "props", rows)


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
    rows = tuple(_pair_row(f"modal/{k}", label, "Hz", exp, fe, 0) for k, label, exp, fe in pairs)
    return ComparisonTable("table3", "Table 3. Free-free modal analysis of the bat", "modal", rows)


def table4(seed: SeedTables) -> ComparisonTable:
    """Table 4: the MAT_006 parameters; batball's column is the parameters its runs used."""
    rows = []
    for ball, material in seed.ball_materials:
        for name, unit, label in MATERIAL_PARAMETERS:
            value = to_unit(material.values[name], unit)
            rows.append(
                ComparisonRow(f"material/{ball}/{name}", f"{ball}: {label}", unit, None, value, 0)
            )
    note = (
        "Fitted constants, not measurements: the seed's hand-tuned MAT_006 constants and the "
        "ones batball calibrate fitted to the seed's experiment columns of Tables 5-8 (the "
        "calibrated balls' own CCOR, DS, peak load and contact time follow Table 8). The CCOR "
        "runs of Tables 5-8 use the seed's constants (see Inputs)."
    )
    return ComparisonTable(
        "table4",
        "Table 4. MAT_006 parameters of ball types 1 and 2",
        "calibrate",
        tuple(rows),
        note,
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
            )
        )
    full_title = f"Table {number}. {title} against the rigid half-cylinder (ASTM F2845)"
    return ComparisonTable(f"table{number}", full_title, "ccor", tuple(rows))


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
    rows = []
    for quantity, label, unit, digits in IMPACT_QUANTITIES:
        for name, mph in BALL_CASES:
            if name != ball:
                continue
            s = seed.ball_impact(ball, mph)
            exp, fe = getattr(s, f"{quantity}_exp"), getattr(s, f"{quantity}_fe")
            key = f"calibrated/{quantity}/{ball}/{mph}mph"
            rows.append(_pair_row(key, f"{label} at {mph} mph", unit, exp, fe, digits))
    note = (
        f"batball: {ball} with the constants of Table 4 fitted by batball calibrate (MAT_006, "
        "all eight targets), run on the calibration's last mesh; the seed's LS-DYNA column is "
        "its hand-tuned ball (Tables 5-8)."
    )
    return ComparisonTable(
        f"calibrated_{ball}",
        f"Calibrated ball {ball}: CCOR, DS, peak load, contact time against the seed",
        "calibrate",
        tuple(rows),
        note,
    )


def table9(seed: SeedTables) -> ComparisonTable:
    """Table 9: batted-ball speed at the 6-in location of the bat."""
    rows = []
    for ball, mph in BALL_CASES:
        s = seed.batted_ball_speed(ball, mph)
        rows.append(
            _pair_row(f"bbs/{ball}/{mph}mph", f"{ball} at {mph} mph", "mph", s.bbs_exp, s.bbs_fe, 1)
        )
    return ComparisonTable(
        "table9",
        "Table 9. Batted-ball speed, 6-in impact location (ASTM F2219)",
        "bbs",
        tuple(rows),
    )


def compression_table() -> ComparisonTable:
    """batball's ball compression (ASTM F1888); the seed publishes no compression values."""
    rows = tuple(
        ComparisonRow(f"compression/{ball}", f"{ball}: compression force", "lbf", None, None, 0)
        for ball in ("type1", "type2")
    )
    note = "The seed reports no compression measurements: batball's values stand alone."
    return ComparisonTable(
        "compression", "Ball compression (ASTM F1888; not in the seed)", "compression", rows, note
    )


def comparison_tables(seed: SeedTables) -> tuple[ComparisonTable, ...]:
    """All tables of the report in page order: Tables 1-8, the calibrated balls, Table 9, then
    ball compression."""
    return (
        table1(seed),
        table2(seed),
        table3(seed),
        table4(seed),
        *(ball_impact_table(seed, n) for n in (5, 6, 7, 8)),
        *(calibrated_ball_table(seed, ball) for ball in CALIBRATED_BALLS),
        table9(seed),
        compression_table(),
    )


def table_records(
    table: ComparisonTable, values: Mapping[str, float]
) -> list[dict[str, float | str | None]]:
    """One dict per row (for CSV and JSON): the seed's values, batball's and the differences."""
    records = []
    for row in table.rows:
        ours = values.get(row.key)
        records.append(
            {
                "key": row.key,
                "quantity": row.label,
                "unit": row.unit,
                "experiment": row.experiment,
                "seed_lsdyna": row.seed_fe,
                "batball": ours,
                "batball_vs_experiment_pct": percent_difference(ours, row.experiment),
                "lsdyna_vs_experiment_pct": percent_difference(row.seed_fe, row.experiment),
                "verdict": verdict(row, ours),
            }
        )
    return records
