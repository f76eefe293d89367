"""The SIMD-width setting of batball.numerics (issue 2): applied in a fresh process only where the
CPU has AVX-512, switchable off, and a bad value is named."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

SRC = str(Path(__file__).resolve().parents[2] / "src")
PROBE = (
    "import numba; from llvmlite import binding; from batball import numerics; "
    "print(binding.get_host_cpu_features().get('avx512f', False), "
    "numba.config.CPU_FEATURES is not None and '-prefer-256-bit' in numba.config.CPU_FEATURES)"
)


def probe(**env: str) -> subprocess.CompletedProcess:
    clean = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CPU_FEATURES",)}
    clean.pop("BATBALL_VECTOR_WIDTH", None)
    return subprocess.run(
        [sys.executable, "-c", PROBE], env=clean | {"PYTHONPATH": SRC} | env,
        capture_output=True, text=True, check=False,
    )  # fmt: skip


def test_default_prefers_512_bit_exactly_where_the_cpu_has_avx512() -> None:
    out = probe()
    assert out.returncode == 0, out.stderr
    has_avx512, applied = out.stdout.split()
    assert applied == has_avx512


def test_256_leaves_llvm_tuning_alone() -> None:
    out = probe(BATBALL_VECTOR_WIDTH="256")
    assert out.returncode == 0, out.stderr
    assert out.stdout.split()[1] == "False"


@pytest.mark.parametrize("value", ["300", "wide"])
def test_bad_width_names_the_variable_and_the_choices(value: str) -> None:
    out = probe(BATBALL_VECTOR_WIDTH=value)
    assert out.returncode != 0
    assert "BATBALL_VECTOR_WIDTH" in out.stderr and "256 or 512" in out.stderr
