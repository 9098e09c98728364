"""Modified Cam Clay at the quadrature points (Roscoe & Burland 1968): the yield ellipse

    f = q^2 / M^2 + p' (p' - p_c) <= 0,

p' = -tr(sigma') / 3 (compression positive), q = sqrt(3/2) |s| (s the deviator), p_c the
preconsolidation pressure (the ellipse's tip), M the critical state's stress ratio;
associated flow, and the hardening of the plastic volume change,

    p_c = p_c0 exp(eps_v^p / (lambda* - kappa*)),

eps_v^p compressive. Inside it the bulk modulus is p' / kappa* (volumetric elastic strain
kappa* ln(p' / p'_0), integrated exactly over a step: p' = p'_n exp(d eps_v^e / kappa*)),
and the shear modulus G = 3 K (1 - 2 nu) / (2 (1 + nu)) of the committed state (fixed
over a step, so that the deviatoric return is radial). lambda* and kappa* are the modified
indices (the volumetric strain against ln p'; lambda / (1 + e) of the e-ln p' chart).

Below ``p_min`` (the least mean stress) the bulk modulus is that of p_min: a ground surface
at p' = 0 would have no stiffness. p_min is also the least preconsolidation pressure: p_c =
max(p_c0 exp(eps_v^p / (lambda* - kappa*)), p_min), so that a dilating point on the dry side
softens down to the ellipse of p_min and no further (as OpenGeoSys' MFront Cam Clay's
``MinimalPreConsolidationPressure``), hardening from it again when compressed; without it
its ellipse shrinks towards the origin without end and the return with it. The ground at rest
has p_c0 >= p_min (:mod:`tankfx.laws.cam_clay`), so the strength above p_min is not changed.

The return (Borja & Lee 1990; de Souza Neto, Peric & Owen 2008, Sec. 10.2): unknowns the
plastic volume change x and the multiplier dgamma, with

    p' = P(p'_n, d eps_v - x),   p_c = p_cn exp(x / (lambda* - kappa*)),
    q = q_tr / (1 + 6 G dgamma / M^2),
    x = dgamma (2 p' - p_c),     f(p', q, p_c) = 0,

solved by Newton per point (vectorised over the points), and its consistent tangent from
the same equations (implicit differentiation). Where that p_c falls below p_min the return is
solved again with p_c = p_min held (perfect plasticity on the least ellipse: dp_c/dx = 0 in
the same equations and tangent). Everything here is numpy; Mandel vectors
(rr, zz, sqrt 2 rz, theta), tension positive, as :mod:`tankfx.laws.point_law`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

from .plasticity import IDENTITY
from .point_law import PointUpdate

#: the deviatoric projector of Mandel vectors
DEVIATORIC = np.eye(4) - np.outer(IDENTITY, IDENTITY) / 3.0
#: the return's Newton: its iterations at most, and its tolerance on f / p_c^2 and on x
RETURN_ITERATIONS, RETURN_TOLERANCE = 60, 1e-12
#: the largest exponent taken in the exponential laws (a step of more is no soil's)
MAX_EXPONENT = 30.0


def critical_state_ratio(friction_angle_deg):
    """M of triaxial compression from the critical state's friction angle (degrees):
    6 sin phi / (3 - sin phi)."""
    s = np.sin(np.radians(friction_angle_deg))
    return 6.0 * s / (3.0 - s)


def critical_state_angle(M):
    """The inverse of :func:`critical_state_ratio`: phi_cs (degrees) of M."""
    M = np.asarray(M, dtype=float)
    return np.degrees(np.arcsin(3.0 * M / (6.0 + M)))


def shear_modulus(K, nu):
    """G of the bulk modulus K and Poisson's ratio nu."""
    return 1.5 * K * (1.0 - 2.0 * nu) / (1.0 + nu)


def normally_consolidated_ratio(M, lambda_star, kappa_star, nu):
    """The stress ratio eta = q / p' and K0 = sigma'_h / sigma'_v of one-dimensional
    normally consolidated compression: the eta at which an increment on the ellipse (eta
    constant, p_c / p' = 1 + eta^2 / M^2) strains the soil only vertically, eps_q = 2/3
    eps_v:

        eta kappa* 2 (1 + nu) / (9 (1 - 2 nu)) + (lambda* - kappa*) 2 eta / (M^2 - eta^2)
            = 2/3 lambda*,

    solved by bisection on (0, M) (its left side rises from 0 to infinity).
    K0 = (3 - eta) / (3 + 2 eta)."""
    M, lam, kap, nu = (np.asarray(v, dtype=float) for v in (M, lambda_star, kappa_star, nu))
    lo, hi = np.zeros_like(M * lam), M * np.ones_like(lam)

    def left(eta):
        return (eta * kap * 2.0 * (1.0 + nu) / (9.0 * (1.0 - 2.0 * nu))
                + (lam - kap) * 2.0 * eta / (M * M - eta * eta) - 2.0 / 3.0 * lam)

    for _ in range(80):
        mid = 0.5 * (lo + hi)
        below = left(mid) < 0.0
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    eta = 0.5 * (lo + hi)
    return eta, (3.0 - eta) / (3.0 + 2.0 * eta)


def elastic_pressure(p_n, e, kappa_star, p_min):
    """p' after the compressive elastic volumetric strain ``e`` from p'_n, and the bulk
    modulus there (dp'/de), where dp'/de = max(p', p_min) / kappa*: exponential above p_min,
    linear below it (exact, continuous, with a continuous modulus)."""
    p_n, e = np.asarray(p_n, dtype=float), np.asarray(e, dtype=float)
    lin = p_min / kappa_star
    above = p_n >= p_min
    with np.errstate(divide="ignore", invalid="ignore"):
        # strain at which p' reaches p_min: down from above, up from below
        e_star = np.where(above, kappa_star * np.log(np.maximum(p_min, 1e-300)
                                                     / np.maximum(p_n, 1e-300)),
                          kappa_star * (p_min - p_n) / np.maximum(p_min, 1e-300))
    expo = np.where(above, e, e - e_star) / kappa_star
    exp_part = np.where(above, p_n, p_min) * np.exp(np.minimum(expo, MAX_EXPONENT))
    lin_part = np.where(above, p_min + lin * (e - e_star), p_n + lin * e)
    use_exp = np.where(above, e >= e_star, e > e_star)
    p = np.where(use_exp, exp_part, lin_part)
    return p, np.maximum(p, p_min) / kappa_star


def invariants(sigma):
    """(p', q, the deviator s) of Mandel stresses (N, 4), tension positive, p' compressive."""
    p = -(sigma @ IDENTITY) / 3.0
    s = sigma + p[:, None] * IDENTITY
    return p, np.sqrt(1.5 * np.einsum("ij,ij->i", s, s)), s


def cam_clay_update(d_eps, sigma_n, p_cn, M, lambda_star, kappa_star, nu, p_min):
    """The total effective stress after the strain increment ``d_eps`` (N, 4) from the
    committed total ``sigma_n`` (N, 4) and preconsolidation pressure ``p_cn`` (N,; at least
    ``p_min``): (stress, consistent tangent (N, 4, 4), yielding (N,), plastic strain
    increment (N, 4), p_c (N,), converged (N,): the return's Newton converged). A zero
    increment gives ``sigma_n`` back bit for bit (the ground at rest is in equilibrium
    exactly, its crust capped on the ellipse too)."""
    N = len(d_eps)
    p_cn = np.maximum(p_cn, p_min)
    p_n, _, s_n = invariants(sigma_n)
    G = shear_modulus(np.maximum(p_n, p_min) / kappa_star, nu)
    e_c = -(d_eps @ IDENTITY)                                  # compressive volume change
    s_tr = s_n + 2.0 * G[:, None] * (d_eps @ DEVIATORIC)
    norm = np.sqrt(np.einsum("ij,ij->i", s_tr, s_tr))
    q_tr = math.sqrt(1.5) * norm
    n = np.where(norm[:, None] > 0.0, s_tr / np.maximum(norm, 1e-300)[:, None], 0.0)
    p_tr, K_tr = elastic_pressure(p_n, e_c, kappa_star, p_min)
    scale = np.maximum(p_cn, p_min) ** 2
    f_tr = (q_tr ** 2 / M ** 2 + p_tr * (p_tr - p_cn)) / scale
    out = f_tr > RETURN_TOLERANCE
    # elastic: K_t m m^T + 2 G I_d
    C = K_tr[:, None, None] * np.outer(IDENTITY, IDENTITY) + \
        2.0 * G[:, None, None] * DEVIATORIC
    # (the committed stress plus its change, not -p_tr m + s_tr: that rebuilds sigma_n from
    # its invariants, and a zero strain gave a change of 1e-13 Pa at a capped crust's points
    # at rest, an out-of-balance force with no load)
    sigma = sigma_n + (p_n - p_tr)[:, None] * IDENTITY + \
        2.0 * G[:, None] * (d_eps @ DEVIATORIC)
    p_c = np.array(p_cn, dtype=float, copy=True)
    d_eps_p = np.zeros((N, 4))
    converged = np.ones(N, dtype=bool)
    if out.any():
        args = (e_c[out], q_tr[out], p_n[out], p_cn[out], G[out], n[out], M[out],
                lambda_star[out], kappa_star[out], p_min)
        r = list(_return(*args))
        # the least preconsolidation pressure: where the hardening law's p_c falls below
        # p_min (a point dilating on the dry side, or one whose return found no end there:
        # its ellipse shrinking towards the origin), the return with p_c = p_min held,
        # kept where it is consistent (its plastic volume change at most the one that
        # takes p_c to p_min)
        low = (r[2] < p_min) | ~r[4]
        if low.any():
            held = _return(*(a[low] if isinstance(a, np.ndarray) else a for a in args),
                           floored=True)
            x_star = (lambda_star[out][low] - kappa_star[out][low]) * np.log(
                p_min / p_cn[out][low])
            x_held = -(held[3] @ IDENTITY)
            ok = held[4] & (x_held <= x_star + 1e-12 * (1.0 + np.abs(x_star)))
            idx = np.flatnonzero(low)[ok]
            for k in range(5):
                r[k][idx] = held[k][ok]
            r[4][np.flatnonzero(low)[~ok]] = False
        sigma[out], C[out], p_c[out], d_eps_p[out], converged[out] = r
    return sigma, C, out, d_eps_p, p_c, converged


def _return(e_c, q_tr, p_n, p_cn, G, n, M, lam, kap, p_min, floored=False):
    """The return to the ellipse of the points outside it (the module's docstring);
    ``floored``: with p_c = p_min held (the least ellipse, perfectly plastic)."""
    hard = lam - kap
    M2 = M * M
    a = 6.0 * G / M2
    scale = p_cn * p_cn

    def local(x, g):
        """The state at (x, dgamma) and the local system's Jacobian d(R1, R2)/d(x, g)."""
        p, K = elastic_pressure(p_n, e_c - x, kap, p_min)
        if floored:
            pc = np.full_like(x, p_min)
            dpc_dx = np.zeros_like(x)
        else:
            pc = p_cn * np.exp(np.clip(x / hard, -MAX_EXPONENT, MAX_EXPONENT))
            dpc_dx = pc / hard
        beta = 1.0 / (1.0 + a * g)
        q = q_tr * beta
        dp_dx, dq_dg = -K, -q * a * beta
        J = (1.0 - g * (2.0 * dp_dx - dpc_dx), -(2.0 * p - pc),
             ((2.0 * p - pc) * dp_dx - p * dpc_dx) / scale, 2.0 * q * dq_dg / M2 / scale)
        return p, K, pc, beta, q, J

    x, g = np.zeros_like(e_c), np.zeros_like(e_c)
    done = np.zeros(len(e_c), dtype=bool)
    for _ in range(RETURN_ITERATIONS):
        p, K, pc, beta, q, (J11, J12, J21, J22) = local(x, g)
        R1 = x - g * (2.0 * p - pc)
        f = q * q / M2 + p * (p - pc)
        R2 = f / scale
        # (f relative to the state's own size: p_c may grow tenfold in a step, and f's
        # round-off with it)
        done = (np.abs(R1) <= RETURN_TOLERANCE * (1.0 + np.abs(x))) & \
            (np.abs(f) <= RETURN_TOLERANCE * np.maximum(pc, p) ** 2)
        if done.all():
            break
        det = J11 * J22 - J12 * J21
        dx = -(J22 * R1 - J12 * R2) / det
        dg = -(-J21 * R1 + J11 * R2) / det
        # (a step that would make the multiplier negative or p_c jump by more than e^2
        # is shortened: the exponential laws' Newton overshoots from far outside)
        t = np.ones_like(dx)
        t = np.where(g + dg < 0.0, np.minimum(t, 0.5 * g / np.maximum(-dg, 1e-300)), t)
        if not floored:
            t = np.where(np.abs(dx) > 2.0 * hard,
                         np.minimum(t, 2.0 * hard / np.maximum(np.abs(dx), 1e-300)), t)
        t = np.where(done, 0.0, t)
        x, g = x + t * dx, np.maximum(g + t * dg, 0.0)
    p, K, pc, beta, q, (J11, J12, J21, J22) = local(x, g)
    sigma = -p[:, None] * IDENTITY + math.sqrt(2.0 / 3.0) * q[:, None] * n
    # the consistent tangent: the local system's derivatives with respect to the inputs
    # e_c (d e_c = -m . d eps) and q_tr (d q_tr = sqrt 6 G n . d eps)
    det = J11 * J22 - J12 * J21
    R1_e, R2_e = -2.0 * g * K, (2.0 * p - pc) * K / scale
    R2_q = 2.0 * q / M2 * beta / scale
    # dy = -J^-1 dR
    x_e = -(J22 * R1_e - J12 * R2_e) / det
    g_e = -(-J21 * R1_e + J11 * R2_e) / det
    x_q = -(-J12 * R2_q) / det
    g_q = -(J11 * R2_q) / det
    c_e = -np.broadcast_to(IDENTITY, n.shape)                  # d e_c / d eps
    c_q = math.sqrt(6.0) * G[:, None] * n                      # d q_tr / d eps
    dp = K[:, None] * ((1.0 - x_e)[:, None] * c_e - x_q[:, None] * c_q)
    dg = g_e[:, None] * c_e + g_q[:, None] * c_q
    dq = beta[:, None] * (c_q - (q * a)[:, None] * dg)
    C = -np.einsum("i,nj->nij", IDENTITY, dp) \
        + math.sqrt(2.0 / 3.0) * np.einsum("ni,nj->nij", n, dq) \
        + (2.0 * G * beta)[:, None, None] * (DEVIATORIC - np.einsum("ni,nj->nij", n, n))
    # the plastic strain: -x/3 m (volume) and sqrt(3/2) d eps_q^p along n
    d_eps_p = -(x / 3.0)[:, None] * IDENTITY + \
        (math.sqrt(1.5) * 2.0 * q * g / M2)[:, None] * n
    return sigma, C, pc, d_eps_p, done


@dataclass(frozen=True)
class CamClayPoints:
    """Modified Cam Clay at N points (:class:`tankfx.laws.point_law.PointLaw`): per point
    ``M``, ``lambda_star``, ``kappa_star``, ``nu``, the ground at rest ``sigma0`` (N, 4,
    effective) and its preconsolidation pressure ``p_c0`` (N,); ``p_min`` the least mean
    stress of the bulk modulus (Pa). Points with a finite ``E_fixed`` are linear elastic with
    it and ``nu`` and never yield (a ringwall's, a void's). Its own state: ``p_c``."""

    M: np.ndarray
    lambda_star: np.ndarray
    kappa_star: np.ndarray
    nu: np.ndarray
    sigma0: np.ndarray
    p_c0: np.ndarray
    p_min: float
    E_fixed: np.ndarray

    state: ClassVar[dict[str, int]] = {"p_c": 1}
    #: associated flow, but its tangent is not symmetric: the bulk modulus is the step's
    #: end's and G its start's (no elastic energy of which both derive); LU, not LDL^T
    symmetric: ClassVar[bool] = False

    def initial_stress(self) -> np.ndarray:
        return self.sigma0

    def initial_state(self) -> dict[str, np.ndarray]:
        return {"p_c": self.p_c0[:, None]}

    def elastic_matrix(self, stress: np.ndarray | None = None) -> np.ndarray:
        """The elastic tangent at the committed ``stress`` (its change from the ground at
        rest; None: at rest): K = max(p', p_min) / kappa*, G of nu."""
        total = self.sigma0 if stress is None else self.sigma0 + stress
        p = invariants(total)[0]
        K = np.maximum(p, self.p_min) / self.kappa_star
        G = shear_modulus(K, self.nu)
        fixed = np.isfinite(self.E_fixed)
        K = np.where(fixed, self.E_fixed / (3.0 * (1.0 - 2.0 * self.nu)), K)
        G = np.where(fixed, self.E_fixed / (2.0 * (1.0 + self.nu)), G)
        return K[:, None, None] * np.outer(IDENTITY, IDENTITY) + \
            2.0 * G[:, None, None] * DEVIATORIC

    def update(self, d_eps, stress, state) -> PointUpdate:
        sigma, C, yielding, d_eps_p, p_c, ok = cam_clay_update(
            d_eps, self.sigma0 + stress, state["p_c"][:, 0], self.M, self.lambda_star,
            self.kappa_star, self.nu, self.p_min)
        fixed = np.isfinite(self.E_fixed)
        if fixed.any():
            D = self.elastic_matrix()[fixed]
            sigma[fixed] = self.sigma0[fixed] + stress[fixed] + \
                (D @ d_eps[fixed][..., None])[..., 0]
            C[fixed], yielding[fixed], d_eps_p[fixed] = D, False, 0.0
            p_c[fixed] = state["p_c"][fixed, 0]
            # (an elastic point has no return to fail: a void's points, whose strains are
            # no soil's, were set NaN here and committed so, and a strength search's
            # next update read them; measured on a tank's inside, 170 % strain)
            ok[fixed] = True
        # (a point whose return did not converge: no state to report, and the solve that
        # asked for it fails as not finite, to be cut back)
        sigma[~ok] = np.nan
        return PointUpdate(stress=sigma - self.sigma0, tangent=C, yielding=yielding,
                           plastic_strain=d_eps_p, state={"p_c": p_c[:, None]})

    def reduced(self, factor: float) -> "CamClayPoints":
        """tan phi_cs / factor: M of the reduced critical-state angle."""
        phi = np.radians(critical_state_angle(self.M))
        return replace(self, M=critical_state_ratio(np.degrees(np.arctan(np.tan(phi)
                                                                         / factor))))

    def elastic_where(self, mask, E=None, nu=None) -> "CamClayPoints":
        # (without E: the modulus at rest, K = max(p'_0, p_min) / kappa*)
        K = np.maximum(invariants(self.sigma0)[0], self.p_min) / self.kappa_star
        E_here = np.where(np.isfinite(self.E_fixed), self.E_fixed,
                          3.0 * K * (1.0 - 2.0 * self.nu)) if E is None else E
        return replace(self, E_fixed=np.where(mask, E_here, self.E_fixed),
                       nu=self.nu if nu is None else np.where(mask, nu, self.nu))

    def undrained_strength(self, stress, state) -> np.ndarray:
        """s_u (Pa) of each point's effective ``stress`` (its total: at rest plus its
        change) and preconsolidation pressure: the deviator half at the critical state
        reached undrained from an isotropic state of the same p' and p_c,
        s_u = (M / 2) p' (p_c / (2 p'))^L, L = (lambda* - kappa*) / lambda* (Wood 1990,
        Eq. 10.35): what a field vane measures, up to the anisotropy Cam Clay leaves out.
        NaN at the points that never yield (a ringwall's, a void's)."""
        p = np.maximum(invariants(stress)[0], self.p_min)
        L = (self.lambda_star - self.kappa_star) / self.lambda_star
        s_u = 0.5 * self.M * p * (state["p_c"][:, 0] / (2.0 * p)) ** L
        return np.where(np.isfinite(self.E_fixed), np.nan, s_u)

    def mobilised(self, stress, per: int = 1) -> np.ndarray:
        """q / (M p'): the stress ratio's share of the critical state's (1 there; the
        ellipse's dry side passes it)."""
        p, q, _ = invariants(stress)
        M = self.M if per == 1 else self.M.reshape(-1, per).mean(axis=1)
        return q / (M * np.maximum(p, self.p_min))


__all__ = ["CamClayPoints", "cam_clay_update", "critical_state_ratio",
           "normally_consolidated_ratio", "elastic_pressure"]
