"""Calibration tests run many tiny impact runs: one Numba thread each (the machine is shared, and
a parallel region on a 400-hex ball costs more in synchronisation than it saves)."""

from __future__ import annotations

from collections.abc import Iterator

import numba
import pytest


@pytest.fixture(autouse=True)
def one_numba_thread() -> Iterator[None]:
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)
