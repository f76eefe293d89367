"""The comparison tables: the seed's numbers as printed, signed differences, the verdict."""

from __future__ import annotations

import pytest

from batball.report.seed_comparison import (
    ComparisonRow,
    ComparisonTable,
    comparison_tables,
    percent_difference,
    table_records,
    verdict,
)
from batball.specs import load_seed_tables


def tables_by_id() -> dict[str, object]:
    return {t.id: t for t in comparison_tables(load_seed_tables(), refit=True)}


def row(table_id: str, key: str) -> ComparisonRow:
    table = tables_by_id()[table_id]
    return next(r for r in table.rows if r.key == key)  # type: ignore[attr-defined]


def test_model_of_record_then_solver_check_then_refit_in_page_order() -> None:
    record = ["table1", "table2", "table3", "table5", "table6", "table7", "table8", "table9",
              "compression"]  # fmt: skip
    check = ["table4", "check_impact", "check_table9"]
    tables = comparison_tables(load_seed_tables())
    assert [t.id for t in tables] == record + check
    assert [t.section for t in tables] == ["record"] * len(record) + ["check"] * len(check)
    refit = comparison_tables(load_seed_tables(), refit=True)
    assert [t.id for t in refit] == record + check + ["calibrated_type1", "calibrated_type2"]
    assert {t.section for t in refit[-2:]} == {"refit"}


def roles(table_id: str) -> dict[str, str]:
    return {r.key: r.role for r in tables_by_id()[table_id].rows}  # type: ignore[attr-defined]


def test_each_row_carries_the_role_the_model_of_record_gives_it() -> None:
    # the bat was fitted to Table 1 and the hoop modes, the balls to Tables 5-8; nothing to
    # Table 2, the bending modes or Table 9 (docs/fidelity.md)
    assert set(roles("table1").values()) == {"fitted"}
    assert set(roles("table2").values()) == {"predicted"}
    assert roles("table3") == {"modal/bending_1": "predicted", "modal/bending_2": "predicted",
                               "modal/hoop_1": "fitted", "modal/hoop_2": "fitted"}  # fmt: skip
    for n in (5, 6, 7, 8):
        assert set(roles(f"table{n}").values()) == {"fitted"}
    assert set(roles("table9").values()) == {"predicted"}
    for table_id in ("table4", "check_impact", "check_table9"):
        assert set(roles(table_id).values()) == {"check"}
        assert all(key.startswith("check/") for key in roles(table_id))
    assert len(roles("check_impact")) == 16 and len(roles("check_table9")) == 4


def test_calibrated_ball_rows_carry_the_seed_values_of_tables_5_to_8() -> None:
    tables = tables_by_id()
    impact = {r.key: r for n in (5, 6, 7, 8) for r in tables[f"table{n}"].rows}  # type: ignore[attr-defined]
    for ball in ("type1", "type2"):
        rows = tables[f"calibrated_{ball}"].rows  # type: ignore[attr-defined]
        constants = [r for r in rows if r.key.startswith("calibrated/material/")]
        assert [r.seed_fe for r in constants] == [
            r.seed_fe for r in tables["table4"].rows if f"/{ball}/" in r.key  # type: ignore[attr-defined]
        ]  # the seed's Table 4 constants beside the refitted ones
        rows = [r for r in rows if r not in constants]
        assert len(rows) == 8
        for r in rows:
            same = impact[r.key.removeprefix("calibrated/")]
            assert ball in same.key
            assert (r.experiment, r.seed_fe, r.unit, r.digits) == (
                same.experiment, same.seed_fe, same.unit, same.digits,
            )  # fmt: skip


@pytest.mark.parametrize(
    ("table_id", "key", "experiment", "lsdyna"),
    [  # as printed in the seed's Tables 1, 2, 3, 6, 8 and 9, in the display units
        ("table1", "props/moi", 6920, 7020),
        ("table2", "barrel/preload", 186, 155),
        ("table3", "modal/bending_2", 555, 468),
        ("table6", "ds/type1/95mph", 7190, 6153),
        ("table8", "contact/type2/110mph", 1.20, 1.30),
        ("table9", "bbs/type2/95mph", 95.2, 90.1),
    ],
)
def test_seed_values_are_shown_in_the_seeds_units(
    table_id: str, key: str, experiment: float, lsdyna: float
) -> None:
    r = row(table_id, key)
    assert r.experiment == pytest.approx(experiment, rel=1e-9)
    assert r.seed_fe == pytest.approx(lsdyna, rel=1e-9)


def test_lsdyna_differences_match_the_seeds_printed_columns() -> None:
    # The seed prints |exp - fe| / exp; Table 8 type 2 at 95 mph repeats type 1's 16.50 (typo).
    seed = load_seed_tables()
    printed = {"ccor": "ccor_pct_printed", "ds": "ds_pct_printed", "peak": "peak_pct_printed",
               "contact": "contact_pct_printed"}  # fmt: skip
    for table in (tables_by_id()[f"table{n}"] for n in (5, 6, 7, 8)):
        for record in table_records(table, {}):
            quantity, ball, speed = str(record["key"]).split("/")
            seed_row = seed.ball_impact(ball, int(speed.removesuffix("mph")))
            expected = getattr(seed_row, printed[quantity])
            if (quantity, ball, speed) == ("contact", "type2", "95mph"):
                expected = 15.70
            assert abs(record["lsdyna_vs_experiment_pct"]) == pytest.approx(expected, abs=0.3)


def test_percent_difference_is_signed_and_none_without_a_value() -> None:
    assert percent_difference(110.0, 100.0) == pytest.approx(10.0)
    assert percent_difference(90.0, 100.0) == pytest.approx(-10.0)
    assert percent_difference(None, 100.0) is None
    assert percent_difference(1.0, None) is None


def test_verdict_compares_distances_to_the_experiment_at_shown_precision() -> None:
    r = ComparisonRow("x", "x", "lbf", experiment=100.0, seed_fe=90.0, digits=0)
    assert verdict(r, 105.0) == "closer"
    assert verdict(r, 111.0) == "farther"
    assert verdict(r, 110.2) == "tie"  # shows as 110: as far as LS-DYNA's 90
    assert verdict(r, None) is None
    no_experiment = ComparisonRow("x", "x", "psi", experiment=None, seed_fe=750.0, digits=0)
    assert verdict(no_experiment, 750.0) is None


def test_no_verdict_for_a_solver_check_or_an_indicative_value() -> None:
    r = ComparisonRow("x", "x", "lbf", experiment=100.0, seed_fe=90.0, digits=0)
    assert verdict(r, 105.0, indicative=True) is None  # a coarse mesh's value
    check = ComparisonRow("check/x", "x", "lbf", 100.0, 90.0, 0, "check")
    assert verdict(check, 105.0) is None  # compared with LS-DYNA, not with the experiment
    (record,) = table_records(
        ComparisonTable("t", "t", "ccor", (check,), section="check"), {"check/x": 99.0}
    )
    assert record["role"] == "check" and record["verdict"] is None
    assert record["batball_vs_lsdyna_pct"] == pytest.approx(10.0)


def test_records_leave_unmeasured_rows_empty() -> None:
    table = tables_by_id()["table9"]
    records = table_records(table, {"bbs/type1/95mph": 96.0})  # type: ignore[arg-type]
    assert records[0]["batball"] == 96.0
    assert records[0]["verdict"] == "closer"  # 0.5 mph off against LS-DYNA's 0.7
    assert records[0]["role"] == "predicted" and records[0]["indicative"] is False
    coarse = table_records(table, {"bbs/type1/95mph": 96.0}, indicative=True)  # type: ignore[arg-type]
    assert coarse[0]["verdict"] is None and coarse[0]["indicative"] is True
    assert all(r["batball"] is None and r["verdict"] is None for r in records[1:])
