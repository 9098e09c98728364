"""Duncan & Chang's soil (1970): Kondner's law (Eqs. 17-19) whose constants follow each cell's
confining stress sigma_3: the initial modulus 1/a = K p_a (sigma_3 / p_a)^n and the ultimate
deviator 1/b = q_f / R_f, q_f = (2 c cos phi + 2 sigma_3 sin phi) / (1 - sin phi) (Mohr-Coulomb);
past q_f a cell is perfectly plastic. Pure numpy functions of per-cell arrays.
"""
from __future__ import annotations

import numpy as np

from .kondner import (
    MIN_CONFINEMENT,
    geostatic_stress,
    kondner_parameters,
    principal_strains,
    secant_modulus,
)


def duncan_chang_parameters(soil, sigma_3, st):
    """Kondner's (a, b) of Duncan & Chang's soil at confining stress ``sigma_3`` (Pa,
    compression positive, held at MIN_CONFINEMENT p_a at least) of cells whose strata's
    constants are ``st`` (``soil.at_depth`` of their depths): 1/a = K p_a (sigma_3 /
    p_a)^n, 1/b = (2 c cos phi + 2 sigma_3 sin phi) / ((1 - sin phi) R_f)."""
    p_a = soil.atmospheric_pressure
    s3 = np.maximum(sigma_3, MIN_CONFINEMENT * p_a)
    E_i = st["modulus_number"] * p_a * (s3 / p_a) ** st["modulus_exponent"]
    phi = np.radians(st["friction_angle"])
    q_f = (2.0 * st["cohesion"] * np.cos(phi) + 2.0 * s3 * np.sin(phi)) / (1.0 - np.sin(phi))
    return 1.0 / E_i, st["failure_ratio"] / q_f


def initial_modulus(soil, depth, st=None):
    """The nonlinear soil's initial tangent modulus of cells at ``depth``: Kondner's 1/a of
    their stratum, or Duncan & Chang's at the geostatic confinement (``st``: their strata's
    constants, ``soil.at_depth(depth)``, if at hand)."""
    if soil.model == "duncan_chang":
        sigma_v, sigma_h = geostatic_stress(soil, depth)
        return 1.0 / duncan_chang_parameters(soil, np.minimum(sigma_v, sigma_h),
                                             soil.at_depth(depth) if st is None else st)[0]
    return 1.0 / kondner_parameters(soil, depth)[0]


def failed_moduli(K, G):
    """(E, nu) of an isotropic cell of bulk modulus K and shear modulus G."""
    return 9.0 * K * G / (3.0 * K + G), (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G))


#: Halvings of the bracket of ln G in the consistent Duncan-Chang update (from a width of
#: 120: ln G to 1e-10).
CONSISTENT_HALVINGS = 40


_MEAN = np.array([1.0, 1.0, 0.0, 1.0])      # the identity in (rr, zz, rz, theta)


def duncan_chang_secant(soil, st, geostatic, stress, G, eps_min, eps_max) -> dict:
    """Duncan & Chang's secant moduli of cells, consistent with the confinement they give.

    ``stress``: the cells' current stress ((rr, zz, rz, theta), tension positive) at shear
    modulus ``G``; ``geostatic``: the ground's at rest; ``st``: the cells' strata's
    constants (``soil.at_depth``). The law is G = min(G_K, G_f): Kondner's secant
    E / (2 (1 + nu)), E = 1 / (a + b eps_p), or where that would pass the Mohr-Coulomb
    strength q_f = R_f / b the perfectly plastic q_f / (2 (eps_1 - eps_3)) (the two are
    equal at q = q_f, so the cell has failed where G_K > G_f); a failed cell keeps the bulk
    modulus of Kondner's secant at q_f, (1 - R_f) / a / (3 (1 - 2 nu)). a, b and q_f follow
    sigma_3, the minor principal compression of the geostatic plus the current stress.

    That stress's deviator is proportional to G, and a larger deviator lowers sigma_3 and
    with it the strength (d ln q_f / d ln q ~ -0.9 at phi = 35 deg): a Picard step that
    reads sigma_3 off the current stress feeds each change of modulus back with the
    opposite sign, and the failed cells' moduli swing from one iteration to the next. So
    each cell's G here solves G = min(G_K, G_f)(sigma_3(G)), its deviator scaled by
    G / G_current, its mean stress and strains held (bisection on ln G). The root is
    unique where the mean and geostatic stress alone confine the cell: sigma_3 is concave
    in the deviator's scale s, so s dsigma_3/ds < sigma_3 and the law's log-slope is below
    1. At a fixed point G = G_current and this is the law at the current stress.

    Returns ``E``, ``nu``, ``G``, ``K`` (failed cells' bulk modulus, else nan), ``failed``
    and Kondner's ``a``, ``b`` at the solved confinement."""
    nu = st["nu"]
    R_f = st["failure_ratio"]
    mean = (stress[:, 0] + stress[:, 1] + stress[:, 3]) / 3.0
    fixed = geostatic + mean[:, None] * _MEAN
    dev = stress - mean[:, None] * _MEAN
    spread = eps_max - eps_min
    eps_p = spread / (1.0 + nu)

    def law(ln_G):
        total = fixed + (np.exp(ln_G) / G)[:, None] * dev
        _, most_tensile = principal_strains(total[:, 0], total[:, 1], total[:, 2], total[:, 3])
        a, b = duncan_chang_parameters(soil, -most_tensile, st)
        G_K = secant_modulus(eps_p, a, b) / (2.0 * (1.0 + nu))
        with np.errstate(divide="ignore"):           # unstrained cells: no plastic branch
            G_f = R_f / b / (2.0 * spread)
        return np.minimum(G_K, G_f), G_K > G_f, a, b

    lo, hi = np.log(G) - 60.0, np.log(G) + 60.0
    for _ in range(CONSISTENT_HALVINGS):
        mid = 0.5 * (lo + hi)
        above = law(mid)[0] > np.exp(mid)            # the root lies above mid
        lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
    G_new, failed, a, b = law(0.5 * (lo + hi))
    K = np.where(failed, (1.0 - R_f) / a / (3.0 * (1.0 - 2.0 * np.minimum(nu, 0.4999))),
                 np.nan)
    E, nu_new = _moduli(G_new, K, nu)
    return {"E": E, "nu": nu_new, "G": G_new, "K": K, "failed": failed, "a": a, "b": b}


def duncan_chang_unloading(soil, st, geostatic, stress, peak_stress, E, ratio) -> np.ndarray:
    """Duncan & Chang's unloading-reloading modulus of cells on their unloading line,
    consistent with the confinement it gives: E_ur = ratio K p_a (sigma_3 / p_a)^n, sigma_3
    the minor principal compression of the geostatic stress plus the cell's.

    ``stress``: the cells' current stress at modulus ``E`` ((rr, zz, rz, theta), tension
    positive), ``peak_stress`` theirs at their most loaded state: on the line the stress
    moves from the peak's in proportion to E_ur, so at a trial modulus E' it is
    peak + (E' / E) (stress - peak). As for the loading branch (duncan_chang_secant), a
    Picard step reading sigma_3 off the current stress swings: unloading lowers the
    confinement, a stiffer line unloads it more. The root of E' = E_ur(sigma_3(E')) is
    unique (the right-hand side falls as E' grows): bisection on ln E'."""
    change = stress - peak_stress

    def law(ln_E):
        total = geostatic + peak_stress + (np.exp(ln_E) / E)[:, None] * change
        _, most_tensile = principal_strains(total[:, 0], total[:, 1], total[:, 2], total[:, 3])
        return ratio / duncan_chang_parameters(soil, -most_tensile, st)[0]

    lo, hi = np.log(E) - 60.0, np.log(E) + 60.0
    for _ in range(CONSISTENT_HALVINGS):
        mid = 0.5 * (lo + hi)
        above = law(mid) > np.exp(mid)
        lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
    return law(0.5 * (lo + hi))


def _moduli(G, K, nu):
    """(E, nu) of cells of shear modulus G: intact ones (K nan) keep their nu, failed ones
    have bulk modulus K."""
    failed = np.isfinite(K)
    E_f, nu_f = failed_moduli(np.where(failed, K, 1.0), G)
    return np.where(failed, E_f, 2.0 * (1.0 + nu) * G), np.where(failed, nu_f, nu)
