"""The SIMD-width setting of batball.numerics: applied in a fresh process only where the CPU has
AVX-512, either width giving code of that width, and a bad value is named."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from llvmlite import binding

SRC = str(Path(__file__).resolve().parents[2] / "src")
PROBE = (
    "import numba; from llvmlite import binding; from batball import numerics; "
    "print(binding.get_host_cpu_features().get('avx512f', False), "
    "numba.config.CPU_FEATURES is not None and '-prefer-256-bit' in numba.config.CPU_FEATURES, "
    "numba.config.CPU_FEATURES is not None and '+prefer-256-bit' in numba.config.CPU_FEATURES)"
)
# a loop LLVM vectorises; which registers its machine code names
ASM_PROBE = (
    "import numpy as np, numba; from batball import numerics\n"
    "@numba.njit\n"
    "def axpy(a, b):\n"
    "    for i in range(a.size):\n"
    "        a[i] = 2.0 * a[i] + b[i]\n"
    "x = np.ones(4096)\n"
    "axpy(x, x)\n"
    "asm = ''.join(axpy.inspect_asm().values())\n"
    "print('zmm' in asm, 'ymm' in asm)"
)


def probe(code: str = PROBE, **env: str) -> subprocess.CompletedProcess:
    clean = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CPU_FEATURES",)}
    clean.pop("BATBALL_VECTOR_WIDTH", None)
    return subprocess.run(
        [sys.executable, "-c", code], env=clean | {"PYTHONPATH": SRC} | env,
        capture_output=True, text=True, check=False,
    )  # fmt: skip


def test_default_prefers_512_bit_exactly_where_the_cpu_has_avx512() -> None:
    out = probe()
    assert out.returncode == 0, out.stderr
    has_avx512, wide, narrow = out.stdout.split()
    assert (wide, narrow) == (has_avx512, "False")


def test_256_asks_for_256_bit_vectors_where_the_cpu_has_avx512() -> None:
    out = probe(BATBALL_VECTOR_WIDTH="256")
    assert out.returncode == 0, out.stderr
    has_avx512, wide, narrow = out.stdout.split()
    assert (wide, narrow) == ("False", has_avx512)


@pytest.mark.parametrize("width", ["256", "512"])
def test_the_machine_code_has_the_width_asked_for(width: str) -> None:
    """512-bit registers (zmm) in a vectorised loop only where 512 is asked for and the CPU has
    AVX-512; LLVM's own choice would give them for 256 too on some CPUs (AMD Zen 5)."""
    has_avx512 = bool(binding.get_host_cpu_features().get("avx512f", False))
    out = probe(ASM_PROBE, BATBALL_VECTOR_WIDTH=width)
    assert out.returncode == 0, out.stderr
    zmm, ymm = out.stdout.split()
    assert zmm == str(has_avx512 and width == "512")
    if width == "256" and has_avx512:
        assert ymm == "True"  # vectorised all the same, 256 bits wide


@pytest.mark.parametrize("value", ["300", "wide"])
def test_bad_width_names_the_variable_and_the_choices(value: str) -> None:
    out = probe(BATBALL_VECTOR_WIDTH=value)
    assert out.returncode != 0
    assert "BATBALL_VECTOR_WIDTH" in out.stderr and "256 or 512" in out.stderr
