"""Modified Cam Clay (Roscoe & Burland 1968), the critical-state clay: the yield ellipse

    q^2 / M^2 + p' (p' - p_c) <= 0,

hardening with the plastic volume change (p_c = p_c0 exp(eps_v^p / (lambda* - kappa*))), a
bulk modulus p' / kappa* and Poisson's ratio ``nu`` inside it (unloading-reloading), in
effective stress: the pore water's pressure is hydrostatic below ``water_table`` (drained)
or the consolidation's unknown (with a ``[consolidation]``: its undrained strength is then
an outcome, not an input). The return at the points is
:mod:`tankfx.laws.cam_clay_points`.

The ground at rest (per stratum, compression positive): sigma'_v from the unit weights less
the hydrostatic pore pressure; its preconsolidation sigma'_vc = OCR sigma'_v, or sigma'_v +
POP; on the one-dimensional normally consolidated line there, sigma'_hc = K0_nc sigma'_vc
(K0_nc by default the law's own, :func:`~tankfx.laws.cam_clay_points.normally_consolidated_ratio`,
so that a wide load keeps a normally consolidated ground on it), and p_c the ellipse through
that state, p'_c (1 + eta_nc^2 / M^2). Unloaded from it in one dimension, elastically:

    sigma'_h = K0_nc sigma'_vc - nu / (1 - nu) (sigma'_vc - sigma'_v).

The least mean stress P_MIN: below it the bulk modulus is P_MIN / kappa* (the top tens of
centimetres of a clay at rest; without it the ground surface, at p' = 0, would have no
stiffness); it is also the least preconsolidation pressure (p_c >= P_MIN at rest and after:
:mod:`~tankfx.laws.cam_clay_points`), the strength of a normally consolidated clay's top
(q at most M P_MIN / 2 where its own p_c would be less), which a clay with a crust never
reaches.

A stratum's ``E`` is not an input: it is the law's modulus at rest, 3 (1 - 2 nu) p' /
kappa*, at the middle of the stratum's first REPRESENTATIVE_DEPTH metres: what the rest of
tankfx reads as one modulus of the soil (the interface's penalty, the consolidation's c_v
and time scale, the plate's relative stiffness in words). The points' own modulus follows
their p'.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .cam_clay_points import (CamClayPoints, critical_state_angle, critical_state_ratio,
                              invariants, normally_consolidated_ratio)
from .geostatic import geostatic_stress, lighter_than_water
from .soil_law import WATER_UNIT_WEIGHT, ElastoplasticSoil

#: the least mean effective stress of the bulk modulus, Pa (the module's docstring)
P_MIN = 1e3
#: M at most: 3 M / (3 - M), the drained strength's ratio, must stay finite; M = 1.8 is
#: phi_cs = 44 degrees, beyond any clay
MAX_M = 1.8
#: a stratum's E is its modulus at rest at the middle of its first this many metres
REPRESENTATIVE_DEPTH = 5.0

_LAW = "for model = \"cam_clay\""


class CamClaySoil(ElastoplasticSoil):
    """Modified Cam Clay in effective stress, with a geostatic start."""

    word = "cam_clay"
    title = "a Modified Cam Clay soil (critical state, effective stress)"
    layer_keys = ("lambda_star", "kappa_star", "M", "critical_state_friction_angle", "OCR",
                  "POP", "K0_nc", "unit_weight")
    keys = (*layer_keys, "water_table", "water_unit_weight")
    own_keys = {
        "lambda_star": dict(
            type=float, unit="-", limit=(0.0, 1.0), default_doc="required",
            meaning=f"{{its}} modified compression index lambda*, {_LAW} (required): the "
                    "volumetric strain of normally consolidated compression per unit of ln "
                    "p' (lambda / (1 + e) of the e-ln p' chart; C_c / (2.3 (1 + e)))"),
        "kappa_star": dict(
            type=float, unit="-", limit=(0.0, 1.0), default_doc="required",
            meaning=f"{{its}} modified swelling index kappa*, {_LAW} (required, below "
                    "lambda*): the volumetric strain of unloading and reloading per unit of "
                    "ln p'; the bulk modulus is p' / kappa*"),
        "M": dict(
            type=float, unit="-", limit=(0.0, MAX_M), default_doc="from phi_cs",
            meaning=f"{{its}} critical state's stress ratio M = q / p', {_LAW}: give it or "
                    "`critical_state_friction_angle` (M = 6 sin phi / (3 - sin phi))"),
        "critical_state_friction_angle": dict(
            type=float, unit="deg", limit=(0.0, 44.0), default_doc="from M",
            meaning=f"{{its}} critical state's friction angle phi_cs (degrees), {_LAW}: "
                    "gives M = 6 sin phi_cs / (3 - sin phi_cs); or give `M`"),
        "OCR": dict(
            type=float, unit="-", limit=(1.0, None, False), default=1.0,
            meaning=f"{{its}} overconsolidation ratio sigma'_vc / sigma'_v, {_LAW} (1: "
                    "normally consolidated); or give `POP`"),
        "POP": dict(
            type=float, unit="Pa", limit=(0.0, None, False), default_doc="none (OCR)",
            meaning=f"{{its}} pre-overburden pressure sigma'_vc - sigma'_v (Pa), {_LAW}: a "
                    "crust's overconsolidation, largest near the surface; or give `OCR`"),
        "K0_nc": dict(
            type=float, unit="-", limit=(0.0, 1.0), default_doc="the law's own",
            meaning=f"{{its}} K0 of normally consolidated one-dimensional compression, "
                    f"{_LAW}: by default the law's own (a wide load keeps a normally "
                    "consolidated ground on it); the ground at rest is unloaded from it "
                    "elastically by the OCR or POP"),
    }
    stress_level_label = "q / (M p')"
    fixed_constants = False
    #: the default domain, 40 foundation radii wide and deep: its modulus grows with p', so
    #: the far ground adds nothing (a 25 m flexible load's w0: -0.37 % at 10 a, -0.05 % at
    #: 20 a, against 40 and 80 a, which agree to 0.03 %), while at 10000 a the stiffness
    #: grows a millionfold with depth and the solve loses its digits (-0.3 % at 200 a; at
    #: 400 a no equilibrium is found at all)
    domain_factor = 40.0
    why_no_bounds = ("the limit analysis takes Mohr-Coulomb's strength; a Cam Clay's "
                     "depends on its state (ask for collapse = \"strength\")")

    @classmethod
    def stratum_text(cls, st):
        M = st.get("M") or (float(critical_state_ratio(st["critical_state_friction_angle"]))
                            if st.get("critical_state_friction_angle") else None)
        text = (f", lambda* = {st.get('lambda_star')}, kappa* = {st.get('kappa_star')}, "
                f"M = {M:.4g} (phi_cs = {float(critical_state_angle(M)):.3g} deg)"
                if M else "")
        if st.get("POP"):
            text += f", POP = {st['POP']:.4g} Pa"
        elif st.get("OCR") and st["OCR"] != 1.0:
            text += f", OCR = {st['OCR']:g}"
        return text

    @classmethod
    def check(cls, table, given, name, p_a=None):
        """lambda* and kappa* given, kappa* < lambda*; M or phi_cs, not both; OCR or POP,
        not both; no E or E_gradient (the modulus follows p'); nu <= 0.49."""
        out = []
        for key, why in (("lambda_star", "the modified compression index, e.g. 0.1"),
                         ("kappa_star", "the modified swelling index, e.g. 0.02")):
            if key not in given:
                out.append(f"{name}.{key}: missing for model = \"cam_clay\"; add it ({why})")
        lam, kap = table.get("lambda_star"), table.get("kappa_star")
        if isinstance(lam, float) and isinstance(kap, float) and kap >= lam:
            out.append(f"{name}.kappa_star = {kap!r} is not below {name}.lambda_star = "
                       f"{lam!r}: the swelling line is flatter than the compression line "
                       f"(kappa* about lambda* / 5 to / 10); lower kappa_star")
        if ("M" in given) == ("critical_state_friction_angle" in given):
            out.append(f"{name}.M, {name}.critical_state_friction_angle: give one of them (M "
                       f"= q / p' at the critical state, or phi_cs in degrees)")
        if "OCR" in given and "POP" in given:
            out.append(f"{name}.OCR, {name}.POP: give one of them (the overconsolidation as a "
                       f"ratio, or as a pressure in Pa)")
        for key in ("E", "E_gradient"):
            if key in given:
                out.append(f"{name}.{key}: not used with model = \"cam_clay\" (its modulus is "
                           f"p' / kappa*, from the stress); remove it")
        nu = table.get("nu")
        if isinstance(nu, float) and nu > 0.49:
            out.append(f"{name}.nu = {nu!r}: at most 0.49 with model = \"cam_clay\" (the "
                       f"displacement form; its undrained response is a consolidation's); "
                       f"lower it")
        if "unit_weight" not in given:
            out.append(f"{name}.unit_weight: missing for model = \"cam_clay\"; add it (N/m^3, "
                       f"saturated below the water table): the clay's strength and stiffness "
                       f"follow its effective stress")
        return out

    @classmethod
    def check_ground(cls, soil, layers):
        return lighter_than_water(soil, layers,
                                  soil.get("water_unit_weight", WATER_UNIT_WEIGHT))

    @classmethod
    def resolve_ground(cls, soil):
        return {"water_table": soil.get("water_table"),
                "water_unit_weight": soil.get("water_unit_weight", WATER_UNIT_WEIGHT)
                if "water_table" in soil else None}

    @classmethod
    def resolve_stratum(cls, table, ground):
        """The constants as given (M or phi_cs, OCR or POP, K0_nc or none: the law derives
        the rest where it reads them, so that a changed nu or phi_cs changes them too); E a
        placeholder (:meth:`finish` sets the modulus at rest)."""
        return {"E": 1.0, **{k: table.get(k) for k in cls.layer_keys}}

    @classmethod
    def written(cls, table):
        return {k: v for k, v in table.items() if k not in ("E", "E_gradient")}

    @staticmethod
    def constants(st) -> dict:
        """A stratum's M, K0_nc, OCR and POP (None: by OCR), the derived ones derived."""
        M = st.M if st.M is not None else float(
            critical_state_ratio(st.critical_state_friction_angle))
        K0_nc = st.K0_nc if st.K0_nc is not None else float(
            normally_consolidated_ratio(M, st.lambda_star, st.kappa_star, st.nu)[1])
        return {"M": M, "K0_nc": K0_nc, "POP": st.POP,
                "OCR": 1.0 if st.OCR is None else st.OCR}

    @classmethod
    def finish(cls, soil):
        """Each stratum's E: the modulus at rest, 3 (1 - 2 nu) p' / kappa*, at the middle of
        its first REPRESENTATIVE_DEPTH metres (or of its thickness), and no E_gradient (the
        points' modulus follows p' itself; a gradient would grade the mesh for E(h))."""
        strata = soil.strata
        out = []
        for k, st in enumerate(strata):
            below = strata[k + 1].depth if k + 1 < len(strata) else math.inf
            middle = 0.5 * (st.depth + min(below, st.depth + REPRESENTATIVE_DEPTH))
            E = float(cls._modulus_at_rest(soil, np.array([middle]))[0])
            out.append(replace(st, E=E, E_gradient=0.0))
        return replace(soil, E=out[0].E, E_gradient=0.0, layers=tuple(out[1:]))

    @classmethod
    def _modulus_at_rest(cls, soil, depth):
        sigma = cls.initial_stress(soil, depth)
        st = soil.at_depth(depth)
        p = invariants(sigma)[0]
        return 3.0 * (1.0 - 2.0 * st["nu"]) * np.maximum(p, P_MIN) / st["kappa_star"]

    # ---- the ground at rest ----------------------------------------------------------------
    @classmethod
    def _at_rest(cls, soil, depth):
        """(sigma'_v, sigma'_h, p_c) at ``depth`` (compression positive)."""
        depth = np.asarray(depth, dtype=float)
        sv = geostatic_stress(soil, depth)[0]
        idx = soil.stratum_of(depth)
        st = soil.strata
        k = [cls.constants(x) for x in st]
        ocr = np.array([x["OCR"] for x in k])[idx]
        pop = np.array([x["POP"] or 0.0 for x in k])[idx]
        has_pop = np.array([x["POP"] is not None for x in k])[idx]
        nu = np.array([x.nu for x in st])[idx]
        K0_nc = np.array([x["K0_nc"] for x in k])[idx]
        M = np.array([x["M"] for x in k])[idx]
        svc = np.where(has_pop, sv + pop, ocr * sv)
        sh = K0_nc * svc - nu / (1.0 - nu) * (svc - sv)
        eta_nc = 3.0 * (1.0 - K0_nc) / (1.0 + 2.0 * K0_nc)
        p_c = svc * (1.0 + 2.0 * K0_nc) / 3.0 * (1.0 + eta_nc ** 2 / M ** 2)
        return sv, np.minimum(sh, _passive(sv, p_c, M)), p_c

    @classmethod
    def capped_depth(cls, soil, bottom: float) -> float:
        """The depth (m) down to which the ground at rest's sigma'_h is capped at its
        ellipse (0: nowhere): an overconsolidated crust unloaded elastically would lie
        outside it (in extension, passive)."""
        d = _sampled(soil, bottom)
        sv, sh, p_c = cls._at_rest(soil, d)
        raw = cls._unloaded(soil, d)
        capped = raw > sh * (1.0 + 1e-9) + 1e-9
        return float(d[capped].max()) if capped.any() else 0.0

    @classmethod
    def _unloaded(cls, soil, depth):
        sv = geostatic_stress(soil, depth)[0]
        idx = soil.stratum_of(depth)
        k = [cls.constants(x) for x in soil.strata]
        nu = np.array([x.nu for x in soil.strata])[idx]
        K0_nc = np.array([x["K0_nc"] for x in k])[idx]
        svc = np.where(np.array([x["POP"] is not None for x in k])[idx],
                       sv + np.array([x["POP"] or 0.0 for x in k])[idx],
                       np.array([x["OCR"] for x in k])[idx] * sv)
        return K0_nc * svc - nu / (1.0 - nu) * (svc - sv)

    @classmethod
    def ground_warnings(cls, soil, bottom: float) -> list[str]:
        out = []
        top = cls.constants(soil.strata[0])
        if top["POP"] is None:
            # (measured, a 10 m flexible load on 10 m of an OCR = 1 clay, consolidating:
            # it fails at 2.5 kPa on the coarse mesh, 2.0 kPa on the default one; before
            # the least p_c at 1.1, 1.6, 3.0 and 6.1 kPa with P_MIN = 0.5, 1, 2 and 4 kPa;
            # drained, a Mohr-Coulomb ground of c' = 0.2 kPa and the same phi fails at
            # 6.7 kPa where this one did at 7.3. Drained, a 30 m steel tank's floor on 12 m
            # of it carried 118 kPa, the clay hardening as it compressed: w0 2.24 m)
            q = (2.0 + math.pi) * top["M"] * P_MIN / 2.0
            out.append(
                f"soil: normally consolidated at the ground surface (no POP; an OCR leaves "
                f"sigma'_vc = 0 there): a clay's strength is nil at p' = 0, held at the "
                f"least preconsolidation pressure {P_MIN:g} Pa (q at most M P_MIN / 2), so "
                f"the edge of a load on the surface (a flexible load's, a shell's foot) may "
                f"punch in from about (2 + pi) M P_MIN / 2 = {q / 1e3:.2g} kPa where the clay "
                f"cannot harden first (loaded faster than it drains: a flexible 10 m load on "
                f"10 m of such clay found no equilibrium beyond 2-2.5 kPa); give the clay "
                f"its crust (POP: its undrained strength at the surface above the load / "
                f"(2 + pi)) to carry a load's edge there")
        h = cls.capped_depth(soil, bottom)
        if h:
            out.append(
                f"soil: the ground at rest's horizontal stress, unloaded elastically from "
                f"K0_nc by the OCR or POP, would lie outside the clay's yield ellipse down to "
                f"{h:.3g} m (passive, in extension): it is capped at the ellipse there (what "
                f"a plastic nil-step would give); those points yield at the first load")
        return out

    @classmethod
    def _M(cls, soil, depth) -> np.ndarray:
        return np.array([cls.constants(x)["M"] for x in soil.strata])[soil.stratum_of(depth)]

    @classmethod
    def initial_stress(cls, soil, depth) -> np.ndarray:
        sv, sh, _ = cls._at_rest(soil, depth)
        return np.column_stack([-sh, -sv, 0.0 * sv, -sh])

    @classmethod
    def point_law(cls, soil, depth) -> CamClayPoints:
        depth = np.asarray(depth, dtype=float)
        st = soil.at_depth(depth)
        _, _, p_c = cls._at_rest(soil, depth)
        M = cls._M(soil, depth)
        return CamClayPoints(M=M, lambda_star=st["lambda_star"], kappa_star=st["kappa_star"],
                             nu=st["nu"], sigma0=cls.initial_stress(soil, depth),
                             p_c0=np.maximum(p_c, P_MIN), p_min=P_MIN,
                             E_fixed=np.full(len(depth), np.nan))

    @classmethod
    def symmetric_tangent(cls, soil) -> bool:
        return False

    @classmethod
    def scene_problems(cls, scene) -> list[str]:
        """No overturning load, no linear triangles. (The ground at rest is never outside
        its ellipse: a crust's sigma'_h is capped there, :meth:`ground_warnings`.)"""
        out = []
        for k, ld in enumerate((scene.load, *scene.stages)):
            if ld.overturning:
                where = "load" if k == 0 else f"stages[{k}]"
                out.append(f"{where}.overturning_moment, {where}.base_shear: the overturning "
                           f"load is solved as a harmonic about a linear soil's state, not "
                           f"with soil.model = \"cam_clay\"; remove them")
                break
        if scene.mesh.degree == 1:
            out.append("mesh.degree = 1: linear triangles lock under plastic flow at constant "
                       "volume (the critical state); use degree 2 (the default), 3 or 4")
        return out

    @classmethod
    def undrained_strength(cls, soil, depth: float) -> float | None:
        return None


def _passive(sv, p_c, M):
    """The largest sigma'_h on the ellipse at sigma'_v (compression positive): the upper
    root of q^2 / M^2 + p' (p' - p_c) = 0 with p' = (sigma'_v + 2 x) / 3, q = x - sigma'_v."""
    a = 1.0 / M ** 2 + 4.0 / 9.0
    b = -2.0 * sv / M ** 2 + 4.0 * sv / 9.0 - 2.0 * p_c / 3.0
    c = sv ** 2 / M ** 2 + sv ** 2 / 9.0 - sv * p_c / 3.0
    return (-b + np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)


def _sampled(soil, bottom: float) -> np.ndarray:
    """Depths down to ``bottom`` (m) dense near the surface and at the strata's tops and
    the water table, where the ground at rest's stresses kink."""
    tops = [st.depth for st in soil.strata]
    wt = [soil.water_table] if soil.water_table is not None else []
    d = np.concatenate([np.geomspace(1e-4, bottom, 3001), np.linspace(0.0, bottom, 2001)[1:],
                        tops[1:], [t + 1e-9 * (1.0 + t) for t in tops], wt])
    return np.unique(d[(d > 0.0) & (d <= bottom)])


__all__ = ["CamClaySoil", "P_MIN"]
