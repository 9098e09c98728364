"""Consolidation (Biot: tankfx.laws.biot, tankfx.iterations.time_stepping): Terzaghi's column,
the undrained and drained limits of the flexible load and of a tank, a wide load on a thin
layer, the scene's rules."""
import math

import numpy as np
import pytest

from conftest import COARSE, assemble_whole_system, flexible_scene, small_tank
from tankfx import Scene, analyse
from tankfx.verification import reference as ref
from tankfx.verification.rigs import MandelCylinder, Oedometer
from tankfx.laws.biot import consolidation_coefficient
from tankfx.iterations.time_stepping import time_steps
from tankfx.scene.sections import SceneError

E, NU, K = 5e6, 0.3, 1e-8          # Pa, -, m/s
DAY = 86400.0


def test_terzaghi_reference():
    """The series against the textbook values: U = 50 % at T_v = 0.197, 90 % at 0.848; the
    small-time limit 2 sqrt(T_v / pi) joins the series; the mean excess pore pressure over
    the layer is q (1 - U)."""
    U = ref.terzaghi_degree([0.19674, 0.84811])
    np.testing.assert_allclose(U, [0.5, 0.9], atol=2e-5)
    assert abs(ref.terzaghi_degree(1.0001e-4)[0] - 2 * math.sqrt(1e-4 / math.pi)) < 1e-6
    Z = (np.arange(2000) + 0.5) / 2000
    for Tv in (0.05, 0.3, 1.0):
        mean = np.mean(ref.terzaghi_pore_pressure(1.0, Z, Tv))
        assert abs(mean - (1.0 - ref.terzaghi_degree(Tv)[0])) < 1e-5


def _column_errors(per_decade, second_order=True, cells=40, drained_base=False):
    H, q = 10.0, 1e5
    c_v = consolidation_coefficient(E, NU, K, 9810.0)
    H_dr = H / 2 if drained_base else H
    Tv = np.array([0.01, 0.05, 0.2, 0.5, 1.0])
    times = Tv * H_dr**2 / c_v
    oed = Oedometer(H, E, NU, K, q, cells=cells, drained_base=drained_base)
    history = oed.run(time_steps(times, times[0] / 1000, per_decade), second_order)
    t = np.array([h["t"] for h in history])
    at = [int(np.argmin(abs(t - ti))) for ti in times]
    s = np.array([history[i]["settlement"] for i in at])
    final = q * H / (E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)))
    exact = ref.terzaghi_settlement(q, H, E, NU, K, times, drained_base=drained_base)
    p_base = np.array([history[i]["base_pressure"] for i in at])
    p_exact = ref.terzaghi_pore_pressure(q, 0.0 if drained_base else 1.0, Tv)
    return history[0], (s - exact) / final, (p_base - p_exact) / q


def test_oedometer_against_terzaghi():
    """The column drained at its top: no settlement at t = 0 (Nitsche's drained boundary
    leaves the undrained step undrained), then Terzaghi's settlement within 0.7 % of the
    final one and the base's pore pressure within 1 % of the load at 10 steps a decade;
    BDF2's error falls as the square of the step (measured 0.27 x for twice the steps),
    backward Euler's as the step (0.52 x), four times larger to start with."""
    start, err10, perr10 = _column_errors(10)
    assert abs(start["settlement"]) < 1e-12 and abs(start["base_pressure"] / 1e5 - 1) < 1e-9
    assert np.max(np.abs(err10)) < 7e-3 and np.max(np.abs(perr10)) < 1e-2
    _, err20, _ = _column_errors(20)
    assert np.max(np.abs(err20)) < 0.35 * np.max(np.abs(err10))
    _, be10, _ = _column_errors(10, second_order=False)
    _, be20, _ = _column_errors(20, second_order=False)
    assert np.max(np.abs(be10)) > 3 * np.max(np.abs(err10))
    assert 0.4 < np.max(np.abs(be20)) / np.max(np.abs(be10)) < 0.6


def test_nitsche_penalty_does_not_matter(monkeypatch):
    """The drained boundary's Nitsche penalty (10 k^2 / h by default) from 5 to 1000: the
    column's settlement the same to 9e-6 of the final at T_v = 0.01, where the drained
    boundary's layer is thinnest, and 1.5e-8 at T_v = 1 (consistent terms: the penalty
    only has to be large enough)."""
    import tankfx.laws.biot as cf

    errors = []
    for penalty in (5.0, 1e3):
        monkeypatch.setattr(cf, "NITSCHE_PENALTY", penalty)
        errors.append(_column_errors(10)[1])
    gap = np.abs(errors[0] - errors[1])
    assert gap[0] < 2e-5 and gap[-1] < 1e-7, gap


def test_oedometer_drained_both_faces():
    """Drained at the base too: the drainage path halves (T_v on H / 2) and the base's
    pore pressure stays zero."""
    _, err, perr = _column_errors(10, drained_base=True)
    assert np.max(np.abs(err)) < 7e-3
    assert np.max(np.abs(perr)) < 2e-3


def _mandel_errors(cells, per_decade):
    a, strain = 1.0, -1e-3
    c = ref.mandel_cylinder(E, NU, K, a, strain, [1.0])["c"]
    times = np.array([0.01, 0.05, 0.2, 0.5]) * a**2 / c
    exact = ref.mandel_cylinder(E, NU, K, a, strain, times, terms=200)
    history = MandelCylinder(a, E, NU, K, strain, cells=cells).run(
        time_steps(times, times[0] / 100, per_decade))
    t = np.array([h["t"] for h in history])
    at = [int(np.argmin(abs(t - ti))) for ti in times]
    p0 = exact["p0"]
    return history[0], exact, {
        "centre": np.array([history[i]["centre_pressure"] for i in at]) - exact["centre"],
        "mean": np.array([history[i]["mean_pressure"] for i in at]) - exact["mean"],
        "force": (np.array([history[i]["force"] for i in at]) - exact["force"])
        / exact["force"][0] * p0}


def test_mandel_cylinder():
    """The cylinder shortened between smooth impervious plates and drained on its side,
    against the closed form derived by Laplace transform
    (tankfx.verification.reference.mandel_cylinder):
    the undrained start (p = -G strain, force 3 G pi a^2 |strain|) to round-off; then the
    mean and the centre's pore pressure within 0.5 % of the start, the force within 0.02 %
    of it, on 16 x 16 cells at 20 steps a decade: the centre's pressure first rises 13 %
    above its start (Mandel and Cryer's effect) before it falls. Twice the cells and the
    steps per decade: the errors fall by 3.7 (centre) and 3.9 (mean) (measured)."""
    start, exact, err = _mandel_errors(16, 20)
    p0 = exact["p0"]
    assert start["mean_pressure"] == pytest.approx(p0, rel=1e-9)
    assert start["force"] == pytest.approx(3 * E / (2 * (1 + NU)) * math.pi * 1e-3, rel=1e-9)
    assert exact["centre"][1] > 1.12 * p0           # the effect, in the closed form...
    for key, tol in (("centre", 5e-3), ("mean", 2e-3), ("force", 3e-4)):
        assert np.max(np.abs(err[key])) < tol * p0, (key, err[key] / p0)
    _, _, finer = _mandel_errors(32, 40)
    for key in ("centre", "mean"):
        assert np.max(np.abs(finer[key])) < 0.4 * np.max(np.abs(err[key])), key


def _flexible(times_days, **consolidation):
    return flexible_scene(consolidation={"permeability": 1e-9,
                                         "times": [DAY * t for t in times_days],
                                         **consolidation}).with_coarse_mesh()


def test_flexible_load_undrained_and_drained_limits():
    """Boussinesq's settlement at nu = 0.5 with the undrained modulus 3 G at t = 0, and at
    nu' with E' in the drained limit (0.02 % on the coarse mesh); in between the degree of
    consolidation rises from 0 towards 1 and the excess pore pressure falls; each reported
    state is in equilibrium, and the results' top level is the last reported time."""
    sol = analyse(_flexible([0.1, 10, 1000], steps_per_decade=4))
    r, c = sol.results, sol.results["consolidation"]
    E_s, nu, p, a = 10e6, 0.3, 100e3, 1.0
    G = E_s / (2 * (1 + nu))
    undrained = ref.flexible_centre_settlement(p, a, 3 * G, 0.5)
    drained = ref.flexible_centre_settlement(p, a, E_s, nu)
    assert abs(c["undrained"]["w0"] / undrained - 1) < 2e-4
    assert abs(c["drained"]["w0"] / drained - 1) < 2e-4
    assert c["drained"]["max_pore_pressure"] < 1e-6 * p
    U = [s["degree"] for s in c["at_times"]]
    assert U[0] == 0.0 and all(0 < b - a_ for a_, b in zip(U, U[1:])) and U[-1] < 1
    pmax = [s["max_pore_pressure"] for s in c["at_times"]]
    assert all(b < a_ for a_, b in zip(pmax, pmax[1:]))
    assert r["w0"] == c["at_times"][-1]["w0"]
    assert r["equilibrium"]["relative_error"] < 1e-9
    assert r["dofs"]["pore_pressure"] > 0
    # the steps: 4 a decade from a hundredth of the first time through each reported one
    assert c["steps"] == len(time_steps(c["times"], 1e-2 * c["times"][0], 4))


def test_wide_load_on_a_thin_layer_is_terzaghi():
    """A load ten times wider than the drained layer under it is one-dimensional at its
    centre: the settlement there follows Terzaghi within 0.6 % of the final one, from an
    undrained settlement of 0.2 % of it (the finite width), and the pore pressure down the
    axis his isochrone within 1 % of the load (0.64 % at the base at T_v = 1: the step)."""
    E_s, nu, k, a, q, H = 10e6, 0.3, 1e-9, 10.0, 1e5, 1.0
    c_v = consolidation_coefficient(E_s, nu, k, 9810.0)
    times = list(np.array([0.02, 0.1, 0.3, 1.0]) * H**2 / c_v)
    scene = Scene.from_dict({
        "soil": {"E": E_s, "nu": nu}, "load": {"pressure": q, "load_radius": a},
        "domain": {"radius": 3 * a, "depth": H},
        "mesh": {"edge_size": 0.1, "near_size": 0.25, "growth": 0.3},
        "consolidation": {"permeability": k, "times": times}})
    r = analyse(scene).results
    c = r["consolidation"]
    final = q * H * (1 + nu) * (1 - 2 * nu) / (E_s * (1 - nu))
    # down the axis at the last time (T_v = 1): Terzaghi's isochrone, and the effective
    # stress the total less it
    axis = r["profiles"]["axis"]
    z = np.array(axis["z"])
    isochrone = ref.terzaghi_pore_pressure(q, z / H, 1.0)
    assert np.max(np.abs(np.array(axis["pore_pressure"]) - isochrone)) < 1e-2 * q
    np.testing.assert_allclose(axis["sigma_zz_effective"],
                               np.array(axis["sigma_zz"]) - axis["pore_pressure"], atol=1e-9)
    s = np.array([x["w0"] for x in c["at_times"][1:]])
    err = (s - ref.terzaghi_settlement(q, H, E_s, nu, k, np.array(times))) / final
    assert np.max(np.abs(err)) < 6e-3, err
    assert 0 < c["undrained"]["w0"] < 3e-3 * final
    assert abs(c["drained"]["w0"] / final - 1) < 1e-3


@pytest.mark.parametrize("interface", [
    pytest.param({"condition": "bonded"}, marks=pytest.mark.verify),
    {"condition": "mohr_coulomb", "tan_phi": 0.5}])
def test_tank_limits_are_the_undrained_and_drained_analyses(interface):
    """An embedded tank (plate, wall, a Mohr-Coulomb interface iterated at every step): its
    drained limit is the analysis with E', nu' (1e-6), its start the analysis of the
    undrained soil, nu = 0.5 with the same shear modulus, in the mixed form (w0 1e-4, M0
    1e-3; where the pit's wall slips and separates w0 5.7e-4 and M0 3.9e-3, 3.7e-4 and
    2.5e-3 on a mesh twice as fine: Taylor-Hood enforces tr eps = 0 only weakly, and the
    drained skeleton's lambda' (tr eps)^2 stiffens what it leaves, most beside the
    separated band)."""
    times = [DAY * t for t in (1, 100)]
    # the same plate, wall and interface whatever the soil (Kp, Kt and the penalty
    # stiffnesses would resolve on its E and nu)
    tank = small_tank(interface=interface | {"normal_stiffness": 3e10,
                                             "shear_stiffness": 3e10})
    resolved = Scene.from_dict(tank)
    tank["plate"] = {k: v for k, v in tank["plate"].items() if k != "Kp"} | {
        "thickness": resolved.plate.thickness}
    tank["wall"] = {k: v for k, v in tank["wall"].items() if k != "Kt"} | {
        "thickness": resolved.wall.thickness}
    # (the limits do not depend on the steps between them: a few)
    sol = analyse(Scene.from_dict(tank | {"consolidation": {"permeability": 1e-9,
                                                            "times": times,
                                                            "steps_per_decade": 2}}))
    c = sol.results["consolidation"]
    drained = analyse(Scene.from_dict(tank)).results
    G = 10e6 / (2 * 1.3)
    undrained = analyse(Scene.from_dict(tank | {"soil": {"E": 3 * G, "nu": 0.5}})).results
    for key, tol in (("w0", 1e-6), ("wd", 1e-5), ("M0", 1e-6)):
        assert abs(c["drained"][key] / drained[key] - 1) < tol, key
    slipping = interface["condition"] == "mohr_coulomb"
    for key, tol in (("w0", 1e-3 if slipping else 1e-4), ("M0", 6e-3 if slipping else 1e-3)):
        assert abs(c["undrained"][key] / undrained[key] - 1) < tol, \
            (key, c["undrained"][key] / undrained[key] - 1)
    w = [s["w0"] for s in c["at_times"]]
    assert w[0] < w[1] < w[2] < c["drained"]["w0"]
    assert sol.results["equilibrium"]["relative_error"] < 1e-8


@pytest.mark.parametrize("changes, words", [
    ({"soil": {"model": "hyperbolic", "hyperbolic_a": 1e-7, "hyperbolic_b": 1e-6,
               "nu": 0.3}}, "no effective-stress meaning"),
    ({"soil": {"E": 1e7, "nu": 0.49}}, "drained (effective) Poisson's ratio"),
    ({"soil": {"E": 1e7, "nu": 0.3, "layers": [{"depth": 2.0, "E": 2e7, "nu": 0.49}]}},
     "soil.layers[1].nu = 0.49 with [consolidation]"),
    ({"soil": {"E": 1e7, "nu": 0.3, "layers": [{"depth": 2.0, "E": 2e7, "nu": 0.3,
                                                 "permeability": -1.0}]}},
     "soil.layers[1].permeability = -1.0: must be > 0"),
    ({"solver": {"method": "iterative"}}, "solved by MUMPS"),
    ({"mesh": {"degree": 1}}, "Taylor-Hood"),
    ({"consolidation": {"permeability": 1e-9, "times": [10.0, 5.0]}}, "increasing"),
    ({"consolidation": {"permeability": 1e-9, "times": [-1.0]}}, "positive"),
    ({"consolidation": {"permeability": 1e-9, "times": []}}, "a list of the times"),
    ({"consolidation": {"permeability": 1e-9, "times": ["a day"]}}, "a list of the times"),
    ({"consolidation": {"permeability": 0.0, "times": [1.0]}}, "permeability = 0.0"),
    ({"consolidation": {"permeability": 1e-9, "times": [1.0], "drainage": "bottom"}},
     "consolidation.drainage = 'bottom'"),
    ({"consolidation": {"permeability": 1e-9, "times": [1.0], "steps_per_decade": 1}},
     "steps_per_decade = 1"),
    ({"consolidation": {"times": [1.0]}}, "consolidation.permeability: missing"),
    ({"consolidation": {"permeability": 1e-9, "times": [1.0], "k": 1}}, "unknown key"),
])
def test_refused_scenes(changes, words):
    data = {"soil": {"E": 1e7, "nu": 0.3}, "load": {"pressure": 1e5, "load_radius": 1.0},
            "consolidation": {"permeability": 1e-9, "times": [DAY]}} | changes
    with pytest.raises(SceneError, match=None) as e:
        Scene.from_dict(data)
    assert any(words in p for p in e.value.problems), e.value.problems


def test_layer_permeability_needs_a_consolidation():
    with pytest.raises(SceneError, match="only used with a \\[consolidation\\]"):
        Scene.from_dict({"soil": {"E": 1e7, "nu": 0.3, "layers": [
            {"depth": 2.0, "E": 2e7, "nu": 0.3, "permeability": 1e-5}]},
            "load": {"pressure": 1e5, "load_radius": 1.0}})


@pytest.mark.parametrize("sand_below", [True, pytest.param(False, marks=pytest.mark.verify)])
def test_clay_and_sand_layers(sand_below):
    """A load of 20 m radius on 1 m of clay and 0.5 m of sand (k 1e4 times the clay's;
    with the stiff sand on top a narrower load spreads: 3.8 % of the final settlement at
    once for 10 m, 0.6 % for 20 m): with the sand below and the base drained, the clay
    drains at both faces (Terzaghi on half its thickness); with the sand above and the base
    impervious, it drains upwards only, through the sand (on its whole thickness). The sand
    drains at once either way and its compression is added; the pore pressure is one
    field across the layers' boundary. Within 0.6 % of the final settlement, from T_v =
    0.02."""
    E_c, E_sand, nu, k, a, q = 5e6, 50e6, 0.3, 1e-9, 20.0, 1e5
    H_c, H_s = 1.0, 0.5
    c_v = consolidation_coefficient(E_c, nu, k, 9810.0)
    H_dr = 0.5 * H_c if sand_below else H_c
    times = np.array([0.02, 0.1, 0.3, 1.0]) * H_dr**2 / c_v
    clay, sand = {"E": E_c, "nu": nu}, {"E": E_sand, "nu": nu, "permeability": 1e4 * k}
    if sand_below:
        soil = clay | {"layers": [sand | {"depth": H_c}]}
    else:
        soil = sand | {"layers": [clay | {"depth": H_s, "permeability": k}]}
        soil.pop("permeability")
    scene = Scene.from_dict({
        "soil": soil, "load": {"pressure": q, "load_radius": a},
        "domain": {"radius": 3 * a, "depth": H_c + H_s},
        "mesh": {"edge_size": 0.1, "near_size": 0.25, "growth": 0.3},
        "consolidation": {"permeability": 1e4 * k if not sand_below else k,
                          "times": list(times),
                          "drainage": "top_and_bottom" if sand_below else "top"}})
    c = analyse(scene).results["consolidation"]
    E_oed = E_c * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    sand_part = ref.one_dimensional_settlement(q, [(H_s, E_sand, nu)])
    final = q * H_c / E_oed + sand_part
    s = np.array([x["w0"] for x in c["at_times"][1:]])
    exact = sand_part + ref.terzaghi_settlement(q, H_c, E_c, nu, k, times,
                                                drained_base=sand_below)
    err = (s - exact) / final
    assert np.max(np.abs(err)) < 6e-3, err
    assert abs(c["drained"]["w0"] / final - 1) < 1e-3


def test_ramp_reference_and_the_column_filled_over_time():
    """Olson's constant-rate loading (Duhamel on Terzaghi: reference.
    terzaghi_ramp_settlement) tends to the step response for a short ramp (1e-6); the column
    loaded over T_v = 0.2 then held follows it within 0.4 % of the final settlement at 10
    steps a decade, 0.09 % at 20."""
    H, q = 10.0, 1e5
    c_v = consolidation_coefficient(E, NU, K, 9810.0)
    ramp = 0.2 * H**2 / c_v
    times = np.array([0.05, 0.2, 0.5, 1.0]) * H**2 / c_v
    step = ref.terzaghi_settlement(q, H, E, NU, K, times)
    short = ref.terzaghi_ramp_settlement(q, H, E, NU, K, 1e-6 * ramp, times)
    assert np.max(np.abs(short / step - 1)) < 2e-6
    final = q * H * (1 + NU) * (1 - 2 * NU) / (E * (1 - NU))
    exact = ref.terzaghi_ramp_settlement(q, H, E, NU, K, ramp, times)
    errors = []
    for per_decade in (10, 20):
        grid = np.unique(np.concatenate([
            time_steps([ramp], ramp / 100, per_decade),
            ramp + time_steps(times[times > ramp] - ramp, ramp / 100, per_decade)]))
        history = Oedometer(H, E, NU, K, q).run(grid, load_factor=lambda t: min(t / ramp, 1))
        t = np.array([h["t"] for h in history])
        s = np.array([history[int(np.argmin(abs(t - ti)))]["settlement"] for ti in times])
        errors.append(np.max(np.abs(s - exact)) / final)
    assert errors[0] < 4.5e-3 and errors[1] < 1e-3, errors


def _wide(stages=None, times=(0.05, 0.2, 0.5, 1.0), **consolidation):
    """The wide load on a thin drained layer, as a scene dict with a load path."""
    E_s, nu, k, a, H = 10e6, 0.3, 1e-9, 10.0, 1.0
    c_v = consolidation_coefficient(E_s, nu, k, 9810.0)
    data = {"soil": {"E": E_s, "nu": nu}, "load": {"pressure": 1e5, "load_radius": a},
            "domain": {"radius": 3 * a, "depth": H},
            "mesh": {"edge_size": 0.1, "near_size": 0.25, "growth": 0.3},
            "consolidation": {"permeability": k, "times": [T * H**2 / c_v for T in times],
                              **consolidation}}
    if stages is not None:
        data["stages"] = [{k_: (v * H**2 / c_v if k_ == "time" else v)
                           for k_, v in st.items()} for st in stages]
    return data, H**2 / c_v


def test_a_load_path_in_time_fills_and_holds():
    """[[stages]] with times: the wide load reached linearly at T_v = 0.2 and held follows
    Olson's ramp within 0.6 % of the final settlement; each step balances its own load;
    the state at the stage's time is reported; a stage at t = 0 is the load at once (the
    same numbers as without stages)."""
    data, scale = _wide([{"time": 0.2}])
    r = analyse(Scene.from_dict(data)).results
    c = r["consolidation"]
    q, H, E_s, nu, k = 1e5, 1.0, 10e6, 0.3, 1e-9
    final = q * H * (1 + nu) * (1 - 2 * nu) / (E_s * (1 - nu))
    times = np.array(c["times"])
    s = np.array([x["w0"] for x in c["at_times"][1:]])
    exact = ref.terzaghi_ramp_settlement(q, H, E_s, nu, k, 0.2 * scale, times)
    assert np.max(np.abs(s - exact)) < 6e-3 * final
    loads = [x["applied_load"] for x in c["at_times"]]
    assert loads[0] == 0.0 and loads[1] == pytest.approx(0.25 * math.pi * 1e7, rel=1e-12)
    assert c["at_stages"][0]["t"] == pytest.approx(0.2 * scale)
    assert r["equilibrium"]["relative_error"] < 1e-9
    at_once = analyse(Scene.from_dict(_wide([{"time": 0.0}])[0])).results["consolidation"]
    plain = analyse(Scene.from_dict(_wide()[0])).results["consolidation"]
    assert [x["w0"] for x in at_once["at_times"]] == pytest.approx(
        [x["w0"] for x in plain["at_times"]], rel=1e-10)


@pytest.mark.verify
def test_loads_at_once_along_a_path_superpose():
    """Half the load at t = 0, the other half at once at T_v = 0.1, and all of it taken off
    at once at T_v = 0.5: a linear soil superposes the responses to each change alone
    (within 2e-3 of the settlement, the steps of the histories differing: 1.1e-3 measured,
    after the unloading; a change at t1 on an unloaded soil alone is the response at t -
    t1 to 6e-5, the grids differing only by the other run's reported times); after the
    unloading the soil swells back towards zero, its drained limit."""
    t1, t2 = 0.1, 0.5
    report = (0.05, 0.2, 0.4, 0.7, 1.0)
    # (a stage is reached linearly from the one before: a change at once is two stages at
    # one time, a hold two of one load)
    path, scale = _wide([{"pressure": 5e4, "time": 0.0}, {"pressure": 5e4, "time": t1},
                         {"pressure": 1e5, "time": t1}, {"pressure": 1e5, "time": t2},
                         {"pressure": 0.0, "time": t2}], report, steps_per_decade=20)
    c = analyse(Scene.from_dict(path)).results["consolidation"]
    shifted = sorted({T - d for T in report for d in (0.0, t1, t2) if T > d})
    single, _ = _wide(None, shifted, steps_per_decade=20)
    single["load"]["pressure"] = 5e4
    h = analyse(Scene.from_dict(single)).results["consolidation"]["at_times"]
    w = {round(x["t"] / scale * 1e6): x["w0"] for x in h}

    def unit(T):     # the settlement T (in H^2 / c_v) after a change of 50 kPa
        return 0.0 if T < 0 else w[round(T * 1e6)]

    for state in c["at_times"][1:]:
        T = state["t"] / scale
        expected = unit(T) + unit(T - t1) - 2 * unit(T - t2)
        assert state["w0"] == pytest.approx(expected, abs=2e-3 * unit(1.0)), T
    assert abs(c["drained"]["w0"]) < 1e-12
    assert c["at_times"][-1]["w0"] < c["at_times"][-2]["w0"]    # swelling back
    # the load at once at t1 = 0.1 on the unloaded soil: the response at t - t1
    late, _ = _wide([{"pressure": 0.0, "time": 0.0}, {"pressure": 0.0, "time": t1},
                     {"pressure": 5e4, "time": t1}], (0.15, 0.2, 0.4), steps_per_decade=20)
    c = analyse(Scene.from_dict(late)).results["consolidation"]
    assert [x["w0"] for x in c["at_times"][1:]] == pytest.approx(
        [unit(T - t1) for T in (0.15, 0.2, 0.4)], rel=1e-4)



@pytest.mark.verify
def test_a_mohr_coulomb_interface_emptied_to_a_twentieth(monkeypatch):
    """The small tank filled at once, held 10 days and emptied over 20 to 5 % of its load,
    with a slipping interface: the step that empties it does not converge from the full
    tank's states (its reversed slips cycled for 50 solves: the run stopped there), and
    converges from every element stuck. The states are only a starting guess (the law
    keeps no slip): starting every step from stuck states gives the same history (equal
    at two steps a decade; 1.5e-5 measured at three)."""
    from tankfx.iterations import active_set

    tank = small_tank(interface={"condition": "mohr_coulomb", "tan_phi": 0.5})
    tank["consolidation"] = {"permeability": 1e-9, "steps_per_decade": 2,
                             "times": [d * DAY for d in (10, 30, 100)]}
    tank["stages"] = [{"pressure": 50e3, "time": 0.0}, {"pressure": 50e3, "time": 10 * DAY},
                      {"pressure": 2.5e3, "time": 30 * DAY}]
    r = analyse(Scene.from_dict(tank)).results
    assert r["interface"]["converged"] and r["interface"]["restarts_from_stuck"] >= 1
    assert r["equilibrium"]["relative_error"] < 1e-9
    w = [s["w0"] for s in r["consolidation"]["at_times"]]
    assert w[1] > w[2] > w[3] > 0.0               # emptied, and swelling back
    monkeypatch.setattr(active_set, "CARRIED_STATES_SOLVES", 0)
    fresh = analyse(Scene.from_dict(tank)).results["consolidation"]["at_times"]
    for key in ("w0", "M0"):
        assert [s[key] for s in fresh] == pytest.approx(
            [s[key] for s in r["consolidation"]["at_times"]], rel=1e-4), key

@pytest.mark.parametrize("stages, words", [
    ([{"pressure": 1e5}], "stages[1].time: missing"),
    ([{"pressure": 1e5, "time": -1.0}], "stages[1].time = -1.0"),
    ([{"time": 10.0}, {"pressure": 2e5, "time": 5.0}], "is before stages[1].time"),
    ([{"time": 2 * DAY}], "before the load path's end"),
])
def test_refused_load_paths(stages, words):
    data = {"soil": {"E": 1e7, "nu": 0.3}, "load": {"pressure": 1e5, "load_radius": 1.0},
            "consolidation": {"permeability": 1e-9, "times": [DAY]}, "stages": stages}
    with pytest.raises(SceneError) as e:
        Scene.from_dict(data)
    assert any(words in p for p in e.value.problems), e.value.problems


def test_a_stage_time_needs_a_consolidation_and_one_self_weight():
    with pytest.raises(SceneError, match="only used with a \\[consolidation\\]"):
        Scene.from_dict({"soil": {"E": 1e7, "nu": 0.3}, "load": {"pressure": 1e5,
                                                                 "load_radius": 1.0},
                         "stages": [{"time": 1.0}]})
    with pytest.raises(SceneError, match="self_weight changes"):
        Scene.from_dict(small_tank(consolidation={"permeability": 1e-9, "times": [DAY]},
                                   stages=[{"time": 0.0}, {"time": DAY,
                                                           "self_weight": True}]))


def test_overturning_on_a_consolidating_soil_is_undrained():
    """An overturning moment on a consolidating soil rocks it undrained, about the state
    at the last reported time: a rigid disc's rocking stiffness is Borowicka's with E_u =
    3 G and nu = 0.5 (+0.11 % on the coarse mesh; the drained soil's +0.28 % off its own),
    the same as the undrained soil's analysed directly (nu = 0.5, mixed form; 1e-6), and
    moment equilibrium holds."""
    from tankfx.verification.reference import rigid_disc_rocking_stiffness

    plate = {"radius": 1.0, "thickness": 0.5, "E": 30e9, "nu": 0.2}
    load = {"pressure": 10e3, "overturning_moment": 1e4}
    base = {"soil": {"E": 10e6, "nu": 0.3}, "plate": plate,
            "interface": {"condition": "smooth", "normal_stiffness": 1e11,
                          "shear_stiffness": 1e11},
            "load": load, "mesh": COARSE}
    o = analyse(Scene.from_dict(base | {"consolidation": {
        "permeability": 1e-9, "times": [DAY], "steps_per_decade": 2}})).results["overturning"]
    G = 10e6 / 2.6
    undrained = analyse(Scene.from_dict(base | {"soil": {"E": 3 * G, "nu": 0.5}})).results
    K = o["rocking_stiffness"]
    assert K == pytest.approx(undrained["overturning"]["rocking_stiffness"], rel=1e-6)
    assert K == pytest.approx(rigid_disc_rocking_stiffness(3 * G, 0.5, 1.0), rel=5e-3)
    assert o["equilibrium"]["moment_relative_error"] < 1e-8


@pytest.mark.parametrize("fill", [pytest.param(False, marks=pytest.mark.verify), True])
def test_a_ringwall_on_consolidating_ground(fill):
    """A concrete ringwall (and a compacted fill inside it, which drains) under the wall
    of a surface tank on consolidating clay: the drained limit is the drained analysis of
    the same ringwall (2.5e-7), the start the undrained one (the ground at nu = 0.5 and
    its shear modulus, the ring and fill their own: w0 1.1e-4, M0 2.3e-4, with the fill
    1.1e-4 and 1.8e-4: its faces drain by Nitsche's terms, none at t = 0; with a Dirichlet
    condition there, as first written, 8.5e-4 and 5.3e-3); no pore pressure inside the
    ring's and the fill's cells, little on the fill's faces (median 0.016 % of the largest,
    1.5 % at a corner with the ring); an overturning moment
    balances. (The interface's default stiffness, by each cell's E: the undrained
    analysis's is 1.15 times the consolidation's in the ground.)"""
    tank = small_tank(interface={"condition": "bonded"},
                      ringwall={"inner_radius": 0.8, "outer_radius": 1.1, "depth": 0.4,
                                "E": 30e9, "nu": 0.2, **({"fill_E": 50e6, "fill_nu": 0.3}
                                                         if fill else {})})
    tank["plate"] = {"radius": 1.0, "thickness": 0.2, "E": 30e9, "nu": 0.2}
    tank["wall"] = {"radius": 1.0, "thickness": 0.1, "height": 3.0, "E": 30e9, "nu": 0.2}
    sol = analyse(Scene.from_dict(tank | {
        "consolidation": {"permeability": 1e-9, "times": [DAY], "steps_per_decade": 2},
        "load": {"pressure": 50e3, "overturning_moment": 1e4}}))
    c = sol.results["consolidation"]
    drained = analyse(Scene.from_dict(tank)).results
    undrained = analyse(Scene.from_dict(tank | {"soil": {"E": 3e7 / 2.6, "nu": 0.5}})).results
    for key in ("w0", "wd", "M0"):
        assert c["drained"][key] == pytest.approx(drained[key], rel=1e-6), key
    for key, tol in (("w0", 2e-4), ("M0", 4e-4)):
        assert c["undrained"][key] == pytest.approx(undrained[key], rel=tol), key
    soil = sol.model.soil
    p = soil.pore_pressure
    dofs = p.function_space.dofmap
    inside = np.unique(dofs.list[np.flatnonzero(soil.linear_cells)])
    ground = np.unique(dofs.list[soil.stratum_cells(soil.ground)])
    scale = np.max(np.abs(p.x.array))
    assert scale > 0
    assert np.max(np.abs(p.x.array[np.setdiff1d(inside, ground)]), initial=0.0) == 0.0
    if fill:
        faces = np.intersect1d(np.unique(dofs.list[np.flatnonzero(soil.fill_cells)]),
                               ground)
        # (weakly 0: 1.5 % of the largest at one node, a corner with the impervious ring)
        assert 0 < np.max(np.abs(p.x.array[faces])) < 3e-2 * scale
        assert np.median(np.abs(p.x.array[faces])) < 2e-3 * scale
    assert sol.results["overturning"]["equilibrium"]["moment_relative_error"] < 1e-8


@pytest.mark.parametrize("case", [
    *(pytest.param(c, marks=pytest.mark.verify) for c in ("ringwall with a fill",
                                                          "mohr_coulomb")),
    "flexible load"])
def test_only_the_flow_terms_are_reassembled_at_each_step(case, monkeypatch):
    """A consolidation's time step changes only the flow terms of the matrix (dt k /
    gamma_w times the pore pressure's blocks; a Mohr-Coulomb interface's states too): the
    rest is assembled once. The same history as re-assembling the whole system at every
    step (a ringwall's pinned pore pressures and its fill's interior-facet drainage, an
    interface iterated at every step, the bare soil under a flexible load)."""
    from tankfx.fem.solvers import SPLIT_ASSEMBLY

    consolidation = {"permeability": 1e-9, "times": [DAY, 30 * DAY], "steps_per_decade": 2}
    if case == "flexible load":
        scene = flexible_scene(consolidation=consolidation).with_coarse_mesh()
    else:
        tank = small_tank(interface={"condition": "mohr_coulomb", "tan_phi": 0.5}) \
            if case == "mohr_coulomb" else small_tank(ringwall={
                "inner_radius": 0.8, "outer_radius": 1.1, "depth": 0.4, "E": 30e9,
                "nu": 0.2, "fill_E": 50e6, "fill_nu": 0.3})
        scene = Scene.from_dict(tank | {"consolidation": consolidation})
    split = analyse(scene).results
    assert split["linear_solver"]["assembly"] == SPLIT_ASSEMBLY
    assemble_whole_system(monkeypatch)
    full = analyse(scene).results
    assert full["linear_solves"] == split["linear_solves"] > 3
    for a, b in zip(split["consolidation"]["history"], full["consolidation"]["history"]):
        keys = ("w0", "wd", "axis_pore_pressure") + (("M0",) if case != "flexible load"
                                                     else ())   # (no plate, no moment)
        for key in keys:
            assert a[key] == pytest.approx(b[key], rel=1e-10, abs=1e-12), (key, a["t"])


def test_scene_round_trip(tmp_path):
    scene = _flexible([1, 30], drainage="top_and_bottom", steps_per_decade=5)
    path = tmp_path / "s.toml"
    path.write_text(scene.to_toml())
    again = Scene.from_toml(path)
    assert again == scene and again.consolidation.times == (DAY, 30 * DAY)
    assert COARSE  # (the coarse mesh of the other tests)


def test_tankfx_run_writes_the_history_figure_and_pore_pressure(tmp_path):
    """`tankfx run` on the demo's scene (coarse): the summary's consolidation rows, the
    history as CSV (units in the header, every step), its figure, and the excess pore
    pressure among the soil's fields for ParaView; `tankfx check` says what it builds."""
    import csv
    import subprocess
    import sys
    from pathlib import Path

    from tankfx.cli import main

    scene = Path(__file__).resolve().parents[1] / "demos" / "scenes" / "tank_on_clay.toml"
    out = tmp_path / "out"
    assert main(["run", str(scene), "--out", str(out), "--coarse"]) == 0
    with (out / "profiles" / "consolidation.csv").open() as f:
        rows = list(csv.DictReader(f))
    results = __import__("json").loads((out / "results.json").read_text())
    c = results["consolidation"]
    assert len(rows) == len(c["history"]) == c["steps"] + 1
    assert float(rows[-1]["w0 [m]"]) == pytest.approx(results["w0"], rel=1e-12)
    assert float(rows[0]["max_pore_pressure [Pa]"]) > 0 and rows[0]["t [s]"] == "0.0"
    assert c["drained"]["t"] is None          # (infinity: null in JSON)
    report = (out / "report.md").read_text()
    assert "undrained w0 (t = 0)" in report and "drained limit w0" in report
    for name in ("consolidation.png", "isochrones.png"):
        assert (out / name).stat().st_size > 10_000, name
    # the isochrones: at t = 0 and each reported time, the last the axis profile's
    iso = c["isochrones"]
    assert len(iso["pore_pressure"]) == len(c["times"]) + 1 == len(iso["t_days"])
    assert np.interp(results["profiles"]["axis"]["z"][40], iso["z"], iso["pore_pressure"][-1]) \
        == pytest.approx(results["profiles"]["axis"]["pore_pressure"][40], rel=2e-2, abs=1.0)
    import pyvista

    soil = pyvista.read(sorted((out / "fields").glob("soil*.vtu"))[0])
    p = soil.point_data["excess_pore_pressure"]
    assert 0 < p.max() < c["at_times"][-1]["max_pore_pressure"] * 1.01
    check = subprocess.run([sys.executable, "-m", "tankfx", "check", str(scene)],
                           capture_output=True, text=True)
    assert check.returncode == 0 and "Biot's consolidation" in check.stdout
    assert "time steps to 1095 days" in check.stdout


def test_a_sweep_over_the_permeability(tmp_path):
    """A sweep's axis may be the permeability: its table has the degree of consolidation
    reached at the last reported time (rising with k), and the undrained and drained
    settlements (the same for every k)."""
    import csv

    from mpi4py import MPI

    from tankfx.studies.sweep import Sweep, scene_with, run_sweep

    base = _flexible([30], steps_per_decade=4)
    axis = [1e-10, 1e-9, 1e-8]
    cases = [{"consolidation.permeability": k} for k in axis]
    sweep = Sweep(base=base, axes={"consolidation.permeability": axis}, cases=cases,
                  scenes=[scene_with(base, c) for c in cases])
    run_sweep(sweep, tmp_path / "out", MPI.COMM_SELF)
    with (tmp_path / "out" / "table.csv").open() as f:
        table = list(csv.DictReader(f))
    U = [float(r["consolidation.degree"]) for r in table]
    assert 0 < U[0] < U[1] < U[2] < 1
    for key in ("consolidation.undrained.w0", "consolidation.drained.w0"):
        values = [float(r[key]) for r in table]
        assert values == pytest.approx([values[0]] * 3, rel=1e-7), key


def test_a_load_path_in_time_round_trips_and_is_described(tmp_path):
    """A hydrotest as a scene file: read back equal (each stage with its time), and
    `tankfx check` says what each stage reaches and when."""
    from tankfx.cli import describe

    data = small_tank(consolidation={"permeability": 1e-9, "times": [DAY, 100 * DAY]},
                      stages=[{"time": 10 * DAY}, {"time": 60 * DAY},
                              {"pressure": 1e4, "time": 65 * DAY}])
    scene = Scene.from_dict(data)
    assert scene.stage_times == (10 * DAY, 60 * DAY, 65 * DAY)
    path = tmp_path / "hydrotest.toml"
    path.write_text(scene.to_toml())
    assert Scene.from_toml(path) == scene
    text = "\n".join(describe(scene))
    assert "stage 1 reached at t = 10 days ([load])" in text
    assert "stage 3 reached at t = 65 days: pressure = 10000" in text


@pytest.mark.parametrize("k, degrees", [(1e-16, (0.0, 1e-5, 0.1)), (1e-2, (0.8, 1.0 - 1e-3,
                                                                         1.0 + 1e-5))])
def test_extreme_permeabilities(k, degrees):
    """k = 1e-16 m/s (a clay that hardly drains in ten thousand years) and 1e-2 m/s (a
    gravel, drained within seconds): the degree of consolidation stays near 0, or is near
    1 after a second, and never leaves [0, 1] by more than round-off; the residual stays
    at its floor."""
    r = analyse(Scene.from_dict(small_tank(consolidation={
        "permeability": k, "times": [1.0, DAY, 1e4 * 365 * DAY],
        "steps_per_decade": 2}) | {"accept": ["consolidation.permeability"]})).results
    U = [x["degree"] for x in r["consolidation"]["at_times"][1:]]
    lo, mid, hi = degrees
    if k < 1e-10:
        assert abs(U[0]) < 1e-6 and abs(U[1]) < mid and 0 < U[2] < hi
    else:
        assert lo < U[0] < 1 and mid < U[1] < hi and abs(U[2] - 1) < 1e-5
    assert r["linear_solver"]["last_relative_residual"] < 1e-8
