"""Headless Chromium for the tests that render a page (the report, the documentation site):
Debian's chromium, which `make test` installs where it may (tests/install_chromium.sh). Where
it is missing, those tests are skipped with the reason (``pytest -rs`` prints it) and
`make test` says so at its end."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]
#: added to a copy of a page: on load, the body records how many images were decoded
PROBE = ("<script>window.addEventListener('load', () => document.body.setAttribute("
         "'data-images', [...document.images].filter(i => i.complete && "
         "i.naturalWidth > 0).length));</script></body>")


def chromium(profile: Path) -> list[str]:
    """The command line that starts headless Chromium with a profile of its own."""
    path = shutil.which("chromium")
    if path is None:
        pytest.skip("no chromium on the PATH: the page is not rendered; install Debian's "
                    "chromium (sudo apt-get install chromium), as `make test` does where it "
                    "may")
    return [path, *FLAGS, f"--user-data-dir={profile}"]


def rendered_dom(page: Path, profile: Path) -> str:
    """The DOM Chromium builds of ``page`` once loaded, from a copy beside it with the probe
    (so that its relative links resolve): ``data-images`` on the body counts the images
    decoded."""
    copy = page.with_name(f"probe-{page.name}")
    copy.write_text(page.read_text().replace("</body>", PROBE))
    return subprocess.run([*chromium(profile), "--virtual-time-budget=10000", "--dump-dom",
                           copy.as_uri()], capture_output=True, text=True, timeout=120).stdout
