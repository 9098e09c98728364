"""Drucker-Prager's soil (tankfx.laws.drucker_prager), the second law behind the point-law
contract: its return lies on its cone, its tangent is the return's derivative (Taylor), its
cone passes through Mohr-Coulomb's meridian it is matched to, a plane-strain point flows at
Mohr-Coulomb's strength with the plane-strain match, the thick cylinder carries von Mises'
limit pressure, and the rigid footing's collapse lies on the side of Tresca's exact value
that the cones' inclusion says."""
from __future__ import annotations

import math

import numpy as np
import pytest
from mpi4py import MPI

from tankfx import Scene
from tankfx.laws.drucker_prager import MATCHES, DruckerPragerPoints, cone
from tankfx.laws.plasticity import IDENTITY
from tankfx.laws.point_law import PointLaw

C = 10e3


def points(n, phi=30.0, psi=None, match="compression", E=10e6, nu=0.3, seed=0):
    """n points of Drucker-Prager soil from a random ground at rest inside the cone (a
    compression of 20-120 kPa, sigma_z up to 5 kPa more than the others)."""
    rng = np.random.default_rng(seed)
    psi = phi if psi is None else psi
    p0 = -rng.uniform(20e3, 120e3, n)
    sigma0 = np.column_stack([p0, p0 - rng.uniform(0.0, 5e3, n), np.zeros(n), p0])
    full = np.ones(n)
    return DruckerPragerPoints(E=E * full, nu=nu * full, cohesion=C * full,
                               sin_phi=math.sin(math.radians(phi)) * full,
                               sin_psi=math.sin(math.radians(psi)) * full, sigma0=sigma0,
                               match=match)


def test_it_is_a_point_law():
    assert isinstance(points(2), PointLaw)


@pytest.mark.parametrize("phi,psi,match", [(30.0, 30.0, "compression"), (30.0, 5.0, "extension"),
                                           (0.0, 0.0, "plane_strain"), (20.0, 0.0, "plane_strain")])
def test_every_return_lies_on_its_cone_and_its_tangent_is_the_derivative(phi, psi, match):
    """Random strain increments from random states at rest: a yielding point's stress lies
    on the cone (mobilised 1 to 1e-9), an elastic one inside; the tangent's first-order
    remainder falls as h^2 (Taylor) at points on the cone's smooth part; symmetric exactly
    where the flow is associated."""
    law = points(400, phi, psi, match)
    rng = np.random.default_rng(1)
    # (sizes from 1e-5 to 0.1: some points stay inside, most flow)
    d_eps = rng.normal(0.0, 1.0, (400, 4)) * np.exp(rng.uniform(np.log(1e-5), np.log(1e-1), 400))[:, None]
    up = law.update(d_eps, np.zeros((400, 4)), {})
    level = law.mobilised(up.stress + law.sigma0)
    assert up.yielding.sum() > 50 and (~up.yielding).sum() > 10
    assert np.all(np.abs(level[up.yielding] - 1.0) < 1e-9)
    assert np.all(level[~up.yielding] <= 1.0 + 1e-9)
    symmetric = np.allclose(up.tangent, np.swapaxes(up.tangent, 1, 2), rtol=0, atol=1e-6 * 10e6)
    assert symmetric == (phi == psi) == law.symmetric
    # Taylor at points off the apex (its tangent is a fixed fraction of D, not the derivative)
    total = up.stress + law.sigma0
    s = total - (total @ IDENTITY / 3.0)[:, None] * IDENTITY
    smooth = up.yielding & (np.linalg.norm(s, axis=1) > 1e-3 * C)
    direction = rng.normal(0.0, 1.0, (400, 4))
    remainders = []
    for h in (1e-5, 5e-6, 2.5e-6):
        moved = law.update(d_eps + h * direction, np.zeros((400, 4)), {})
        linear = up.stress + h * np.einsum("nij,nj->ni", up.tangent, direction)
        remainders.append(np.linalg.norm(moved.stress - linear, axis=1)[smooth])
    rate = np.log2(remainders[0] / remainders[1]), np.log2(remainders[1] / remainders[2])
    assert np.median(rate[0]) > 1.9 and np.median(rate[1]) > 1.9


@pytest.mark.parametrize("phi,psi", [(25.0, 0.0), (25.0, 10.0), (25.0, 25.0)])
def test_past_the_apex_the_return_is_a_flow_and_its_tangent_the_derivative(phi, psi):
    """Trials about the apex xi c / eta (psi = 0, psi < phi, psi = phi). A trial is taken to
    the apex exactly where its plastic strain D^-1 (sigma_tr - sigma_apex) has the volume
    change a flow gives there (the cone's potential, or at psi = 0 the associated cap p <=
    p_apex that the apex carries: tr e >= sqrt 2 eta_bar |dev e|), and to the smooth cone
    elsewhere; the finite-difference remainder relative to h |D d| falls as h on the cone
    and is the millionth of D kept at the apex (where the stress is fixed)."""
    n = 20000
    law = points(n, phi, psi, E=10e6, nu=0.3, seed=3)
    rng = np.random.default_rng(4)
    # (the ground at rest taken to about the apex: compressions of 0-30 kPa)
    law = DruckerPragerPoints(**{**{k: getattr(law, k) for k in ("E", "nu", "cohesion",
                                                                  "sin_phi", "sin_psi")},
                                 "sigma0": -rng.uniform(0.0, 30e3, (n, 4)) * [1, 1, 0.1, 1],
                                 "match": "compression"})
    d_eps = rng.standard_normal((n, 4)) * 1e-3 + 5e-4
    up = law.update(d_eps, np.zeros((n, 4)), {})
    total = up.stress + law.sigma0
    eta, xi = cone(np.sin(np.radians(phi)), "compression")
    eta_bar = cone(np.sin(np.radians(psi)), "compression")[0]
    p = total @ IDENTITY / 3.0
    at_apex = up.yielding & np.isclose(p, xi * C / eta, rtol=1e-9)
    smooth = up.yielding & ~at_apex
    assert at_apex.sum() > 100 and smooth.sum() > 100
    # (on the cone, the deviator not turned over)
    assert np.all(np.abs(law.mobilised(total)[up.yielding] - 1.0) < 1e-9)
    # the plastic strain of an apex point is a flow's
    e = up.plastic_strain[at_apex]
    tr = e @ IDENTITY
    dev = np.linalg.norm(e - (tr / 3.0)[:, None] * IDENTITY, axis=1)
    assert np.all(tr >= math.sqrt(2.0) * eta_bar * dev - 1e-12)
    direction = rng.standard_normal((n, 4)) * 1e-4
    D = law.update(np.zeros((1, 4)), np.zeros((1, 4)), {}).tangent[0]
    scale = np.linalg.norm(direction @ D, axis=1)
    remainder = []
    for h in (1e-2, 1e-3):
        moved = law.update(d_eps + h * direction, np.zeros((n, 4)), {})
        p_h = (moved.stress + law.sigma0) @ IDENTITY / 3.0
        same = np.isclose(p_h, xi * C / eta, rtol=1e-9) == at_apex
        r = np.linalg.norm(moved.stress - up.stress
                           - h * np.einsum("nij,nj->ni", up.tangent, direction), axis=1)
        remainder.append(np.where(same, r / (h * scale), np.nan))
    assert np.nanmedian(remainder[1][at_apex]) < 2e-6
    coarse, fine = np.nanmedian(remainder[0][smooth]), np.nanmedian(remainder[1][smooth])
    assert fine < 1e-4 and coarse / fine > 10 ** 0.8, (coarse, fine)


@pytest.mark.parametrize("match", MATCHES)
def test_the_cone_passes_through_its_mohr_coulomb_meridian(match):
    """phi = 30 degrees, c = 10 kPa: at Mohr-Coulomb's strength in triaxial compression
    (sigma_r = sigma_theta > sigma_z, tension positive) the compression-matched cone is at
    its strength and the extension-matched one beyond it; in triaxial extension the other
    way round; the plane-strain cone lies inside Mohr-Coulomb's pyramid on both meridians
    (it touches the pyramid between them, where plane strain flows)."""
    phi = math.radians(30.0)
    s = math.sin(phi)
    law = points(2, 30.0, match=match)
    conf = 50e3                                        # the confining compression
    q_c = (2 * C * math.cos(phi) + 2 * conf * s) / (1 - s)      # compression: sigma_1 - sigma_3
    comp = np.array([[-conf, -conf - q_c, 0.0, -conf]])
    # extension: sigma_z the least compression, sigma_r = sigma_theta the largest
    q_e = (2 * C * math.cos(phi) + 2 * conf * s) / (1 - s)
    ext = np.array([[-conf - q_e, -conf, 0.0, -conf - q_e]])
    at_comp, at_ext = law.mobilised(comp)[0], law.mobilised(ext)[0]
    if match == "compression":
        assert at_comp == pytest.approx(1.0, rel=1e-12) and at_ext < 1.0
    elif match == "extension":
        assert at_ext == pytest.approx(1.0, rel=1e-12) and at_comp > 1.0
    else:
        assert at_comp > 1.0 and at_ext > 1.0


@pytest.mark.parametrize("phi", [0.0, 20.0, 35.0])
def test_the_plane_strain_cone_flows_at_mohr_coulombs_strength(phi):
    """Drucker & Prager (1952): where associated flow leaves the plane's normal strain
    (theta's) unchanged, d f / d sigma_theta = 0, so sigma_theta = p + t with
    t = -eta R / sqrt(1 - eta^2 / 3) beside the in-plane circle (p, R); the plane-strain
    cone is there at its strength exactly when the circle touches Mohr-Coulomb's line,
    R = c cos phi - p sin phi (checked at five confinements). At phi = 0 a point sheared in
    plane strain (e_r = -e_z, e_theta = 0) from the ground at rest flows at R = c."""
    s = math.sin(math.radians(phi))
    law = points(5, phi, phi, "plane_strain", seed=3)
    eta = law._eta[0]
    p = -np.array([0.0, 10e3, 50e3, 200e3, 1e6])
    R = C * math.cos(math.radians(phi)) - p * s
    t = -eta * R / math.sqrt(1.0 - eta ** 2 / 3.0)
    stress = np.column_stack([p + R, p - R, 0.0 * p, p + t])
    assert np.allclose(law.mobilised(stress), 1.0, rtol=1e-12)
    if phi == 0.0:
        one = points(1, 0.0, 0.0, "plane_strain", seed=3)
        stress = np.zeros((1, 4))
        for _ in range(200):
            stress = one.update(np.array([[2e-4, -2e-4, 0.0, 0.0]]), stress, {}).stress
        total = (stress + one.sigma0)[0]
        assert 0.5 * abs(total[0] - total[1]) == pytest.approx(C, rel=1e-9)


@pytest.mark.parametrize("match,xi", [("compression", 2.0 / math.sqrt(3.0)), ("plane_strain", 1.0)])
def test_a_thick_cylinder_carries_von_mises_limit_pressure(match, xi):
    """A thick cylinder (a = 1 m, b = 2 m, plane strain) of von Mises soil (phi = 0),
    sqrt(J2) <= xi c: in plane strain its flow leaves sigma_z the mean of sigma_r and
    sigma_theta, so sigma_theta - sigma_r = 2 xi c where it flows, and the limit pressure
    is 2 xi c ln(b / a) (Hill 1950). It carries 99.9 % of it and not 101 %."""
    from tankfx.verification.cylinder import ThickCylinder

    soil = Scene.from_dict({"soil": {"model": "drucker_prager", "E": 10e6, "nu": 0.3,
                                     "cohesion": C, "drucker_prager_match": match},
                            "load": {"pressure": 1e3, "load_radius": 1.0}}).soil
    cyl = ThickCylinder(soil, 1.0, 2.0, cells=(40, 2), degree=2, comm=MPI.COMM_SELF)
    limit = 2.0 * xi * C * math.log(2.0)
    for share in (0.5, 0.9, 0.99, 0.999):
        cyl.load(share * limit, max_iterations=40)
    assert cyl.plastic_radius() > 1.95
    with pytest.raises(RuntimeError, match="did not converge|the linear solve"):
        cyl.load(1.01 * limit, max_iterations=40)


def test_a_footing_on_von_mises_soil_collapses_on_its_side_of_tresca():
    """The smooth rigid footing (Shield's N_c = 5.69 on Tresca soil) on von Mises soil
    (Drucker-Prager at phi = 0), sqrt(J2) <= xi c. The plane-strain cone (xi = 1) lies
    inside Tresca's hexagon of c: it carries at most 5.69 (within the elements' 1 %) and at
    least sqrt 3 / 2 of it. The compression cone (xi = 2 / sqrt 3) is the same soil scaled:
    with E and the load scaled by 2 / sqrt 3 too, every stress of its path is 2 / sqrt 3
    times the plane-strain one's at the same displacements, so its search takes the same
    steps and its bearing capacity is 2 / sqrt 3 times the other's to the search's
    round-off (a wrong xi moves it by the error in xi). The bounds are refused in words
    (Drucker-Prager has none in tankfx)."""
    from test_collapse import footing

    from tankfx import analyse
    from tankfx.scene.sections import SceneError

    xi = 2.0 / math.sqrt(3.0)
    found = {}
    for match, scale in (("plane_strain", 1.0), ("compression", xi)):
        data = footing("smooth", pressure=C * scale)
        data["soil"] = {**data["soil"], "model": "drucker_prager",
                        "drucker_prager_match": match, "E": data["soil"]["E"] * scale}
        found[match] = analyse(Scene.from_dict(data)).results["collapse"]
        assert found[match]["found"]
    N = found["plane_strain"]["bearing_pressure"] / C
    assert 5.69 * math.sqrt(3.0) / 2.0 <= N <= 5.69 * 1.01
    assert found["compression"]["load_factor"] == pytest.approx(
        found["plane_strain"]["load_factor"], rel=1e-6)
    assert found["compression"]["bearing_pressure"] / C == pytest.approx(xi * N, rel=1e-6)
    with pytest.raises(SceneError, match="takes Mohr-Coulomb's cones"):
        Scene.from_dict({**data, "analysis": {"collapse": "bounds"}})


def test_the_cones_reduce_to_von_mises_at_phi_zero():
    """At phi = 0 every match has eta = 0; xi is 2 / sqrt 3 through the meridians, 1 in
    plane strain."""
    for match, xi in (("compression", 2 / math.sqrt(3)), ("extension", 2 / math.sqrt(3)),
                      ("plane_strain", 1.0)):
        eta, x = cone(np.zeros(1), match)
        assert eta[0] == 0.0 and x[0] == pytest.approx(xi, rel=1e-15)
