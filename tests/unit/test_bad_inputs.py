"""Bad input gets one line naming the field or file, exit 2, and nothing left behind; a deck's
*INCLUDE stays inside the deck's folder and never echoes what it should not have read."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from batball.cli import main
from batball.errors import SpecError
from batball.lsdyna.deck import MAX_FILES, read_keyword_file

BALL = 'name = "{name}"\ncircumference = "12 in"\nmass = "6.5 oz"\n[material]\nlaw = "mat006"\n' \
    'bulk_modulus = "100000 psi"\ng0 = "11000 psi"\ng_inf = "640 psi"\nbeta = "60000 1/s"\n'


def one_line_error(capsys: pytest.CaptureFixture[str], *needles: str) -> str:
    captured = capsys.readouterr()
    assert captured.err.count("\n") == 1 and captured.err.startswith("batball: error: ")
    assert "Traceback" not in captured.err
    for needle in needles:
        assert needle in captured.err, captured.err
    return captured.err


@pytest.mark.parametrize("name", ["two\nlines", "../escape", "a*KEYWORD", "", "x" * 65, "sp ace"])
def test_a_ball_name_that_could_reach_a_deck_or_a_path_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str
) -> None:
    spec = tmp_path / "ball.toml"
    spec.write_text(BALL.format(name=name.replace("\n", "\\n")), encoding="utf-8")
    deck = tmp_path / "out.k"
    assert main(["export", "ccor", "--ball", str(spec), "--divisions", "2", "-o", str(deck)]) == 2
    one_line_error(capsys, "name", "letters, digits")
    assert not deck.exists()


def test_a_spec_that_is_not_utf8_text_names_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    spec = tmp_path / "ball.toml"
    spec.write_bytes(b'name = "t\xff\xfe"\n')
    assert main(["ccor", "--ball", str(spec), "--divisions", "2"]) == 2
    one_line_error(capsys, str(spec), "UTF-8")


@pytest.mark.parametrize("output", ["missing/deck.k", "."])
def test_an_export_path_that_cannot_be_written_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
    output: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["export", "ccor", "--divisions", "2", "-o", output]) == 2
    one_line_error(capsys, output.split("/")[0])
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_a_study_that_is_not_a_study_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    study = tmp_path / "study.db"
    study.write_text("some text, not a database\n")
    args = ["calibrate", "--ball", "type1", "--quick", "--coarse-divisions", "2",
            "--global-points", "1", "--max-evaluations", "2", "--workers", "0",
            "--study", str(study)]  # fmt: skip
    assert main(args) == 2
    one_line_error(capsys, "study file")


def test_an_option_out_of_range_is_refused_before_the_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["ccor", "--contact-threshold", "2", "--divisions", "2", "--runs-dir", str(tmp_path)]
    assert main(args) == 2
    one_line_error(capsys, "contact-threshold")
    assert list(tmp_path.iterdir()) == []  # nothing ran, nothing stored


def test_an_include_outside_the_decks_folder_is_refused_without_reading_it(
    tmp_path: Path,
) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("SECRET-CONTENT\n")
    folder = tmp_path / "deck"
    folder.mkdir()
    deck = folder / "main.k"
    deck.write_text("*KEYWORD\n*INCLUDE\n../secret.txt\n*END\n")
    with pytest.raises(SpecError) as error:
        read_keyword_file(deck)
    assert "*INCLUDE at" in str(error.value) and "the deck's folder" in str(error.value)
    assert "SECRET" not in str(error.value)


def test_a_named_include_root_admits_a_shared_library_and_nothing_outside_it(
    tmp_path: Path,
) -> None:
    library = tmp_path / "library"
    (library / "decks").mkdir(parents=True)
    (library / "parts.k").write_text("*KEYWORD\n*TITLE\nshared parts\n")
    deck = library / "decks" / "main.k"
    deck.write_text("*KEYWORD\n*INCLUDE\n../parts.k\n*END\n")
    with pytest.raises(SpecError):  # the default root is the deck's own folder
        read_keyword_file(deck)
    blocks = read_keyword_file(deck, include_root=library)
    assert [b.name for b in blocks] == ["KEYWORD", "KEYWORD", "TITLE"]
    (tmp_path / "secret.txt").write_text("SECRET-CONTENT\n")
    deck.write_text("*KEYWORD\n*INCLUDE\n../../secret.txt\n*END\n")
    with pytest.raises(SpecError) as error:
        read_keyword_file(deck, include_root=library)
    assert str(library) in str(error.value) and "SECRET" not in str(error.value)
    (tmp_path / "elsewhere").mkdir()
    with pytest.raises(SpecError, match="a folder holding the deck"):  # the deck itself outside
        read_keyword_file(deck, include_root=tmp_path / "elsewhere")


def test_run_names_the_include_root_option_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    deck = tmp_path / "main.k"
    deck.write_text("*KEYWORD\n*END\n")
    assert main(["run", str(deck), "--include-root", str(tmp_path / "missing")]) == 2
    one_line_error(capsys, "include root")


def test_a_file_that_is_not_a_deck_is_never_quoted(tmp_path: Path) -> None:
    other = tmp_path / "notes.txt"
    other.write_text("PRIVATE first line\n*KEYWORD\n")
    deck = tmp_path / "main.k"
    deck.write_text("*KEYWORD\n*INCLUDE\nnotes.txt\n*END\n")
    with pytest.raises(SpecError) as error:
        read_keyword_file(deck)
    assert "notes.txt:1" in str(error.value) and "PRIVATE" not in str(error.value)


def test_includes_that_fan_out_stop_at_the_file_budget(tmp_path: Path) -> None:
    """Ten levels that each include the next ten times would read 10^10 files; the reader stops
    at MAX_FILES, quickly."""
    for level in range(10):
        includes = "*INCLUDE\n" + f"level{level + 1}.k\n" * 10 if level < 9 else ""
        body = "*KEYWORD\n" + includes
        (tmp_path / f"level{level}.k").write_text(body)
    with pytest.raises(SpecError, match=f"at most {MAX_FILES} files"):
        read_keyword_file(tmp_path / "level0.k")


def test_a_ball_that_never_reaches_the_target_says_so_with_the_distance() -> None:
    from batball.errors import SimulationError
    from batball.lab.impact import run_impact
    from batball.models.impact import ImpactSetup
    from batball.specs import load_ball_spec

    setup = ImpactSetup(test="ccor", speed=42.0, divisions=2, gap=0.01, end_time=1e-5)
    with pytest.raises(SimulationError, match=r"never reached the target .* mm travelled"):
        run_impact(load_ball_spec("type1"), setup)


def test_a_deck_run_in_other_units_than_its_header_says_warns(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    deck = tmp_path / "mm.k"
    assert main(["export", "ccor", "--divisions", "2", "--units", "mm-N-ms", "-o", str(deck)]) == 0
    capsys.readouterr()
    assert main(["run", str(deck), "--json"]) == 0  # read as in-lbf-s, the default
    captured = capsys.readouterr()
    assert "header says its units are mm-N-ms" in captured.err
    assert any("--units mm-N-ms" in w for w in json.loads(captured.out)["warnings"])
    assert main(["run", str(deck), "--units", "mm-N-ms", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["warnings"] == []


def test_the_contact_penalty_scale_is_an_option_of_every_test_with_contact(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--sfs (alias --penalty-scale) reaches the contact and is recorded; a stiffer penalty lets
    the ball sink less into the cylinder, so the peak force rises."""
    from batball.lab.registry import LAB_TESTS

    for name in ("ccor", "cor", "compression", "bbs"):
        assert "sfs" in [o.name for o in LAB_TESTS[name].options], name
    base = ["ccor", "--divisions", "3", "--json", "--runs-dir", str(tmp_path)]
    assert main(base) == 0
    soft = json.loads(capsys.readouterr().out)
    assert main([*base, "--penalty-scale", "3"]) == 0
    stiff = json.loads(capsys.readouterr().out)
    assert "contact_sfs" not in soft and stiff["contact_sfs"] == 3.0
    assert stiff["peak_force_lbf"] > soft["peak_force_lbf"]


def test_output_keywords_a_hypermesh_deck_carries_are_read_past_with_a_warning(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    deck = tmp_path / "ccor.k"
    assert main(["export", "ccor", "--divisions", "2", "-o", str(deck)]) == 0
    capsys.readouterr()
    extra = ("*CONTROL_ENERGY\n         2         2         2         2\n"
             "*DATABASE_EXTENT_BINARY\n         0         0         3         1\n*END")  # fmt: skip
    deck.write_text(deck.read_text().replace("*END", extra))
    assert main(["run", str(deck), "--json"]) == 0
    warnings = json.loads(capsys.readouterr().out)["warnings"]
    assert [w.split(" at ")[0] for w in warnings] == ["*CONTROL_ENERGY", "*DATABASE_EXTENT_BINARY"]
    deck.write_text(deck.read_text().replace("*CONTROL_ENERGY", "*CONTROL_SHELL"))
    assert main(["run", str(deck)]) == 2  # a keyword with physics batball cannot honour
    one_line_error(capsys, "*CONTROL_SHELL")
