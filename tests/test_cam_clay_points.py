"""Modified Cam Clay at a material point (tankfx.laws.cam_clay_points), each test against a
closed form: isotropic compression and unloading, undrained triaxial compression from any
overconsolidation, drained triaxial compression from a normally consolidated state, the
one-dimensional normally consolidated ratio K0_nc, and the Taylor test of the tangent."""
from __future__ import annotations

import numpy as np
import pytest

from tankfx.laws.cam_clay_points import (CamClayPoints, critical_state_angle,
                                         critical_state_ratio, elastic_pressure, invariants,
                                         normally_consolidated_ratio)

M, LAMBDA, KAPPA, NU, P_MIN = 1.2, 0.1, 0.02, 0.25, 1e3
P0 = 100e3


def _points(sigma0, p_c0, M=M) -> CamClayPoints:
    sigma0 = np.atleast_2d(np.asarray(sigma0, dtype=float))
    N = len(sigma0)
    return CamClayPoints(M=np.full(N, M), lambda_star=np.full(N, LAMBDA),
                         kappa_star=np.full(N, KAPPA), nu=np.full(N, NU), sigma0=sigma0,
                         p_c0=np.full(N, p_c0), p_min=P_MIN, E_fixed=np.full(N, np.nan))


def _isotropic(p):
    return [-p, -p, 0.0, -p]


def _strain_path(law, increments):
    """Drive the law through strain increments (each (4,)), committing each: the final
    change of stress and state."""
    stress, state = np.zeros((1, 4)), law.initial_state()
    for d in increments:
        u = law.update(np.atleast_2d(d), stress, state)
        assert np.isfinite(u.stress).all()
        stress, state = u.stress, u.state
    return stress, state, u


def test_isotropic_compression_and_unloading():
    """Normally consolidated: eps_v = lambda* ln(p'/p'_0), the ellipse's tip following p';
    back: kappa* ln, elastic."""
    law = _points(_isotropic(P0), P0)
    stress, state, u = _strain_path(law, [[-1e-3, -1e-3, 0.0, -1e-3]] * 50)
    p = invariants(law.sigma0 + stress)[0][0]
    assert u.yielding[0]
    assert p == pytest.approx(P0 * np.exp(0.15 / LAMBDA), rel=1e-12)
    assert state["p_c"][0, 0] == pytest.approx(p, rel=1e-12)
    back = _points(law.sigma0 + stress, state["p_c"][0, 0])
    stress2, state2, u2 = _strain_path(back, [[1e-3, 1e-3, 0.0, 1e-3]] * 20)
    p2 = invariants(back.sigma0 + stress2)[0][0]
    assert not u2.yielding[0] and state2["p_c"][0, 0] == state["p_c"][0, 0]
    assert p2 == pytest.approx(p * np.exp(-0.06 / KAPPA), rel=1e-12)


@pytest.mark.parametrize("R0", [1.0, 1.5, 2.0, 4.0, 8.0])
def test_undrained_triaxial_compression(R0):
    """No volume change from an isotropic state at p'_0 = p_c0 / R0: at the critical state
    p'_f / p'_0 = (R0 / 2)^L, L = (lambda* - kappa*) / lambda*, q_f = M p'_f, s_u / p'_0 =
    (M / 2) (R0 / 2)^L; the excess pore pressure (total stress path of the triaxial test,
    sigma_3 constant) p'_0 + q_f / 3 - p'_f. Wet side (R0 < 2) and dry (R0 > 2)."""
    law = _points(_isotropic(P0), R0 * P0)
    e = 2e-3
    stress, state, u = _strain_path(law, [[e / 2, -e, 0.0, e / 2]] * 400)
    p, q, _ = invariants(law.sigma0 + stress)
    L = (LAMBDA - KAPPA) / LAMBDA
    assert p[0] / P0 == pytest.approx((R0 / 2) ** L, rel=1e-9)
    assert q[0] == pytest.approx(M * p[0], rel=1e-6)
    assert q[0] / 2 / P0 == pytest.approx(M / 2 * (R0 / 2) ** L, rel=1e-6)
    excess = P0 + q[0] / 3 - p[0]
    assert excess == pytest.approx(P0 * (1 + M / 3 * (R0 / 2) ** L - (R0 / 2) ** L), rel=1e-6)


def _drained_triaxial(law, axial, steps):
    """Axial compression with the lateral stress held (a Newton per step on the lateral
    strain with the law's tangent): the stress change and the volumetric strain."""
    stress, state = np.zeros((1, 4)), law.initial_state()
    volume = 0.0
    for _ in range(steps):
        er = 0.0
        for _ in range(30):
            u = law.update(np.array([[er, axial, 0.0, er]]), stress, state)
            misfit = u.stress[0, 0] - stress[0, 0]
            if abs(misfit) < 1e-7 * P0:
                break
            er -= misfit / (u.tangent[0, 0, 0] + u.tangent[0, 0, 3])
        else:
            raise AssertionError("lateral stress not held")
        stress, state = u.stress, u.state
        volume -= axial + 2.0 * er
    return stress, state, volume


def test_drained_triaxial_compression():
    """From the isotropic normally consolidated state: the stress path p' = p'_0 + q / 3,
    q_f / p'_0 = 3 M / (3 - M) at the critical state, and along the way the volumetric
    strain kappa* ln(p'/p'_0) + (lambda* - kappa*) ln(p_c / p'_0) with p_c = p' + q^2 /
    (M^2 p') on the ellipse (exact: both laws are integrated exactly)."""
    law = _points(_isotropic(P0), P0)
    stress, state, volume = _drained_triaxial(law, -5e-4, 300)
    p, q, _ = invariants(law.sigma0 + stress)
    expected = KAPPA * np.log(p / P0) + (LAMBDA - KAPPA) * np.log((p + q * q / (M * M * p)) / P0)
    assert volume == pytest.approx(expected[0], rel=1e-9)
    # (the lateral stress is held to 1e-7 p'_0 a step)
    assert p[0] == pytest.approx(P0 + q[0] / 3, rel=1e-5)
    # on to the critical state, in large steps (the return takes them)
    stress, state, volume = _drained_triaxial(law, -2e-2, 200)
    p, q, _ = invariants(law.sigma0 + stress)
    assert q[0] / P0 == pytest.approx(3 * M / (3 - M), rel=1e-3)
    assert q[0] / p[0] == pytest.approx(M, rel=1e-3)


def test_one_dimensional_normally_consolidated_compression():
    """From sigma'_h = K0_nc sigma'_v on the ellipse, compressed with no lateral strain:
    the ratio stays K0_nc and sigma'_v grows as exp(eps_v / lambda*)."""
    eta, K0 = normally_consolidated_ratio(M, LAMBDA, KAPPA, NU)
    assert K0 == pytest.approx((3 - eta) / (3 + 2 * eta))
    sv = 100e3
    sigma0 = [-K0 * sv, -sv, 0.0, -K0 * sv]
    p, q, _ = invariants(np.atleast_2d(sigma0))
    law = _points(sigma0, p[0] + q[0] ** 2 / (M * M * p[0]))
    stress, _, u = _strain_path(law, [[0.0, -1e-3, 0.0, 0.0]] * 200)
    s = law.sigma0 + stress
    assert u.yielding[0]
    assert s[0, 0] / s[0, 1] == pytest.approx(K0, rel=2e-4)
    assert -s[0, 1] == pytest.approx(sv * np.exp(0.2 / LAMBDA), rel=2e-5)


def test_the_tangent_is_the_derivative_of_the_update():
    """Taylor: the remainder of the first-order expansion falls as the square of the step,
    at yielding points on both sides of the critical state and at an elastic one."""
    rng = np.random.default_rng(7)
    sigma0 = np.array([[-P0, -1.3 * P0, 0.0, -P0], [-P0, -P0, 0.0, -P0],
                       [-P0, -P0, 0.0, -P0]])
    law = CamClayPoints(M=np.full(3, M), lambda_star=np.full(3, LAMBDA),
                        kappa_star=np.full(3, KAPPA), nu=np.full(3, NU), sigma0=sigma0,
                        p_c0=np.array([1.2 * P0, 3.0 * P0, 3.0 * P0]), p_min=P_MIN,
                        E_fixed=np.full(3, np.nan))
    d = np.array([[1e-3, -4e-3, 5e-4, 1e-3], [1e-2, -2e-2, 5e-3, 1e-2],
                  [1e-4, -1e-4, 0.0, 0.0]])
    stress, state = np.zeros((3, 4)), law.initial_state()
    u = law.update(d, stress, state)
    assert list(u.yielding) == [True, True, False]
    h = rng.standard_normal((3, 4))
    remainders = []
    for t in (1e-5, 1e-6, 1e-7):
        v = law.update(d + t * h, stress, state)
        remainders.append(np.linalg.norm(v.stress - u.stress - t * np.einsum(
            "nij,nj->ni", u.tangent, h), axis=1))
    rates = np.log10(np.array(remainders[0]) / np.array(remainders[1]))
    # (the elastic point's too: its bulk modulus follows p')
    assert np.all(rates > 1.9), remainders
    # (associated, yet not symmetric: the bulk modulus is the step's end's, G its start's)
    assert not law.symmetric


def test_the_least_mean_stress_and_the_reduced_strength():
    """Below p_min the bulk modulus is p_min's (linear), above it p' / kappa*, continuous;
    the strength reduction divides tan phi_cs."""
    p, K = elastic_pressure(np.array([0.0, 0.5 * P_MIN, 2 * P_MIN]), np.array([1e-3] * 3),
                            KAPPA, P_MIN)
    assert p[0] == pytest.approx(P_MIN / KAPPA * 1e-3)
    assert p[2] == pytest.approx(2 * P_MIN * np.exp(1e-3 / KAPPA))
    assert np.all(K >= P_MIN / KAPPA)
    # crossing p_min within a step, both ways, returns where it started
    up, _ = elastic_pressure(np.array([0.5 * P_MIN]), np.array([0.2]), KAPPA, P_MIN)
    down, _ = elastic_pressure(up, np.array([-0.2]), KAPPA, P_MIN)
    assert down[0] == pytest.approx(0.5 * P_MIN, rel=1e-12)
    law = _points(_isotropic(P0), P0)
    phi = np.radians(critical_state_angle(M))
    reduced = law.reduced(1.25)
    assert np.tan(np.radians(critical_state_angle(reduced.M))) == pytest.approx(
        np.tan(phi) / 1.25)
    assert critical_state_ratio(critical_state_angle(M)) == pytest.approx(M)


def test_an_elastic_point_never_fails_its_return():
    """The points made elastic (a void's, a ringwall's) take any strain elastically, their
    stress finite, even a strain no clay's return converges from (170 %: measured in a
    tank's inside); they must not be reported as failed returns (committed as NaN there,
    a strength search's next update read them and found no equilibrium)."""
    sigma0 = np.array([[-10e3, -20e3, -10e3, 0.0]] * 2)
    points = _points(sigma0, np.full(2, 30e3)).elastic_where(np.array([True, False]))
    d_eps = np.array([[2e-4, -1.7, 0.37, 1e-6]] * 2)
    up = points.update(d_eps, np.zeros((2, 4)), points.initial_state())
    assert np.all(np.isfinite(up.stress[0])) and not up.yielding[0]
    D = points.elastic_matrix()[0]
    assert np.allclose(up.stress[0], D @ d_eps[0])


def test_the_least_preconsolidation_pressure():
    """A point dilating on the dry side softens to the ellipse of p_c = p_min and no further
    (its return converges there: before, p_c fell towards 0 without end), from the floor
    and from above it; compressed, a point at the floor hardens from it; the tangent is the
    update's derivative on the floor too (Taylor), and a zero increment gives the stress
    back exactly."""
    sigma0 = np.array([[-200.0, -300.0, 0.0, -200.0], [-300.0, -300.0, 0.0, -300.0],
                       [-100.0, -100.0, 0.0, -100.0], [-200.0, -300.0, 0.0, -200.0]])
    N = len(sigma0)
    law = CamClayPoints(M=np.full(N, M), lambda_star=np.full(N, LAMBDA),
                        kappa_star=np.full(N, KAPPA), nu=np.full(N, NU), sigma0=sigma0,
                        p_c0=np.array([P_MIN, 1.2 * P_MIN, P_MIN, P_MIN]), p_min=P_MIN,
                        E_fixed=np.full(N, np.nan))
    d = np.array([[1e-2, -2e-2, 1.5e-2, 5e-3], [3e-2, -2e-2, 2e-2, 3e-2],
                  [5e-2, 3e-2, 0.0, 4e-2], [-3e-2, -8e-2, 1e-2, -3e-2]])
    stress, state = np.zeros((N, 4)), law.initial_state()
    u = law.update(d, stress, state)
    assert np.all(u.yielding) and np.all(np.isfinite(u.stress))
    p, q, _ = invariants(sigma0 + u.stress)
    p_c = u.state["p_c"][:, 0]
    assert np.allclose(p_c[:3], P_MIN, rtol=0.0, atol=0.0)
    assert p_c[3] > 3.0 * P_MIN
    assert np.all(np.abs(q ** 2 / M ** 2 + p * (p - p_c)) <= 1e-12 * p_c ** 2)
    h = np.random.default_rng(3).standard_normal((N, 4))
    remainders = [np.linalg.norm(law.update(d + t * h, stress, state).stress - u.stress
                                 - t * np.einsum("nij,nj->ni", u.tangent, h), axis=1)
                  for t in (1e-5, 1e-6)]
    assert np.all(np.log10(remainders[0] / remainders[1]) > 1.9), remainders
    rest = _points(_isotropic(0.3 * P0), P0)
    assert np.all(rest.update(np.zeros((1, 4)), np.zeros((1, 4)),
                              rest.initial_state()).stress == 0.0)
