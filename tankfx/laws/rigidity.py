"""The relative rigidities of the paper, Eqs. 21-22: K = (1 - nu_s^2) (E / E_s) (t / a)^3 for the
plate (Kp: t_p, a_p) and the wall (Kt: t_t, a_t), and their inverse; the non-dimensional
results of Eq. 23 (:mod:`tankfx.results.contract` applies them).
"""
from __future__ import annotations


def Kp_from_thickness(t: float, a: float, E: float, E_s: float, nu_s: float) -> float:
    """Eqs. 21-22: K = (1 - nu_s^2) (E / E_s) (t / a)^3."""
    return (1.0 - nu_s**2) * (E / E_s) * (t / a) ** 3


def nondimensional(w0: float, wd: float, M0: float | None, p: float, a: float,
                   E_s: float) -> dict[str, float | None]:
    """The paper's non-dimensional results, Eq. 23: w0 = p a w0_bar / E_s, wd = p a wd_bar /
    E_s, M0 = p a^2 M0_bar (p the pressure on the plate, a its radius, E_s the soil's modulus
    at the surface). Without a pressure (self-weight alone) there is no p to scale by: the
    measures are None rather than NaN (results.json must stay valid JSON); so is M0_bar
    without a plate."""
    w_scale, m_scale = p * a / E_s, p * a**2
    return {"w0": w0 / w_scale if p > 0 else None, "wd": wd / w_scale if p > 0 else None,
            "M0": None if M0 is None or p <= 0 else M0 / m_scale}


def plate_thickness_from_Kp(K: float, a: float, E: float, E_s: float, nu_s: float) -> float:
    """Inverse of Eqs. 21-22: the thickness that gives relative rigidity K."""
    return a * (K * E_s / ((1.0 - nu_s**2) * E)) ** (1.0 / 3.0)
