"""The elastoplastic Mohr-Coulomb / Tresca soil (soil.model = "mohr_coulomb") in the block
system: its scene refused where it cannot be solved, the ground at rest, the linear soil's
numbers below yield, and the bearing capacity of a rigid circular footing against the exact
values."""
from __future__ import annotations

import numpy as np
import pytest
from mpi4py import MPI

from conftest import COARSE
from tankfx import Scene, SceneError, analyse
from tankfx.results.contract import settlement_kept
from tankfx.results.report import summary_table

C_U = 10e3      # Pa: Tresca's undrained strength of the footing tests


def plastic_scene(soil=None, **sections) -> dict:
    """A rigid 1 m footing (Kp = 1000) on a weightless Tresca soil, s_u = 10 kPa."""
    d = {"soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": C_U},
         "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2},
         "interface": {"condition": "smooth"}, "load": {"pressure": 20e3},
         "mesh": COARSE}
    d["soil"].update(soil or {})
    for k, v in sections.items():
        d[k] = v
    return d


@pytest.mark.parametrize("soil,sections,says", [
    ({"cohesion": 0.0}, {}, "soil.cohesion, soil.friction_angle: the soil has no strength"),
    ({"friction_angle": 20.0, "dilation_angle": 25.0}, {},
     "soil.dilation_angle = 25.0 exceeds soil.friction_angle = 20.0"),
    ({"friction_angle": 60.0}, {}, "soil.friction_angle = 60.0: at most 60"),
    ({"tensile_strength": -1.0}, {}, "soil.tensile_strength"),
    ({"nu": 0.495}, {}, "soil.nu = 0.495: at most 0.49"),
    ({"unit_weight": 18e3, "K0": 3.0}, {},
     "soil: the ground at rest lies outside the yield surface"),
    ({"unit_weight": 18e3, "water_table": 0.2},
     {"plate": {"radius": 1.0, "Kp": 10.0, "E": 30e9, "nu": 0.2, "embedment": 0.5}},
     "soil.water_table = 0.2 is above the pit's bottom (plate.embedment = 0.5)"),
    ({}, {"load": {"pressure": 20e3, "overturning_moment": 1e4}},
     "load.overturning_moment, load.base_shear"),
    ({}, {"mesh": {**COARSE, "degree": 1}}, "mesh.degree = 1: linear triangles lock"),
    ({}, {"stages": [{"pressure": 0.0}]}, "stages: no stage applies any load"),
])
def test_what_the_plastic_soil_cannot_take_is_refused_before_any_mesh(soil, sections, says):
    with pytest.raises(SceneError) as e:
        Scene.from_dict(plastic_scene(soil, **sections))
    assert says in str(e.value), str(e.value)


def test_a_normally_consolidated_clay_starts_inside_its_yield_surface():
    """s_u = 5 kPa + 1.5 kPa/m, gamma' = 7 kN/m^3 (a water table at the surface) and K0 =
    0.6: the deviator at rest, 0.4 x 7 z / 2 = 1.4 z kPa, stays below 5 + 1.5 z: taken; a
    K0 of 0.2 (2.8 z > 5 + 1.5 z below 3.8 m) is refused with its depth."""
    clay = {"cohesion": 5e3, "cohesion_gradient": 1.5e3, "unit_weight": 16.81e3,
            "water_table": 0.0, "K0": 0.6}
    Scene.from_dict(plastic_scene(clay))
    with pytest.raises(SceneError) as e:
        Scene.from_dict(plastic_scene(clay | {"K0": 0.2}))
    assert "outside the yield surface from 3.8" in str(e.value), str(e.value)


class _Quiet:
    def info(self, *args):
        pass

    debug = warning = info


def _model(data):
    """A built model of a scene dict, its solver and its chain of iterations."""
    from tankfx.fem.solvers import make_solver
    from tankfx.iterations.stage import StageIterations
    from tankfx.mesh import build_domain
    from tankfx.model.build import build_model

    scene = Scene.from_dict(data)
    model = build_model(scene, build_domain(scene))
    solver = make_solver(scene.solver, model.a, model.L, model.bcs, model.unknowns,
                         entity_maps=model.entity_maps, name="plastic", symmetric=True)
    return scene, model, StageIterations.of(scene, model, solver)


def test_the_ground_at_rest_stays_at_rest():
    """A heavy layered clay with a water table, at rest (nothing on the footing): the
    displacement stays zero, the stress is the geostatic one exactly at every point, and the
    out-of-balance force vanishes."""
    from dataclasses import fields, replace

    clay = {"cohesion": 5e3, "cohesion_gradient": 1.5e3, "unit_weight": 17e3,
            "water_table": 1.5, "K0": 0.7}
    data = plastic_scene(clay, domain={"radius": 5.0, "depth": 5.0})
    data["soil"]["layers"] = [{"depth": 2.0, "E": 20e6, "nu": 0.3, "cohesion": 12e3,
                               "unit_weight": 19e3, "K0": 0.8}]
    scene, model, chain = _model(data)
    nothing = replace(scene.load, **{f.name: 0.0 for f in fields(scene.load)
                                     if isinstance(getattr(scene.load, f.name), float)
                                     and f.name != "load_radius"})
    model.set_loads(nothing)
    model.begin_stage()
    chain.begin_stage()
    chain.run(_Quiet())
    p = model.soil.plastic
    u = np.concatenate([f.x.array for f in model.unknowns])
    assert np.abs(u).max() < 1e-12
    # (the points hold the stress's change from the ground at rest: none)
    assert np.abs(p.stress.x.array).max() < 1e-6
    assert model.out_of_balance() < 1e-12
    # the weight is there: 17 kN/m^3 x 1.5 m + (17 - 9.81) x 0.5 m above the layer
    sz = p.cell_average(p.stress, 4)[:, 1] + p.cell_average(p.geostatic, 4)[:, 1]
    assert -sz.min() > 17e3 * 1.5 + 7.19e3 * 0.5


def test_below_yield_the_plastic_soil_is_the_linear_one():
    """A strength far above the load's stresses: every number the linear soil gives, to
    1e-8 of its scale."""
    data = plastic_scene({"cohesion": 9e5})
    linear = plastic_scene()
    linear["soil"] = {"E": 10e6, "nu": 0.3}
    a, b = analyse(Scene.from_dict(data)).results, analyse(Scene.from_dict(linear)).results
    assert a["soil"]["plastic_points"] == 0
    for key in ("w0", "w_edge", "wd"):
        assert a[key] == pytest.approx(b[key], rel=1e-8), key
    np.testing.assert_allclose(a["profiles"]["surface"]["w"], b["profiles"]["surface"]["w"],
                               rtol=0, atol=1e-8 * abs(b["w0"]))


def test_a_hydrotest_on_plastic_clay_keeps_a_permanent_settlement():
    """A flexible tank floor (4 s_u on a 1 m circle) on Tresca clay, filled and emptied:
    the ground keeps a permanent settlement (more than a tenth of the elastic one), and the
    unloading is elastic: the settlement given back is the linear soil's under the load taken
    off, to 1e-6 at the centre and 1e-4 of it along the surface (measured: 1.1e-7 and 2e-5,
    the latter beside the load's edge, where 3 points yield again on the way back; at 3 s_u
    none do, and the centre's agrees to 8e-15). (Under a rigid footing the unloading is not elastic at its edge,
    where the elastic stress is singular: 39 points yield again when a quarter of 0.8 N_c
    comes off.)"""
    q = 4.0 * C_U
    flexible = {"soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": C_U},
                "load": {"pressure": q, "load_radius": 1.0}, "mesh": COARSE,
                "stages": [{}, {"pressure": 0.0}]}
    full, empty = (s.results for s in analyse_path_of(flexible))
    assert full["soil"]["plastic_points"] > 1000
    assert empty["soil"]["plastic_points"] < 0.01 * full["soil"]["plastic_points"]
    linear = {"soil": {"E": 10e6, "nu": 0.3}, "load": {"pressure": q, "load_radius": 1.0},
              "mesh": COARSE}
    elastic = analyse(Scene.from_dict(linear)).results
    assert full["w0"] - empty["w0"] == pytest.approx(elastic["w0"], rel=1e-6)
    np.testing.assert_allclose(
        np.array(full["profiles"]["surface"]["w"]) - empty["profiles"]["surface"]["w"],
        elastic["profiles"]["surface"]["w"], rtol=0, atol=1e-4 * elastic["w0"])
    assert empty["w0"] > 0.1 * elastic["w0"]
    # the path names it: the settlement kept, back at no load
    kept = empty["stages"][1]["settlement_kept"]
    assert kept["since"] == 0 and kept["w0"] == empty["w0"]
    assert "settlement_kept" not in empty["stages"][0]
    assert "stage 2: settlement kept" in summary_table(empty)


def test_the_settlement_kept_is_measured_from_the_same_load():
    """Back at an earlier stage's load, the settlement kept is counted from that stage (a
    tank's own weight, filled, emptied: from the first); back at no load, from the start;
    a stage loaded more than before keeps nothing to report."""
    def stage(k, load, P, w0):
        return {"stage": k, "load": load, "applied_load": P, "w0": w0, "w_mean": 0.5 * w0}

    own, full = {"liquid_height": 0.0}, {"liquid_height": 10.0}
    path = [stage(1, own, 1.0, 0.01), stage(2, full, 5.0, 0.10), stage(3, own, 1.0, 0.04),
            stage(4, {"pressure": 0.0}, 0.0, 0.03)]
    settlement_kept(path)
    assert "settlement_kept" not in path[0] and "settlement_kept" not in path[1]
    assert path[2]["settlement_kept"] == pytest.approx({"since": 1, "w0": 0.03,
                                                        "w_mean": 0.015})
    assert path[3]["settlement_kept"] == {"since": 0, "w0": 0.03, "w_mean": 0.015}


def analyse_path_of(data):
    from tankfx import analyse_path

    scene = Scene.from_dict(data)
    return analyse_path(scene, list(scene.stages))


@pytest.mark.mpi
@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="needs mpiexec -n 2 (make test-mpi)")
def test_serial_and_two_ranks_give_the_same_plastic_footing():
    """The footing at 90 % of its capacity, plastic under its edge: the same numbers on
    one rank and on all."""
    from tankfx.results.fields import soil_cell_fields
    from tankfx.results.figures import gather_grid

    scene = Scene.from_dict(plastic_scene(load={"pressure": 0.9 * 5.69 * C_U}))
    solution = analyse(scene, MPI.COMM_WORLD)
    parallel = solution.results
    serial = analyse(scene, MPI.COMM_SELF).results
    assert parallel["dofs"] == serial["dofs"]
    assert parallel["soil"]["plastic_points"] == serial["soil"]["plastic_points"] > 0
    for key in ("w0", "w_edge", "wd"):
        assert parallel[key] == pytest.approx(serial[key], rel=1e-8), key
    # the section figure's yielding cells, gathered from every rank: each cell once
    plastic = soil_cell_fields(solution.model, solution.statuses)["plastic"]
    owned = solution.domain.mesh.topology.index_map(2).size_local
    yielding = MPI.COMM_WORLD.allreduce(int(np.sum(plastic.x.array[
        plastic.function_space.dofmap.list[:owned, 0]] > 0.0)))
    grid = gather_grid({"u": solution.u}, cell_fields={"marked": plastic})
    if MPI.COMM_WORLD.rank == 0:
        assert 0 < int(np.sum(grid.cell_data["marked"] > 0.0)) == yielding


def test_a_mohr_coulomb_interface_in_the_newton_iteration():
    """The interface's active set converges inside every Newton iteration of the plastic
    soil: frictionless it is the smooth interface, with tan phi = 10 (no element slips) the
    bonded one, to the tolerances, yielding points and all; a friction between lies between
    them (a footing at 3 s_u, half its capacity)."""
    def w0(interface):
        r = analyse(Scene.from_dict(plastic_scene(load={"pressure": 3.0 * C_U},
                                                  interface=interface))).results
        return r["w0"], r["soil"]["plastic_points"]

    smooth, bonded = w0({"condition": "smooth"}), w0({"condition": "bonded"})
    frictionless = w0({"condition": "mohr_coulomb", "tan_phi": 0.0})
    rough = w0({"condition": "mohr_coulomb", "tan_phi": 10.0})
    assert frictionless[0] == pytest.approx(smooth[0], rel=1e-9)
    assert rough[0] == pytest.approx(bonded[0], rel=1e-9)
    assert (frictionless[1], rough[1]) == (smooth[1], bonded[1])
    between = w0({"condition": "mohr_coulomb", "tan_phi": 0.1})[0]
    assert bonded[0] * (1 + 1e-4) < between < smooth[0] * (1 - 1e-4)


# (quadratic elements, smooth and rough, through the scene's collapse search:
# tests/test_collapse.py; here quartic ones under the settlement control to 0.1 a)
@pytest.mark.verify
@pytest.mark.parametrize("condition,exact,mesh", [("smooth", 5.69, (4, 0.04, 0.4))])
def test_a_rigid_footing_on_tresca_soil_collapses_at_its_exact_bearing_capacity(condition,
                                                                                exact, mesh):
    """N_c = q_ult / s_u of a rigid circular footing on weightless Tresca soil: 5.69 smooth
    (Shield 1955), 6.05 rough (Eason & Shield 1960). Followed by settlement control to w0 =
    0.1 a, the load reaches its plateau (it rises by less than 0.1 % from 0.075 a) at N_c
    within 1 % (measured, quadratic elements, 7.2k unknowns: +0.82 % smooth, +0.83 % rough;
    quartic, 8.1k: +0.56 % smooth; the finite element limit lies above the exact one, as it
    must).
    benchmarks/bearing_capacity.py tabulates degrees and meshes."""
    from tankfx.verification.footing import collapse_curve, footing_scene

    curve = collapse_curve(footing_scene(condition, *mesh), comm=MPI.COMM_SELF)
    N, w = np.array(curve["factor"]), np.array(curve["w0"])
    assert np.all(np.diff(N) > -1e-9 * N[-1]), "the load falls: not perfect plasticity"
    plateau = N[-1]
    assert plateau - N[w >= 0.075 - 1e-9][0] < 1e-3 * plateau
    assert plateau == pytest.approx(exact, rel=0.01)
    assert plateau > exact


def test_a_thick_cylinder_yields_as_hills_closed_form():
    """A thick cylinder (a = 1 m, b = 2 m, plane strain) of Tresca soil under internal
    pressure: at Hill's pressure for a plastic radius rho, p = k (1 - rho^2 / b^2 +
    2 ln(rho / a)), the yielding points reach rho to within one cell (1/80 m), from rho =
    1.1 to 1.9 m; Newton takes at most 6 iterations a load (quadratic convergence); the
    cylinder carries 99.9 % of the fully plastic 2 k ln(b / a) and not 101 % of it."""
    from tankfx.verification.cylinder import ThickCylinder
    from tankfx.verification.reference import thick_cylinder_tresca_pressure as hill

    k, a, b = 10e3, 1.0, 2.0
    soil = Scene.from_dict({"soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3,
                                     "cohesion": k},
                            "load": {"pressure": 1e3, "load_radius": 1.0}}).soil
    cyl = ThickCylinder(soil, a, b, cells=(80, 2), degree=2, comm=MPI.COMM_SELF)
    for rho in np.linspace(1.1, 1.9, 5):
        iterations = cyl.load(hill(rho, a, b, k))
        assert iterations <= 6
        assert rho - 1.0 / 80 < cyl.plastic_radius() <= rho + 1e-9, rho
    limit = 2.0 * k * np.log(b / a)
    cyl.load(0.999 * limit)
    assert cyl.plastic_radius() > 1.9
    # (beyond it no equilibrium: Newton does not converge, or its tangent is singular)
    with pytest.raises(RuntimeError, match="did not converge|the linear solve"):
        cyl.load(1.01 * limit)


def test_a_steel_tank_on_heavy_soft_clay_in_the_default_half_space():
    """A 20 m steel tank on Tresca clay (s_u = 20 kPa + 1.5 kPa/m, 17 kN/m^3, a water table
    1 m down, K0 = 0.7) filled with 10 m of water and emptied, in the default domain of 10^4
    radii: the ground at rest there reaches gigapascals, and held as totals its round-off
    stalled Newton at an out-of-balance force of 4e-4 past a quarter of the fill; held as
    changes from it the fill converges in 3 steps. The emptied tank keeps a permanent
    settlement; equilibrium holds."""
    from tankfx import analyse_path

    data = {"title": "tank on soft clay",
            "soil": {"model": "mohr_coulomb", "E": 5e6, "nu": 0.45, "cohesion": 20e3,
                     "cohesion_gradient": 1.5e3, "unit_weight": 17e3, "water_table": 1.0,
                     "K0": 0.7},
            "plate": {"radius": 10.0, "thickness": 0.012, "E": 200e9, "nu": 0.3},
            "wall": {"radius": 10.0, "height": 12.0, "thickness": 0.015, "E": 200e9,
                     "nu": 0.3},
            "interface": {"condition": "bonded"},
            "load": {"liquid_unit_weight": 9810.0, "liquid_height": 10.0},
            "stages": [{}, {"liquid_height": 0.0}]}
    scene = Scene.from_dict(data).with_coarse_mesh()
    assert scene.domain.depth > 1e4
    full, empty = (s.results for s in analyse_path(scene, list(scene.stages)))
    assert full["soil"]["plastic_points"] > 1000 and full["soil"]["steps"] <= 4
    assert 0.0 < empty["w0"] < 0.5 * full["w0"]
    assert full["equilibrium"]["relative_error"] < 1e-8


def embedded_tank(soil, wall: bool = True, depth: float = 2.0) -> dict:
    """A 10 m concrete tank (or plate alone) ``depth`` m deep in clay of 18 kN/m^3,
    filled with 9 m of water (a plate alone: 90 kPa), on a coarse mesh."""
    d = {"soil": {"E": 10e6, "nu": 0.3, **soil},
         "plate": {"radius": 10.0, "Kp": 1.0, "E": 30e9, "nu": 0.2, "embedment": depth},
         "interface": {"condition": "bonded"},
         "mesh": {"edge_size": 0.2, "near_size": 2.0, "growth": 0.3},
         "domain": {"radius": 60.0, "depth": 40.0}}
    if wall:
        d["wall"] = {"radius": 10.0, "Kt": 0.1, "height": 10.0, "E": 30e9, "nu": 0.2}
        d["load"] = {"liquid_unit_weight": 9810.0, "liquid_height": 9.0}
    else:
        d["load"] = {"pressure": 90e3}
    return d


@pytest.mark.parametrize("wall", [True, False])
def test_an_embedded_foundations_pit_is_dug_before_it_is_built(wall):
    """The pit of an embedded foundation is excavated first (its faces relieved of the
    stress at rest), then the structure is built on it free of strain. The supports lose
    exactly the weight taken out, sigma'_v(D) pi a^2 (the pit under a wall, inside the tank's
    void: interior facets; a plate alone: the domain's boundary); in a ground that does not
    yield, the tank's settlement and moments are then the linear soil's, to the Newton
    tolerance, whatever the heave before it."""
    import ufl
    from dolfinx import fem

    gamma, depth, a = 18e3, 2.0, 10.0
    strong = {"model": "mohr_coulomb", "cohesion": 1e6, "unit_weight": gamma, "K0": 0.7}
    solution = analyse(Scene.from_dict(embedded_tank(strong, wall)))
    r, pit = solution.results, solution.model.soil.pit
    # the side's relief, summed radially: -int K0 gamma z 2 pi a dz = -K0 gamma D^2 pi a
    radial = fem.assemble_scalar(fem.form(pit.load(ufl.as_vector([1.0, 0.0]))))
    assert radial == pytest.approx(-0.7 * gamma * depth ** 2 * np.pi * a, rel=1e-9)
    ex = r["excavation"]
    released = gamma * depth * np.pi * a ** 2
    assert ex["released_load"] == pytest.approx(released, rel=1e-9)
    assert ex["reaction"] == pytest.approx(-released, rel=1e-8)
    assert ex["plastic_points"] == 0 and ex["heave"] > 0.0
    assert r["equilibrium"]["excavation_relief"] == pytest.approx(released, rel=1e-9)
    assert r["equilibrium"]["relative_error"] < 1e-8
    linear = analyse(Scene.from_dict(embedded_tank({}, wall))).results
    for key in ("w0", "w_edge", "M0"):
        # (measured: 4e-10 on M0, the structure's stand-by stiffness's doing)
        assert r[key] == pytest.approx(linear[key], rel=1e-7), key
    assert "excavation of the pit: heave" in summary_table(r)


@pytest.mark.verify
def test_a_pit_too_deep_for_its_clay_gives_way():
    """An unsupported 8 m pit in clay of s_u = 10 kPa: its sides are four times the height
    a vertical cut in it stands (3.85 s_u / gamma = 2.1 m), and its bottom is relieved of
    gamma D = 14 s_u, beyond the 6-9 s_u a circular pit's bottom holds (Bjerrum & Eide
    1956): the excavation fails (measured: at 0.35 of the relief, 5 s_u), said in physical
    terms, before anything is built."""
    from tankfx import SoilFailure

    soft = {"model": "mohr_coulomb", "cohesion": 10e3, "unit_weight": 18e3, "K0": 1.0,
            "max_iterations": 10}
    with pytest.raises(SoilFailure) as e:
        analyse(Scene.from_dict(embedded_tank(soft, wall=False, depth=8.0)))
    assert "the pit cannot be excavated" in str(e.value)
    assert "sigma'_v = 144 kPa at its bottom, 8 m deep" in str(e.value)


@pytest.mark.mpi
@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="needs mpiexec -n 2 (make test-mpi)")
def test_serial_and_two_ranks_dig_the_same_pit():
    """A pit dug in clay that yields around it (s_u = 40 kPa + 2 kPa/m), then the tank
    filled: the same heave, yielding points and settlement on one rank and on all (the
    pit's faces are interior facets beside the tank's void, split between the ranks)."""
    clay = {"model": "mohr_coulomb", "cohesion": 40e3, "cohesion_gradient": 2e3,
            "unit_weight": 18e3, "K0": 0.7}
    scene = Scene.from_dict(embedded_tank(clay))
    parallel = analyse(scene, MPI.COMM_WORLD).results
    serial = analyse(scene, MPI.COMM_SELF).results
    assert parallel["excavation"]["plastic_points"] == serial["excavation"]["plastic_points"] > 0
    assert parallel["excavation"]["heave"] == pytest.approx(serial["excavation"]["heave"],
                                                            rel=1e-8)
    assert parallel["soil"]["plastic_points"] == serial["soil"]["plastic_points"]
    for key in ("w0", "w_edge", "M0"):
        assert parallel[key] == pytest.approx(serial[key], rel=1e-7), key
