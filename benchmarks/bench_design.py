"""Time a design study end to end: ``python benchmarks/bench_design.py [STUDY.toml]``.

Runs the study (default: benchmarks/design_screening_100.toml: 100 designs screened on
16 x 0.5 in shells and a 4-division ball, the best three confirmed at full size) into a fresh
results store, so nothing is reused, on every core; prints the wall time per stage, the CPU and
its vector width, and the best designs with their ASA margins, as a row for RESULTS.md.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

from batball.design import load_design_study, run_design_study
from batball.numerics import wide_vectors
from batball.report.design_page import write_design_page

HERE = Path(__file__).resolve().parent


def cpu_model() -> str:
    """The CPU's model name (Linux), else what the platform says."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def main() -> None:
    """Run the study and print its timings."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("study", nargs="?", default=HERE / "design_screening_100.toml", type=Path)
    parser.add_argument("--out", type=Path, default=None, help="the study's folder (a temp dir)")
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    study = load_design_study(args.study)
    with tempfile.TemporaryDirectory() as scratch:
        out = args.out or Path(scratch) / "study"
        start = time.perf_counter()
        result = run_design_study(study, out_dir=out, runs_dir=Path(scratch) / "runs",
                                  workers=args.workers, progress=True,
                                  log=lambda text: print(text, flush=True))  # fmt: skip
        write_design_page(out)
        wall = time.perf_counter() - start
        summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    screened = {d.id: d for d in result.designs if d.stage != "confirm"}
    print(json.dumps({
        "study": study.name, "cpu": cpu_model(), "cores": os.cpu_count(),
        "vector_width_bits": 512 if wide_vectors() else 256, "designs": summary["designs"],
        "feasible": summary["feasible"], "wall_seconds": wall,
        "stage_seconds": summary["stage_seconds"],
        "best": [{"design": b["design"], "parameters": b["parameters"],
                  "screened": {k: b["responses"][k] for k in ("bbs_type1_110mph",
                                                              "moi_pivot_oz_in2", "weight_oz")},
                  "confirmed": b.get("confirmed")} for b in summary["best"]],
        "best_confirmed": summary["best_confirmed"],
        "confirmation_offset": summary["confirmation_offset"],
        "confirmed": [{"design": d.id, "round": d.round, "feasible": d.feasible,
                       "screened": screened[d.id].responses, "confirmed": d.responses}
                      for d in result.designs if d.stage == "confirm"],
    }, indent=2))  # fmt: skip
    print(f"{len(result.designs)} evaluations in {wall:.0f} s")


if __name__ == "__main__":
    main()
