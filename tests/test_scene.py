"""Scene files: the keys of the contract are read, resolved and, when wrong, refused before
any mesh is built with one message that names each key and its fix."""
import math
import subprocess
import sys
import textwrap

import pytest

from tankfx import Scene, SceneError, load_scene
from tankfx.laws.rigidity import Kp_from_thickness, plate_thickness_from_Kp

GOOD = {"soil": {"E": 10e6, "nu": 0.3}, "load": {"pressure": 100e3, "load_radius": 1.0}}
PLATE = {"radius": 1.0, "thickness": 0.5, "E": 30e9, "nu": 0.2}
WALL = {"radius": 1.0, "thickness": 0.01, "height": 5.0, "E": 200e9, "nu": 0.3}


def with_(base=GOOD, **sections):
    data = {k: dict(v) if isinstance(v, dict) else v for k, v in base.items()}
    for name, values in sections.items():
        if values is None:
            data.pop(name, None)
        else:
            data.setdefault(name, {}).update(values)
    return data


def problems(data):
    with pytest.raises(SceneError) as info:
        Scene.from_dict(data)
    return "\n".join(info.value.problems)


def test_defaults_are_resolved():
    s = Scene.from_dict(GOOD)
    assert s.foundation_radius == 1.0
    assert s.soil.model == "linear" and s.soil.E_gradient == 0.0
    # a flexible load: P3 on a mesh twice as coarse (on the efficient front); a plate: P2
    assert s.mesh.degree == 3 and s.mesh.edge_size == pytest.approx(0.004)
    assert s.mesh.near_size == pytest.approx(0.2)
    plated = Scene.from_dict({**GOOD, "plate": {"radius": 1.0, "thickness": 0.1, "E": 30e9,
                                                "nu": 0.2}})
    assert plated.mesh.degree == 2 and plated.mesh.edge_size == pytest.approx(0.002)
    assert s.domain.radius == s.domain.depth == pytest.approx(10000.0)
    assert s.Kp is None and s.Kt is None
    assert Scene.from_dict(s.to_dict()) == s


def test_Kp_and_thickness_are_inverse():
    t = plate_thickness_from_Kp(0.1, 2.0, 30e9, 10e6, 0.3)
    assert Kp_from_thickness(t, 2.0, 30e9, 10e6, 0.3) == pytest.approx(0.1, rel=1e-12)


@pytest.mark.parametrize("data, key, fix", [
    (with_(soil={"Ee": 1.0}), "soil.Ee", "did you mean 'E'"),
    (with_(sol={"E": 1.0}), "[sol]", "did you mean 'soil'"),
    (with_(load={"presure": 1.0}), "load.presure", "did you mean 'pressure'"),
    ({"load": GOOD["load"]}, "[soil]", "add a '[soil]' table"),
    ({"soil": {"nu": 0.3}, "load": GOOD["load"]}, "soil.E", "add 'E = ...'"),
    (with_(soil={"E": "10 MPa"}), "soil.E", "expected a number"),
    (with_(soil={"E": True}), "soil.E", "expected a number"),
    (with_(soil={"E": 0.0}), "soil.E", "must be > 0"),
    (with_(soil={"E": -5.0}), "soil.E", "must be > 0"),
    (with_(soil={"nu": 0.51}), "soil.nu", "(-1, 0.5]"),
    (with_(soil={"nu": -1.0}), "soil.nu", "(-1, 0.5]"),
    (with_(plate=PLATE | {"nu": 0.5}), "plate.nu", "(-1, 0.5)"),
    (with_(soil={"nu": 0.49}, mesh={"degree": 1}), "mesh.degree", "degree 2"),
    (with_(soil={"nu": math.nan}), "soil.nu", "finite"),
    (with_(load={"pressure": math.inf}), "load.pressure", "finite"),
    (with_(soil={"model": "hyperbolicc"}), "soil.model", "did you mean 'hyperbolic'"),
    (with_(soil={"E_gradient": -0.1}), "soil.E_gradient", ">= 0"),
    (with_() | {"load": {"pressure": 1.0}}, "load.load_radius",
     "add 'load_radius = ...'"),
    (with_(load={"pressure": 0.0}), "[load]", "no load"),
    (with_(domain={"radius": 1.5}), "domain.radius", "must exceed"),
    (with_(plate=PLATE | {"embedment": 0.5}, domain={"depth": 0.5}), "domain.depth",
     "below the foundation"),
    (with_(mesh={"degree": 5}), "mesh.degree", "1, 2, 3 or 4"),
    (with_(mesh={"degree": 2.0}), "mesh.degree", "expected an integer"),
    (with_(mesh={"edge_size": 0.9}), "mesh.edge_size", "half the foundation radius"),
    (with_(mesh={"growth": 2.0}), "mesh.growth", "(0, 1]"),
    (with_(plate=PLATE | {"Kp": 1.0}), "plate.thickness and plate.Kp", "not both"),
    (with_(plate=PLATE | {"thickness": -0.5}), "plate.thickness", "> 0"),
    (with_(plate=PLATE, wall=WALL | {"radius": 1.2}), "wall.radius", "wider than plate.radius"),
    (with_(wall=WALL), "[wall]", "needs a foundation plate"),
    (with_(wall=WALL | {"Kt": 0.1}), "wall.thickness and wall.Kt", "not both"),
    (with_(plate=PLATE | {"embedment": 3000.0}, domain={"depth": 2000.0}), "domain.depth",
     "embedment"),
    (with_(plate=PLATE, wall=WALL, load={"liquid_height": 6.0, "liquid_unit_weight": 1e4}),
     "load.liquid_height", "higher than wall.height"),
    (with_(plate=PLATE, interface={"condition": "rough"}), "interface.condition", "valid"),
    (with_(plate=PLATE, interface={"condition": "mohr_coulomb", "tan_phi": 0.5,
                                   "friction_angle": 30.0}), "interface.tan_phi", "not both"),
    (with_(plate=PLATE, interface={"condition": "mohr_coulomb", "tan_phi": 0.5,
                                   "states": "point"}), "interface.states", "element"),
    (with_(plate=PLATE, interface={"condition": "mohr_coulomb", "tan_phi": 0.5,
                                   "on_cycle": "halt"}), "interface.on_cycle", "stop"),
    (with_(plate=PLATE, interface={"condition": "bonded", "states": "node"}),
     "interface.states", "only used with"),
    (with_(interface={"condition": "smooth"}), "[interface]", "needs a [plate]"),
])
def test_bad_input_is_refused_with_key_and_fix(data, key, fix):
    msg = problems(data)
    assert key in msg and fix in msg, msg


def test_all_problems_are_reported_at_once():
    msg = problems(with_(soil={"E": -1.0, "nu": 0.7}, load={"presure": 1.0}))
    assert "soil.E" in msg and "soil.nu" in msg and "load.presure" in msg


def test_hyperbolic_soil_keys():
    hyper = {"model": "hyperbolic", "nu": 0.3}
    msg = problems({"soil": hyper, "load": GOOD["load"]})
    assert "soil.hyperbolic_a" in msg and "soil.hyperbolic_b" in msg
    full = hyper | {"hyperbolic_a": 2.1e-7, "hyperbolic_b": 1e-5}
    s = Scene.from_dict({"soil": full, "load": GOOD["load"]})
    assert s.soil.E == pytest.approx(1 / 2.1e-7) and s.soil.tolerance == 0.05
    assert Scene.from_dict(s.to_dict()) == s
    msg = problems({"soil": full | {"E": 1e7}, "load": GOOD["load"]})
    assert "soil.E" in msg and "contradicts" in msg
    msg = problems({"soil": full | {"tolerance": 1.5}, "load": GOOD["load"]})
    assert "soil.tolerance" in msg
    msg = problems(with_(soil={"hyperbolic_b": 1e-5}))
    assert "soil.hyperbolic_b" in msg and "only used with" in msg


def test_mohr_coulomb_needs_friction_and_refuses_uplift():
    plate_scene = with_(load=None, plate=PLATE) | {"load": {"pressure": 1e5}}
    msg = problems(plate_scene | {"interface": {"condition": "mohr_coulomb"}})
    assert "interface.tan_phi" in msg and "friction_angle" in msg
    msg = problems(plate_scene | {"interface": {"condition": "bonded", "tan_phi": 0.5}})
    assert "interface.tan_phi" in msg and "only used with" in msg
    uplift = with_(load=None, plate=PLATE) | {"load": {"pressure": -1e4},
                                              "interface": {"condition": "mohr_coulomb",
                                                            "tan_phi": 0.5}}
    msg = problems(uplift)
    assert "upward" in msg and "no tension" in msg
    # an anchored (bonded) foundation may be pulled up
    Scene.from_dict(uplift | {"interface": {"condition": "bonded"}})
    msg = problems(with_(load={"pressure": -1.0}))
    assert "load.pressure" in msg and "flexible load must press" in msg


def test_plate_and_wall_are_resolved_from_Kp_and_Kt():
    s = Scene.from_dict(with_(load=None, plate={"radius": 2.0, "Kp": 0.5, "E": 30e9, "nu": 0.2},
                              wall={"radius": 2.0, "Kt": 0.01, "height": 6.0, "E": 200e9,
                                    "nu": 0.3})
                        | {"load": {"pressure": 1e5}})
    assert s.Kp == pytest.approx(0.5, rel=1e-12) and s.Kt == pytest.approx(0.01, rel=1e-12)
    assert s.foundation_radius == 2.0 and s.load.load_radius == 2.0


def test_toml_file_with_nan_and_unknown_key(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(textwrap.dedent("""
        [soil]
        E = nan
        nu = 0.3
        [load]
        pressure = 1e5
        load_radius = 1.0
        radius = 2.0
    """))
    with pytest.raises(SceneError) as info:
        load_scene(f)
    msg = str(info.value)
    assert "soil.E" in msg and "finite" in msg
    assert "load.radius" in msg and "did you mean 'load_radius'" in msg


def test_not_toml_and_missing_file(tmp_path):
    bad = tmp_path / "x.toml"
    bad.write_text("[soil\nE = 1")
    with pytest.raises(SceneError, match="not valid TOML"):
        load_scene(bad)
    with pytest.raises(SceneError, match="no such scene file"):
        load_scene(tmp_path / "missing.toml")


def test_cli_bad_scene_exits_cleanly_without_traceback(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text("[soil]\nE = 1e7\nnu = 0.6\n[load]\npressure = 1e5\nload_radius = 1.0\n")
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "tankfx", "run", str(f), "--out", str(out)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "soil.nu" in proc.stderr and "Traceback" not in proc.stderr + proc.stdout
    assert not out.exists(), "nothing may be written for a refused scene"


def test_load_stages_from_a_scene_file(tmp_path):
    """[[stages]] tables: each the [load] with its keys changed, checked like [load]; a
    flexible load keeps its meshed circle; the stages survive to_dict / from_dict, as
    changes of [load] (so that a sweep over a load key reaches them)."""
    path = tmp_path / "path.toml"
    path.write_text(textwrap.dedent("""
        [soil]
        E = 10e6
        nu = 0.3
        [plate]
        radius = 1.0
        thickness = 0.5
        E = 30e9
        nu = 0.2
        [wall]
        radius = 1.0
        thickness = 0.01
        height = 5.0
        E = 200e9
        nu = 0.3
        [load]
        pressure = 10e3
        liquid_unit_weight = 9810.0
        [[stages]]
        [[stages]]
        liquid_height = 4.0
        [[stages]]
        pressure = 0.0
        liquid_height = 2.0
        """))
    s = load_scene(path)
    assert [(st.pressure, st.liquid_height) for st in s.stages] == [(10e3, 0.0), (10e3, 4.0),
                                                                    (0.0, 2.0)]
    assert all(st.liquid_unit_weight == 9810.0 for st in s.stages)
    assert Scene.from_dict(s.to_dict()) == s
    # a change of [load] reaches the stages that do not set that key themselves
    heavier = s.with_changes(load={"pressure": 20e3, "liquid_unit_weight": 1e4})
    assert [(st.pressure, st.liquid_unit_weight) for st in heavier.stages] == \
        [(20e3, 1e4), (20e3, 1e4), (0.0, 1e4)]
    tank = {**with_(GOOD, plate=PLATE, wall=WALL), "load": {"pressure": 10e3}}
    for stages, key, fix in (
            ({"pressure": 1e4}, "stages:", "[[stages]]"),
            ([{"pressur": 1e4}], "stages[1]", "did you mean 'pressure'"),
            ([{}, {"liquid_height": 9.0}], "stages[2]", "liquid_height"),
            ([{}, {"pressure": float("nan")}], "stages[2]", "finite")):
        text = problems({**tank, "stages": stages})
        assert key in text and fix in text, text
    text = problems({**GOOD, "stages": [{}, {"load_radius": 2.0}]})
    assert "stages[2].load_radius" in text and "meshed once" in text
