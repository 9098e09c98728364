"""The elastoplastic Mohr-Coulomb soil (Tresca at phi = 0): linear elastic (E(h), nu) inside
the yield surface, perfectly plastic on it,

    (sigma_1 - sigma_3) + (sigma_1 + sigma_3) sin phi <= 2 c cos phi        (tension positive)

with c = cohesion + cohesion_gradient x (h - top), h the depth (a normally consolidated
clay's undrained strength), the flow of the dilation angle psi <= phi, and an optional Rankine
tension cut-off sigma_1 <= t. The stress is held at the quadrature points of the soil's forms
and updated by :func:`tankfx.laws.plasticity.stress_update`; a stage is solved by Newton's
method with load steps (:mod:`tankfx.iterations.newton`). The ground starts from its
geostatic state: sigma'_v = the weight of the strata above less the pore pressure below the
water table, sigma'_h = K0 sigma'_v, which must lie inside the yield surface.
"""
from __future__ import annotations

import math

import numpy as np

from .geostatic import geostatic_stress, lighter_than_water
from .soil_law import WATER_UNIT_WEIGHT, SoilLaw

#: the largest friction angle taken, degrees: beyond it no real soil, and the Mohr-Coulomb
#: cone's apex is so sharp that its returns lose their accuracy
MAX_FRICTION_ANGLE = 60.0
#: the largest Poisson's ratio taken: the displacement form (no mixed form is built for
#: this law); the limit load does not depend on nu
MAX_NU = 0.49


class MohrCoulombSoil(SoilLaw):
    """Perfect plasticity of Mohr-Coulomb and Tresca with a geostatic start."""

    word = "mohr_coulomb"
    title = "an elastoplastic Mohr-Coulomb soil"
    iteration = "newton"
    iteration_keys = ("max_iterations",)
    #: Newton iterations of a load step before it is halved
    max_iterations = 25
    layer_keys = ("cohesion", "friction_angle", "dilation_angle", "tensile_strength",
                  "cohesion_gradient", "unit_weight", "K0")
    keys = (*layer_keys, "water_table", "water_unit_weight")
    reports = ("plastic", "stress_level")
    #: its stress level is the mobilised shear strength
    stress_level_label = "tau / tau_f"
    #: its state lives at the forms' quadrature points (stress, plastic strain, the
    #: plastic flag): the soil block holds it for the Newton iteration
    point_state = True
    #: its ground fails: a collapse load and a strength factor are its to compute
    fails = True
    #: the displacement form only: a stratum's nu at most MAX_NU
    displacement_form_only = True
    #: its plastic strain stays when the load comes off
    keeps_permanent_strain = True

    @classmethod
    def stratum_text(cls, st):
        phi = st.get("friction_angle") or 0.0
        c = st.get("cohesion") or 0.0
        grad = st.get("cohesion_gradient") or 0.0
        text = f", {'Tresca s_u' if phi == 0.0 else 'c'} = {c:.4g} Pa"
        if grad:
            text += f" + {grad:.4g} Pa/m below its top"
        if phi:
            text += f", phi = {phi:g} deg, psi = {st.get('dilation_angle') or 0.0:g} deg"
        if st.get("tensile_strength") is not None:
            text += f", tension cut-off {st['tensile_strength']:.4g} Pa"
        return text

    @classmethod
    def check(cls, table, given, name, p_a=None):
        """A strength (c or phi > 0, phi < 60 degrees), psi <= phi, a tensile strength >= 0,
        E given, nu <= 0.49."""
        out = []
        if "E" not in given:
            out.append(f"{name}.E: missing for model = \"mohr_coulomb\"; add it (Pa: the "
                       f"soil's Young's modulus inside the yield surface)")
        c = table.get("cohesion", 0.0) or 0.0
        phi = table.get("friction_angle", 0.0) or 0.0
        grad = table.get("cohesion_gradient", 0.0) or 0.0
        if not (c > 0.0 or phi > 0.0 or grad > 0.0):
            out.append(f"{name}.cohesion, {name}.friction_angle: the soil has no strength; "
                       f"give cohesion > 0 (Pa: Tresca's s_u with friction_angle = 0) or "
                       f"friction_angle > 0 (degrees)")
        if phi >= MAX_FRICTION_ANGLE:
            out.append(f"{name}.friction_angle = {phi!r}: at most {MAX_FRICTION_ANGLE:g} "
                       f"degrees is taken (no soil has more; the cone's apex is too sharp "
                       f"to return to accurately); give the soil's angle in degrees")
        psi = table.get("dilation_angle", 0.0) or 0.0
        if psi > phi:
            out.append(f"{name}.dilation_angle = {psi!r} exceeds {name}.friction_angle = "
                       f"{phi!r}: a soil dilates at most as its friction (psi <= phi; 0: no "
                       f"volume change in plastic flow, the usual choice); lower it")
        t = table.get("tensile_strength")
        if t is not None and t < 0.0:
            out.append(f"{name}.tensile_strength = {t!r}: a tensile strength is >= 0 (Pa); "
                       f"leave it out for none beyond the Mohr-Coulomb apex")
        nu = table.get("nu")
        if isinstance(nu, float) and nu > MAX_NU:
            out.append(f"{name}.nu = {nu!r}: at most {MAX_NU} with model = \"mohr_coulomb\" "
                       f"(it is solved in the displacement form; the collapse load does not "
                       f"depend on nu); lower it")
        return out

    @classmethod
    def check_ground(cls, soil, layers):
        """Below the water table a stratum heavier than water (or weightless)."""
        return lighter_than_water(soil, layers,
                                  soil.get("water_unit_weight", WATER_UNIT_WEIGHT),
                                  weightless=True)

    @classmethod
    def resolve_ground(cls, soil):
        return {"water_table": soil.get("water_table"),
                "water_unit_weight": soil.get("water_unit_weight", WATER_UNIT_WEIGHT)
                if "water_table" in soil else None}

    @classmethod
    def resolve_stratum(cls, table, ground):
        """E and the constants, their defaults resolved (c 0, phi 0, psi 0, no cut-off, no
        gradient, weightless, K0 Jaky's 1 - sin phi)."""
        phi = table.get("friction_angle", 0.0)
        return {"E": table["E"], "cohesion": table.get("cohesion", 0.0),
                "friction_angle": phi, "dilation_angle": table.get("dilation_angle", 0.0),
                "tensile_strength": table.get("tensile_strength"),
                "cohesion_gradient": table.get("cohesion_gradient", 0.0),
                "unit_weight": table.get("unit_weight", 0.0),
                "K0": table.get("K0", 1.0 - math.sin(math.radians(phi)))}

    @classmethod
    def cell_reports(cls, soil, eps_min, eps_max, deviator, depth, converged=None,
                     unloading=None):
        """``plastic``: the share of a cell's points that yield (1: all); ``stress_level``:
        tau / tau_f of its mean stress, 1 at the strength. From the Newton iteration's
        status (zeros before it has run)."""
        if converged is None:
            return {"plastic": np.zeros_like(depth), "stress_level": np.zeros_like(depth)}
        return {"plastic": converged["plastic"], "stress_level": converged["stress_level"]}

    @classmethod
    def scene_problems(cls, scene) -> list[str]:
        """What the elastoplastic soil does not take yet: an overturning load (solved as a
        harmonic about a linear state), a Mohr-Coulomb interface, a pit dug below the water
        table; and what it refuses: linear triangles, a ground at rest outside the yield
        surface."""
        out = []
        for k, ld in enumerate((scene.load, *scene.stages)):
            if ld.overturning:
                where = "load" if k == 0 else f"stages[{k}]"
                out.append(f"{where}.overturning_moment, {where}.base_shear: the overturning "
                           f"load is solved as a harmonic about a linear soil's state, not yet "
                           f"with soil.model = \"mohr_coulomb\"; remove them, or use a linear "
                           f"or secant soil")
                break
        out += cls._at_rest_outside(scene.soil, scene.domain.depth)
        if scene.mesh.degree == 1:
            # (measured: the rigid footing's N_c +33 % at 6k unknowns, +17 % at 23k, where
            # quadratic elements are within 1 %: docs/development/2026-11-27-plastic-soil.md)
            out.append("mesh.degree = 1: linear triangles lock under plastic flow without "
                       "volume change (Tresca, or zero dilation; Sloan & Randolph 1982) and "
                       "overestimate the collapse load by 15-35 %; use degree 2 (the "
                       "default), 3 or 4")
        wt = scene.soil.water_table
        if scene.plate is not None and scene.embedment > 0.0 and wt is not None \
                and wt < scene.embedment:
            out.append(f"soil.water_table = {wt!r} is above the pit's bottom (plate.embedment "
                       f"= {scene.embedment!r}): its excavation would need the pit dewatered "
                       f"and the seepage into it, which are not modelled; give a water table "
                       f"at or below {scene.embedment!r} m")
        return out

    @staticmethod
    def _at_rest_outside(soil, bottom: float) -> list[str]:
        """The ground at rest must lie inside the yield surface down to the domain's base
        (``bottom``, m). Linear in depth within a stratum and above and below the water
        table, so checked at those kinks, the onset found between them exactly."""
        tops = [st.depth for st in soil.strata]
        wt = [soil.water_table] if soil.water_table is not None else []
        d = np.array(sorted({*tops, *(t + 1e-9 * (1.0 + t) for t in tops), *wt, bottom}))
        d = d[d <= bottom]
        sv, sh, excess = _at_rest(soil, d)
        bad = excess > 1e-9 * (np.abs(sv) + 1.0)
        if not bad.any():
            return []
        i = int(np.flatnonzero(bad)[0])
        h = d[i] if i == 0 else d[i - 1] + (d[i] - d[i - 1]) * (
            -excess[i - 1] / (excess[i] - excess[i - 1]))
        k = int(soil.stratum_of(np.array([h]))[0])
        where = "soil" if k == 0 else f"soil.layers[{k}]"
        return [f"{where}: the ground at rest lies outside the yield surface from {h:.4g} m "
                f"down (there sigma'_h = K0 sigma'_v = {float(_at_rest(soil, np.array([h]))[1][0]):.4g} "
                f"Pa differs from sigma'_v by more than twice the strength that "
                f"{where}.cohesion, cohesion_gradient and friction_angle give); raise the "
                f"strength or give a K0 nearer 1"]

    @classmethod
    def undrained_strength(cls, soil, depth: float) -> float | None:
        """Tresca's s_u at ``depth`` (cohesion + gradient below the stratum's top) where
        every stratum has phi = 0, else None."""
        if any(st.friction_angle for st in soil.strata):
            return None
        return float(cls.point_constants(soil, np.array([depth]))["cohesion"][0])

    @classmethod
    def symmetric_tangent(cls, soil) -> bool:
        """Associated flow (psi = phi in every stratum) has a symmetric tangent."""
        return all((st.dilation_angle or 0.0) == (st.friction_angle or 0.0)
                   for st in soil.strata)

    @classmethod
    def point_constants(cls, soil, depth) -> dict[str, np.ndarray]:
        """Per point at ``depth`` (m): E, nu, the cohesion there, sin phi, sin psi and the
        tension cut-off (inf: none)."""
        st = soil.at_depth(depth)
        h = np.maximum(np.asarray(depth, dtype=float), 0.0)
        cut = np.array([np.inf if x.tensile_strength is None else x.tensile_strength
                        for x in soil.strata])[soil.stratum_of(depth)]
        return {"E": st["E"], "nu": st["nu"],
                "cohesion": st["cohesion"] + st["cohesion_gradient"] * (h - st["top"]),
                "sin_phi": np.sin(np.radians(st["friction_angle"])),
                "sin_psi": np.sin(np.radians(st["dilation_angle"])), "tension": cut}

    @classmethod
    def initial_stress(cls, soil, depth) -> np.ndarray:
        """The geostatic effective stress at ``depth`` as Mandel vectors (N x 4, tension
        positive): sigma_rr = sigma_theta = -K0 sigma'_v, sigma_zz = -sigma'_v."""
        sv, sh = geostatic_stress(soil, depth)
        return np.column_stack([-sh, -sv, 0.0 * sv, -sh])


def _at_rest(soil, depths):
    """(sigma'_v, sigma'_h, the excess of the at-rest deviator over the strength) at
    ``depths`` (compression positive; the excess > 0 outside the yield surface)."""
    sv, sh = geostatic_stress(soil, depths)
    st = soil.at_depth(depths)
    c = st["cohesion"] + st["cohesion_gradient"] * (depths - st["top"])
    s = np.sin(np.radians(st["friction_angle"]))
    # (s1 - s3) / 2 <= c cos phi + (s1 + s3) / 2 sin phi
    return sv, sh, 0.5 * np.abs(sv - sh) - c * np.sqrt(1.0 - s * s) - 0.5 * (sv + sh) * s
