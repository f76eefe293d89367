"""The machine's own yardstick, measured in the same run as a benchmark: NumPy SGEMM and DGEMM
GFLOP/s on a given number of threads, and the CPU's model and vector width.

Hosts differ by about 3x in absolute speed, so a kernel's element-cycles per second is only
comparable between hosts (or between runs on a shared host) as a fraction of a yardstick taken
at the same time on the same threads. GEMM is the yardstick because it is what the machine's
floating-point units and caches can sustain on dense work, measured by a library tuned for the
host (OpenBLAS here, its kernel selected at run time for the CPU). An environment can force a
narrower kernel than the CPU has (OPENBLAS_CORETYPE=Haswell, AVX2, on an AVX-512 AMD Zen 5: half
the rate). So on a CPU with AVX-512 the yardstick is the better of the kernel the environment
gives OpenBLAS and its AVX-512 kernel.

Used by ``bench_ccor.py`` and ``bench_bbs_cycles.py``; on its own:

    python benchmarks/yardstick.py [--threads 1 2] [--size 2048]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

CHILD = """
import json, time
import numpy as np
n, repeats = {size}, {repeats}
out = {{}}
for name, dtype in (("sgemm", np.float32), ("dgemm", np.float64)):
    rng = np.random.default_rng(0)
    a = rng.standard_normal((n, n)).astype(dtype)
    b = rng.standard_normal((n, n)).astype(dtype)
    a @ b  # warm up (threads started, pages touched)
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        a @ b
        best = min(best, time.perf_counter() - start)
    out[name] = 2.0 * n**3 / best / 1e9
print(json.dumps(out))
"""

#: The environment variables that set the BLAS libraries' thread counts.
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


#: OpenBLAS's AVX-512 kernel. The kernel the environment gives OpenBLAS can be narrower than the
#: CPU: a host that sets OPENBLAS_CORETYPE=Haswell (AVX2) on an AVX-512 AMD EPYC (Zen 5)
#: measured 118-127 GFLOP/s of SGEMM on one thread, against 216-225 with this kernel
#: (benchmarks/RESULTS.md).
AVX512_CORETYPE = "SkylakeX"


def blas_kernels() -> list[str | None]:
    """The OpenBLAS kernels the yardstick tries: the one the environment gives it (None: its
    OPENBLAS_CORETYPE if set, else OpenBLAS's run-time choice) and, on a CPU with AVX-512F,
    :data:`AVX512_CORETYPE`. A BLAS other than OpenBLAS ignores the variable, and then both runs
    measure the same kernel."""
    kernels: list[str | None] = [None]
    if cpu_description()["vector_bits"] == 512 and os.environ.get("OPENBLAS_CORETYPE") != (
        AVX512_CORETYPE
    ):
        kernels.append(AVX512_CORETYPE)
    return kernels


def yardstick_label() -> str:
    """Words for the printouts: which BLAS kernels the yardstick is the best of."""
    kernels = blas_kernels()
    forced = os.environ.get("OPENBLAS_CORETYPE")
    given = f"OpenBLAS's {forced} kernel" if forced else "the BLAS's own choice of kernel"
    if len(kernels) == 1:
        return given
    return f"the best of {given} and OpenBLAS's {kernels[1]} (AVX-512) kernel"


def gemm_gflops(threads: int, *, size: int = 2048, repeats: int = 5) -> dict[str, float]:
    """SGEMM and DGEMM GFLOP/s (2 n^3 per product, the best of ``repeats``) on ``threads``
    BLAS threads, in a child process so that the thread count takes effect; each the best over
    :func:`blas_kernels`, so that the yardstick has the CPU's vector width, whatever kernel
    the environment gives the BLAS."""
    best: dict[str, float] = {}
    code = CHILD.format(size=size, repeats=repeats)
    for kernel in blas_kernels():
        env = {**os.environ, **dict.fromkeys(BLAS_THREADS, str(threads))}
        if kernel is not None:
            env["OPENBLAS_CORETYPE"] = kernel
        out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                             text=True, env=env)  # fmt: skip
        for name, rate in json.loads(out.stdout.strip().splitlines()[-1]).items():
            best[name] = max(best.get(name, 0.0), rate)
    return best


def cpu_description() -> dict[str, str | int]:
    """The CPU's model name, its widest vector unit in bits (from the kernel's flags: 512 with
    AVX-512F, 256 with AVX2, 128 otherwise) and the logical CPUs."""
    model, flags = platform.processor() or "unknown", set()
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.is_file():
        for line in cpuinfo.read_text(encoding="utf-8", errors="replace").splitlines():
            key, _, value = line.partition(":")
            if key.strip() == "model name":
                model = value.strip()
            elif key.strip() == "flags":
                flags = set(value.split())
    width = 512 if "avx512f" in flags else 256 if "avx2" in flags else 128
    return {"model": model, "vector_bits": width, "logical_cpus": os.cpu_count() or 1}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--threads", type=int, nargs="*", default=[1, os.cpu_count() or 1])
    parser.add_argument("--size", type=int, default=2048)
    args = parser.parse_args()
    cpu = cpu_description()
    print(f"{cpu['model']}, {cpu['vector_bits']}-bit vectors, {cpu['logical_cpus']} logical "
          f"CPUs; GEMM by {yardstick_label()}")  # fmt: skip
    for threads in sorted(set(args.threads)):
        g = gemm_gflops(threads, size=args.size)
        print(
            f"{threads} thread(s): SGEMM {g['sgemm']:.1f} GFLOP/s, DGEMM {g['dgemm']:.1f} GFLOP/s"
        )


if __name__ == "__main__":
    main()
