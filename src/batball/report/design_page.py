"""A design study's page: ``index.html`` beside the study's ``summary.json`` and ``designs.csv``.

One static HTML page (inline CSS, figures as PNG files under ``figures/``) for a bat designer:
the study as run (bat, parameters and ranges, balls and speeds, constraints with the rules'
sources, objectives, meshes, counts, wall time), the best designs with every response and each
constraint's margin (and the confirmation mesh's values where the study reran them), a scatter
matrix of the parameters and the objectives' responses, the objectives' trade-off with the Pareto
front, and each parameter's influence on the batted-ball speed. Every value is read from the two
files; nothing is recomputed.

Example:
    >>> write_design_page(Path("study-out"))   # doctest: +SKIP
    PosixPath('study-out/index.html')
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from html import escape
from pathlib import Path
from typing import Any

from batball.report.design_figures import (
    Axis,
    plot_influence,
    plot_scatter_matrix,
    plot_tradeoff,
)
from batball.report.html_parts import IMAGE_CHECK, STYLE, table
from batball.report.reproduce_html import display_unit

#: Decimals shown per unit (``""``: a ratio such as BBCOR).
DIGITS = {"mph": 2, "oz": 2, "in": 3, "oz*in**2": 0, "Hz": 1, "lbf": 1, "deg": 1, "": 4}

#: Readable names of the responses every study may compute.
RESPONSE_NAMES = {
    "weight_oz": "weight",
    "balance_point_in": "balance point from the knob",
    "moi_pivot_oz_in2": "MOI about the 6-in pivot",
    "bending1_hz": "1st bending frequency",
    "bending2_hz": "2nd bending frequency",
    "hoop1_hz": "1st hoop frequency",
    "hoop2_hz": "2nd hoop frequency",
    "barrel_preload_lbf": "barrel compression preload",
    "barrel_final_load_lbf": "barrel compression final load",
}
#: Per ball and speed: the column's prefix -> its name.
BALL_RESPONSES = {"bbs_": "BBS", "bbcor_": "BBCOR", "e_a_": "e_A", "bpf_": "BPF"}
#: The stages of a study as the wall times name them.
STAGES = {"ball_cor": "balls' COR", "sample": "sampling", "optimise": "local search",
          "confirm": "confirmation"}  # fmt: skip
SENSES = {"max": "maximise", "min": "minimise", "target": "bring to target"}


@dataclass(frozen=True)
class PageFigure:
    """A PNG under ``figures/``: its name and caption."""

    name: str
    caption: str
    wide: bool = False


@dataclass(frozen=True)
class StudyOutput:
    """A finished study's files as read: summary.json and designs.csv's rows."""

    summary: dict[str, Any]
    rows: list[dict[str, Any]]
    out_dir: Path

    @property
    def screened(self) -> list[dict[str, Any]]:
        """The rows evaluated on the screening mesh (sampled and local-search designs)."""
        return [r for r in self.rows if r["stage"] != "confirm"]

    @property
    def confirmed(self) -> list[dict[str, Any]]:
        """The rows rerun on the confirmation mesh."""
        return [r for r in self.rows if r["stage"] == "confirm"]

    def unit(self, column: str) -> str:
        """The unit of a parameter or response column (``""`` for a ratio)."""
        for p in self.summary["parameters"]:
            if column == parameter_column(p):
                return str(p["unit"])
        return str(self.summary["responses"].get(column, ""))

    def axis(self, column: str) -> Axis:
        """The column with its axis label (name and unit)."""
        return Axis(column, quantity_label(column, self.unit(column), self.parameter_names))

    @property
    def parameter_names(self) -> dict[str, str]:
        """Parameter column -> the parameter's name."""
        return {parameter_column(p): str(p["name"]) for p in self.summary["parameters"]}

    @property
    def objective_columns(self) -> list[str]:
        """The objectives' responses, first objective first, each once."""
        return list(dict.fromkeys(o["response"] for o in self.summary["objectives"]))


def parameter_column(parameter: Mapping[str, Any]) -> str:
    """A summary parameter's column in designs.csv: ``carbon_angle_deg``."""
    return f"{parameter['name']}_{parameter['unit']}"


def response_name(column: str) -> str:
    """A response column in words: ``bbs_type1_110mph`` -> ``BBS, type1 at 110 mph``."""
    if column in RESPONSE_NAMES:
        return RESPONSE_NAMES[column]
    for prefix, name in BALL_RESPONSES.items():
        if column.startswith(prefix) and column.endswith("mph"):
            ball, _, speed = column.removeprefix(prefix).rpartition("_")
            return f"{name}, {ball} at {speed.removesuffix('mph').replace('p', '.')} mph"
    return column


def quantity_label(column: str, unit: str, parameters: Mapping[str, str]) -> str:
    """An axis label: the parameter's name or the response in words, and the unit."""
    name = parameters.get(column) or response_name(column)
    return f"{name} ({display_unit(unit) if unit else 'ratio'})"


def number(value: Any, unit: str) -> str:
    """``value`` to the unit's decimals; "—" when absent."""
    if value is None or isinstance(value, bool):
        return "—" if value is None else ("yes" if value else "no")
    return f"{float(value):,.{DIGITS.get(unit, 3)}f}"


def with_unit(value: Any, unit: str) -> str:
    """``value`` and its unit (``98.00 mph``); "—" when absent."""
    text = number(value, unit)
    return text if value is None or not unit else f"{text} {display_unit(unit)}"


def balls_and_speeds(summary: Mapping[str, Any]) -> dict[str, list[str]]:
    """Each ball the study fires and its inbound speeds, read from the BBS response columns."""
    out: dict[str, list[str]] = {}
    for column in summary["responses"]:
        if column.startswith("bbs_"):
            ball, _, speed = column.removeprefix("bbs_").rpartition("_")
            out.setdefault(ball, []).append(speed.removesuffix("mph").replace("p", ".") + " mph")
    return out


def read_study_output(out_dir: Path) -> StudyOutput:
    """summary.json and designs.csv of the study written into ``out_dir``."""
    from batball.design.run import load_rows

    summary = json.loads((out_dir / "summary.json").read_text(encoding="utf-8"))
    return StudyOutput(summary, load_rows(out_dir), out_dir)


def write_design_page(out_dir: Path) -> Path:
    """Write ``out_dir/index.html`` and its figures (``out_dir/figures/*.png``) from the study's
    ``summary.json`` and ``designs.csv`` in ``out_dir``, each file atomically.

    Returns:
        The page's path.
    """
    from batball.results.store import write_text_atomic

    out_dir = Path(out_dir)
    study = read_study_output(out_dir)
    figures = draw_figures(study)
    path = out_dir / "index.html"
    write_text_atomic(path, render_page(study, figures))
    return path


# --- the study ------------------------------------------------------------------------------


def overview(study: StudyOutput) -> str:
    """Bat, meshes, counts, wall time and the balls' COR."""
    s = study.summary
    counts = s["designs"]
    screened = counts.get("sample", 0) + counts.get("optimise", 0)
    stages = ", ".join(f"{STAGES.get(k, k)} {v:.1f} s" for k, v in s["stage_seconds"].items())
    items = [
        ("base bat", f"<code>{escape(str(s['bat']))}</code>"),
        ("screening mesh", escape(s["mesh"])),
        ("confirmation mesh", escape(s["confirm_mesh"] or "none (no confirmation stage)")),
        ("sampled designs", str(counts.get("sample", 0))),
        ("local-search designs", str(counts.get("optimise", 0))),
        ("designs rerun on the confirmation mesh", str(counts.get("confirm", 0))),
        ("feasible (screening mesh)", f"{s['feasible']} of {screened}"),
        ("wall time", f"{s['wall_seconds']:.1f} s ({escape(stages)})"),
        *((f"ball COR, {escape(b)} (flat wall, 60 mph)", f"{c:.4f}")
          for b, c in s["ball_cor"].items()),
    ]  # fmt: skip
    return table([], items, data="study")


def parameters_table(study: StudyOutput) -> str:
    """Each parameter: what it sets, its unit and range."""
    rows = [
        (escape(p["name"]), f"<code>{escape(p['set'])}</code>",
         with_unit(p["range"][0], p["unit"]), with_unit(p["range"][1], p["unit"]))
        for p in study.summary["parameters"]
    ]  # fmt: skip
    return table(["parameter", "sets", "from", "to"], rows, numeric=(2, 3), data="parameters")


def balls_table(study: StudyOutput) -> str:
    """Each ball and the speeds it is fired at the bat."""
    speeds = balls_and_speeds(study.summary)
    if not speeds:
        return "<p class='note'>No ball: the study has no batted-ball-speed response.</p>"
    rows = [(escape(ball), escape(", ".join(v))) for ball, v in speeds.items()]
    return table(["ball", "inbound speeds"], rows, data="balls")


def constraints_table(study: StudyOutput) -> str:
    """Each constraint's response and limits, and each rule's title and source."""
    constraints = study.summary["constraints"]
    if not constraints:
        return "<p class='note'>No constraint: every design is feasible.</p>"
    rows = []
    for c in constraints:
        unit = study.unit(c["response"])
        rows.append((escape(quantity_label(c["response"], unit, {})),
                     with_unit(c["min"], unit), with_unit(c["max"], unit),
                     escape(c["rule"] or "—")))  # fmt: skip
    out = table(
        ["response", "at least", "at most", "rule"], rows, numeric=(1, 2), data="constraints"
    )
    rules = [(f"<code>{escape(r['name'])}</code>", escape(r["title"]), escape(r["source"]))
             for r in study.summary["rules"]]  # fmt: skip
    if rules:
        out += table(["rule", "what it asks", "source"], rules, data="rules")
    return out


def objectives_table(study: StudyOutput) -> str:
    """Each objective, first first (the ranking uses the first; the front, the first two)."""
    objectives = study.summary["objectives"]
    if not objectives:
        return "<p class='note'>No objective: the designs are ranked by feasibility alone.</p>"
    rows = []
    for i, o in enumerate(objectives, start=1):
        unit = study.unit(o["response"])
        rows.append((str(i), SENSES.get(o["sense"], o["sense"]),
                     escape(quantity_label(o["response"], unit, {})),
                     with_unit(o["target"], unit)))  # fmt: skip
    return table(
        ["objective", "sense", "response", "target"], rows, numeric=(3,), data="objectives"
    )


def study_section(study: StudyOutput) -> str:
    """The study as run."""
    return (
        "<h2 id='study'>The study</h2>" + overview(study)
        + "<h3>Parameters (the design space)</h3>" + parameters_table(study)
        + "<h3>Balls</h3>" + balls_table(study)
        + "<h3>Constraints</h3>" + constraints_table(study)
        + "<h3>Objectives</h3>" + objectives_table(study)
    )  # fmt: skip


# --- the best designs -----------------------------------------------------------------------


@dataclass(frozen=True)
class BestColumn:
    """One column of the best-designs table: a design's values on one mesh."""

    rank: int
    design: str
    mesh: str
    parameters: Mapping[str, float]
    responses: Mapping[str, float]
    margins: Mapping[str, float]
    feasible: bool
    confirmed: bool


def best_columns(summary: Mapping[str, Any]) -> list[BestColumn]:
    """Each best design on the screening mesh, followed by its confirmation rerun if any."""
    out = []
    for rank, b in enumerate(summary["best"], start=1):
        out.append(BestColumn(rank, b["design"], summary["mesh"], b["parameters"],
                              b["responses"], b["margins"], b["feasible"], False))  # fmt: skip
        c = b.get("confirmed")
        if c:
            out.append(BestColumn(rank, b["design"], c["mesh"], b["parameters"],
                                  c["responses"], c["margins"], c["feasible"], True))  # fmt: skip
    return out


def margin_labels(study: StudyOutput, keys: Sequence[str]) -> list[tuple[str, str]]:
    """(label, unit) of each margin column, in the constraints' order (one margin each)."""
    constraints = study.summary["constraints"]
    if len(constraints) != len(keys):
        return [(k, "") for k in keys]
    out = []
    for c in constraints:
        unit = study.unit(c["response"])
        limit = " and ".join(t for t in (
            f"≥ {with_unit(c['min'], unit)}" if c["min"] is not None else "",
            f"≤ {with_unit(c['max'], unit)}" if c["max"] is not None else "") if t)  # fmt: skip
        rule = f"{c['rule']}: " if c["rule"] else ""
        out.append((f"{rule}{response_name(c['response'])} {limit}", unit))
    return out


def best_rows(study: StudyOutput, columns: Sequence[BestColumn]) -> list[str]:
    """The table's body: parameters, responses (objectives in bold), margins, feasibility."""
    n = len(columns)

    def group(title: str) -> str:
        return f"<tr><th class='group' colspan='{n + 2}'>{escape(title)}</th></tr>"

    def row(label: str, unit: str, cells: Iterable[str], css: str = "") -> str:
        tr = f"<tr class='{css}'>" if css else "<tr>"
        return (
            f"{tr}<td class='label'>{escape(label)}</td>"
            f"<td class='label'>{escape(display_unit(unit))}</td>{''.join(cells)}</tr>"
        )

    def cell(column: BestColumn, text: str, css: str = "") -> str:
        classes = " ".join(c for c in (css, "confirmed" if column.confirmed else "") if c)
        return f"<td class='{classes}'>{text}</td>" if classes else f"<td>{text}</td>"

    out = [group("parameters")]
    for p in study.summary["parameters"]:
        key = parameter_column(p)
        out.append(row(p["name"], p["unit"], (cell(c, number(c.parameters[key], p["unit"]))
                                              for c in columns)))  # fmt: skip
    out.append(group("responses (objectives in bold)"))
    for response, unit in study.summary["responses"].items():
        css = "objective" if response in study.objective_columns else ""
        out.append(
            row(
                response_name(response),
                unit or "ratio",
                (cell(c, number(c.responses.get(response), unit)) for c in columns),
                css,
            )
        )
    keys = list(columns[0].margins)
    if keys:
        out.append(group("constraint margins (positive: inside the limit)"))
    for key, (label, unit) in zip(keys, margin_labels(study, keys), strict=True):
        out.append(row(label, unit or "ratio", (
            cell(c, number(c.margins[key], unit), "violated" if c.margins[key] < 0 else "")
            for c in columns)))  # fmt: skip
    out.append(row("feasible", "", (cell(c, "yes" if c.feasible else "no",
                                         "" if c.feasible else "violated")
                                    for c in columns)))  # fmt: skip
    return out


def best_section(study: StudyOutput) -> str:
    """The best feasible designs, ranked, each with its bat spec and confirmation rerun."""
    columns = best_columns(study.summary)
    heading = "<h2 id='best'>Best designs</h2>"
    if not columns:
        return heading + (
            "<p class='note'>No feasible design: no design met every constraint "
            "on the screening mesh (see the margins in designs.csv).</p>"
        )
    specs = {p.name.partition("-")[2].removesuffix(".toml"): p.name
             for p in sorted((study.out_dir / "best").glob("*.toml"))}  # fmt: skip
    head = []
    for c in columns:
        name = f"#{c.rank} {escape(c.design)}"
        if c.design in specs and not c.confirmed:
            name = f"<a href='best/{escape(specs[c.design])}'>{name}</a>"
        mesh = "confirmation mesh" if c.confirmed else "screening mesh"
        css = " class='confirmed'" if c.confirmed else ""
        head.append(f"<th{css}>{name}<br><small>{mesh}:<br>{escape(c.mesh)}</small></th>")
    note = (
        "<p class='note'>The best designs, ranked by the first objective: those feasible on "
        "the confirmation mesh first, then those feasible on the screening mesh that were not "
        "rerun (a design the confirmation mesh found infeasible is left out); each links to "
        "its bat spec (<code>best/&lt;rank&gt;-&lt;design&gt;.toml</code>). "
    )
    if any(c.confirmed for c in columns):
        note += (
            "Green columns: the same design rerun on the finer confirmation mesh, the "
            "values to rely on. "
        )
    note += "Margins are in the constraint's unit; a negative margin breaks the limit.</p>"
    return (
        f"{heading}{note}<table data-table='best'><tr><th class='label'>quantity</th>"
        f"<th class='label'>unit</th>{''.join(head)}</tr>{''.join(best_rows(study, columns))}"
        "</table>"
    )


# --- figures --------------------------------------------------------------------------------


def draw_figures(study: StudyOutput) -> list[PageFigure]:
    """The scatter matrix, the trade-off and the influence bars, as far as the study allows."""
    figures = [scatter_matrix_figure(study), tradeoff_figure(study), influence_figure(study)]
    return [f for f in figures if f is not None]


def best_design(study: StudyOutput) -> str | None:
    """The id of the best feasible design, if any."""
    best = study.summary["best"]
    return str(best[0]["design"]) if best else None


def scatter_matrix_figure(study: StudyOutput) -> PageFigure | None:
    """Parameters and the objectives' responses (the constraints' without objectives)."""
    s = study.summary
    responses = study.objective_columns or list(
        dict.fromkeys(c["response"] for c in s["constraints"])
    )
    columns = [parameter_column(p) for p in s["parameters"]] + responses
    if len(columns) < 2 or not study.screened:
        return None
    name = "scatter_matrix.png"
    plot_scatter_matrix(study.out_dir / "figures" / name, study.screened,
                        [study.axis(c) for c in columns], best_design(study))  # fmt: skip
    n_feasible = sum(bool(r["feasible"]) for r in study.screened)
    crosses = len(study.screened) - n_feasible
    return PageFigure(name, f"Every screened design ({s['mesh']}), each pair of parameters and "
                      f"{'objective' if study.objective_columns else 'constrained'} responses: "
                      f"circles the {n_feasible} feasible, crosses the {crosses} infeasible"
                      + (", the star the best design." if best_design(study) else "."),
                      wide=True)  # fmt: skip


def constraint_limits(study: StudyOutput, x: Axis, y: Axis) -> list[tuple[str, float, str]]:
    """(axis, limit, label) of each constraint limit on x's or y's response."""
    out = []
    for c in study.summary["constraints"]:
        for where, axis in (("x", x), ("y", y)):
            if c["response"] != axis.column:
                continue
            unit = study.unit(axis.column)
            for bound, word in (("min", "at least"), ("max", "at most")):
                if c[bound] is not None:
                    label = f"{c['rule'] or 'constraint'}: {word} {with_unit(c[bound], unit)}"
                    out.append((where, float(c[bound]), label))
    return out


def most_influential(study: StudyOutput, response: str) -> str:
    """The parameter column with the largest |standardised coefficient| on ``response`` (the
    first parameter without influences)."""
    parameters = study.summary["parameters"]
    coefficients = study.summary["influence"].get(response, {})
    best = max(parameters, key=lambda p: abs(coefficients.get(p["name"], 0.0)))
    return parameter_column(best)


def tradeoff_figure(study: StudyOutput) -> PageFigure | None:
    """The first two objectives' responses with the Pareto front; with one objective, its
    response against the most influential parameter."""
    s, objectives = study.summary, study.objective_columns
    if not objectives or not study.screened:
        return None
    senses = {o["response"]: SENSES.get(o["sense"], o["sense"]) for o in s["objectives"]}
    if len(objectives) >= 2:
        x, y = study.axis(objectives[0]), study.axis(objectives[1])
        title = f"Pareto front: {senses[x.column]} x, {senses[y.column]} y"
        caption = (
            f"The first two objectives over every screened design; the Pareto front "
            f"(feasible designs no other feasible design beats in both) joined, the best "
            f"designs numbered by rank ({senses[x.column]} {response_name(x.column)}, "
            f"{senses[y.column]} {response_name(y.column)})."
        )
    else:
        x, y = study.axis(most_influential(study, objectives[0])), study.axis(objectives[0])
        title = (f"{senses[y.column]} {response_name(y.column)}: against the parameter "
                 "of most influence")  # fmt: skip
        caption = (
            f"The one objective ({senses[y.column]} {response_name(y.column)}) against "
            f"the parameter with the largest standardised influence on it, every "
            f"screened design; the best designs numbered by rank."
        )
    if study.confirmed:
        caption += " Triangles: the best designs rerun on the confirmation mesh."
    name = "pareto.png"
    plot_tradeoff(study.out_dir / "figures" / name, study.screened, x, y, front=s["pareto"],
                  ranked=[b["design"] for b in s["best"]], confirmed=study.confirmed,
                  limits=constraint_limits(study, x, y), title=title)  # fmt: skip
    return PageFigure(name, caption)


def influence_responses(study: StudyOutput) -> list[str]:
    """The BBS responses with influences; without one, the first objective's response (the
    first response with influences when no objective has them)."""
    influence = study.summary["influence"]
    bbs = [r for r in influence if r.startswith("bbs_")]
    if bbs:
        return bbs
    candidates = [r for r in [*study.objective_columns, *influence] if r in influence]
    return candidates[:1]


def influence_figure(study: StudyOutput) -> PageFigure | None:
    """Each parameter's standardised regression coefficient on the BBS responses."""
    responses = influence_responses(study)
    if not responses:
        return None
    influence = study.summary["influence"]
    names = [str(p["name"]) for p in study.summary["parameters"]]
    bbs = responses[0].startswith("bbs_")
    title = f"Influence on {'the batted-ball speed' if bbs else response_name(responses[0])}"
    name = "influence.png"
    plot_influence(study.out_dir / "figures" / name, influence, names,
                   [Axis(r, response_name(r)) for r in responses], title=title)  # fmt: skip
    fits = "; ".join(f"{response_name(r)}: R² = {influence[r]['r2']:.3f}" for r in responses)
    return PageFigure(name, "Each parameter's influence: the standardised coefficient of a "
                      "linear fit over the sampled designs, the change of the response in its "
                      "standard deviations per standard deviation of the parameter (no unit). "
                      f"How much of the variation the fit explains: {fits}.")  # fmt: skip


def figures_section(study: StudyOutput, figures: Sequence[PageFigure]) -> str:
    """Every figure with its caption; what could not be drawn, and why."""
    parts = ["<h2 id='figures'>Figures</h2>"]
    for f in figures:
        css = " class='wide'" if f.wide else ""
        parts.append(f"<figure{css}><img src='figures/{escape(f.name)}' alt='{escape(f.caption)}'>"
                     f"<figcaption>{escape(f.caption)}</figcaption></figure>")  # fmt: skip
    if not study.summary["influence"]:
        n = len(study.summary["parameters"])
        parts.append(f"<p class='note'>No influences: they need at least {n + 2} sampled "
                     "designs (the parameters + 2).</p>")  # fmt: skip
    if not study.summary["objectives"]:
        parts.append("<p class='note'>No trade-off figure: the study has no objective.</p>")
    return "".join(parts)


# --- the page -------------------------------------------------------------------------------


def files_section(study: StudyOutput) -> str:
    """The study's files."""
    n = len(study.rows)
    specs = sorted((study.out_dir / "best").glob("*.toml"))
    links = "".join(f"<li><a href='best/{escape(p.name)}'>best/{escape(p.name)}</a></li>"
                    for p in specs)  # fmt: skip
    return (
        "<h2 id='files'>Files</h2><ul>"
        f"<li><a href='designs.csv'>designs.csv</a>: every evaluated design ({n} rows): stage, "
        "mesh, parameters and responses (units in the column names), each constraint's margin, "
        "feasible, on the Pareto front, rank</li>"
        "<li><a href='summary.json'>summary.json</a>: the study, the best designs, the "
        f"influences, wall times</li>{links}</ul>"
    )


def render_page(study: StudyOutput, figures: Sequence[PageFigure]) -> str:
    """The whole page."""
    s = study.summary
    description = f"<p>{escape(s['description'])}</p>" if s["description"] else ""
    header = (
        f"<h1>batball design study: {escape(s['study'])}</h1>{description}"
        f"<p class='note'>Bat <code>{escape(str(s['bat']))}</code>, "
        f"{len(s['parameters'])} parameters, {len(study.rows)} evaluations, "
        f"{s['wall_seconds']:.1f} s. Screening mesh: {escape(s['mesh'])}; coarse meshes rank "
        "designs, the confirmation mesh (where run) gives the values to rely on.</p>"
        "<p><a href='#study'>study</a> · <a href='#best'>best designs</a> · "
        "<a href='#figures'>figures</a> · <a href='#files'>files</a> · "
        "<a href='designs.csv'>designs.csv</a></p>"
    )
    body = (header + study_section(study) + best_section(study)
            + figures_section(study, figures) + files_section(study))  # fmt: skip
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>batball design study {escape(s['study'])}</title><style>{STYLE}</style></head>"
        f"<body>{body}{IMAGE_CHECK}</body></html>\n"
    )
