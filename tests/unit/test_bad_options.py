"""Every option of every test, given a value it cannot take, and every subject that does not
exist: exit 2, one line that names the option, nothing run and nothing written. The cases are
made from the lab registry, so a new option gets its cases too."""

from __future__ import annotations

from pathlib import Path

import pytest

from batball.cli import main
from batball.cli.decks import export_options
from batball.lab.protocol import Option
from batball.lab.registry import LAB_TESTS


def bad_values(option: Option) -> list[str]:
    """Values ``option`` must refuse, by its kind."""
    if option.kind == "quantity":
        wrong_unit = "5 in" if option.dimension == "mass" else "5 kg"
        return ["abc", "5", wrong_unit]  # text, a bare number, another dimension
    if option.kind == "int":
        return ["x", "1.5"]
    if option.kind == "float":
        return ["x", "nan"]
    if option.kind == "choice":
        return ["nope"]
    return []  # a flag takes no value


CASES = [
    pytest.param(test.name, option, value, id=f"{test.name}-{option.field}-{value}")
    for test in LAB_TESTS.values()
    for option in test.options
    for value in bad_values(option)
] + [
    pytest.param(test.name, None, kind, id=f"{test.name}-{kind}")
    for test in LAB_TESTS.values()
    for kind in test.subjects
]


def test_there_are_at_least_a_hundred_cases() -> None:
    assert len(CASES) >= 100


@pytest.mark.parametrize(("test", "option", "value"), CASES)
def test_a_bad_value_is_one_line_naming_the_option_and_nothing_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], test: str, option: Option | None,
    value: str,
) -> None:
    runs = tmp_path / "runs"
    if option is None:  # a subject: neither embedded nor a file
        args, field = [test, f"--{value}", str(tmp_path / "missing.toml")], value
    else:
        args, field = [test, option.flags[0], value], option.field
    assert main([*args, "--runs-dir", str(runs)]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(f"batball: error: {field}") and captured.err.count("\n") == 1
    assert captured.out == ""
    assert not runs.exists()  # checked before anything ran or was stored


EXPORT_CASES = [
    pytest.param(name, option, value, id=f"export-{name}-{option.field}-{value}")
    for name in ("ccor", "cor", "compression", "modal", "barrel", "bbs")
    for option in export_options(name)
    for value in bad_values(option)
]


@pytest.mark.parametrize(("test", "option", "value"), EXPORT_CASES)
def test_export_refuses_a_bad_value_in_one_line_and_writes_no_deck(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], test: str, option: Option, value: str
) -> None:
    deck = tmp_path / "deck.k"
    assert main(["export", test, option.flags[0], value, "-o", str(deck)]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(f"batball: error: {option.field}")
    assert captured.err.count("\n") == 1 and captured.out == ""
    assert not deck.exists()
