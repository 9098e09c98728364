"""The documentation as a product: the site builds (warnings as errors) and its index page
renders in headless Chromium with every local link resolving; the README is short, its
scene is the scene file it names, and what it shows is what the commands it shows print;
the tutorials are the demos; no tracked file keeps a working diary."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest
from browser import rendered_dom

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
BIN = Path(sys.executable).parent
def blocks(text: str, language: str) -> list[str]:
    """The fenced code blocks of one language in a Markdown text."""
    return re.findall(rf"^```{language}\n(.*?)^```", text, flags=re.M | re.S)


def commands(text: str) -> list[str]:
    """The commands of a Markdown text's sh blocks, one a line, without their comments."""
    return [line.split("  #")[0].strip() for block in blocks(text, "sh")
            for line in block.splitlines() if line.strip()]


# -- the site ----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built as `make docs` builds it (warnings are errors), into a scratch
    directory."""
    out = tmp_path_factory.mktemp("site") / "html"
    proc = subprocess.run([str(BIN / "sphinx-build"), "-q", "-W", "--keep-going", "-b",
                           "html", str(ROOT / "docs"), str(out)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return out


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("href", "src"):
            if key in a and a[key]:
                self.links.append(a[key])


def test_every_local_link_of_the_site_resolves(site):
    pages = list(site.rglob("*.html"))
    assert len(pages) > 30
    missing = []
    for page in pages:
        if "_modules" in page.parts:
            continue
        parser = _Links()
        parser.feed(page.read_text())
        for link in parser.links:
            url = urlparse(link)
            if url.scheme or link.startswith(("#", "mailto:")) or not url.path:
                continue
            if not (page.parent / unquote(url.path)).exists():
                missing.append(f"{page.relative_to(site)} -> {link}")
    assert not missing, missing


def test_the_site_has_every_part_the_readme_points_to(site):
    for page in ("index", "getting-started", "tutorials/index", "guide/index",
                 "guide/cli", "scene-keys", "theory/index", "theory/paper-and-tankfx",
                 "verification", "performance", "limitations", "api", "development/index",
                 "development/testing", "development/benchmarks", "development/releasing"):
        assert (site / f"{page}.html").exists(), page
    for link in re.findall(r"\]\(docs/([\w/.-]+)\.md\)", README):
        assert (site / f"{link}.html").exists(), link
    # the command line's help is the program's own
    cli = (site / "guide" / "cli.html").read_text()
    assert "--allow-large" in cli and "--resolved" in cli and "exit codes" in cli
    # the API reference documents every public name
    import tankfx

    api = (site / "api.html").read_text()
    for name in set(tankfx.__all__) - {"__version__"}:
        assert f'id="tankfx.{name}"' in api, name


def test_the_index_page_renders_in_chromium(site, tmp_path):
    """Chromium shows the index page, its figure decoded and its table of contents in
    place."""
    dom = rendered_dom(site / "index.html", tmp_path / "profile")
    assert 'data-images="1"' in dom
    for title in ("Getting started", "Tutorials", "User guide", "Verification",
                  "Performance", "Limitations", "Python API", "Development"):
        assert f">{title}</a>" in dom, title


# -- the README --------------------------------------------------------------------------

def test_the_readme_is_short():
    assert len(README.splitlines()) <= 200


def test_the_readme_scene_is_the_scene_file_it_names():
    scene, = blocks(README, "toml")
    assert "demos/scenes/steel_tank.toml" in README
    assert scene == (ROOT / "demos" / "scenes" / "steel_tank.toml").read_text()


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """A scratch directory that sees the repository's demos, where the README's commands
    write their results (never into the repository)."""
    d = tmp_path_factory.mktemp("readme")
    (d / "demos").symlink_to(ROOT / "demos")
    (d / ".venv").mkdir()
    (d / ".venv" / "bin").symlink_to(BIN)
    return d


def test_every_readme_command_runs_and_the_run_prints_the_summary_shown(workdir):
    """Each tankfx command of the README runs from the repository's root as written (here a
    scratch copy of it); the run prints every summary row the README shows, digit for
    digit. make's targets are checked by a dry run: `make test` is this suite, and
    `make demo` runs demos/embedded_tank.py, which tests/test_demos.py runs."""
    cmds = commands(README)
    assert any(c.startswith(".venv/bin/tankfx run") for c in cmds)
    shown, = [b for b in blocks(README, "text") if b.startswith("quantity")]
    for cmd in cmds:
        if cmd.startswith("make "):
            proc = subprocess.run(["make", "-n", *cmd.split()[1:]], cwd=ROOT,
                                  capture_output=True, text=True)
            assert proc.returncode == 0, (cmd, proc.stderr)
            continue
        proc = subprocess.run(cmd.split(), cwd=workdir, capture_output=True, text=True,
                              timeout=600, env=dict(os.environ, COLUMNS="100"))
        assert proc.returncode == 0, (cmd, proc.stdout[-2000:], proc.stderr[-2000:])
        if " run " in cmd:
            printed = {" ".join(line.split()) for line in proc.stdout.splitlines()}
            for line in shown.splitlines():
                assert " ".join(line.split()) in printed, line
            assert (workdir / "results" / "steel_tank" / "report.html").exists()


def test_the_readme_python_prints_what_its_comments_say(workdir):
    code, = blocks(README, "python")
    expected = re.findall(r"# (w0 = [\d.]+ mm)", code)
    assert len(expected) == 2
    proc = subprocess.run([sys.executable, "-c", code], cwd=workdir, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.splitlines() == expected


# -- the tutorials and the diary ---------------------------------------------------------

def test_the_tutorials_are_the_demos_and_each_is_run_by_the_suite():
    """Every demo is a tutorial, in jupytext's percent format, whose figures exist; the
    command each tutorial shows (`python demos/<name>.py`) is what tests/test_demos.py runs
    (on the coarse mesh)."""
    import jupytext

    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import conf
    finally:
        sys.path.pop(0)
    demos = sorted(p.stem for p in (ROOT / "demos").glob("*.py"))
    assert sorted(conf.TUTORIALS) == demos
    index = (ROOT / "docs" / "tutorials" / "index.md").read_text()
    tested = (ROOT / "tests" / "test_demos.py").read_text()
    for name in demos:
        source = (ROOT / "demos" / f"{name}.py").read_text()
        assert source.startswith("# %% [markdown]\n"), name
        cells = jupytext.reads(source, fmt="py:percent").cells
        assert sum(c.cell_type == "markdown" for c in cells) >= 3, name
        assert f"\n{name}\n" in index
        for figure in re.findall(r"\]\(\.\./docs/(figures/[\w.-]+)\)", source):
            assert (ROOT / "docs" / figure).exists(), (name, figure)
        page = conf.demo_page(name)
        assert f"demos/{name}.py" in page
        for command in re.findall(r"`((?:\.venv/bin/)?python demos/[\w.]+)`", page):
            assert command.split("/")[-1] == f"{name}.py", (name, command)
    # every demo: tests/test_demos.py runs all but its SLOW ones, which make verify runs
    assert 'sorted(d for d in (ROOT / "demos").glob("*.py") if d.stem not in SLOW)' in tested
    slow = re.search(r"^SLOW = \{(.*)\}$", tested, re.M).group(1)
    assert all(f'"{name}"' in slow for name in ("hydrotest_schedule", "tank_collapse"))


def test_no_tracked_file_keeps_a_working_diary():
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                           check=True).stdout.split()
    diary = re.compile(r"\bsession\s+\d+", re.I)
    found = []
    for name in files:
        path = ROOT / name
        if path.suffix in (".png", ".msh", ".pdf") or not path.is_file():
            continue
        try:
            text = path.read_text()
        except UnicodeDecodeError:
            continue
        found += [f"{name}: {m.group(0)}" for m in diary.finditer(text)]
    assert not found, found
