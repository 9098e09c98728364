"""The shell elements on rigid supports, against thin plate and shell theory (Timoshenko &
Woinowsky-Krieger, "Theory of plates and shells", 1959, sections 15-16 and 117), at thick and
very thin members: the Kirchhoff constraint is exact, so there is no shear locking."""
import math

import numpy as np
import pytest

from tankfx.fem.evaluate import evaluate_at
from tankfx.verification.rigs import StandaloneShell
from tankfx.laws.shell import flexural_rigidity, wall_beta

A, Q_LOAD, E, NU = 1.0, 1e4, 30e9, 0.3


def plate(thickness, clamped, n=24):
    """Circular plate of radius A under uniform downward q, supported at r = A; elements
    graded towards the edge."""
    s = 1.0 - (1.0 - np.linspace(0.0, 1.0, n + 1)) ** 1.5
    pts = np.column_stack([A * s, np.zeros(n + 1)])
    edge = {"u_r", "u_z", "beta"} if clamped else {"u_r", "u_z"}
    return StandaloneShell(
        pts, E, NU, thickness,
        supports={lambda x: np.isclose(x[0], 0.0): {"u_r", "beta"},
                  lambda x: np.isclose(x[0], A): edge},
        load=lambda v, x: -Q_LOAD * v[1])


@pytest.mark.parametrize("t_over_a", [0.2, 0.1, 0.01, 0.001])
@pytest.mark.parametrize("clamped", [True, False], ids=["clamped", "simply_supported"])
def test_circular_plate_on_rigid_supports(t_over_a, clamped):
    t = t_over_a * A
    D = flexural_rigidity(E, NU, t)
    shell = plate(t, clamped)
    F = shell.resultants()
    w0 = -evaluate_at(F["u"], np.array([[0.0, 0.0]]))[0, 1]
    M = evaluate_at(F["M_s"], np.array([[0.0, 0.0], [A, 0.0]]))[:, 0]
    Qa = evaluate_at(F["Q"], np.array([[A, 0.0]]))[0, 0]
    if clamped:
        assert w0 == pytest.approx(Q_LOAD * A**4 / (64 * D), rel=5e-3)
        assert M[0] == pytest.approx((1 + NU) * Q_LOAD * A**2 / 16, rel=5e-3)
        assert M[1] == pytest.approx(-Q_LOAD * A**2 / 8, rel=5e-3)
    else:
        assert w0 == pytest.approx((5 + NU) * Q_LOAD * A**4 / (64 * (1 + NU) * D), rel=5e-3)
        assert M[0] == pytest.approx((3 + NU) * Q_LOAD * A**2 / 16, rel=5e-3)
        assert abs(M[1]) < 5e-3 * Q_LOAD * A**2
    # the edge section carries the whole load: Q_r(a) = q a / 2 (upward on the inner part)
    assert Qa == pytest.approx(Q_LOAD * A / 2, rel=1e-8)


@pytest.mark.parametrize("t_over_R", [1e-2, 1e-3, 1e-4])
def test_wall_with_clamped_base_under_liquid(t_over_R):
    """Long cylindrical shell full of liquid (unit weight gamma, height H): base moment
    gamma (H - 1/beta) / (2 beta^2) (inner face in tension: negative here) and base shear
    gamma (2 beta H - 1) / (2 beta^2), beta^4 = 3 (1 - nu^2) / (R t)^2."""
    R, H, gamma = 10.0, 8.0, 9810.0
    t = t_over_R * R
    beta = wall_beta(R, t, NU)
    assert beta * H > 10, "the long-shell formulas need beta H >> 1"
    n = 60
    z = H * np.linspace(0.0, 1.0, n + 1) ** 2
    shell = StandaloneShell(np.column_stack([np.full(n + 1, R), z]), 200e9, NU, t,
                            supports={lambda x: np.isclose(x[1], 0.0): {"u_r", "u_z", "beta"}},
                            load=lambda v, x: gamma * (H - x[1]) * v[0])
    F = shell.resultants()
    M0 = evaluate_at(F["M_s"], np.array([[R, 0.0]]))[0, 0]
    Q0 = evaluate_at(F["Q"], np.array([[R, 0.0]]))[0, 0]
    assert M0 == pytest.approx(-gamma * (H - 1 / beta) / (2 * beta**2), rel=1e-2)
    assert abs(Q0) == pytest.approx(gamma * (2 * beta * H - 1) / (2 * beta**2), rel=1e-2)
    # away from the base the wall carries the liquid by hoop tension alone, N = gamma (H-z) R,
    # up to the base's bending disturbance, which has decayed to e^(-beta z) < 1 % there
    zm = 0.5 * H
    N = evaluate_at(F["N_theta"], np.array([[R, zm]]))[0, 0]
    assert N == pytest.approx(gamma * (H - zm) * R, rel=1e-2)


def test_uniform_plate_bending_is_exact_on_a_coarse_mesh():
    """Rotation is C0 P2 and u.n C1 cubic: the clamped plate's deflection (quartic) is
    already within 0.1 % on 6 elements, whatever the thickness."""
    for t in (0.2, 1e-3):
        D = flexural_rigidity(E, NU, t)
        F = plate(t, True, n=6).resultants()
        w0 = -evaluate_at(F["u"], np.array([[0.0, 0.0]]))[0, 1]
        assert w0 == pytest.approx(Q_LOAD * A**4 / (64 * D), rel=1e-3)
    assert math.isfinite(w0)


# ---- members whose thickness steps: a wall of courses, a plate with a thickened annular
# ring, against the thin-shell and thin-plate equations solved exactly stretch by stretch
# (tankfx.verification.reference: continuity of w, slope, moment and shear at each step)

COURSES = [(2.0, 0.020), (3.0, 0.012), (3.0, 0.008)]     # (height, thickness) from the base


def _course_of(z):
    tops = np.cumsum([h for h, _ in COURSES])
    return np.array([t for _, t in COURSES])[np.searchsorted(tops, z)]


def _wall_of_courses(per_course):
    """The wall on a mesh with a vertex at every joint, graded towards both ends of each
    course (where the joints disturb the membrane state)."""
    z, base = [0.0], 0.0
    s = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, per_course + 1))[1:]
    for h, _ in COURSES:
        z += list(base + h * s)
        base += h
    R, gamma, H = 10.0, 9810.0, base
    return StandaloneShell(np.column_stack([np.full(len(z), R), z]), 200e9, NU,
                           lambda mid: _course_of(mid[:, 1]),
                           supports={lambda x: np.isclose(x[1], 0.0): {"u_r", "u_z", "beta"}},
                           load=lambda v, x: gamma * (H - x[1]) * v[0])


def test_wall_of_courses_under_liquid_converges_to_the_stepped_shell_solution():
    from tankfx.verification.reference import stepped_wall_under_liquid

    R, gamma, H = 10.0, 9810.0, sum(h for h, _ in COURSES)
    # the base, both sides of each joint, mid-course
    z = np.array([0.0, 0.5, 1.0, 1.95, 2.05, 3.5, 4.95, 5.05, 6.5])
    w_ref, M_ref = stepped_wall_under_liquid(R, COURSES, 200e9, NU, gamma, H, z)
    pts = np.column_stack([np.full(len(z), R), z])
    errors = []
    for per_course in (10, 20):
        F = _wall_of_courses(per_course).resultants()
        M = evaluate_at(F["M_s"], pts)[:, 0]
        w = evaluate_at(F["u"], pts)[:, 0]
        errors.append(np.max(np.abs(M - M_ref)) / np.max(np.abs(M_ref)))
        assert np.max(np.abs(w - w_ref)) < 5e-4 * np.max(np.abs(w_ref))
    # measured 7.9e-3 and 2.4e-3: second order (the moment is the derivative of the P2
    # rotation); the joints' moments (a tenth of the base's) are resolved too
    assert errors[1] < 3e-3
    assert errors[0] / errors[1] > 2.8


@pytest.mark.parametrize("clamped", [True, False], ids=["clamped", "simply_supported"])
def test_plate_with_annular_ring_matches_the_stepped_plate_solution(clamped):
    """A floor 10 mm thick with a 30 mm annular ring on 0.8 a < r < a (an API 650 tank's
    annular bottom plate), under a uniform pressure."""
    from tankfx.verification.reference import stepped_plate

    zones = [(0.8, 0.01), (A, 0.03)]
    n = 24
    r = np.concatenate([0.8 * (1 - (1 - np.linspace(0, 1, n + 1)) ** 1.5),
                        0.8 + 0.2 * np.linspace(0, 1, n // 3 + 1)[1:]])
    edge = {"u_r", "u_z", "beta"} if clamped else {"u_r", "u_z"}
    shell = StandaloneShell(np.column_stack([r, 0 * r]), E, NU,
                            lambda mid: np.where(mid[:, 0] < 0.8, 0.01, 0.03),
                            supports={lambda x: np.isclose(x[0], 0.0): {"u_r", "beta"},
                                      lambda x: np.isclose(x[0], A): edge},
                            load=lambda v, x: -Q_LOAD * v[1])
    F = shell.resultants()
    rq = np.array([0.0, 0.4, 0.79, 0.81, 0.9, A])
    pts = np.column_stack([rq, 0 * rq])
    w = -evaluate_at(F["u"], pts)[:, 1]
    M = evaluate_at(F["M_s"], pts)[:, 0]
    w_ref, M_ref, _ = stepped_plate(A, zones, E, NU, Q_LOAD, clamped, rq)
    # measured: w 1.8e-5 / 6.2e-6, M 3.1e-3 / 7.9e-3 of the largest (clamped / simply
    # supported), halving the elements quarters the moment's error
    assert np.max(np.abs(w - w_ref)) < 1e-4 * np.max(w_ref)
    assert np.max(np.abs(M - M_ref)) < 1e-2 * np.max(np.abs(M_ref))
