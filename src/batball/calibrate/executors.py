"""Where evaluations run: in this process, a local process pool (default) or a Dask cluster.

All three are :class:`concurrent.futures.Executor` objects: Dask's ``Client.get_executor()``
speaks the same interface, so the study code does not know which one it drives.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterator
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from contextlib import contextmanager
from typing import Any

from batball.calibrate.evaluate import limit_threads
from batball.errors import SpecError

#: How often a pool worker checks that the process that started it is alive [s].
PARENT_CHECK_SECONDS = 0.5


def _exit_with_parent(parent: int) -> None:
    """Watch ``parent`` from a daemon thread; exit this process at once when it is gone (a
    SIGKILLed ``batball calibrate`` cannot shut its pool down, and its workers would otherwise
    wait on their pipe forever)."""
    import threading
    import time

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_CHECK_SECONDS)
        os._exit(1)

    threading.Thread(target=watch, name="batball-parent-watch", daemon=True).start()


def _init_worker(threads: int, parent: int) -> None:
    """Pool worker initialiser: its Numba threads, and exit when the parent dies."""
    _exit_with_parent(parent)
    limit_threads(threads)


class InlineExecutor(Executor):
    """Runs each call at submission, in this process (for debugging and tiny studies)."""

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future[Any]:
        future: Future[Any] = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # handed to the caller through the future
            future.set_exception(exc)
        return future


def default_workers() -> int:
    """Workers of the local pool: the CPU cores this process may use."""
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1)


@contextmanager
def open_executor(*, workers: int, scheduler: str | None = None) -> Iterator[Executor]:
    """An executor for the study, shut down on exit.

    Args:
        workers: local pool size (0: run in this process); ignored with ``scheduler``.
        scheduler: a Dask scheduler address (``tcp://host:8786``), or None for the local pool.

    Raises:
        SpecError: ``workers`` negative, or a scheduler given without dask.distributed installed.
    """
    if workers < 0:
        raise SpecError("workers", workers, "0 (this process) or a positive pool size")
    if scheduler is not None:
        with _dask_executor(scheduler) as executor:
            yield executor
        return
    if workers == 0:
        yield InlineExecutor()
        return
    threads = max(1, default_workers() // workers)
    # spawn, not fork: a forked child of a process whose Numba threads already run can hang
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=_init_worker,
                             initargs=(threads, os.getpid())) as pool:  # fmt: skip
        yield pool


@contextmanager
def _dask_executor(scheduler: str) -> Iterator[Executor]:
    """A ``concurrent.futures`` view of a Dask distributed client."""
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - the extra is part of the test dependencies
        raise SpecError(
            "scheduler", scheduler, "an address usable after pip install 'batball[dask]'"
        ) from None
    try:
        client = Client(scheduler, timeout="20s")
    except (ValueError, TypeError, OSError) as exc:  # a malformed address, or none listening
        raise SpecError("scheduler", scheduler, "the address of a running Dask scheduler, "
                        f"e.g. tcp://host:8786 ({type(exc).__name__})") from None  # fmt: skip
    with client:
        yield client.get_executor(pure=False)
