"""Serial and parallel runs of one scene give the same numbers (1e-8 relative): the mesh is
made on rank 0 and distributed, so both solve the same discrete problem.

Run on two ranks by `make test-mpi`; each rank also solves the scene alone on COMM_SELF
for the serial reference."""
import logging
import os

import numpy as np
import pytest
from mpi4py import MPI
from threadpoolctl import threadpool_info

from conftest import (COARSE, HYPERBOLIC_SOIL, WATER_LOAD, flexible_scene,
                      incompressible_hyperbolic_punch, small_tank)
from tankfx import Scene, analyse
from tankfx.fem.threads import USER_SETTINGS, cores_per_rank

pytestmark = pytest.mark.mpi


needs_two_ranks = pytest.mark.skipif(MPI.COMM_WORLD.size == 1,
                                     reason="needs mpiexec -n 2 (make test-mpi)")


def _solve_both(scene):
    """The scene's results on all ranks and, on each rank alone, serially."""
    return analyse(scene, MPI.COMM_WORLD).results, analyse(scene, MPI.COMM_SELF).results


def _assert_same_numbers(parallel, serial, rtol=1e-8):
    assert parallel["dofs"] == serial["dofs"]
    p, s = _numbers(parallel), _numbers(serial)
    for key in s:
        scale = np.max(np.abs(s[key]))
        if key == "wall.N_z":
            # without an axial load N_z is the residue of the cancellation E t (eps_s +
            # nu eps_theta): judged on the scale of the wall's membrane forces
            scale = max(scale, np.max(np.abs(s["wall.N_theta"])))
        np.testing.assert_allclose(p[key], s[key], rtol=rtol, atol=rtol * scale + 1e-14,
                                   err_msg=key)


def _numbers(results):
    """Every number of results.json that must not depend on the partition."""
    out = {k: results[k] for k in ("w0", "w_edge", "wd", "w_mean")}
    if results["M0"] is not None:
        out["M0"] = results["M0"]
        out["contact_resultant"] = results["equilibrium"]["contact_resultant"]
    out.update({f"junction.{k}": v for k, v in results.get("junction", {}).items()})
    out["reaction"] = results["equilibrium"]["reaction"]
    for name, prof in results["profiles"].items():
        for key, values in prof.items():
            if key != "contact_status":
                out[f"{name}.{key}"] = np.asarray(values)
    return out


@needs_two_ranks
@pytest.mark.parametrize("soil", [{"nu": 0.3}, {"nu": 0.45, "E_gradient": 0.5},
                                  {"nu": 0.5}])
def test_parallel_equals_serial(soil):
    scene = flexible_scene(**{"soil": soil})
    parallel, serial = _solve_both(scene)
    assert parallel["mpi_ranks"] == MPI.COMM_WORLD.size and serial["mpi_ranks"] == 1
    _assert_same_numbers(parallel, serial)
    if not any(os.environ.get(key) for key in USER_SETTINGS):
        # numpy's BLAS keeps to this rank's share of the cores (tankfx._threads)
        share = cores_per_rank(MPI.COMM_WORLD.size)
        assert parallel["linear_solver"]["numpy_blas_threads"] == share
        assert max(i["num_threads"] for i in threadpool_info()
                   if i["user_api"] == "blas") == share


@needs_two_ranks
@pytest.mark.parametrize("embedment, condition, nu, tan_phi, states", [
    (0.0, "bonded", 0.3, None, None),
    (0.3, "smooth", 0.3, None, None),
    (0.3, "mohr_coulomb", 0.3, 0.1, "element"),     # 11 reversed slips
    (0.3, "mohr_coulomb", 0.3, 0.3, "node"),        # 4 reversed slips
    pytest.param(0.3, "mohr_coulomb", 0.3, 10.0, "node",      # 19 nodes held at the wall foot
                 marks=pytest.mark.verify),
    (0.3, "bonded", 0.5, None, None)])
def test_tank_parallel_equals_serial(embedment, condition, nu, tan_phi, states):
    """A surface and an embedded tank, plate + wall + liquid: the block system with its
    interior-facet interface terms, and the Mohr-Coulomb iteration (the same element or node
    states, in the same number of iterations, the same reversed slips on their secant law,
    the same nodes held), give the same numbers on 1 and 2 ranks."""
    interface = {"condition": condition} | (
        {"tan_phi": tan_phi, "states": states} if condition == "mohr_coulomb" else {})
    scene = Scene.from_dict({
        "soil": {"E": 10e6, "nu": nu},
        "plate": {"radius": 1.0, "Kp": 1.0, "E": 30e9, "nu": 0.2, "embedment": embedment},
        "wall": {"radius": 1.0, "Kt": 0.1, "height": 3.0, "E": 30e9, "nu": 0.2},
        "interface": interface,
        "load": {"pressure": 50e3, "liquid_unit_weight": 9810.0, "liquid_height": 2.5}})
    parallel, serial = _solve_both(scene)
    assert parallel["interface"]["iterations"] == serial["interface"]["iterations"]
    if condition == "mohr_coulomb":     # the secant law of reversed slips runs on both
        assert parallel["interface"]["reversed_slips"] == serial["interface"][
            "reversed_slips"] > 0
        assert parallel["interface"]["frozen_elements"] == \
            serial["interface"]["frozen_elements"] == (19 if tan_phi == 10.0 else 0)
    for part in ("plate", "wall"):
        assert parallel["profiles"][part].get("contact_status") == \
            serial["profiles"][part].get("contact_status")
    _assert_same_numbers(parallel, serial)


@needs_two_ranks
@pytest.mark.parametrize("soil", [
    # a linear tank on an undrained clay layer (its own pressure) at the plate's level over
    # a stiffer stratum, under a Mohr-Coulomb interface
    {"E": 10e6, "nu": 0.3, "layers": [{"depth": 0.3, "E": 4e6, "nu": 0.5},
                                      {"depth": 1.5, "E": 20e6, "nu": 0.3}]},
    # a hyperbolic soil with a weaker layer
    dict(HYPERBOLIC_SOIL, layers=[{"depth": 0.8, "hyperbolic_a": 5e-7, "hyperbolic_b": 4e-5,
                                   "nu": 0.35}]),
    # Duncan & Chang's soil: the confinement from the cells' stresses on every rank
    {"model": "duncan_chang", "nu": 0.3, "modulus_number": 400.0, "modulus_exponent": 0.5,
     "cohesion": 5e3, "friction_angle": 35.0, "unit_weight": 18e3}],
    ids=["linear_mixed", "hyperbolic", "duncan_chang"])
def test_layered_ground_parallel_equals_serial(soil):
    """Layered ground: the cells' strata, the per-layer pressures and pins, the secant
    iteration's per-layer parameters are the same on 1 and 2 ranks; and so are Duncan &
    Chang's constants from the cells' confinement."""
    scene = Scene.from_dict(small_tank(soil=soil, interface={
        "condition": "mohr_coulomb", "tan_phi": 0.5}, load=WATER_LOAD))
    parallel, serial = _solve_both(scene)
    assert parallel["soil"]["iterations"] == serial["soil"]["iterations"]
    assert parallel["interface"]["iterations"] == serial["interface"]["iterations"]
    _assert_same_numbers(parallel, serial)


@needs_two_ranks
def test_section_figure_is_built_from_all_ranks():
    """The section figure's grid is gathered from every rank: on 2 ranks it holds the same
    cells with the same field values as the serial one (compared cell by cell on rank 0)."""
    from tankfx.results.figures import gather_grid

    scene = flexible_scene(nu=0.3, mesh={"edge_size": 0.05, "near_size": 0.4, "growth": 0.3})
    grids = []
    for comm in (MPI.COMM_WORLD, MPI.COMM_SELF):
        sol = analyse(scene, comm)
        grids.append(gather_grid({"u": sol.u, "s": sol.sigma_zz}))

    def cell_table(grid, name):
        centres = grid.cell_centers().points[:, :2]
        values = np.asarray(grid.point_data_to_cell_data().cell_data[name])
        order = np.lexsort((np.round(centres[:, 1], 9), np.round(centres[:, 0], 9)))
        return centres[order], values[order]

    if MPI.COMM_WORLD.rank == 0:
        parallel, serial = grids
        assert parallel.n_cells == serial.n_cells
        for name in ("u", "s"):
            xp, vp = cell_table(parallel, name)
            xs, vs = cell_table(serial, name)
            np.testing.assert_allclose(xp, xs, rtol=1e-12, atol=1e-9)
            np.testing.assert_allclose(vp, vs, rtol=1e-7, atol=1e-7 * np.abs(vs).max())


@needs_two_ranks
def test_iterative_solver_parallel_equals_serial():
    """CG + GAMG: the multigrid hierarchy depends on the partition, the solution (to the
    solver's 1e-10) does not."""
    scene = flexible_scene(solver={"method": "iterative"})
    parallel, serial = _solve_both(scene)
    _assert_same_numbers(parallel, serial)


@needs_two_ranks
def test_structure_condensed_iterative_through_picard_parallel_equals_serial():
    """GMRES with the structure condensed and GAMG on the soil's Schur complement, through a
    hyperbolic soil's Picard iteration (GAMG keeps its interpolation between solves): the
    same solves and, to the solver's tolerance, the same numbers on 1 and 2 ranks."""
    data = small_tank(soil=HYPERBOLIC_SOIL, load=WATER_LOAD, solver={"method": "iterative"})
    parallel, serial = _solve_both(Scene.from_dict(data))
    assert parallel["linear_solves"] == serial["linear_solves"] >= 3
    for key in ("w0", "wd", "M0"):
        assert parallel[key] == pytest.approx(serial[key], rel=1e-6), key


@needs_two_ranks
def test_load_stages_sharing_one_factorisation_parallel_equals_serial():
    """Load stages of a bonded tank reuse the first stage's factorisation on 2 ranks too."""
    from tankfx.analysis import analyse_path
    from tankfx.fem.solvers import KEPT_ASSEMBLY

    scene = Scene.from_dict(small_tank())
    loads = [{"pressure": 50e3}, {"pressure": 20e3, "liquid_unit_weight": 9810.0,
                                  "liquid_height": 2.5}]
    parallel = analyse_path(scene, loads, MPI.COMM_WORLD)[-1].results
    serial = analyse_path(scene, loads, MPI.COMM_SELF)[-1].results
    assert parallel["linear_solver"]["assembly"] == KEPT_ASSEMBLY
    _assert_same_numbers(parallel, serial)


def _hydrotest(soil, interface):
    """The 1 m tank with its concrete's weight filled, emptied and filled again."""
    d = small_tank(soil=soil | {"unloading_modulus_ratio": 3.0}, interface=interface,
                   load=WATER_LOAD | {"self_weight": True})
    d["plate"]["unit_weight"] = d["wall"]["unit_weight"] = 24e3
    return d | {"stages": [{}, {"pressure": 0.0, "liquid_height": 0.0}, {}]}


@needs_two_ranks
@pytest.mark.parametrize("data, rtol", [
    # (the emptied tank's wd, 1.4e-5 m, is a difference of settlements of 1.5e-2 m: its
    # round-off, 6e-13 m, is 4e-8 of itself)
    pytest.param(_hydrotest(HYPERBOLIC_SOIL, {"condition": "mohr_coulomb", "tan_phi": 0.5}),
                 1e-7, marks=pytest.mark.verify),
    # (the round-off of the two runs, through the iteration's bisections for every cell's
    # confinement and its Anderson steps: 2-3e-8 in a tank's plate rotations, 2.3e-7 at
    # one node of the ground's surface)
    ({"soil": {"model": "duncan_chang", "nu": 0.3, "modulus_number": 400.0,
               "modulus_exponent": 0.5, "cohesion": 5e3, "friction_angle": 35.0,
               "unit_weight": 18e3, "unloading_modulus_ratio": 3.0},
      "load": {"pressure": 30e3, "load_radius": 1.0}, "mesh": COARSE,
      "stages": [{}, {"pressure": 10e3}, {}]}, 1e-6)],
    ids=["kondner_tank", "duncan_chang_load"])
def test_unloading_memory_parallel_equals_serial(data, rtol):
    """A nonlinear soil with an unloading modulus (Kondner's under a Mohr-Coulomb
    interface, the tank filled, emptied and filled again; Duncan & Chang's, mixed, its E_ur
    following the confinement, under a flexible load taken down and up again): each
    cell's most loaded state (kept on ghost cells too) gives the same path on 2 ranks as
    serially, stage by stage."""
    from tankfx.analysis import analyse_path

    scene = Scene.from_dict(data)
    parallel = analyse_path(scene, list(scene.stages), MPI.COMM_WORLD)
    serial = analyse_path(scene, list(scene.stages), MPI.COMM_SELF)
    for p, s in zip(parallel, serial):
        assert p.results["soil"]["unloading_cells"] == s.results["soil"]["unloading_cells"]
        assert p.results["soil"]["iterations"] == s.results["soil"]["iterations"]
        _assert_same_numbers(p.results, s.results, rtol=rtol)
    assert serial[1].results["soil"]["unloading_cells"] > 0


@needs_two_ranks
@pytest.mark.parametrize("condition", ["bonded", "mohr_coulomb"])
def test_overturning_parallel_equals_serial(condition):
    """The first harmonic (overturning moment and shear) of the embedded tank: every
    profile and summary number the same on 2 ranks as serially."""
    ifc = {"condition": condition, **({"tan_phi": 0.5} if condition != "bonded" else {})}
    scene = Scene.from_dict(small_tank(interface=ifc) | {"load": {
        "pressure": 50e3, "overturning_moment": 3e4, "base_shear": 1e4}})
    parallel, serial = _solve_both(scene)
    _assert_same_numbers(parallel, serial)
    p, s = parallel["overturning"], serial["overturning"]
    for key in ("tilt", "rocking_stiffness"):
        assert p[key] == pytest.approx(s[key], rel=1e-8), key
    for key in ("N_z_toe", "N_z_heel"):
        assert p["wall_foot"][key] == pytest.approx(s["wall_foot"][key], rel=1e-7), key
    for key, value in s["junction"].items():
        assert p["junction"][key] == pytest.approx(value, rel=1e-7), key
    for member in ("plate", "wall", "soil_line"):
        for key, values in s["profiles"][member].items():
            scale = np.max(np.abs(values)) + 1e-300
            np.testing.assert_allclose(p["profiles"][member][key], values, rtol=1e-7,
                                       atol=1e-7 * scale, err_msg=f"{member}.{key}")


@pytest.mark.verify
@needs_two_ranks
def test_consolidation_parallel_equals_serial():
    """Biot's consolidation of the embedded tank under a Mohr-Coulomb interface, loaded
    over half a day and held: its whole history (the drained limit, the undrained start,
    every step) and the last state's profiles the same on 2 ranks as serially."""
    scene = Scene.from_dict(small_tank(
        interface={"condition": "mohr_coulomb", "tan_phi": 0.5},
        consolidation={"permeability": 1e-9, "times": [86400.0, 8640000.0],
                       "steps_per_decade": 4},
        stages=[{"time": 43200.0}]))
    parallel, serial = _solve_both(scene)
    _assert_same_numbers(parallel, serial)
    p, s = parallel["consolidation"], serial["consolidation"]
    assert len(p["history"]) == len(s["history"])
    for key in ("w0", "wd", "M0", "max_pore_pressure", "degree"):
        np.testing.assert_allclose([x[key] for x in p["history"]],
                                   [x[key] for x in s["history"]], rtol=1e-7, err_msg=key)
        assert p["drained"][key] == pytest.approx(s["drained"][key], rel=1e-7), key



@needs_two_ranks
def test_bare_soil_consolidation_parallel_equals_serial():
    """A flexible load on consolidating soil (no structure: the soil's own split of the
    matrix, its flow terms re-assembled at each step): the history the same on 2 ranks."""
    from tankfx.fem.solvers import SPLIT_ASSEMBLY

    scene = flexible_scene(consolidation={"permeability": 1e-9, "times": [86400.0, 8640000.0],
                                          "steps_per_decade": 2}).with_coarse_mesh()
    parallel, serial = _solve_both(scene)
    assert parallel["linear_solver"]["assembly"] == SPLIT_ASSEMBLY
    _assert_same_numbers(parallel, serial)
    p, s = parallel["consolidation"], serial["consolidation"]
    assert len(p["history"]) == len(s["history"]) > 3
    for key in ("w0", "wd", "max_pore_pressure", "axis_pore_pressure"):
        np.testing.assert_allclose([x[key] for x in p["history"]],
                                   [x[key] for x in s["history"]], rtol=1e-7, err_msg=key)


@pytest.mark.verify
@needs_two_ranks
def test_an_interface_restarted_from_stuck_states_parallel_equals_serial():
    """The small tank's consolidation emptied to 5 % of its load with a slipping interface
    (test_consolidation): the steps whose Mohr-Coulomb iteration starts again from stuck
    states do so on every rank together (the choice is collective), and the history is the
    serial one."""
    day = 86400.0
    scene = Scene.from_dict(small_tank(
        interface={"condition": "mohr_coulomb", "tan_phi": 0.5},
        consolidation={"permeability": 1e-9, "steps_per_decade": 2,
                       "times": [d * day for d in (10, 30, 100)]},
        stages=[{"pressure": 50e3, "time": 0.0}, {"pressure": 50e3, "time": 10 * day},
                {"pressure": 2.5e3, "time": 30 * day}]))
    parallel, serial = _solve_both(scene)
    assert parallel["interface"]["restarts_from_stuck"] == \
        serial["interface"]["restarts_from_stuck"] >= 1
    _assert_same_numbers(parallel, serial, rtol=1e-6)
    p, s = parallel["consolidation"], serial["consolidation"]
    for key in ("w0", "M0"):
        np.testing.assert_allclose([x[key] for x in p["history"]],
                                   [x[key] for x in s["history"]], rtol=1e-6, err_msg=key)

@needs_two_ranks
def test_consolidation_around_a_ringwall_and_its_fill_parallel_equals_serial():
    """Consolidation with a ringwall and a draining fill (Nitsche's terms on interior
    facets, which a partition may cut) and an undrained overturning moment: the same on 2
    ranks as serially."""
    tank = small_tank(ringwall={"inner_radius": 0.8, "outer_radius": 1.1, "depth": 0.4,
                                "E": 30e9, "nu": 0.2, "fill_E": 50e6, "fill_nu": 0.3},
                      consolidation={"permeability": 1e-9, "times": [86400.0],
                                     "steps_per_decade": 2},
                      load={"pressure": 50e3, "overturning_moment": 1e4})
    tank["plate"] = {"radius": 1.0, "thickness": 0.2, "E": 30e9, "nu": 0.2}
    tank["wall"] = {"radius": 1.0, "thickness": 0.1, "height": 3.0, "E": 30e9, "nu": 0.2}
    parallel, serial = _solve_both(Scene.from_dict(tank))
    _assert_same_numbers(parallel, serial)
    for key in ("w0", "M0", "axis_pore_pressure"):
        assert parallel["consolidation"]["undrained"][key] == pytest.approx(
            serial["consolidation"]["undrained"][key], rel=1e-7), key
    assert parallel["overturning"]["tilt"] == pytest.approx(serial["overturning"]["tilt"],
                                                            rel=1e-7)


@needs_two_ranks
def test_failed_unscaled_factorisation_redone_scaled_parallel_equals_serial():
    """An unscaled factorisation that fails (tankfx.fem.solvers) is redone scaled on all ranks
    together: the same solves and numbers as serially."""
    from tankfx.fem.solvers import RESCALED

    parallel, serial = _solve_both(Scene.from_dict(incompressible_hyperbolic_punch()))
    assert parallel["linear_solver"]["scaling"] == serial["linear_solver"]["scaling"] \
        == RESCALED
    assert parallel["linear_solves"] == serial["linear_solves"]
    _assert_same_numbers(parallel, serial)


def test_a_figure_rank_0_cannot_render_leaves_the_others(tmp_path_factory, monkeypatch):
    """Rank 0's renderer fails on the first figure (as on a machine without EGL): a warning
    names it, the other figures are drawn, and no rank is left waiting in a gathering."""
    from tankfx.results import figures as plots

    comm = MPI.COMM_WORLD
    out = comm.bcast(tmp_path_factory.mktemp("figures") if comm.rank == 0 else None)
    solution = analyse(Scene.from_dict(small_tank(soil=HYPERBOLIC_SOIL)), comm)
    save, calls = plots.save_figure, []

    def failing_once(plotter, path, *args, **kwargs):
        calls.append(path)
        if len(calls) == 1:
            plotter.close()
            raise RuntimeError("no rendering context")
        return save(plotter, path, *args, **kwargs)

    monkeypatch.setattr(plots, "save_figure", failing_once)
    monkeypatch.delenv(plots.STRICT_FIGURES)
    warned = []
    handler = logging.Handler(logging.WARNING)
    handler.emit = lambda record: warned.append(record.getMessage())
    logging.getLogger("tankfx").addHandler(handler)     # whatever the logger's propagation
    try:
        written = plots.write_figures(solution, out)
    finally:
        logging.getLogger("tankfx").removeHandler(handler)
    comm.barrier()              # every rank got here: no gathering was left open
    if comm.rank == 0:
        assert [p.name for p in written] == ["stress_level.png", "settlement.png", "moments.png",
                                             "profiles.png", "contact.png"]
        assert any("section.png not written (RuntimeError: no rendering context)" in w
                   for w in warned)
    else:
        assert written == []
