"""MkDocs hooks: pages that are generated from the code, so they cannot drift from it.

- ``{{ options NAME }}`` on a page becomes the table of the virtual test NAME's options, made
  from the lab registry (the same declarations the command line and the API are made from).
- ``{{ cli_reference }}`` becomes every subcommand's ``--help``, made from the parser.
"""

from __future__ import annotations

import os
import re
from typing import Any

_OPTIONS = re.compile(r"\{\{\s*options\s+([a-z]+)\s*\}\}")
_CLI = re.compile(r"\{\{\s*cli_reference\s*\}\}")


def options_table(name: str) -> str:
    """The options of the virtual test ``name`` as a Markdown table."""
    from batball.lab.registry import LAB_TESTS

    test = LAB_TESTS[name]
    rows = ["| option | default | allowed | what it sets |", "|---|---|---|---|"]
    for option in test.options:
        flags = ", ".join(f"`{f}`" for f in option.flags)
        if option.kind == "flag":
            default = "on" if option.default else "off"
        else:
            default = "the test's own" if option.default is None else f"`{option.default}`"
        if option.kind == "quantity":
            allowed = f"a {option.dimension.replace('_', ' ')} with its unit"  # type: ignore[union-attr]
            if option.words:
                allowed += " or " + ", ".join(f"`{w}`" for w in option.words)
        elif option.kind == "choice":
            allowed = ", ".join(f"`{c}`" for c in option.choices)
        elif option.kind == "flag":
            allowed = "a flag"
        else:
            allowed = "an integer" if option.kind == "int" else "a number"
        if option.allowed:
            allowed = option.allowed
        text = option.help.replace("|", "\\|")
        rows.append(f"| {flags} | {default} | {allowed.replace('|', '/')} | {text} |")
    python = ", ".join(o.name for o in test.options)
    subjects = " and ".join(f"`--{kind}`" for kind in test.subjects)
    return "\n".join([
        *rows,
        "",
        f"Every test also takes {subjects} (an embedded name or a TOML file), `--runs-dir`, "
        f"`--no-reuse` and `--json`. In Python the options are keywords of `batball.{name}`: "
        f"{python}.",
    ])  # fmt: skip


def cli_reference() -> str:
    """``batball --help`` and each subcommand's ``--help``, as code blocks."""
    os.environ["COLUMNS"] = "100"
    from batball.cli import build_parser

    parser = build_parser()
    parts = ["## batball", "", "```text", parser.format_help().rstrip(), "```"]
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    for name, subparser in sub.choices.items():  # type: ignore[union-attr]
        parts += ["", f"## batball {name}", "", "```text", subparser.format_help().rstrip(), "```"]
    return "\n".join(parts)


def on_page_markdown(markdown: str, **_: Any) -> str:
    """Fill the generated parts of a page."""
    markdown = _OPTIONS.sub(lambda m: options_table(m.group(1)), markdown)
    return _CLI.sub(lambda _m: cli_reference(), markdown)
