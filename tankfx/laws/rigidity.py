"""The relative rigidities of the paper, Eqs. 21-22: K = (1 - nu_s^2) (E / E_s) (t / a)^3 for the
plate (Kp: t_p, a_p) and the wall (Kt: t_t, a_t), and their inverse; the non-dimensional
results of Eq. 23 (:mod:`tankfx.results.contract` applies them).
"""
from __future__ import annotations


def Kp_from_thickness(t: float, a: float, E: float, E_s: float, nu_s: float) -> float:
    """Eqs. 21-22: K = (1 - nu_s^2) (E / E_s) (t / a)^3."""
    return (1.0 - nu_s**2) * (E / E_s) * (t / a) ** 3


def plate_thickness_from_Kp(K: float, a: float, E: float, E_s: float, nu_s: float) -> float:
    """Inverse of Eqs. 21-22: the thickness that gives relative rigidity K."""
    return a * (K * E_s / ((1.0 - nu_s**2) * E)) ** (1.0 / 3.0)
