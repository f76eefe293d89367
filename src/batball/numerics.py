"""Settings shared by every Numba kernel.

Importing this module (every kernel module does, before anything is compiled) also picks the SIMD
width LLVM generates (:func:`set_vector_width`) and makes Numba's inlining copy each inlined
function once rather than block by block (:func:`share_inline_copies`).
"""

from __future__ import annotations

import copy
import functools
import os

import numba as nb

from batball.errors import SpecError

#: Fast-math flags that keep NaN and infinity semantics, so failure checks still see them, and
#: leave out ``reassoc``: Numba links a copy of each non-inlined callee (and of each prange body)
#: into every cached kernel and optimises it again there, and with reassociation that copy and
#: the callee's first one round differently, so a process that compiled a kernel and one that
#: loaded it from the cache gave different bits (docs/notes/precision.md,
#: "Same input, same bits, compiled or cached").
FASTMATH = {"nsz", "arcp", "contract", "afn"}

#: Environment variable choosing the SIMD width of the kernels on a CPU with AVX-512: "512" (the
#: default) or "256".
VECTOR_WIDTH_VARIABLE = "BATBALL_VECTOR_WIDTH"

#: The LLVM feature that gives each width (bits, as the variable spells it) on a CPU with
#: AVX-512; on a CPU without it, "+prefer-256-bit" changes nothing.
WIDTH_FEATURES = {"512": "-prefer-256-bit", "256": "+prefer-256-bit"}


def set_vector_width() -> str | None:
    """Set the SIMD width LLVM vectorises with on a CPU with AVX-512 (512-bit, or 256-bit where
    ``BATBALL_VECTOR_WIDTH=256``); returns the feature string given to Numba, or None where
    nothing was changed (no AVX-512, or the user set ``NUMBA_CPU_FEATURES``).

    LLVM's own choice differs between CPUs: it tunes Skylake-server and later Intel CPUs with
    ``prefer-256-bit``, so loops are vectorised 4 doubles wide even where 8-wide AVX-512 exists
    (to avoid the frequency drop of heavy 512-bit code on early Skylake parts), and AMD's Zen 5
    without it. The hex kernel's element loop is straight-line arithmetic on blocks of cells
    (:mod:`batball.elements.hex8_block`); measured on this project's 2-core machines it runs
    20-25 % faster 8 wide on an Intel model 167, and the full-size CCOR solver takes 1.5-1.7 s
    on one thread of a Zen 5 against 1.8-1.85 s with 256-bit vectors (benchmarks/RESULTS.md).
    So the width is set either way, not left to LLVM. The setting only takes effect if Numba
    has not compiled anything yet in this process (its code generator is created once).
    Numba's on-disk cache is keyed on the feature string, so code compiled either way is never
    mixed up.
    """
    choice = os.environ.get(VECTOR_WIDTH_VARIABLE, "512")
    if choice not in ("256", "512"):
        raise SpecError(f"environment variable {VECTOR_WIDTH_VARIABLE}", choice, "256 or 512")
    if os.environ.get("NUMBA_CPU_FEATURES"):
        return None
    from llvmlite import binding

    host = binding.get_host_cpu_features()
    if not host.get("avx512f", False):
        return None
    features = host.flatten() + "," + WIDTH_FEATURES[choice]
    nb.config.CPU_FEATURES = features  # type: ignore[attr-defined]
    # so that Numba's reload of its configuration from the environment keeps it, and so that
    # worker processes (calibration pools, Dask) compile the same code
    os.environ["NUMBA_CPU_FEATURES"] = features
    return features


#: The feature string :func:`set_vector_width` gave Numba on import (None where it changed nothing).
VECTOR_FEATURES = set_vector_width()


def wide_vectors() -> bool:
    """Whether the kernels are compiled for 512-bit vectors: Numba's CPU features (set by
    :func:`set_vector_width`, or by the user in ``NUMBA_CPU_FEATURES``) enable AVX-512F and
    turn off LLVM's preference for 256-bit vectors.

    A function of the feature string alone, which is also part of the key of Numba's on-disk
    cache: a layout chosen from it (``hex8_block.BLOCK``) is the same in every process that
    shares a cached kernel, worker processes included (they inherit the string).
    """
    features = os.environ.get("NUMBA_CPU_FEATURES", "").split(",")
    return "+avx512f" in features and "-prefer-256-bit" in features


#: Environment variable choosing how Numba's inliner copies a function: "graph" (the default, one
#: copy of all its blocks) or "numba" (Numba's own, block by block; :func:`share_inline_copies`).
INLINE_COPY_VARIABLE = "BATBALL_INLINE_COPY"


class _OneMemoCopy:
    """Stands in for the ``copy`` module during one call of Numba's ``InlineWorker.inline_ir``:
    its ``deepcopy`` copies with one memo for all the calls, so the callee's blocks are copied
    as one graph."""

    def __init__(self) -> None:
        self.memo: dict[int, object] = {}

    def deepcopy(self, x: object, memo: dict[int, object] | None = None) -> object:
        return copy.deepcopy(x, self.memo if memo is None else memo)


def share_inline_copies() -> bool:
    """Make Numba copy a function's IR as one graph when it inlines it (``inline="always"``);
    returns whether it did (False where ``BATBALL_INLINE_COPY=numba`` or where Numba's inliner
    is not the one this was written for: nothing is changed then).

    Numba inlines a callee by copying its IR (twice: one copy to splice in, one to keep) with
    a separate ``copy.deepcopy`` for each basic block. Every block's variables refer to the
    function's one scope, which holds all its variables, so each block's copy copies all the
    function's variables again: the work grows as blocks times variables, for every inlined
    call at every level of a tree of inlined helpers (numba/numba issues 8989 and 9204). The
    kernels here inline deep trees: compiling the hex element loop spent about 40 % of its time
    in these copies. Within a call of ``inline_ir`` its module's ``copy`` is replaced by
    :class:`_OneMemoCopy`, so each copy of the callee is one deep copy of all its blocks,
    sharing what the original shares (the scope once), and the second copy is made from the
    first as before. The machine code of every kernel is the same either way, instruction for
    instruction (benchmarks/RESULTS.md, "Compile time"); only the time to make it changes. The
    swap of the module's ``copy`` is safe across threads because Numba compiles (and so inlines)
    under its global compiler lock.
    """
    choice = os.environ.get(INLINE_COPY_VARIABLE, "graph")
    if choice not in ("graph", "numba"):
        raise SpecError(f"environment variable {INLINE_COPY_VARIABLE}", choice, "graph or numba")
    if choice == "numba":
        return False
    from numba.core import inline_closurecall

    worker = getattr(inline_closurecall, "InlineWorker", None)
    inline_ir = getattr(worker, "inline_ir", None)
    if inline_closurecall.__dict__.get("copy") is not copy or inline_ir is None:
        return False
    if getattr(inline_ir, "_batball_one_memo", False):
        return True

    @functools.wraps(inline_ir)
    def one_memo_inline_ir(*args: object, **kwargs: object) -> object:
        previous = inline_closurecall.copy
        inline_closurecall.copy = _OneMemoCopy()  # type: ignore[assignment]
        try:
            return inline_ir(*args, **kwargs)
        finally:
            inline_closurecall.copy = previous

    one_memo_inline_ir._batball_one_memo = True  # type: ignore[attr-defined]
    worker.inline_ir = one_memo_inline_ir  # type: ignore[union-attr]
    return True


#: Whether :func:`share_inline_copies` changed Numba's inliner on import.
INLINE_COPIES_SHARED = share_inline_copies()
