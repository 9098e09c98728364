"""The command line, as a user runs it: results.json with the contract's keys, a log, no
overwriting without --force, and the same numbers under `mpiexec -n 2`."""
import csv
import json
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
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


def _png_size(path: Path) -> tuple[int, int]:
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


def _owned_grid(pvd: Path):
    """The fields file read back with PyVista, without the ranks' ghost cells."""
    import pyvista

    grid = pyvista.read(pvd)[0]
    ghost = grid.cell_data.get("vtkGhostType")
    return grid if ghost is None else grid.extract_cells(np.flatnonzero(ghost == 0))


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
    log = (out / "tankfx.log").read_text()
    assert "solved" in log
    # the summary table: the soil's rows only (no plate, no interface), w0 as in results
    w0_row = f"{1e3 * r['w0']:.2f} mm"
    assert f"{'centre settlement w0':36s} {w0_row:>26s}" in log
    assert "M0" not in log.split("summary:")[1] and "interface slipping" not in log
    # a load without a plate: its section and settlement figures, and the soil's fields
    for name in ("section.png", "settlement.png"):
        width, height = _png_size(out / name)
        assert width >= 800 and height >= 500
    assert not (out / "moments.png").exists()
    # the report: the summary as a Markdown table and the figures beside it
    report = (out / "report.md").read_text()
    assert f"| centre settlement w0 | {1e3 * r['w0']:.2f} mm |" in report
    assert "![section](section.png)" in report and "![settlement](settlement.png)" in report
    grid = _owned_grid(out / "fields" / "soil.pvd")
    centre = np.argmin(np.hypot(grid.points[:, 0], grid.points[:, 1]))
    assert -grid.point_data["u"][centre, 1] == pytest.approx(r["w0"], rel=1e-12)
    before = (out / "results.json").read_text()
    again = _run("run", SCENE, "--out", out)
    assert again.returncode == 2 and "--force" in again.stderr
    assert (out / "results.json").read_text() == before
    # a figure or field file of ours is not overwritten either
    (out / "results.json").unlink()
    again = _run("run", SCENE, "--out", out)
    assert again.returncode == 2 and "section.png" in again.stderr
    # --force replaces ours, and removes those the new run does not write (a stress-level
    # figure of an earlier hyperbolic run here); a file of the user's stays
    (out / "stress_level.png").write_bytes((out / "section.png").read_bytes())
    (out / "notes.txt").write_text("mine")
    assert _run("run", SCENE, "--out", out, "--force").returncode == 0
    assert (out / "results.json").read_text() != before    # rewritten (new timings)
    assert not (out / "stress_level.png").exists() and (out / "section.png").exists()
    assert (out / "notes.txt").read_text() == "mine"


def test_an_out_that_cannot_be_written_is_refused_before_any_work(tmp_path):
    a_file = tmp_path / "taken"
    a_file.write_text("a user's file")
    for args in (("run", SCENE), ("sweep", ROOT / "demos" / "sweeps" / "kp_interface.toml")):
        for out, why in ((a_file, "a file, not a directory"), (a_file / "sub", "")):
            proc = _run(*args, "--out", out)
            assert proc.returncode == 2, proc.stderr
            assert f"--out {out}: cannot write there" in proc.stderr and why in proc.stderr
            assert "Traceback" not in proc.stderr
    assert a_file.read_text() == "a user's file"


def test_a_load_path_scene_file(tmp_path):
    """demos/scenes/rebonding.toml: [[stages]] through the command line. Its first stage is
    the weights alone, which have no Eq. 23 pressure: null non-dimensional measures, valid
    JSON (they were NaN, and the run ended in a traceback writing results.json)."""
    out = tmp_path / "out"
    proc = _run("run", ROOT / "demos" / "scenes" / "rebonding.toml", "--out", out,
                "--coarse", "--no-figures", "--no-fields")
    assert proc.returncode == 0, proc.stderr
    r = json.loads((out / "results.json").read_text())
    first, second = r["stages"]
    assert first["nondim"]["w0"] is None and second["nondim"]["w0"] > 0.0
    assert first["interface"]["separated_length"]["plate"] > 0.0
    assert second["interface"]["rebonded_length"]["plate"] > 0.0
    assert r["w0"] == second["w0"] and r["stage"] == 2
    assert "stage 2: w0" in (out / "tankfx.log").read_text()
    # the profiles as CSV files: the numbers of results.json, a unit in each header
    for name in ("surface", "axis", "plate", "wall"):
        with (out / "profiles" / f"{name}.csv").open() as f:
            rows = list(csv.reader(f))
        prof = r["profiles"][name]
        assert [h.split(" [")[0] for h in rows[0]] == list(prof)
        for col, key in enumerate(prof):
            got = [row[col] for row in rows[1:]]
            expected = prof[key] if key == "contact_status" else None
            if expected is None:
                np.testing.assert_array_equal(np.array(got, dtype=float), prof[key])
            else:
                assert got == expected
    assert "M_r [N m/m]" in (out / "profiles" / "plate.csv").read_text().splitlines()[0]
    # the load path's figure: settlements against the stages' applied loads
    from tankfx.results.figures import plot_load_path

    fig = plot_load_path(r, tmp_path / "load_path.png", title="path")
    assert fig is not None and fig.stat().st_size > 10_000
    assert [st["applied_load"] for st in r["stages"]] == pytest.approx(
        [first["applied_load"], r["equilibrium"]["applied_load"]])
    assert r["stages"][1]["applied_load"] > r["stages"][0]["applied_load"] > 0


@pytest.mark.verify
def test_hydrotest_scene_file_remembers_through_the_command_line(tmp_path):
    """demos/scenes/hydrotest.toml (Kondner's soil with an unloading modulus, ten stages):
    `tankfx check` says how it unloads; `tankfx run` writes each stage's unloading cells in
    results.json and the log, the report names E_ur, and the stage table's emptied tank
    keeps most of its settlement; the fields file has the cells' unloading state."""
    scene = ROOT / "demos" / "scenes" / "hydrotest.toml"
    proc = _run("check", scene)
    assert proc.returncode == 0, proc.stderr
    assert "E_ur = 3 x each cell's initial modulus" in proc.stdout
    out = tmp_path / "out"
    proc = _run("run", scene, "--out", out, "--coarse", "--no-figures")
    assert proc.returncode == 0, proc.stderr[-3000:]
    r = json.loads((out / "results.json").read_text())
    stages = r["stages"]
    assert len(stages) == 10 and stages[0]["unloading_cells"] == 0
    assert stages[6]["unloading_cells"] > 1000
    assert stages[6]["w0"] > stages[0]["w0"] + 0.5 * (stages[3]["w0"] - stages[0]["w0"])
    assert r["w0"] == pytest.approx(stages[3]["w0"], rel=2e-3)
    assert not any("less vertical load" in w for w in r["warnings"])
    assert "soil cells unloading" in (out / "tankfx.log").read_text()
    assert "unloading_modulus_ratio = 3" in (out / "report.md").read_text()
    assert "unloading" in _owned_grid(out / "fields" / "soil.pvd").cell_data


def test_without_figures_and_fields_writes_neither(tmp_path):
    out = tmp_path / "out"
    assert _run("run", SCENE, "--out", out, "--no-figures", "--no-fields").returncode == 0
    assert sorted(p.name for p in out.iterdir()) == ["profiles", "report.html", "report.md",
                                                     "results.json", "tankfx.log"]
    assert "![" not in (out / "report.md").read_text()
    # --coarse: the same scene on the coarse mesh, w0 within a few tenths of a per cent
    coarse = tmp_path / "coarse"
    assert _run("run", SCENE, "--out", coarse, "--coarse", "--no-figures",
                "--no-fields").returncode == 0
    r, rc = (json.loads((d / "results.json").read_text()) for d in (out, coarse))
    assert rc["dofs"]["total"] < 0.75 * r["dofs"]["total"]
    assert rc["w0"] == pytest.approx(r["w0"], rel=5e-3)
    version = _run("--version")
    assert version.returncode == 0 and version.stdout.startswith("tankfx 0.")


def test_fields_file_holds_the_soil_state(tmp_path):
    """The cell fields of a hyperbolic soil under the 1 m tank, read back from the VTK file:
    the secant modulus and Kondner's stress level obey Eq. 17's identity q_m b = 1 - E_sec /
    E_initial, the deviator of the stress is the model's to the Eq. 18 tolerance, the
    centre's displacement is the soil's, and the soil cells are the soil's."""
    from conftest import small_tank

    from tankfx import Scene, analyse
    from tankfx.results.fields import STATUS_CODES, write_fields
    from tankfx.results.report import summary_rows

    lam, a, b = 0.5, 1e-7, 1e-5
    scene = Scene.from_dict(small_tank(soil={"model": "hyperbolic", "hyperbolic_a": a,
                                             "hyperbolic_b": b, "nu": 0.3, "E_gradient": lam}))
    with warnings.catch_warnings():
        # E(h) of this steep gradient is negative in the cells above the ground (inside
        # the tank, not soil): the secant iteration must leave them out quietly
        warnings.simplefilter("error", RuntimeWarning)
        solution = analyse(scene)
    r = solution.results
    paths = write_fields(solution, tmp_path / "fields")
    assert [p.name for p in paths] == ["soil.pvd", "plate.vtp", "wall.vtp"]
    grid = _owned_grid(paths[0])
    soil = grid.cell_data["soil"] > 0.5
    assert soil.sum() == len(solution.domain.cells("soil"))
    depth = np.maximum(-grid.cell_centers().points[soil, 1], 0.0)
    E_initial = (1.0 + lam * depth) / a
    E, level = grid.cell_data["modulus"][soil], grid.cell_data["stress_level"][soil]
    deviator = grid.cell_data["deviator"][soil]
    tol = scene.soil.tolerance
    assert 0.3 < level.max() < 1.0 and level.min() >= 0.0
    assert np.all(E <= E_initial * (1 + 1e-12))
    assert np.max(np.abs(level - (1.0 - E / E_initial))) <= tol
    assert np.all(np.abs(deviator * b - level) <= tol * deviator * b + 1e-12)
    assert np.all(grid.cell_data["modulus"][~soil] == 0.0)
    # the soil's settlement under the plate's centre (w0 is the plate's: the bonded
    # interface's penalty lets the two differ by a little)
    centre = np.argmin(np.hypot(grid.points[:, 0], grid.points[:, 1] + scene.embedment))
    surface = r["profiles"]["surface"]
    w_soil = surface["w"][int(np.argmin(surface["r"]))]
    assert -grid.point_data["u"][centre, 1] == pytest.approx(w_soil, rel=1e-12)
    # the plate and wall files: lines through the profiles' stations, with their values
    import pyvista

    plate, wall = r["profiles"]["plate"], r["profiles"]["wall"]
    base = -scene.embedment
    expected = {  # station coordinates, displacement (u_r, u_z), moment
        "plate": (np.column_stack([plate["r"], np.full(len(plate["r"]), base)]),
                  np.column_stack([plate["u_r"], -np.asarray(plate["w"])]), "M_r"),
        "wall": (np.column_stack([np.full(len(wall["z"]), scene.wall.radius),
                                  base + np.asarray(wall["z"])]),
                 np.column_stack([wall["u_r"], wall["u_z"]]), "M_z")}
    for path, (part, (xy, u, moment)) in zip(paths[1:], expected.items()):
        line, prof = pyvista.read(path), r["profiles"][part]
        np.testing.assert_allclose(line.points[:, :2], xy, atol=1e-12)
        np.testing.assert_allclose(line.point_data["u"][:, :2], u, rtol=1e-12)
        np.testing.assert_allclose(line.point_data[moment], prof[moment], rtol=1e-12)
        assert line.point_data["contact_status"].tolist() == \
            [STATUS_CODES[c] for c in prof["contact_status"]]
    # the summary of a bonded tank: its moments and hoop force, no interface states
    rows = {name: value for name, value, _ in summary_rows(r)}
    assert rows["centre moment M0"] == f"{r['M0'] / 1e3:.4g} kN m/m"
    assert rows["largest wall hoop force"] == \
        f"{max(r['profiles']['wall']['N_theta']) / 1e3:.4g} kN/m"
    assert "interface slipping" not in rows
    # the figures `tankfx run` draws for a tank on a hyperbolic soil
    from tankfx.results.figures import write_figures

    written = write_figures(solution, tmp_path)
    assert sorted(p.name for p in written) == ["contact.png", "moments.png", "profiles.png",
                                                "section.png", "settlement.png",
                                                "stress_level.png"]
    assert all(_png_size(p)[0] >= 800 for p in written)


def test_mpiexec_writes_the_same_numbers(tmp_path):
    if shutil.which("mpiexec", path=os.path.dirname(sys.executable)) is None:
        pytest.skip("no mpiexec beside this Python")
    serial, parallel = tmp_path / "s", tmp_path / "p"
    assert _run("run", SCENE, "--out", serial, "--no-figures").returncode == 0
    proc = _run("run", SCENE, "--out", parallel, np_=2)     # figures and fields too
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
    # the fields file of 2 ranks (one piece each) holds the serial one's cells and values
    gs, gp = (_owned_grid(d / "fields" / "soil.pvd") for d in (serial, parallel))
    assert gp.n_cells == gs.n_cells
    for name in ("deviator", "mean_stress", "modulus", "soil"):
        assert np.sort(gp.cell_data[name]) == pytest.approx(np.sort(gs.cell_data[name]),
                                                           rel=1e-8, abs=1e-6)
    assert all(_png_size(parallel / f)[0] >= 800 for f in ("section.png", "settlement.png"))


def test_every_shipped_scene_is_valid():
    """The scenes in demos/scenes load and resolve (the demos run them; the nonlinear one is
    run on a coarse mesh in test_hyperbolic)."""
    from tankfx import load_scene

    scenes = sorted((ROOT / "demos" / "scenes").glob("*.toml"))
    assert len(scenes) >= 4
    for path in scenes:
        scene = load_scene(path)
        assert scene.title


def test_a_plate_without_a_wall_gets_its_figures_and_fields(tmp_path):
    """The figure and field sets follow the scene: a plate without a wall has no wall file,
    and its moment diagram and profiles draw the plate alone."""
    from conftest import small_tank

    from tankfx import Scene, analyse
    from tankfx.results.figures import write_figures
    from tankfx.results.fields import write_fields

    data = small_tank(interface={"condition": "smooth"})
    del data["wall"]
    solution = analyse(Scene.from_dict(data))
    assert [p.name for p in write_fields(solution, tmp_path / "fields")] == ["soil.pvd",
                                                                              "plate.vtp"]
    written = write_figures(solution, tmp_path)
    assert [p.name for p in written] == ["section.png", "settlement.png", "moments.png",
                                         "profiles.png", "contact.png"]
    assert all(_png_size(p)[0] >= 800 for p in written)


def test_check_says_what_a_scene_builds_without_solving(tmp_path):
    """`tankfx check`: a valid scene is described (its strata and forms, the parts built and
    the iterations run), `--resolved` prints a scene file that reads back to the same scene,
    `--mesh` counts the unknowns an analysis has; a sweep is checked case by case; a bad
    scene gets exit code 2 and the key, no traceback."""
    import tomllib

    from tankfx import Scene, analyse, load_scene

    proc = _run("check", SCENE, "--resolved", "--mesh")
    assert proc.returncode == 0, proc.stderr
    assert "valid" in proc.stdout and "builds: soil; iterates: nothing" in proc.stdout
    resolved = proc.stdout.split("every default written out:\n", 1)[1]
    assert Scene.from_dict(tomllib.loads(resolved)) == load_scene(SCENE)
    dofs = analyse(load_scene(SCENE)).results["dofs"]["total"]
    assert f"total {dofs}" in proc.stdout

    layered = _run("check", ROOT / "demos" / "scenes" / "layered_tank.toml")
    assert "from 5 m: E = 5e+07 Pa, nu = 0.3" in layered.stdout
    assert "(mixed u-p form)" in layered.stdout and "(displacement form)" in layered.stdout
    nonlinear = _run("check", ROOT / "demos" / "scenes" / "embedded_tank_nonlinear.toml")
    assert "iterates: Picard on the secant modulus" in nonlinear.stdout
    assert "the Mohr-Coulomb active set" in nonlinear.stdout

    sweep = _run("check", ROOT / "demos" / "sweeps" / "kp_interface.toml")
    assert sweep.returncode == 0 and "a sweep of 12 cases" in sweep.stdout
    for path in sorted((ROOT / "demos" / "sweeps").glob("*.toml")):     # every shipped one
        assert _run("check", path).returncode == 0, path

    bad = tmp_path / "bad.toml"
    bad.write_text(SCENE.read_text().replace("nu = 0.3", "nu = 0.7"))
    proc = _run("check", bad)
    assert proc.returncode == 2 and "soil.nu = 0.7" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_scene_file_round_trip_through_to_toml():
    """Every demo scene written out resolved (Scene.to_toml) reads back equal, stages and
    layers included."""
    import tomllib

    from tankfx import Scene, load_scene

    for path in sorted((ROOT / "demos" / "scenes").glob("*.toml")):
        scene = load_scene(path)
        assert Scene.from_dict(tomllib.loads(scene.to_toml())) == scene, path
