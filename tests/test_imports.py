"""What a run loads: ``import tankfx`` and ``tankfx run --no-figures`` (its fields, profiles
and report written) import neither matplotlib nor PyVista (nor VTK, which PyVista wraps);
the figure modules are imported where a figure is drawn. Their import costs a whole-process
run about 0.4 s (docs/development/2026-11-26-suite.md), a flexible load's whole run is under
a second.

And the members' profiles, which a run without figures writes as .vtp files without
PyVista, read back in PyVista as the polyline it would have written itself."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PLOTTING = ("matplotlib", "pyvista", "vtkmodules")

#: runs the command line in this process, then prints which plotting modules it loaded
PROBE = ("import sys\n"
         "from tankfx.cli import main\n"
         "code = main(sys.argv[1:])\n"
         f"print('loaded:', *[m for m in {PLOTTING!r} if m in sys.modules])\n"
         "sys.exit(code)\n")


def _loaded(*args: str, cwd: Path) -> list[str]:
    proc = subprocess.run([sys.executable, "-c", PROBE, *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    line, = [s for s in proc.stdout.splitlines() if s.startswith("loaded:")]
    return line.split()[1:]


def test_import_tankfx_loads_no_plotting_library():
    code = f"import sys, tankfx; print(*[m for m in {PLOTTING!r} if m in sys.modules])"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == []


def test_a_run_without_figures_loads_no_plotting_library_and_one_with_them_does(tmp_path):
    """A tank with a plate and a wall (so the members' .vtp files are written too)."""
    scene = ROOT / "demos" / "scenes" / "embedded_tank.toml"
    out = tmp_path / "bare"
    assert _loaded("run", str(scene), "--coarse", "--no-figures", "--out", str(out),
                   cwd=tmp_path) == []
    assert (out / "fields" / "plate.vtp").exists() and (out / "fields" / "wall.vtp").exists()
    assert (out / "report.html").exists()
    # the probe can see them: drawing the figures loads both
    drawn = _loaded("run", str(scene), "--coarse", "--no-fields", "--out",
                    str(tmp_path / "drawn"), cwd=tmp_path)
    assert {"matplotlib", "pyvista"} <= set(drawn)


def test_a_member_profile_reads_back_in_pyvista_as_its_own_polyline(tmp_path):
    """Points, segments and every value exactly as written (17 digits), the contact state
    as its code."""
    import pyvista

    from tankfx.results.fields import STATUS_CODES, _write_member

    r = np.linspace(0.0, 1.0, 9)
    z = np.full_like(r, -0.3)
    states = list(STATUS_CODES)
    values = {"r": r, "M_r": np.sin(3 * r) * 1e3 / 7,
              "contact_status": [states[i % len(states)] for i in range(len(r))]}
    _write_member(tmp_path / "plate.vtp", r, z, values, 1e-3 * r, -2e-3 * r ** 2)
    line = pyvista.read(tmp_path / "plate.vtp")
    own = pyvista.lines_from_points(np.column_stack([r, z, np.zeros_like(r)]))
    assert np.array_equal(line.points, own.points) and np.array_equal(line.lines, own.lines)
    assert np.array_equal(line.point_data["M_r"], values["M_r"])
    assert np.array_equal(line.point_data["u"][:, 1], -2e-3 * r ** 2)
    assert line.point_data["contact_status"].tolist() == [STATUS_CODES[s] for s in
                                                          values["contact_status"]]
    assert set(line.point_data.keys()) == {"u", "M_r", "contact_status"}
