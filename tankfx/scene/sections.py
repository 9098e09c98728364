"""The scene's sections as frozen dataclasses, in SI units (m, Pa, N/m^3): the soil and its
layers, the plate, the wall, a ringwall, the interface, the load, a consolidation, the domain,
the mesh and the solver; and the load's resultant.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from ..laws.soil_law import ATMOSPHERIC_PRESSURE, WATER_UNIT_WEIGHT, SoilLaw, words
from ..laws.soil_laws import SOIL_LAWS
from .keys import NON_NEGATIVE, POSITIVE, Key, Limit, key

#: Default domain size, in multiples of the foundation radius. The truncation error of the
#: centre settlement falls like 1/R (measured, homogeneous half-space with a fixed far
#: boundary: -0.74 % at 100 a, -0.074 % at 1000 a, -0.0074 % at 10000 a;
#: docs/development/2026-11-26-error-against-time.md, "Truncation of the half-space"). The
#: graded mesh makes the size almost free: going from 1000 a to 10000 a adds 1.5 % to the
#: dofs.
DEFAULT_DOMAIN_FACTOR = 10000.0


#: Default element sizes, in multiples of the foundation radius: at the foundation edge (the
#: stress singularity) and the cap over the near field (6 radii around the centre). Measured
#: on the flexible load (docs/performance.md): with P2 these keep the centre and edge
#: settlements within 0.1 % and sigma_zz on the axis within 1 % up to nu = 0.45.
DEFAULT_EDGE_SIZE = 0.002


DEFAULT_NEAR_SIZE = 0.1


#: A flexible load (no plate: the soil alone decides the error) defaults to P3 on a mesh
#: FLEXIBLE_COARSENING times coarser: measured, largest error 1.5e-3 -> 1.9e-4 (sigma_zz on
#: the axis) at the same whole-process time (docs/performance.md).
FLEXIBLE_DEGREE = 3


FLEXIBLE_COARSENING = 2.0




#: A nonlinear soil's Eq. 18 tolerance (the paper's); its iterations at most are its law's
#: (SoilLaw.max_iterations)
DEFAULT_TOLERANCE = 0.05


#: Above this soil Poisson's ratio the soil is solved in the mixed displacement-pressure
#: (Taylor-Hood) form, chosen automatically: the displacement form's stresses lock (measured
#: on the flexible load: sigma_zz on the axis off by 0.5 % of p at 0.45, 2.6 % at 0.49,
#: 17.6 % at 0.499), and it cannot take 0.5 at all.
MIXED_FROM_NU = 0.45


#: The limits of the Poisson's ratios: a soil's may be 0.5 (incompressible: the mixed form),
#: a shell's not (thin-shell theory), a ringwall's and its fill's are solved in the
#: displacement form
SOIL_POISSON = Limit(-1.0, 0.5)
SOIL_POISSON_WHY = "Poisson's ratio; 0.5: incompressible, e.g. undrained clay"
SHELL_POISSON = Limit(-1.0, 0.5, high_open=True)
SHELL_POISSON_WHY = "Poisson's ratio of a plate or wall: thin-shell theory; use e.g. 0.3"
RING_POISSON = Limit(-1.0, MIXED_FROM_NU)
#: an angle in degrees, [0, 90)
ANGLE = Limit(0.0, 90.0, low_open=False, high_open=True)
EXPONENT_WHY = "0: a modulus independent of confinement; 1: proportional to it"
RF_WHY = "R_f, typically 0.7-0.9"


class SceneError(ValueError):
    """A scene that cannot be run, found before any work.

    Attributes
    ----------
    problems : list of str
        Every problem, each naming the key, the value and the fix; the message lists them.
    """

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        lines = "\n".join(f"  - {p}" for p in self.problems)
        super().__init__(f"the scene has {len(self.problems)} problem(s):\n{lines}")


#: Duncan & Chang's constants, declared once for [soil] and each [[soil.layers]] table
#: (a layer's p_a is the soil's): their keys' units, limits, defaults and meanings, where
#: "{its}" is the soil's or the layer's
_DC = 'for model = "duncan_chang"'


def for_models(name: str) -> str:
    """'for model = "a" or "b"': the laws that take the [soil] key ``name`` (the registry's
    word, so that a new law's keys say it)."""
    return f"for model = {words(SOIL_LAWS.values(), lambda law: name in law.keys)}"


_DUNCAN_CHANG_KEYS: dict[str, Key] = {
    "modulus_number": Key(
        unit="-", limit=POSITIVE,
        meaning=f"{{its}} modulus number K, {_DC} (required): a cell's initial tangent modulus "
                "is K p_a (sigma_3 / p_a)^n, n the `modulus_exponent` and sigma_3 the cell's "
                "minor principal compression (geostatic plus the tank's, at least 0.01 p_a); "
                "K p_a is {its} E, which may then be left out"),
    "modulus_exponent": Key(
        unit="-", limit=Limit(0.0, 1.0, False), why=EXPONENT_WHY,
        meaning=f"{{its}} modulus exponent n, {_DC} (required): the power of the confinement "
                "in the initial modulus K p_a (sigma_3 / p_a)^n, K the `modulus_number`; 0: a "
                "modulus independent of the confinement, 1: proportional to it (about 0.5 is "
                "usual)"),
    "failure_ratio": Key(
        unit="-", limit=Limit(0.0, 1.0), why=RF_WHY, default_doc="0.9",
        meaning=f"{{its}} failure ratio R_f, {_DC}: Kondner's ultimate deviator 1/b is q_f / "
                "R_f, q_f the Mohr-Coulomb strength of `cohesion` and `friction_angle`; a cell "
                "past q_f is perfectly plastic (R_f typically 0.7-0.9)"),
    "cohesion": Key(
        unit="Pa", limit=NON_NEGATIVE, default_doc="0",
        meaning="{its} cohesion c, {for_models}: with `friction_angle` phi it makes the "
                "Mohr-Coulomb strength q_f = (2 c cos phi + 2 sigma_3 sin phi) / (1 - sin phi) "
                "at confinement sigma_3 (with phi = 0, Tresca's undrained strength s_u, q_f = "
                "2 s_u); c or phi must be > 0"),
    "friction_angle": Key(
        unit="deg", limit=ANGLE, why="degrees", default_doc="0",
        meaning="{its} friction angle phi (degrees), {for_models}: with `cohesion` c it makes "
                "the strength q_f, which grows with the confinement as 2 sigma_3 sin phi / (1 - "
                "sin phi); c or phi must be > 0; `K0` defaults to 1 - sin phi; 0 is Tresca's "
                "soil, and mohr_coulomb takes less than 60"),
    "unit_weight": Key(
        unit="N/m^3", limit=NON_NEGATIVE, default_doc="required (duncan_chang); 0",
        meaning="{its} unit weight gamma, {for_models}: the geostatic vertical stress at a "
                "depth is the weight of the strata above it (less the pore pressure below the "
                "soil's `water_table`, where gamma is the saturated unit weight), the "
                "horizontal `K0` times it; mohr_coulomb's soil carries its weight as a load "
                "from that state (0: weightless)"),
    "K0": Key(
        unit="-", limit=POSITIVE, default_doc="1 - sin(phi)",
        meaning="{its} coefficient of earth pressure at rest K0, {for_models}: the geostatic "
                "horizontal stress is K0 times the vertical one (from `unit_weight`); by "
                "default Jaky's 1 - sin phi of {its} `friction_angle`; mohr_coulomb refuses a "
                "K0 that puts the ground at rest outside its yield surface"),
    "dilation_angle": Key(
        unit="deg", limit=ANGLE, why="degrees", default_doc="0",
        meaning="{its} dilation angle psi (degrees), {for_models}: the plastic flow's volume "
                "change, (sigma_1 - sigma_3) + (sigma_1 + sigma_3) sin psi its potential; "
                "at most `friction_angle` (psi = phi: associated flow); 0: no volume change"),
    "tensile_strength": Key(
        unit="Pa", limit=NON_NEGATIVE, default_doc="none (the cone's apex, c cot phi)",
        meaning="{its} tensile strength t, {for_models}: a Rankine cut-off, the largest "
                "principal stress at most t (tension positive); beyond the Mohr-Coulomb "
                "apex c cot phi it never acts"),
    "cohesion_gradient": Key(
        unit="Pa/m", limit=NON_NEGATIVE, default_doc="0",
        meaning="{its} cohesion's growth with depth k, {for_models}: c = `cohesion` + k (h - "
                "top), h the depth, top the stratum's top (0 for the surface soil): a normally "
                "consolidated clay's undrained strength s_u0 + k z"),
}


def duncan_chang_key(name: str, layer: bool = False) -> Any:
    """The field of one of Duncan & Chang's constants (None unless given), as declared in
    _DUNCAN_CHANG_KEYS, its meaning the layer's or the soil's."""
    spec = _DUNCAN_CHANG_KEYS[name]
    values = {f.name: getattr(spec, f.name) for f in fields(spec)}
    its = "the layer's" if layer else "the soil's"
    return key(None, **(values | {"meaning": spec.meaning.format(its=its,
                                                                  for_models=for_models(name))}))


def with_law_keys(layer: bool):
    """A class decorator, before ``dataclass``: every soil law's ``own_keys`` (those of its
    ``layer_keys`` for a layer's table) as fields of the section, None unless given, so
    that a new law declares its keys in its own module."""
    def add(cls):
        for law in SOIL_LAWS.values():
            for name, spec in law.own_keys.items():
                if name in cls.__annotations__ or (layer and name not in law.layer_keys):
                    continue
                spec = dict(spec)
                kind = spec.pop("type")
                default = spec.pop("default", None)
                if "meaning" in spec:
                    spec["meaning"] = spec["meaning"].replace(
                        "{its}", "the layer's" if layer else "the soil's")
                if isinstance(spec.get("limit"), tuple):
                    # (a law below the scene gives its limit as Limit's arguments)
                    spec["limit"] = Limit(*spec["limit"])
                cls.__annotations__[name] = f"{kind.__name__} | None"
                doc = spec.pop("default_doc", f"{default!r}".replace("'", '"'))
                setattr(cls, name, key(None, **spec, default_doc=doc))
        return cls
    return add


@dataclass(frozen=True)
@with_law_keys(layer=True)
class Layer:
    """A stratum of the ground from ``depth`` down to the next layer's top (or to the rigid
    base): E(h) = E (1 + E_gradient (h - depth)) within it."""

    depth: float = key(unit="m", required=True, limit=POSITIVE,
                       meaning="depth of the layer's top below the ground surface (it may lie "
                               "above, on or below an embedded plate's underside; each deeper than "
                               "the last, above `domain.depth`); the tops are lines of the mesh")
    E: float = key(unit="Pa", limit=POSITIVE, default_doc="required (linear soil)",
                   meaning="the layer's Young's modulus at its top, growing below it as E (1 + "
                           "`E_gradient` (h - depth)); a hyperbolic soil's layer has 1/"
                           "`hyperbolic_a` there, Duncan & Chang's K p_a, and may leave it out")
    nu: float = key(unit="-", required=True, limit=SOIL_POISSON, why=SOIL_POISSON_WHY,
                    meaning="the layer's Poisson's ratio, up to 0.5: a layer above 0.45 is solved "
                            "in the mixed form with a pressure of its own, the others in the "
                            "displacement form (Duncan & Chang's soil: every layer mixed, nu > 0); "
                            "with a `[consolidation]`, its drained nu' <= 0.45")
    E_gradient: float = key(0.0, unit="1/m", limit=NON_NEGATIVE,
                            meaning="the layer's lambda: its modulus grows from `E` at its top as "
                                    "E (1 + E_gradient (h - depth)), h the depth below the ground "
                                    "(a hyperbolic layer's 1/a too); not with model = "
                                    "\"duncan_chang\"")
    hyperbolic_a: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="the layer's Kondner a, for model = \"hyperbolic\" "
                                             "(required, with `hyperbolic_b`): 1/a is its initial "
                                             "tangent modulus at its top (its `E`, which may then "
                                             "be left out), growing with `E_gradient`")
    hyperbolic_b: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="the layer's Kondner b, for model = \"hyperbolic\" "
                                             "(required, with `hyperbolic_a`): 1/b is its ultimate "
                                             "deviator stress, the same at every depth in it")
    # Duncan & Chang's constants of the layer (model = "duncan_chang"; p_a is the soil's)
    modulus_number: float | None = duncan_chang_key("modulus_number", layer=True)
    modulus_exponent: float | None = duncan_chang_key("modulus_exponent", layer=True)
    failure_ratio: float | None = duncan_chang_key("failure_ratio", layer=True)
    cohesion: float | None = duncan_chang_key("cohesion", layer=True)
    friction_angle: float | None = duncan_chang_key("friction_angle", layer=True)
    unit_weight: float | None = duncan_chang_key("unit_weight", layer=True)
    K0: float | None = duncan_chang_key("K0", layer=True)
    dilation_angle: float | None = duncan_chang_key("dilation_angle", layer=True)
    tensile_strength: float | None = duncan_chang_key("tensile_strength", layer=True)
    cohesion_gradient: float | None = duncan_chang_key("cohesion_gradient", layer=True)
    permeability: float | None = key(None, unit="m/s", limit=POSITIVE,
                                     default_doc="[consolidation] permeability",
                                     meaning="the layer's own Darcy k in a `[consolidation]` (e.g. "
                                             "a sand layer that drains a clay: a large k); the pore"
                                             " pressure and its flux are continuous across the "
                                             "layers' tops")


#: The [soil] (or layer) keys that set its E (1/a, K p_a): a change of one of them drops
#: the E resolved from the old value (Scene.with_changes, sweep axes)
E_FROM_KEYS = tuple(dict.fromkeys(k for law in SOIL_LAWS.values() for k in law.E_keys))


#: the constants of its law that each stratum has, of every law
STRATUM_LAW_KEYS = tuple(dict.fromkeys(k for law in SOIL_LAWS.values()
                                       for k in law.layer_keys))


@dataclass(frozen=True)
@with_law_keys(layer=False)
class Soil:
    """The ground: the surface soil, from the ground surface down to the first
    ``[[soil.layers]]`` table's top (the whole ground without layers), its model, which its
    layers share, and the model's settings."""

    E: float = key(unit="Pa", limit=POSITIVE, default_doc="required (linear soil)",
                   meaning="E_s, the soil's Young's modulus at the ground surface (the E_s of Eqs. "
                           "21-23); a hyperbolic soil's is 1/`hyperbolic_a`, Duncan & Chang's "
                           "`modulus_number` x `atmospheric_pressure`, and may be left out")
    nu: float = key(unit="-", required=True, limit=SOIL_POISSON, why=SOIL_POISSON_WHY,
                    meaning="nu_s, the soil's Poisson's ratio: above 0.45 the soil is solved in "
                            "the mixed displacement-pressure form (chosen automatically), 0.5 is "
                            "incompressible (undrained); Duncan & Chang's soil is always mixed "
                            "(nu > 0); with a `[consolidation]`, the drained nu' <= 0.45")
    E_gradient: float = key(0.0, unit="1/m", limit=NON_NEGATIVE,
                            meaning="lambda, the soil's growth of modulus with depth: E(h) = E_s "
                                    "(1 + lambda h), h the depth below the ground surface (a "
                                    "hyperbolic soil's 1/a too); not with model = "
                                    "\"duncan_chang\"")
    model: str = key("linear", choices=tuple(SOIL_LAWS),
                     meaning="the soil's stress-strain law: " + "; ".join(
                         f"\"{word}\", {law.title}" for word, law in SOIL_LAWS.items()))
    hyperbolic_a: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="Kondner's a, for model = \"hyperbolic\" (required, "
                                             "with `hyperbolic_b`): 1/a is the initial tangent "
                                             "modulus at the surface (E_s), scaled by 1 + lambda h "
                                             "with depth; the paper's a = 0.00021 1/kPa is 2.1e-7 "
                                             "1/Pa")
    hyperbolic_b: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="Kondner's b, for model = \"hyperbolic\" (required, "
                                             "with `hyperbolic_a`): 1/b is the ultimate deviator "
                                             "stress, the same at every depth; the paper's b = 0.01"
                                             " 1/kPa is 1e-5 1/Pa")
    tolerance: float | None = key(None, unit="-", limit=Limit(0.0, 1.0, high_open=True),
                                  why="the relative deviator misfit of Eq. 18; the paper's "
                                      "0.05 is the default",
                                  default_doc=f"{DEFAULT_TOLERANCE:g} (nonlinear soil)",
                                  meaning="a nonlinear soil's Eq. 18 tolerance: the secant "
                                          "iteration ends when no cell's relative deviator misfit "
                                          "exceeds it and the displacement update is small; at "
                                          "most `max_iterations` iterations")
    max_iterations: int | None = key(None, unit="-", limit=Limit(1, low_open=False),
                                     default_doc=", ".join(
                                         f"{law.max_iterations} ({word})" for word, law in
                                         SOIL_LAWS.items() if law.max_iterations),
                                     meaning="a nonlinear soil's secant (Picard) iterations at "
                                             "most, to reach the `tolerance`; not converged by then"
                                             " is an error (Duncan & Chang's failed zones settle "
                                             "slowly: 10-64 iterations measured); for model = "
                                             "\"mohr_coulomb\" the Newton iterations of one load "
                                             "step, after which the step is halved")
    # Duncan & Chang's soil (model = "duncan_chang"): Kondner's law with the initial modulus
    # K p_a (sigma_3 / p_a)^n and the ultimate deviator (Mohr-Coulomb strength) / R_f of
    # each cell's confining stress: geostatic (unit weight, K0) plus the tank's
    modulus_number: float | None = duncan_chang_key("modulus_number")
    modulus_exponent: float | None = duncan_chang_key("modulus_exponent")
    failure_ratio: float | None = duncan_chang_key("failure_ratio")
    cohesion: float | None = duncan_chang_key("cohesion")
    friction_angle: float | None = duncan_chang_key("friction_angle")
    unit_weight: float | None = duncan_chang_key("unit_weight")
    K0: float | None = duncan_chang_key("K0")
    dilation_angle: float | None = duncan_chang_key("dilation_angle")
    tensile_strength: float | None = duncan_chang_key("tensile_strength")
    cohesion_gradient: float | None = duncan_chang_key("cohesion_gradient")
    atmospheric_pressure: float | None = key(None, unit="Pa", limit=POSITIVE,
                                             default_doc=f"{ATMOSPHERIC_PRESSURE:g}",
                                             meaning=f"p_a, {_DC}: the reference pressure of the"
                                                     " initial modulus K p_a (sigma_3 / p_a)^n "
                                                     "and of the least confinement, 0.01 p_a "
                                                     "(E = K p_a); one for the soil and all its "
                                                     "layers")
    #: the confinement is effective below it: the geostatic stress less the hydrostatic
    #: pore pressure
    water_table: float | None = key(None, unit="m", limit=NON_NEGATIVE,
                                    default_doc="below everything",
                                    meaning="the water table's depth below the ground surface, "
                                            f"{for_models('water_table')}: below it the stresses are effective, the "
                                            "geostatic stress less the pore pressure gamma_w (h - "
                                            "water_table), gamma_w the `water_unit_weight`; the "
                                            "strata there take their saturated unit weights")
    water_unit_weight: float | None = key(None, unit="N/m^3", limit=POSITIVE,
                                          default_doc=f"{WATER_UNIT_WEIGHT:g} (with a "
                                                      f"water_table)",
                                          meaning=f"gamma_w, the pore water's unit weight, {for_models('water_unit_weight')} "
                                                  "with a `water_table`: the pore pressure below "
                                                  "the table is gamma_w (h - water_table); each "
                                                  "stratum's unit weight there must exceed it")
    #: the strata below the surface soil (which the keys above describe, from the surface
    #: down to the first layer's top), top down
    layers: tuple[Layer, ...] = ()
    #: E_ur / E_i of a nonlinear soil along a load path: a cell whose strain falls below the
    #: largest it has had unloads (and reloads) linearly with E_ur = this times its initial
    #: modulus (Duncan & Chang's: at its current confinement, K_ur = this x K) and keeps its
    #: permanent strain; None: the paper's nonlinear elastic secant law, which unloads
    #: along its loading curve
    unloading_modulus_ratio: float | None = key(
        None, unit="-", limit=Limit(1.0, low_open=False), custom=True,
        default_doc="none: unloads along the loading curve",
        meaning="E_ur / E_i of a nonlinear soil (\"hyperbolic\" or \"duncan_chang\") along "
                "`[[stages]]`: below its most loaded state so far each cell unloads and reloads "
                "along a line of E_ur = this times its initial modulus (Duncan & Chang's K_ur = "
                "this x K, at its current confinement), keeping its permanent strain; 1 is "
                "Masing's rule, K_ur / K is 1.2-3 in Duncan & Chang's tables. It holds for every "
                "stratum, lets a stage take the load off entirely, and is refused with a "
                "`[consolidation]`")

    @property
    def strata(self) -> tuple[Layer, ...]:
        """Every stratum from the surface down, the surface soil as the first (depth 0)."""
        top = Layer(depth=0.0, E=self.E, nu=self.nu, E_gradient=self.E_gradient,
                    **{k: getattr(self, k) for k in STRATUM_LAW_KEYS})
        return (top, *self.layers)

    @property
    def law(self) -> type[SoilLaw]:
        """The soil's law (:data:`tankfx.laws.soil_laws.SOIL_LAWS` of its ``model``)."""
        return SOIL_LAWS[self.model]

    @property
    def mixed_strata(self) -> list[int]:
        """Indices into :attr:`strata` of those solved in the mixed u-p form: nu >
        MIXED_FROM_NU, and every stratum of a law that is always mixed (Duncan & Chang's: a
        failed cell keeps its bulk modulus while its secant shear modulus falls: nu ->
        0.5)."""
        if self.law.displacement_form_only:
            return []
        return [i for i, st in enumerate(self.strata)
                if self.law.all_mixed or st.nu > MIXED_FROM_NU]

    @property
    def max_nu(self) -> float:
        """The largest Poisson's ratio of any stratum (it decides the mixed form)."""
        return max(st.nu for st in self.strata)

    def stratum_of(self, depth) -> np.ndarray:
        """Index into :attr:`strata` of the stratum at each depth (m; a depth on a layer's
        top belongs to that layer; above the ground, the surface soil)."""
        tops = np.array([st.depth for st in self.strata])
        return np.maximum(np.searchsorted(tops, np.asarray(depth, dtype=float),
                                          side="right") - 1, 0)

    def at_depth(self, depth) -> dict[str, np.ndarray]:
        """Per depth (m, arrays): the stratum's top ``top``, its ``E_top``, ``E_gradient``,
        ``nu``, Kondner's ``hyperbolic_a`` and ``hyperbolic_b`` (hyperbolic model), Duncan &
        Chang's constants (STRATUM_LAW_KEYS; 0 where the model has none), and the
        initial modulus ``E`` = E_top (1 + E_gradient (h - top)) (h clipped at the ground)."""
        idx = self.stratum_of(depth)
        out = {key: np.array([getattr(st, key) or 0.0 for st in self.strata])[idx]
               for key in ("E_gradient", "nu", *STRATUM_LAW_KEYS)}
        out["top"] = np.array([st.depth for st in self.strata])[idx]
        out["E_top"] = np.array([st.E for st in self.strata])[idx]
        h = np.maximum(np.asarray(depth, dtype=float), 0.0)
        out["E"] = out["E_top"] * (1.0 + out["E_gradient"] * (h - out["top"]))
        return out


@dataclass(frozen=True)
class Plate:
    radius: float = key(unit="m", required=True, limit=POSITIVE,
                        meaning="a_p, the plate's radius: the foundation's radius a, in which the "
                                "domain's and the mesh's defaults are given")
    thickness: float = key(unit="m", limit=POSITIVE, default_doc="from Kp (Eq. 21)",
                           meaning="t_p, the plate's thickness (with an annular ring, the floor's"
                                   " inside it), above its flat underside; give it or `Kp`, not "
                                   "both")
    E: float = key(unit="Pa", required=True, limit=POSITIVE,
                   meaning="E_p, the plate's Young's modulus: the plate is a thin elastic shell "
                           "(Kirchhoff), rigidly joined to a wall; with its `nu`")
    nu: float = key(unit="-", required=True, limit=SHELL_POISSON, why=SHELL_POISSON_WHY,
                    meaning="the plate's Poisson's ratio, below 0.5 (thin-shell theory); with its "
                            "`E`")
    #: Eq. 21's relative rigidity where the scene gives it instead of the thickness: held
    #: (the thickness follows) when the soil changes (Scene.with_changes, a sweep's case)
    Kp: float | None = key(None, unit="-", limit=POSITIVE, default_doc="-",
                           meaning="the plate's relative rigidity Kp = (1 - nu_s^2)(E_p / E_s)(t_p "
                                   "/ a_p)^3 (Eq. 21, E_s and nu_s the soil's at the surface), "
                                   "given instead of `thickness`, which then follows from it (and "
                                   "changes with the soil, Kp held)")
    embedment: float = key(0.0, unit="m", limit=NON_NEGATIVE,
                           meaning="depth of the plate's underside (and the wall's foot) below the "
                                   "ground; the soil above it, inside r <= a_p, is excavated; 0: a "
                                   "tank on the surface")
    unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                             meaning="the plate's unit weight (steel's is about 77e3): with `load."
                                     "self_weight = true` its weight, unit_weight x thickness per "
                                     "unit area, loads the plate")
    #: a ring of another thickness along the edge, under the wall (an API 650 tank's
    #: annular bottom plate, or a thickened edge). The underside stays flat; Kp is the
    #: floor's.
    annular_width: float = key(0.0, unit="m", limit=POSITIVE, default_doc="0: none",
                               meaning="the width, inward from the plate's edge, of a ring of "
                                       "another thickness under the wall (an API 650 tank's "
                                       "annular bottom plate, or a thickened edge), given with "
                                       "`annular_thickness`; the ring must reach inside the "
                                       "wall's radius a_t, so that the wall stands on it")
    annular_thickness: float | None = key(None, unit="m", limit=POSITIVE,
                                          meaning="the thickness of the annular ring of "
                                                  "`annular_width`, given with it; the underside "
                                                  "stays flat, and `thickness` (and Kp) are then "
                                                  "the floor's inside the ring")

    @property
    def ring_inner_radius(self) -> float:
        """Where the annular ring begins, m (the plate's radius when there is none)."""
        return self.radius - self.annular_width

    def thickness_at(self, r):
        """Thickness at radii ``r``, m (the ring's from its inner edge outward)."""
        r = np.asarray(r, dtype=float)
        if not self.annular_width:
            return np.full(r.shape, self.thickness)
        return np.where(r > self.ring_inner_radius, self.annular_thickness, self.thickness)

    @property
    def volume(self) -> float:
        """m^3 (for its self-weight)."""
        b = self.ring_inner_radius
        ring = (self.annular_thickness or 0.0) * math.pi * (self.radius**2 - b**2)
        return self.thickness * math.pi * b**2 + ring


@dataclass(frozen=True)
class Wall:
    radius: float = key(unit="m", required=True, limit=POSITIVE,
                        meaning="a_t, the radius of the wall's outer face (its mid-surface lies "
                                "half a thickness inside), at most a_p: at the plate's edge, or "
                                "inside it (a T-joint)")
    thickness: float = key(unit="m", limit=POSITIVE, default_doc="from Kt (Eq. 22) or courses",
                           meaning="t_t, the wall's thickness, the same over its height; give it, "
                                   "`Kt` or `courses`, one of them")
    height: float = key(unit="m", limit=POSITIVE, default_doc="the courses' sum",
                        meaning="H, the wall's height from the plate's underside (the wall's foot) "
                                "to its top edge, which carries the roof")
    E: float = key(unit="Pa", required=True, limit=POSITIVE,
                   meaning="E_t, the wall's Young's modulus: a thin elastic shell, rigidly joined "
                           "to the plate; with its `nu`")
    nu: float = key(unit="-", required=True, limit=SHELL_POISSON, why=SHELL_POISSON_WHY,
                    meaning="the wall's Poisson's ratio, below 0.5 (thin-shell theory); with its "
                            "`E`")
    #: Eq. 22's relative rigidity where the scene gives it instead of the thickness: held
    #: (the thickness follows) when the soil changes
    Kt: float | None = key(None, unit="-", limit=POSITIVE, default_doc="-",
                           meaning="the wall's relative rigidity Kt = (1 - nu_s^2)(E_t / E_s)(t_t "
                                   "/ a_t)^3 (Eq. 22, E_s and nu_s the soil's at the surface), "
                                   "given instead of `thickness`, which then follows from it (and "
                                   "changes with the soil, Kt held); not with `courses`")
    unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                             meaning="the wall's unit weight (steel's is about 77e3): with `load."
                                     "self_weight = true` its weight, unit_weight x thickness per "
                                     "unit area, course by course, loads the wall")
    #: the courses of a wall whose thickness steps, (height, thickness) in m from the bottom
    #: up, their outer faces flush (empty: one course of ``thickness``, the paper's wall)
    courses: tuple[tuple[float, float], ...] = key(
        (), unit="m", kind=list, custom=True,
        meaning="a wall whose thickness steps, instead of `thickness` and `Kt`: `courses = "
                "[{height = 2.4, thickness = 0.013}, ...]` from the bottom course up, their outer "
                "faces flush; `height` may then be left out (it is their sum; given, it must "
                "equal it)")

    @property
    def course_table(self) -> list[tuple[float, float, float]]:
        """(bottom, top, thickness) of each course, heights above the wall's foot, m."""
        if not self.courses:
            return [(0.0, self.height, self.thickness)]
        out, z = [], 0.0
        for h, t in self.courses:
            out.append((z, z + h, t))
            z += h
        return out

    def thickness_at(self, height):
        """Thickness at ``height`` above the foot, m (a joint belongs to the course below)."""
        table = self.course_table
        tops = np.array([top for _, top, _ in table[:-1]])
        return np.array([t for *_, t in table])[np.searchsorted(tops, np.asarray(height))]

    @property
    def volume(self) -> float:
        """m^3 (for its self-weight)."""
        return 2 * math.pi * self.radius * sum((top - bottom) * t
                                               for bottom, top, t in self.course_table)


@dataclass(frozen=True)
class Ringwall:
    """A concrete ringwall under the wall: an annulus of another, linear elastic material
    in the ground, from the plate's underside down ``depth`` and from ``inner_radius`` to
    ``outer_radius`` (m), bonded to the soil around it; the plate rests on it and on the
    soil (or a compacted fill of its own, ``fill_E``) inside it, through the same
    interface."""

    inner_radius: float = key(unit="m", required=True, limit=NON_NEGATIVE,
                              meaning="the ringwall's inner radius, less than the wall's a_t "
                                      "(inner_radius < a_t <= `outer_radius`: the wall stands on "
                                      "the ring); 0: a solid disc, with no inside for a fill")
    outer_radius: float = key(unit="m", required=True, limit=POSITIVE,
                              meaning="the ringwall's outer radius, at or beyond the wall's a_t "
                                      "and within half the domain's radius; with `inner_radius`, "
                                      "the ring's width")
    depth: float = key(unit="m", required=True, limit=POSITIVE,
                       meaning="the ringwall's depth below the plate's underside (it must end "
                               "above the rigid base); a fill inside it reaches as deep")
    E: float = key(unit="Pa", required=True, limit=POSITIVE,
                   meaning="the ringwall's Young's modulus (concrete's about 30e9), linear elastic "
                           "on any soil model (a nonlinear soil's iteration leaves it at this "
                           "modulus); with its `nu`")
    nu: float = key(0.2, unit="-", limit=RING_POISSON, why="concrete's is about 0.2",
                    meaning="the ringwall's Poisson's ratio, at most 0.45: it is solved in the "
                            "displacement form, also in a mixed soil; with its `E`")
    #: its weight in excess of the soil it replaces (the soil's own weight is the ground's
    #: initial state, not a load here)
    unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                             meaning="with `load.self_weight = true`, the ringwall's unit weight "
                                     "in excess of the soil it replaces (the soil's own weight is "
                                     "the ground's initial state, not a load): e.g. 24e3 - 18e3 = "
                                     "6e3; it loads the ground, not the interface")
    #: a compacted fill inside the ring, from the plate's underside to the ring's depth
    #: (linear elastic)
    fill_E: float | None = key(None, unit="Pa", limit=POSITIVE, default_doc="none: the soil",
                               meaning="the Young's modulus of a compacted fill inside the ring, "
                                       "from the plate's underside to the ring's `depth`, linear "
                                       "elastic in place of the soil there; with `fill_nu`; needs "
                                       "inner_radius > 0")
    fill_nu: float = key(0.3, unit="-", limit=RING_POISSON, why="e.g. 0.3",
                         meaning="the Poisson's ratio of the fill of `fill_E`, at most 0.45 (the "
                                 "displacement form); only with `fill_E`")

    @property
    def volume(self) -> float:
        """m^3."""
        return math.pi * (self.outer_radius**2 - self.inner_radius**2) * self.depth

    def _band(self, r, z, embedment: float, r_min: float, r_max: float):
        """Points (r, z) strictly between the radii, from the ring's top (included: the
        plate's underside at -embedment) to its depth."""
        r, z = np.asarray(r), np.asarray(z)
        top = -embedment
        return (r > r_min) & (r < r_max) & (z < top + 1e-9 * self.outer_radius) & \
            (z > top - self.depth)

    def holds(self, r, z, embedment: float):
        """Whether points (r, z) (m; z up from the ground surface) lie inside the ringwall
        or on its top (the plate's underside at -embedment)."""
        return self._band(r, z, embedment, self.inner_radius, self.outer_radius)

    def fill_holds(self, r, z, embedment: float):
        """Whether points (r, z) lie in the fill inside the ring or on its top (never
        without a fill)."""
        return (self.fill_E is not None) & self._band(r, z, embedment, -np.inf,
                                                      self.inner_radius)


#: the interface condition whose elements take states (the soil model of the same word is
#: another thing: an elastoplastic soil)
STATES_CONDITION = "mohr_coulomb"


@dataclass(frozen=True)
class Interface:
    """The contact between the structure (the plate's underside, and an embedded wall's
    outer face) and the soil (or a ringwall): a zero-thickness penalty layer."""

    condition: str = key("bonded", choices=("bonded", "smooth", "mohr_coulomb"),
                         meaning="the interface's law: \"bonded\" (no slip, takes tension), "
                                 "\"smooth\" (no shear, takes tension) or \"mohr_coulomb\" (Eqs. "
                                 "6-16: stick, slip at c + sigma_n tan phi, separate, rebond)")
    cohesion: float = key(0.0, unit="Pa", limit=NON_NEGATIVE,
                          meaning="c, the interface's cohesion (adhesion) in Eq. 13's shear "
                                  "strength c + sigma_n tan phi, with `tan_phi`; \"mohr_coulomb\" "
                                  "only")
    tan_phi: float | None = key(None, unit="-", limit=NON_NEGATIVE,
                                meaning="tan phi, the interface's friction coefficient in Eq. 13's"
                                        " shear strength c + sigma_n tan phi, with `cohesion`; "
                                        "\"mohr_coulomb\" only, and required there (or "
                                        "`friction_angle`); the paper's limits are tan phi = 10 "
                                        "(bonded) and 0.001 (smooth)")
    normal_stiffness: float | None = key(None, unit="Pa/m", limit=POSITIVE,
                                         default_doc="1e3 E / h",
                                         meaning="E_nn of Eq. 5, the interface's normal penalty "
                                                 "stiffness: normal stress per metre of the "
                                                 "soil-structure gap; by default 1e3 times the "
                                                 "soil's (or ringwall's) modulus at the facet "
                                                 "over the element length h, whose compliance is "
                                                 "then h / (1000 a) of the foundation's")
    shear_stiffness: float | None = key(None, unit="Pa/m", limit=POSITIVE,
                                        default_doc="normal_stiffness",
                                        meaning="E_ss of Eq. 5, the interface's shear penalty "
                                                "stiffness while it sticks: shear stress per metre "
                                                "of slip; by default the `normal_stiffness`; a "
                                                "smooth interface has none")
    #: what a cycling Mohr-Coulomb active set gets: "hold" its alternating elements in the
    #: weaker state and go on (reported), or "stop" with the history
    on_cycle: str = key("hold", choices=("hold", "stop"),
                        meaning="a cycling Mohr-Coulomb active set: `\"hold\"` the alternating "
                                "elements in the weaker state and go on (reported as "
                                "`frozen_elements`), or `\"stop\"` with the history")
    #: where a Mohr-Coulomb state lives: "element" (the paper's Eqs. 11-12: one state per
    #: interface element, from its average jump) or "node" (one per node of the soil's trace,
    #: at the Gauss-Lobatto points of each facet, which then integrate the interface)
    states: str = key("element", choices=("element", "node"),
                      meaning="where a Mohr-Coulomb state lives: `\"element\"` (the paper's Eqs. "
                              "11-12: one per interface element, from its average jump) or "
                              "`\"node\"` (one per node of the soil's trace, at the Gauss-Lobatto "
                              "points that then integrate the interface; agrees with the element "
                              "states to 0.3 %, in 1-6 times their solves; a node that changes "
                              "state 4 times is held in the weaker state: see Limitations)")

    @property
    def has_states(self) -> bool:
        """Whether its elements take states (stick, slip, separation: the Mohr-Coulomb
        interface of Eqs. 6-16; not the soil model of the same name)."""
        return self.condition == STATES_CONDITION


#: The keys a scene file may give instead of a field: a friction angle for tan phi
ALTERNATIVE_KEYS: dict[str, dict[str, Key]] = {
    "interface": {"friction_angle": Key(unit="deg", limit=ANGLE, why="degrees", default_doc="-",
                                        meaning="phi, the interface's friction angle in "
                                                "degrees, given instead of `tan_phi` (which is "
                                                "then tan phi); \"mohr_coulomb\" only")},
}


#: a load's amounts, which a stage's first step starts from zero (a unit weight is no amount)
LOAD_AMOUNTS = ("pressure", "liquid_height", "roof_weight", "gas_pressure",
                "overturning_moment", "base_shear")


@dataclass(frozen=True)
class Load:
    pressure: float = key(0.0, unit="Pa",
                          meaning="p, a uniform downward pressure (Eq. 23's p): on the whole plate,"
                                  " or without a plate on r <= `load_radius` (there >= 0); "
                                  "negative (upward) only on a plate, and a Mohr-Coulomb "
                                  "interface refuses a net upward load")
    load_radius: float | None = key(None, unit="m", limit=POSITIVE,
                                    default_doc="the plate's radius",
                                    meaning="a, the radius of a flexible load (no `[plate]`): the "
                                            "`pressure` acts on r <= load_radius; required without "
                                            "a plate; with one, it is the plate's radius")
    liquid_unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                                    meaning="gamma, the unit weight of the liquid in the tank "
                                            "(water's 9810), filled to `liquid_height` h: gamma h "
                                            "on the floor inside the wall (r < a_t), gamma (h - z) "
                                            "outward on the wall, z the height above its foot")
    liquid_height: float = key(0.0, unit="m", limit=NON_NEGATIVE,
                               meaning="h, the liquid's height above the plate's underside (the "
                                       "wall's foot), at most the wall's height; its unit weight is"
                                       " `liquid_unit_weight`; needs a wall")
    self_weight: bool = key(False, meaning="whether the structure's own weight is a load: the "
                                           "plate's and the wall's `unit_weight` x thickness "
                                           "(course by course and ring by ring), and a ringwall's "
                                           "excess weight; false: weightless")
    #: N: the roof's weight and what it carries (snow, equipment), borne by the wall's top
    #: edge (a ring load of roof_weight / (2 pi a_t) N/m)
    roof_weight: float = key(0.0, unit="N", limit=NON_NEGATIVE,
                             meaning="the roof's weight and what it carries (snow, equipment), "
                                     "borne by the wall's top edge: a ring load roof_weight / (2 pi"
                                     " a_t) N/m down (needs a wall)")
    #: Pa: a gas (vapour) pressure in the closed tank, above the liquid: on the floor (down),
    #: the wall (outward) and the roof, which carries it to the wall's top (up); no net
    #: vertical load on the foundation. Negative: a vacuum
    gas_pressure: float = key(0.0, unit="Pa",
                              meaning="a gas (vapour) pressure in the closed tank above the liquid:"
                                      " on the floor inside the wall (down), on the whole wall "
                                      "(outward) and on the roof, which carries p pi a_t^2 to the "
                                      "wall's top (up): no net vertical load; it adds to Eq. 23's "
                                      "p; negative for a vacuum (the shell's buckling is not "
                                      "modelled); needs a wall")
    #: N m: an overturning moment (wind, earthquake) about the plate's underside at the
    #: axis, pressing the side theta = 0 down; with a wall it reaches the foundation through
    #: the wall's foot (API 650 Annex E's ringwall moment). Solved as the first Fourier
    #: harmonic about the axisymmetric state (tankfx.model.overturning)
    overturning_moment: float = key(0.0, unit="N m",
                                    meaning="M, an overturning moment (wind, earthquake: API 650 "
                                            "Annex E's ringwall moment M_rw) about the plate's "
                                            "underside at the axis, pressing the side theta = 0 "
                                            "down, with its `base_shear` V: a wall takes both at "
                                            "its top edge and passes exactly V and M to the "
                                            "foundation at its foot; without a wall M is a pressure"
                                            " 4 M r cos theta / (pi a^4) on the plate. Solved as "
                                            "the first Fourier harmonic about the stage's converged"
                                            " state and superposed (`overturning` in the results); "
                                            "needs a plate")
    #: N: the horizontal force that comes with it (towards theta = 0), carried by the wall
    #: (or the plate) to the interface
    base_shear: float = key(0.0, unit="N",
                            meaning="V, the horizontal force that comes with the "
                                    "`overturning_moment`, towards theta = 0: on the wall's top "
                                    "edge as a thin tube's shear flow -V sin theta / (pi a_t), or "
                                    "without a wall as a uniform traction on the plate; needs a "
                                    "plate")

    @property
    def overturning(self) -> bool:
        """Whether the load has a first-harmonic part (an overturning moment or shear)."""
        return bool(self.overturning_moment or self.base_shear)

    def held(self) -> "Load":
        """This load with its amounts (LOAD_AMOUNTS) zero: what is held while the variable
        loads are raised, the self-weight (its unit weights kept, so that a tank filling
        from empty loads in proportion to its height)."""
        return replace(self, **{name: 0.0 for name in LOAD_AMOUNTS})

    @property
    def nothing(self) -> bool:
        """Whether the load applies nothing at all (an emptied tank without its weight)."""
        return not (self.pressure or self.liquid_height * self.liquid_unit_weight
                    or self.self_weight or self.roof_weight or self.gas_pressure
                    or self.overturning)


@dataclass(frozen=True)
class Consolidation:
    """Biot's consolidation of a saturated soil (tankfx.laws.biot): the load is applied
    at t = 0, when the soil answers undrained, and held while the excess pore pressure
    drains; the soil's E and nu are then its drained (effective) constants."""

    permeability: float = key(unit="m/s", required=True, limit=POSITIVE,
                              meaning="k, Darcy's hydraulic conductivity of the saturated soil "
                                      "(and of each layer that gives none of its own): the pore "
                                      "water flows at (k / gamma_w) grad p, gamma_w the "
                                      "`water_unit_weight`")
    times: tuple[float, ...] = key((), unit="s", kind=list, custom=True,
                                   default_doc="required (with [fill]: none, the schedule's)",
                                   meaning="the times after the load starts (t = 0) at which "
                                           "results are reported (positive, increasing); t = 0 "
                                           "(undrained) and the drained limit are always reported;"
                                           " the results' top level is the last time's. With a "
                                           "[fill] the schedule's own times are reported: leave "
                                           "it out")
    piezometers: tuple[tuple[float, float], ...] = key(
        (), unit="m", kind=list, custom=True,
        meaning="points [r, depth] in the ground (r from the axis, depth below the ground "
                "surface) where the excess pore pressure is followed in time, e.g. [[0, 5], "
                "[12.5, 3]]: each reported state and each stage's record gives `piezometers`, "
                "the excess pore pressure (Pa) at each, and `consolidation.piezometers` their "
                "history")
    water_unit_weight: float = key(WATER_UNIT_WEIGHT, unit="N/m^3", limit=POSITIVE,
                                   meaning="gamma_w, the pore water's unit weight in Darcy's flow "
                                           "(k / gamma_w) grad p: with `permeability` k it sets "
                                           "the pace of consolidation, c_v = k E_oed / gamma_w")
    #: the foundation, the pit's sides and the far side are impervious
    drainage: str = key("top", choices=("top", "top_and_bottom"),
                        meaning="the drained boundaries: \"top\" (the ground surface around the "
                                "foundation, and a flexible load's loaded area) or "
                                "\"top_and_bottom\" (also the rigid base: a clay on sand or "
                                "gravel); the foundation, the pit's sides, the axis and the far "
                                "side are impervious")
    steps_per_decade: int = key(10, unit="-", limit=Limit(2, low_open=False),
                                why="10 keep Terzaghi's settlement within 0.6 %; 20 within "
                                    "0.2 %",
                                meaning="the time steps per decade of time: variable-step BDF2, "
                                        "growing geometrically from a hundredth of the first "
                                        "reported time (restarted at each breakpoint of a load "
                                        "path: from a hundredth of its stretch after a load "
                                        "applied at once, from a fifth where only the load's "
                                        "rate changes); 10 keep Terzaghi's settlement within 0.6 % of its "
                                        "final value, 20 within 0.2 %; with an "
                                        "elastoplastic skeleton the longest steps, shorter "
                                        "ones chosen by `time_tolerance`")
    time_tolerance: float = key(1e-3, unit="-", limit=POSITIVE,
                                why="measured on a yielding clay layer: benchmarks/"
                                    "yielding_layer.py",
                                meaning="with an elastoplastic skeleton, the local error "
                                        "allowed in a time step (BDF2's, estimated from its "
                                        "quadratic predictor), relative to the soil's largest "
                                        "displacement and to the largest excess pore "
                                        "pressure so far: a step whose error is more than "
                                        "twice it is taken again shorter, and the next "
                                        "step is chosen from it")


@dataclass(frozen=True)
class Fill:
    """The safe filling of a tank on a consolidating plastic soil: the liquid raised to
    ``height`` in steps of ``step`` at ``rate``, each step preceded by the shortest hold
    (to half a day) after which the factor of safety on the soil's strength at the step's
    end, the pore water held, is at least ``target_factor``
    (:class:`tankfx.iterations.fill_schedule.FillSchedule`)."""

    height: float = key(unit="m", required=True, limit=POSITIVE,
                        meaning="the liquid's final height in the tank (the hydrotest's full "
                                "height); [load] gives the liquid's unit weight")
    step: float = key(unit="m", required=True, limit=POSITIVE,
                      meaning="the rise of the liquid in one filling step (the last one may be "
                              "shorter, to end at `height`); before each step the schedule may "
                              "hold")
    rate: float = key(unit="m/day", required=True, limit=POSITIVE,
                      meaning="how fast the liquid rises while filling, in metres a day "
                              "(e.g. 1.0 for a pump filling a 25 m tank at 490 m^3/day)")
    target_factor: float = key(1.3, unit="-", limit=Limit(1.0, low_open=False),
                               meaning="the least factor of safety on the soil's strength (c' "
                                       "and tan phi', or M's tan phi_cs) at the end of every "
                                       "filling step, the pore water held (undrained): a "
                                       "step begins only after a hold that gives it")
    max_days: float = key(365.0, unit="day", limit=POSITIVE,
                          meaning="the longest the whole schedule may take: where the holds "
                                  "it needs would pass it, the schedule stops at the highest "
                                  "level reached safely, and says why")

    @property
    def heights(self) -> tuple[float, ...]:
        """The liquid's height at the end of each filling step, m."""
        n = max(1, math.ceil(self.height / self.step - 1e-9))
        return tuple(min(k * self.step, self.height) for k in range(1, n + 1))


@dataclass(frozen=True)
class DomainSize:
    radius: float = key(unit="m", limit=POSITIVE, default_doc="10000 a (cam_clay: 40 a)",
                        meaning="the soil's radius, from the axis to its far side (held as `side` "
                                "says); the default 10000 a leaves a truncation error of the "
                                "centre settlement below 0.01 % (homogeneous soil)")
    depth: float = key(unit="m", limit=POSITIVE, default_doc="10000 a (cam_clay: 40 a)",
                       meaning="the depth of the rigid base below the ground surface (held as "
                               "`base` says), anywhere below the foundation and the layers' tops "
                               "(e.g. rock under a thin layer); the default 10000 a is a "
                               "half-space")
    #: the far side's support: "fixed" (both displacements) or "roller" (u_r = 0, free
    #: to settle: PLAXIS's standard vertical rollers)
    side: str = key("fixed", choices=("fixed", "roller"),
                    meaning="the far side r = radius: \"fixed\" (u_r = u_z = 0) or \"roller\" "
                            "(u_r = 0, free to settle: the standard box of a verification, e.g. "
                            "PLAXIS's); with an overturning load the roller also holds u_theta")
    #: the rigid base's contact: "rough" (both displacements) or "smooth" (u_z = 0)
    base: str = key("rough", choices=("rough", "smooth"),
                    meaning="the rigid base z = depth: \"rough\" (u_r = u_z = 0, bonded to rock)"
                            " or \"smooth\" (u_z = 0, free to slide)")


@dataclass(frozen=True)
class MeshOptions:
    degree: int = key(2, unit="-", choices=(1, 2, 3, 4), custom=True,
                      default_doc="2 (3 for a flexible load)",
                      meaning="the Lagrange degree of the soil's displacement (1 to 4; 2 to 4 "
                              "for a mixed soil or a consolidation); the structure is always "
                              "cubic")
    edge_size: float = key(0.0, unit="m", limit=POSITIVE,
                           default_doc="0.002 a (0.004 a for a flexible load)",
                           meaning="the element size at the foundation's edge, where the soil's "
                                   "stress is singular (and at the other such corners: an "
                                   "embedded pit's rim, the wall's foot, a ringwall's corners)")
    growth: float = key(0.2, unit="-", limit=Limit(0.0, 1.0),
                        why="element size grows by this fraction of the distance from the "
                            "foundation edge",
                        meaning="how fast the elements grow away from the edge: their size is "
                                "`edge_size` + growth x the distance from it (and likewise beyond "
                                "the `near_size` zone)")
    near_size: float = key(0.0, unit="m", limit=POSITIVE,
                           default_doc="0.1 a (0.2 a for a flexible load)",
                           meaning="the largest element size within 6 a of the centre, where the "
                                   "soil's stresses are reported")


@dataclass(frozen=True)
class CollapseKind:
    """What ``analysis.collapse`` asks, composed: the ``search`` ("load": the variable loads
    raised until the ground fails; "strength": c and tan phi divided) and whether the limit
    analysis' ``bounds`` are set beside a search by load."""

    search: str
    bounds: bool = False


@dataclass(frozen=True)
class Analysis:
    """What is asked of the scene beyond its response to the load: the ground's collapse."""

    collapse: str | None = key(
        None, choices=("load", "strength", "bounds"), custom=True, default_doc="none",
        meaning="the ground's collapse, after the scene's own analysis: \"load\" raises the "
                "variable loads (pressure, liquid, gas, roof; the self-weight held) by a "
                "factor until the ground fails, \"strength\" holds the loads and divides "
                "the soil's c and tan phi by a factor until it fails; either is bracketed "
                "between a converged and a failed state to 0.5 % (`collapse` in the "
                "results). \"bounds\": the lower and upper bound of limit analysis on the "
                "variable loads' factor (`bounds`), beside \"load\"'s elastoplastic one. "
                "Needs soil.model = \"mohr_coulomb\" and one [load] (no [[stages]])")
    bounds_gap: float = key(0.03, unit="-", limit=Limit(0.0, 1.0),
                            meaning="with collapse = \"bounds\": the gap (upper - lower) / lower "
                                    "the mesh is refined to")
    bounds_cells: int = key(20000, unit="-", limit=POSITIVE,
                            meaning="with collapse = \"bounds\": the most triangles the refined "
                                    "mesh may have (about 1 min per 10^4 on two cores)")
    bounds_floor: str = key(
        "rigid", choices=("rigid", "flexible"),
        meaning="with collapse = \"bounds\" and a [wall]: the tank's floor and shell as one "
                "rigid body (\"rigid\": the elastic structure of the elastoplastic analysis "
                "moves rigidly once the ground flows, so these bound its limit), or a floor "
                "without bending strength (\"flexible\": the liquid's pressure on the ground, "
                "the shell's load on a band inside it; a lower bound for any floor; "
                "embedded, its pit's side free)")
    bounds_ring_width: float | None = key(
        None, unit="m", limit=POSITIVE, default_doc="the annular plate's width, else 0.05 a",
        meaning="with collapse = \"bounds\", a [wall] and bounds_floor = \"flexible\": the "
                "width of the band inside the shell over which the floor spreads the shell's load (its weight, the roof's) "
                "onto the ground; rigid plasticity carries no line load, the floor's bending "
                "spreads it (docs/theory/limit-analysis.md, \"The tank\")")

    @property
    def collapse_kind(self) -> CollapseKind | None:
        """``collapse`` composed (the one place it is read), None where none is asked."""
        if self.collapse is None:
            return None
        return CollapseKind(search="strength" if self.collapse == "strength" else "load",
                            bounds=self.collapse == "bounds")


@dataclass(frozen=True)
class SolverOptions:
    method: str = key("direct", choices=("direct", "iterative"), custom=True,
                      meaning="\"direct\": MUMPS (LDL^T, or LU with a Mohr-Coulomb interface); "
                              "\"iterative\": CG + GAMG for the soil alone, GMRES with the "
                              "structure condensed and GAMG on the soil's Schur complement with a "
                              "structure (faster than MUMPS beyond about a million dofs, leaner "
                              "from 150k); not with nu_s > 0.45, Duncan & Chang's soil or a "
                              "`[consolidation]` (see \"Iterative solver\")")
    rtol: float = key(1e-10, unit="-", limit=Limit(0.0, 1e-4),
                      why="the results are checked to 1e-6 of the load",
                      meaning="the relative residual each iterative solve (`method = "
                              "\"iterative\"`) must reach within `max_iterations`, else an error "
                              "with its residual; unused by the direct solver")
    max_iterations: int = key(1000, unit="-", limit=Limit(1, low_open=False),
                              meaning="the Krylov iterations an iterative solve may take to reach "
                                      "`rtol`; unused by the direct solver (a nonlinear soil's "
                                      "iterations are `[soil] max_iterations`)")

def load_breakdown(load: Load, plate: Plate | None, wall: Wall | None,
                   ringwall: "Ringwall | None" = None) -> dict[str, float]:
    """The vertical load's parts, N, downward positive: ``pressure`` on the plate (or the
    loaded circle), ``liquid`` on the floor, ``roof`` on the wall, ``self_weight`` (the
    plate's, the wall's and a ringwall's net weight, when asked for), and ``gas`` (a gas
    pressure's force on the floor inside the wall; the roof carries as much up to the wall,
    so it is not part of the resultant)."""
    a = plate.radius if plate is not None else load.load_radius
    out = {"pressure": load.pressure * math.pi * a**2, "liquid": 0.0, "roof": 0.0,
           "self_weight": 0.0, "gas": 0.0}
    if wall is not None:
        out["liquid"] = load.liquid_unit_weight * load.liquid_height * math.pi * wall.radius**2
        out["roof"] = load.roof_weight
        out["gas"] = load.gas_pressure * math.pi * wall.radius**2
    if load.self_weight and plate is not None:
        out["self_weight"] = plate.unit_weight * plate.volume
        if wall is not None:
            out["self_weight"] += wall.unit_weight * wall.volume
        if ringwall is not None:
            out["self_weight"] += ringwall.unit_weight * ringwall.volume
    return out


def load_between(a: Load, b: Load, f: float, base: Load | None = None) -> Load:
    """The load a fraction ``f`` of the way from ``a`` to ``b``: their amounts (the float
    fields but the loaded radius) interpolated, the rest ``base``'s (default ``a``'s)."""
    return replace(base or a, **{
        fd.name: (1.0 - f) * getattr(a, fd.name) + f * getattr(b, fd.name)
        for fd in fields(Load) if isinstance(getattr(a, fd.name), float)
        and fd.name != "load_radius"})


def factored_load(held: Load, full: Load, f: float) -> Load:
    """The loads at a factor ``f`` of the variable loads of ``full`` (its pressure, liquid,
    gas pressure and roof's weight; its self-weight and unit weights held, as in ``held``,
    the same load with those amounts at zero): up to 1 as a stage applies them (a tank
    fills: its liquid rises), beyond 1 the full loads times f (the liquid as one f times as
    heavy at its full height, so that its pressures, on the floor as on the wall, are f
    times the full ones)."""
    if f <= 1.0:
        return load_between(held, full, f, base=full)
    return replace(full, pressure=f * full.pressure, gas_pressure=f * full.gas_pressure,
                   roof_weight=f * full.roof_weight,
                   liquid_unit_weight=f * full.liquid_unit_weight)


def vertical_load(load: Load, plate: Plate | None, wall: Wall | None,
                  ringwall: "Ringwall | None" = None) -> float:
    """The load's resultant, N, downward positive (:func:`load_breakdown`'s parts but the
    gas pressure, which presses the floor down as hard as it lifts the roof)."""
    parts = load_breakdown(load, plate, wall, ringwall)
    return sum(v for k, v in parts.items() if k != "gas")


def vertical_load_scale(load: Load, plate: Plate | None, wall: Wall | None,
                        ringwall: "Ringwall | None" = None) -> float:
    """The size of the vertical loads, N, for relative equilibrium errors: the resultant's,
    and a gas pressure's force on the floor, which the roof's cancels in the resultant."""
    gas = abs(load.gas_pressure) * math.pi * wall.radius**2 if wall is not None else 0.0
    return abs(vertical_load(load, plate, wall, ringwall)) + gas


def toml_value(v) -> str:
    """A value as TOML writes it (the scene's values are finite: checked on reading); a list
    of tables (a wall's courses) as inline tables."""
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)        # a TOML basic string
    return repr(v)


def plain(part) -> dict[str, Any]:
    """A section's dataclass as the dict of its set values."""
    return {f.name: getattr(part, f.name) for f in fields(part)
            if getattr(part, f.name) is not None}




