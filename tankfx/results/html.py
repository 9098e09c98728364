"""report.html: the run's calculation report as one self-contained page (the figures inline
as data, the style in the page, no script, nothing fetched), which opens in any browser
and prints to paper: the scene with its units, whether the results are valid, the summary,
the warnings and the figures.
"""
from __future__ import annotations

import base64
import html
from pathlib import Path

from .report import footer, scene_rows, summary_rows

#: the page's style: readable on screen, and a calculation report on A4 (no figure split
#: across pages, tables kept whole where they fit)
STYLE = """
body { font-family: "DejaVu Sans", Arial, sans-serif; margin: 2em auto; max-width: 60em;
       color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.2em; margin-top: 1.6em; border-bottom: 1px solid #999; }
table { border-collapse: collapse; width: 100%; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.5em; text-align: left;
         vertical-align: top; }
th { background: #eee; }
td.value { text-align: right; white-space: nowrap; font-variant-numeric: tabular-nums; }
.valid { background: #e6f4e6; border: 1px solid #6a6; padding: 0.5em; }
.invalid { background: #fbe3e3; border: 1px solid #c33; padding: 0.5em; font-weight: bold; }
.warning { background: #fff6dd; border-left: 4px solid #e0a800; padding: 0.3em 0.6em;
           margin: 0.4em 0; }
figure { margin: 1.2em 0; page-break-inside: avoid; break-inside: avoid; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.85em; color: #555; }
footer { margin-top: 2em; font-size: 0.8em; color: #555; }
@media print {
  body { margin: 0; max-width: none; font-size: 10pt; }
  h2 { page-break-after: avoid; break-after: avoid; }
  table { page-break-inside: auto; }
  tr { page-break-inside: avoid; break-inside: avoid; }
}
@page { size: A4; margin: 15mm; }
"""


def _e(text) -> str:
    return html.escape(str(text), quote=True)


def _img(path: Path) -> str:
    """A PNG as an inline image (its bytes in the page)."""
    data = base64.b64encode(Path(path).read_bytes()).decode("ascii")
    return f'<img src="data:image/png;base64,{data}" alt="{_e(Path(path).stem)}">'


def report_html(results: dict, figures: list[Path]) -> str:
    """The page's HTML (a string)."""
    r = results
    v = r.get("validity", {"valid": True, "notes": []})
    parts = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             f"<title>{_e(r['title'])}: tankfx report</title>",
             f"<style>{STYLE}</style>", "</head>", "<body>",
             f"<h1>{_e(r['title'])}</h1>"]
    if v["valid"]:
        parts.append('<p class="valid">Valid: every part of the results lies within its '
                     "model's range.</p>")
    else:
        parts.append('<p class="invalid">NOT VALID: ' + _e("; ".join(v["notes"])) + "</p>")
    parts += ["<h2>Scene</h2>", "<table>", "<tr><th>part</th><th>as analysed (SI units)</th>"
              "</tr>"]
    parts += [f"<tr><td>{_e(k)}</td><td>{_e(text)}</td></tr>" for k, text in scene_rows(r)]
    parts += ["</table>", "<h2>Summary</h2>", "<table>",
              "<tr><th>quantity</th><th>value</th><th>note</th></tr>"]
    parts += [f'<tr><td>{_e(a)}</td><td class="value">{_e(b)}</td><td>{_e(c)}</td></tr>'
              for a, b, c in summary_rows(r)]
    parts.append("</table>")
    warnings = r.get("warnings", [])
    if warnings:
        parts.append("<h2>Warnings</h2>")
        parts += [f'<p class="warning">{_e(w)}</p>' for w in warnings]
    if figures:
        parts.append("<h2>Figures</h2>")
        for f in figures:
            parts.append(f"<figure>{_img(f)}<figcaption>{_e(Path(f).name)}</figcaption>"
                         "</figure>")
    parts += [f"<footer>{_e(footer(r))}</footer>", "</body>", "</html>", ""]
    return "\n".join(parts)


def write_report_html(results: dict, figures: list[Path], path) -> Path:
    """Write report.html (rank 0 only)."""
    path = Path(path)
    path.write_text(report_html(results, figures), encoding="utf-8")
    return path
