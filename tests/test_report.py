"""The run's reports: report.html, one self-contained page, valid HTML (every table whole),
rendered in headless Chromium with its summary and every figure shown, and printable to a
calculation report (PDF); report.md's tables whole where a cell holds a pipe; the summary's
dimensional results first, the bearing pressure and the load by its parts."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest
from browser import chromium, rendered_dom

ROOT = Path(__file__).resolve().parents[1]
#: the flags a headless Chromium needs on a closed machine, as root
VOID = {"meta", "img", "br", "hr", "link", "input"}


class _Checker(HTMLParser):
    """Balanced tags, and each table's rows of one length."""

    def __init__(self):
        super().__init__()
        self.stack, self.problems, self.tables, self.images = [], [], [], 0

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.images += 1
            assert dict(attrs)["src"].startswith("data:image/png;base64,")
        if tag in VOID:
            return
        self.stack.append(tag)
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append(0)
        elif tag in ("td", "th"):
            self.tables[-1][-1] += 1

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.problems.append(f"</{tag}> closes <{self.stack[-1] if self.stack else ''}>")
        else:
            self.stack.pop()


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The steel tank (coarse): a Mohr-Coulomb interface, courses, a roof, self-weight."""
    out = tmp_path_factory.mktemp("report") / "out"
    proc = subprocess.run([sys.executable, "-m", "tankfx", "run",
                           str(ROOT / "demos" / "scenes" / "steel_tank.toml"), "--out",
                           str(out), "--coarse", "--no-fields"],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return out, json.loads((out / "results.json").read_text())


def test_report_html_is_valid_and_self_contained(run):
    out, r = run
    page = (out / "report.html").read_text()
    checker = _Checker()
    checker.feed(page)
    assert not checker.problems and not checker.stack
    assert len(checker.tables) == 2                   # the scene and the summary
    for rows in checker.tables:
        assert len(set(rows)) == 1, rows              # no row breaks its table
    figures = [p for p in out.glob("*.png")]
    assert checker.images == len(figures) >= 4
    assert "http" not in page.replace("http-equiv", "")   # nothing fetched


def test_report_html_renders_in_chromium_and_prints(run, tmp_path):
    """Chromium shows the summary and decodes every figure (a probe script, added to a copy
    of the page, counts the images loaded); the page prints to a PDF."""
    out, r = run
    dom = rendered_dom(out / "report.html", tmp_path / "profile")
    n = len(list(out.glob("*.png")))
    assert f'data-images="{n}"' in dom
    assert f"<td>centre settlement w0</td><td class=\"value\">{1e3 * r['w0']:.2f} mm</td>" \
        in dom
    pdf = tmp_path / "report.pdf"
    subprocess.run([*chromium(tmp_path / "profile"), "--no-pdf-header-footer",
                    f"--print-to-pdf={pdf}", (out / "report.html").as_uri()],
                   capture_output=True, timeout=120)
    assert pdf.read_bytes()[:5] == b"%PDF-" and pdf.stat().st_size > 50_000


def test_the_summary_leads_with_dimensional_results(run):
    """The load by its parts, the settlements in mm, the bearing pressure (mean = load over
    area), moments in kN m/m, then Eq. 23's set with its p; stresses with their digits."""
    from tankfx.results.report import summary_rows

    out, r = run
    rows = summary_rows(r)
    names = [n for n, _, _ in rows]
    assert names[:4] == ["vertical load", "centre settlement w0", "edge settlement w_edge",
                         "differential settlement wd"]
    assert names.index("bearing pressure: mean") < names.index("w0_bar, wd_bar, M0_bar")
    values = {n: (v, note) for n, v, note in rows}
    vl = r["vertical_load"]
    assert vl["total"] == pytest.approx(vl["liquid"] + vl["self_weight"] + vl["roof"])
    assert "liquid" in values["vertical load"][1] and "roof 500 kN" in values["vertical load"][1]
    a = r["scene"]["plate"]["radius"]
    assert r["bearing_pressure"]["mean"] == pytest.approx(vl["total"] / (math.pi * a**2))
    assert values["bearing pressure: mean"][0] == f"{r['bearing_pressure']['mean'] / 1e3:.3g} kPa"
    assert "p = " in values["w0_bar, wd_bar, M0_bar"][1]
    for name, (value, note) in values.items():
        assert "0.0 MPa" not in value + note, name


def test_report_md_keeps_its_tables_whole_and_gives_units(run):
    out, _ = run
    text = (out / "report.md").read_text()
    for line in text.splitlines():
        if line.startswith("| ") and "|---" not in line:
            cells = line.replace("\\|", "").count("|")
            assert cells in (3, 4), line                  # 2 or 3 columns
    assert "roof_weight = 500 kN" in text and "E = 200 GPa" in text
    assert "friction angle = 30 deg" in text
