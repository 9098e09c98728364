"""Mohr-Coulomb's strength, the one envelope of the interface (Eq. 13), Duncan & Chang's
soil and the elastoplastic soil: on a plane whose normal stress is sigma_n (compression
positive), failure where the shear stress reaches

    tau_f = c + sigma_n tan phi.

In principal stresses (compression positive, sigma_1 >= sigma_3), Mohr's circle touches
that line where (sigma_1 - sigma_3) / 2 = c cos phi + (sigma_1 + sigma_3) / 2 sin phi, so the
deviator at failure under a confinement sigma_3 is

    q_f = sigma_1 - sigma_3 = (2 c cos phi + 2 sigma_3 sin phi) / (1 - sin phi).

Pure numpy functions of arrays (or floats).
"""
from __future__ import annotations

import numpy as np


def circle_strength(p, cohesion, sin_phi):
    """The radius Mohr's circle of centre ``p`` (tension positive) reaches at failure,
    c cos phi - p sin phi: the criterion (sigma_max - sigma_min) / 2 <= c cos phi -
    (sigma_max + sigma_min) / 2 sin phi, which the elastoplastic return tests, the stress
    level divides by and the ground at rest is checked against. The return's planes
    (:mod:`tankfx.laws.plasticity`) and the bounds' cones (:mod:`tankfx.laws.limit_cones`)
    are its forms, each tested against it."""
    return cohesion * np.sqrt(1.0 - np.asarray(sin_phi) ** 2) - p * sin_phi


def shear_strength(sigma_n, cohesion, tan_phi):
    """tau_f = c + sigma_n tan phi on a plane of normal stress ``sigma_n`` (compression
    positive; a plane in tension, sigma_n < 0, keeps only its cohesion)."""
    return cohesion + np.maximum(sigma_n, 0.0) * tan_phi


def deviator_strength(sigma_3, cohesion, phi):
    """q_f = (2 c cos phi + 2 sigma_3 sin phi) / (1 - sin phi): the deviator sigma_1 -
    sigma_3 at failure under the confinement ``sigma_3`` (compression positive), ``phi`` in
    radians."""
    return (2.0 * cohesion * np.cos(phi) + 2.0 * sigma_3 * np.sin(phi)) / (1.0 - np.sin(phi))
