"""`tankfx sweep`: validated before any case runs, the same per-case results on 1 and 2
ranks, written case by case, and resumed without recomputing finished cases."""
import json
import os
import shutil
import subprocess
import sys
import textwrap

import pytest

BASE = textwrap.dedent("""
    title = "sweep base"
    [soil]
    E = 10e6
    nu = 0.3
    [load]
    pressure = 100e3
    load_radius = 1.0
    [mesh]
    edge_size = 0.05
    near_size = 0.4
    growth = 0.3
""")
SWEEP = textwrap.dedent("""
    base = "base.toml"
    [axes]
    "soil.nu" = [0.0, 0.2, 0.4]
    "soil.E_gradient" = [0.0, 0.5]
""")


def _sweep(tmp_path, text=SWEEP, ranks=1, out="out"):
    (tmp_path / "base.toml").write_text(BASE)
    (tmp_path / "sweep.toml").write_text(text)
    cmd = [sys.executable, "-m", "tankfx", "sweep", str(tmp_path / "sweep.toml"), "--out",
           str(tmp_path / out)]
    if ranks > 1:
        cmd = [shutil.which("mpiexec", path=os.path.dirname(sys.executable)), "-n",
               str(ranks), *cmd]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=900)


def _cases(path):
    return {p.name: json.loads(p.read_text()) for p in sorted((path / "cases").glob("*.json"))}


def test_sweep_on_two_ranks_equals_serial_and_resumes(tmp_path):
    serial = _sweep(tmp_path, out="serial")
    assert serial.returncode == 0, serial.stderr
    parallel = _sweep(tmp_path, ranks=2, out="parallel")
    assert parallel.returncode == 0, parallel.stderr
    s, p = _cases(tmp_path / "serial"), _cases(tmp_path / "parallel")
    assert len(s) == 6 and s.keys() == p.keys()
    for name in s:
        assert s[name]["axes"] == p[name]["axes"]
        for key in ("w0", "wd", "w_edge"):
            assert p[name]["results"][key] == pytest.approx(s[name]["results"][key], rel=1e-8)
    table = (tmp_path / "serial" / "table.csv").read_text().splitlines()
    assert len(table) == 7 and table[0].startswith("case,soil.nu,soil.E_gradient,converged")
    assert "ETA" in serial.stdout and "case 6 of 6" in serial.stdout
    chart = tmp_path / "serial" / "charts.png"
    assert chart.exists() and chart.stat().st_size > 10_000
    # an interrupted sweep: two cases lost, the others must not be recomputed
    cases = tmp_path / "serial" / "cases"
    (cases / "0001.json").unlink()
    (cases / "0004.json").unlink()
    kept = {p.name: p.stat().st_mtime_ns for p in cases.glob("*.json")}
    again = _sweep(tmp_path, out="serial")
    assert again.returncode == 0, again.stderr
    assert "4 already done, 2 to run" in again.stdout
    after = {p.name: p.stat().st_mtime_ns for p in cases.glob("*.json")}
    assert len(after) == 6
    assert all(after[name] == mtime for name, mtime in kept.items())
    assert _cases(tmp_path / "serial")["0004.json"]["results"]["w0"] == pytest.approx(
        s["0004.json"]["results"]["w0"], rel=1e-12)


@pytest.mark.parametrize("axes, message", [
    ('"soil.nuu" = [0.1]', "soil.nuu"),
    ('"soil.nu" = [0.1, 0.6]', "soil.nu"),
    ('"nu" = [0.1]', "section.key"),
    ('"soil.nu" = []', "non-empty"),
])
def test_bad_sweep_is_refused_before_any_case_runs(tmp_path, axes, message):
    proc = _sweep(tmp_path, text=f'base = "base.toml"\n[axes]\n{axes}\n')
    assert proc.returncode == 2
    assert message in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "out").exists()


def test_resuming_another_studys_output_is_refused(tmp_path):
    """The same --out for a changed study: resuming would mix two studies in one table, so
    it is refused before any case runs and nothing is touched; --force starts afresh."""
    one = 'base = "base.toml"\n[axes]\n"soil.nu" = [0.1, 0.3]\n'
    assert _sweep(tmp_path, text=one).returncode == 0
    cases = tmp_path / "out" / "cases"
    before = {p.name: p.read_bytes() for p in cases.glob("*.json")}
    other = 'base = "base.toml"\n[axes]\n"soil.nu" = [0.2, 0.3]\n'
    proc = _sweep(tmp_path, text=other)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "0000.json" in proc.stderr and "--force" in proc.stderr
    assert {p.name: p.read_bytes() for p in cases.glob("*.json")} == before
    (tmp_path / "sweep.toml").write_text(other)
    forced = subprocess.run([sys.executable, "-m", "tankfx", "sweep",
                             str(tmp_path / "sweep.toml"), "--out", str(tmp_path / "out"),
                             "--force"], capture_output=True, text=True, timeout=900)
    assert forced.returncode == 0, forced.stderr
    assert "0 already done, 2 to run" in forced.stdout
    assert [c["axes"]["soil.nu"] for c in _cases(tmp_path / "out").values()] == [0.2, 0.3]


def test_sweep_killed_mid_run_resumes_without_losing_or_redoing_cases(tmp_path):
    """A real interruption: the sweep process is killed (SIGKILL) once two cases are on
    disk; the restart keeps those files as they are, leaves no half-written case behind,
    and finishes the rest."""
    import signal
    import time

    (tmp_path / "base.toml").write_text(BASE)
    (tmp_path / "sweep.toml").write_text(SWEEP)
    cases = tmp_path / "out" / "cases"
    cmd = [sys.executable, "-m", "tankfx", "sweep", str(tmp_path / "sweep.toml"), "--out",
           str(tmp_path / "out")]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    deadline = time.monotonic() + 600
    while len(list(cases.glob("*.json"))) < 2 and proc.poll() is None:
        assert time.monotonic() < deadline, "the sweep wrote no case in 10 minutes"
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    kept = {p.name: p.stat().st_mtime_ns for p in cases.glob("*.json")}
    assert 2 <= len(kept) < 6, "the sweep must be killed mid-run"
    for p in cases.glob("*.json"):
        json.loads(p.read_text())                      # whole files only
    again = _sweep(tmp_path)
    assert again.returncode == 0, again.stderr
    assert f"{len(kept)} already done, {6 - len(kept)} to run" in again.stdout
    after = {p.name: p.stat().st_mtime_ns for p in cases.glob("*.json")}
    assert len(after) == 6 and all(after[n] == t for n, t in kept.items())
    table = (tmp_path / "out" / "table.csv").read_text().splitlines()
    assert len(table) == 7


def test_sweep_axes_reach_a_layer_and_kondners_a(tmp_path):
    """A sweep's axis can name a key of the base scene's k-th soil layer
    ("soil.layers[k].depth"), and hyperbolic_a (whose 1/a is the stored E); a layer the base
    scene does not have is refused."""
    from tankfx import Scene, SceneError
    from tankfx.studies.sweep import scene_with

    base = Scene.from_dict({"soil": {"model": "hyperbolic", "hyperbolic_a": 1e-7,
                                     "hyperbolic_b": 1e-5, "nu": 0.3, "layers": [
                                         {"depth": 2.0, "hyperbolic_a": 5e-8,
                                          "hyperbolic_b": 1e-5, "nu": 0.3}]},
                            "load": {"pressure": 1e4, "load_radius": 1.0}})
    scene = scene_with(base, {"soil.layers[1].depth": 3.0, "soil.layers[1].hyperbolic_a": 2e-8,
                         "soil.hyperbolic_a": 2e-7})
    assert scene.soil.layers[0].depth == 3.0 and scene.soil.layers[0].E == pytest.approx(5e7)
    assert scene.soil.E == pytest.approx(5e6)
    with pytest.raises(SceneError, match=r"soil.layers\[2\].E: the base scene has 1"):
        scene_with(base, {"soil.layers[2].E": 1e6})
