"""The coupled tank: plate (and wall) on the elastic half-space through the bonded or smooth
interface, against the limits and published solutions of the structure issue."""
import math

import numpy as np
import pytest

from tankfx import Scene, analyse

E_S, P = 10e6, 100e3


def tank(nu=0.3, Kp=1.0, condition="smooth", wall=None, embedment=0.0, load=None, **extra):
    data = {"soil": {"E": E_S, "nu": nu},
            "plate": {"radius": 1.0, "Kp": Kp, "E": 30e9, "nu": 0.3, "embedment": embedment},
            "interface": {"condition": condition}, "load": load or {"pressure": P}}
    if wall is not None:
        data["wall"] = {"radius": 1.0, "Kt": 0.1, "height": 3.0, "E": 30e9, "nu": 0.2} | wall
    data.update(extra)
    return Scene.from_dict(data)


def test_flexible_limit_is_boussinesq():
    """Kp = 1e-4, smooth: the plate no longer spreads the load, w0 and w_edge are those of
    the flexible load, 2 p a (1 - nu^2) / E and 4 p a (1 - nu^2) / (pi E), within 1 %."""
    r = analyse(tank(Kp=1e-4)).results
    assert r["w0"] == pytest.approx(2 * P * (1 - 0.09) / E_S, rel=1e-2)
    assert r["w_edge"] == pytest.approx(4 * P * (1 - 0.09) / (math.pi * E_S), rel=1e-2)


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.4])
def test_rigid_limit_smooth_and_bonded_punch(nu):
    """Kp = 1e3: a rigid punch. Smooth: w = P (1 - nu^2) / (2 a E) (Boussinesq); bonded:
    P = 4 G a w ln(3 - 4 nu) / (1 - 2 nu) (Mossakovskii 1954, Spence 1968)."""
    force = P * math.pi
    G = E_S / (2 * (1 + nu))
    smooth = analyse(tank(nu=nu, Kp=1e3, condition="smooth")).results
    bonded = analyse(tank(nu=nu, Kp=1e3, condition="bonded")).results
    assert smooth["w0"] == pytest.approx(force * (1 - nu**2) / (2 * E_S), rel=1e-2)
    factor = math.log(3 - 4 * nu) / (1 - 2 * nu)
    assert bonded["w0"] == pytest.approx(force / (4 * G * factor), rel=1e-2)
    for r in (smooth, bonded):
        assert r["wd"] < 1e-3 * r["w0"], "a Kp = 1000 plate must settle as a rigid body"
        assert r["equilibrium"]["contact_relative_error"] < 1e-8
        assert r["equilibrium"]["relative_error"] < 1e-8


def test_rigid_plate_centre_moment_converges_to_the_rigid_limit():
    """Kp = 1e3, smooth: the centre moment tends to that of a free plate under q and the
    rigid punch's contact pressure q a / (2 sqrt(a^2 - r^2)) (closed form in
    tankfx.verification.reference, 0.07736 q a^2 at nu_p = 0.3). The contact stress is singular at
    the
    edge, so M0 converges slower than w0: measured +0.38 % at the default mesh, +0.10 % with
    edge and near sizes halved (a plate of Kp = 1e4: +0.42 / +0.13 %)."""
    from tankfx.verification.reference import rigid_plate_centre_moment

    exact = rigid_plate_centre_moment(P, 1.0, 0.3)
    assert exact / P == pytest.approx(0.0773562, rel=1e-6)
    # the ring-load sum the closed form comes from, by quadrature (b = a sin t)
    t = np.linspace(0.0, math.pi / 2, 400_001)[1:]
    b = np.sin(t)
    ring = (1 - 1 / (2 * np.cos(t))) * 2 * math.pi * b * np.cos(t) * \
        (0.7 * (1 - b**2) + 2 * 1.3 * np.log(1 / b)) / (8 * math.pi)
    assert np.trapezoid(ring, t) == pytest.approx(exact / P, rel=1e-6)
    errors = []
    for refine in (1.0, 0.5):
        mesh = {"edge_size": 0.002 * refine, "near_size": 0.1 * refine}
        r = analyse(tank(Kp=1e3, condition="smooth", mesh=mesh)).results
        errors.append(r["M0"] / exact - 1)
    assert 0 < errors[0] < 6e-3
    assert 0 < errors[1] < errors[0] / 2.5, f"M0 does not converge: {errors}"


@pytest.mark.parametrize("Kp, w0, wd, M0", [(0.1, 1.954, 0.5572, 0.01462),
                                            (10.0, 1.588, 0.02378, 0.07470)])
def test_free_raft_against_brown_1969(Kp, w0, wd, M0):
    """Uniformly loaded free circular raft on a half-space, smooth contact, nu_p = 0.3 (Brown
    1969): settlements normalised by q a (1 - nu_s^2) / E_s, moment by q a^2, within 2 %."""
    r = analyse(tank(Kp=Kp)).results
    scale = P * 1.0 * (1 - 0.09) / E_S
    assert r["w0"] / scale == pytest.approx(w0, rel=2e-2)
    assert r["wd"] / scale == pytest.approx(wd, rel=2e-2)
    assert r["M0"] / (P * 1.0**2) == pytest.approx(M0, rel=2e-2)
    assert r["nondim"]["M0"] == pytest.approx(r["M0"] / P, rel=1e-12)
    assert r["nondim"]["Kp"] == pytest.approx(Kp, rel=1e-12)
    assert "wall" not in r["profiles"] and r["nondim"]["Kt"] is None


LIQUID = {"pressure": 50e3, "liquid_unit_weight": 9810.0, "liquid_height": 2.5}


@pytest.mark.parametrize("embedment, condition, tol", [(0.0, "smooth", 5e-3),
                                                       (0.3, "smooth", 5e-3),
                                                       (0.3, "bonded", 5e-3),
                                                       (0.0, "bonded", 2e-2)])
def test_rigid_junction_balances_moments(embedment, condition, tol):
    """a_t = a_p: the plate and wall meet at the rigid corner of the foundation (their faces'
    meeting point); about that corner the plate's moment equals the wall's base moment,
    M_p - N_p t_p / 2 = M_w - N_w t_w / 2 (membrane forces act on the mid-surfaces, half a
    thickness away). Bonded surface contact puts a singular shear right at the corner, and is
    checked more loosely. Vertical equilibrium holds to 1e-8."""
    sol = analyse(tank(Kp=1.0, condition=condition, wall={}, embedment=embedment,
                       load=LIQUID))
    r, j = sol.results, sol.results["junction"]
    assert j["M_plate_about_corner"] == pytest.approx(j["M_wall_about_corner"], rel=tol)
    # both faces carry the same displacement and rotation at the corner: a rigid joint
    plate, wall = r["profiles"]["plate"], r["profiles"]["wall"]
    assert plate["rotation"][-1] == pytest.approx(wall["rotation"][0], rel=1e-12)
    assert plate["u_r"][-1] == pytest.approx(wall["u_r"][0], rel=1e-12)
    applied = 50e3 * math.pi + 9810.0 * 2.5 * math.pi
    assert r["equilibrium"]["applied_load"] == pytest.approx(applied, rel=1e-14)
    assert r["equilibrium"]["contact_relative_error"] < 1e-8
    assert r["equilibrium"]["relative_error"] < 1e-8
    # hydrostatic wall: hoop tension = gamma (h - z) a well above the base
    z = np.array(wall["z"])
    k = np.argmin(abs(z - 2.0))
    assert wall["N_theta"][k] == pytest.approx(9810.0 * (2.5 - z[k]) * 1.0, rel=5e-2)


def test_wall_inside_the_plate_edge_is_a_rigid_T_joint():
    """a_t < a_p: plate, outer plate annulus and wall share the junction's displacement and
    rotation; the liquid presses only inside the wall; equilibrium to 1e-8."""
    s = tank(Kp=1.0, condition="bonded", wall={"radius": 0.8}, load=LIQUID)
    sol = analyse(s)
    r = sol.results
    plate = r["profiles"]["plate"]
    rr = np.array(plate["r"])
    k = np.where(np.isclose(rr, 0.8))[0]
    assert len(k) == 1
    assert plate["rotation"][k[0]] == pytest.approx(r["profiles"]["wall"]["rotation"][0])
    applied = 50e3 * math.pi + 9810.0 * 2.5 * math.pi * 0.8**2
    assert r["equilibrium"]["applied_load"] == pytest.approx(applied, rel=1e-14)
    assert r["equilibrium"]["contact_relative_error"] < 1e-8
    # moments about the corner balance over the three members at the T
    j = r["junction"]
    assert j["M_plate_about_corner"] == pytest.approx(j["M_wall_about_corner"], rel=2e-2)


def test_self_weight_only_when_asked():
    s0 = tank().with_changes(plate={"unit_weight": 24e3})
    s1 = s0.with_changes(load={"self_weight": True})
    r0, r1 = analyse(s0).results, analyse(s1).results
    weight = 24e3 * s0.plate.thickness * math.pi
    assert r0["equilibrium"]["applied_load"] == pytest.approx(P * math.pi, rel=1e-14)
    assert r1["equilibrium"]["applied_load"] == pytest.approx(P * math.pi + weight, rel=1e-14)
    assert r1["equilibrium"]["contact_relative_error"] < 1e-8
    assert r1["w0"] > r0["w0"]


def test_a_scene_without_a_wall_builds_no_wall():
    no_wall = analyse(tank(Kp=1.0)).results
    with_wall = analyse(tank(Kp=1.0, wall={}, load=LIQUID)).results
    assert set(no_wall["dofs"]) == {"soil", "structure", "total"}
    assert no_wall["dofs"]["structure"] < with_wall["dofs"]["structure"]
    assert no_wall["dofs"]["soil"] < with_wall["dofs"]["soil"], "no void region without a wall"
    assert "wall" not in no_wall["profiles"] and "junction" not in no_wall


def test_block_forms_assemble_as_nest_and_mpi_alike():
    """The blocks are kept, so a fieldsplit (kind="nest") sees the same operator as the
    monolithic matrix (kind="mpi") used with MUMPS: equal products with a random vector."""
    from dolfinx import fem
    from dolfinx.fem import petsc as fem_petsc

    from tankfx.model.tank import TankModel
    from tankfx.mesh import build_domain

    scene = tank(Kp=1.0, condition="bonded", wall={}, embedment=0.3, load=LIQUID,
                 mesh={"edge_size": 0.05, "near_size": 0.3})
    model = TankModel(scene, build_domain(scene))
    forms = fem.form(model.a, entity_maps=model.entity_maps)
    A = fem_petsc.assemble_matrix(forms, bcs=model.bcs, kind="mpi")
    A.assemble()
    N = fem_petsc.assemble_matrix(forms, bcs=model.bcs, kind="nest")
    N.assemble()
    x_mono, y_mono = A.createVecs()
    rng = np.random.default_rng(1)
    x_mono.array[:] = rng.standard_normal(x_mono.getLocalSize())
    A.mult(x_mono, y_mono)
    # the same product block by block: y_i = sum_j N_ij x_j (serial: blocks are contiguous)
    sizes = [N.getNestSubMatrix(i, i).getLocalSize()[0] for i in range(2)]
    bounds = np.cumsum([0] + sizes)
    parts = []
    for i in range(2):
        y_i = np.zeros(sizes[i])
        for j in range(2):
            block = N.getNestSubMatrix(i, j)
            if block is None or block.handle == 0:
                continue
            xj, yi = block.createVecs()
            xj.array[:] = x_mono.array[bounds[j]:bounds[j + 1]]
            block.mult(xj, yi)
            y_i += yi.array
        parts.append(y_i)
    np.testing.assert_allclose(np.concatenate(parts), y_mono.array, rtol=1e-12,
                               atol=1e-12 * np.abs(y_mono.array).max())


def test_settlement_summary_of_the_tank_codes():
    r = analyse(tank(Kp=1.0, condition="bonded", wall={"radius": 0.8}, load=LIQUID)).results
    ss, plate = r["settlement_summary"], r["profiles"]["plate"]
    assert ss["uniform_settlement"] == pytest.approx(r["w_mean"], rel=1e-12)
    k = int(np.argmin(np.abs(np.array(plate["r"]) - 0.8)))
    assert ss["shell_settlement"] == pytest.approx(plate["w"][k], rel=1e-9)
    assert ss["dish"] == pytest.approx(r["w0"] - plate["w"][k], rel=1e-9)
    assert ss["planar_tilt"] is None and "axisymmetric" in ss["note"]
