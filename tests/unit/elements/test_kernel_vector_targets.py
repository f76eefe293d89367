"""The element kernels (hex, MITC4 and Belytschko-Tsay shells) vectorise for both kinds of x86
CPU batball runs on, whatever the host.

Their speed rests on LLVM vectorising their loops across the cells of a block or chunk, and the
width is the target's: sixteen 256-bit registers on an AVX2 CPU (AMD Zen 3), thirty-two 512-bit
ones on an AVX-512 CPU with batball's 512-bit setting. A host compiles only for itself, so the
other width is checked here by compiling for a named CPU in a new process with an empty Numba
cache (LLVM compiles for the CPU Numba names to it). Nothing compiled there is run: code for a
CPU the host is not may not run on it, which is why the child also checks that importing the
kernel's module compiled nothing.
"""

from __future__ import annotations

import os
import platform
import re
import subprocess
import sys
from pathlib import Path

import pytest

from batball.numerics import WIDTH_FEATURES

SRC = str(Path(__file__).resolve().parents[3] / "src")

#: The child's start: import a kernel's module, and check that no batball function was compiled
#: (hence run) on the way.
IMPORT = """
import sys
import numpy as np
import numba
from numba.core.registry import CPUDispatcher
from batball.elements import {module} as kernels
ran = [f"{{name}}.{{key}}" for name, module in sys.modules.items() if name.startswith("batball")
       for key, value in vars(module).items()
       if isinstance(value, CPUDispatcher) and value.overloads]
assert not ran, f"compiled at import (would run code built for another CPU): {{ran}}"
"""

#: The hex element loop in single precision (the CCOR's), typed from its arguments' types.
HEX = (
    IMPORT.format(module="hex8_block")
    + """
signature = kernels.element_block_types(np.float32)
kernel = kernels.element_block_viscous
"""
)

#: The MITC4 kernel's chunk (a chunk of cells of one kind), typed from arrays of its arguments'
#: dtypes and ranks (n_points, n_cells and n_chunks of 1: only the types matter).
MITC4 = (
    IMPORT.format(module="shell_corotational")
    + """
f8, i8 = np.zeros((1, 3)), np.zeros((1, 4), np.int64)
arguments = (f8, i8, np.zeros((1, 3, 3)), np.zeros(1), np.zeros((24, 24)),
             np.zeros((6, 6), np.uint8), 0, 1, np.zeros(4, np.int8), np.zeros(1), np.zeros((1, 6)))
signature = tuple(numba.typeof(a) for a in arguments)
kernel = kernels.chunk_forces
"""
)

#: The Belytschko-Tsay shells' kinematics over a block of cells (frame, B, strain rates, the
#: shear and hourglass update), typed from its arguments' types.
BT = (
    IMPORT.format(module="shell_bt")
    + """
arguments = (np.zeros(1), 1, 0.1, (0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
signature = tuple(numba.typeof(a) for a in arguments)
kernel = kernels.block_kinematics
"""
)

#: The child's end: compile, without running, and print the assembly.
PRINT = """
kernel.compile(signature)
print(kernel.inspect_asm(signature))
"""

#: Packed arithmetic (add, sub, mul, div, FMA) of a precision (ps, pd) naming a register kind.
PACKED = r"\tv(?:add|sub|mul|div|f[n]?m(?:add|sub)\d*){precision}\s[^\n]*%{register}"


def assembly(kernel: str, cpu: str, features: str, cache: Path) -> str:
    env = {k: v for k, v in os.environ.items() if k != "BATBALL_VECTOR_WIDTH"}
    env |= {"PYTHONPATH": SRC, "NUMBA_CPU_NAME": cpu, "NUMBA_CPU_FEATURES": features,
            "NUMBA_CACHE_DIR": str(cache)}  # fmt: skip
    out = subprocess.run([sys.executable, "-c", kernel + PRINT], env=env, capture_output=True,
                         text=True, check=False)  # fmt: skip
    assert out.returncode == 0, out.stderr
    return out.stdout


TARGETS = [
    ("znver3", WIDTH_FEATURES["256"], "ymm", "zmm"),  # AVX2 only: the AMD EPYC hosts
    ("sapphirerapids", WIDTH_FEATURES["512"], "zmm", None),  # batball's 512-bit setting
]


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="reads x86 assembly")
@pytest.mark.parametrize(
    ("kernel", "precision", "least"),
    [
        # the host's own hex loop has over 400 such instructions (test_hex8_kernel.py); compiled
        # for either target here, 990
        pytest.param(HEX, "ps", 400, id="hex8"),
        # the MITC4 chunk's SIMD loops over its columns (deformation, the rotation series,
        # K0 d, balance and global axes): 676 for either target here, the deformation's loop
        # alone well over a third of them
        pytest.param(MITC4, "pd", 400, id="mitc4"),
        # the BT shells' kinematics loop: 304 for either target here
        pytest.param(BT, "pd", 150, id="bt"),
    ],
)
@pytest.mark.parametrize(("cpu", "features", "register", "other"), TARGETS)
def test_kernel_vectorises_for_the_cpu_named(
    kernel: str,
    precision: str,
    least: int,
    cpu: str,
    features: str,
    register: str,
    other: str | None,
    tmp_path: Path,
) -> None:
    asm = assembly(kernel, cpu, features, tmp_path)
    packed = re.findall(PACKED.format(precision=precision, register=register), asm)
    assert len(packed) > least, f"{len(packed)} packed {precision} instructions on {register}"
    if other is not None:
        assert f"%{other}" not in asm  # no instruction of a width the CPU lacks
