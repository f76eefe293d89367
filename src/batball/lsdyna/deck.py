"""A small LS-DYNA keyword-deck reader: keyword blocks and their cards, fixed or free format.

Lines starting with ``$`` are comments; a line starting with ``*`` opens a keyword; ``*INCLUDE``
cards name files read in place (relative to the including file's folder); ``*END`` ends a file.
A card with a comma is free format (comma-separated fields in the card's order); otherwise the
fields are cut at the card's fixed columns (:data:`batball.lsdyna.cards.LAYOUTS`), 20 columns
each in long format (a keyword written ``*NODE +``, or every keyword after ``*KEYWORD LONG=Y``;
``-`` switches one keyword back to standard). Keyword Manual Vol I, "General card format" and
*INCLUDE, *KEYWORD. What a deck *means* is read in :mod:`batball.lsdyna.model`; this module
only splits it, and fails with a :class:`SpecError` naming the file and line on text it cannot
read.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from batball.errors import SpecError
from batball.lsdyna.cards import ALIASES, LAYOUTS

LONG_WIDTH = 20


@dataclass(frozen=True)
class CardLine:
    """One data line of a keyword: its text and where it came from."""

    text: str
    path: Path
    line: int

    def where(self) -> str:
        """``file:line`` for messages."""
        return f"{self.path}:{self.line}"


@dataclass
class KeywordBlock:
    """A keyword (name upper-case, without ``*``, aliases resolved) and its data lines."""

    name: str
    path: Path
    line: int
    long: bool = False
    cards: list[CardLine] = field(default_factory=list)

    def where(self) -> str:
        """``file:line`` of the keyword line."""
        return f"{self.path}:{self.line}"


#: The most files one deck may read, itself and its *INCLUDEs together, and their total size: a
#: chain of decks that each include the next several times would otherwise read exponentially
#: many files.
MAX_FILES = 64
MAX_BYTES = 256 * 2**20


@dataclass
class _Budget:
    """What a deck's reading may still take: its folder (every include must lie inside it), and
    the files and bytes left."""

    root: Path
    files: int = MAX_FILES
    bytes: int = MAX_BYTES


#: The header line batball writes with a deck's unit system (``$ units in-lbf-s: ...``).
_UNITS_LINE = re.compile(r"^\$ units (\S+):")


def header_units(path: str | Path) -> str | None:
    """The unit system a deck's batball header names, or None (no such line in its first 40)."""
    try:
        with open(path, encoding="latin-1") as stream:
            for _, line in zip(range(40), stream, strict=False):
                match = _UNITS_LINE.match(line)
                if match:
                    return match.group(1)
    except OSError:
        return None
    return None


def read_keyword_file(
    path: str | Path, *, include_root: str | Path | None = None
) -> list[KeywordBlock]:
    """Every keyword block of the deck at ``path``, includes expanded in place.

    An *INCLUDE is read relative to the deck that names it and must lie inside the folder of
    the deck at ``path``, or inside ``include_root`` where one is named (a library of parts
    shared by decks in several folders); at most :data:`MAX_FILES` files and :data:`MAX_BYTES`
    bytes are read. Errors name the file and line and never quote a file that is not a keyword
    deck.
    """
    path = Path(path)
    if not path.is_file():
        raise SpecError("deck", str(path), "an existing keyword file")
    if include_root is None:
        root = path.resolve().parent
    else:
        root = Path(include_root).resolve()
        if not root.is_dir():
            raise SpecError("include root", str(include_root), "an existing folder")
        if not path.resolve().is_relative_to(root):
            raise SpecError("include root", str(include_root), f"a folder holding the deck {path}")
    return _read(path, long_default=False, depth=0, budget=_Budget(root))


def _read(path: Path, long_default: bool, depth: int, budget: _Budget) -> list[KeywordBlock]:
    """The blocks of one file; *INCLUDE blocks are replaced by the included file's blocks."""
    if depth > 20:
        raise SpecError("*INCLUDE", str(path), "an include depth of at most 20 (a cycle?)")
    if not path.is_file():
        raise SpecError("deck", str(path), "an existing keyword file")
    budget.files -= 1
    budget.bytes -= path.stat().st_size
    if budget.files < 0 or budget.bytes < 0:
        raise SpecError("*INCLUDE", str(path), f"a deck of at most {MAX_FILES} files and "
                        f"{MAX_BYTES // 2**20} MiB in all, includes counted each time")  # fmt: skip
    blocks: list[KeywordBlock] = []
    current: KeywordBlock | None = None
    long_all = long_default
    try:
        text = path.read_text(encoding="latin-1")
    except OSError as exc:
        raise SpecError("deck", str(path), f"a readable keyword file ({exc.strerror})") from None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.rstrip("\r\n")
        if line.startswith("$") or (current is None and not line.strip()):
            continue  # a blank line inside a keyword is a card of defaults, as in LS-DYNA
        if line.startswith("*"):
            current, long_all = _open_keyword(line, path, number, long_all)
            if current.name == "END":
                break
            blocks.append(current)
        elif current is None:  # not a deck: say where, not what (the file may be anything)
            raise SpecError(f"{path}:{number}", "a line before any keyword",
                            "a keyword line (*...) first")  # fmt: skip
        else:
            current.cards.append(CardLine(line, path, number))
    return _expand_includes(blocks, long_all, depth, budget)


def _open_keyword(line: str, path: Path, number: int, long_all: bool) -> tuple[KeywordBlock, bool]:
    """The block a ``*KEYWORD`` line opens, and the deck-wide long-format switch after it."""
    words = line[1:].split()
    name = words[0].upper() if words else ""
    suffix = words[1] if len(words) > 1 else ""
    if name.endswith("+") or name.endswith("-"):
        name, suffix = name[:-1], name[-1]
    if name == "KEYWORD":
        long_all = any(w.upper() in ("LONG=Y", "LONG=S") for w in words[1:]) or long_all
    long = {"+": True, "-": False}.get(suffix, long_all)
    name = ALIASES.get(name, name)
    return KeywordBlock(name, path, number, long=long), long_all


def _expand_includes(blocks: list[KeywordBlock], long_all: bool, depth: int,
                     budget: _Budget) -> list[KeywordBlock]:  # fmt: skip
    """Replace each *INCLUDE block by the blocks of the files it names."""
    out: list[KeywordBlock] = []
    for block in blocks:
        if block.name != "INCLUDE":
            out.append(block)
            continue
        for card in block.cards:
            name = card.text.strip()
            target = (card.path.parent / name).resolve()
            if not target.is_relative_to(budget.root):
                raise SpecError(f"*INCLUDE at {card.where()}", name,
                                f"a file inside {budget.root} (the deck's folder, or "
                                "the include root named)")  # fmt: skip
            if not target.is_file():
                raise SpecError(f"*INCLUDE at {card.where()}", name, "an existing file")
            out.extend(_read(target, long_all, depth + 1, budget))
    return out


def split_fields(card: CardLine, keyword: str, index: int, long: bool) -> dict[str, object]:
    """The named fields of card ``index`` of ``keyword`` from one data line (blank = None)."""
    layout = LAYOUTS[keyword][index]
    if "," in card.text and layout[0][2] != "s":
        pieces = [p.strip() for p in card.text.split(",")]
        if len(pieces) > len(layout):
            raise SpecError(
                f"*{keyword} at {card.where()}", card.text.strip(),
                f"at most {len(layout)} comma-separated fields",
            )  # fmt: skip
    else:
        pieces, start = [], 0
        for _, width, kind in layout:
            w = LONG_WIDTH if long and kind != "s" else width
            pieces.append(card.text[start : start + w].strip())
            start += w
        if card.text[start:].strip():
            raise SpecError(
                f"*{keyword} at {card.where()}", card.text[start:].strip(),
                f"nothing after column {start} (fields {', '.join(n for n, _, _ in layout)})",
            )  # fmt: skip
    values: dict[str, object] = {}
    for (name, _, kind), text in zip(layout, pieces, strict=False):
        values[name] = _convert(text, kind, keyword, name, card)
    return values


def _convert(text: str, kind: str, keyword: str, name: str, card: CardLine) -> object:
    """A field's text as int, float or str; blank is None; unreadable text is a SpecError."""
    if not text:
        return None
    if kind == "s":
        return text
    try:
        number = float(_fortran_real(text))
    except ValueError:
        raise SpecError(f"*{keyword}.{name.upper()} at {card.where()}", text, "a number") from None
    if not math.isfinite(number):  # NaN or an overflow ('1+400'): never a value batball can use
        raise SpecError(f"*{keyword}.{name.upper()} at {card.where()}", text, "a finite number")
    if kind == "i":
        if number != int(number):
            raise SpecError(f"*{keyword}.{name.upper()} at {card.where()}", text, "an integer")
        return int(number)
    return number


def _fortran_real(text: str) -> str:
    """Fortran reals without the 'e' (``1.5-3``, ``2.+4``) and with 'd' made Python-readable."""
    t = text.lower().replace("d", "e")
    if "e" not in t:
        for i in range(len(t) - 1, 0, -1):
            if t[i] in "+-" and t[i - 1] not in "e":
                return t[:i] + "e" + t[i:]
    return t
