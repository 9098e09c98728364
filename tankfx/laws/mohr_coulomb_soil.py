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
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

from .geostatic import geostatic_stress, lighter_than_water
from .mohr_coulomb import circle_strength
from .plasticity import ELASTIC, elastic_matrix, mobilised_strength, stress_update
from .point_law import PointUpdate
from .soil_law import WATER_UNIT_WEIGHT, ElastoplasticSoil

#: the largest friction angle taken, degrees: beyond it no real soil, and the Mohr-Coulomb
#: cone's apex is so sharp that its returns lose their accuracy
MAX_FRICTION_ANGLE = 60.0
#: the largest Poisson's ratio taken: the displacement form (no mixed form is built for
#: this law); the limit load does not depend on nu
MAX_NU = 0.49


class MohrCoulombSoil(ElastoplasticSoil):
    """Perfect plasticity of Mohr-Coulomb and Tresca with a geostatic start."""

    word = "mohr_coulomb"
    title = "an elastoplastic Mohr-Coulomb soil"
    layer_keys = ("cohesion", "friction_angle", "dilation_angle", "tensile_strength",
                  "cohesion_gradient", "unit_weight", "K0")
    keys = (*layer_keys, "water_table", "water_unit_weight")
    #: its stress level is the mobilised shear strength
    stress_level_label = "tau / tau_f"
    #: the limit analysis' cones are its own
    has_bounds = True

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
            out.append(f"{name}.E: missing for model = \"{cls.word}\"; add it (Pa: the "
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
            out.append(f"{name}.nu = {nu!r}: at most {MAX_NU} with model = \"{cls.word}\" "
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
                           f"with soil.model = \"{cls.word}\"; remove them, or use a linear "
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
    def limit_strength(cls, soil, depth) -> dict:
        """Each depth's stratum's cohesion as a line in z: c = cohesion + gradient (depth -
        top) = (cohesion - gradient top) - gradient z."""
        st = soil.at_depth(depth)
        gradient = st["cohesion_gradient"]
        return {"c_top": st["cohesion"] - gradient * st["top"], "dc_dz": -gradient,
                "phi": np.radians(st["friction_angle"]), "gamma": st["unit_weight"]}

    @classmethod
    def limit_strata(cls, soil, top: float, bottom: float) -> np.ndarray:
        """Within a stratum the yield margin of a field constant in z grows with depth (the
        cohesion's gradient and gamma z sin phi are non-negative), so its top suffices."""
        rows = []
        for k, st in enumerate(soil.strata):
            below = soil.strata[k + 1].depth if k + 1 < len(soil.strata) else math.inf
            d = max(st.depth, top)
            if d >= min(below, bottom):
                continue
            c = (st.cohesion or 0.0) + (st.cohesion_gradient or 0.0) * (d - st.depth)
            rows.append((-d, c, math.radians(st.friction_angle or 0.0), st.unit_weight or 0.0))
        return np.array(rows, dtype=float).reshape(-1, 4)

    @classmethod
    def limit_notes(cls, soil) -> tuple[list[str], bool]:
        """Limit analysis assumes associated flow and takes no tension cut-off."""
        notes, associated = [], True
        for k, st in enumerate(soil.strata):
            phi, psi = st.friction_angle or 0.0, st.dilation_angle or 0.0
            where = "soil" if k == 0 else f"soil.layers[{k}]"
            if psi != phi:
                associated = False
                notes.append(f"{where}: the dilation angle {psi:g} differs from the friction "
                             f"angle {phi:g}: limit analysis assumes associated flow (psi = "
                             f"phi), and these are the associated soil's bounds")
            if st.tensile_strength is not None:
                notes.append(f"{where}: the tension cut-off ({st.tensile_strength:g} Pa) is not "
                             f"taken: the bounds are Mohr-Coulomb's without it")
        return notes, associated

    @classmethod
    def point_law(cls, soil, depth) -> MohrCoulombPoints:
        """The law at the points at ``depth`` (m): :class:`MohrCoulombPoints`."""
        return MohrCoulombPoints.at(soil, depth)

    @classmethod
    def initial_stress(cls, soil, depth) -> np.ndarray:
        """The geostatic effective stress at ``depth`` as Mandel vectors (N x 4, tension
        positive): sigma_rr = sigma_theta = -K0 sigma'_v, sigma_zz = -sigma'_v."""
        sv, sh = geostatic_stress(soil, depth)
        return np.column_stack([-sh, -sv, 0.0 * sv, -sh])


class FrictionalPoints:
    """What a perfectly plastic law at points whose strength is a cohesion and a friction
    angle (Mohr-Coulomb's, Drucker-Prager's) shares: its fields ``E``, ``nu``,
    ``cohesion`` (inf: never yields), ``sin_phi``, ``sin_psi`` and ``sigma0`` (the ground
    at rest), no state of its own, the strength reduced through c and tan phi. A subclass
    is a frozen dataclass with those fields and its ``update``."""

    state: ClassVar[dict[str, int]] = {}

    def __post_init__(self):
        # (the elastic matrices, read at every update: made once)
        object.__setattr__(self, "_D", elastic_matrix(self.E, self.nu))

    @property
    def symmetric(self) -> bool:
        """Associated flow (psi = phi at every point that can yield)."""
        can = np.isfinite(self.cohesion)
        return bool(np.all(self.sin_psi[can] == self.sin_phi[can]))

    def initial_stress(self) -> np.ndarray:
        return self.sigma0

    def initial_state(self) -> dict[str, np.ndarray]:
        return {}

    def elastic_matrix(self, stress=None) -> np.ndarray:
        return self._D

    def reduced(self, factor: float):
        """c / F and tan phi / F; the dilation angle kept until the reduced friction angle
        reaches it."""
        tan_phi = np.tan(np.arcsin(self.sin_phi))
        sin_phi = np.sin(np.arctan(tan_phi / factor))
        return replace(self, cohesion=self.cohesion / factor, sin_phi=sin_phi,
                       sin_psi=np.minimum(self.sin_psi, sin_phi))

    def elastic_where(self, mask, E=None, nu=None):
        return replace(self, E=self.E if E is None else np.where(mask, E, self.E),
                       nu=self.nu if nu is None else np.where(mask, nu, self.nu),
                       cohesion=np.where(mask, np.inf, self.cohesion))


@dataclass(frozen=True)
class MohrCoulombPoints(FrictionalPoints):
    """Mohr-Coulomb (Tresca at phi = 0) at N points (:class:`tankfx.laws.point_law.PointLaw`):
    per point ``E``, ``nu``, the ``cohesion`` (inf: never yields), ``sin_phi``,
    ``sin_psi``, the ``tension`` cut-off (inf: none) and the ground at rest ``sigma0``
    (N, 4). Perfect plasticity: no state of its own. The return is
    :func:`tankfx.laws.plasticity.stress_update`."""

    E: np.ndarray
    nu: np.ndarray
    cohesion: np.ndarray
    sin_phi: np.ndarray
    sin_psi: np.ndarray
    tension: np.ndarray
    sigma0: np.ndarray
    @classmethod
    def at(cls, soil, depth) -> "MohrCoulombPoints":
        """The points at ``depth`` (m) of a resolved [soil]."""
        k = MohrCoulombSoil.point_constants(soil, depth)
        return cls(E=k["E"], nu=k["nu"], cohesion=k["cohesion"], sin_phi=k["sin_phi"],
                   sin_psi=k["sin_psi"], tension=k["tension"],
                   sigma0=MohrCoulombSoil.initial_stress(soil, depth))

    def update(self, d_eps, stress, state) -> PointUpdate:
        sigma, C, code, d_eps_p = stress_update(
            d_eps, stress, self.E, self.nu, self.cohesion, self.sin_phi, self.sin_psi,
            self.tension, D=self._D, reference=self.sigma0)
        return PointUpdate(stress=sigma, tangent=C, yielding=code != ELASTIC,
                           plastic_strain=d_eps_p, state={})

    def mobilised(self, stress, per: int = 1) -> np.ndarray:
        """tau / tau_f of Mohr's largest circle (:func:`tankfx.laws.plasticity.mobilised_strength`)."""
        if per == 1:
            return mobilised_strength(stress, self.cohesion, self.sin_phi)
        return mobilised_strength(stress, self.cohesion.reshape(-1, per).mean(axis=1),
                                  self.sin_phi.reshape(-1, per)[:, 0])


def _at_rest(soil, depths):
    """(sigma'_v, sigma'_h, the excess of the at-rest deviator over the strength) at
    ``depths`` (compression positive; the excess > 0 outside the yield surface)."""
    sv, sh = geostatic_stress(soil, depths)
    st = soil.at_depth(depths)
    c = st["cohesion"] + st["cohesion_gradient"] * (depths - st["top"])
    s = np.sin(np.radians(st["friction_angle"]))
    # (compression positive here: the circle's centre is -(sv + sh) / 2 in tension)
    return sv, sh, 0.5 * np.abs(sv - sh) - circle_strength(-0.5 * (sv + sh), c, s)
