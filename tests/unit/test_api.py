"""The Python API and the lab registry it shares with the command line."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib
import pint
import pytest

import batball
from batball.cli import build_parser, main
from batball.errors import SpecError
from batball.lab.registry import LAB_TESTS

MPH = 0.44704  # m/s, exact by definition (5280 ft of 0.3048 m per hour)


@pytest.mark.parametrize("name", sorted(LAB_TESTS))
def test_every_dimensioned_option_refuses_a_bare_number(name: str) -> None:
    test = LAB_TESTS[name]
    quantities = [o for o in test.options if o.kind == "quantity"]
    assert quantities
    for option in quantities:
        with pytest.raises(SpecError) as caught:
            test.setup(**{option.name: 1.0})
        assert caught.value.field == option.field


def test_a_bare_speed_is_an_error_naming_speed_before_anything_runs(tmp_path: Path) -> None:
    with pytest.raises(SpecError) as caught:
        batball.ccor("type1", speed=95, runs_dir=tmp_path)
    assert caught.value.field == "speed"
    assert not any(tmp_path.iterdir())  # nothing was run or stored


def test_an_unknown_option_is_an_error_listing_the_test_options() -> None:
    with pytest.raises(SpecError, match="an option of ccor: speed, divisions"):
        batball.ccor("type1", sped="95 mph")


def test_a_pint_quantity_and_its_text_give_the_same_setup() -> None:
    units = pint.UnitRegistry()
    from_text = LAB_TESTS["ccor"].setup(speed="95 mph")
    from_pint = LAB_TESTS["ccor"].setup(speed=95 * units.mph)
    assert from_text == from_pint
    assert from_text.speed == pytest.approx(95 * MPH, rel=1e-15)


@pytest.mark.parametrize("name", sorted(LAB_TESTS))
def test_the_command_line_defaults_are_the_registry_defaults(name: str) -> None:
    """Each subcommand is made from its registry entry: with no options it builds the same
    Setup as the API with none."""
    test = LAB_TESTS[name]
    args = build_parser().parse_args([name])
    assert test.setup(**{o.name: getattr(args, o.name) for o in test.options}) == test.setup()


def test_one_flag_name_means_one_thing() -> None:
    """Ball mesh divisions are --divisions everywhere (bbs keeps --ball-divisions as an
    alias); bat commands without a pivot do not accept one."""
    parser = build_parser()
    assert parser.parse_args(["bbs", "--ball-divisions", "4"]).divisions == "4"
    assert parser.parse_args(["bbs", "--divisions", "4"]).divisions == "4"
    for name in ("modal", "barrel"):
        with pytest.raises(SystemExit):
            parser.parse_args([name, "--pivot", "6 in"])
    # the ball's hourglass control is set the same way in the cylinder and the bat test
    for name in ("ccor", "bbs"):
        args = parser.parse_args([name, "--hourglass-type", "4", "--hourglass-coefficient", "0.01"])
        test = LAB_TESTS[name]
        setup = test.setup(**{o.name: getattr(args, o.name) for o in test.options})
        assert (setup.hourglass.type, setup.hourglass.coefficient) == (4, 0.01)


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"batball {batball.__version__}"


def test_api_and_command_line_run_the_same_test(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The API's run and the CLI's with the same options are one run in the store (the CLI
    reuses it), and the Result reads back what the run wrote."""
    backend = matplotlib.get_backend()
    matplotlib.use("svg")  # a backend no run should change (old runs switched it to Agg)
    try:
        result = batball.ccor("type2", speed="95 mph", divisions=3, runs_dir=tmp_path)
        fig = result.plot()
        assert matplotlib.get_backend() == "svg"
    finally:
        matplotlib.use(backend)
    assert result.summary["n_cells"] == 7 * 27  # 7 blocks of 3 x 3 x 3 hexes
    assert result.summary["inbound_mph"] == pytest.approx(95.0)
    assert result.run_dir.parent == tmp_path
    history = result.history
    assert {"time_ms", "contact_force_lbf"} <= set(history.columns)
    assert history["time_ms"].is_monotonic_increasing
    assert fig.axes[0].get_xlabel() == "time (ms)"
    assert "<table>" in result._repr_html_()

    code = main(["ccor", "--ball", "type2", "--speed", "95 mph", "--divisions", "3", "--json",
                 "--runs-dir", str(tmp_path)])  # fmt: skip
    assert code == 0
    assert json.loads(capsys.readouterr().out) == result.summary
