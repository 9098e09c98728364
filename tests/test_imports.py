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


def _definitions():
    """Every function and class of tankfx/ with its length in lines."""
    import ast

    for path in sorted((ROOT / "tankfx").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                yield path.relative_to(ROOT), node, node.end_lineno - node.lineno + 1


def test_no_function_over_100_lines_and_no_class_over_350():
    """A reader holds a function on one screen's scroll and a class in one sitting."""
    long = [f"{path}: {node.name} {n} lines" for path, node, n in _definitions()
            if n > (350 if isinstance(node, __import__("ast").ClassDef) else 100)]
    assert not long, "\n".join(long)


def test_the_collapse_kind_is_read_in_one_place_and_no_private_method_of_another_is_called():
    """``analysis.collapse`` is read by ``Analysis.collapse_kind`` alone (the scene's checks
    read the table's word before any section exists); the elastoplastic soil's drivers and
    the collapse study call no other object's private methods."""
    import re

    reads = [f"{p.relative_to(ROOT)}:{k + 1}" for p in (ROOT / "tankfx").rglob("*.py")
             if p.name != "sections.py"
             for k, line in enumerate(p.read_text().splitlines())
             if re.search(r"\.analysis\.collapse\b(?!_kind)", line.split("#")[0])]
    assert not reads, reads
    private = re.compile(r"\b(?!self\b|cls\b)[a-z_][a-z0-9_]*\._[a-z][a-z0-9_]*\(")
    calls = [f"{p.relative_to(ROOT)}:{k + 1}: {line.strip()}"
             for p in [*(ROOT / "tankfx" / "iterations").glob("*.py"),
                       ROOT / "tankfx" / "collapse_study.py", ROOT / "tankfx" / "analysis.py"]
             for k, line in enumerate(p.read_text().splitlines())
             if private.search(line.split("#")[0])]
    assert not calls, "\n".join(calls)
