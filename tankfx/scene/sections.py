"""The scene's sections as frozen dataclasses, in SI units (m, Pa, N/m^3): the soil and its
layers, the plate, the wall, a ringwall, the interface, the load, a consolidation, the domain,
the mesh and the solver; and the load's resultant.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

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


#: gamma_w, N/m^3
WATER_UNIT_WEIGHT = 9810.0
#: p_a, Pa: the reference pressure of Duncan & Chang's modulus
ATMOSPHERIC_PRESSURE = 101325.0


#: A nonlinear soil's Eq. 18 tolerance (the paper's) and its secant iterations at most, by
#: model (Duncan & Chang's failed zones settle slowly: 10-64 iterations measured)
DEFAULT_TOLERANCE = 0.05
MAX_ITERATIONS = {"hyperbolic": 40, "duncan_chang": 80}


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
#: (a layer's p_a is the soil's): their keys' units, limits, defaults and meanings
_KN = ("Duncan & Chang's K and n: the initial modulus K p_a (sigma_3 / p_a)^n, sigma_3 each "
       "cell's minor principal compression (geostatic plus the tank's; at least 0.01 p_a); E "
       "is then K p_a (the E_s of Eqs. 21-23) and may be left out; the soil is solved in the "
       "mixed form (nu > 0; mesh degree 2 or 3; direct solver)")
_STRENGTH = ("the Mohr-Coulomb strength q_f = (2 c cos phi + 2 sigma_3 sin phi) / (1 - sin phi) "
             "and R_f: the ultimate deviator 1/b = q_f / R_f; c or phi must be > 0")
_GEOSTATIC = "the geostatic stress gamma h (vertical) and K0 gamma h (horizontal), and p_a"
_DUNCAN_CHANG_KEYS: dict[str, Key] = {
    "modulus_number": Key(unit="-", limit=POSITIVE, meaning=_KN),
    "modulus_exponent": Key(unit="-", limit=Limit(0.0, 1.0, False), why=EXPONENT_WHY,
                            meaning=_KN),
    "failure_ratio": Key(unit="-", limit=Limit(0.0, 1.0), why=RF_WHY, default_doc="0.9",
                         meaning=_STRENGTH),
    "cohesion": Key(unit="Pa", limit=NON_NEGATIVE, default_doc="0", meaning=_STRENGTH),
    "friction_angle": Key(unit="deg", limit=ANGLE, why="degrees", default_doc="0",
                          meaning=_STRENGTH),
    "unit_weight": Key(unit="N/m^3", limit=POSITIVE, meaning=_GEOSTATIC),
    "K0": Key(unit="-", limit=POSITIVE, default_doc="1 - sin(phi)", meaning=_GEOSTATIC),
}
#: a layer's Duncan & Chang constants, in words
LAYER_DUNCAN_CHANG = ("Duncan & Chang's constants of the layer (E is K p_a, p_a the soil's); "
                      "the geostatic stress sums the weights of the strata above")


def duncan_chang_key(name: str, layer: bool = False) -> Any:
    """The field of one of Duncan & Chang's constants (None unless given), as declared in
    _DUNCAN_CHANG_KEYS (a layer's with the layer's meaning)."""
    spec = _DUNCAN_CHANG_KEYS[name]
    values = {f.name: getattr(spec, f.name) for f in fields(spec)}
    return key(None, **(values | ({"meaning": LAYER_DUNCAN_CHANG} if layer else {})))


@dataclass(frozen=True)
class Layer:
    """A stratum of the ground from ``depth`` down to the next layer's top (or to the rigid
    base): E(h) = E (1 + E_gradient (h - depth)) within it."""

    depth: float = key(unit="m", required=True, limit=POSITIVE,
                       meaning="depth of the layer's top below the ground surface (it may lie "
                               "above, on or below an embedded plate's underside; each deeper than "
                               "the last, above `domain.depth`); the tops are lines of the mesh")
    E: float = key(unit="Pa", limit=POSITIVE, default_doc="required (linear soil)",
                   meaning="the layer's modulus at its top, Poisson's ratio (up to 0.5: a layer "
                           "above 0.45 is solved in the mixed form with a pressure of its own, the "
                           "others in the displacement form), and its growth within the layer, E (1"
                           " + E_gradient (h - depth))")
    nu: float = key(unit="-", required=True, limit=SOIL_POISSON, why=SOIL_POISSON_WHY,
                    meaning="the layer's modulus at its top, Poisson's ratio (up to 0.5: a layer "
                            "above 0.45 is solved in the mixed form with a pressure of its own, the"
                            " others in the displacement form), and its growth within the layer, E "
                            "(1 + E_gradient (h - depth))")
    E_gradient: float = key(0.0, unit="1/m", limit=NON_NEGATIVE,
                            meaning="the layer's modulus at its top, Poisson's ratio (up to 0.5: a "
                                    "layer above 0.45 is solved in the mixed form with a pressure "
                                    "of its own, the others in the displacement form), and its "
                                    "growth within the layer, E (1 + E_gradient (h - depth))")
    hyperbolic_a: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="Kondner's a and b of the layer (then E is 1/a and may"
                                             " be left out)")
    hyperbolic_b: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="Kondner's a and b of the layer (then E is 1/a and may"
                                             " be left out)")
    # Duncan & Chang's constants of the layer (model = "duncan_chang"; p_a is the soil's)
    modulus_number: float | None = duncan_chang_key("modulus_number", layer=True)
    modulus_exponent: float | None = duncan_chang_key("modulus_exponent", layer=True)
    failure_ratio: float | None = duncan_chang_key("failure_ratio", layer=True)
    cohesion: float | None = duncan_chang_key("cohesion", layer=True)
    friction_angle: float | None = duncan_chang_key("friction_angle", layer=True)
    unit_weight: float | None = duncan_chang_key("unit_weight", layer=True)
    K0: float | None = duncan_chang_key("K0", layer=True)
    permeability: float | None = key(None, unit="m/s", limit=POSITIVE,
                                     default_doc="[consolidation] permeability",
                                     meaning="a layer's own Darcy k in a consolidation (e.g. a sand"
                                             " layer that drains a clay: a large k); the pore "
                                             "pressure is one field, continuous across the layers' "
                                             "boundaries, and so is its flux; each layer's drained "
                                             "nu <= 0.45")


#: The [soil] (or layer) keys that set its E (1/a, K p_a): a change of one of them drops
#: the E resolved from the old value (Scene.with_changes, sweep axes)
E_FROM_KEYS = ("hyperbolic_a", "modulus_number", "atmospheric_pressure")


#: Duncan & Chang's constants that each stratum has (p_a is the soil's, one for all)
STRATUM_DUNCAN_CHANG = ("modulus_number", "modulus_exponent", "failure_ratio", "cohesion",
                        "friction_angle", "unit_weight", "K0")


@dataclass(frozen=True)
class Soil:
    E: float = key(unit="Pa", limit=POSITIVE, default_doc="required (linear soil)",
                   meaning="Young's modulus at the ground surface, E_s; for a hyperbolic soil it is"
                           " 1/a and may be left out")
    nu: float = key(unit="-", required=True, limit=SOIL_POISSON, why=SOIL_POISSON_WHY,
                    meaning="Poisson's ratio, -1 < nu <= 0.5; above 0.45 the soil is solved in the "
                            "mixed displacement-pressure form (chosen automatically), 0.5 is an "
                            "incompressible (undrained) soil")
    E_gradient: float = key(0.0, unit="1/m", limit=NON_NEGATIVE,
                            meaning="lambda: E(h) = E_s (1 + lambda h), h = depth below the "
                                    "surface")
    model: str = key("linear", choices=("linear", "hyperbolic", "duncan_chang"),
                     meaning="\"linear\", \"hyperbolic\" (Kondner, Eqs. 17-20) or \"duncan_chang\" "
                             "(Kondner's law with the constants of each cell's confinement, below)")
    hyperbolic_a: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="1/a = initial tangent modulus at the surface (scaled "
                                             "by 1 + lambda h with depth), 1/b = ultimate deviator "
                                             "stress; the paper's a = 0.00021, b = 0.01 read in kPa"
                                             " are 2.1e-7 and 1e-5 1/Pa")
    hyperbolic_b: float | None = key(None, unit="1/Pa", limit=POSITIVE,
                                     meaning="1/a = initial tangent modulus at the surface (scaled "
                                             "by 1 + lambda h with depth), 1/b = ultimate deviator "
                                             "stress; the paper's a = 0.00021, b = 0.01 read in kPa"
                                             " are 2.1e-7 and 1e-5 1/Pa")
    tolerance: float | None = key(None, unit="-", limit=Limit(0.0, 1.0, high_open=True),
                                  why="the relative deviator misfit of Eq. 18; the paper's "
                                      "0.05 is the default",
                                  default_doc=f"{DEFAULT_TOLERANCE:g} (nonlinear soil)",
                                  meaning="Eq. 18's relative deviator misfit, and the Picard "
                                          "iterations allowed (Duncan & Chang's failed zones settle"
                                          " slowly: 10-64 measured)")
    max_iterations: int | None = key(None, unit="-", limit=Limit(1, low_open=False),
                                     default_doc=", ".join(f"{n} ({m})" for m, n in
                                                           MAX_ITERATIONS.items()),
                                     meaning="Eq. 18's relative deviator misfit, and the Picard "
                                             "iterations allowed (Duncan & Chang's failed zones "
                                             "settle slowly: 10-64 measured)")
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
    atmospheric_pressure: float | None = key(None, unit="Pa", limit=POSITIVE,
                                             default_doc=f"{ATMOSPHERIC_PRESSURE:g}",
                                             meaning="the geostatic stress gamma h (vertical) and "
                                                     "K0 gamma h (horizontal), and p_a")
    #: the confinement is effective below it: the geostatic stress less the hydrostatic
    #: pore pressure
    water_table: float | None = key(None, unit="m", limit=NON_NEGATIVE,
                                    default_doc="below everything",
                                    meaning="(\"duncan_chang\") the water table's depth: below it "
                                            "the confinement is effective, the geostatic stress "
                                            "less gamma_w (h - water_table) (give the strata there "
                                            "their saturated unit weights, which must exceed "
                                            "gamma_w)")
    water_unit_weight: float | None = key(None, unit="N/m^3", limit=POSITIVE,
                                          default_doc=f"{WATER_UNIT_WEIGHT:g} (with a "
                                                      f"water_table)",
                                          meaning="(\"duncan_chang\") the water table's depth: "
                                                  "below it the confinement is effective, the "
                                                  "geostatic stress less gamma_w (h - water_table) "
                                                  "(give the strata there their saturated unit "
                                                  "weights, which must exceed gamma_w)")
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
        meaning="(\"hyperbolic\" or \"duncan_chang\", along `[[stages]]` of two or more) E_ur / "
                "E_i: below its most loaded state so far each cell unloads and reloads along a line"
                " of E_ur = this times its initial modulus (Duncan & Chang's: K_ur = this x K, at "
                "the cell's current confinement), keeping its permanent strain (K_ur / K: 1.2-3 in "
                "Duncan & Chang's tables; 1 is Masing's rule); >= 1; every stratum, any nu; a stage"
                " may then have no load at all (the load taken off entirely; equilibrium errors "
                "relative to the path's largest load); refused with a `[consolidation]`")

    @property
    def strata(self) -> tuple[Layer, ...]:
        """Every stratum from the surface down, the surface soil as the first (depth 0)."""
        top = Layer(depth=0.0, E=self.E, nu=self.nu, E_gradient=self.E_gradient,
                    hyperbolic_a=self.hyperbolic_a, hyperbolic_b=self.hyperbolic_b,
                    **{k: getattr(self, k) for k in STRATUM_DUNCAN_CHANG})
        return (top, *self.layers)

    @property
    def nonlinear(self) -> bool:
        """Whether the soil is iterated (Kondner's law, alone or Duncan & Chang's)."""
        return self.model in ("hyperbolic", "duncan_chang")

    @property
    def mixed_strata(self) -> list[int]:
        """Indices into :attr:`strata` of those solved in the mixed u-p form: nu >
        MIXED_FROM_NU, and every stratum of Duncan & Chang's soil (a failed cell keeps its
        bulk modulus while its secant shear modulus falls: nu -> 0.5)."""
        dc = self.model == "duncan_chang"
        return [i for i, st in enumerate(self.strata) if dc or st.nu > MIXED_FROM_NU]

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
        Chang's constants (STRATUM_DUNCAN_CHANG; 0 where the model has none), and the
        initial modulus ``E`` = E_top (1 + E_gradient (h - top)) (h clipped at the ground)."""
        idx = self.stratum_of(depth)
        out = {key: np.array([getattr(st, key) or 0.0 for st in self.strata])[idx]
               for key in ("E_gradient", "nu", "hyperbolic_a", "hyperbolic_b",
                           *STRATUM_DUNCAN_CHANG)}
        out["top"] = np.array([st.depth for st in self.strata])[idx]
        out["E_top"] = np.array([st.E for st in self.strata])[idx]
        h = np.maximum(np.asarray(depth, dtype=float), 0.0)
        out["E"] = out["E_top"] * (1.0 + out["E_gradient"] * (h - out["top"]))
        return out


@dataclass(frozen=True)
class Plate:
    radius: float = key(unit="m", required=True, limit=POSITIVE, meaning="a_p")
    thickness: float = key(unit="m", limit=POSITIVE, default_doc="from Kp (Eq. 21)",
                           meaning="t_p, or the relative rigidity Kp = (1 - nu_s^2)(E_p / E_s)(t_p "
                                   "/ a_p)^3 (Eq. 21, E_s and nu_s at the surface)")
    E: float = key(unit="Pa", required=True, limit=POSITIVE, meaning="plate material")
    nu: float = key(unit="-", required=True, limit=SHELL_POISSON, why=SHELL_POISSON_WHY,
                    meaning="plate material")
    #: Eq. 21's relative rigidity where the scene gives it instead of the thickness: held
    #: (the thickness follows) when the soil changes (Scene.with_changes, a sweep's case)
    Kp: float | None = key(None, unit="-", limit=POSITIVE, default_doc="-",
                           meaning="t_p, or the relative rigidity Kp = (1 - nu_s^2)(E_p / E_s)(t_p "
                                   "/ a_p)^3 (Eq. 21, E_s and nu_s at the surface)")
    embedment: float = key(0.0, unit="m", limit=NON_NEGATIVE,
                           meaning="depth of the plate's underside below the ground; the soil above"
                                   " it, inside r <= a_p, is excavated")
    unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                             meaning="used only with `load.self_weight = true`")
    #: a ring of another thickness along the edge, under the wall (an API 650 tank's
    #: annular bottom plate, or a thickened edge). The underside stays flat; Kp is the
    #: floor's.
    annular_width: float = key(0.0, unit="m", limit=POSITIVE, default_doc="0: none",
                               meaning="a ring of another thickness along the plate's edge, under "
                                       "the wall (an API 650 tank's annular bottom plate, or a "
                                       "thickened edge): its width inward from the edge and its "
                                       "thickness; both or neither; the ring must reach the wall "
                                       "(it is what the wall stands on); the underside stays flat; "
                                       "`thickness` (and Kp) are then the floor's")
    annular_thickness: float | None = key(None, unit="m", limit=POSITIVE,
                                          meaning="a ring of another thickness along the plate's "
                                                  "edge, under the wall (an API 650 tank's annular "
                                                  "bottom plate, or a thickened edge): its width "
                                                  "inward from the edge and its thickness; both or "
                                                  "neither; the ring must reach the wall (it is "
                                                  "what the wall stands on); the underside stays "
                                                  "flat; `thickness` (and Kp) are then the floor's")

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
                        meaning="a_t <= a_p (a wall inside the plate edge makes a T-joint)")
    thickness: float = key(unit="m", limit=POSITIVE, default_doc="from Kt (Eq. 22) or courses",
                           meaning="t_t, or Kt = (1 - nu_s^2)(E_t / E_s)(t_t / a_t)^3 (Eq. 22), or "
                                   "a wall whose thickness steps: `courses = [{height = 2.4, "
                                   "thickness = 0.013}, ...]` from the bottom up (m), their outer "
                                   "faces flush; `height` may then be left out (it is their sum; "
                                   "given, it must equal it), and Kt is the bottom course's")
    height: float = key(unit="m", limit=POSITIVE, default_doc="the courses' sum",
                        meaning="H is measured from the plate's underside")
    E: float = key(unit="Pa", required=True, limit=POSITIVE, meaning="H is measured from the "
                                                                     "plate's underside")
    nu: float = key(unit="-", required=True, limit=SHELL_POISSON, why=SHELL_POISSON_WHY,
                    meaning="H is measured from the plate's underside")
    #: Eq. 22's relative rigidity where the scene gives it instead of the thickness: held
    #: (the thickness follows) when the soil changes
    Kt: float | None = key(None, unit="-", limit=POSITIVE, default_doc="-",
                           meaning="t_t, or Kt = (1 - nu_s^2)(E_t / E_s)(t_t / a_t)^3 (Eq. 22), or "
                                   "a wall whose thickness steps: `courses = [{height = 2.4, "
                                   "thickness = 0.013}, ...]` from the bottom up (m), their outer "
                                   "faces flush; `height` may then be left out (it is their sum; "
                                   "given, it must equal it), and Kt is the bottom course's")
    unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                             meaning="H is measured from the plate's underside")
    #: the courses of a wall whose thickness steps, (height, thickness) in m from the bottom
    #: up, their outer faces flush (empty: one course of ``thickness``, the paper's wall)
    courses: tuple[tuple[float, float], ...] = key(
        (), unit="m", kind=list, custom=True,
        meaning="t_t, or Kt = (1 - nu_s^2)(E_t / E_s)(t_t / a_t)^3 (Eq. 22), or a wall whose "
                "thickness steps: `courses = [{height = 2.4, thickness = 0.013}, ...]` from the "
                "bottom up (m), their outer faces flush; `height` may then be left out (it is their"
                " sum; given, it must equal it), and Kt is the bottom course's")

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
                              meaning="a concrete ringwall (ring beam) under the wall: an annulus "
                                      "of its own material in the ground, from the plate's "
                                      "underside down `depth`, between the radii (inner < a_t <= "
                                      "outer: the wall stands on it; outer within half the domain),"
                                      " bonded to the soil around it; the plate rests on it and on "
                                      "the soil (or fill) inside through the same interface; on any"
                                      " soil model (a nonlinear soil's secant iteration leaves its "
                                      "cells at their own modulus)")
    outer_radius: float = key(unit="m", required=True, limit=POSITIVE,
                              meaning="a concrete ringwall (ring beam) under the wall: an annulus "
                                      "of its own material in the ground, from the plate's "
                                      "underside down `depth`, between the radii (inner < a_t <= "
                                      "outer: the wall stands on it; outer within half the domain),"
                                      " bonded to the soil around it; the plate rests on it and on "
                                      "the soil (or fill) inside through the same interface; on any"
                                      " soil model (a nonlinear soil's secant iteration leaves its "
                                      "cells at their own modulus)")
    depth: float = key(unit="m", required=True, limit=POSITIVE,
                       meaning="a concrete ringwall (ring beam) under the wall: an annulus of its "
                               "own material in the ground, from the plate's underside down "
                               "`depth`, between the radii (inner < a_t <= outer: the wall stands "
                               "on it; outer within half the domain), bonded to the soil around it;"
                               " the plate rests on it and on the soil (or fill) inside through the"
                               " same interface; on any soil model (a nonlinear soil's secant "
                               "iteration leaves its cells at their own modulus)")
    E: float = key(unit="Pa", required=True, limit=POSITIVE, meaning="its material, linear elastic "
                                                                     "(nu <= 0.45: the displacement"
                                                                     " form, also in a mixed soil)")
    nu: float = key(0.2, unit="-", limit=RING_POISSON, why="concrete's is about 0.2",
                    meaning="its material, linear elastic (nu <= 0.45: the displacement form, also "
                            "in a mixed soil)")
    #: its weight in excess of the soil it replaces (the soil's own weight is the ground's
    #: initial state, not a load here)
    unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                             meaning="with `load.self_weight = true`, its weight in excess of the "
                                     "soil it replaces (the soil's own weight is the ground's "
                                     "initial state, not a load): e.g. 24e3 - 18e3 = 6e3; it loads "
                                     "the ground, not the interface")
    #: a compacted fill inside the ring, from the plate's underside to the ring's depth
    #: (linear elastic)
    fill_E: float | None = key(None, unit="Pa", limit=POSITIVE, default_doc="none: the soil",
                               meaning="a compacted fill inside the ring, from the plate's "
                                       "underside to the ring's depth, linear elastic (nu <= 0.45);"
                                       " needs inner_radius > 0")
    fill_nu: float = key(0.3, unit="-", limit=RING_POISSON, why="e.g. 0.3",
                         meaning="a compacted fill inside the ring, from the plate's underside to "
                                 "the ring's depth, linear elastic (nu <= 0.45); needs inner_radius"
                                 " > 0")

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


@dataclass(frozen=True)
class Interface:
    condition: str = key("bonded", choices=("bonded", "smooth", "mohr_coulomb"),
                         meaning="\"bonded\" (no slip, takes tension), \"smooth\" (no shear, takes "
                                 "tension), \"mohr_coulomb\" (Eqs. 6-16)")
    cohesion: float = key(0.0, unit="Pa", limit=NON_NEGATIVE,
                          meaning="c, \"mohr_coulomb\" only")
    tan_phi: float | None = key(None, unit="-", limit=NON_NEGATIVE,
                                meaning="the interface friction; the paper's limits are tan_phi = "
                                        "10 (bonded) and 0.001 (smooth)")
    normal_stiffness: float | None = key(None, unit="Pa/m", limit=POSITIVE,
                                         default_doc="1e3 E / h",
                                         meaning="the penalty stiffnesses (h: the element length)")
    shear_stiffness: float | None = key(None, unit="Pa/m", limit=POSITIVE,
                                        default_doc="normal_stiffness", meaning="the penalty "
                                                                                "stiffnesses (h: "
                                                                                "the element "
                                                                                "length)")
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


#: The keys a scene file may give instead of a field: a friction angle for tan phi
ALTERNATIVE_KEYS: dict[str, dict[str, Key]] = {
    "interface": {"friction_angle": Key(unit="deg", limit=ANGLE, why="degrees", default_doc="-",
                                        meaning="the interface friction; the paper's limits are "
                                                "tan_phi = 10 (bonded) and 0.001 (smooth)")},
}


@dataclass(frozen=True)
class Load:
    pressure: float = key(0.0, unit="Pa", meaning="uniform downward pressure: on the whole plate, "
                                                  "or without a plate on r <= `load_radius` (>= 0);"
                                                  " negative (uplift) only on a bonded or smooth "
                                                  "plate")
    load_radius: float | None = key(None, unit="m", limit=POSITIVE,
                                    default_doc="the plate's radius",
                                    meaning="radius of the flexible load (with a plate: the plate "
                                            "radius)")
    liquid_unit_weight: float = key(0.0, unit="N/m^3", limit=NON_NEGATIVE,
                                    meaning="liquid inside the wall: gamma h on the floor (r < "
                                            "a_t), gamma (h - z) outward on the wall")
    liquid_height: float = key(0.0, unit="m", limit=NON_NEGATIVE,
                               meaning="liquid inside the wall: gamma h on the floor (r < a_t), "
                                       "gamma (h - z) outward on the wall")
    self_weight: bool = key(False, meaning="adds the plate's and wall's weight (their `unit_weight`"
                                           " x thickness, course by course and ring by ring)")
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
                                    meaning="an overturning moment (wind, earthquake: API 650 Annex"
                                            " E's ringwall moment M_rw) about the plate's underside"
                                            " at the axis, pressing the side theta = 0 down: with a"
                                            " wall it reaches the foundation through the wall's "
                                            "foot (the wall's top edge carries the shear, as a thin"
                                            " tube's shear flow -V sin theta / (pi a_t), and a "
                                            "couple, so that its foot carries exactly V and M); "
                                            "without one, a pressure 4 M r cos theta / (pi a^4) on "
                                            "the plate. Solved as the first Fourier harmonic about "
                                            "the stage's converged state and superposed "
                                            "(`overturning` in the results); needs a plate")
    #: N: the horizontal force that comes with it (towards theta = 0), carried by the wall
    #: (or the plate) to the interface
    base_shear: float = key(0.0, unit="N", meaning="the horizontal force that comes with it, "
                                                   "towards theta = 0 (on the wall's top edge, or "
                                                   "as a uniform traction on a plate without a "
                                                   "wall)")

    @property
    def overturning(self) -> bool:
        """Whether the load has a first-harmonic part (an overturning moment or shear)."""
        return bool(self.overturning_moment or self.base_shear)


@dataclass(frozen=True)
class Consolidation:
    """Biot's consolidation of a saturated soil (tankfx.laws.biot): the load is applied
    at t = 0, when the soil answers undrained, and held while the excess pore pressure
    drains; the soil's E and nu are then its drained (effective) constants."""

    permeability: float = key(unit="m/s", required=True, limit=POSITIVE,
                              meaning="Darcy's k of a saturated soil: with a `[consolidation]` "
                                      "table the soil consolidates in time (Biot's equations; "
                                      "`[soil] E`, `nu` are then its drained constants E', nu' <= "
                                      "0.45); the `[load]` is applied at t = 0 (undrained) and "
                                      "held")
    times: tuple[float, ...] = key(unit="s", required=True, kind=list, custom=True,
                                   meaning="the times after loading at which results are reported "
                                           "(positive, increasing); t = 0 (undrained) and the "
                                           "drained limit are always reported; the results' top "
                                           "level is the last time's")
    water_unit_weight: float = key(WATER_UNIT_WEIGHT, unit="N/m^3", limit=POSITIVE,
                                   meaning="gamma_w; the time steps per decade of time "
                                           "(variable-step BDF2 from a hundredth of the first time:"
                                           " 10 keep Terzaghi's settlement within 0.6 % of its "
                                           "final value, 20 within 0.2 %)")
    #: the foundation, the pit's sides and the far side are impervious
    drainage: str = key("top", choices=("top", "top_and_bottom"),
                        meaning="the drained boundaries: \"top\" (the ground surface around the "
                                "foundation, and a flexible load's loaded area) or "
                                "\"top_and_bottom\" (also the rigid base: a clay on sand or "
                                "gravel); the foundation, the pit's sides, the axis and the far "
                                "side are impervious")
    steps_per_decade: int = key(10, unit="-", limit=Limit(2, low_open=False),
                                why="10 keep Terzaghi's settlement within 0.6 %; 20 within "
                                    "0.2 %", meaning="gamma_w; the time steps per decade of time "
                                                     "(variable-step BDF2 from a hundredth of the "
                                                     "first time: 10 keep Terzaghi's settlement "
                                                     "within 0.6 % of its final value, 20 within "
                                                     "0.2 %)")


@dataclass(frozen=True)
class DomainSize:
    radius: float = key(unit="m", limit=POSITIVE, default_doc="10000 a",
                        meaning="extent of the soil; `depth` is the depth of a rigid base "
                                "(rough or smooth: `base`), anywhere below the foundation (e.g. "
                                "rock under a thin layer)")
    depth: float = key(unit="m", limit=POSITIVE, default_doc="10000 a",
                       meaning="extent of the soil; `depth` is the depth of a rigid base "
                               "(rough or smooth: `base`), anywhere below the foundation (e.g. "
                               "rock under a thin layer)")
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
    degree: int = key(2, unit="-", choices=(1, 2, 3), custom=True,
                      default_doc="2 (3 for a flexible load)",
                      meaning="Lagrange degree of the soil displacement (1, 2 or 3); the structure "
                              "is always cubic")
    edge_size: float = key(0.0, unit="m", limit=POSITIVE,
                           default_doc="0.002 a (0.004 a for a flexible load)",
                           meaning="element size at the foundation edge (the stress singularity)")
    growth: float = key(0.2, unit="-", limit=Limit(0.0, 1.0),
                        why="element size grows by this fraction of the distance from the "
                            "foundation edge",
                        meaning="element size grows as edge_size + growth x distance from the edge")
    near_size: float = key(0.0, unit="m", limit=POSITIVE,
                           default_doc="0.1 a (0.2 a for a flexible load)",
                           meaning="element size cap within 6 a of the centre, where soil stresses "
                                   "are reported")


@dataclass(frozen=True)
class SolverOptions:
    method: str = key("direct", choices=("direct", "iterative"), custom=True,
                      meaning="\"direct\": MUMPS (LDL^T, or LU with a Mohr-Coulomb interface); "
                              "\"iterative\": CG + GAMG for the soil alone, GMRES with the "
                              "structure condensed and GAMG on the soil's Schur complement with a "
                              "structure (faster than MUMPS beyond about a million dofs, leaner "
                              "from 150k); not with nu_s > 0.45 (see \"Iterative solver\")")
    rtol: float = key(1e-10, unit="-", limit=Limit(0.0, 1e-4),
                      why="the results are checked to 1e-6 of the load",
                      meaning="the iterative solve's relative residual and iteration bound (a solve"
                              " that does not reach it is an error, with its residual)")
    max_iterations: int = key(1000, unit="-", limit=Limit(1, low_open=False),
                              meaning="the iterative solve's relative residual and iteration bound "
                                      "(a solve that does not reach it is an error, with its "
                                      "residual)")


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




