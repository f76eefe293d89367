"""Settings shared by every Numba kernel."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numba as nb

#: Fast-math flags that keep NaN and infinity semantics, so failure checks still see them.
FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}


@contextmanager
def threads_for_work(work: int, *, parallel_min_work: int) -> Iterator[None]:
    """Run the enclosed Numba parallel kernels on one thread when ``work`` (a count of inner
    iterations) is below ``parallel_min_work``, on all of Numba's threads otherwise.

    A parallel region has to wake its worker threads: microseconds on an idle machine, but on
    the shared 2-core machine under load (load average 6) each region of the full-size BBS
    contact cost about 30 ms with 2 threads against 0.01-4 ms on one (docs/bbs.md), so small
    kernels are better left serial.
    """
    threads = nb.get_num_threads()
    if work >= parallel_min_work or threads == 1:
        yield
        return
    nb.set_num_threads(1)
    try:
        yield
    finally:
        nb.set_num_threads(threads)
