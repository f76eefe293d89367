"""The hex element loop vectorises for both kinds of x86 CPU batball runs on, whatever the host.

The loop's speed rests on LLVM vectorising it across the cells of a block, and the width is the
target's: eight single-precision lanes in sixteen 256-bit registers on an AVX2 CPU (AMD Zen 3),
sixteen in thirty-two 512-bit registers on an AVX-512 one. A host only runs its own width, so
the other is checked here by compiling for a named CPU in a new process (LLVM compiles for the
CPU Numba names to it; nothing compiled there is run).
"""

from __future__ import annotations

import os
import platform
import re
import subprocess
import sys
from pathlib import Path

import pytest

SRC = str(Path(__file__).resolve().parents[3] / "src")
COMPILE = """
import numba
from numba import types
from batball.elements import hex8_block as hb
from numba.core.registry import CPUDispatcher
ran = [name for name, obj in vars(hb).items() if isinstance(obj, CPUDispatcher) and obj.overloads]
assert not ran, f"compiled at import (would run code built for another CPU): {ran}"
array = types.Array(types.float32, 1, "C")
signature = (array, array, types.int64, types.float64, types.float64, types.float64, types.float64)
hb.element_block_viscous.compile(signature)
print(hb.element_block_viscous.inspect_asm(signature))
"""
PACKED_SINGLE = r"\tv(?:add|sub|mul|div|f[n]?m(?:add|sub)\d*)ps\s[^\n]*%{register}"


def loop_assembly(cpu: str, features: str, cache: Path) -> str:
    env = {k: v for k, v in os.environ.items() if k != "BATBALL_VECTOR_WIDTH"}
    env |= {"PYTHONPATH": SRC, "NUMBA_CPU_NAME": cpu, "NUMBA_CPU_FEATURES": features,
            "NUMBA_CACHE_DIR": str(cache)}  # fmt: skip
    out = subprocess.run([sys.executable, "-c", COMPILE], env=env, capture_output=True,
                         text=True, check=False)  # fmt: skip
    assert out.returncode == 0, out.stderr
    return out.stdout


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="reads x86 assembly")
@pytest.mark.parametrize(
    ("cpu", "features", "register", "other"),
    [
        ("znver3", "+prefer-256-bit", "ymm", "zmm"),  # AVX2 only: the AMD EPYC hosts
        ("sapphirerapids", "-prefer-256-bit", "zmm", None),  # batball's 512-bit setting
    ],
)
def test_element_loop_vectorises_for_the_cpu_named(
    cpu: str, features: str, register: str, other: str | None, tmp_path: Path
) -> None:
    asm = loop_assembly(cpu, features, tmp_path)
    # over 400 packed-single arithmetic instructions on the target's widest registers, as the
    # host's own loop has (test_hex8_kernel.py): the cells of a block in the lanes
    packed = re.findall(PACKED_SINGLE.format(register=register), asm)
    assert len(packed) > 400, f"{len(packed)} packed-single instructions on {register}"
    if other is not None:
        assert f"%{other}" not in asm  # no instruction of a width the CPU lacks
