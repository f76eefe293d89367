"""Property tests (Hypothesis): whatever a spec or a keyword deck holds, reading it gives a result
or a one-line SpecError, never another exception or a hang."""

from __future__ import annotations

import contextlib
import tempfile
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from batball.errors import SpecError
from batball.lsdyna.model import read_deck
from batball.specs.ball import ball_spec_from_dict
from batball.specs.bat import bat_spec_from_dict
from batball.specs.document import read_spec_document

SETTINGS = settings(max_examples=200, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])  # fmt: skip

#: Values a TOML document can hold, biased toward what specs hold (quantities with units).
LEAVES = st.one_of(
    st.none(), st.booleans(), st.integers(-10**6, 10**6), st.floats(allow_nan=True),
    st.text(max_size=12),
    st.sampled_from(["12 in", "6.9 oz", "-1 in", "0 psi", "1e400 psi", "nan in", "3000 psi",
                     "mat006", "mat057", "elastic", "carbon", "30 deg", "0.001 in", "1 1/s"]),
)  # fmt: skip
VALUES = st.recursive(
    LEAVES,
    lambda inner: st.one_of(st.lists(inner, max_size=4),
                            st.dictionaries(st.text(max_size=8), inner, max_size=4)),
    max_leaves=12,
)  # fmt: skip
BALL_KEYS = ["name", "description", "circumference", "mass", "material"]
MATERIAL_KEYS = ["law", "bulk_modulus", "g0", "g_inf", "beta", "youngs_modulus", "curves",
                 "curve_scale", "hu", "shape", "damp"]  # fmt: skip


def spec_like(keys: list[str], nested: dict[str, list[str]]) -> st.SearchStrategy[dict[str, Any]]:
    """Dicts with a spec's keys (some missing, some odd) and odd values."""
    tables = {k: st.dictionaries(st.sampled_from(v), VALUES, max_size=len(v))
              for k, v in nested.items()}  # fmt: skip
    return st.dictionaries(
        st.sampled_from([*keys, "extra"]),
        st.deferred(lambda: VALUES),
        max_size=len(keys) + 1,
    ).flatmap(lambda d: st.fixed_dictionaries({k: tables[k] for k in nested}).map(
        lambda t: {**d, **{k: v for k, v in t.items() if k in d or v}}))


def only_spec_errors(read: Any, document: dict[str, Any]) -> None:
    with contextlib.suppress(SpecError):
        read(document, source="fuzz")


@SETTINGS
@given(spec_like(BALL_KEYS, {"material": MATERIAL_KEYS}))
def test_any_ball_document_reads_or_gives_a_spec_error(document: dict[str, Any]) -> None:
    only_spec_errors(ball_spec_from_dict, document)


@SETTINGS
@given(spec_like(["name", "description", "length", "materials", "profile", "parts", "insert"],
                 {"insert": ["start", "end", "layup", "interference"]}))
def test_any_bat_document_reads_or_gives_a_spec_error(document: dict[str, Any]) -> None:
    only_spec_errors(bat_spec_from_dict, document)


@SETTINGS
@given(st.binary(max_size=200))
def test_any_spec_file_reads_or_gives_a_spec_error(content: bytes) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "spec.toml"
        path.write_bytes(content)
        with contextlib.suppress(SpecError):
            read_spec_document(path, kind="ball", embedded=(), file_pattern="{name}.toml")


KEYWORDS = ["*KEYWORD", "*TITLE", "*NODE", "*ELEMENT_SOLID", "*PART", "*SECTION_SOLID",
            "*MAT_VISCOELASTIC", "*MAT_ELASTIC", "*HOURGLASS", "*CONTROL_TERMINATION",
            "*CONTROL_TIMESTEP", "*CONTACT_AUTOMATIC_NODES_TO_SURFACE", "*INITIAL_VELOCITY",
            "*DEFINE_CURVE", "*SET_NODE_LIST", "*INCLUDE", "*END", "*BOGUS"]  # fmt: skip
CARDS = st.one_of(
    st.text(alphabet=" 0123456789.-+eE,", max_size=80),
    st.lists(st.one_of(st.integers(-5, 10**6), st.floats(allow_nan=True, width=32)), max_size=8)
    .map(lambda xs: "".join(f"{x:>10}"[:10] for x in xs)),
    st.text(max_size=40),
)  # fmt: skip
DECKS = st.lists(st.tuples(st.sampled_from(KEYWORDS), st.lists(CARDS, max_size=4)), max_size=10)


@SETTINGS
@given(DECKS)
def test_any_deck_reads_or_gives_a_spec_error(blocks: list[tuple[str, list[str]]]) -> None:
    text = "\n".join(line for keyword, cards in blocks for line in (keyword, *cards)) + "\n"
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "deck.k"
        path.write_text(text, encoding="latin-1", errors="replace")
        with contextlib.suppress(SpecError):
            read_deck(path)
