"""``batball export TEST`` takes TEST's own options; what a deck cannot hold is refused, and the
bbs deck carries the shells' mass scaling as DT2MS (docs/lsdyna.md)."""

from __future__ import annotations

from pathlib import Path

import pytest

from batball.cli import main
from batball.errors import SpecError
from batball.lab.registry import LAB_TESTS
from batball.lsdyna.bat_bbs import read_bbs_deck
from batball.lsdyna.bat_model import read_bat_deck
from batball.lsdyna.model import parse_deck, read_deck
from batball.models.bbs import build_bbs_model
from batball.specs import load_ball_spec, load_bat_spec

MESH = ["--circumferential", "8", "--axial-size", "1 in"]
BBS = [*MESH, "--divisions", "3", "--pivot-band", "0.5 in"]


def export(tmp_path: Path, *args: str) -> Path:
    deck = tmp_path / "deck.k"
    assert main(["export", *args, "--long", "-o", str(deck)]) == 0
    return deck


@pytest.mark.parametrize(
    ("test", "option", "value"),
    [
        ("modal", "--insert", "contact"),
        ("barrel", "--friction", "0.3"),
        ("barrel", "--solver", "explicit"),
        ("bbs", "--insert-friction", "0.3"),
        ("bbs", "--bat-damping", "1000 1/s"),
        ("bbs", "--shell", "mitc4"),
        ("bbs", "--hourglass-ratio", "0.5"),
    ],
)
def test_an_option_the_deck_cannot_hold_is_refused_naming_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], test: str, option: str, value: str
) -> None:
    deck = tmp_path / "deck.k"
    assert main(["export", test, *MESH, option, value, "-o", str(deck)]) == 2
    error = capsys.readouterr().err
    assert f"export {test} {option}" in error and error.count("\n") == 1
    assert not deck.exists()  # checked before anything is built or written


def test_export_takes_each_tests_own_options_with_its_defaults() -> None:
    from batball.cli.decks import export_options

    for name in ("ccor", "cor", "compression", "bbs"):
        assert [o.name for o in export_options(name)] == [o.name for o in LAB_TESTS[name].options]
        assert [o.default for o in export_options(name) if o.name != "shell"] == [
            o.default for o in LAB_TESTS[name].options if o.name != "shell"
        ]
    # the defaults that differ are the ones a deck cannot hold otherwise, and say so: the modal
    # test's insert, and the BBS test's shells (the deck's are LS-DYNA's ELFORM 2)
    (insert,) = [o for o in export_options("modal") if o.name == "insert"]
    assert insert.default == "bonded" and LAB_TESTS["modal"].option("insert").default == "contact"
    assert "a deck carries bonded only" in insert.help
    (shell,) = [o for o in export_options("bbs") if o.name == "shell"]
    assert shell.default == "bt" and LAB_TESTS["bbs"].option("shell").default == "mitc4"
    assert "a deck carries bt only" in shell.help
    assert [o.name for o in export_options("barrel")][-1] == "orientation"


def test_a_bbs_deck_carries_the_shells_mass_scaling_and_reads_it_back(tmp_path: Path) -> None:
    """DT2MS = -(the step below which batball adds mass) / TSSFAC, as LS-DYNA reads it
    (TSSFAC |DT2MS| is the smallest step); read back, it is that step again."""
    deck = export(tmp_path, "bbs", *BBS)
    step = parse_deck(deck).controls["CONTROL_TIMESTEP"]
    setup = LAB_TESTS["bbs"].setup(divisions=3, circumferential=8, axial_size="1 in",
                                   pivot_band="0.5 in")  # fmt: skip
    model = build_bbs_model(load_bat_spec("default"), load_ball_spec("type1"), setup)
    assert model.mass_scaling_step is not None and model.mass_scaling_step > 0.0
    assert step["dt2ms"] == pytest.approx(-model.mass_scaling_step / step["tssfac"], rel=1e-15)
    read = read_bbs_deck(read_bat_deck(deck))
    assert read.setup.mass_scaling == pytest.approx(model.mass_scaling_step, rel=1e-15)
    added = read.model.added_mass
    assert added.sum() == pytest.approx(model.added_mass.sum(), rel=1e-12) and added.sum() > 0.0


def test_a_bbs_deck_without_mass_scaling_writes_none_and_reads_none(tmp_path: Path) -> None:
    deck = export(tmp_path, "bbs", *BBS, "--mass-scaling", "off")
    assert not parse_deck(deck).controls["CONTROL_TIMESTEP"].get("dt2ms")
    read = read_bbs_deck(read_bat_deck(deck))
    assert read.setup.mass_scaling is None and not read.model.added_mass.any()


def test_a_ball_deck_with_mass_scaling_is_refused(tmp_path: Path) -> None:
    deck = export(tmp_path, "ccor", "--divisions", "2")
    lines = deck.read_text().split("\n")
    at = lines.index("*CONTROL_TIMESTEP") + 1
    while lines[at].startswith("$"):
        at += 1
    # DTINIT TSSFAC ISDO TSLIMT DT2MS, 20-column fields (--long)
    lines[at] = lines[at].ljust(80)[:80] + f"{-1e-6:>20}"
    deck.write_text("\n".join(lines))
    with pytest.raises(SpecError, match="DT2MS"):
        read_deck(deck)
