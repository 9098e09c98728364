"""Mohr-Coulomb's yield condition in axial symmetry as three second-order cones, the form a
limit analysis by conic optimisation takes (:mod:`tankfx.bounds`).

Stresses tension positive, the vector ``(sigma_r, sigma_z, tau_rz, sigma_theta)``.
sigma_theta is a principal stress; the in-plane ones are p +- R, with
p = (sigma_r + sigma_z) / 2 and R = sqrt(((sigma_r - sigma_z) / 2)^2 + tau_rz^2). With
s = sin phi, Mohr-Coulomb asks of every pair of principal stresses (a, b)
|a - b| + (a + b) s <= 2 c cos phi. Written out for the three pairs, each absolute value
splits into two linear conditions. Two of the six are implied by the other four:
sigma_theta - p - R + (p + R + sigma_theta) s <= 2 c cos phi follows from the
(p - R, sigma_theta) condition with +R (1 - s), because R (1 - s) >= 0. The remaining ones
are three cones:

    (1)            R <=   c cos phi - p s
    (2)  R (1 - s) <= 2 c cos phi - sigma_theta (1 + s) + p (1 - s)
    (3)  R (1 + s) <= 2 c cos phi + sigma_theta (1 - s) - p (1 + s)

Tresca is s = 0. Each cone k is ``alpha_k R <= beta_k c + g_k . sigma``.

The dissipation of a strain rate E = (eps_r, eps_z, gamma_rz, eps_theta), the support
function D(E) = sup {sigma . E : sigma admissible}, is by conic duality

    D(E) = min { c sum_k beta_k y_k0 : sum_k M_k^T y_k = -E, y_k in the cone },

with M_k the rows (g_k; alpha_k (1/2, -1/2, 0, 0); alpha_k (0, 0, 1, 0)). Any feasible y
gives an upper estimate of D: an upper bound stays one with an inexact solve.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class YieldCones:
    """The three cones of a friction angle: ``alpha`` (3,), ``beta`` (3,), ``g`` (3, 4)
    over (sigma_r, sigma_z, tau_rz, sigma_theta)."""

    alpha: np.ndarray
    beta: np.ndarray
    g: np.ndarray

    def rows(self, k: int) -> np.ndarray:
        """M_k (3 x 4): the cone's affine part and its radius's two components, so that
        sigma is admissible where M_k sigma + (beta_k c, 0, 0) lies in the cone."""
        a = self.alpha[k]
        return np.array([self.g[k], [0.5 * a, -0.5 * a, 0.0, 0.0], [0.0, 0.0, a, 0.0]])


def mohr_coulomb_cones(friction_angle: float) -> YieldCones:
    """Cones (1)-(3) of the module's docstring for ``friction_angle`` (radians)."""
    s, cos_phi = math.sin(friction_angle), math.cos(friction_angle)
    alpha = np.array([1.0, 1.0 - s, 1.0 + s])
    beta = np.array([cos_phi, 2.0 * cos_phi, 2.0 * cos_phi])
    g = np.array([[-0.5 * s, -0.5 * s, 0.0, 0.0],
                  [0.5 * (1.0 - s), 0.5 * (1.0 - s), 0.0, -(1.0 + s)],
                  [-0.5 * (1.0 + s), -0.5 * (1.0 + s), 0.0, 1.0 - s]])
    return YieldCones(alpha, beta, g)


def admissible(sigma: np.ndarray, cohesion, friction_angle: float) -> np.ndarray:
    """The largest violation of the three cones at each stress (n, 4): <= 0 where
    admissible, in Pa."""
    cones = mohr_coulomb_cones(friction_angle)
    sigma = np.atleast_2d(sigma)
    R = np.hypot(0.5 * (sigma[:, 0] - sigma[:, 1]), sigma[:, 2])
    return np.max([cones.alpha[k] * R - cones.beta[k] * cohesion - sigma @ cones.g[k]
                   for k in range(3)], axis=0)


def tresca_dissipation(E: np.ndarray, cohesion) -> np.ndarray:
    """Tresca's dissipation of isochoric strain rates (n, 4): c (|e1| + |e2| + |e3|) with the
    principal rates e_theta and (e_r + e_z) / 2 +- rho, rho = sqrt(((e_r - e_z) / 2)^2 +
    (gamma / 2)^2). A closed form to check the conic one against."""
    E = np.atleast_2d(E)
    mid = 0.5 * (E[:, 0] + E[:, 1])
    rho = np.hypot(0.5 * (E[:, 0] - E[:, 1]), 0.5 * E[:, 2])
    return cohesion * (np.abs(mid + rho) + np.abs(mid - rho) + np.abs(E[:, 3]))
