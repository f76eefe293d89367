"""Reading a spec's TOML document: an embedded name or a file path, with one-line errors."""

from __future__ import annotations

import re
import tomllib
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

from batball.errors import SpecError


def read_spec_document(
    name_or_path: str | Path, *, kind: str, embedded: Sequence[str], file_pattern: str
) -> tuple[dict[str, Any], str]:
    """The parsed TOML of an embedded spec or of a file, and a description of where it came from.

    Args:
        name_or_path: an embedded name (one of ``embedded``) or the path of a TOML file.
        kind: what is read, for messages and the error's field ("ball", "bat").
        embedded: the embedded names.
        file_pattern: package-data file name of an embedded spec, with ``{name}``.

    Raises:
        SpecError: neither an embedded name nor an existing file, or invalid TOML.
    """
    if isinstance(name_or_path, str) and name_or_path in embedded:
        data = resources.files("batball.specs").joinpath(
            "data", file_pattern.format(name=name_or_path)
        )
        text, source = data.read_text(encoding="utf-8"), f"embedded {kind} {name_or_path!r}"
    else:
        path = Path(name_or_path)
        if not path.is_file():
            allowed = f"an embedded {kind} ({', '.join(embedded)}) or the path of a TOML file"
            raise SpecError(kind, str(name_or_path), allowed)
        try:
            text, source = path.read_text(encoding="utf-8"), str(path)
        except UnicodeDecodeError:
            raise SpecError(kind, str(path), "a TOML file in UTF-8 text") from None
        except OSError as exc:
            raise SpecError(kind, str(path), f"a readable TOML file ({exc.strerror})") from None
    try:
        return tomllib.loads(text), source
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(kind, source, f"valid TOML ({exc})") from None


#: What a name in a spec (a ball, a bat, a part, a material, a ply label) may be: it is written
#: into keyword decks and run-folder and study-file names, so it must not carry a newline, a
#: path separator or a keyword's ``*``.
NAME_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}")
NAME_TEXT = "1-64 letters, digits, '.', '_' or '-', starting with a letter or digit"


def check_name(field: str, value: object) -> str:
    """``value`` if it is a safe name (:data:`NAME_PATTERN`), else a one-line
    :class:`~batball.errors.SpecError` naming ``field``."""
    if not isinstance(value, str) or NAME_PATTERN.fullmatch(value) is None:
        raise SpecError(field, value, NAME_TEXT)
    return value
