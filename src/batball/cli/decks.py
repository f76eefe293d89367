"""LS-DYNA keyword decks: ``batball export`` writes a test as a deck, ``batball run`` reads a
deck back and runs it with the same measurements (docs/lsdyna.md)."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from batball.cli.options import add_json_option, add_options, add_subject, progress_bar
from batball.errors import SpecError
from batball.lab.protocol import Option
from batball.lab.registry import (
    CONTACT_THRESHOLD,
    DISPLACEMENT,
    LAB_TESTS,
    PRECISION,
    load_subject,
    parse_options,
)

#: The tests ``batball export`` writes as decks.
EXPORTS = ("ccor", "cor", "compression", "modal", "barrel", "bbs")

#: Per test, the options a deck cannot carry: the value the deck does carry and what it does.
#: ``batball export TEST`` takes the test's own options, so a deck is what ``batball TEST`` runs;
#: one of these set to anything else is refused. The options that only choose how batball runs
#: or reads a test (the ball's arithmetic, the contact-time level, the BBS's pitch and swing
#: speeds, the statics' ramp) do not change the deck and are accepted.
NOT_IN_DECK: dict[str, dict[str, tuple[Any, str]]] = {
    "modal": {"insert": ("bonded", "bonded (the deck ties the insert to the barrel)")},
    "barrel": {
        "friction": (None, "not set or 0 (the deck's insert contact is frictionless)"),
        "platen_friction": (0.0, "0 (the deck's platen contacts are frictionless)"),
        "solver": ("static", "static (the deck is the implicit static test)"),
        "shell": (None, "not set (the deck is the implicit static test)"),
        "hourglass_ratio": (None, "not set (the deck is the implicit static test)"),
    },
    "bbs": {
        "insert_friction": (None, "not set or 0 (the deck's interference contact is "
                                  "frictionless)"),
        "bat_damping": (0.0, "0 1/s (the deck has no damping of the bat's deformation)"),
        "shell": ("bt", "bt (the deck's shells are Belytschko-Tsay, ELFORM 2)"),
        "hourglass_ratio": (None, "not set (the deck writes no hourglass card for the shells)"),
    },
}

#: The insert's friction options: not set (the bat's, which a deck requires to be 0) or 0.
FRICTIONS = ("friction", "insert_friction")

#: ``batball export barrel``'s one option of its own: the deck holds one orientation.
ORIENTATION = Option("orientation", 0.0, "bat rotation about its axis, 0 or 90 deg",
                     kind="float")  # fmt: skip


def export_options(name: str) -> tuple[Option, ...]:
    """The options of ``batball export NAME``: the test's, each defaulting to what the deck
    carries (help says so where that is not the test's default)."""
    fixed = NOT_IN_DECK.get(name, {})
    options = []
    for option in LAB_TESTS[name].options:
        if option.name in fixed and option.default_value != fixed[option.name][0]:
            carried = fixed[option.name][0]
            option = option.with_default(carried, f"{option.help}; a deck carries {carried} only")
        options.append(option)
    return (*options, ORIENTATION) if name == "barrel" else tuple(options)


#: The options of ``batball run`` shared with the tests: the contact-time level, where a
#: compression deck's force is read, the ball's arithmetic.
DECK_RUN_OPTIONS = (
    CONTACT_THRESHOLD,
    DISPLACEMENT.with_default("0.25 in", "compression decks: where the force is read"),
    PRECISION,
)


def add_export_parser(sub: Any) -> None:
    """``batball export TEST``: the test as a keyword deck, with the test's own options."""
    help_text = "write a ball or bat test as a complete LS-DYNA keyword deck (docs/lsdyna.md)"
    p = sub.add_parser("export", help=help_text, description=help_text)
    tests = p.add_subparsers(dest="test", required=True, metavar="TEST",
                             help=" | ".join(EXPORTS) + ": the test to export, with its options")
    for name in EXPORTS:
        test = LAB_TESTS[name]
        q = tests.add_parser(name, help=f"{test.help} (as a deck)",
                             description=f"{test.help}, written as a keyword deck")  # fmt: skip
        for kind in test.subjects:
            add_subject(q, kind)
        add_options(q, export_options(name))
        q.add_argument("--units", default="in-lbf-s", help="in-lbf-s (default), m-N-s or mm-N-ms")
        q.add_argument("--long", action="store_true", help="long format: 20-column fields")
        q.add_argument("-o", "--output", required=True, help="the deck file to write (.k)")
    p.set_defaults(handler=run_export_command)


def export_setup(name: str, args: argparse.Namespace) -> tuple[Any, dict[str, Any]]:
    """The test's Setup from the command's options, and the parsed values; an option the deck
    cannot carry, set to anything else, is refused before anything is built."""
    values = parse_options(export_options(name), args)
    for option, (carried, what) in NOT_IN_DECK.get(name, {}).items():
        frictionless = option in FRICTIONS and values[option] == 0.0
        if values[option] != carried and not frictionless:
            raise SpecError(f"export {name} --{option.replace('_', '-')}", values[option], what)
    test = LAB_TESTS[name]
    return test.build({o.name: values[o.name] for o in test.options}), values


def run_export_command(args: argparse.Namespace) -> int:
    """Write the deck and say where."""
    setup, values = export_setup(args.test, args)
    kinds = LAB_TESTS[args.test].subjects
    subjects = {kind: load_subject(kind, getattr(args, kind)) for kind in kinds}
    common = {"units": args.units, "long": args.long}
    if args.test in ("ccor", "cor", "compression"):
        from batball.lsdyna.export import write_impact_deck

        ball = subjects["ball"]
        n_lines = write_impact_deck(args.output, ball, setup, args.units, long=args.long)
        print(f"wrote {args.output}: {args.test} of ball {ball.name}, {n_lines} lines, "
              f"units {args.units}")  # fmt: skip
        return 0
    from batball.lsdyna.bat import barrel_deck, bbs_deck, modal_deck

    spec = subjects["bat"]
    given = [values[o] for o in FRICTIONS if o in values]
    rubs = spec.insert is not None and spec.insert.friction > 0.0
    if args.test in ("barrel", "bbs") and rubs and None in given:
        raise SpecError(f"bat {spec.name} insert.friction", spec.insert.friction,
                        "0 for a deck (its insert contact is frictionless), or the test's "
                        "friction option set to 0")  # fmt: skip
    mesh = {"circumferential": setup.circumferential, "axial_size": setup.axial_size}
    if args.test == "modal":
        text = modal_deck(spec, n_modes=setup.modes, **common, **mesh)
    elif args.test == "barrel":
        text = barrel_deck(spec, setup.protocol, orientation_deg=values["orientation"],
                           **common, **mesh)  # fmt: skip
    else:
        text = bbs_deck(spec, subjects["ball"], setup, **common)
    Path(args.output).write_text(text, encoding="ascii")
    print(f"wrote {args.output}: {args.test} of bat {spec.name}, {text.count(chr(10))} lines, "
          f"units {args.units}")  # fmt: skip
    return 0


def deck_warnings(args: argparse.Namespace, ignored: Sequence[str]) -> list[str]:
    """What ``batball run`` says about a deck besides its results: the output keywords it read
    past (``ignored``), and units given that disagree with the ones its batball header names
    (every number is then read at the wrong scale)."""
    from batball.lsdyna.deck import header_units

    warnings = [f"{where}: an output or output-control keyword, read past (batball writes its "
                "own histories)" for where in ignored]  # fmt: skip
    named = header_units(args.deck)
    if named is not None and named != args.units:
        warnings.append(f"the deck's header says its units are {named}, but it was read as "
                        f"{args.units}: run it with --units {named}")  # fmt: skip
    return warnings


def add_run_deck_parser(sub: Any) -> None:
    """``batball run deck.k``: read a keyword deck and run it as an impact test."""
    help_text = "read an LS-DYNA keyword deck (ball hexes + rigid target) and run it"
    p = sub.add_parser("run", help=help_text, description=help_text)
    p.add_argument("deck", type=Path, help="the keyword file (*INCLUDEs are followed)")
    p.add_argument("--units", default="in-lbf-s", help="the deck's units (default in-lbf-s)")
    p.add_argument(
        "--include-root",
        type=Path,
        default=None,
        help="a folder every *INCLUDE must lie inside (default: the deck's own folder)",
    )
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

    if parse_deck(args.deck, include_root=args.include_root).composites:
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
        precision=args.precision, include_root=args.include_root,
    )  # fmt: skip
    unit = "s" if deck.test == "compression" else "ms"
    update, bar = progress_bar(deck.controls.end_time, enabled=True, unit=unit)
    try:
        summary = run_deck(deck, threshold=values["contact_threshold"], progress=update)
    finally:
        bar.close()
    summary["deck"] = str(args.deck)
    summary["warnings"] = deck_warnings(args, deck.ignored)
    for warning in summary["warnings"]:
        print(f"batball: warning: {warning}", file=sys.stderr)
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


def run_bat_deck_command(args: argparse.Namespace) -> int:
    """``batball run`` of a bat deck: modal, barrel or bbs (docs/lsdyna.md)."""
    from batball.lab.decks import run_barrel_deck, run_modal_deck
    from batball.lsdyna.bat_model import read_bat_deck

    bat = read_bat_deck(args.deck, units=args.units, include_root=args.include_root)
    if bat.test == "bbs":
        return run_bbs_deck_command(args, bat)
    summary = run_modal_deck(bat) if bat.test == "modal" else run_barrel_deck(bat)
    summary["deck"] = str(args.deck)
    summary["warnings"] = deck_warnings(args, bat.deck.ignored)
    for warning in summary["warnings"]:
        print(f"batball: warning: {warning}", file=sys.stderr)
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
    summary["warnings"] = deck_warnings(args, bat.deck.ignored)
    for warning in summary["warnings"]:
        print(f"batball: warning: {warning}", file=sys.stderr)
    summary["run_folder"] = None
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    from batball.lab.describe import describe_bbs

    print(describe_bbs({**summary, "run_folder": f"none (deck {args.deck})"}))
    return 0
