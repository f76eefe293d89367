"""Parts the HTML pages share: the design and ensemble pages' style sheet, their tables, and the
check that a page's figures loaded (a headless browser reads ``data-images-loaded`` on the body)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 72em; color: #222;
       line-height: 1.4; padding: 0 1em; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f0f0f0; } td.label, th.label { text-align: left; }
th.group { background: #e4e9f2; text-align: left; }
td.confirmed, th.confirmed { background: #eaf5ea; }
td.violated { background: #f6cfcf; } tr.objective td.label { font-weight: bold; }
.note { color: #555; font-size: 0.9em; max-width: 60em; }
figure { display: inline-block; margin: 0.6em 1em 1em 0; vertical-align: top; width: 34em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figure.wide { width: 60em; }
figcaption { font-size: 0.85em; color: #444; }
code { background: #f4f4f4; padding: 0 0.2em; white-space: nowrap; }
"""

IMAGE_CHECK = """<script>
window.addEventListener("load", function () {
  var images = Array.prototype.slice.call(document.images);
  var loaded = images.filter(function (i) { return i.complete && i.naturalWidth > 0; });
  document.body.setAttribute("data-image-count", String(images.length));
  document.body.setAttribute("data-images-loaded",
                             loaded.length === images.length ? "all" : "missing");
});
</script>"""


def table(head: Sequence[str], rows: Iterable[Sequence[str]], *, numeric: Sequence[int] = (),
          data: str = "") -> str:  # fmt: skip
    """An HTML table (no header row when ``head`` is empty); the ``numeric`` columns
    right-aligned, the others left. Cells are HTML already."""

    def css(i: int) -> str:
        return "" if i in numeric else " class='label'"

    attribute = f" data-table='{data}'" if data else ""
    header = "".join(f"<th{css(i)}>{h}</th>" for i, h in enumerate(head))
    body = "".join(
        "<tr>" + "".join(f"<td{css(i)}>{c}</td>" for i, c in enumerate(row)) + "</tr>"
        for row in rows
    )
    return f"<table{attribute}>{f'<tr>{header}</tr>' if head else ''}{body}</table>"
