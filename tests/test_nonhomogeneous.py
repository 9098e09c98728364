"""Soil whose modulus grows with depth, E(h) = E_s (1 + lambda h) (the paper's
non-homogeneous soil): no closed form, so checked against a refined self-reference, for
monotonicity in lambda, and for the homogeneous limit lambda = 0."""
import pytest

from conftest import flexible_scene
from tankfx import analyse


def _w(**kw):
    return analyse(flexible_scene(nu=0.3, **kw)).results


def test_lambda_zero_is_the_homogeneous_answer():
    assert _w(soil={"E_gradient": 0.0})["w0"] == _w()["w0"]


def test_settlement_falls_as_lambda_grows():
    w = [_w(soil={"E_gradient": lam})["w0"] for lam in (0.0, 0.1, 0.5, 2.0)]
    assert all(w1 < w0 for w0, w1 in zip(w, w[1:])), w


def test_agrees_with_refined_self_reference():
    """Default mesh against a mesh twice as fine and one degree higher: within 0.2 %."""
    kw = {"soil": {"E_gradient": 0.5}}
    coarse = _w(**kw)
    fine = _w(soil={"E_gradient": 0.5}, mesh={"degree": 3, "edge_size": 0.025,
                                              "near_size": 0.05})
    for key in ("w0", "w_edge", "w_mean"):
        assert coarse[key] == pytest.approx(fine[key], rel=2e-3), key
    assert coarse["equilibrium"]["relative_error"] < 1e-8
