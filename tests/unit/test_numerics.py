"""The kernels' vector-width choice, read from Numba's CPU feature string."""

from __future__ import annotations

import pytest

from batball.numerics import wide_vectors


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
