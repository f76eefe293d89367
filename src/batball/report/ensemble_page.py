"""An ensemble's page: ``index.html`` beside its ``summary.json`` and ``members.csv``.

One static HTML page (the design page's style; the figure a PNG under ``figures/``): each cell
(ball and speed) with its mean, 95 % interval, width against the experiment, the bat's, the
ball's and the interaction's share, the experiment and the seed's LS-DYNA where seed Table 9
has the cell; each trend; each ranking's probability; the bats (their offsets in spreads and
each parameter's posterior over prior spread). The figure shows every member, the interval and
the experiment per cell. Every value is read from the two files; nothing is recomputed.
"""

from __future__ import annotations

import csv
import json
import math
from collections.abc import Mapping, Sequence
from html import escape
from pathlib import Path
from typing import Any

from batball.report.html_parts import IMAGE_CHECK, STYLE, table

#: The figure's size (inches) and resolution.
FIGSIZE = (7.5, 4.5)
DPI = 120


def write_ensemble_page(out_dir: Path) -> Path:
    """Write ``out_dir/index.html`` and ``out_dir/figures/cells.png`` from the ensemble's
    ``summary.json`` and ``members.csv`` in ``out_dir``, each file atomically.

    Returns:
        The page's path.
    """
    from batball.results.store import write_text_atomic

    out_dir = Path(out_dir)
    summary = json.loads((out_dir / "summary.json").read_text(encoding="utf-8"))
    with (out_dir / "members.csv").open(encoding="utf-8", newline="") as stream:
        members = list(csv.DictReader(stream))
    draw_cells(summary, members, out_dir / "figures" / "cells.png")
    path = out_dir / "index.html"
    write_text_atomic(path, render_page(summary, members))
    return path


def draw_cells(summary: Mapping[str, Any], members: Sequence[Mapping[str, str]],
               path: Path) -> None:  # fmt: skip
    """Per cell: every member (one colour per ball model, the study's own bat filled), the
    95 % interval as a bar, the experiment as a black diamond, the seed's LS-DYNA as a cross."""
    from batball.report.design_figures import save
    from batball.results.plots import new_figure

    fig, ax = new_figure(figsize=FIGSIZE, dpi=DPI)
    cells = summary["cells"]
    models = list(summary["balls"])
    colours = {m: f"C{i % 10}" for i, m in enumerate(models)}
    labelled: set[str] = set()
    for x, cell in enumerate(cells):
        st = cell["stats"]
        ax.plot([x, x], [st["low"], st["high"]], color="0.6", linewidth=6, solid_capstyle="butt",
                label=None if "interval" in labelled else "95 % interval")  # fmt: skip
        labelled.add("interval")
        for m in members:
            if m["ball"] != cell["ball"] or not math.isclose(float(m["speed_mph"]),
                                                               cell["speed_mph"], rel_tol=1e-9):
                continue
            if not m["bbs_mph"]:
                continue
            group = [s for s in models if summary["balls"][s] == cell["ball"]]
            offset = 0.1 + 0.3 * group.index(m["ball_model"]) / max(len(group) - 1, 1)
            name = Path(m["ball_model"]).stem
            ax.scatter(x + offset, float(m["bbs_mph"]), s=22, color=colours[m["ball_model"]],
                       edgecolors="black" if m["bat"] == "bat-0" else "none", zorder=3,
                       label=None if name in labelled else name)  # fmt: skip
            labelled.add(name)
        if "experiment_mph" in cell:
            ax.scatter(x, cell["experiment_mph"], marker="D", s=50, color="black", zorder=4,
                       label=None if "exp" in labelled else "experiment")  # fmt: skip
            ax.scatter(x, cell["seed_lsdyna_mph"], marker="x", s=50, color="tab:red", zorder=4,
                       label=None if "exp" in labelled else "seed LS-DYNA")  # fmt: skip
            labelled.add("exp")
    ax.set_xticks(range(len(cells)),
                  [f"{c['ball']}\n{c['speed_mph']:.4g} mph" for c in cells])  # fmt: skip
    ax.set_xlim(-0.4, len(cells) - 0.4)
    ax.set_ylabel("batted-ball speed [mph]")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    save(fig, path)


def _mph(value: float, sign: bool = False) -> str:
    return f"{value:+.2f}" if sign else f"{value:.2f}"


def cells_section(summary: Mapping[str, Any]) -> str:
    """The cells' table: mean, interval, width, shares, experiment, seed LS-DYNA."""
    head = ["ball", "speed [mph]", "mean [mph]", "95 % interval [mph]", "width [% of exp.]",
            "sd bat [mph]", "sd ball [mph]", "sd interaction [mph]", "experiment [mph]",
            "inside", "seed LS-DYNA [mph]", "bats x models"]  # fmt: skip
    rows = []
    for c in summary["cells"]:
        st = c["stats"]
        exp = c.get("experiment_mph")
        rows.append([
            escape(c["ball"]), f"{c['speed_mph']:.4g}", _mph(st["mean"]),
            f"{_mph(st['low'])} to {_mph(st['high'])}",
            "" if exp is None else f"{100 * (st['high'] - st['low']) / exp:.1f}",
            _mph(st["sd_bat"]), _mph(st["sd_ball"]), _mph(st["sd_interaction"]),
            "" if exp is None else f"{exp:.4g}",
            "" if exp is None else ("yes" if st["low"] <= exp <= st["high"] else "no"),
            "" if exp is None else f"{c['seed_lsdyna_mph']:.4g}", f"{c['bats']} x {c['models']}",
        ])  # fmt: skip
    return "<h2 id='cells'>Cells</h2>" + table(head, rows, numeric=range(1, 12), data="cells")


def trends_section(summary: Mapping[str, Any]) -> str:
    """Each ball's change from the lowest to the highest speed, and each ranking."""
    head = ["ball", "from [mph]", "to [mph]", "change: mean [mph]", "95 % interval [mph]",
            "experiment [mph]"]  # fmt: skip
    rows = [[escape(t["ball"]), f"{t['from_mph']:.4g}", f"{t['to_mph']:.4g}",
             _mph(t["stats"]["mean"], True),
             f"{_mph(t['stats']['low'], True)} to {_mph(t['stats']['high'], True)}",
             _mph(t["experiment_mph"], True) if "experiment_mph" in t else ""]
            for t in summary["trends"]]  # fmt: skip
    ranks = [[escape(r["first"]), escape(r["second"]), f"{r['speed_mph']:.4g}",
              "—" if r["probability_first_faster"] is None
              else f"{r['probability_first_faster']:.2f}", str(r["bats"])]
             for r in summary["rankings"]]  # fmt: skip
    return ("<h2 id='trends'>Trends and rankings</h2>"
            + (table(head, rows, numeric=range(1, 6), data="trends") if rows else "")
            + table(["first", "second", "speed [mph]", "P(first faster)", "bats"], ranks,
                    numeric=range(2, 5), data="rankings"))  # fmt: skip


def bats_section(summary: Mapping[str, Any]) -> str:
    """Each free parameter's spread and posterior ratio, and each bat's offsets."""
    names = list(summary["free"])
    rows = [[f"<code>{escape(n)}</code>", f"{summary['posterior_ratio'][n]:.2f}"]
            + [f"{b['offsets_spreads'][n]:+.2f}" for b in summary["bats"]] for n in names]
    head = ["parameter", "posterior / prior spread"] + [escape(b["id"]) for b in summary["bats"]]
    return ("<h2 id='bats'>Bats</h2><p class='note'>Offsets from the study's bat "
            f"(<code>{escape(str(summary['bat']))}</code>, bat-0) in prior spreads; a posterior "
            "over prior spread near 1 is a value the bat's measurements do not pin.</p>"
            + table(head, rows, numeric=range(1, len(head)), data="bats"))  # fmt: skip


def render_page(summary: Mapping[str, Any], members: Sequence[Mapping[str, str]]) -> str:
    """The whole page."""
    failed = summary["failed"]
    header = (
        f"<h1>batball ensemble: {escape(summary['study'])}</h1>"
        f"<p class='note'>{len(summary['bats'])} bats x {len(summary['balls'])} ball models, "
        f"{summary['members']} batted-ball-speed runs ({len(failed)} failed), "
        f"{summary['wall_seconds']:.0f} s. The interval is the models' (mean +- 1.96 sd over "
        "the members, each weighted equally); it leaves out the lab's own scatter.</p>"
        "<p><a href='#cells'>cells</a> · <a href='#trends'>trends and rankings</a> · "
        "<a href='#bats'>bats</a> · <a href='members.csv'>members.csv</a> · "
        "<a href='summary.json'>summary.json</a></p>"
    )
    figure = ("<figure class='wide'><img src='figures/cells.png' alt='each cell's members, "
              "interval and experiment'><figcaption>Each member (colour: ball model; outlined: "
              "the study's own bat), the 95 % interval (grey), the experiment (diamond) and the "
              "seed's LS-DYNA (cross).</figcaption></figure>")  # fmt: skip
    errors = "".join(f"<li>{escape(f['bat'])}, {escape(f['ball_model'])}, "
                     f"{f['speed_mph']:.4g} mph: {escape(f['error'])}</li>" for f in failed)
    body = (header + cells_section(summary) + figure + trends_section(summary)
            + bats_section(summary)
            + (f"<h2>Failed runs</h2><ul>{errors}</ul>" if failed else ""))  # fmt: skip
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>batball ensemble {escape(summary['study'])}</title><style>{STYLE}</style>"
        f"</head><body>{body}{IMAGE_CHECK}</body></html>\n"
    )
