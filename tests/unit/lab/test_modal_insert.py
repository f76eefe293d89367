"""The modal test's insert model is checked before any mesh is built."""

from __future__ import annotations

import pytest

from batball.errors import SpecError
from batball.lab.modal import bat_modes
from batball.specs import load_bat_spec


def test_an_unknown_insert_model_is_refused_by_name() -> None:
    with pytest.raises(SpecError, match="insert.*glued.*bonded, contact"):
        bat_modes(load_bat_spec("default"), insert="glued")
