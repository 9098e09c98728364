"""Closed-form reference solutions used by the tests, benchmarks and demos.

All for a linear elastic, homogeneous, isotropic half-space (modulus E, Poisson's ratio nu)
under a uniform pressure p on a circle of radius a (Boussinesq's flexible load; Poulos &
Davis, "Elastic solutions for soil and rock mechanics", 1974, Table 3.1 and Eq. 3.1), and
the rigid limit of a free plate on it (:func:`rigid_plate_centre_moment`); and for
layered ground, the flexible load's surface settlement by Hankel transform
(:func:`layered_surface_settlement`: Burmister's layered system, evaluated to round-off).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["elliptic_K_E", "flexible_surface_settlement", "flexible_centre_settlement",
           "flexible_edge_settlement",
           "flexible_mean_settlement", "flexible_axis_stress", "flexible_axis_radial_stress",
           "point_load_displacement",
           "rigid_plate_centre_moment", "bessel_j", "layered_surface_compliance",
           "layered_surface_settlement", "one_dimensional_settlement"]


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


# --------------------------------------------------------------------------- layered ground
# Under a surface load p(r) J0-transformed, the displacements of an axisymmetric layered
# elastic body are u_r = U(z) J1(k r), u_z = W(z) J0(k r) (z down), with the tractions on
# horizontal planes sigma_rz = S(z) J1(k r), sigma_zz = T(z) J0(k r). In a homogeneous layer
# Navier's equations give four solutions per wavenumber k: two decaying from the layer's top
# (a harmonic potential's, and one with z e^{-kz}), and their mirror images decaying from
# its bottom. Written so, every coefficient multiplies a function bounded by 1 in the layer,
# and the layers' continuity conditions form a small well-conditioned system per k (no
# propagator matrices whose e^{kh} overflow).


def bessel_j(n: int, x) -> np.ndarray:
    """J_n(x), n = 0 or 1, to round-off: below x = 30 by Bessel's integral (1/pi) int_0^pi
    cos(n t - x sin t) dt, whose periodic integrand the trapezoidal rule integrates to
    round-off with more than x/2 + 20 points; above, by Hankel's asymptotic expansion (its
    14 terms there below 1e-14)."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    out = np.empty_like(x)
    small = x < 30.0
    m = 96
    t = np.linspace(0.0, np.pi, m + 1)
    w = np.full(m + 1, np.pi / m)
    w[[0, -1]] *= 0.5
    for chunk in np.array_split(np.flatnonzero(small), max(1, small.sum() // 4096)):
        out[chunk] = np.cos(n * t[None, :] - x[chunk, None] * np.sin(t)[None, :]) @ w / np.pi
    xl = x[~small]
    mu = 4.0 * n * n
    P, Q, term = np.ones_like(xl), np.zeros_like(xl), np.ones_like(xl)
    for k in range(1, 28):
        term = term * (mu - (2 * k - 1) ** 2) / (k * 8.0 * xl)
        if k % 2:
            Q += (-1) ** (k // 2) * term
        else:
            P += (-1) ** (k // 2) * term
    chi = xl - (0.5 * n + 0.25) * np.pi
    out[~small] = np.sqrt(2.0 / (np.pi * xl)) * (P * np.cos(chi) - Q * np.sin(chi))
    return out


def _modes(k, x, h, G, nu):
    """(U, W, S / (2 G_1 k) ...) of the four solutions at depth x below a layer's top (a
    layer of thickness h; h = inf: a half-space, whose two growing modes are absent), per
    wavenumber k: an array (n_k, 4 quantities, 4 modes). S and T are per unit of 2 G k."""
    kappa = 3.0 - 4.0 * nu
    e = np.exp(-k * x)
    kx = k * x
    cols = [(e, e, -G * e, -G * e),
            (kx * e, (kx + kappa) * e, -G * (1.0 - 2.0 * nu + kx) * e,
             -G * (2.0 * (1.0 - nu) + kx) * e)]
    if np.isfinite(h):
        eta = x - h
        g = np.exp(k * eta)
        ke = k * eta
        cols += [(g, -g, G * g, -G * g),
                 (-ke * g, (ke - kappa) * g, G * (1.0 - 2.0 * nu - ke) * g,
                  -G * (2.0 * (1.0 - nu) - ke) * g)]
    return np.stack([np.stack(np.broadcast_arrays(*c), axis=-1) for c in cols], axis=-1)


def layered_surface_compliance(k, layers, base=None) -> np.ndarray:
    """W(0) per unit of surface pressure amplitude (m/Pa... per k), for the J0 mode of
    wavenumber k (1/m, array) on ``layers`` = [(thickness, E, nu), ...] from the surface
    down, over ``base`` = (E, nu), an elastic half-space, or None, a rough rigid base.
    A homogeneous half-space gives 2 (1 - nu^2) / (E k)."""
    k = np.atleast_1d(np.asarray(k, dtype=float))
    parts = [(float(h), E / (2.0 * (1.0 + nu)), nu) for h, E, nu in layers]
    if base is not None:
        parts.append((math.inf, base[0] / (2.0 * (1.0 + base[1])), base[1]))
    if not parts:
        raise ValueError("layered_surface_compliance: no ground (give layers or a base)")
    G_ref = parts[0][1]
    sizes = [2 if math.isinf(h) else 4 for h, _, _ in parts]
    n = sum(sizes)
    A = np.zeros((len(k), n, n))
    rhs = np.zeros((len(k), n))
    col = np.cumsum([0, *sizes])
    # the tractions are carried per unit of 2 G k; scaled by G_ref, every row is O(1)
    top = _modes(k, 0.0, parts[0][0], parts[0][1] / G_ref, parts[0][2])
    A[:, 0, col[0]:col[1]] = top[:, 2]
    A[:, 1, col[0]:col[1]] = top[:, 3]
    rhs[:, 1] = -1.0 / (2.0 * G_ref * k)      # T(0) = -1: a unit pressure, downward
    row = 2
    for i in range(len(parts) - 1):
        h, G, nu = parts[i]
        below = parts[i + 1]
        A[:, row:row + 4, col[i]:col[i + 1]] = _modes(k, h, h, G / G_ref, nu)
        A[:, row:row + 4, col[i + 1]:col[i + 2]] = -_modes(k, 0.0, below[0], below[1] / G_ref,
                                                           below[2])
        row += 4
    if base is None:
        h, G, nu = parts[-1]
        A[:, row:row + 2, col[-2]:col[-1]] = _modes(k, h, h, G / G_ref, nu)[:, :2]
    c = np.linalg.solve(A, rhs[..., None])[..., 0]
    return np.einsum("km,km->k", top[:, 1], c[:, col[0]:col[1]])


def layered_surface_settlement(p, a, r, layers, base=None, panels_per_period=2,
                               points=16) -> np.ndarray:
    """Surface settlement (m) at radii ``r`` of a uniform pressure p on a circle of radius a
    on layered ground (see :func:`layered_surface_compliance` for ``layers`` and ``base``):
    w(r) = p a int_0^inf J1(k a) J0(k r) W(k) dk. The part of W of a half-space of the top
    layer's material is Boussinesq's (:func:`flexible_surface_settlement`); the rest decays
    like exp(-2 k h_1) and is integrated by Gauss-Legendre panels, graded near k = 0 (the
    deep layers' scale) and a few per period of the Bessel functions' oscillation."""
    r = np.atleast_1d(np.asarray(r, dtype=float))
    _, E1, nu1 = layers[0] if layers else (None, *base)
    G1 = E1 / (2.0 * (1.0 + nu1))
    w = flexible_surface_settlement(p, a, E1, nu1, r)
    if not layers:
        return w
    h1 = layers[0][0]
    depth = sum(h for h, _, _ in layers)
    k_max = 40.0 / h1
    breaks = [np.geomspace(1e-4 / max(depth, a), k_max, 400)]
    for rr in r:
        period = 2.0 * np.pi / (a + rr)
        breaks.append(np.arange(0.0, k_max, period / panels_per_period))
    breaks = np.unique(np.concatenate([[0.0], *breaks]))
    xg, wg = np.polynomial.legendre.leggauss(points)
    lo, hi = breaks[:-1, None], breaks[1:, None]
    k = (0.5 * (hi - lo) * xg + 0.5 * (hi + lo)).ravel()
    wk = (0.5 * (hi - lo) * wg).ravel()
    rest = layered_surface_compliance(k, layers, base) - (1.0 - nu1) / (G1 * k)
    j1 = bessel_j(1, k * a)
    for i, rr in enumerate(r):
        j0 = bessel_j(0, k * rr) if rr > 0 else 1.0
        w[i] += p * a * np.sum(wk * j1 * j0 * rest)
    return w


def one_dimensional_settlement(p, layers) -> float:
    """Settlement of a uniform pressure p over the whole surface of ``layers`` =
    [(thickness, E, nu), ...] on a rigid base: every layer compresses in confined
    (oedometric) strain, sum of p h / M with M = E (1 - nu) / ((1 + nu)(1 - 2 nu))."""
    return sum(p * h * (1.0 + nu) * (1.0 - 2.0 * nu) / (E * (1.0 - nu)) for h, E, nu in layers)
