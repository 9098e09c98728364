"""Stiff and extreme cases: what the solver does at the ends of every parameter's range
(the table "Stiff and extreme cases" of docs/development/2026-11-26-error-against-time.md
has one row per test here).

Meshes are coarse (edge 0.01 a): the cases test behaviour at the extremes (limits,
monotonicity, residuals, refusals), not the last digit; the fine-mesh accuracy of the same
limits is in test_tank.py."""
import math

import numpy as np
import pytest

from conftest import COARSE, WATER_LOAD, small_tank
from tankfx import Scene, SolveError, analyse
from tankfx.laws import interface as ifc
from tankfx import SoilFailure
from tankfx.verification.reference import gradient_surface_settlement


def plate(Kp=1.0, condition="bonded", a=1.0, p=1e5, wall=None, **interface):
    data = {"soil": {"E": 10e6, "nu": 0.3},
            "plate": {"radius": a, "Kp": Kp, "E": 30e9, "nu": 0.2},
            "interface": {"condition": condition, **interface}, "load": {"pressure": p},
            "mesh": {k: v * a if k != "growth" else v for k, v in COARSE.items()},
            # (the extreme cases are the tests: a bonded interface's cohesion, a heavy rim)
            "accept": ["interface.cohesion", "wall.unit_weight"]}
    if wall:
        data["wall"] = {"radius": a, "height": 3.0 * a, "E": 30e9, "nu": 0.2, **wall}
    return Scene.from_dict(data)


def _finite(r):
    return all(np.isfinite(r[k]) for k in ("w0", "wd", "M0"))


def test_plate_rigidity_from_flexible_to_rigid():
    """Kp from 1e-4 to 1e4 (smooth contact): wd falls and M0 rises monotonically, w0 falls
    from Kp = 0.01 on, from Boussinesq's flexible w0 = 2 (1 - nu^2) p a / E to the rigid
    punch's pi (1 - nu^2) p a / (2 E); the 8 orders of magnitude of plate stiffness cost no
    accuracy: the residual stays at round-off. Below Kp = 0.01, w0 rises by up to 0.15 %
    above Boussinesq's before it falls: see test_a_slightly_stiff_plate_loads_its_centre."""
    nd = {Kp: analyse(plate(Kp, "smooth")).results for Kp in (1e-4, 1e-2, 1.0, 1e2, 1e4)}
    w0, wd, M0 = ([nd[k]["nondim"][q] for k in sorted(nd)] for q in ("w0", "wd", "M0"))
    assert all(b < a for a, b in zip(w0[1:], w0[2:])), w0
    assert w0[1] == pytest.approx(w0[0], rel=2e-3), w0
    assert all(b < a for a, b in zip(wd, wd[1:])), wd
    assert all(b > a for a, b in zip(M0, M0[1:])), M0
    assert w0[0] == pytest.approx(2 * (1 - 0.3**2), rel=1e-3)
    assert w0[-1] == pytest.approx(math.pi * (1 - 0.3**2) / 2, rel=5e-3)
    assert wd[-1] < 1e-4 * w0[-1]
    for r in nd.values():
        assert r["linear_solver"]["last_relative_residual"] < 1e-9
        assert r["equilibrium"]["contact_relative_error"] < 1e-9


def test_a_slightly_stiff_plate_loads_its_centre():
    """Why w0 first rises with Kp. The flexible load's surface bowl w_B ~ E(r/a) (complete
    elliptic integral) has every Taylor coefficient beyond r^2 negative, so its
    biharmonic is negative all over the plate: a plate that follows it needs the contact
    pressure q - D lap^2 w_B > q inside, balanced by relief in a ring near the edge. The
    centre then settles more than under the flexible load, until the edge concentration of
    a stiffer plate takes over (w0 falls from Kp ~ 0.05). Measured on the default mesh:
    w0 +0.016 / +0.146 % at Kp = 1e-3 / 1e-2, growing in proportion to Kp; the same on a
    mesh 4 x finer (+0.143 %) and with P3 (+0.147 %), so it is the model's, not the mesh's.
    Mean contact pressure over r < a/2 1.013-1.021 q (P3 / default / 4 x finer: the
    contact stress is less converged than w0), at most 0.93 q at 0.8-0.95 a."""
    def run(Kp, mesh=None):
        data = {"soil": {"E": 10e6, "nu": 0.3},
                "plate": {"radius": 1.0, "Kp": Kp, "E": 30e9, "nu": 0.2},
                "interface": {"condition": "smooth"}, "load": {"pressure": 1e5}}
        if mesh:
            data["mesh"] = mesh
        return analyse(Scene.from_dict(data)).results

    boussinesq = 2 * (1 - 0.3**2)
    rise = {Kp: run(Kp)["nondim"]["w0"] / boussinesq - 1 for Kp in (1e-3, 1e-2)}
    assert 1e-3 < rise[1e-2] < 2e-3
    assert 5 < rise[1e-2] / rise[1e-3] < 15, rise       # first order in the stiffness
    r = run(1e-2, {"degree": 3})
    assert r["nondim"]["w0"] / boussinesq - 1 == pytest.approx(rise[1e-2], rel=0.1)
    plate = r["profiles"]["plate"]
    x, p = np.array(plate["r"]), np.array(plate["contact_normal"]) / 1e5
    inner = x < 0.5
    mean = np.trapezoid(p[inner] * x[inner], x[inner]) / np.trapezoid(x[inner], x[inner])
    assert mean > 1.005, "the inner half carries more than the applied pressure"
    assert p[(x > 0.8) & (x < 0.95)].max() < 0.95, "relief near the edge"


def test_wall_rigidity_range():
    """Kt from 1e-5 to 1e3: a stiffer wall holds the plate's edge more (w0, wd and M0
    fall) and takes more moment at the junction; the residual stays small. The limits:
    towards Kt = 1e3 the results settle on the clamping wall's (the last two decades move
    them 3 % of the way from Kt = 1e-5, measured 2.9 %); at Kt = 1e-5 the wall is the
    wall-less plate's (on the default mesh: w0 +0.003 %, wd -0.09 %, M0 -0.08 %; the coarse
    mesh of this test resolves the wall-less plate's M0 only to 1.7 %, the wall refines
    the mesh at its foot)."""
    kts = (1e-5, 1e-3, 1e-1, 10.0, 1e3)
    res = [analyse(plate(wall={"Kt": Kt})).results for Kt in kts]
    for key in ("w0", "wd", "M0"):
        values = [r[key] for r in res]
        assert all(b < a for a, b in zip(values, values[1:])), (key, values)
        assert abs(values[-1] - values[-2]) < 0.05 * abs(values[0] - values[-2]), key
    M_wall = [abs(r["junction"]["M_wall"]) for r in res]
    assert all(b > a for a, b in zip(M_wall, M_wall[1:])), M_wall
    for r in res:
        assert r["linear_solver"]["last_relative_residual"] < 1e-7 and _finite(r)
    default = {"edge_size": 0.002, "near_size": 0.1}
    soft = analyse(plate(wall={"Kt": 1e-5}).with_changes(mesh=default)).results
    bare = analyse(plate().with_changes(mesh=default)).results
    for key in ("w0", "wd", "M0"):
        assert soft[key] == pytest.approx(bare[key], rel=2e-3), key


@pytest.mark.verify
def test_modulus_rising_from_almost_zero_at_the_surface():
    """E = E_s (1 + lambda h) with E_s = 10 kPa: at lambda = 50 /m the modulus doubles
    within 2 cm, and the mesh grades its elements from 0.25 / lambda at the surface
    (tankfx.mesh.SURFACE_GRADING): against the Riccati reference (tankfx.verification.reference;
    measured on the coarse mesh w0 -2.8e-5, w_edge -9.7e-4; before the grading -2.3 % in
    w0 on the default mesh). At lambda = 1e3 and 1e4 /m (a modulus doubling within 1 and
    0.1 mm) no matrix is singular, the residual stays small, and the grading's floor (the
    edge size) is said in a warning that names mesh.edge_size."""
    scene = {"soil": {"E": 1e4, "nu": 0.3, "E_gradient": 50.0},
             "load": {"pressure": 1e3, "load_radius": 1.0}, "mesh": COARSE}
    r = analyse(Scene.from_dict(scene)).results
    w0, w_edge = gradient_surface_settlement(1e3, 1.0, [0.0, 1.0], 1e4, 50.0, 0.3,
                                             steps=150, points=8)
    assert r["w0"] == pytest.approx(w0, rel=2e-4)
    assert r["w_edge"] == pytest.approx(w_edge, rel=3e-3)
    assert not r["warnings"]
    for lam in (1e3, 1e4):
        scene["soil"]["E_gradient"] = lam
        r = analyse(Scene.from_dict(scene)).results
        assert r["linear_solver"]["last_relative_residual"] < 1e-9
        assert r["equilibrium"]["relative_error"] < 1e-9
        assert any("mesh.edge_size" in w for w in r["warnings"]), r["warnings"]


def test_incompressible_gibson_soil_settles_like_winkler_springs():
    """Gibson (1967, Geotechnique 17, 58-67): an incompressible half-space whose shear
    modulus grows from zero as m z settles under a uniform load by exactly p / (2 m) where
    loaded and not at all beside it. E = E_s (1 + lambda h) at nu = 0.5 (mixed form) is
    that soil with m = E_s lambda / 3, plus a surface modulus E_s whose share falls as
    1 / (lambda a): measured w0 -2.0e-3 at lambda a = 1e3, -2.0e-4 at 1e4, w(1.5 a)
    5.7e-4 / 5.7e-5 of p / 2m; the step at the load's edge is half-way (0.52 / 0.50)."""
    p, a = 1e3, 1.0
    for lam in (1e3, 1e4):
        tol = 3.0 / (lam * a)
        r = analyse(Scene.from_dict({
            "soil": {"E": 1e4, "nu": 0.5, "E_gradient": lam},
            "load": {"pressure": p, "load_radius": a}, "mesh": COARSE})).results
        w_gibson = p / (2 * 1e4 * lam / 3)
        assert r["w0"] == pytest.approx(w_gibson, rel=tol)
        surface = r["profiles"]["surface"]
        w = np.interp([0.5 * a, 1.5 * a, 3 * a], surface["r"], surface["w"]) / w_gibson
        assert w[0] == pytest.approx(1.0, abs=3 * tol)
        assert abs(w[1]) < tol and abs(w[2]) < tol / 10
        assert r["linear_solver"]["last_relative_residual"] < 1e-9


@pytest.fixture(scope="module")
def bonded():
    return analyse(plate()).results


@pytest.mark.parametrize("factor, warns, changes", [
    (1e-2, "compliance adds about", 0.05),     # soft: 2.4 % more M0, and said so
    (1e-1, "compliance adds about", 0.005),
    (1.0, None, 0.0),
    (1e1, None, 0.006),                        # the physical range: within 0.6 %
    (1e2, "point by point", 0.03),             # over-stiff: moments shift, and said so
])
def test_penalty_stiffness_range(bonded, monkeypatch, factor, warns, changes):
    monkeypatch.setattr(ifc, "PENALTY_FACTOR", factor * ifc.PENALTY_FACTOR)
    r = analyse(plate()).results
    for key in ("w0", "wd", "M0"):
        assert r[key] == pytest.approx(bonded[key], rel=changes, abs=1e-300), key
    if warns is None:
        assert r["warnings"] == []
    else:
        assert r["warnings"] and all(warns in w for w in r["warnings"])
        assert all("interface.normal_stiffness" in w or "interface.shear_stiffness" in w
                   for w in r["warnings"])


def test_penalty_far_too_stiff_is_refused_by_the_residual_check(monkeypatch):
    """1e6 times the default: the solve loses 9 digits; the residual check refuses the
    numbers rather than report them."""
    monkeypatch.setattr(ifc, "PENALTY_FACTOR", 1e6 * ifc.PENALTY_FACTOR)
    with pytest.raises(SolveError, match="ill-conditioned"):
        analyse(plate())


@pytest.mark.verify
def test_penalty_too_stiff_for_a_mohr_coulomb_interface_is_refused(monkeypatch):
    """A Mohr-Coulomb interface 1e3 times stiffer than the default (embedded 1 m tank, water
    load, tan phi = 0.5): the element tractions change sign from solve to solve, the
    cycling elements were held separated while the soil pressed into them (by up to 47 % of
    the largest displacement; legitimate holds at a contact zone's edge: 0.25 % at most),
    and the numbers were 26 % (w0) and 130 % (M0) off. Refused, naming the keys. At 1e2
    times the default: no element held, the default's numbers within 0.1 %; node states
    hold at 1e3 times."""
    data = small_tank(load=WATER_LOAD,
                      interface={"condition": "mohr_coulomb", "friction_angle": 26.6})
    default = analyse(Scene.from_dict(data)).results
    monkeypatch.setattr(ifc, "PENALTY_FACTOR", 1e2 * ifc.PENALTY_FACTOR)
    stiff = analyse(Scene.from_dict(data)).results
    assert stiff["interface"]["frozen_elements"] == 0
    for key in ("w0", "wd", "M0"):
        assert stiff[key] == pytest.approx(default[key], rel=1e-3), key
    monkeypatch.setattr(ifc, "PENALTY_FACTOR", 10 * ifc.PENALTY_FACTOR)
    with pytest.raises(SolveError, match="soil presses into them") as err:
        analyse(Scene.from_dict(data))
    assert "interface.normal_stiffness" in str(err.value) and err.value.history
    # one state per node: the tractions at the trace's nodes do not flip
    node = analyse(Scene.from_dict(data | {"interface": {**data["interface"],
                                                         "states": "node"}})).results
    assert node["interface"]["frozen_elements"] == 0
    assert node["w0"] == pytest.approx(default["w0"], rel=1e-3)


@pytest.mark.parametrize("keys, limit", [
    ({"tan_phi": 1e-6}, "smooth"),
    ({"tan_phi": 1e3}, "bonded"),
    ({"tan_phi": 0.0, "cohesion": 1e12}, "bonded"),
])
def test_extreme_interface_strengths(bonded, keys, limit):
    """A vanishing friction is smooth, an enormous friction or cohesion is bonded (where
    the bonded plate is in compression everywhere): converged, in a few iterations; with
    element states to 1e-5, with node states (the default) to the 2 % by which their lumped
    Gauss-Lobatto rule moves M0 on this coarse mesh (measured 0.85 % smooth, 1.0 % bonded;
    0.2-0.26 % on the default mesh, tests/test_interface.py)."""
    ref = bonded if limit == "bonded" else analyse(plate(condition="smooth")).results
    for states, rel in (("element", 1e-5), ("node", 2e-2)):
        r = analyse(plate(condition="mohr_coulomb", states=states, **keys)).results
        assert r["interface"]["converged"] and r["interface"]["iterations"] <= 5
        for key in ("w0", "wd", "M0"):
            assert r[key] == pytest.approx(ref[key], rel=rel), (states, key)


def test_nearly_full_separation():
    """A weightless plate carrying only its wall's weight (a rim load), on a Mohr-Coulomb
    interface: the more flexible the plate, the more of it lifts off, until only a ring
    under the wall touches (measured: 73 / 88 / 94 % of the radius separated at Kp = 1e-2 /
    1e-3 / 1e-4, the centre rising). Converged in a few iterations, no tension, and the
    contact still carries the whole load."""
    separated = []
    for Kp in (1e-2, 1e-3, 1e-4):
        s = plate(Kp=Kp, condition="mohr_coulomb", tan_phi=0.5,
                  wall={"Kt": 0.1, "unit_weight": 2e6})
        r = analyse(s.with_changes(load={"pressure": 0.0, "self_weight": True})).results
        assert r["interface"]["converged"] and r["interface"]["iterations"] <= 8
        assert all(np.isfinite(r[k]) for k in ("w0", "wd", "M0"))
        normal = np.array(r["profiles"]["plate"]["contact_normal"])
        assert normal.min() >= -1e-9 * normal.max(), "tension in the contact"
        assert r["equilibrium"]["contact_relative_error"] < 1e-6
        separated.append(r["interface"]["separated_length"]["plate"])
    assert separated[0] > 0.6 and separated[-1] > 0.9
    assert separated == sorted(separated), separated


HYPER = {"model": "hyperbolic", "hyperbolic_a": 2.1e-7, "hyperbolic_b": 1e-5, "nu": 0.3}


@pytest.mark.verify
def test_loads_just_below_and_above_the_soils_capacity():
    """The flexible load on Kondner's soil (1/b = 100 kPa ultimate deviator): 150 kPa
    converges with a few cells at the ultimate deviator, reported; 200 kPa cannot be
    carried and ends with the soil-failure message and the iteration history, within the
    iteration bound, never NaN, saying that this is the secant model's limit, not the
    ground's bearing capacity, and where that is computed."""
    def load(p):
        return Scene.from_dict({"soil": HYPER, "load": {"pressure": p, "load_radius": 1.0},
                                "mesh": COARSE})

    below = analyse(load(150e3)).results
    assert below["soil"]["converged"] and below["soil"]["cells_at_ultimate"] > 0
    assert np.isfinite(below["w0"])
    with pytest.raises(SoilFailure,
                       match="cells of the soil under the foundation's edge") as failure:
        analyse(load(200e3))
    assert len(failure.value.history) == 40          # the scene's max_iterations
    assert all(np.isfinite(h["max_misfit"]) for h in failure.value.history)
    # what it is: the secant model's limit, not the ground's bearing capacity
    assert "This is where the secant iteration of Kondner's hyperbolic soil stops, which is " \
           "the model's limit" in str(failure.value)
    assert "soil.model = \"mohr_coulomb\" with [analysis] collapse = \"load\"" in \
        str(failure.value)


def test_scale_invariance():
    """A plate of 0.5 m under 1 Pa and one of 100 m under 10 MPa (linear, same Kp): the
    non-dimensional results are the same."""
    small = analyse(plate(a=0.5, p=1.0)).results["nondim"]
    large = analyse(plate(a=100.0, p=1e7)).results["nondim"]
    for key in ("w0", "wd", "M0"):
        assert large[key] == pytest.approx(small[key], rel=1e-4), key


@pytest.mark.parametrize("condition", ["smooth", "bonded"])
def test_rigid_punch_on_incompressible_soil(condition):
    """nu_s = 0.5 exactly (undrained clay), mixed form: a rigid plate settles
    P (1 - nu^2) / (2 a E), bonded or smooth alike (an incompressible surface does not move
    radially under a normal load, so bonding changes nothing)."""
    data = {"soil": {"E": 10e6, "nu": 0.5},
            "plate": {"radius": 1.0, "Kp": 1e3, "E": 30e9, "nu": 0.2},
            "interface": {"condition": condition}, "load": {"pressure": 1e5}, "mesh": COARSE}
    r = analyse(Scene.from_dict(data)).results
    assert "soil_pressure" in r["dofs"]
    assert r["w0"] == pytest.approx(1e5 * math.pi * (1 - 0.25) / (2 * 10e6), rel=1e-2)
    assert r["wd"] < 1e-3 * r["w0"]
    assert r["equilibrium"]["contact_relative_error"] < 1e-9
