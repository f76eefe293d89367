"""How much CCOR and DS change from 95 to 110 mph over every candidate of calibration studies.

The experiment (seed Tables 5 and 6) has type 1's CCOR falling by 6.6 % from 95 to 110 mph while
its DS rises by 1 %; this counts what the candidates a study evaluated (both speeds on the same
mesh) can do, to tell an optimiser that stopped early from a model that cannot follow the data.

Usage: python benchmarks/ccor_speed_dependence.py STUDY.db [STUDY.db ...]
"""

from __future__ import annotations

import json
import sqlite3
import sys
from collections import defaultdict

MPH = 0.44704


def pairs(path: str) -> list[tuple[int, dict, dict]]:
    """(divisions, measures at 95 mph, at 110 mph) of every candidate run at both speeds."""
    runs: dict[str, dict[int, dict]] = defaultdict(dict)
    divisions: dict[str, int] = {}
    with sqlite3.connect(path) as db:
        for inputs, outcome in db.execute("select inputs, outcome from runs"):
            i, o = json.loads(inputs), json.loads(outcome)
            if i["test"] != "ccor" or "measures" not in o:
                continue
            key = json.dumps([i["divisions"], i["law"], i["values"]], sort_keys=True)
            runs[key][round(float.fromhex(i["speed"]) / MPH)] = o["measures"]
            divisions[key] = i["divisions"]
    return [(divisions[k], r[95], r[110]) for k, r in runs.items() if 95 in r and 110 in r]


def summary(path: str, near: float = 0.10) -> str:
    """Per mesh: the CCOR and DS change over all candidates, and over those whose DS at both
    speeds lies within ``near`` of type 1's experiment (7190 and 7260 lbf/in)."""
    lines = [path]
    ds_exp = {95: 7190 * 4.4482216152605 / 0.0254, 110: 7260 * 4.4482216152605 / 0.0254}
    by_mesh: dict[int, list[tuple[float, float, bool]]] = defaultdict(list)
    for div, a, b in pairs(path):
        ccor = 100 * (b["restitution"] / a["restitution"] - 1)
        ds = 100 * (b["dynamic_stiffness"] / a["dynamic_stiffness"] - 1)
        close = all(
            abs(m["dynamic_stiffness"] / ds_exp[s] - 1) <= near for s, m in ((95, a), (110, b))
        )
        by_mesh[div].append((ccor, ds, close))
    for div, rows in sorted(by_mesh.items()):
        for label, sel in (("all", rows), (f"DS within {near:.0%}", [r for r in rows if r[2]])):
            if not sel:
                continue
            c = [r[0] for r in sel]
            d = [r[1] for r in sel]
            lines.append(
                f"  {div} div, {label}: {len(sel)} candidates, CCOR change "
                f"{min(c):+.1f} .. {max(c):+.1f} %, DS change {min(d):+.1f} .. {max(d):+.1f} %"
            )
    return "\n".join(lines)


if __name__ == "__main__":
    print("\n".join(summary(p) for p in sys.argv[1:]))
