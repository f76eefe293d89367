"""LS-DYNA keyword decks: ``batball export`` writes a test as a deck, ``batball run`` reads a
deck back and runs it with the same measurements (docs/lsdyna.md)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from batball.cli.options import add_json_option, add_options, add_subject, progress_bar
from batball.errors import SpecError
from batball.lab.protocol import Option
from batball.lab.registry import (
    AXIAL_SIZE,
    BULK_VISCOSITY,
    CIRCUMFERENTIAL,
    CONTACT_THRESHOLD,
    DISPLACEMENT,
    DIVISIONS,
    HOURGLASS_COEFFICIENT,
    HOURGLASS_TYPE,
    LAB_TESTS,
    MODES,
    PIVOT_BAND,
    PRECISION,
    SOFT,
    SPEED,
    ball_numerics,
    load_subject,
    parse_options,
)

#: The bat tests ``batball export`` writes as decks (the ball tests are ccor, cor, compression).
BAT_EXPORTS = ("modal", "barrel", "bbs")

#: The ball options of ``batball export``: the registry's, the speed defaulting to the test's.
EXPORT_BALL_OPTIONS = (
    SPEED.with_default(None, "inbound speed with its unit (default: the test's)"),
    DIVISIONS, HOURGLASS_TYPE, HOURGLASS_COEFFICIENT, BULK_VISCOSITY, SOFT,
)  # fmt: skip

#: The bat options of ``batball export`` (modal, barrel, bbs).
EXPORT_BAT_OPTIONS = (
    CIRCUMFERENTIAL, AXIAL_SIZE,
    MODES,
    Option("orientation", 0.0, "barrel: bat rotation about its axis, 0 or 90 deg",
           kind="float"),
    PIVOT_BAND,
)  # fmt: skip


#: The options of ``batball run`` shared with the tests: the contact-time level, where a
#: compression deck's force is read, the ball's arithmetic.
DECK_RUN_OPTIONS = (
    CONTACT_THRESHOLD,
    DISPLACEMENT.with_default("0.25 in", "compression decks: where the force is read"),
    PRECISION,
)


def add_export_parser(sub: Any) -> None:
    """``batball export ccor|cor|compression|modal|barrel|bbs``: the test as a keyword deck."""
    help_text = "write a ball or bat test as a complete LS-DYNA keyword deck (docs/lsdyna.md)"
    p = sub.add_parser("export", help=help_text, description=help_text)
    p.add_argument("test", choices=["ccor", "cor", "compression", *BAT_EXPORTS],
                   help="the test to export")  # fmt: skip
    add_subject(p, "ball")
    add_options(p, EXPORT_BALL_OPTIONS)
    p.add_argument("--units", default="in-lbf-s", help="in-lbf-s (default), m-N-s or mm-N-ms")
    p.add_argument("--long", action="store_true", help="long format: 20-column fields")
    p.add_argument("-o", "--output", required=True, help="the deck file to write (.k)")
    add_subject(p, "bat")
    add_options(p, EXPORT_BAT_OPTIONS)
    p.set_defaults(handler=run_export_command)


def run_export_command(args: argparse.Namespace) -> int:
    """Write the deck and say where."""
    from batball.lsdyna.export import write_impact_deck

    values = parse_options(EXPORT_BALL_OPTIONS, args)
    if args.test in BAT_EXPORTS:
        return run_bat_export(args, values)
    ball = load_subject("ball", args.ball)
    if args.test == "compression":
        from batball.models.compression import CompressionSetup

        numerics = ball_numerics(values)
        setup: Any = CompressionSetup(divisions=values["divisions"],
                                      hourglass=numerics["hourglass"],
                                      bulk_viscosity=numerics["bulk_viscosity"])  # fmt: skip
        what = "compression (F1888, 1 in/min to 0.25 in)"
    else:
        test = LAB_TESTS[args.test]
        speed = args.speed or test.option("speed").default
        setup = test.setup(**{**values, "speed": speed})
        what = f"{args.test} at {speed}"
    n_lines = write_impact_deck(args.output, ball, setup, args.units, long=args.long)
    print(f"wrote {args.output}: {what} of ball {ball.name}, {n_lines} lines, units {args.units}")
    return 0


def add_run_deck_parser(sub: Any) -> None:
    """``batball run deck.k``: read a keyword deck and run it as an impact test."""
    help_text = "read an LS-DYNA keyword deck (ball hexes + rigid target) and run it"
    p = sub.add_parser("run", help=help_text, description=help_text)
    p.add_argument("deck", type=Path, help="the keyword file (*INCLUDEs are followed)")
    p.add_argument("--units", default="in-lbf-s", help="the deck's units (default in-lbf-s)")
    p.add_argument(
        "--separation-time",
        default=None,
        help="stop this long after the ball leaves the target (0.1 ms; bbs decks 0.2 ms, as "
        "batball bbs; 'none' runs an impact deck to ENDTIM)",
    )
    add_options(p, DECK_RUN_OPTIONS)
    add_json_option(p)
    p.set_defaults(handler=run_deck_command)


def run_deck_command(args: argparse.Namespace) -> int:
    """Read, run and report a deck with the impact measurements."""
    from batball.lab.decks import run_deck
    from batball.lsdyna.model import parse_deck, read_deck
    from batball.units import parse_quantity

    if parse_deck(args.deck).composites:
        return run_bat_deck_command(args)
    text = args.separation_time or "0.1 ms"
    separation = (
        None
        if text.strip().lower() == "none"
        else parse_quantity(text, "time", field="separation-time")
    )
    values = parse_options(DECK_RUN_OPTIONS, args)
    displacement = values["displacement"]
    deck = read_deck(
        args.deck, units=args.units, separation_time=separation, displacement=displacement,
        precision=args.precision,
    )  # fmt: skip
    unit = "s" if deck.test == "compression" else "ms"
    update, bar = progress_bar(deck.controls.end_time, enabled=True, unit=unit)
    try:
        summary = run_deck(deck, threshold=values["contact_threshold"], progress=update)
    finally:
        bar.close()
    summary["deck"] = str(args.deck)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    if deck.test == "compression":
        print("\n".join([
            f"compression of deck {args.deck} at {summary['rate_in_per_min']:.3g} in/min",
            f"  {'force at ' + format(summary['displacement_in'], '.3g') + ' in':<22} "
            f"{summary['compression_lbf']:.1f} lbf (power-law fit "
            f"{summary['compression_fit_lbf']:.1f} lbf)",
            f"  {'top-bottom difference':<22} "
            f"{100 * summary['plate_force_difference_fraction']:.2f} %",
            f"  {'energy balance error':<22} {100 * summary['energy_balance_error']:.2f} %",
            f"  {summary['n_cells']} hexes, {summary['n_steps']} steps",
        ]))  # fmt: skip
        return 0
    name = summary["test"].upper()
    print("\n".join([
        f"{name} of deck {args.deck} ({summary['ball_mass_oz']:.2f} oz) "
        f"at {summary['inbound_mph']:.1f} mph",
        f"  {name:<22} {summary[summary['test']]:.3f}",
        f"  {'rebound speed':<22} {summary['rebound_mph']:.1f} mph",
        f"  {'dynamic stiffness':<22} {summary['ds_lbf_per_in']:.0f} lb/in",
        f"  {'peak force':<22} {summary['peak_force_lbf']:.0f} lbf",
        f"  {'contact time':<22} {summary['contact_time_ms']:.3f} ms",
        f"  {'energy balance error':<22} {100 * summary['energy_balance_error']:.2f} %",
        f"  {summary['n_cells']} hexes, {summary['n_steps']} steps",
    ]))  # fmt: skip
    return 0


def run_bat_export(args: argparse.Namespace, ball_values: dict[str, Any]) -> int:
    """Write a bat test's deck (modal, barrel or bbs) and say where."""
    from batball.lsdyna.bat import barrel_deck, bbs_deck, modal_deck

    spec = load_subject("bat", args.bat)
    bat_values = parse_options(EXPORT_BAT_OPTIONS, args)
    mesh = {k: bat_values[k] for k in ("circumferential", "axial_size")}
    common = {"units": args.units, "long": args.long}
    if args.test == "modal":
        text = modal_deck(spec, n_modes=bat_values["modes"], **common, **mesh)
    elif args.test == "barrel":
        from batball.models.barrel import BarrelTestOptions

        text = barrel_deck(spec, BarrelTestOptions(), orientation_deg=bat_values["orientation"],
                           **common, **mesh)  # fmt: skip
    else:
        setup = bat_export_bbs_setup(ball_values, bat_values["pivot_band"], mesh)
        text = bbs_deck(spec, load_subject("ball", args.ball), setup, **common)
    Path(args.output).write_text(text, encoding="ascii")
    print(f"wrote {args.output}: {args.test} of bat {spec.name}, {text.count(chr(10))} lines, "
          f"units {args.units}")  # fmt: skip
    return 0


def bat_export_bbs_setup(values: dict[str, Any], pivot_band: float, mesh: dict[str, Any]) -> Any:
    """The BbsSetup of ``batball export bbs``'s options (speed default: the bbs test's)."""
    from batball.models.bbs import BbsSetup

    speed = values["speed"]
    if speed is None:
        speed = LAB_TESTS["bbs"].option("speed").default_value
    return BbsSetup(
        speed=speed, ball_divisions=values["divisions"], pivot_band=pivot_band,
        **ball_numerics(values), **mesh,
    )  # fmt: skip


def run_bat_deck_command(args: argparse.Namespace) -> int:
    """``batball run`` of a bat deck: modal, barrel or bbs (docs/lsdyna.md)."""
    from batball.lab.decks import run_barrel_deck, run_modal_deck
    from batball.lsdyna.bat_model import read_bat_deck

    bat = read_bat_deck(args.deck, units=args.units)
    if bat.test == "bbs":
        return run_bbs_deck_command(args, bat)
    summary = run_modal_deck(bat) if bat.test == "modal" else run_barrel_deck(bat)
    summary["deck"] = str(args.deck)
    if args.json:
        print(json.dumps(summary, indent=2))
    elif bat.test == "barrel":
        print(f"Barrel compression of deck {args.deck} at {summary['orientation_deg']:g} deg "
              f"({summary['n_shells']} shells): preload {summary['preload_lbf']:.1f} lbf, "
              f"final load {summary['final_load_lbf']:.1f} lbf")  # fmt: skip
    else:
        print("\n".join([
            f"Free-free modes of deck {args.deck} ({summary['n_shells']} shells)",
            "  bending " + (", ".join(f"{f:.1f} Hz" for f in summary["bending_hz"]) or "none"),
            "  hoop    " + (", ".join(f"{f:.1f} Hz" for f in summary["hoop_hz"]) or "none"),
        ]))  # fmt: skip
    return 0


def run_bbs_deck_command(args: argparse.Namespace, bat: Any) -> int:
    """``batball run`` of a bbs deck: the summary ``batball bbs`` prints (no run folder)."""
    from batball.lab.decks import run_bbs_deck
    from batball.units import parse_quantity

    text = args.separation_time or "0.2 ms"
    if text.strip().lower() == "none":
        raise SpecError("separation-time", text, "a time: the rebound is read over it (0.2 ms)")
    separation = parse_quantity(text, "time", field="separation-time")
    summary = run_bbs_deck(bat, separation_time=separation, precision=args.precision)
    summary["deck"] = str(args.deck)
    summary["run_folder"] = None
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    from batball.lab.describe import describe_bbs

    print(describe_bbs({**summary, "run_folder": f"none (deck {args.deck})"}))
    return 0
