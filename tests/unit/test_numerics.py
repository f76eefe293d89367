"""The kernels' vector-width choice, read from Numba's CPU feature string, and Numba's inliner
copying each inlined function as one graph (:func:`batball.numerics.share_inline_copies`)."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable

import numpy as np
import pytest

from batball.numerics import INLINE_COPY_VARIABLE, wide_vectors


@pytest.mark.parametrize(
    ("features", "wide"),
    [
        ("+avx2,+avx512f,-prefer-256-bit", True),  # as set_vector_width sets it
        ("+avx2,+avx512f", False),  # AVX-512 with LLVM's own tuning
        ("+avx2,+avx512f,+prefer-256-bit", False),
        ("+avx2,+fma,-prefer-256-bit", False),  # no AVX-512
        ("+avx2,-avx512f,-prefer-256-bit", False),
        ("", False),
    ],
)
def test_wide_vectors_follows_the_feature_string(monkeypatch, features: str, wide: bool) -> None:
    monkeypatch.setenv("NUMBA_CPU_FEATURES", features)
    assert wide_vectors() is wide


# Numba's inlining copy (batball.numerics.share_inline_copies): a small tree of inlined helpers,
# with branches and loops so that the callees have several blocks, compiled once with the
# one-graph copy and once with Numba's own.


def _helpers() -> Callable[[np.ndarray], np.ndarray]:
    """A fresh (uncompiled) kernel calling its own fresh inlined helpers."""
    import numba

    @numba.njit(inline="always")
    def leaf(x: float, k: int) -> float:
        return x * k if k % 2 else x - k

    @numba.njit(inline="always")
    def middle(a: np.ndarray, i: int) -> float:
        s = 0.0
        for k in range(3):
            s += leaf(a[i], k) if a[i] > 0 else leaf(-a[i], k + 1)
        return s

    def kernel(a: np.ndarray) -> np.ndarray:
        out = np.empty_like(a)
        for i in range(a.size):
            out[i] = middle(a, i) + leaf(a[i], i)
        return out

    return kernel


def _instructions(dispatcher: object) -> list[str]:
    """The mnemonics of the compiled function's machine code (names, which carry per-process
    hashes, left out)."""
    (signature,) = dispatcher.signatures  # type: ignore[attr-defined]
    asm = dispatcher.inspect_asm(signature)  # type: ignore[attr-defined]
    return [line.split()[0] for line in asm.splitlines() if line.startswith("\t") and
            not line.startswith("\t.")]  # fmt: skip


def test_inlined_code_is_the_same_with_the_one_graph_copy(monkeypatch) -> None:
    import numba
    from numba.core import inline_closurecall

    from batball import numerics

    if os.environ.get(INLINE_COPY_VARIABLE) == "numba":
        pytest.skip("BATBALL_INLINE_COPY=numba: Numba's own inliner copies asked for")
    assert numerics.INLINE_COPIES_SHARED  # on the Numba the project pins
    copies = []
    one_memo = numerics._OneMemoCopy.deepcopy

    def counted(self: object, x: object, memo: object = None) -> object:
        copies.append(id(self))
        return one_memo(self, x, memo)  # type: ignore[arg-type]

    monkeypatch.setattr(numerics._OneMemoCopy, "deepcopy", counted)
    worker = inline_closurecall.InlineWorker
    shared = worker.inline_ir
    a = np.array([1.5, -2.0, 0.25, 3.0, -0.5])
    ours = numba.njit(_helpers())
    ours(a)
    # each inlined call (leaf twice in middle, middle and leaf in kernel) copied its callee's
    # blocks through one memo
    assert len(set(copies)) == 4 and len(copies) > 8
    worker.inline_ir = shared.__wrapped__  # Numba's own, block by block
    try:
        numbas = numba.njit(_helpers())
        expected = numbas(a)
    finally:
        worker.inline_ir = shared
    got = ours(a)
    np.testing.assert_array_equal(got, _helpers()(a))  # as plain Python computes it
    np.testing.assert_array_equal(got, expected)
    assert _instructions(ours) == _instructions(numbas)


def _import_numerics(value: str | None) -> subprocess.CompletedProcess:
    """Import batball.numerics in a fresh interpreter with BATBALL_INLINE_COPY set to ``value``
    (unset for None), printing whether the one-graph copy was applied."""
    env = {k: v for k, v in os.environ.items() if k != INLINE_COPY_VARIABLE}
    if value is not None:
        env[INLINE_COPY_VARIABLE] = value
    code = "import batball.numerics as n; print(n.INLINE_COPIES_SHARED)"
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=False)  # fmt: skip


@pytest.mark.parametrize(("value", "shared"), [(None, True), ("numba", False)])
def test_batball_inline_copy_numba_leaves_numbas_inliner(value: str | None, shared: bool) -> None:
    done = _import_numerics(value)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == str(shared)


def test_another_batball_inline_copy_is_refused_by_name() -> None:
    done = _import_numerics("off")
    assert done.returncode != 0
    last = done.stderr.strip().splitlines()[-1]
    assert INLINE_COPY_VARIABLE in last and "'off'" in last and "graph or numba" in last
