"""Overturning: the first Fourier harmonic of soil, shells and interface (tankfx.laws.harmonic,
tankfx.model.overturning) against rigid-body kinematics, plate and beam theory, the antisymmetric
Boussinesq problem, Borowicka's rocking disc and the equilibrium of moment and shear."""
import math

import numpy as np
import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI

from conftest import COARSE, HYPERBOLIC_SOIL, small_tank
from tankfx import Scene, analyse
from tankfx.laws.harmonic import shell_strains, soil_strain
from tankfx.verification.rigs import StandaloneHarmonicShell
from tankfx.verification import reference as ref
from tankfx.fem.lines import line_mesh
from tankfx.laws.shell import tangent
from tankfx.fem.evaluate import evaluate_at
from tankfx.scene.sections import SceneError


def _surface_plate(Kp, condition="smooth", nu=0.3, mesh=COARSE, **load):
    return {"soil": {"E": 10e6, "nu": nu},
            "plate": {"radius": 1.0, "Kp": Kp, "E": 30e9, "nu": 0.2},
            "interface": {"condition": condition},
            "load": {"pressure": 10e3, **load}, "mesh": mesh}


# ----------------------------------------------------------------------- kinematics
@pytest.mark.parametrize("offset", [0.0, 0.05])
def test_rigid_motions_strain_nothing(offset):
    """A translation along x and a rotation about y strain neither the shell (a cone,
    Koiter's bending strains, with and without the face offset) nor the soil: the
    harmonic's forms do no work in a rigid motion (what makes moment equilibrium exact)."""
    pts = np.array([[0.5, 0.0], [1.0, 0.4], [1.5, 1.0]])
    msh, _ = line_mesh(MPI.COMM_SELF, pts)
    x = ufl.SpatialCoordinate(msh)
    t = tangent(msh)
    dx = ufl.Measure("dx", domain=msh, metadata={"quadrature_degree": 6})
    one, zero = fem.Constant(msh, 1.0), fem.Constant(msh, 0.0)
    # (A, Z), V, beta = d(u.n)/ds
    motions = {"translation": (ufl.as_vector([one, zero]), -one, zero),
               "rotation": (ufl.as_vector([x[1], -x[0]]), -x[1], -one)}
    for name, (u, V, beta) in motions.items():
        strains = shell_strains(u, V, beta, x[0], t, offset)
        total = fem.assemble_scalar(fem.form(sum(e**2 for e in strains) * dx))
        assert abs(total) < 1e-24, (name, total)
    # a bending mode is not rigid: the check can fail
    bent = shell_strains(ufl.as_vector([zero, x[0] ** 2]), zero, 2 * x[0], x[0],
                            t, offset)
    assert fem.assemble_scalar(fem.form(sum(e**2 for e in bent) * dx)) > 1e-2

    from dolfinx.mesh import create_unit_square
    sq = create_unit_square(MPI.COMM_SELF, 2, 2)
    y = ufl.SpatialCoordinate(sq)
    r = y[0] + 0.5
    dxs = ufl.Measure("dx", domain=sq, metadata={"quadrature_degree": 4})
    two, nil = fem.Constant(sq, 2.0), fem.Constant(sq, 0.0)
    for U in (ufl.as_vector([two, nil, nil]), ufl.as_vector([2.0 * y[1], -r, nil])):
        eps = soil_strain(U, r)
        assert abs(fem.assemble_scalar(fem.form(ufl.inner(eps, eps) * dxs))) < 1e-26


# ----------------------------------------------------------------------- structure
def test_clamped_plate_under_antisymmetric_load():
    """A clamped circular plate under q (r/a) cos theta: w = q a^4 rho (1 - rho^2)^2 /
    (192 D) cos theta (Timoshenko & Woinowsky-Krieger, Sec. 19, antisymmetric load) and
    its moment; 4th order in the deflection, 2nd in the moment."""
    a, t, E, nu, q = 1.0, 0.02, 2e11, 0.3, 1e4
    D = E * t**3 / (12 * (1 - nu**2))
    rho = np.linspace(0, 1, 11)[1:-1]
    A = q * a**4 / (192 * D)
    w_ref = A * rho * (1 - rho**2) ** 2
    f, f1, f2 = rho - 2 * rho**3 + rho**5, 1 - 6 * rho**2 + 5 * rho**4, -12 * rho + 20 * rho**3
    M_ref = -D * A / a**2 * (f2 + nu * (f1 / rho - f / rho**2))       # sagging positive
    errors = []
    for n in (20, 40):
        shell = StandaloneHarmonicShell(
            np.column_stack([np.linspace(0, a, n + 1), np.zeros(n + 1)]), E, nu, t,
            {lambda x: np.isclose(x[0], 0.0): ("Z", "S"),
             lambda x: np.isclose(x[0], a): ("D", "Z", "S", "beta")},
            lambda u, V, x: -q * x[0] / a * u[1], comm=MPI.COMM_SELF)
        F = shell.resultants()
        P = np.column_stack([rho * a, 0 * rho])
        w = -evaluate_at(F["u"], P)[:, 1]
        M = evaluate_at(F["M_s"], P)[:, 0]
        errors.append((np.max(abs(w - w_ref)) / w_ref.max(),
                       np.max(abs(M - M_ref)) / abs(M_ref).max()))
    assert errors[1][0] < 2e-7 and errors[0][0] / errors[1][0] > 12
    assert errors[1][1] < 2e-3 and errors[0][1] / errors[1][1] > 3.5


def test_cantilever_cylinder_is_a_thin_tube_beam():
    """A cylinder clamped at its foot under a horizontal pull V at its top: away from the
    ends the membrane state of beam theory, N_z = -V (H - z) / (pi R^2) cos theta (the side
    pulled towards in compression), N_z_theta = -V / (pi R) sin theta, and the neutral axis
    (theta = 90 deg, u_x = -V) moves as a Timoshenko beam with shear area pi R t."""
    R, H, t, E, nu, V = 10.0, 30.0, 0.02, 2e11, 0.3, 1e6
    G, inertia = E / (2 * (1 + nu)), math.pi * R**3 * t
    z = np.linspace(0, H, 121)
    qh = V / (2 * math.pi * R)
    shell = StandaloneHarmonicShell(
        np.column_stack([np.full_like(z, R), z]), E, nu, t,
        {lambda x: np.isclose(x[1], 0.0): ("D", "Z", "S", "beta")},
        lambda u, V_, x: 0.0 * u[0],
        edge_load=lambda u, V_, x: ufl.conditional(ufl.gt(x[1], H / 2), qh * (u[0] - V_), 0.0),
        comm=MPI.COMM_SELF)
    F = shell.resultants()
    zz = np.array([0.3, 0.5, 0.7]) * H
    P = np.column_stack([np.full(3, R), zz])
    np.testing.assert_allclose(evaluate_at(F["N_s"], P)[:, 0], -V * (H - zz) / (math.pi * R**2),
                               rtol=1e-5)
    np.testing.assert_allclose(evaluate_at(F["N_s_theta"], P)[:, 0], -V / (math.pi * R),
                               rtol=1e-5)
    beam = V * zz**2 * (3 * H - zz) / (6 * E * inertia) + V * zz / (G * math.pi * R * t)
    np.testing.assert_allclose(-evaluate_at(F["V"], P)[:, 0], beam, rtol=5e-3)


def test_the_walls_bending_layer_at_a_clamped_foot():
    """The same cylinder under a couple on its top (vertical line load -M cos / (pi R^2)):
    the membrane force N_z = -M / (pi R^2) cos theta, and at the clamped foot, where the
    clamp holds the Poisson expansion, a bending moment |M_z| = nu |N_z| t / (2 sqrt(3 (1 -
    nu^2))) (Timoshenko's semi-infinite cylinder with a clamped edge: the bending layer is
    axisymmetric to O(1 / (beta R))^2, here 1.2e-3): Koiter's bending strains of the
    harmonic against the thin-shell closed form."""
    R, H, t, E, nu, M = 10.0, 10.0, 0.02, 2e11, 0.3, 1e6
    z = np.concatenate([np.linspace(0, 1.0, 201), np.linspace(1.0, H, 91)[1:]])
    qz = M / (math.pi * R**2)
    shell = StandaloneHarmonicShell(
        np.column_stack([np.full_like(z, R), z]), E, nu, t,
        {lambda x: np.isclose(x[1], 0.0): ("D", "Z", "S", "beta")},
        lambda u, V, x: 0.0 * u[0],
        edge_load=lambda u, V, x: ufl.conditional(ufl.gt(x[1], H / 2), -qz * u[1], 0.0),
        comm=MPI.COMM_SELF)
    F = shell.resultants()
    N_z = evaluate_at(F["N_s"], np.array([[R, H / 2]]))[0, 0]
    assert N_z == pytest.approx(-qz, rel=1e-6)
    M_foot = evaluate_at(F["M_s"], np.array([[R, 0.0]]))[0, 0]
    reference = nu * abs(N_z) * t / (2 * math.sqrt(3 * (1 - nu**2)))
    assert abs(abs(M_foot) / reference - 1) < 1e-3            # (measured 2.3e-4)


# ----------------------------------------------------------------------- soil
def test_flexible_plate_under_moment_is_the_antisymmetric_boussinesq_load():
    """A plate of negligible stiffness (Kp = 1e-6; at 1e-4 its edge still settles 2.5 % more)
    on a smooth interface passes the moment's pressure 4 M r cos theta / (pi a^4) to the
    soil: the settlement amplitude and the vertical stress below the edge are those of the
    first harmonic of Boussinesq's problem (reference.antisymmetric_surface_settlement,
    antisymmetric_vertical_stress)."""
    M = 1e5
    sol = analyse(Scene.from_dict(_surface_plate(1e-6, overturning_moment=M)))
    o = sol.results["overturning"]
    plate = o["profiles"]["plate"]
    r, w = np.asarray(plate["r"]), np.asarray(plate["w"])
    w_ref = ref.antisymmetric_surface_settlement(4 * M / math.pi, 1.0, 10e6, 0.3, r)
    inner = (r > 0.05) & (r < 0.9)
    assert np.max(np.abs(w - w_ref)[inner]) < 5e-4 * w_ref.max()
    edge = np.argmin(abs(r - 1.0))
    assert abs(w[edge] / w_ref[edge] - 1) < 0.01
    # the soil's vertical stress amplitude below the load's edge (r = a), against
    # Boussinesq's (reference.antisymmetric_vertical_stress): 0.93 % (default mesh 0.42 %)
    line = o["profiles"]["soil_line"]
    depth, s_zz = np.asarray(line["depth"]), np.asarray(line["sigma_zz"])
    s_ref = ref.antisymmetric_vertical_stress(4 * M / math.pi, 1.0, 1.0, depth)
    deep = depth >= 0.25
    assert np.max(np.abs(s_zz - s_ref)[deep]) < 0.015 * np.max(np.abs(s_ref))
    # toe and heel: the axisymmetric 10 kPa's stress plus and minus it
    np.testing.assert_allclose(np.asarray(line["sigma_zz_toe"]) - line["sigma_zz_heel"],
                               2 * s_zz, rtol=1e-12, atol=1e-9)
    assert o["equilibrium"]["moment_relative_error"] < 1e-8


@pytest.mark.parametrize("nu", [0.3, 0.5])
def test_rigid_disc_rocks_as_borowickas(nu):
    """A rigid plate (Kp = 1e3) on a smooth interface: M / tilt = 4 E a^3 / (3 (1 - nu^2))
    (Borowicka), also at nu = 0.5 (the harmonic's mixed form), and the contact pressure
    3 M r / (2 pi a^3 sqrt(a^2 - r^2)) for 0.1 < r / a < 0.9."""
    M = 1e5
    sol = analyse(Scene.from_dict(_surface_plate(1e3, nu=nu, overturning_moment=M)))
    o = sol.results["overturning"]
    K = ref.rigid_disc_rocking_stiffness(10e6, nu, 1.0)
    assert abs(o["rocking_stiffness"] / K - 1) < 5e-3        # (default mesh: 6e-4)
    assert o["rocking_stiffness_rigid_disc"] == pytest.approx(K)
    assert o["nondim"]["rocking_stiffness"] == pytest.approx(4 / 3 * o["rocking_stiffness"] / K)
    plate = o["profiles"]["plate"]
    # (the contact stresses are cell averages, at every second station the cell's
    # midpoint between its vertices: against the reference's average over the ring)
    r, sn = np.asarray(plate["r"]), np.asarray(plate["contact_normal"])
    errors = [sn[i] / ref.ring_average(lambda x: ref.rigid_disc_rocking_pressure(M, 1.0, x),
                                       r[i - 1], r[i + 1]) - 1
              for i in range(1, len(r) - 1, 2) if 0.1 < r[i] < 0.9]
    # (coarse mesh: 3.7 % in its first, 0.24 a wide cell, 0.7-1.6 % beyond 0.5 a; the
    # default mesh 1.2 % at most, where the element size changes)
    assert np.max(np.abs(errors)) < 0.04
    assert np.max(np.abs(errors[len(errors) // 2:])) < 0.02
    # (the tractions are the penalty times jumps of a rigid plate: 1.5e-8 at nu = 0.5)
    assert o["equilibrium"]["moment_relative_error"] < 1e-7
    # under its 10 kPa the whole disc is one contact zone, whose heel side loses its net
    # force at 4 P a / (3 pi M) (the closed forms' zone integral; measured +2.9 % on this
    # mesh, +1.7 % on the default one: the element averages at the singular edge)
    P = 10e3 * math.pi
    assert o["uplift"]["zone"] == [0.0, 1.0]
    assert o["uplift"]["onset_factor"] == pytest.approx(4 * P / (3 * math.pi * M), rel=0.04)


# ----------------------------------------------------------------------- the tank
@pytest.mark.parametrize("condition", ["bonded", "mohr_coulomb"])
def test_embedded_tank_balances_the_moment_and_the_shear(condition):
    """The embedded 1 m tank (wall, pit faces, plate) under M and V: the soil's tractions
    on the structure resist both (1e-8), and the wall carries the base moment of its top
    loads as a tube beam, N_z pi R r_m = -(M - V (H - z)) at mid-height (r_m the
    mid-surface's radius; 0.1 %); serial and axisymmetric parts unchanged by it."""
    ifc = {"condition": condition, **({"tan_phi": 0.5} if condition != "bonded" else {})}
    M, V = 3e4, 1e4
    base = small_tank(interface=ifc)
    sol = analyse(Scene.from_dict(base | {"load": {"pressure": 50e3, "overturning_moment": M,
                                                   "base_shear": V}}))
    res = sol.results
    o = res["overturning"]
    assert o["equilibrium"]["moment_relative_error"] < 1e-8
    assert o["equilibrium"]["shear_relative_error"] < 1e-8
    assert o["relative_residual"] < 1e-8
    wall = o["profiles"]["wall"]
    z, Nz = np.asarray(wall["z"]), np.asarray(wall["N_z"])
    H, R = 3.0, 1.0
    t_wall = Scene.from_dict(base).wall.thickness
    r_m = R - t_wall / 2
    zm = 0.6 * H
    beam = -(M - V * zm) / (math.pi * R * r_m)
    assert abs(np.interp(zm, z, Nz) / beam - 1) < 1e-3
    # the first harmonic leaves the axisymmetric solution as it was
    plain = analyse(Scene.from_dict(base)).results
    assert res["w0"] == pytest.approx(plain["w0"], rel=1e-12)
    assert res["M0"] == pytest.approx(plain["M0"], rel=1e-12)
    # toe and heel: the axisymmetric state plus and minus the amplitude
    assert o["toe"]["max_contact_normal"] > max(res["profiles"]["plate"]["contact_normal"])
    assert res["settlement_summary"]["planar_tilt"] == o["tilt"] > 0
    assert o["wall_foot"]["N_z_toe"] < o["wall_foot"]["N_z_heel"]
    # the joint's bending: the amplitude is the wall profile's at its foot, toe and heel
    # the axisymmetric moment plus and minus it
    jn = o["junction"]
    assert jn["M_wall_amplitude"] == pytest.approx(wall["M_z"][0], rel=1e-12)
    for member in ("wall", "plate"):
        assert jn[f"M_{member}_toe"] + jn[f"M_{member}_heel"] == pytest.approx(
            2 * res["junction"][f"M_{member}"], rel=1e-9)
        assert jn[f"M_{member}_toe"] - jn[f"M_{member}_heel"] == pytest.approx(
            2 * jn[f"M_{member}_amplitude"], rel=1e-9)


def test_uplift_of_the_heel_is_reported():
    """A contact zone whose net force on the heel side vanishes lifts as a whole: the
    results and a warning say so, with the multiple of the moment at which it happens
    (``onset_factor``, the same load for both moments: both parts are linear); a moderate
    moment gives neither. Local tension at a zone's edge is reported apart (no warning)."""
    small = analyse(Scene.from_dict(_surface_plate(1.0, overturning_moment=1e3))).results
    assert not small["overturning"]["uplift"]["lifts"]
    assert not any("overturning" in w for w in small["warnings"])
    big = analyse(Scene.from_dict(_surface_plate(1.0, overturning_moment=3e4))).results
    u = big["overturning"]["uplift"]
    assert u["lifts"] and big["overturning"]["heel"]["min_contact_normal"] < 0
    assert u["zone"] == [0.0, 1.0] and u["local_tension"]
    onset = [res["overturning"]["uplift"]["onset_factor"] for res in (small, big)]
    assert onset[0] > 1 > onset[1]
    assert onset[0] * 1e3 == pytest.approx(onset[1] * 3e4, rel=1e-8)
    assert any("heel" in w and "load.overturning_moment" in w for w in big["warnings"])


def test_heel_uplift_of_a_rigid_disc_and_of_a_zone_beside_a_separated_band():
    """heel_uplift on closed forms: the rigid disc's contact P / (2 pi a sqrt(a^2 - r^2))
    and amplitude 3 M r / (2 pi a^3 sqrt(...)) lift as a zone at M = 4 P a / (3 pi) (its
    edge opens at M = P a / 3); two zones either side of a separated band, each with its
    own onset, the band itself none."""
    from tankfx.results.overturning import heel_uplift

    a, P, M = 1.0, 1e5, 1e4
    r = np.linspace(0.0, a * (1 - 1e-6), 200001)
    root = np.sqrt(a**2 - r**2)
    zones = heel_uplift(r, P / (2 * math.pi * a * root), 3 * M * r / (2 * math.pi * a**3 * root))
    assert len(zones) == 1
    assert zones[0]["onset_factor"] == pytest.approx(4 * P * a / (3 * math.pi * M), rel=2e-3)
    r = np.linspace(0.0, 3.0, 301)
    sn0 = np.where((r > 1.0) & (r < 2.0), 0.0, 1.0)
    sn1 = np.where(r >= 2.0, 2.0, 0.1)
    zones = heel_uplift(r, sn0, sn1)
    assert [(z["r_min"], z["r_max"]) for z in zones] == [(0.0, 1.0), (2.0, 3.0)]
    assert [z["onset_factor"] for z in zones] == pytest.approx([10.0, 0.5])


def test_nonlinear_soil_rocks_on_its_secant_moduli():
    """The harmonic uses the converged secant moduli: Kondner's soil of negligible b is the
    linear soil of E = 1/a (1e-6); the paper's b softens the soil under the load, and the
    tank rocks more."""
    def tilt(soil):
        d = small_tank(soil=soil)
        d["load"] = {"pressure": 50e3, "overturning_moment": 2e4}
        d["accept"] = ["soil.hyperbolic_b"]       # (a strength too large to matter)
        return analyse(Scene.from_dict(d)).results["overturning"]["tilt"]

    a = HYPERBOLIC_SOIL["hyperbolic_a"]
    linear = tilt({"E": 1.0 / a, "nu": 0.3})
    assert tilt({**HYPERBOLIC_SOIL, "hyperbolic_b": 1e-14}) == pytest.approx(linear, rel=1e-6)
    assert tilt(HYPERBOLIC_SOIL) > 1.02 * linear


def test_overturning_needs_a_plate():
    with pytest.raises(SceneError, match="load.overturning_moment.*plate"):
        Scene.from_dict({"soil": {"E": 1e7, "nu": 0.3},
                         "load": {"pressure": 1e3, "load_radius": 1.0,
                                  "overturning_moment": 1e3}})
    with pytest.raises(SceneError, match="load.base_shear"):
        Scene.from_dict({"soil": {"E": 1e7, "nu": 0.3},
                         "load": {"pressure": 1e3, "load_radius": 1.0, "base_shear": 1e3}})
    with pytest.raises(SceneError, match="overturning_moment"):
        Scene.from_dict(_surface_plate(1.0, overturning_moment=float("nan")))


def test_a_sweep_over_the_overturning_moment_tabulates_the_tilt(tmp_path):
    """A sweep's axis may be the overturning load; its table then has the tilt, the rocking
    stiffness and the uplift's onset (the tilt in proportion to the moment, the stiffness
    the same)."""
    import csv

    from tankfx.studies.sweep import Sweep, scene_with, run_sweep

    base = Scene.from_dict(_surface_plate(1.0, overturning_moment=1e3))
    cases = [{"load.overturning_moment": m} for m in (1e3, 2e3)]
    sweep = Sweep(base=base, axes={"load.overturning_moment": [1e3, 2e3]}, cases=cases,
                  scenes=[scene_with(base, c) for c in cases])
    rows = run_sweep(sweep, tmp_path / "out", MPI.COMM_SELF)
    with (tmp_path / "out" / "table.csv").open() as f:
        table = list(csv.DictReader(f))
    assert [float(r["overturning.tilt"]) for r in table] == pytest.approx(
        [rows[0]["overturning.tilt"], 2 * rows[0]["overturning.tilt"]], rel=1e-9)
    assert float(table[1]["overturning.rocking_stiffness"]) == pytest.approx(
        float(table[0]["overturning.rocking_stiffness"]), rel=1e-9)
    assert float(table[0]["overturning.uplift.onset_factor"]) == pytest.approx(
        2 * float(table[1]["overturning.uplift.onset_factor"]), rel=1e-8)
    # its chart has the tilt's panel (four panels: wider than the three of w0, wd, M0)
    import pyvista

    from tankfx.results.charts import DPI, PANEL

    chart = pyvista.read(tmp_path / "out" / "charts.png")
    assert chart.dimensions[0] == round(4 * PANEL[0] * DPI)


def _steel_on_ringwall():
    from pathlib import Path

    from tankfx import load_scene

    root = Path(__file__).resolve().parents[1]
    return load_scene(root / "demos" / "scenes" / "steel_tank.toml").with_coarse_mesh() \
        .with_changes(ringwall={"inner_radius": 14.7, "outer_radius": 15.3, "depth": 1.2,
                                "E": 30e9},
                      load={"overturning_moment": 2e7, "base_shear": 3e6}).to_dict()


@pytest.mark.parametrize("case", ["node states", "plate alone, embedded, with shear",
                                  "layers with an undrained one", "Duncan & Chang",
                                  "steel tank on a ringwall"])
def test_every_kind_of_scene_balances_the_overturning(case):
    """The first harmonic's equilibrium (moment about the plate's underside, shear) on the
    other parts of the model: Mohr-Coulomb states per node, a plate without a wall (the
    shear's traction on its mid-surface), layered ground with a mixed layer, Duncan &
    Chang's soil (mixed, its converged secant moduli), a steel tank on a ringwall."""
    load = {"pressure": 50e3, "overturning_moment": 1e4, "base_shear": 4e3}
    d = {"node states": lambda: small_tank(interface={
            "condition": "mohr_coulomb", "tan_phi": 0.5, "states": "node"}),
         "plate alone, embedded, with shear": lambda: {
            "soil": {"E": 10e6, "nu": 0.3}, "mesh": COARSE,
            "plate": {"radius": 1.0, "Kp": 1.0, "E": 30e9, "nu": 0.2, "embedment": 0.2}},
         "layers with an undrained one": lambda: small_tank(soil={
            "E": 10e6, "nu": 0.3, "layers": [{"depth": 2.0, "E": 50e6, "nu": 0.5}]}),
         "Duncan & Chang": lambda: small_tank(soil={
            "model": "duncan_chang", "modulus_number": 400, "modulus_exponent": 0.5,
            "failure_ratio": 0.85, "cohesion": 5e3, "friction_angle": 35.0,
            "unit_weight": 18e3, "nu": 0.3}),
         "steel tank on a ringwall": _steel_on_ringwall}[case]()
    if case != "steel tank on a ringwall":
        d["load"] = load
    o = analyse(Scene.from_dict(d)).results["overturning"]
    assert o["equilibrium"]["moment_relative_error"] < 1e-8
    assert o["equilibrium"]["shear_relative_error"] < 1e-8
    assert o["tilt"] > 0


def test_a_load_path_overturns_only_where_a_stage_says_so():
    """Stages: the full tank, then the full tank in an earthquake; the first has no
    overturning results, the second its own (about the second stage's state), and the
    stages' table carries its tilt."""
    from tankfx.analysis import analyse_path

    scene = Scene.from_dict(small_tank())
    first, second = analyse_path(scene, [{"pressure": 50e3},
                                         {"pressure": 50e3, "overturning_moment": 1e4}])
    assert "overturning" not in first.results
    assert second.results["overturning"]["equilibrium"]["moment_relative_error"] < 1e-8
    assert second.results["stages"][1]["tilt"] == second.results["overturning"]["tilt"]
    assert second.results["stages"][0]["tilt"] is None


def test_rocking_from_a_flexible_to_a_rigid_plate():
    """Kp from 1e-6 to 1e4 under a moment: the rocking stiffness (moment over the edge's
    tilt) falls monotonically from the flexible load's 3 pi^2 E a^3 / (16 (1 - nu^2)) (the
    antisymmetric Boussinesq load's edge, 4 (1 - nu^2) q a / (3 pi E)) to the rigid disc's
    4 E a^3 / (3 (1 - nu^2)); every solve's residual and equilibrium at round-off."""
    E_, nu = 10e6, 0.3
    stiffness = []
    for Kp in (1e-6, 1e-2, 1.0, 1e2, 1e4):
        o = analyse(Scene.from_dict(_surface_plate(Kp, overturning_moment=1e5))).results[
            "overturning"]
        assert o["relative_residual"] < 1e-7
        assert o["equilibrium"]["moment_relative_error"] < 1e-8
        stiffness.append(o["rocking_stiffness"] * (1 - nu**2) / E_)
    assert all(b < a for a, b in zip(stiffness, stiffness[1:]))
    assert stiffness[0] == pytest.approx(3 * math.pi**2 / 16, rel=5e-3)      # (-0.3 %)
    assert stiffness[-1] == pytest.approx(4 / 3, rel=5e-3)                   # (+0.33 %)


def test_tankfx_run_writes_the_overturning_profiles_and_figures(tmp_path):
    """`tankfx run` on a scene with an overturning load: the summary's overturning rows, its
    profiles as CSV (amplitudes and toe / heel totals, units in the header), its figures,
    and its fields for ParaView."""
    import csv
    import tomllib

    from tankfx.cli import main

    d = small_tank(interface={"condition": "mohr_coulomb", "tan_phi": 0.5})
    d["load"] = {"pressure": 50e3, "overturning_moment": 3e4, "base_shear": 1e4}
    lines = []
    for section, values in d.items():
        lines.append(f"[{section}]")
        lines += [f"{k} = {v!r}" if not isinstance(v, str) else f'{k} = "{v}"'
                  for k, v in values.items()]
    (tmp_path / "tank.toml").write_text("\n".join(lines) + "\n")
    assert tomllib.loads((tmp_path / "tank.toml").read_text())["load"]["base_shear"] == 1e4
    out = tmp_path / "out"
    assert main(["run", str(tmp_path / "tank.toml"), "--out", str(out)]) == 0
    with (out / "profiles" / "overturning_wall.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert "axial_stress_toe [Pa]" in rows[0] and len(rows) > 10
    with (out / "profiles" / "overturning_plate.csv").open() as f:
        assert "contact_normal_heel [Pa]" in next(csv.reader(f))
    report = (out / "report.md").read_text()
    assert "overturning: tilt" in report and "rocking stiffness" in report
    for name in ("overturning.png", "overturning_wall.png", "tilt.png"):
        assert (out / name).stat().st_size > 10_000, name
    # the fields for ParaView: the soil's amplitudes beside its axisymmetric displacement,
    # the members' overturning profiles beside theirs
    import pyvista

    wall = pyvista.read(out / "fields" / "wall.vtp")
    assert np.allclose(wall.point_data["overturning_N_z_toe"], [float(r["N_z_toe [N/m]"])
                                                                for r in rows])
    soil = pyvista.read(sorted((out / "fields").glob("soil*.vtu"))[0])
    assert soil.point_data["u_overturning"].shape[1] == 3
    assert np.abs(soil.point_data["u_overturning"]).max() > 0


def test_a_negative_moment_is_the_same_tank_turned_round():
    """M < 0 presses theta = 180 deg down: the amplitudes change sign, and the toe and heel
    (the sides pressed down and lifted) are the same numbers on the other sides."""
    def run(M):
        d = small_tank()
        d["load"] = {"pressure": 50e3, "overturning_moment": M, "base_shear": M / 3}
        return analyse(Scene.from_dict(d)).results["overturning"]

    plus, minus = run(3e4), run(-3e4)
    assert minus["tilt"] == pytest.approx(-plus["tilt"], rel=1e-9)
    assert minus["rocking_stiffness"] == pytest.approx(plus["rocking_stiffness"], rel=1e-9)
    assert (plus["toe"]["theta"], minus["toe"]["theta"]) == (0.0, 180.0)
    for side in ("toe", "heel"):
        for key, value in plus[side].items():
            if key != "theta":
                assert minus[side][key] == pytest.approx(value, rel=1e-9), (side, key)
    for key in ("N_z_toe", "N_z_heel", "axial_stress_toe"):
        assert minus["wall_foot"][key] == pytest.approx(plus["wall_foot"][key], rel=1e-9)
    for key in ("M_wall_toe", "M_plate_heel", "plate_bending_stress_toe"):
        assert minus["junction"][key] == pytest.approx(plus["junction"][key], rel=1e-9)
    assert minus["uplift"]["onset_factor"] == pytest.approx(plus["uplift"]["onset_factor"],
                                                            rel=1e-9)


def test_a_shear_alone_tilts_the_tank_without_a_rocking_stiffness():
    """base_shear without a moment: the wall carries V to its foot with no moment there (the
    couple -V H on its top edge), the interface resists V and no moment, and no rocking
    stiffness is reported (the summary says so)."""
    from tankfx.results.report import summary_table

    d = small_tank()
    d["load"] = {"pressure": 50e3, "base_shear": 1e4}
    r = analyse(Scene.from_dict(d)).results
    o = r["overturning"]
    assert o["rocking_stiffness"] is None and o["nondim"]["rocking_stiffness"] is None
    assert abs(o["equilibrium"]["moment_resisted"]) < 1e-8 * 1e4 * 3.0
    assert o["equilibrium"]["moment_relative_error"] < 1e-8      # (on the scale V H)
    assert o["equilibrium"]["shear_relative_error"] < 1e-8
    assert "no moment" in summary_table(r)


def test_the_shipped_seismic_scene_runs_as_a_load_path():
    """demos/scenes/steel_tank_seismic.toml (coarse mesh): the full tank, then the full tank
    in the earthquake; the second stage alone overturns, its axisymmetric part is the first
    stage's (the same total vertical load and states to start from), and its heel zone
    stays down at this earthquake (onset 1.28 x on this mesh)."""
    from pathlib import Path

    from tankfx import load_scene
    from tankfx.analysis import analyse_path

    scene = load_scene(Path(__file__).resolve().parents[1] / "demos" / "scenes" /
                       "steel_tank_seismic.toml").with_coarse_mesh()
    full, quake = analyse_path(scene, list(scene.stages))
    assert "overturning" not in full.results
    o = quake.results["overturning"]
    assert quake.results["w0"] == pytest.approx(full.results["w0"], rel=1e-9)
    assert o["equilibrium"]["moment_relative_error"] < 1e-8
    assert not o["uplift"]["lifts"] and o["uplift"]["onset_factor"] == pytest.approx(1.28,
                                                                                     abs=0.02)
