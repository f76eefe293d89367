"""The report's cells: a batball value coloured by its verdict, or "not yet available"."""

from __future__ import annotations

from batball.report.reproduce_html import batball_cell, display_unit, number, percent
from batball.report.seed_comparison import ComparisonRow

ROW = ComparisonRow("ds/type1/95mph", "type1 at 95 mph", "lbf/in", 7190.0, 6153.0, 0)


def test_batball_cell_is_coloured_by_the_verdict() -> None:
    assert batball_cell(ROW, 7000.0, "").startswith('<td class="closer"')  # 190 off vs 1037
    assert batball_cell(ROW, 5000.0, "").startswith('<td class="farther"')
    assert ">7,000<" in batball_cell(ROW, 7000.0, "")


def test_missing_value_says_not_yet_available_with_the_reason() -> None:
    cell = batball_cell(ROW, None, "the barrel compression test is not built yet")
    assert "not yet available" in cell
    assert 'title="the barrel compression test is not built yet"' in cell
    assert 'class="missing"' in cell


def test_numbers_and_units_as_a_reader_writes_them() -> None:
    assert number(None, 2) == "—"
    assert number(6919.6, 0) == "6,920"
    assert percent(-14.42) == "-14.4 %"
    assert percent(None) == "—"
    assert display_unit("oz*in**2") == "oz·in²"
