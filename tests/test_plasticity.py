"""The elastoplastic soil's law at material points (tankfx.laws.plasticity): Mohr-Coulomb and
Tresca limits exactly where their closed forms put them, the apex and the tension cut-off, a
return on a sector boundary, and a consistent tangent (Taylor test: second order)."""
from __future__ import annotations

import numpy as np
import pytest

from tankfx.laws.plasticity import (
    APEX,
    CANDIDATES,
    ELASTIC,
    IDENTITY,
    SQRT2,
    elastic_matrix,
    mobilised_strength,
    principal,
    stress_update,
)

E, NU = 20e6, 0.3


def triaxial(p, c, phi_deg, psi_deg=0.0, extension=False, steps=60, strain=0.08,
             tension=None):
    """A triaxial test from the isotropic stress -p: the radial stress held at -p (the cell
    pressure), the axial strain driven to -strain (compression) or +strain (extension),
    each step's radial strain found by Newton with the consistent tangent. Returns the
    axial stresses (Pa, tension positive) and the last state's code."""
    sp, sq = np.sin(np.radians(phi_deg)), np.sin(np.radians(psi_deg))
    sigma = np.array([[-p, -p, 0.0, -p]])
    eps = np.zeros((1, 4))
    out = []
    dz = (strain if extension else -strain) / steps
    for _ in range(steps):
        x = 0.0 if not out else last_dx
        for _ in range(50):
            d = np.array([[x, dz, 0.0, x]])
            s, C, code, _ = stress_update(d, sigma, E, NU, c, sp, sq, tension)
            r = s[0, 0] + p
            if abs(r) < 1e-9 * p:
                break
            x -= r / (C[0, 0, 0] + C[0, 0, 3])
        else:
            raise AssertionError("the material point's Newton did not converge")
        last_dx = x
        sigma, eps = s, eps + d
        out.append(s[0, 1])
    return np.array(out), code[0]


@pytest.mark.parametrize("phi", [0.0, 20.0, 35.0])
@pytest.mark.parametrize("p", [50e3, 200e3])
def test_triaxial_compression_reaches_the_mohr_coulomb_limit(p, phi):
    """sigma_1 = -p (radial), sigma_3 axial: failure where (1 + s) sigma_1 - (1 - s) sigma_3 =
    2 c cos phi, |sigma_axial| = (p (1 + s) + 2 c cos phi) / (1 - s)."""
    c = 20e3
    s = np.sin(np.radians(phi))
    axial, code = triaxial(p, c, phi)
    exact = (p * (1 + s) + 2 * c * np.cos(np.radians(phi))) / (1 - s)
    assert -axial[-1] == pytest.approx(exact, rel=1e-10)
    assert code != ELASTIC
    # the load rises elastically, then holds at the limit: never above it
    assert np.all(-axial <= exact * (1 + 1e-10))


@pytest.mark.parametrize("phi", [0.0, 30.0])
def test_triaxial_extension_reaches_the_mohr_coulomb_limit(phi):
    """Extension: the axial stress is the largest, sigma_1 = axial, sigma_3 = -p:
    sigma_axial = (2 c cos phi - p (1 - s)) / (1 + s) (compression, where negative)."""
    p, c = 200e3, 20e3
    s = np.sin(np.radians(phi))
    axial, _ = triaxial(p, c, phi, extension=True)
    exact = (2 * c * np.cos(np.radians(phi)) - p * (1 - s)) / (1 + s)
    assert axial[-1] == pytest.approx(exact, rel=1e-10)


def test_isochoric_flow_keeps_the_volume():
    """With psi = 0 the plastic strain has no volume change (Tresca: and the limit is
    2 c whatever the pressure)."""
    rng = np.random.default_rng(3)
    d = rng.standard_normal((500, 4)) * 5e-3
    sigma_n = np.tile([-100e3, -100e3, 0.0, -100e3], (500, 1))
    for phi in (0.0, 0.5):
        _, _, code, d_eps_p = stress_update(d, sigma_n, E, NU, 10e3, np.sin(phi), 0.0)
        # (the cut-off's flow, associated, opens: a tension crack)
        plastic = on_mohr_coulomb_only(code)
        assert plastic.sum() > 100
        np.testing.assert_allclose(d_eps_p[plastic] @ IDENTITY, 0.0, atol=1e-15)


def on_mohr_coulomb_only(code):
    """The points whose return is to Mohr-Coulomb's planes alone (no cut-off plane)."""
    return np.array([0 <= k < APEX and all(j < 3 for j in CANDIDATES[k]) for k in code])


def test_every_return_lies_on_or_inside_the_yield_surface():
    rng = np.random.default_rng(1)
    n = 4000
    d = rng.standard_normal((n, 4)) * 3e-3
    c, phi = 15e3, np.radians(25.0)
    sigma, _, code, _ = stress_update(d, np.zeros((n, 4)), E, NU, c, np.sin(phi),
                                      np.sin(np.radians(10.0)))
    level = mobilised_strength(sigma, c, np.sin(phi))
    assert np.all(level <= 1 + 1e-9)
    plastic = code != ELASTIC
    np.testing.assert_allclose(level[plastic], 1.0, rtol=1e-9)
    # every kind of return is met: the plane, both edges, the apex (the corner of the
    # cut-off that sits there); none is left without a return
    assert {CANDIDATES.index((0,)), CANDIDATES.index((0, 1)), CANDIDATES.index((0, 2)),
            CANDIDATES.index((3, 4, 5))} <= set(code.tolist())
    assert APEX not in code


@pytest.mark.parametrize("psi", [0.0, 20.0])
def test_hydrostatic_tension_returns_to_the_apex(psi):
    """c cot phi: the apex, the largest isotropic tension the soil takes, reached by the flow
    of the cut-off that sits there (also where psi < phi, when no Mohr-Coulomb potential's
    flow reaches it)."""
    c, phi = 10e3, np.radians(30.0)
    d = np.array([[1e-2, 1e-2, 0.0, 1e-2]])
    sigma, C, code, _ = stress_update(d, np.zeros((1, 4)), E, NU, c, np.sin(phi),
                                      np.sin(np.radians(psi)))
    np.testing.assert_allclose(sigma[0], c / np.tan(phi) * IDENTITY, rtol=1e-10)
    # (its tangent, zero, is held at a millionth of the elastic one: a cell of apex points
    # would make the matrix singular; more would slow Newton)
    assert CANDIDATES[code[0]] == (3, 4, 5)
    assert 0.0 < np.abs(C).max() <= 1.01e-6 * np.abs(elastic_matrix(E, NU)).max()


def test_the_tension_cut_off_holds_the_largest_stress():
    """Uniaxial extension past the cut-off t: sigma_1 = t, the others as the return makes
    them, inside Mohr-Coulomb."""
    c, phi, t = 50e3, np.radians(30.0), 5e3
    d = np.array([[0.0, 1e-2, 0.0, 0.0]])
    sigma, _, code, _ = stress_update(d, np.zeros((1, 4)), E, NU, c, np.sin(phi), 0.0,
                                      tension=t)
    assert principal(sigma)[0].max() == pytest.approx(t, rel=1e-10)
    assert any(j >= 3 for j in CANDIDATES[code[0]])
    # a cut-off beyond the apex never acts
    apex = c / np.tan(phi)
    d = np.array([[1e-2, 1e-2, 0.0, 1e-2]])
    sigma, *_ = stress_update(d, np.zeros((1, 4)), E, NU, c, np.sin(phi), 0.0,
                              tension=2 * apex)
    np.testing.assert_allclose(sigma[0], apex * IDENTITY, rtol=1e-10)


def test_a_trial_on_a_sector_boundary_returns_as_its_neighbours_do():
    """Trial stresses exactly on the boundary between the plane's and an edge's returns
    (two equal principal stresses), and ones a round-off either side of it: the same stress
    to round-off, whichever return each takes; and an in-plane pair that is equal, turned
    by any angle, gives the same principal stresses."""
    c, phi = 10e3, np.radians(30.0)
    sp = np.sin(phi)
    base = np.array([-50e3, -300e3, 0.0, -50e3])       # sigma_1 = sigma_2: an edge
    sigma_n = np.zeros((3, 4))
    d0 = np.linalg.solve(_D(), base)
    d = np.array([d0, d0 * (1 + 1e-15), d0 * (1 - 1e-15)])
    sigma, _, code, _ = stress_update(d, sigma_n, E, NU, c, sp, 0.0)
    np.testing.assert_allclose(sigma, sigma[[0, 0, 0]], rtol=1e-12, atol=1e-6)
    # the same state turned in the (r, z) plane: theta's pair with an in-plane one
    for angle in np.linspace(0.0, np.pi, 7):
        ca, sa = np.cos(angle), np.sin(angle)
        Rm = np.array([[ca, -sa], [sa, ca]])
        s2 = Rm @ np.diag([base[0], base[1]]) @ Rm.T
        turned = np.array([s2[0, 0], s2[1, 1], SQRT2 * s2[0, 1], base[3]])
        out, *_ = stress_update(np.linalg.solve(_D(), turned)[None], np.zeros((1, 4)), E,
                                NU, c, sp, 0.0)
        np.testing.assert_allclose(np.sort(principal(out)[0][0]),
                                   np.sort(principal(sigma[:1])[0][0]), rtol=1e-12)


def _D():
    lmbda, G = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    return lmbda * np.outer(IDENTITY, IDENTITY) + 2 * G * np.eye(4)


def near_the_apex(n, c, seed):
    """Committed stresses about the apex (c cot phi, phi 25 degrees) and strain increments
    that take them past it, beside it and back: trials of every kind of return."""
    rng = np.random.default_rng(seed)
    apex = max(c, 1e3) / np.tan(np.radians(25.0))
    sigma_n = rng.uniform(-3.0 * apex, apex, (n, 4))
    sigma_n[:, 2] *= 0.3
    return rng.standard_normal((n, 4)) * 2e-4 + 1e-4, sigma_n


def equal_in_plane(n, seed):
    """Trials whose in-plane principal values are equal (rr = zz, rz = 0), past the
    surface: the eigenvectors' turn at its limit."""
    rng = np.random.default_rng(seed)
    d = np.zeros((n, 4))
    d[:, 0] = d[:, 1] = rng.uniform(-6e-3, 2e-3, n)
    d[:, 3] = rng.uniform(-6e-3, 2e-3, n)
    return d, np.tile([-60e3, -60e3, 0.0, -60e3], (n, 1))


@pytest.mark.parametrize("phi,psi,c,tension", [
    (25.0, 0.0, 2e3, None), (25.0, 25.0, 2e3, None), (25.0, 10.0, 0.0, None),
    (25.0, 0.0, 2e3, 0.0), (25.0, 25.0, 2e3, 500.0), (0.0, 0.0, 2e3, None),
    (0.0, 0.0, 2e3, 1e3)])
def test_each_kind_of_return_has_its_derivative_as_tangent(phi, psi, c, tension):
    """Finite differences of the stress update per kind of return (the plane, both edges,
    the cut-off's planes, edges and corners, the apex; Tresca's prism), at random states
    about the apex and at equal in-plane principal values: the remainder
    |sigma(eps + h d) - sigma(eps) - h C d| relative to h |D d| falls as h (the tangent is
    the derivative) wherever the return leaves the stress free to move, and at a corner of
    three planes (where the principal stresses are fixed) falls so to the millionth of D the
    tangent keeps there, no more. A wrong sign, a missing term or a wrong branch leaves an O(1) remainder."""
    d1, s1 = near_the_apex(20000, c, seed=11)
    d2, s2 = equal_in_plane(2000, seed=12)
    d_eps, sigma_n = np.vstack([d1, d2]), np.vstack([s1, s2])
    direction = np.random.default_rng(13).standard_normal(d_eps.shape) * 1e-4
    args = (E, NU, c, np.sin(np.radians(phi)), np.sin(np.radians(psi)), tension)
    s0, C, code, _ = stress_update(d_eps, sigma_n, *args)
    assert APEX not in code
    D = elastic_matrix(E, NU)[0]
    scale = np.linalg.norm(direction @ D, axis=1)
    hs = (1e-2, 1e-3)
    remainders, same = [], np.ones(len(code), dtype=bool)
    for h in hs:
        s_h, _, code_h, _ = stress_update(d_eps + h * direction, sigma_n, *args)
        # (a point whose return changes kind between the two is at a kink: left out)
        same &= code_h == code
        remainders.append(np.linalg.norm(s_h - s0 - h * np.einsum("nij,nj->ni", C, direction),
                                         axis=1) / (h * scale))
    kinds = 0
    for k in sorted(set(code[code != ELASTIC].tolist())):
        at = same & (code == k)
        if at.sum() < 10:
            continue
        kinds += 1
        coarse, fine = np.median(remainders[0][at]), np.median(remainders[1][at])
        # (at a corner the principal stresses are fixed, their directions may still turn:
        # the remainder falls as h down to the floor kept there)
        at_floor = len(CANDIDATES[k]) == 3 and fine < 2e-6
        assert fine < 1e-4 and (at_floor or coarse / fine > 10 ** 0.8), \
            (CANDIDATES[k], coarse, fine)
        # and every point of the kind, not only the median
        assert np.quantile(remainders[1][at], 0.95) < 1e-3, CANDIDATES[k]
    assert kinds >= (2 if phi == 0.0 and tension is None else 5)


@pytest.mark.parametrize("phi,psi,tension", [(0.0, 0.0, None), (30.0, 30.0, None),
                                             (30.0, 5.0, None), (25.0, 0.0, 4e3)])
def test_the_consistent_tangent_converges_at_second_order(phi, psi, tension):
    """Taylor test: |sigma(eps + h d) - sigma(eps) - h C d| falls as h^2 at plastic points
    of every kind of return (as h if the tangent were wrong)."""
    rng = np.random.default_rng(7)
    n = 3000
    d_eps = rng.standard_normal((n, 4)) * 2e-3
    sigma_n = np.tile([-80e3, -120e3, 10e3, -90e3], (n, 1))
    direction = rng.standard_normal((n, 4)) * 1e-3
    args = (E, NU, 10e3, np.sin(np.radians(phi)), np.sin(np.radians(psi)), tension)
    s0, C, code, _ = stress_update(d_eps, sigma_n, *args)
    plastic = (code != ELASTIC) & (code != APEX)
    errors = []
    hs = [1e-2, 1e-3]
    for h in hs:
        s1, _, code1, _ = stress_update(d_eps + h * direction, sigma_n, *args)
        # (points whose return changes kind between the two are at a kink: left out)
        same = plastic & (code1 == code)
        r = np.linalg.norm(s1 - s0 - h * np.einsum("nij,nj->ni", C, direction), axis=1)
        errors.append(r[same])
    kinds = set(code[plastic].tolist())
    assert len(kinds) >= 2, kinds
    m = min(len(e) for e in errors)
    rate = np.log10(np.median(errors[0][:m]) / np.median(errors[1][:m]))
    assert rate > 1.8, rate
