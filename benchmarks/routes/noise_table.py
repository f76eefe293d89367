"""The spread of the routes under measurement noise (docs/notes/calibration-routes.md, issue 12).

Reads ``results/noise-<tag>-seed-<N>.json`` (benchmarks/routes/noise_study.sh) and prints, per
route, each seed's BBS error and G(t), then the mean and sample standard deviation over the
seeds, as a Markdown table.

Run: ``PYTHONPATH=src python benchmarks/routes/noise_table.py [tag]`` (tag: ``synthetic``).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).resolve().parent / "results"


def _row(route: dict) -> list[float]:
    """BBS errors (mph) per speed, then G(t) (psi) at the report's times, then K (psi)."""
    errors = [route["bbs_error_mph"][s] for s in sorted(route["bbs_error_mph"], key=float)]
    relaxation = list(route["relaxation_psi"].values())
    k = float(route["parameters"]["bulk_modulus"].split()[0])
    return [*errors, *relaxation, k]


def main(tag: str = "synthetic") -> None:
    files = sorted(RESULTS.glob(f"noise-{tag}-seed-*.json"))
    if not files:
        raise SystemExit(f"no results/noise-{tag}-seed-*.json")
    reports = [json.loads(f.read_text()) for f in files]
    speeds = sorted(reports[0]["routes"][0]["bbs_error_mph"], key=float)
    times = list(reports[0]["routes"][0]["relaxation_psi"])
    head = [f"BBS err @ {s} mph" for s in speeds] + [f"G({t}) psi" for t in times] + ["K psi"]
    print("| route | seed | " + " | ".join(head) + " |")
    print("|---" * (len(head) + 2) + "|")
    for i, route in enumerate(reports[0]["routes"]):
        rows = []
        for f, r in zip(files, reports, strict=True):
            values = _row(r["routes"][i])
            rows.append(values)
            seed = f.stem.rsplit("-", 1)[1]
            cells = [f"{v:+.2f}" for v in values[: len(speeds)]]
            cells += [f"{v:,.0f}" for v in values[len(speeds) :]]
            print(f"| `{route['route']}` | {seed} | " + " | ".join(cells) + " |")
        a = np.array(rows)
        mean, sd = a.mean(axis=0), a.std(axis=0, ddof=1) if len(a) > 1 else 0 * a[0]
        pairs = list(zip(mean, sd, strict=True))
        cells = [f"{m:+.2f} ± {s:.2f}" for m, s in pairs[: len(speeds)]]
        cells += [f"{m:,.0f} ± {s:,.0f}" for m, s in pairs[len(speeds) :]]
        print(f"| `{route['route']}` | mean ± sd | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(*sys.argv[1:])
