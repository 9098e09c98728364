"""Kondner's hyperbolic soil (Eqs. 17-20) by a secant modulus held per soil cell (DG0),
updated by Picard iteration.

Kondner's law relates the deviator stress to the major principal strain,
``q = sigma_1 - sigma_3 = eps_p / (a + b eps_p)``: 1/a is the initial tangent modulus, 1/b the
ultimate deviator stress. Depth scales the initial modulus as in the linear soil,
a(h) = a / (1 + lambda h), and leaves 1/b alone.

Each iteration solves the whole problem (structure and interface included) with the current
moduli, then takes each cell's principal strains at its centroid. The computed deviator is
q_c = E / (1 + nu) (eps_max - eps_min) = E eps_p with eps_p = (eps_max - eps_min) / (1 + nu),
the major principal strain of the unconfined triaxial test to which Kondner's law is fitted
(there eps_max - eps_min = (1 + nu) eps_axial); the model's deviator is
q_m = eps_p / (a + b eps_p). Where the misfit |q_c - q_m| / q_c exceeds the tolerance
(Eq. 18, the paper's 0.05 by default) the modulus becomes the secant (Eq. 19)

    E = q_m / eps_p = 1 / (a + b eps_p)

which is positive and never above the initial modulus; near the ultimate deviator it tends to
zero and is held at a floor, which marks the cell as failing. The iteration stops when no cell
needs a change (Eq. 20) and the relative displacement update is below the tolerance
times ``DISPLACEMENT_TOLERANCE_RATIO`` (1e-3 for the paper's 0.05: the error the default mesh
leaves is larger; a tighter tolerance tightens both);
unlike the paper, every cell takes its new secant modulus at every iteration, so the result
does not keep a misfit of up to the tolerance (measured: 2.5 % of w0 at 0.05). Using the
principal strain spread rather than the largest principal strain keeps the rule well defined
for nearly isotropic strain states, where the deviator vanishes but a principal strain does
not.

Like the paper, the secant approach ignores the in-situ (geostatic) stress: the soil is
unstressed before the tank is built, and the moduli depend on the strains the tank causes.

Duncan & Chang's soil (model = "duncan_chang", 1970) is Kondner's law whose constants follow
each cell's confining stress sigma_3 (the minor principal compression of the geostatic
stress, gamma h vertically and K0 gamma h horizontally, plus the tank's): the initial
modulus 1/a = K p_a (sigma_3 / p_a)^n and the ultimate deviator 1/b = q_f / R_f, q_f = (2 c
cos phi + 2 sigma_3 sin phi) / (1 - sin phi) (Mohr-Coulomb); past q_f a cell is perfectly
plastic. The same Picard iteration gives each cell the secant moduli of this law with the
confinement those moduli produce (``duncan_chang_secant``), since read off the current
stress the confinement would move against the modulus and the iteration swing.
"""
from __future__ import annotations

import numpy as np

from .tensors import principal_strains  # noqa: F401  (Kondner reads its strains)
from .geostatic import geostatic_stress  # noqa: F401  (Duncan & Chang's start)
from .soil_law import SoilLaw

#: Duncan & Chang's confining stress is held at this fraction of p_a at least: at the
#: ground surface, and where the tank's stress puts a cell in tension, sigma_3 would give no
#: modulus and no strength.
MIN_CONFINEMENT = 0.01


#: A cell whose model deviator reaches this fraction of 1/b counts as at the ultimate.
ULTIMATE_FRACTION = 0.99


#: The secant modulus never falls below this fraction of the initial one (it must not reach
#: zero); a cell held there is at the ultimate and is reported.
MODULUS_FLOOR = 1e-4


def kondner_deviator(eps_p, a, b):
    """(sigma_1 - sigma_3) = eps / (a + b eps) (Eq. 17)."""
    return eps_p / (a + b * eps_p)


def major_strain(eps_min, eps_max, nu):
    """eps_p = (eps_max - eps_min) / (1 + nu), the strain Kondner's law reads (see
    secant_update)."""
    return (eps_max - eps_min) / (1.0 + nu)


def kondner_parameters(soil, depth):
    """Kondner's (a, b) and Poisson's ratio of cells whose centroids lie at ``depth`` (m;
    none above the ground), from their strata (:class:`tankfx.scene.Soil`): the initial
    modulus 1/a grows with depth as the linear soil's, E_top (1 + lambda (h - top))."""
    st = soil.at_depth(depth)
    return 1.0 / st["E"], st["hyperbolic_b"], st["nu"]


def stress_level(eps_min, eps_max, nu, a, b):
    """The deviator Kondner's law gives the strain (Eq. 17) over the ultimate 1/b: 1 at
    failure."""
    return kondner_deviator(major_strain(eps_min, eps_max, nu), a, b) * b


def secant_modulus(eps_p, a, b):
    """The secant modulus of Kondner's law at the major strain eps_p, Eq. 19:
    E = (sigma_1 - sigma_3)_m / eps_p = 1 / (a + b eps_p) (the initial modulus 1/a at eps_p = 0)."""
    return 1.0 / (a + b * eps_p)


def secant_update(E, nu, eps_min, eps_max, a, b):
    """Per cell: (q_c, q_m, misfit, E_new, at_ultimate) of the current strains and moduli.

    The major strain is eps_p = (eps_max - eps_min) / (1 + nu): the axial strain of the
    unconfined triaxial test for which Kondner's law is calibrated (there eps_max - eps_min =
    (1 + nu) eps_axial). Then q_c = E eps_p, and the secant rule (Eq. 19) is
    E = q_m / eps_p = 1 / (a + b eps_p): positive, never above the initial modulus."""
    eps_p = major_strain(eps_min, eps_max, nu)
    q_c = E * eps_p
    q_m = kondner_deviator(eps_p, a, b)
    E_new = secant_modulus(eps_p, a, b)
    misfit = np.abs(E - E_new) / E          # = |q_c - q_m| / q_c (Eq. 18)
    at_ultimate = q_m * b >= ULTIMATE_FRACTION
    return q_c, q_m, misfit, E_new, at_ultimate


class Kondner(SoilLaw):
    """Kondner's hyperbolic soil, Eqs. 17-20 (``model = "hyperbolic"``): the functions of
    this module, iterated by the secant (Picard) loop."""

    word = "hyperbolic"
    title = "Kondner's hyperbolic soil"
    iteration = "secant"
    why_it_cannot_fail = ("it is nonlinear elastic: where its secant iteration stops depends on "
                          "nu (at a constant nu it loses its bulk stiffness with its shear "
                          "stiffness), not on the ground's bearing capacity")
    iteration_keys = ("tolerance", "max_iterations")
    max_iterations = 40
    keys = layer_keys = ("hyperbolic_a", "hyperbolic_b")
    E_keys = ("hyperbolic_a",)
    remembers = unloads_on_curve = True
    reports = ("stress_level",)
    state_fields = ("E",)      # the secant modulus, per cell
    #: the least secant modulus, a fraction of the initial 1/a (see MODULUS_FLOOR)
    modulus_floor = MODULUS_FLOOR
    #: the strain measure its deviator follows: eps_p of its principal strains and nu
    major_strain = staticmethod(major_strain)
    #: the secant iteration reads the cells' stress (not only their strains)
    needs_stress = False
    #: depth of the Anderson acceleration of its secant update (0: plain Picard)
    anderson_depth = 3

    @classmethod
    def cell_reports(cls, soil, eps_min, eps_max, deviator, depth, converged=None,
                     unloading=None):
        """``stress_level``: the deviator the law gives each cell's strain (Eq. 17) over the
        ultimate 1/b, 1 at failure; a cell on its unloading line, below its loading curve,
        its deviator x b. The constants are those the iteration converged on (Duncan &
        Chang's follow the stress), else those of the cell's stratum."""
        a, b, nu = (converged["a"], converged["b"], converged["nu"]) if converged else \
            kondner_parameters(soil, depth)
        level = stress_level(eps_min, eps_max, nu, a, b)
        if unloading is not None:
            level = np.where(unloading, deviator * b, level)
        return {"stress_level": level}

    @classmethod
    def stratum_text(cls, st):
        return f", Kondner 1/b = {1.0 / st['hyperbolic_b']:.4g} Pa (1/a = E)"

    @classmethod
    def check(cls, table, given, name, p_a=None):
        """Kondner's a and b, both required; an E given must be 1/a."""
        out = [f"{name}.{key}: missing for model = \"hyperbolic\"; add it (1/Pa: 1/a is the "
               f"initial tangent modulus, 1/b the ultimate deviator stress)"
               for key in ("hyperbolic_a", "hyperbolic_b") if key not in given]
        what_E = ("the surface modulus of a hyperbolic soil" if name == "soil" else
                  "the layer's modulus at its top")
        a_h = table.get("hyperbolic_a")
        if "E" in table and a_h and a_h > 0 and abs(table["E"] * a_h - 1.0) > 1e-6:
            out.append(f"{name}.E = {table['E']!r} contradicts {name}.hyperbolic_a (1/a = "
                       f"{1.0 / a_h:.6g} Pa is {what_E}); remove {name}.E")
        return out

    @classmethod
    def resolve_stratum(cls, table, ground):
        return {"E": 1.0 / table["hyperbolic_a"], "hyperbolic_a": table["hyperbolic_a"],
                "hyperbolic_b": table["hyperbolic_b"]}

    # -- the secant iteration's steps (per cell, in cell order; numpy) -------------------

    @classmethod
    def secant_start(cls, soil, depth, cell_strata) -> dict:
        """The cells' constants before the first iteration: Kondner's ``a``, ``b`` and the
        law's ``nu`` (``nu_intact``: the one its strain measure reads) of their strata."""
        a, b, nu = kondner_parameters(soil, depth)
        return {"a": a, "b": b, "nu": nu, "nu_intact": nu}

    @classmethod
    def secant_step(cls, soil, start, nu, E, eps_min, eps_max, stress, is_soil) -> dict:
        """The secant moduli of the current strains (Eq. 19: ``E``), their misfit (Eq. 18)
        and the cells at the ultimate deviator; Kondner's ``a`` and ``b`` stay."""
        _, _, misfit, E_new, ultimate = secant_update(E, nu, eps_min, eps_max, start["a"],
                                                      start["b"])
        return {"E": E_new, "misfit": misfit, "ultimate": ultimate, "a": start["a"],
                "b": start["b"]}

    @classmethod
    def next_moduli(cls, step, E_new, E, nu, nu_intact, E_initial, floor, accelerate
                    ) -> tuple:
        """The moduli of the next iteration, (E, nu or None where the law keeps nu), from
        the current ``E`` and this step's: the new secant modulus ``E_new`` (an unloading
        cell's E_ur), floored, accelerated (``accelerate(x, x_new, floor, ceiling)``) up to
        the initial modulus."""
        return accelerate(E, np.maximum(E_new, floor), floor, E_initial), None

    @classmethod
    def unloading_modulus(cls, soil, start, E_initial, E, stress, peak_stress, ratio,
                          is_soil):
        """Each cell's unloading line's modulus: ratio x its initial modulus 1/a."""
        return ratio * E_initial

    @classmethod
    def start_text(cls, soil, tol: float) -> str:
        return (f"hyperbolic soil: 1/a = {1.0 / soil.hyperbolic_a:.4g} Pa, 1/b = "
                f"{1.0 / soil.hyperbolic_b:.4g} Pa, tolerance {tol:.3g} (Eq. 18)")

    @classmethod
    def strength_text(cls, soil) -> str:
        return f"the ultimate deviator 1/b = {1.0 / soil.hyperbolic_b / 1e3:.4g} kPa"

    @classmethod
    def exhausted_text(cls, n_ult, where, max_it, worst, du_rel) -> str | None:
        """The iteration's failure in the law's own words, where it has them (None: the
        soil cannot carry its load)."""
        return None
