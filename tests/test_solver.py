"""The linear solvers. The iterative option ([solver] method = "iterative"): the same
numbers as the direct solver (also through nonlinear iterations and a slipping, unsymmetric
interface), a reported iteration count that does not grow with the mesh, clear refusals.
The direct solver: load stages sharing one factorisation; malloc keeping freed pages
changes no number; unscaled refactorisations give the scaled numbers, and one that fails is
redone scaled; numpy's BLAS threads keep to each rank's share of the cores."""
import json
import math
import os
import platform
import subprocess
import sys

import pytest

from conftest import (COARSE, HYPERBOLIC_SOIL, WATER_LOAD, flexible_scene,
                      incompressible_hyperbolic_punch, small_tank)
from tankfx import Scene, SceneError, SolveError, analyse


def test_soil_alone_cg_gamg_equals_direct_and_scales():
    its = []
    for near in (0.2, 0.1):
        scene = flexible_scene(mesh={"edge_size": 0.01, "near_size": near})
        direct = analyse(scene).results
        it = analyse(scene.with_changes(solver={"method": "iterative"})).results
        for key in ("w0", "w_edge", "w_mean"):
            assert it[key] == pytest.approx(direct[key], rel=1e-8), key
        assert it["equilibrium"]["relative_error"] < 1e-8
        assert it["linear_solver"]["factorisation"] == "CG + GAMG"
        its.append(it["linear_solver"]["krylov_iterations"])
        assert it["dofs"] == direct["dofs"]
    # multigrid: four times the near-field cells, about the same iterations
    assert its[1] <= 1.5 * its[0], its


def test_tank_structure_condensed_equals_direct_and_scales():
    """Soil + plate + wall: GMRES with the structure condensed and GAMG on the soil's Schur
    complement gives the direct solution, in about as many iterations on a finer mesh."""
    data = small_tank(load={"pressure": 50e3, "liquid_unit_weight": 9810.0,
                            "liquid_height": 2.5})
    its = []
    for mesh in (COARSE, {"edge_size": 0.005, "near_size": 0.125, "growth": 0.3}):
        direct = analyse(Scene.from_dict(data | {"mesh": mesh})).results
        it = analyse(Scene.from_dict(data | {"mesh": mesh,
                                             "solver": {"method": "iterative"}})).results
        for key in ("w0", "wd", "M0"):
            assert it[key] == pytest.approx(direct[key], rel=1e-6), key
        assert it["equilibrium"]["contact_relative_error"] < 1e-6
        assert it["linear_solver"]["factorisation"].startswith("GMRES + structure condensed")
        its.append(it["linear_solver"]["krylov_iterations"])
    assert 0 < its[1] <= 1.5 * its[0], its


@pytest.mark.verify
def test_nonlinear_tank_iterative_equals_direct():
    """Hyperbolic soil under a bonded plate and wall: every Picard iteration is a new
    operator, on which GAMG keeps the first solve's interpolation (only its coarse operators
    are recomputed); the iteration takes the same solves and reaches the direct answer."""
    data = small_tank(soil=HYPERBOLIC_SOIL, load=WATER_LOAD)
    direct = analyse(Scene.from_dict(data)).results
    it = analyse(Scene.from_dict(data | {"solver": {"method": "iterative"}})).results
    assert it["linear_solves"] == direct["linear_solves"] >= 3
    for key in ("w0", "wd", "M0"):
        assert it[key] == pytest.approx(direct[key], rel=1e-6), key
    assert it["linear_solver"]["krylov_iterations"] < 100 * it["linear_solves"]


def test_load_stages_of_a_linear_scene_share_one_factorisation():
    """Bonded, linear soil: every load stage has the same matrix, so later stages assemble
    only their load and reuse the factorisation (one numeric factorisation in all), with the
    numbers of separate analyses."""
    from petsc4py import PETSc

    from tankfx.analysis import analyse_path
    from tankfx.fem.solvers import KEPT_ASSEMBLY

    data = small_tank()
    loads = [{"pressure": 50e3}, {"pressure": 20e3, "liquid_unit_weight": 9810.0,
                                  "liquid_height": 2.5}]
    PETSc.Log.begin()
    event = PETSc.Log.Event("MatCholFctrNum")
    before = event.getPerfInfo()["count"]
    staged = analyse_path(Scene.from_dict(data), loads)
    assert event.getPerfInfo()["count"] - before == 1
    assert staged[-1].results["linear_solver"]["assembly"] == KEPT_ASSEMBLY
    for stage, load in zip(staged, loads):
        alone = analyse(Scene.from_dict(data | {"load": load})).results
        for key in ("w0", "wd", "M0"):
            assert stage.results[key] == pytest.approx(alone[key], rel=1e-9), key
        assert stage.results["equilibrium"]["relative_error"] < 1e-8
    # the bare soil too; its loaded circle is meshed, so a stage cannot change it
    flexible = flexible_scene(mesh=COARSE)
    first, second = analyse_path(flexible, [{"pressure": 1e5, "load_radius": 1.0},
                                            {"pressure": 3e5, "load_radius": 1.0}])
    assert second.results["w0"] == pytest.approx(3 * first.results["w0"], rel=1e-9)
    assert second.results["linear_solver"]["assembly"] == KEPT_ASSEMBLY
    with pytest.raises(ValueError, match="load.load_radius: every load stage keeps"):
        analyse_path(flexible, [{"pressure": 1e5, "load_radius": 1.0},
                                {"pressure": 1e5, "load_radius": 2.0}])


def test_too_few_iterations_is_a_clear_failure():
    scene = flexible_scene(mesh=COARSE, solver={"method": "iterative", "max_iterations": 2})
    with pytest.raises(SolveError, match="did not reach the relative residual .* raise "
                                         "solver.max_iterations"):
        analyse(scene)


@pytest.mark.parametrize("solver, soil, message", [
    ({"method": "gmres"}, {}, "solver.method"),
    ({"rtol": 0.0}, {}, "solver.rtol"),
    ({"max_iterations": 0}, {}, "solver.max_iterations"),
    ({"method": "iterative"}, {"nu": 0.49}, "zero pressure block"),
])
def test_bad_solver_options_are_refused(solver, soil, message):
    with pytest.raises(SceneError, match=message):
        flexible_scene(solver=solver, soil=soil)


def _results_in_new_process(script: str, data: dict, env: dict, *args: str) -> dict:
    """Run ``script`` (which analyses the scene dict in argv[1] and prints one line
    "RESULT <json>") in a fresh Python process with environment ``env``; its JSON, and the
    process's stderr as "log"."""
    proc = subprocess.run([sys.executable, "-c", script, json.dumps(data), *args], env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    line = [ln for ln in proc.stdout.splitlines() if ln.startswith("RESULT ")][-1]
    return json.loads(line[len("RESULT "):]) | {"log": proc.stderr}


_MALLOC_RUN = """
import json, sys
from tankfx import Scene, analyse
r = analyse(Scene.from_dict(json.loads(sys.argv[1]))).results
print("RESULT " + json.dumps({k: r[k] for k in ("w0", "wd", "M0", "linear_solves")}
                             | {"kept": r["linear_solver"]["keeps_freed_memory"]}))
"""


@pytest.mark.verify
@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="glibc's malloc")
def test_keeping_freed_memory_changes_no_number():
    """Factorisations that reuse the freed pages of the last one (tankfx._memory) give the
    same numbers to the last digit as the system's malloc; the environment can opt out."""
    data = small_tank(interface={"condition": "mohr_coulomb", "friction_angle": 5.0})
    data["plate"]["embedment"] = 0.0           # a surface tank
    out = {}
    for keep in ("1", "0"):
        out[keep] = _results_in_new_process(
            _MALLOC_RUN, data, os.environ | {"TANKFX_KEEP_FREED_MEMORY": keep})
        del out[keep]["log"]
    assert out["1"].pop("kept") is True and out["0"].pop("kept") is False
    assert out["1"]["linear_solves"] > 2          # several factorisations
    assert out["1"] == out["0"]


_THREADS_RUN = """
import json, sys
from threadpoolctl import threadpool_info
if sys.argv[2] == "without threadpoolctl":
    sys.modules["threadpoolctl"] = None        # its import now fails, as where not installed
from tankfx import Scene, analyse
r = analyse(Scene.from_dict(json.loads(sys.argv[1]))).results
blas = [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]
print("RESULT " + json.dumps({k: r[k] for k in ("w0", "wd", "M0", "linear_solves")}
                             | {"limit": r["linear_solver"]["numpy_blas_threads"],
                                "threads": max(blas)}))
"""


@pytest.mark.verify
def test_blas_threads_keep_to_the_share_of_each_rank():
    """Where the MPI launcher says two processes share the machine (MPICH's
    MPI_LOCALNRANKS), numpy's BLAS keeps to half the cores (tankfx._threads: its spinning
    threads took the cores from the other rank); a thread count set by the user is left
    alone, and so is a serial run; without threadpoolctl nothing is limited and the log
    says so. The numbers do not change. The hyperbolic soil's Anderson steps are numpy BLAS
    calls."""
    from tankfx.fem.threads import LAUNCHER_SETTINGS, USER_SETTINGS, cores_per_rank

    data = small_tank(soil=HYPERBOLIC_SOIL, load=WATER_LOAD)
    base = {k: v for k, v in os.environ.items() if k not in USER_SETTINGS + LAUNCHER_SETTINGS}
    out = {case: _results_in_new_process(_THREADS_RUN, data, base | extra, case)
           for case, extra in (("serial", {}), ("two ranks", {"MPI_LOCALNRANKS": "2"}),
                               ("user's choice", {"MPI_LOCALNRANKS": "2",
                                                  "OPENBLAS_NUM_THREADS": "2"}),
                               ("without threadpoolctl", {"MPI_LOCALNRANKS": "2"}))}
    share = cores_per_rank(2)
    assert out["serial"]["limit"] is None
    assert out["two ranks"]["limit"] == share and out["two ranks"]["threads"] == share
    # OpenBLAS's own count under the user's setting (it never exceeds the machine's)
    assert out["user's choice"]["limit"] is None
    assert out["user's choice"]["threads"] == min(2, out["serial"]["threads"])
    assert out["without threadpoolctl"]["limit"] is None
    assert out["without threadpoolctl"]["threads"] == out["serial"]["threads"]
    assert "pip install threadpoolctl" in out["without threadpoolctl"]["log"]
    assert "threadpoolctl" not in out["two ranks"]["log"]
    assert out["serial"]["linear_solves"] > 3          # several Anderson steps
    for case in ("two ranks", "user's choice", "without threadpoolctl"):
        assert out[case]["linear_solves"] == out["serial"]["linear_solves"]
        for key in ("w0", "wd", "M0"):
            assert out[case][key] == pytest.approx(out["serial"][key], rel=1e-9), key


@pytest.mark.verify
def test_slipping_interface_iterative_equals_direct():
    """A Mohr-Coulomb interface that slips makes the system unsymmetric (the friction
    couples the shear to the normal jump): GMRES with GAMG, whose interpolation was built on
    the first, all-stick solve, reaches the direct answer in the same solves, in under 80
    iterations a solve (built afresh on each unsymmetric operator: 124)."""
    data = small_tank(soil=HYPERBOLIC_SOIL, load=WATER_LOAD,
                      interface={"condition": "mohr_coulomb", "friction_angle": 26.6})
    direct = analyse(Scene.from_dict(data)).results
    it = analyse(Scene.from_dict(data | {"solver": {"method": "iterative"}})).results
    assert direct["interface"]["slip_length"]["wall"] > 0.5 * 0.3   # most of the wall slips
    assert it["linear_solves"] == direct["linear_solves"] >= 3
    for key in ("w0", "wd", "M0"):
        assert it[key] == pytest.approx(direct[key], rel=1e-6), key
    assert it["interface"]["slip_length"] == direct["interface"]["slip_length"]
    assert it["linear_solver"]["krylov_iterations"] < 80 * it["linear_solves"]


@pytest.mark.verify
def test_repeated_factorisations_unscaled_give_the_scaled_numbers(monkeypatch):
    """The factorisations of a nonlinear iteration skip MUMPS's scaling: with the two
    refinement steps they give the numbers of scaled factorisations (the nonlinear tank
    with a slipping Mohr-Coulomb wall), at the same residual floor; a single factorisation
    keeps the scaling."""
    from tankfx.fem import solvers as solve

    data = small_tank(soil=HYPERBOLIC_SOIL, load=WATER_LOAD,
                      interface={"condition": "mohr_coulomb", "friction_angle": 26.6})
    unscaled = analyse(Scene.from_dict(data)).results
    monkeypatch.setattr(solve, "UNSCALED_REFACTORISATIONS", False)
    scaled = analyse(Scene.from_dict(data)).results
    assert unscaled["linear_solver"]["scaling"] == solve.NO_SCALING
    assert scaled["linear_solver"]["scaling"] == solve.AUTOMATIC_SCALING
    assert unscaled["linear_solves"] == scaled["linear_solves"] >= 3
    for key in ("w0", "wd", "M0"):
        assert unscaled[key] == pytest.approx(scaled[key], rel=1e-8), key
    assert unscaled["linear_solver"]["last_relative_residual"] < \
        10 * scaled["linear_solver"]["last_relative_residual"]
    linear = analyse(Scene.from_dict(small_tank())).results
    assert linear["linear_solver"]["scaling"] == solve.AUTOMATIC_SCALING


def test_a_failed_unscaled_factorisation_is_redone_scaled():
    """A hyperbolic soil at nu = 0.5 (the mixed displacement-pressure form: a saddle point)
    under a rigid punch: its unscaled factorisation runs out of MUMPS's pivoting workspace,
    the solver factorises again with the scaling and keeps it. At a load far below the
    soil's strength the settlement is that of a linear soil of E = 1/a:
    P (1 - nu^2) / (2 a E)."""
    from tankfx.fem import solvers as solve

    a_hyp = 1e-7
    r = analyse(Scene.from_dict(incompressible_hyperbolic_punch(a_hyp))).results
    assert r["linear_solver"]["scaling"] == solve.RESCALED
    assert r["linear_solver"]["last_relative_residual"] < 1e-9
    assert r["w0"] == pytest.approx(1e3 * math.pi * (1 - 0.25) / (2 / a_hyp), rel=1e-2)
