"""Closed-form reference solutions used by the tests, benchmarks and demos.

All for a linear elastic, homogeneous, isotropic half-space (modulus E, Poisson's ratio nu)
under a uniform pressure p on a circle of radius a (Boussinesq's flexible load; Poulos &
Davis, "Elastic solutions for soil and rock mechanics", 1974, Table 3.1 and Eq. 3.1), and
the rigid limit of a free plate on it (:func:`rigid_plate_centre_moment`).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["elliptic_K_E", "flexible_surface_settlement", "flexible_centre_settlement",
           "flexible_edge_settlement",
           "flexible_mean_settlement", "flexible_axis_stress", "flexible_axis_radial_stress",
           "point_load_displacement",
           "rigid_plate_centre_moment"]


def flexible_centre_settlement(p, a, E, nu):
    """w(0) = 2 p a (1 - nu^2) / E."""
    return 2.0 * p * a * (1.0 - nu**2) / E


def flexible_edge_settlement(p, a, E, nu):
    """w(a) = 4 p a (1 - nu^2) / (pi E)."""
    return 4.0 * p * a * (1.0 - nu**2) / (math.pi * E)


def flexible_mean_settlement(p, a, E, nu):
    """Mean over the loaded circle, 16 p a (1 - nu^2) / (3 pi E) (= 0.849 w(0))."""
    return 16.0 * p * a * (1.0 - nu**2) / (3.0 * math.pi * E)


def elliptic_K_E(k):
    """Complete elliptic integrals K(k) and E(k) of modulus k (0 <= k < 1), by the
    arithmetic-geometric mean (converged to round-off)."""
    k = np.asarray(k, dtype=float)
    a, b = np.ones_like(k), np.sqrt(1.0 - k**2)
    c_sum = 0.5 * k**2
    power = 0.5
    for _ in range(40):
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), np.sqrt(a * b)
        power *= 2.0
        c_sum = c_sum + power * c**2
    K = np.pi / (2.0 * a)
    return K, K * (1.0 - c_sum)


def flexible_surface_settlement(p, a, E, nu, r):
    """Surface settlement of the flexible circular load at radius r (Poulos & Davis Eq. 3.1):
    w = 4 p a (1 - nu^2) / (pi E) * E(r/a) inside, and
    w = 4 p a (1 - nu^2) / (pi E) * (r/a) [E(a/r) - (1 - a^2/r^2) K(a/r)] outside."""
    r = np.atleast_1d(np.asarray(r, dtype=float))
    c = 4.0 * p * a * (1.0 - nu**2) / (math.pi * E)
    w = np.empty_like(r)
    inside = r <= a
    _, Ei = elliptic_K_E(np.minimum(r[inside] / a, 1.0 - 1e-16))
    w[inside] = c * Ei
    k = a / r[~inside]
    Ko, Eo = elliptic_K_E(k)
    w[~inside] = c * (Eo - (1.0 - k**2) * Ko) / k
    return w


def flexible_axis_stress(p, a, depth):
    """Vertical stress on the axis (compression positive), p [1 - z^3 / (a^2 + z^2)^1.5]."""
    z = np.asarray(depth, dtype=float)
    return p * (1.0 - z**3 / (a**2 + z**2) ** 1.5)


def flexible_axis_radial_stress(p, a, nu, depth):
    """Radial (= hoop) stress on the axis (compression positive), p/2 [(1 + 2 nu) - 2 (1 +
    nu) z / R + (z / R)^3], R = sqrt(a^2 + z^2) (Poulos & Davis, Eq. 3.6)."""
    z = np.asarray(depth, dtype=float)
    c = z / np.sqrt(a**2 + z**2)
    return 0.5 * p * ((1.0 + 2.0 * nu) - 2.0 * (1.0 + nu) * c + c**3)


def point_load_displacement(P, E, nu, r, depth):
    """Boussinesq's displacement (u_r outward, w downward) under a downward point force P
    at the surface of a half-space, at radius r and depth h >= 0 (not both zero)."""
    G = E / (2.0 * (1.0 + nu))
    rho = np.hypot(r, depth)
    c = P / (4.0 * math.pi * G * rho)
    w = c * (2.0 * (1.0 - nu) + depth**2 / rho**2)
    u_r = c * (r * depth / rho**2 - (1.0 - 2.0 * nu) * r / (rho + depth))
    return u_r, w


def rigid_plate_centre_moment(q, a, nu_plate):
    """Bending moment at the centre (N m/m, sagging positive) of a free circular plate of
    radius a under a uniform pressure q, in the rigid limit (Kp -> infinity) on a smooth
    half-space.

    The plate then carries q down and the smooth rigid punch's contact pressure
    p(r) = q a / (2 sqrt(a^2 - r^2)) up (Boussinesq; Poulos & Davis 1974, Eq. 7.1): a
    self-equilibrated load, under which the free plate is the simply supported one (no edge
    reaction). Summing the centre moment of a ring load P at radius b on a simply supported
    plate, P / (8 pi) [(1 - nu)(1 - b^2/a^2) + 2 (1 + nu) ln(a / b)] (Timoshenko &
    Woinowsky-Krieger 1959, Sec. 19), over q gives (3 + nu) q a^2 / 16, and over -p, with
    int_0^(pi/2) sin t ln(sin t) dt = ln 2 - 1:

        M0 = q a^2 [(3 + nu) / 16 - (1 - nu) / 24 - (1 + nu)(1 - ln 2) / 4]

    (0.07736 q a^2 at nu = 0.3; Brown's (1969) free raft at Kp = 10 has 0.0747)."""
    return q * a**2 * ((3.0 + nu_plate) / 16.0 - (1.0 - nu_plate) / 24.0
                       - (1.0 + nu_plate) * (1.0 - math.log(2.0)) / 4.0)
