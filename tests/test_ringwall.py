"""A concrete ringwall under the wall (the usual foundation of a large steel tank: a ring
beam under the shell, the floor on compacted fill inside): an annulus of another material
in the ground. Checked against the layered ground it becomes when it spans everything, the
soil it replaces when it is made of that soil, and the trend a stiffer ring must give."""
import copy
import math
import tomllib

import numpy as np
import pytest

from conftest import small_tank
from tankfx import Scene, SceneError
from tankfx.analysis import analyse

TANK = {
    "soil": {"E": 30e6, "nu": 0.3},
    "plate": {"radius": 10.5, "thickness": 0.008, "E": 200e9, "nu": 0.3},
    "wall": {"radius": 10.0, "thickness": 0.016, "height": 12.0, "E": 200e9, "nu": 0.3},
    "load": {"liquid_unit_weight": 9810.0, "liquid_height": 11.0, "roof_weight": 500e3}}
RING = {"inner_radius": 9.5, "outer_radius": 10.8, "depth": 1.5, "E": 30e9}


def tank(ring=None, **sections):
    data = copy.deepcopy(TANK)
    for name, values in sections.items():
        data.setdefault(name, {}).update(values)
    if ring is not None:
        data["ringwall"] = ring
    return Scene.from_dict(data)


@pytest.mark.parametrize("inside", [{"inner_radius": 0.0},
                                    {"inner_radius": 5.0, "fill_E": 300e6, "fill_nu": 0.25}],
                         ids=["from_the_axis", "filled"])
def test_a_ringwall_over_the_whole_ground_is_a_layer(inside):
    """A ringwall from the axis (or from 5 m, filled with its own material) to far beyond
    the tank, 1 m deep, 10 times stiffer than the soil, is a 1 m crust: the same
    settlements and wall moment as [[soil.layers]] with that crust (itself checked against
    Burmister's layered solution, test_layers.py)."""
    ring = tank({"outer_radius": 40e3, "depth": 1.0, "E": 300e6, "nu": 0.25} | inside)
    crust = tank(soil={"E": 300e6, "nu": 0.25,
                       "layers": [{"depth": 1.0, "E": 30e6, "nu": 0.3}]})
    a, b = analyse(ring).results, analyse(crust).results
    # measured on the default meshes (which differ: the ringwall's far corners): w0 5e-7 /
    # 9e-7, wd 4e-5 / 3e-5, w_edge 2e-5 / 2e-5, wall base moment 4e-5 / 9e-5
    for key in ("w0", "wd", "w_edge"):
        assert a[key] == pytest.approx(b[key], rel=5e-4), key
    assert a["junction"]["M_wall"] == pytest.approx(b["junction"]["M_wall"], rel=1e-3)


@pytest.mark.mpi
def test_a_stiffer_ringwall_carries_the_shell_and_lets_the_floor_dish():
    """Coarse meshes: a ringwall of the soil itself changes nothing; a stiffer one settles
    less under the shell while the centre, carried by the soil, settles about as before, so
    the floor dishes more, and the wall's foot, held by the ring, bends more. Every case
    balances its load. (Serial = 2 ranks: this test runs under mpiexec too.)"""
    bare = analyse(tank().with_coarse_mesh()).results
    same = analyse(tank(RING | {"E": 30e6, "nu": 0.3}).with_coarse_mesh()).results
    assert same["w0"] == pytest.approx(bare["w0"], rel=1e-4)
    assert same["wd"] == pytest.approx(bare["wd"], rel=1e-3)
    runs = [same] + [analyse(tank(RING | {"E": E}).with_coarse_mesh()).results
                     for E in (300e6, 30e9)]
    shell = [r["settlement_summary"]["shell_settlement"] for r in runs]
    dish = [r["settlement_summary"]["dish"] for r in runs]
    M_wall = [abs(r["junction"]["M_wall"]) for r in runs]
    assert shell[0] > shell[1] > shell[2], shell
    assert dish[0] < dish[1] < dish[2], dish
    assert M_wall[0] < M_wall[1] < M_wall[2], M_wall
    assert all(abs(r["w0"] / bare["w0"] - 1) < 0.03 for r in runs)
    # a compacted fill inside the ring: of the soil's own material nothing changes, stiffer
    # it carries the floor: the centre settles less and the floor dishes less
    own_fill = analyse(tank(RING | {"fill_E": 30e6, "fill_nu": 0.3}).with_coarse_mesh())
    stiff_fill = analyse(tank(RING | {"fill_E": 100e6}).with_coarse_mesh()).results
    assert own_fill.results["w0"] == pytest.approx(runs[2]["w0"], rel=1e-4)
    assert stiff_fill["w0"] < runs[2]["w0"]
    assert stiff_fill["settlement_summary"]["dish"] < dish[2]
    runs.append(stiff_fill)
    # (the penalty on the ring's top follows its modulus: 1000 times a concrete element's
    # stiffness against the soil's costs digits; measured 6.6e-9 at E = 1000 E_s, residual
    # 6.5e-9; 1.7e-8 and 1.2e-8 on the default mesh)
    for r in (bare, *runs):
        assert r["equilibrium"]["relative_error"] < 1e-7


def _ring_moduli(solution):
    block = solution.model.soil
    E = block.E.x.array[block.E.function_space.dofmap.list[:, 0]]
    return E[block.ringwall_cells]


def test_ringwall_on_nonlinear_soil_keeps_its_own_modulus():
    """On Kondner's and Duncan & Chang's soils the secant iteration leaves the ringwall's
    cells at its modulus: a Kondner soil of a strength too large to matter (1/b = 1e12 Pa)
    is the linear soil of E = 1/a, ringwall included (measured 1e-8); Duncan & Chang's
    sand converges with the ringwall's cells at E to the last digit (the 1 m test tank on a
    ring 0.3 m wide and 0.4 m deep: w0 10.2 against 19.1 mm without, 14 solves)."""
    ring = {"inner_radius": 0.85, "outer_radius": 1.15, "depth": 0.4, "E": 30e9}
    linear = analyse(Scene.from_dict(small_tank(ringwall=ring))).results
    kondner = analyse(Scene.from_dict(small_tank(ringwall=ring, soil={
        "model": "hyperbolic", "hyperbolic_a": 1e-7, "hyperbolic_b": 1e-12, "nu": 0.3},
        accept=["soil.hyperbolic_b"])))
    assert kondner.results["w0"] == pytest.approx(linear["w0"], rel=1e-6)
    assert np.all(_ring_moduli(kondner) == 30e9)
    sand = {"model": "duncan_chang", "nu": 0.3, "modulus_number": 400.0,
            "modulus_exponent": 0.5, "cohesion": 5e3, "friction_angle": 35.0,
            "unit_weight": 18e3}
    dc = analyse(Scene.from_dict(small_tank(ringwall=ring, soil=sand,
                                            load={"pressure": 100e3})))
    assert dc.results["soil"]["converged"]
    assert np.all(_ring_moduli(dc) == 30e9)
    assert dc.results["equilibrium"]["relative_error"] < 1e-7


def test_ringwall_weight_goes_to_the_soil_not_the_interface():
    """With self_weight, a ringwall's net unit weight (concrete less the soil it replaces)
    loads the ground: the supports carry it with the water, the roof and the steel, the
    interface only what stands on the plate. Weighed here by hand."""
    ring = RING | {"unit_weight": 6e3}
    res = analyse(tank(ring, plate={"unit_weight": 77e3}, wall={"unit_weight": 77e3},
                       load={"self_weight": True}).with_coarse_mesh()).results
    water = 9810.0 * 11.0 * math.pi * 10.0**2
    steel = 77e3 * (0.008 * math.pi * 10.5**2 + 0.016 * 2 * math.pi * 10.0 * 12.0)
    concrete = 6e3 * math.pi * (10.8**2 - 9.5**2) * 1.5
    eq = res["equilibrium"]
    assert eq["contact_resultant"] == pytest.approx(water + 500e3 + steel, rel=1e-7)
    assert eq["reaction"] == pytest.approx(water + 500e3 + steel + concrete, rel=1e-7)
    assert eq["applied_load"] == pytest.approx(water + 500e3 + steel + concrete, rel=1e-12)


def test_ringwall_is_read_and_written_back(tmp_path):
    s = tank(RING)
    assert s.ringwall.nu == 0.2 and s.ringwall.E == 30e9
    path = tmp_path / "tank.toml"
    path.write_text(s.to_toml())
    assert Scene.from_dict(tomllib.loads(path.read_text())) == s


@pytest.mark.parametrize("ring, sections, key, fix", [
    (RING | {"inner_radius": 10.2}, {}, "ringwall", "must stand on it"),
    (RING | {"outer_radius": 9.0}, {}, "ringwall.inner_radius", "inner_radius < outer_radius"),
    (RING | {"depth": -1.0}, {}, "ringwall.depth", "> 0"),
    (RING | {"nu": 0.49}, {}, "ringwall.nu", "0.45"),
    (RING | {"E": float("nan")}, {}, "ringwall.E", "finite"),
    (RING | {"widht": 1.0}, {}, "ringwall.widht", "valid"),
    (RING | {"fill_nu": 0.3}, {}, "ringwall.fill_nu", "add ringwall.fill_E"),
    (RING | {"fill_E": -1.0}, {}, "ringwall.fill_E", "> 0"),
    (RING | {"fill_E": 1e8, "inner_radius": 0.0, "outer_radius": 10.5}, {}, "ringwall.fill_E",
     "no inside"),
    ({k: v for k, v in RING.items() if k != "depth"}, {}, "ringwall.depth", "missing"),
    (RING | {"depth": 200e3}, {}, "ringwall.depth", "rigid base"),
])
def test_bad_ringwalls_are_refused_with_key_and_fix(ring, sections, key, fix):
    data = copy.deepcopy(TANK)
    data["ringwall"] = ring
    for name, values in sections.items():
        data[name] = {k: v for k, v in {**data[name], **values}.items() if v is not None}
    with pytest.raises(SceneError) as info:
        Scene.from_dict(data)
    msg = "\n".join(info.value.problems)
    assert key in msg and fix in msg, msg
