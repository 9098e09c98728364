"""Duncan & Chang's soil (1970): Kondner's law (Eqs. 17-19) whose constants follow each cell's
confining stress sigma_3: the initial modulus 1/a = K p_a (sigma_3 / p_a)^n and the ultimate
deviator 1/b = q_f / R_f, q_f = (2 c cos phi + 2 sigma_3 sin phi) / (1 - sin phi) (Mohr-Coulomb);
past q_f a cell is perfectly plastic. Pure numpy functions of per-cell arrays.
"""
from __future__ import annotations

import math

import numpy as np

from .kondner import (
    MIN_CONFINEMENT,
    Kondner,
    geostatic_stress,
    kondner_parameters,
    principal_strains,
    secant_modulus,
)
from .geostatic import lighter_than_water
from .mohr_coulomb import deviator_strength
# (p_a, the reference pressure of Duncan & Chang's modulus, is the atmosphere's by default)
from .soil_law import ATMOSPHERIC_PRESSURE, WATER_UNIT_WEIGHT

#: the constants a stratum must give, and why
REQUIRED = {"modulus_number": "K: the initial modulus is K p_a (sigma_3 / p_a)^n",
            "modulus_exponent": "n, e.g. 0.5",
            "unit_weight": "N/m^3: the geostatic stress sets the confinement"}


def duncan_chang_parameters(soil, sigma_3, st):
    """Kondner's (a, b) of Duncan & Chang's soil at confining stress ``sigma_3`` (Pa,
    compression positive, held at MIN_CONFINEMENT p_a at least) of cells whose strata's
    constants are ``st`` (``soil.at_depth`` of their depths): 1/a = K p_a (sigma_3 /
    p_a)^n, 1/b = (2 c cos phi + 2 sigma_3 sin phi) / ((1 - sin phi) R_f)."""
    p_a = soil.atmospheric_pressure
    s3 = np.maximum(sigma_3, MIN_CONFINEMENT * p_a)
    E_i = st["modulus_number"] * p_a * (s3 / p_a) ** st["modulus_exponent"]
    q_f = deviator_strength(s3, st["cohesion"], np.radians(st["friction_angle"]))
    return 1.0 / E_i, st["failure_ratio"] / q_f


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


#: Duncan & Chang's constants that each stratum has (p_a is the soil's, one for all)
STRATUM_CONSTANTS = ("modulus_number", "modulus_exponent", "failure_ratio", "cohesion",
                     "friction_angle", "unit_weight", "K0")


class DuncanChang(Kondner):
    """Duncan & Chang's soil (``model = "duncan_chang"``): Kondner's law whose constants
    follow each cell's confinement (the functions of this module); every stratum mixed,
    since a failed cell keeps its bulk modulus while its shear modulus falls (nu -> 0.5)."""

    word = "duncan_chang"
    title = "Duncan & Chang's soil"
    why_it_cannot_fail = ("it is nonlinear elastic: where its secant iteration stops is the "
                          "model's limit, with no flow rule and no collapse mechanism, not the "
                          "ground's bearing capacity")
    max_iterations = 80        # (its failed zones settle slowly: 10-64 iterations measured)
    keys = (*STRATUM_CONSTANTS, "atmospheric_pressure", "water_table", "water_unit_weight")
    layer_keys = STRATUM_CONSTANTS
    E_keys = ("modulus_number", "atmospheric_pressure")
    all_mixed = "a failed cell's nu tends to 0.5"
    state_fields = ("E", "nu")   # (a failed cell's nu rises to 0.5)
    needs_stress = True          # (the confinement is the geostatic stress plus the tank's)
    #: deeper Anderson acceleration, for its failed zones settle slowly. Measured on the 1 m
    #: tank on sand (coarse mesh: 100-400 kPa with c = 5 kPa, 50 and 100 kPa without; the
    #: default mesh at 100 kPa; the demo's tank): depth 3 converged 7 of 8 in 80 iterations
    #: (18-53; the demo in 18), depth 6 6 of 8, depth 10 all 8 (10-64; the demo in 10)
    anderson_depth = 10
    fixed_constants = False      # (they follow the confinement)

    @classmethod
    def stratum_text(cls, st):
        return (f", Duncan-Chang K = {st['modulus_number']:g}, n = {st['modulus_exponent']:g},"
                f" R_f = {st['failure_ratio']:g}, c = {st['cohesion']:g} Pa, phi = "
                f"{st['friction_angle']:g} deg, gamma = {st['unit_weight']:g} N/m^3, K0 = "
                f"{st['K0']:.3g} (E = K p_a)")

    @classmethod
    def ground_text(cls, soil):
        return f", p_a = {soil.atmospheric_pressure:g} Pa"

    @classmethod
    def ground_lines(cls, soil):
        if soil.water_table is None:
            return []
        return [f"water table {soil.water_table:g} m down: the confinement below it is "
                f"effective (gamma_w = {soil.water_unit_weight:g} N/m^3)"]

    @classmethod
    def check(cls, table, given, name, p_a=None):
        """K, n and the unit weight required; a strength (c or phi); E is K p_a, not given;
        no E_gradient."""
        out = [f"{name}.{key}: missing for model = \"duncan_chang\"; add it ({why})"
               for key, why in REQUIRED.items() if key not in table]
        if table.get("unit_weight") == 0.0:
            out.append(f"{name}.unit_weight = 0.0: Duncan & Chang's soil takes its confinement "
                       f"from its weight; give its unit weight (N/m^3, > 0)")
        phi = table.get("friction_angle")
        if not table.get("cohesion", 0.0) > 0.0 and not (phi or 0.0) > 0.0:
            out.append(f"{name}.cohesion, {name}.friction_angle: Duncan & Chang's soil needs a "
                       f"strength; give cohesion > 0 (Pa) or friction_angle > 0 (degrees)")
        K = table.get("modulus_number")
        p_a = p_a or table.get("atmospheric_pressure", ATMOSPHERIC_PRESSURE)
        if "E" in table and K and K > 0 and p_a > 0 and abs(table["E"] / (K * p_a) - 1.0) > 1e-6:
            out.append(f"{name}.E = {table['E']!r}: not used with model = \"duncan_chang\" (its "
                       f"reference modulus is K p_a = {K * p_a:.6g} Pa); remove it")
        if table.get("E_gradient", 0.0) != 0.0:
            out.append(f"{name}.E_gradient: not used with model = \"duncan_chang\" (the modulus "
                       f"grows with the confining stress instead); remove it")
        return out

    @classmethod
    def check_ground(cls, soil, layers):
        """Below the water table a stratum must be heavier than water: its effective
        weight gamma - gamma_w carries the confinement."""
        return lighter_than_water(soil, layers,
                                  soil.get("water_unit_weight", WATER_UNIT_WEIGHT))

    @classmethod
    def resolve_ground(cls, soil):
        return {"atmospheric_pressure": soil.get("atmospheric_pressure", ATMOSPHERIC_PRESSURE),
                "water_table": soil.get("water_table"),
                "water_unit_weight": soil.get("water_unit_weight", WATER_UNIT_WEIGHT)
                if "water_table" in soil else None}

    @classmethod
    def resolve_stratum(cls, table, ground):
        """K p_a and the constants, their defaults resolved (R_f 0.9, c 0, phi 0, K0 Jaky's
        1 - sin phi)."""
        phi = table.get("friction_angle", 0.0)
        values = {"modulus_number": table["modulus_number"],
                  "modulus_exponent": table["modulus_exponent"],
                  "failure_ratio": table.get("failure_ratio", 0.9),
                  "cohesion": table.get("cohesion", 0.0), "friction_angle": phi,
                  "unit_weight": table["unit_weight"],
                  "K0": table.get("K0", 1.0 - math.sin(math.radians(phi)))}
        return {"E": values["modulus_number"] * ground["atmospheric_pressure"], **values}

    @classmethod
    def initial_modulus(cls, soil, depth, st):
        """Each cell's initial tangent modulus at its geostatic confinement, 1 / a of
        :func:`duncan_chang_parameters` (``depth``: the cells', ``st``: their strata's
        constants, ``soil.at_depth(depth)``)."""
        sigma_v, sigma_h = geostatic_stress(soil, depth)
        return 1.0 / duncan_chang_parameters(soil, np.minimum(sigma_v, sigma_h), st)[0]

    @classmethod
    def secant_start(cls, soil, depth, cell_strata) -> dict:
        """Each cell's strata's constants (``strata``), the geostatic stress (tension
        positive, (rr, zz, rz, theta)) to which the tank's is added for the confinement,
        and Kondner's a, b at the geostatic confinement."""
        sigma_v, sigma_h = geostatic_stress(soil, depth)
        a, b = duncan_chang_parameters(soil, np.minimum(sigma_v, sigma_h), cell_strata)
        return {"a": a, "b": b, "nu": cell_strata["nu"], "nu_intact": cell_strata["nu"],
                "strata": cell_strata,
                "geostatic": np.stack([-sigma_h, -sigma_v, 0.0 * sigma_v, -sigma_h], axis=1)}

    @classmethod
    def secant_step(cls, soil, start, nu, E, eps_min, eps_max, stress, is_soil) -> dict:
        """Duncan & Chang's secant moduli consistent with the confinement they give
        (:func:`duncan_chang_secant`): a, b and failure follow each cell's confinement; the
        misfit is the modulus's distance from them."""
        # (cells outside the soil, e.g. the pit's void, given G = 1 to keep quiet)
        step = duncan_chang_secant(soil, start["strata"], start["geostatic"], stress,
                                   np.where(is_soil, E / (2.0 * (1.0 + nu)), 1.0), eps_min,
                                   eps_max)
        return step | {"misfit": np.abs(E - step["E"]) / E, "ultimate": step["failed"]}

    @classmethod
    def next_moduli(cls, step, E_new, E, nu, nu_intact, E_initial, floor, accelerate
                    ) -> tuple:
        """The step's shear modulus, accelerated on ln G with each failed cell's bulk
        modulus held, so that a failed cell's (E, nu) stay a pair of the law (an unloading
        cell's E_ur, ``E_new``, is set after)."""
        G = E / (2.0 * (1.0 + nu))
        G_new = accelerate(G, np.maximum(step["G"], floor / 3.0), floor / 3.0,
                           E_initial / 2.0)
        return _moduli(G_new, step["K"], nu_intact)

    @classmethod
    def unloading_modulus(cls, soil, start, E_initial, E, stress, peak_stress, ratio,
                          is_soil):
        """K_ur p_a (sigma_3 / p_a)^n, K_ur = ratio x K, at the confinement it gives
        (:func:`duncan_chang_unloading`)."""
        return duncan_chang_unloading(soil, start["strata"], start["geostatic"], stress,
                                      peak_stress, np.where(is_soil, E, 1.0), ratio)

    @classmethod
    def start_text(cls, soil, tol: float) -> str:
        return (f"Duncan-Chang soil: K = {soil.modulus_number:.4g}, n = "
                f"{soil.modulus_exponent:.3g}, R_f = {soil.failure_ratio:.3g}, c = "
                f"{soil.cohesion:.4g} Pa, phi = {soil.friction_angle:.3g} deg, gamma = "
                f"{soil.unit_weight:.4g} N/m^3, K0 = {soil.K0:.3g}; tolerance {tol:.3g} "
                f"(Eq. 18)")

    @classmethod
    def strength_text(cls, soil) -> str:
        return (f"Duncan & Chang's strength c = {soil.cohesion / 1e3:.4g} kPa, phi = "
                f"{soil.friction_angle:g} deg")

    @classmethod
    def exhausted_text(cls, n_ult, where, max_it, worst, du_rel) -> str | None:
        return (f"no converged state with {n_ult} failed elements (Mohr-Coulomb) {where} "
                f"after {max_it} iterations (largest modulus misfit {worst:.2g}, last "
                f"displacement update {du_rel:.1e}): either the soil cannot carry this load "
                f"(the settlement keeps growing), or the failed zone's moduli settle too "
                f"slowly (a displacement update far below 1e-2: a soil without cohesion has "
                f"almost no strength near the surface beside the foundation; raise [soil] "
                f"max_iterations, or give the soil a little cohesion)")
