"""Every demo runs (on a reduced mesh), serially and on two ranks, ends with its own
assertion, and leaves its figures behind."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DEMOS = sorted((ROOT / "demos").glob("*.py"))


@pytest.mark.parametrize("ranks", [1, 2])
@pytest.mark.parametrize("demo", DEMOS, ids=lambda p: p.stem)
def test_demo_runs(demo, ranks, tmp_path):
    cmd = [sys.executable, str(demo), "--coarse"]
    if ranks > 1:
        mpiexec = shutil.which("mpiexec", path=os.path.dirname(sys.executable))
        if mpiexec is None:
            pytest.skip("no mpiexec beside this Python")
        cmd = [mpiexec, "-n", str(ranks), *cmd]
    proc = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    pngs = list((tmp_path / "results").rglob("*.png"))
    assert pngs, "the demo made no figure"
    assert all(p.stat().st_size > 10_000 for p in pngs), [(p, p.stat().st_size) for p in pngs]
