"""Run the bat design study of ``barrel_layup_study.toml`` from Python and read its results.

    python examples/design_study.py           # the study at its own size: about half an hour
    BATBALL_EXAMPLE_TINY=1 python examples/design_study.py   # tiny meshes, 6 designs, a minute

The same as ``batball design examples/barrel_layup_study.toml``; writes ``designs/barrel-layup/``
(``designs.csv``, ``best/*.toml``, ``summary.json``, ``index.html``) in the current folder.
"""

import os
import tomllib
from pathlib import Path

from batball.design import design_study_from_dict, run_design_study
from batball.design.run import load_rows
from batball.report.design_page import write_design_page


def main() -> None:
    """Run it (a function, so that the process pool's workers can import this file)."""
    here = Path(__file__).resolve().parent
    document = tomllib.loads((here / "barrel_layup_study.toml").read_text(encoding="utf-8"))
    if os.environ.get("BATBALL_EXAMPLE_TINY"):  # the test suite's size: indicative values only
        document["mesh"] = {"circumferential": 8, "axial_size": "1 in", "ball_divisions": 2}
        document["sampling"]["designs"] = 6
        document["optimise"]["evaluations"] = 2
        document["confirm"] = {"top": 1, "circumferential": 8, "axial_size": "0.5 in",
                               "ball_divisions": 3}
    study = design_study_from_dict(document, base=here)

    out = Path("designs") / study.name
    result = run_design_study(study, out_dir=out, runs_dir=Path("runs"), progress=True)
    page = write_design_page(out)

    rows = load_rows(out)
    feasible = [r for r in rows if r["feasible"] and r["stage"] != "confirm"]
    print(f"{len(rows)} designs evaluated, {len(feasible)} feasible, {result.seconds:.0f} s")
    for best in [d for d in result.ranking if d.feasible][:3]:
        r = best.responses
        print(f"  {best.id}: BBS {r['bbs_type1_110mph']:.1f} mph "
              f"(ASA margin {98.0 - r['bbs_type1_110mph']:+.1f} mph), "
              f"MOI {r['moi_pivot_oz_in2']:.0f} oz*in^2, weight {r['weight_oz']:.2f} oz")
    print(f"page: {page}")


if __name__ == "__main__":
    main()
