"""Sphinx configuration of tankfx's documentation site (`make docs`, warnings as errors).

The site is MyST Markdown. Three kinds of page are generated when the site is built, so
that they cannot drift from the code: the tutorials (from the demos' literate source,
jupytext's percent format), the command line's help (from the argument parser) and, before
the build, the scene reference (`python -m tankfx.scene.keydoc`, checked by a test) and the
verification table (`python docs/verification.py`, checked by a test).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))

project = "tankfx"
author = "the tankfx developers"
copyright = "2026, the tankfx developers"

import tankfx  # noqa: E402  (the installed package, for its version and the API reference)

release = version = tankfx.__version__

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon",
              "sphinx.ext.viewcode"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "gallery/*/report.md", "Thumbs.db", ".DS_Store"]
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3
html_theme = "furo"
html_title = f"tankfx {release}"
html_static_path: list[str] = []
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "show-inheritance": False}
napoleon_google_docstring = False
napoleon_numpy_docstring = True
# the Attributes sections as fields of their class: dataclass fields are not described twice
napoleon_use_ivar = True
nitpicky = False
suppress_warnings = ["myst.header"]

#: The demos, in the order a reader meets them, each a tutorial page.
TUTORIALS = ["embedded_tank", "surface_tank", "flexible_load", "nonlinear_soil",
             "layered_ground", "tank_on_sand", "steel_tank", "seismic_tank", "tank_on_clay",
             "hydrotest", "tank_collapse", "hydrotest_schedule"]
GENERATED = DOCS / "_generated"


def demo_page(name: str) -> str:
    """A demo (jupytext percent format) as a MyST page: its Markdown cells as text, its code
    cells as Python blocks, the command that runs it first."""
    import jupytext

    path = ROOT / "demos" / f"{name}.py"
    notebook = jupytext.read(path, fmt="py:percent")
    parts = []
    for k, cell in enumerate(notebook.cells):
        text = cell.source.rstrip()
        if not text:
            continue
        if cell.cell_type == "markdown":
            # figures are linked from the demo's own folder: ../docs/figures/x.png
            text = text.replace("../docs/figures/", "../figures/")
            parts.append(text)
            if k == 0:
                parts.append(f"Source: `demos/{name}.py`, a script in jupytext's percent "
                             "format (`jupytext --to notebook` opens it as a notebook).")
        else:
            parts.append(f"```python\n{text}\n```")
    return "\n\n".join(parts) + "\n"


def cli_help() -> None:
    """The help of `tankfx` and of each command, as the command line prints it (at a width
    of 92 columns, whatever the terminal building the site)."""
    import contextlib
    import io

    from tankfx.cli import build_parser

    os.environ["COLUMNS"] = "92"
    for name, args in {"tankfx": [], "run": ["run"], "check": ["check"],
                       "sweep": ["sweep"]}.items():
        text = io.StringIO()
        with contextlib.redirect_stdout(text), contextlib.suppress(SystemExit):
            build_parser().parse_args([*args, "--help"])
        (GENERATED / f"cli-{name}.txt").write_text(text.getvalue())


def generate(app) -> None:
    GENERATED.mkdir(exist_ok=True)
    for name in TUTORIALS:
        page = DOCS / "tutorials" / f"{name}.md"
        text = demo_page(name)
        if not page.exists() or page.read_text() != text:
            page.write_text(text)
    cli_help()


def setup(app):
    app.connect("builder-inited", generate)
    return {"parallel_read_safe": True}

