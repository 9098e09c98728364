"""Soil whose modulus grows with depth, E(h) = E_s (1 + lambda h) (the paper's
non-homogeneous soil): against an independent reference (the half-space's impedance by a
Riccati equation per wavenumber, tankfx.verification.reference.gradient_surface_settlement), a
refined
self-reference, monotonicity in lambda, and the homogeneous limit lambda = 0 (Gibson's
closed form for the incompressible limit is in test_extreme.py)."""
import numpy as np
import pytest

from conftest import flexible_scene
from tankfx import analyse
from tankfx.verification.reference import gradient_surface_compliance, gradient_surface_settlement


def _w(**kw):
    return analyse(flexible_scene(nu=0.3, **kw)).results


def test_lambda_zero_is_the_homogeneous_answer():
    assert _w(soil={"E_gradient": 0.0})["w0"] == _w()["w0"]


def test_settlement_falls_as_lambda_grows():
    w = [_w(soil={"E_gradient": lam})["w0"] for lam in (0.0, 0.1, 0.5, 2.0)]
    assert all(w1 < w0 for w0, w1 in zip(w, w[1:])), w


@pytest.mark.verify
def test_agrees_with_refined_self_reference():
    """Default mesh against a mesh twice as fine and one degree higher: within 0.2 %."""
    kw = {"soil": {"E_gradient": 0.5}}
    coarse = _w(**kw)
    fine = _w(soil={"E_gradient": 0.5}, mesh={"degree": 3, "edge_size": 0.025,
                                              "near_size": 0.05})
    for key in ("w0", "w_edge", "w_mean"):
        assert coarse[key] == pytest.approx(fine[key], rel=2e-3), key
    assert coarse["equilibrium"]["relative_error"] < 1e-8


def test_riccati_reference_is_boussinesq_at_lambda_zero_and_converges():
    """The reference itself: at lambda = 0 Boussinesq's compliance 2 (1 - nu^2) / (E k) to
    round-off; at lambda = 0.5 /m RK4 converges (100 against 200 steps, over six decades
    of k: measured 2e-6)."""
    k = np.geomspace(1e-3, 1e3, 7)
    W = gradient_surface_compliance(k, 10e6, 0.0, 0.3, steps=100)
    assert np.allclose(W * 10e6 * k / (2 * (1 - 0.3**2)), 1.0, rtol=1e-12)
    coarse, fine = (gradient_surface_compliance(k, 10e6, 0.5, 0.3, steps=n) for n in (100, 200))
    assert np.max(np.abs(coarse / fine - 1)) < 2e-5


def test_agrees_with_the_riccati_reference():
    """lambda = 0.5 /m, nu = 0.3, default mesh, against the reference (converged to about
    3e-6 at 100 steps; 1.1015709 / 0.6143769 p a / E_s at 100 steps, 1.1015734 /
    0.6143787 at 200): measured w0 +1.2e-6, w_edge +1.3e-5; 2e-7 on a mesh twice as fine."""
    r = _w(soil={"E_gradient": 0.5})
    p, a, E = 100e3, 1.0, 10e6
    w0, w_edge = gradient_surface_settlement(p, a, [0.0, a], E, 0.5, 0.3, steps=100)
    assert r["w0"] == pytest.approx(w0, rel=2e-5)
    assert r["w_edge"] == pytest.approx(w_edge, rel=1e-4)
