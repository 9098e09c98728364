"""Biot's consolidation of an elastoplastic skeleton (tankfx.iterations.plastic_consolidation):
the Mohr-Coulomb soil with a [consolidation] is an effective-stress soil, each time step
solved by Newton on the skeleton's points and the pore pressure."""
import numpy as np
import pytest
from mpi4py import MPI

from tankfx import Scene, SceneError, SoilFailure, analyse
from tankfx.results.report import summary_table

DAY = 86400.0
#: a 5 m flexible plate on a weightless drained skeleton (E, nu), consolidating
SCENE = {"soil": {"E": 5e6, "nu": 0.3}, "plate": {"radius": 5.0, "Kp": 1.0, "E": 30e9,
                                                  "nu": 0.2},
         "load": {"pressure": 50e3},
         "consolidation": {"permeability": 1e-8, "times": [DAY, 10 * DAY]},
         "mesh": {"edge_size": 0.5, "near_size": 2.0}}


FAR_FROM_YIELD = SCENE | {"soil": {"model": "mohr_coulomb", "E": 5e6, "nu": 0.3,
                                   "cohesion": 1e9},
                          "accept": ["soil.cohesion"]}


def test_below_yield_the_plastic_skeleton_consolidates_as_the_linear_one():
    """A Mohr-Coulomb skeleton far from yield (c' = 1 GPa) is the linear skeleton: its
    undrained start, its states at every reported time (settlements, the excess pore
    pressure on the axis and its largest, the isochrones) and its drained limit are the
    linear consolidation's to 1e-8 of each quantity (measured: 1e-12), whether each step is
    one linear solve or Newton's, on the same steps (the linear skeleton's grid; the
    elastoplastic one's steps are chosen by their local error, see
    test_the_yielding_layers_path_is_converged_in_time_at_the_default_tolerance); and the
    run says the yielding path is not yet verified."""
    linear = analyse(Scene.from_dict(SCENE).with_coarse_mesh()).results
    # (on the grid's steps alone, as the linear skeleton's: a tolerance of the whole
    # settlement never shortens one)
    plastic = analyse(Scene.from_dict(FAR_FROM_YIELD | {"consolidation": SCENE[
        "consolidation"] | {"time_tolerance": 1.0}}).with_coarse_mesh()).results
    a, b = linear["consolidation"], plastic["consolidation"]
    assert len(a["at_times"]) == len(b["at_times"]) == 3
    for one, two in zip([a["drained"], *a["at_times"]], [b["drained"], *b["at_times"]]):
        for key in ("w0", "w_edge", "wd", "M0"):
            assert two[key] == pytest.approx(one[key], rel=1e-8, abs=1e-12), key
        for key in ("axis_pore_pressure", "max_pore_pressure"):
            assert two[key] == pytest.approx(one[key], rel=1e-8), key
    scale = max(abs(p) for iso in a["isochrones"]["pore_pressure"] for p in iso)
    for one, two in zip(a["isochrones"]["pore_pressure"], b["isochrones"]["pore_pressure"]):
        assert max(abs(x - y) for x, y in zip(one, two)) <= 1e-8 * scale
    assert plastic["soil"]["model"] == "mohr_coulomb" and plastic["soil"]["iterations"] > 0
    assert plastic["soil"]["plastic_points"] == 0
    assert any("not yet verified" in w for w in plastic["warnings"])
    assert not any("not yet verified" in w for w in linear["warnings"])


@pytest.mark.mpi
@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="needs mpiexec -n 2 (make test-mpi)")
def test_serial_and_two_ranks_consolidate_the_same_plastic_skeleton():
    """The coupled Newton path (the skeleton's points beside the pore pressure, split over
    the ranks): every state of the history the same on one rank and on all, to 1e-8."""
    scene = Scene.from_dict(FAR_FROM_YIELD).with_coarse_mesh()
    parallel = analyse(scene, MPI.COMM_WORLD).results["consolidation"]
    serial = analyse(scene, MPI.COMM_SELF).results["consolidation"]
    assert len(parallel["history"]) == len(serial["history"]) > 10
    for p, s in zip([parallel["drained"], *parallel["history"]],
                    [serial["drained"], *serial["history"]]):
        for key in ("w0", "wd", "max_pore_pressure", "axis_pore_pressure"):
            assert p[key] == pytest.approx(s[key], rel=1e-8), key


S_U, Q = 10e3, 30e3


def _footing_in_time(mesh=(0.01, 0.25), **analysis) -> dict:
    """The rigid rough 1 m footing on weightless clay of c' = 10 kPa, phi' = 0, loaded at
    once with 30 kPa (half its bearing capacity) and held for ten days (a^2 / c_v = 0.08
    days: drained by then), its piezometers under the centre and the edge."""
    return {"soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": S_U},
            "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2},
            "interface": {"condition": "bonded"}, "load": {"pressure": Q},
            "mesh": {"edge_size": mesh[0], "near_size": mesh[1], "growth": 0.3},
            "domain": {"radius": 5.0, "depth": 5.0}, "analysis": analysis,
            "consolidation": {"permeability": 1e-7, "times": [10 * DAY],
                              "steps_per_decade": 2, "piezometers": [[0.0, 0.5], [1.0, 1.0]]},
            "stages": [{"time": 0.0}, {"time": 10 * DAY}]}


@pytest.mark.parametrize("mesh,within", [
    ((0.03, 0.5), 0.05), pytest.param((0.01, 0.25), 0.02, marks=pytest.mark.verify)])
def test_the_factor_of_safety_in_time_of_a_clay_without_friction(tmp_path, mesh, within):
    """phi' = 0: the strength does not depend on the effective stress, so the factor of
    safety on c' is the same loaded undrained (at once, t = 0) and drained (ten times
    the consolidation time later): F q / c' = N_c = 6.05 (Eason & Shield, rough), from
    above (displacement elements), within 5 % on a coarse mesh and 2 % on a finer one
    (make verify; measured 6.15: 1.6 % high, the settlement criterion's bracket). Each stage's record has its factor (``stages[k].collapse``) and its
    piezometers; the top-level collapse is the last stage's; the excess pore pressure
    under the centre is about half the load at once and gone ten days later. The figures:
    the history with the factor of safety, the excess pore pressure over the section at
    each reported time."""
    from tankfx.results.figures import write_figures

    solution = analyse(Scene.from_dict(_footing_in_time(mesh, collapse="strength")))
    r = solution.results
    written = {p.name for p in write_figures(solution, tmp_path)}
    if MPI.COMM_WORLD.rank == 0:
        assert {"consolidation.png", "pore_pressure_0.png", "pore_pressure_1.png",
                "mechanism.png"} <= written
    first, last = r["stages"]
    F0, F1 = first["collapse"]["strength_factor"], last["collapse"]["strength_factor"]
    assert first["collapse"]["found"] and last["collapse"]["found"]
    assert 6.05 < F0 * Q / S_U < (1.0 + within) * 6.05
    assert F1 == pytest.approx(F0, rel=first["collapse"]["bracket_width"])
    assert r["collapse"]["strength_factor"] == F1
    c = r["consolidation"]
    assert c["min_strength_factor"] == min(F0, F1)
    assert [s["t_days"] for s in r["stages"]] == [0.0, 10.0]
    assert 0.3 * Q < first["piezometers"][0] < Q
    assert max(abs(u) for u in last["piezometers"]) < 0.01 * Q
    history = c["piezometers"]
    assert history["points"] == [[0.0, 0.5], [1.0, 1.0]]
    assert len(history["excess_pore_pressure"]) == len(history["t_days"]) == len(c["history"])
    assert f"factor of safety {F1:.3g}" in summary_table(r)


@pytest.mark.parametrize("change,says", [
    ({"consolidation": {"permeability": 1e-7, "times": [DAY],
                        "piezometers": [[0.5, 0.5]]}, "plate": {"embedment": 1.0}},
     "piezometers[1] = [0.5, 0.5]: in the foundation's pit"),
    ({"consolidation": {"permeability": 1e-7, "times": [DAY], "piezometers": [[0, -1]]}},
     "above the ground surface"),
    ({"consolidation": {"permeability": 1e-7, "times": [DAY], "piezometers": [0, 1]}},
     "a list of points [r, depth]"),
    ({"analysis": {"collapse": "load"}}, "a consolidation's path takes collapse = \"strength\""),
])
def test_refused_in_time(change, says):
    data = _footing_in_time()
    for section, table in change.items():
        data[section] = {**data[section], **table}
    with pytest.raises(SceneError) as e:
        Scene.from_dict(data)
    assert says in str(e.value)


#: the 5 m plate under 60 kPa at once on a clay of c' = 20 kPa, phi' = 25 deg, its weight
#: and K0 = 0.6 below a water table at the surface: hundreds of points yield as it drains
YIELDING = SCENE | {"soil": {"model": "mohr_coulomb", "E": 5e6, "nu": 0.3, "cohesion": 20e3,
                             "friction_angle": 25.0, "unit_weight": 18e3, "water_table": 0.0,
                             "K0": 0.6},
                    "load": {"pressure": 60e3},
                    "consolidation": {"permeability": 1e-8, "times": [DAY],
                                      "steps_per_decade": 4}}


@pytest.mark.mpi
@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="needs mpiexec -n 2 (make test-mpi)")
def test_serial_and_two_ranks_consolidate_a_yielding_skeleton_alike():
    """Where the skeleton yields (Newton on the points of both ranks' cells, the plastic
    points counted over the ranks): the same history on one rank and on two, to 1e-6."""
    scene = Scene.from_dict(YIELDING).with_coarse_mesh()
    parallel = analyse(scene, MPI.COMM_WORLD).results
    serial = analyse(scene, MPI.COMM_SELF).results
    assert parallel["soil"]["plastic_points"] == serial["soil"]["plastic_points"]
    assert parallel["soil"]["max_plastic_shear_strain"] == pytest.approx(
        serial["soil"]["max_plastic_shear_strain"], rel=1e-6)
    assert serial["soil"]["max_plastic_shear_strain"] > 1e-3
    p, s = parallel["consolidation"], serial["consolidation"]
    assert len(p["history"]) == len(s["history"])
    for a, b in zip([p["drained"], *p["history"]], [s["drained"], *s["history"]]):
        for key in ("w0", "wd", "max_pore_pressure", "axis_pore_pressure"):
            assert a[key] == pytest.approx(b[key], rel=1e-6), key


def _ramp(T_days: float | None, collapse: str | None = None) -> Scene:
    """The rigid rough 1 m footing on weightless c' = 10 kPa, phi' = 20 deg (no dilation),
    E' = 10 MPa, a^2 / c_v = 1 day: its pressure raised linearly to 300 kPa over T days (or,
    None, the drained soil without a consolidation, under 100 kPa)."""
    data = {"soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": 10e3,
                     "friction_angle": 20.0},
            "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2},
            "interface": {"condition": "bonded"},
            "load": {"pressure": 300e3 if T_days else 100e3},
            "mesh": {"edge_size": 0.03, "near_size": 0.5, "growth": 0.3},
            "domain": {"radius": 5.0, "depth": 5.0}}
    if collapse:
        data["analysis"] = {"collapse": collapse}
    if T_days:
        data["consolidation"] = {"permeability": 8.43e-9, "times": [T_days * DAY]}
        data["stages"] = [{"time": T_days * DAY}]
    return Scene.from_dict(data)


@pytest.mark.verify
def test_the_rate_of_loading_orders_the_collapse_loads():
    """Small, Booker & Davis (1976): the faster a footing on a frictional clay is loaded,
    the less it carries. Its pressure raised to 300 kPa over 0.001, 1 and 1000 consolidation
    times a^2 / c_v, each read where its mean settlement passes 0.1 D (the collapse
    searches' criterion, read here from the path's history): the pressure rising with the
    ramp's time (measured 2026-12-02: 71.4, 87.9, 235.5 kPa; 66.9, 81.7, 207 when the
    path failed there, on steps by count), the slowest at the drained soil's collapse load
    (236 kPa by the settlement-controlled search; the limit analysis' bounds 232-238 kPa),
    the fastest less than a third of it. Beyond its strength the ground does not lose
    equilibrium in a time step (the pore water's drag holds it, even on the slowest ramp's
    long steps): each ramp goes on to 300 kPa (15, 19 and 55 m of settlement), its results
    reported not valid (small strains); a loss of equilibrium would be a SoilFailure with
    criterion "equilibrium"."""
    import math

    drained = analyse(_ramp(None, "load")).results["collapse"]["load_factor"] * 100e3
    carried = []
    for T in (0.001, 1.0, 1000.0):
        try:
            r = analyse(_ramp(T)).results
            history = r["consolidation"]["history"]
            assert not r["validity"]["valid"] and not r["validity"]["parts"]["small_strain"]
        except SoilFailure as e:
            assert e.kept["largest_load_carried"]["criterion"] == "equilibrium"
            history = e.history
        w = np.array([s["w_mean"] for s in history])
        P = np.array([s["applied_load"] for s in history]) / math.pi
        k = int(np.argmax(w > 0.2))
        assert k > 0, T
        carried.append(P[k - 1] + (0.2 - w[k - 1]) / (w[k] - w[k - 1]) * (P[k] - P[k - 1]))
    fast, middle, slow = carried
    assert fast < middle < slow
    assert slow <= drained * 1.02
    assert fast < drained / 3.0


def test_a_yielding_clay_layer_consolidates_as_an_independent_code_does():
    """benchmarks/scenes/yielding_layer.toml: 10 m of Mohr-Coulomb clay (c' 10 kPa, phi' 25
    deg, psi 0) under 50 kPa on r <= 5 m ramped over 10 days and held, at tankfx's defaults
    (10 time steps a decade) on the coarse mesh: the centre's settlement within 1 % of
    OpenGeoSys 6.5.9's converged 46.9 and 52.4 mm at 30 and 100 days, the excess pore
    pressure at (0, 2.5 m) within 2 % and 6 % of its 24.4 and 10.5 kPa (measured
    2026-12-01: -0.5 %, -0.2 %, -0.5 %, -3.7 %; on the default mesh at 10, 20, 40 steps a
    decade u(100 d) = 10.11, 10.22, 10.24 kPa: benchmarks/yielding_layer.py). Where a step
    was accepted at 1e-6 of the whole section's load vector (main 88ca880), the excess pore
    pressure at 100 days read 22.6 kPa: the flow, measured in m^3 beside forces in N, was
    never solved."""
    from pathlib import Path

    from tankfx import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "benchmarks" / "scenes" /
                       "yielding_layer.toml").with_coarse_mesh()
    scene = scene.with_changes(consolidation={"times": [30 * DAY, 100 * DAY]})
    r = analyse(scene).results
    at = {round(s["t_days"]): s for s in r["consolidation"]["at_times"]}
    assert r["soil"]["max_plastic_shear_strain"] > 1e-4        # (it yielded on the way)
    for days, w0, u, within in ((30, 46.9e-3, 24.4e3, 0.02), (100, 52.4e-3, 10.5e3, 0.06)):
        assert at[days]["w0"] == pytest.approx(w0, rel=0.01), days
        assert at[days]["piezometers"][0] == pytest.approx(u, rel=within), days


@pytest.mark.verify
def test_the_yielding_layers_path_is_converged_in_time_at_the_default_tolerance():
    """The yielding clay layer (benchmarks/scenes/yielding_layer.toml, coarse mesh), its
    longest steps 2 a decade so that the local error chooses the steps: at the default
    time_tolerance and at a sixteenth of it the centre's settlement agrees within 1 % at 30,
    100, 300 and 1000 days and the excess pore pressure at (0, 2.5 m) within 1 % at 30 and
    100 days (the issue asks 5 %: where it is over a tenth of its peak). The steps of the
    floor alone (no error control) are 3.3 % off at 100 days: the check can fail. Measured
    2026-12-02: 105, 326 and 37 time steps; w0 within 0.02 %, u within 0.32 %."""
    from pathlib import Path

    from tankfx import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "benchmarks" / "scenes" /
                       "yielding_layer.toml").with_coarse_mesh()
    tol = scene.consolidation.time_tolerance
    runs = []
    for tolerance in (tol, tol / 16.0, 1e9):
        r = analyse(scene.with_changes(consolidation={"time_tolerance": tolerance,
                                                      "steps_per_decade": 2})).results
        runs.append({round(s["t_days"]): s for s in r["consolidation"]["at_times"]
                     if s["t_days"]})
    default, fine, floor = runs
    for days in (30, 100, 300, 1000):
        assert default[days]["w0"] == pytest.approx(fine[days]["w0"], rel=0.01), days
    for days in (30, 100):
        assert default[days]["piezometers"][0] == pytest.approx(
            fine[days]["piezometers"][0], rel=0.01), days
    u = [run[100]["piezometers"][0] for run in runs]
    assert abs(u[2] / u[1] - 1.0) > 0.02


def test_the_coupled_residual_has_the_tangent_as_its_derivative_in_a_hold():
    """Taylor test of the coupled residual R = A(x) x - f (the skeleton's equilibrium and
    the pore water's flow) at a yielding state of a real hold: the yielding clay layer
    (benchmarks/scenes/yielding_layer.toml, coarse) held 20 days after its 10-day ramp, its
    last step's displacement increment taken half as far again, so that the 134 points
    that yielded in it yield on (a plastic tangent, not the committed state's elastic one).
    Along the path (that increment, and the pore pressure scaled) no point changes its
    return for h from 0.1 to 1e-3, and |R(x + h d) - R(x) - h A(x) d| / |h A(x) d| falls as
    h (measured 1.4e-7, 1.4e-8, 1.4e-9: second order); the flow's block, linear, to
    round-off (1e-12). A random direction crosses the elastic-plastic boundary of a point
    that sits on it within h = 1e-5. The elastic tangent at the yielding points leaves a
    remainder of O(1e-2) at every h; a coupling term missing from A, one of O(1)."""
    from pathlib import Path

    from tankfx import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "benchmarks" / "scenes" /
                       "yielding_layer.toml").with_coarse_mesh()
    scene = scene.with_changes(consolidation={"times": [30 * DAY]})
    m = analyse(scene).model
    plastic, soil = m.soil.plastic, m.soil
    step = soil.u.x.array - soil.u_n.x.array
    soil.u.x.array[:] += 0.5 * step
    x = [u.x.array.copy() for u in m.unknowns]
    plastic.update()
    flags = plastic.yielding.copy()
    assert int(np.sum(flags)) > 50
    d = [step, x[1].copy()]
    R0, Ad = m.block_vectors(), m.block_vectors(d)
    remainders = []
    for h in (1e-1, 1e-2, 1e-3):
        for u, a, b in zip(m.unknowns, x, d):
            u.x.array[:] = a + h * b
        plastic.update()
        assert np.array_equal(plastic.yielding, flags), h
        remainders.append([np.linalg.norm(r - r0 - h * ad) / np.linalg.norm(h * ad)
                           for r, r0, ad in zip(m.block_vectors(), R0, Ad)])
    remainders = np.array(remainders)                  # (h, block)
    equilibrium, flow = remainders[:, 0], remainders[:, 1]
    assert np.all(equilibrium[:-1] / equilibrium[1:] > 10 ** 0.8), equilibrium
    assert equilibrium[1] < 1e-5 and np.all(flow < 1e-9), remainders
