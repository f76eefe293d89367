"""Settings for the whole suite.

Run in parallel (``pytest -n auto``, pytest-xdist), each worker's Numba kernels take one thread,
so that the workers share the cores rather than each spreading over all of them; a test may
still ask for more (``numba.set_num_threads``, up to the machine's count), as the
thread-independence checks do. (The environment's NUMBA_NUM_THREADS is left alone: Numba reads
it again when it compiles and refuses a change once its threads run.)
"""

from __future__ import annotations

import os

import pytest


@pytest.fixture(autouse=True, scope="session")
def _one_numba_thread_per_worker() -> None:
    if os.environ.get("PYTEST_XDIST_WORKER"):
        import numba

        numba.set_num_threads(1)
