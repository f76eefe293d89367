"""The reproduction report as one static HTML page: inline CSS, images as relative files.

The only script is a few lines that mark ``<body data-images-loaded="all">`` once every image has
loaded (what the browser test checks); the page reads the same without it.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from html import escape
from pathlib import Path
from typing import TYPE_CHECKING, Any

from batball.report.html_parts import IMAGE_CHECK
from batball.report.seed_comparison import (
    ComparisonRow,
    ComparisonTable,
    percent_difference,
    verdict,
)
from batball.specs import ball_spec_to_toml_dict, bat_spec_to_toml_dict
from batball.units import IN

if TYPE_CHECKING:
    from batball.report.reproduce import Reproduction, TestOutcome

NOT_YET = "not yet available"

STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 70em; color: #222;
       line-height: 1.4; padding: 0 1em; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f0f0f0; } td.label, th.label { text-align: left; }
td.closer, span.closer { background: #c9ecc9; } td.tie, span.tie { background: #f3f0c4; }
td.farther, span.farther { background: #f6cfcf; }
td.missing { color: #888; font-style: italic; }
td.indicative { color: #555; font-style: italic; }
td.role { color: #555; font-size: 0.9em; }
.legend span { padding: 0.1em 0.6em; margin-right: 0.6em; border: 1px solid #ccc; }
.note { color: #555; font-size: 0.9em; max-width: 60em; }
figure { display: inline-block; margin: 0.6em 1em 1em 0; vertical-align: top; width: 32em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.85em; color: #444; }
figure.wide { width: 66em; }
code { background: #f4f4f4; padding: 0 0.2em; }
"""


def number(value: float | None, digits: int, unit: str = "") -> str:
    """``value`` with ``digits`` decimals and thousands separators; "—" for None."""
    if value is None:
        return "—"
    return f"{value:,.{digits}f}" + (f" {unit}" if unit else "")


def percent(value: float | None) -> str:
    """A signed percentage with one decimal; "—" for None."""
    return "—" if value is None else f"{value:+.1f} %"


def display_unit(unit: str) -> str:
    """The unit as a reader writes it (``oz*in**2`` -> ``oz·in²``)."""
    return unit.replace("**2", "²").replace("*", "·")


def batball_cell(
    row: ComparisonRow,
    value: float | None,
    missing: str,
    empty: str = NOT_YET,
    *,
    indicative: bool = False,
) -> str:
    """batball's cell: its value coloured by the verdict (none when ``indicative``), or
    ``empty`` and why there is none."""
    if value is None:
        reason = escape(missing or "no run of this batball test measured it")
        return f'<td class="missing" title="{reason}">{escape(empty)}</td>'
    judged = verdict(row, value, indicative=indicative)
    if indicative and row.role != "check" and row.experiment is not None:
        title = "indicative: a mesh coarser than the converged one, given no verdict"
        return f"<td class='indicative' title='{title}'>{number(value, row.digits)}</td>"
    css = f' class="{judged}"' if judged else ""
    title = f' title="batball is {judged} to the experiment than LS-DYNA"' if judged else ""
    return f"<td{css}{title}>{number(value, row.digits)}</td>"


def table_html(
    table: ComparisonTable,
    values: Mapping[str, float],
    missing: str,
    empty: str = NOT_YET,
    *,
    indicative: bool = False,
) -> str:
    """One seed table: each row's role, experiment, the seed's LS-DYNA, batball and the %
    differences (for a solver-check table, batball's against LS-DYNA's as well)."""
    check = table.section == "check"
    head = (
        "<tr><th class='label'>quantity</th><th class='label'>role</th><th>unit</th>"
        "<th>experiment</th><th>seed LS-DYNA</th><th>batball</th>"
        + ("<th>batball vs LS-DYNA</th>" if check else "")
        + "<th>batball vs experiment</th><th>LS-DYNA vs experiment</th></tr>"
    )
    body = []
    for row in table.rows:
        ours = values.get(row.key)
        versus_fe = (
            f"<td>{percent(percent_difference(ours, row.seed_fe))}</td>" if check else ""
        )
        body.append(
            f"<tr><td class='label'>{escape(row.label)}</td>"
            f"<td class='label role'>{row.role}</td>"
            f"<td class='label'>{escape(display_unit(row.unit))}</td>"
            f"<td>{number(row.experiment, row.digits)}</td>"
            f"<td>{number(row.seed_fe, row.digits)}</td>"
            f"{batball_cell(row, ours, missing, empty, indicative=indicative)}{versus_fe}"
            f"<td>{percent(percent_difference(ours, row.experiment))}</td>"
            f"<td>{percent(percent_difference(row.seed_fe, row.experiment))}</td></tr>"
        )
    note = f"<p class='note'>{escape(table.note)}</p>" if table.note else ""
    return (
        f"<h3 id='{table.id}'>{escape(table.title)}</h3>{note}"
        f"<table class='comparison' data-table='{table.id}'>{head}{''.join(body)}</table>"
    )


def verdict_counts(result: Reproduction) -> dict[str, dict[str, int]]:
    """Per role (``predicted``, ``fitted``): how many batball cells are closer to, as close as,
    or farther from the experiment than the seed's LS-DYNA. Empty on indicative meshes."""
    counts = {role: {"closer": 0, "tie": 0, "farther": 0} for role in ("predicted", "fitted")}
    for table in result.tables:
        for row in table.rows:
            judged = verdict(row, result.values.get(row.key), indicative=result.indicative)
            if judged and row.role in counts:
                counts[row.role][judged] += 1
    return counts


def counts_text(counts: dict[str, int]) -> str:
    """``"closer in 3, as close in 1, farther in 2"``."""
    return (
        f"closer in {counts['closer']}, as close in {counts['tie']}, "
        f"farther in {counts['farther']}"
    )


def headline(result: Reproduction) -> str:
    """The page's verdict: predicted cells first, fitted ones apart; none on coarse meshes."""
    if result.indicative:
        return (
            "<p><strong>Coarse meshes: every value is indicative and given no verdict.</strong> "
            "Run <code>batball reproduce</code> without <code>--quick</code> for the verdicts.</p>"
        )
    counts = verdict_counts(result)
    return (
        f"<p><strong>Predicted cells</strong> (no fit saw them): batball "
        f"{counts_text(counts['predicted'])} than the seed's LS-DYNA, against the experiment. "
        f"<strong>Fitted cells</strong> (targets of the fits the model uses): "
        f"{counts_text(counts['fitted'])}.</p>"
    )


SECTION_HEADINGS = {
    "record": (
        "tables",
        "The model of record against the experiment",
        "The embedded balls type1-fit and type2-fit (MAT_057 foam fitted to Tables 5-8) and the "
        "embedded bat named fitted (fitted to Table 1 and to Table 3's hoop modes). Each row's "
        "role says whether a fit saw it.",
    ),
    "check": (
        "check",
        "Solver check: the seed's balls against the seed's LS-DYNA",
        "The seed's own Table 4 balls, with the hourglass control that reproduces its LS-DYNA "
        "(IHQ 4, QM 0.01), run through batball: read batball against the LS-DYNA column. These "
        "cells test the solver, not the prediction.",
    ),
    "refit": (
        "refit",
        "Refit: the seed's balls calibrated here (MAT_006)",
        "batball calibrate run in this invocation (--calibrate).",
    ),
}


def tables_section(result: Reproduction) -> str:
    """The tables by section, each with the reason batball's column is empty where it is."""
    outcomes = {o.test.name: o for o in result.outcomes}
    legend = (
        "<p class='legend'>batball cell: <span class='closer'>closer to the experiment than "
        "the seed's LS-DYNA</span><span class='tie'>as close (at the shown precision)</span>"
        "<span class='farther'>farther</span>. Differences are signed: "
        "100 (value − experiment) / experiment. Roles: <em>predicted</em> (no fit saw it), "
        "<em>fitted</em> (a target of a fit the model uses), <em>check</em> (the seed's "
        "constants, solver against solver).</p>"
    )
    parts = []
    for section, (anchor, heading, text) in SECTION_HEADINGS.items():
        tables = [t for t in result.tables if t.section == section]
        if not tables:
            continue
        parts.append(f"<h2 id='{anchor}'>{escape(heading)}</h2><p class='note'>{escape(text)}</p>")
        if section == "record":
            parts.append(legend)
        for table in tables:
            outcome = outcomes.get(table.test)
            missing = outcome.missing if outcome is not None else f"no test named {table.test}"
            empty = "skipped" if outcome is not None and outcome.skipped else NOT_YET
            parts.append(table_html(table, result.values, missing, empty,
                                    indicative=result.indicative))  # fmt: skip
    return "".join(parts)


def tests_section(result: Reproduction) -> str:
    """Which tests ran (or were reused from the store) and which are not yet available."""
    rows = []
    for o in result.outcomes:
        if o.available:
            reused = sum(r.reused for r in o.runs)
            status = f"{len(o.runs)} run(s), {reused} reused from the store"
        elif o.skipped:
            status = escape(o.missing)
        else:
            status = f"{NOT_YET}: {escape(o.missing)}"
        rows.append(
            f"<tr><td class='label'><code>{o.test.name}</code></td>"
            f"<td class='label'>{escape(o.test.title)}</td>"
            f"<td class='label'>{', '.join(o.test.tables)}</td>"
            f"<td class='label'>{status}</td><td>{o.seconds:.1f}</td></tr>"
        )
    head = (
        "<tr><th class='label'>test</th><th class='label'>what</th>"
        "<th class='label'>tables</th><th class='label'>status</th><th>wall (s)</th></tr>"
    )
    return f"<h2 id='tests'>Tests</h2><table>{head}{''.join(rows)}</table>"


FIGURE_SECTIONS = (
    ("force-time", "Force against time (seed Figure 15)"),
    ("energy", "Energy histories"),
    ("bat", "The bat model"),
    ("modes", "Bat mode shapes"),
    ("compression", "Ball compression"),
    ("prestress", "Barrel pre-stress fringe (seed Figure 10)"),
    ("bbs", "Batted-ball speed: ball-bat contact force"),
    ("check", "Solver check: the seed's balls"),
)


#: Sections whose figures hold several panels: shown at full page width.
WIDE_SECTIONS = ("energy", "bat", "modes")


def figures_section(result: Reproduction) -> str:
    """Every figure, grouped; a group with no figure says so."""
    parts = ["<h2 id='figures'>Figures</h2>"]
    for section, heading in FIGURE_SECTIONS:
        # figures drawn from several runs (e.g. both speeds of a ball) first
        figures = sorted(
            (f for f in result.figures if f.section == section),
            key=lambda f: not f.source.is_relative_to(result.options.out_dir),
        )
        parts.append(f"<h3>{escape(heading)}</h3>")
        if not figures:
            parts.append(f"<p class='note missing'>{NOT_YET}</p>")
        css = " class='wide'" if section in WIDE_SECTIONS else ""
        for f in figures:
            parts.append(
                f"<figure{css}><img src='figures/{escape(f.name)}' alt='{escape(f.caption)}'>"
                f"<figcaption>{escape(f.caption)}</figcaption></figure>"
            )
    return "".join(parts)


def definition_list(items: Iterable[tuple[str, Any]]) -> str:
    """A two-column table of names and values."""
    rows = "".join(
        f"<tr><td class='label'>{escape(str(k))}</td><td class='label'>{escape(str(v))}</td></tr>"
        for k, v in items
    )
    return f"<table>{rows}</table>"


def ball_inputs(result: Reproduction) -> str:
    """Each ball as run: size, mass and material constants with units."""
    parts = []
    named = zip((*result.options.balls, *result.options.check_balls),
                (*result.inputs.balls, *result.inputs.check_balls), strict=True)  # fmt: skip
    for name, ball in named:
        d = ball_spec_to_toml_dict(ball)
        items = [
            ("circumference", d["circumference"]),
            ("mass", d["mass"]),
            *((f"material {k}", v) for k, v in d["material"].items()),
        ]
        parts.append(
            f"<h3>Ball {escape(name)} (seed ball {escape(ball.name)})</h3><p class='note'>"
            f"{escape(ball.description)}</p>{definition_list(items)}"
        )
    return "".join(parts)


def ply_text(plies: list[dict[str, Any]]) -> str:
    """A layup as one line: material thickness ±angle, inner to outer."""
    return "; ".join(
        f"{p['material']} {p['thickness']} {'±' if p.get('braided') else ''}{p['angle']}"
        for p in plies
    )


def bat_inputs(result: Reproduction) -> str:
    """The bats as run: length, parts with layups, insert, lamina materials."""
    bats = [result.inputs.bat]
    if result.inputs.check_bat is not None and result.inputs.check_bat != result.inputs.bat:
        bats.append(result.inputs.check_bat)
    return "".join(one_bat(bat) for bat in bats)


def one_bat(bat: Any) -> str:
    """One bat as run."""
    d = bat_spec_to_toml_dict(bat)
    rows = "".join(
        f"<tr><td class='label'>{escape(p['name'])}</td><td>{p['start']}</td>"
        f"<td>{p['end']}</td><td>{p['lumped_mass']}</td>"
        f"<td class='label'>{escape(ply_text(p['layup']))}</td></tr>"
        for p in d["parts"]
    )
    insert = d.get("insert")
    if insert:
        rows += (
            f"<tr><td class='label'>insert (interference {insert['interference']})</td>"
            f"<td>{insert['start']}</td><td>{insert['end']}</td><td>—</td>"
            f"<td class='label'>{escape(ply_text(insert['layup']))}</td></tr>"
        )
    head = (
        "<tr><th class='label'>part</th><th>from knob</th><th>to</th><th>lumped mass</th>"
        "<th class='label'>plies, inner to outer</th></tr>"
    )
    materials = definition_list(
        (name, ", ".join(f"{k} {v}" for k, v in m.items())) for name, m in d["materials"].items()
    )
    return (
        f"<h3>Bat {escape(d['name'])} ({d['length']})</h3><p class='note'>"
        f"{escape(d['description'])}</p><table>{head}{rows}</table>{materials}"
    )


def runs_table(outcomes: Iterable[TestOutcome]) -> str:
    """Every run: its folder, mesh size, the wall time when computed and in this invocation."""
    rows = []
    for o in outcomes:
        for r in o.runs:
            n = r.summary.get("n_cells") or r.summary.get("n_shells")
            size = f"{n:,}" if isinstance(n, int) else "—"
            rows.append(
                f"<tr><td class='label'>{o.test.name}: {escape(r.label)}</td>"
                f"<td>{size}</td><td>{float(r.summary['wall_seconds']):.1f}</td>"
                f"<td>{r.seconds:.1f}{' (reused)' if r.reused else ''}</td>"
                f"<td class='label'><code>{escape(r.folder.as_posix())}</code></td></tr>"
            )
    head = (
        "<tr><th class='label'>run</th><th>elements</th><th>test's wall time, stored (s)</th>"
        "<th>wall time here (s)</th><th class='label'>run folder</th></tr>"
    )
    return f"<table>{head}{''.join(rows)}</table>"


def load_text(load: list[float] | None) -> str:
    """The load average as ``"3.1, 2.9, 2.5"``, or ``"unknown"``."""
    return "unknown" if not load else ", ".join(f"{x:.2f}" for x in load)


def inputs_section(result: Reproduction) -> str:
    """Specs, meshes, runs, versions and machine: exactly what was run."""
    m, env = result.options.meshes, result.environment
    meshes = definition_list(
        [
            ("ball divisions", f"{m.ball_divisions} (12 = the seed's 12,096 hexes)"),
            ("bat shells around", m.bat_circumferential),
            ("bat shell length", f"{m.bat_axial_size / IN:g} in"),
            ("batted-ball speed: ball divisions, bat shells around, shell length",
             f"{m.bbs[0]}, {m.bbs[1]}, {m.bbs[2] / IN:g} in"),
            ("converged (verdicts given)", "yes" if m.converged else "no: values indicative"),
        ]
    )
    machine = definition_list(
        [
            ("command", result.options.command),
            ("date", env["date_utc"]),
            ("total wall time", f"{result.seconds:.1f} s"),
            *((f"{k} version", v) for k, v in env["versions"].items()),
            ("python", env["python"]),
            ("platform", env["platform"]),
            ("cpu", env["cpu"]),
            ("cpu count", env["cpu_count"]),
            ("NUMBA_NUM_THREADS", env["numba_num_threads"]),
            ("load average (1, 5, 15 min)", load_text(env["load_average_1_5_15_min"])),
        ]
    )
    return (
        f"<h2 id='inputs'>Inputs: what was run</h2><h3>Meshes</h3>{meshes}"
        f"{ball_inputs(result)}{bat_inputs(result)}<h3>Runs</h3>{runs_table(result.outcomes)}"
        f"<h3>Software and machine</h3>{machine}"
    )


def intervals_section(result: Reproduction) -> str:
    """Table 9 with the intervals of the ensemble given by ``--ensemble`` (its own page has
    the members and the bats); empty without one."""
    import json
    import os

    from batball.report.ensemble_page import cells_section, trends_section

    folder = result.options.ensemble
    if folder is None:
        return ""
    summary = json.loads((Path(folder) / "summary.json").read_text(encoding="utf-8"))
    page = Path(os.path.relpath(Path(folder) / "index.html", result.options.out_dir)).as_posix()
    link = (f"Its own page: <a href='{escape(page)}'>{escape(page)}</a>."
            if (Path(folder) / "index.html").is_file() else "")  # fmt: skip
    text = (
        f"Batted-ball speed over the ensemble <code>{escape(summary['study'])}</code>: "
        f"{len(summary['bats'])} bats drawn from the bat's posterior times "
        f"{len(summary['balls'])} ball models, {summary['members']} runs. The interval is the "
        "models' (mean +- 1.96 sd), without the lab's own scatter; the shares say how much of "
        f"it is the bat's and how much the ball's. {link}"
    )
    body = (cells_section(summary) + trends_section(summary)).replace("<h2", "<h3").replace(
        "</h2>", "</h3>")
    return f"<h2 id='intervals'>Table 9 with intervals</h2><p class='note'>{text}</p>{body}"


def render_report(result: Reproduction) -> str:
    """The whole page."""
    quick = "coarse (--quick, indicative)" if result.indicative else "full-size"
    header = (
        f"<h1>batball: the seed study, reproduced</h1><p class='note'>Every table of the "
        f"seed study (a composite softball bat and two ball types, HyperMesh + LS-DYNA) "
        f"beside batball's model of record, and the seed's own balls as a solver check; "
        f"{quick} meshes; {result.seconds:.1f} s; {escape(result.environment['date_utc'])}. "
        f"No batball number here comes from anywhere but a run.</p>{headline(result)}"
        "<p><a href='#tables'>model of record</a> · <a href='#check'>solver check</a> · "
        + ("<a href='#intervals'>Table 9 with intervals</a> · "
           if result.options.ensemble is not None else "")
        + "<a href='#tests'>tests</a> · <a href='#figures'>figures</a> · "
        "<a href='#inputs'>inputs</a> · <a href='summary.json'>summary.json</a></p>"
    )
    body = (
        header
        + tables_section(result)
        + intervals_section(result)
        + tests_section(result)
        + figures_section(result)
        + inputs_section(result)
    )
    return (
        f"<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>batball reproduce</title><style>{STYLE}</style></head>"
        f"<body>{body}{IMAGE_CHECK}</body></html>\n"
    )
