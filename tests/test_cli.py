"""The command line, as a user runs it: results.json with the contract's keys, a log, no
overwriting without --force, and the same numbers under `mpiexec -n 2`."""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "demos" / "scenes" / "flexible_load.toml"
KEYS = {"converged", "w0", "w_edge", "wd", "M0", "nondim", "profiles", "equilibrium", "dofs",
        "timings_s", "versions"}


def _run(*args, np_=1, cwd=None):
    cmd = [sys.executable, "-m", "tankfx", *map(str, args)]
    if np_ > 1:
        mpiexec = shutil.which("mpiexec", path=os.path.dirname(sys.executable))
        cmd = [mpiexec, "-n", str(np_), *cmd]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, timeout=600)


def test_run_writes_results_and_log_and_refuses_to_overwrite(tmp_path):
    out = tmp_path / "out"
    proc = _run("run", SCENE, "--out", out)
    assert proc.returncode == 0, proc.stderr
    r = json.loads((out / "results.json").read_text())
    assert KEYS <= set(r)
    assert set(r["nondim"]) == {"w0", "wd", "M0", "Kp", "Kt"}
    assert set(r["profiles"]["surface"]) == {"r", "z", "w", "u_r"}
    assert set(r["profiles"]["axis"]) == {"z", "sigma_zz"}
    assert r["converged"] is True and r["M0"] is None
    assert "solved" in (out / "tankfx.log").read_text()
    before = (out / "results.json").read_text()
    again = _run("run", SCENE, "--out", out)
    assert again.returncode == 2 and "--force" in again.stderr
    assert (out / "results.json").read_text() == before
    assert _run("run", SCENE, "--out", out, "--force").returncode == 0


def test_mpiexec_writes_the_same_numbers(tmp_path):
    if shutil.which("mpiexec", path=os.path.dirname(sys.executable)) is None:
        pytest.skip("no mpiexec beside this Python")
    serial, parallel = tmp_path / "s", tmp_path / "p"
    assert _run("run", SCENE, "--out", serial).returncode == 0
    proc = _run("run", SCENE, "--out", parallel, np_=2)
    assert proc.returncode == 0, proc.stderr
    rs = json.loads((serial / "results.json").read_text())
    rp = json.loads((parallel / "results.json").read_text())
    assert rp["mpi_ranks"] == 2
    for key in ("w0", "w_edge", "wd", "w_mean"):
        assert rp[key] == pytest.approx(rs[key], rel=1e-8)
    assert rp["equilibrium"]["reaction"] == pytest.approx(rs["equilibrium"]["reaction"],
                                                          rel=1e-8)
    assert rp["profiles"]["axis"]["sigma_zz"] == pytest.approx(
        rs["profiles"]["axis"]["sigma_zz"], rel=1e-8, abs=1e-3)


def test_every_shipped_scene_is_valid():
    """The scenes in demos/scenes load and resolve (the demos run them; the nonlinear one is
    run on a coarse mesh in test_hyperbolic)."""
    from tankfx import load_scene

    scenes = sorted((ROOT / "demos" / "scenes").glob("*.toml"))
    assert len(scenes) >= 4
    for path in scenes:
        scene = load_scene(path)
        assert scene.title
