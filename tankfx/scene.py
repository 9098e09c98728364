"""The scene: one validated description of a tank-foundation-soil problem.

A scene is read from a TOML file (see ``README.md`` for every key) into frozen dataclasses.
All checks happen here, before any mesh is built, and all problems found are reported in one
:class:`SceneError` whose message names each offending key and how to fix it.

Units are SI throughout: metres, pascals, newtons per cubic metre.
"""
from __future__ import annotations

import difflib
import json
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["SceneError", "Soil", "Layer", "Plate", "Wall", "Ringwall", "Interface", "Load",
           "DomainSize", "Consolidation",
           "MeshOptions", "Scene", "load_scene", "plate_thickness_from_Kp", "Kp_from_thickness",
           "vertical_load"]

#: Default domain size, in multiples of the foundation radius. The truncation error of the
#: centre settlement falls like 1/R (measured, homogeneous half-space with a fixed far
#: boundary: -0.74 % at 100 a, -0.074 % at 1000 a, -0.0074 % at 10000 a; README "Truncation
#: of the half-space"). The graded mesh makes the size almost free: going from 1000 a to
#: 10000 a adds 1.5 % to the dofs.
DEFAULT_DOMAIN_FACTOR = 10000.0


#: Default element sizes, in multiples of the foundation radius: at the foundation edge (the
#: stress singularity) and the cap over the near field (6 radii around the centre). Measured
#: on the flexible load (README "Mesh defaults"): with P2 these keep the centre and edge
#: settlements within 0.1 % and sigma_zz on the axis within 1 % up to nu = 0.45.
DEFAULT_EDGE_SIZE = 0.002

#: Above this soil Poisson's ratio the soil is solved in the mixed displacement-pressure
#: (Taylor-Hood) form, chosen automatically: the displacement form's stresses lock (measured
#: on the flexible load: sigma_zz on the axis off by 0.5 % of p at 0.45, 2.6 % at 0.49,
#: 17.6 % at 0.499), and it cannot take 0.5 at all.
MIXED_FROM_NU = 0.45
DEFAULT_NEAR_SIZE = 0.1
#: A flexible load (no plate: the soil alone decides the error) defaults to P3 on a mesh
#: FLEXIBLE_COARSENING times coarser: measured, largest error 1.5e-3 -> 1.9e-4 (sigma_zz on
#: the axis) at the same whole-process time (README "Every case").
FLEXIBLE_DEGREE = 3
FLEXIBLE_COARSENING = 2.0


class SceneError(ValueError):
    """A scene that cannot be run; the message lists every problem and its fix."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        lines = "\n".join(f"  - {p}" for p in self.problems)
        super().__init__(f"the scene has {len(self.problems)} problem(s):\n{lines}")


# --------------------------------------------------------------------------- dataclasses
@dataclass(frozen=True)
class Layer:
    """A stratum of the ground from ``depth`` down to the next layer's top (or to the rigid
    base): E(h) = E (1 + E_gradient (h - depth)) within it."""

    depth: float             #: m below the ground surface, where this layer's top lies
    E: float                 #: Young's modulus at its top, Pa (1/a if hyperbolic)
    nu: float
    E_gradient: float = 0.0  #: 1/m, from its top down
    hyperbolic_a: float | None = None
    hyperbolic_b: float | None = None
    # Duncan & Chang's constants of the layer (model = "duncan_chang"; p_a is the soil's)
    modulus_number: float | None = None
    modulus_exponent: float | None = None
    failure_ratio: float | None = None
    cohesion: float | None = None
    friction_angle: float | None = None
    unit_weight: float | None = None
    K0: float | None = None
    #: m/s, Darcy's k of the layer in a consolidation (None: [consolidation]'s)
    permeability: float | None = None


#: The [soil] (or layer) keys that set its E (1/a, K p_a): a change of one of them drops
#: the E resolved from the old value (Scene.with_changes, sweep axes)
E_FROM_KEYS = ("hyperbolic_a", "modulus_number", "atmospheric_pressure")

#: Duncan & Chang's constants that each stratum has (p_a is the soil's, one for all)
STRATUM_DUNCAN_CHANG = ("modulus_number", "modulus_exponent", "failure_ratio", "cohesion",
                        "friction_angle", "unit_weight", "K0")


def stratum_constants(model: str, st: Mapping[str, Any]) -> str:
    """A nonlinear stratum's constants in words, as `tankfx check` and the report write
    them (``st``: a :class:`Layer` as a dict, or a stratum of results.json's scene):
    Kondner's 1/b (its 1/a is the stratum's E), or Duncan & Chang's K, n, R_f, c, phi,
    gamma and K0; nothing for a linear soil."""
    if model == "hyperbolic":
        return f", Kondner 1/b = {1.0 / st['hyperbolic_b']:.4g} Pa (1/a = E)"
    if model == "duncan_chang":
        return (f", Duncan-Chang K = {st['modulus_number']:g}, n = {st['modulus_exponent']:g}, "
                f"R_f = {st['failure_ratio']:g}, c = {st['cohesion']:g} Pa, phi = "
                f"{st['friction_angle']:g} deg, gamma = {st['unit_weight']:g} N/m^3, K0 = "
                f"{st['K0']:.3g} (E = K p_a)")
    return ""


def ringwall_text(ring: Mapping[str, Any]) -> str:
    """A ringwall in words, as `tankfx check` and the report write it (``ring``: its table
    of :meth:`Scene.to_dict`)."""
    weight = (f", net unit weight {ring['unit_weight']:g} N/m^3" if ring.get("unit_weight")
              else "")
    if ring.get("fill_E") is not None:
        weight += (f"; a fill inside it, E = {ring['fill_E']:.4g} Pa, nu = "
                   f"{ring.get('fill_nu', 0.3):g} (linear)")
    return (f"r = {ring['inner_radius']:g} to {ring['outer_radius']:g} m, {ring['depth']:g} m "
            f"deep, E = {ring['E']:.4g} Pa, nu = {ring.get('nu', 0.2):g} (linear){weight}")


def member_text(name: str, part: Mapping[str, Any], K: float) -> str:
    """The plate's or wall's geometry in words, as `tankfx check` and the report write it
    (``part``: its table of :meth:`Scene.to_dict`; ``K``: its Kp or Kt)."""
    if name == "plate":
        ring = (f" (annular ring {part['annular_width']:g} m wide, "
                f"{part['annular_thickness']:.4g} m thick)" if part.get("annular_width") else "")
        return (f"a = {part['radius']:g} m, t = {part['thickness']:.4g} m{ring}, Kp = {K:.4g}, "
                f"embedment {part.get('embedment', 0.0):g} m")
    courses = part.get("courses")
    t = (f"{len(courses)} courses (height x thickness from the bottom: "
         + ", ".join(f"{c['height']:g} m x {1e3 * c['thickness']:.4g} mm" for c in courses)
         + ")") if courses else f"t = {part['thickness']:.4g} m"
    return (f"a_t = {part['radius']:g} m, {t}, H = {part['height']:g} m, Kt = {K:.4g}"
            + (" (bottom course)" if courses else ""))


@dataclass(frozen=True)
class Soil:
    E: float                 #: Young's modulus at the ground surface, Pa (1/a if hyperbolic)
    nu: float                #: Poisson's ratio
    E_gradient: float = 0.0  #: lambda, 1/m: E(h) = E (1 + lambda h), h = depth below surface
    model: str = "linear"    #: "linear" or "hyperbolic" (Kondner)
    hyperbolic_a: float | None = None  #: 1/a = initial tangent modulus (hyperbolic model)
    hyperbolic_b: float | None = None  #: 1/b = ultimate deviator stress (hyperbolic model)
    tolerance: float | None = None     #: Eq. 18's relative deviator misfit (hyperbolic)
    max_iterations: int | None = None  #: Picard iterations at most (hyperbolic)
    # Duncan & Chang's soil (model = "duncan_chang"): Kondner's law with the initial modulus
    # K p_a (sigma_3 / p_a)^n and the ultimate deviator (Mohr-Coulomb strength) / R_f of
    # each cell's confining stress: geostatic (unit weight, K0) plus the tank's
    modulus_number: float | None = None      #: K
    modulus_exponent: float | None = None    #: n
    failure_ratio: float | None = None       #: R_f = (sigma_1 - sigma_3)_f / ultimate
    cohesion: float | None = None            #: c, Pa
    friction_angle: float | None = None      #: phi, degrees
    unit_weight: float | None = None         #: gamma, N/m^3 (geostatic stress)
    K0: float | None = None                  #: horizontal / vertical geostatic stress
    atmospheric_pressure: float | None = None  #: p_a, Pa
    #: depth of the water table, m (None: below everything): the confinement is effective,
    #: the geostatic stress less the hydrostatic pore pressure below it
    water_table: float | None = None
    water_unit_weight: float | None = None   #: gamma_w, N/m^3
    #: the strata below the surface soil (which the keys above describe, from the surface
    #: down to the first layer's top), top down
    layers: tuple[Layer, ...] = ()
    #: E_ur / E_i of a nonlinear soil along a load path: a cell whose strain falls below the
    #: largest it has had unloads (and reloads) linearly with E_ur = this times its initial
    #: modulus (Duncan & Chang's: at its current confinement, K_ur = this x K) and keeps its
    #: permanent strain; None: the paper's nonlinear elastic secant law, which unloads
    #: along its loading curve
    unloading_modulus_ratio: float | None = None

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
    radius: float            #: a_p, m
    thickness: float         #: t_p, m (given, or derived from Kp by Eq. 21): the floor's
    E: float                 #: Pa
    nu: float
    embedment: float = 0.0   #: depth of the underside below the ground surface, m
    unit_weight: float = 0.0  #: N/m^3, used only when load.self_weight is true
    #: a ring of another thickness along the edge, under the wall (an API 650 tank's
    #: annular bottom plate, or a thickened edge): its width inward from the edge, m (0:
    #: none), and its thickness, m. The underside stays flat; Kp is the floor's.
    annular_width: float = 0.0
    annular_thickness: float | None = None

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
    radius: float            #: a_t, m (<= plate radius)
    thickness: float         #: t_t, m (given, or derived from Kt by Eq. 22): the bottom course's
    height: float            #: H, m, measured from the plate
    E: float
    nu: float
    unit_weight: float = 0.0
    #: the courses of a wall whose thickness steps, (height, thickness) in m from the bottom
    #: up, their outer faces flush (empty: one course of ``thickness``, the paper's wall)
    courses: tuple[tuple[float, float], ...] = ()

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

    inner_radius: float
    outer_radius: float
    depth: float
    E: float                 #: Pa
    nu: float = 0.2
    #: N/m^3, used only when load.self_weight is true: its weight in excess of the soil it
    #: replaces (the soil's own weight is the ground's initial state, not a load here)
    unit_weight: float = 0.0
    #: Pa and -: a compacted fill inside the ring, from the plate's underside to the ring's
    #: depth (linear elastic; None: the soil itself)
    fill_E: float | None = None
    fill_nu: float = 0.3

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
    condition: str = "bonded"   #: "bonded" | "smooth" | "mohr_coulomb"
    cohesion: float = 0.0       #: Pa
    tan_phi: float | None = None
    normal_stiffness: float | None = None  #: Pa/m
    shear_stiffness: float | None = None   #: Pa/m
    #: what a cycling Mohr-Coulomb active set gets: "hold" its alternating elements in the
    #: weaker state and go on (reported), or "stop" with the history
    on_cycle: str = "hold"
    #: where a Mohr-Coulomb state lives: "element" (the paper's Eqs. 11-12: one state per
    #: interface element, from its average jump) or "node" (one per node of the soil's trace,
    #: at the Gauss-Lobatto points of each facet, which then integrate the interface)
    states: str = "element"


@dataclass(frozen=True)
class Load:
    pressure: float = 0.0            #: uniform pressure, Pa, positive downward
    load_radius: float | None = None  #: m; the plate radius when there is a plate
    liquid_unit_weight: float = 0.0  #: N/m^3
    liquid_height: float = 0.0       #: m
    self_weight: bool = False
    #: N: the roof's weight and what it carries (snow, equipment), borne by the wall's top
    #: edge (a ring load of roof_weight / (2 pi a_t) N/m)
    roof_weight: float = 0.0
    #: Pa: a gas (vapour) pressure in the closed tank, above the liquid: on the floor (down),
    #: the wall (outward) and the roof, which carries it to the wall's top (up); no net
    #: vertical load on the foundation. Negative: a vacuum
    gas_pressure: float = 0.0
    #: N m: an overturning moment (wind, earthquake) about the plate's underside at the
    #: axis, pressing the side theta = 0 down; with a wall it reaches the foundation through
    #: the wall's foot (API 650 Annex E's ringwall moment). Solved as the first Fourier
    #: harmonic about the axisymmetric state (tankfx.rocking)
    overturning_moment: float = 0.0
    #: N: the horizontal force that comes with it (towards theta = 0), carried by the wall
    #: (or the plate) to the interface
    base_shear: float = 0.0

    @property
    def overturning(self) -> bool:
        """Whether the load has a first-harmonic part (an overturning moment or shear)."""
        return bool(self.overturning_moment or self.base_shear)


@dataclass(frozen=True)
class Consolidation:
    """Biot's consolidation of a saturated soil (tankfx.consolidation): the load is applied
    at t = 0, when the soil answers undrained, and held while the excess pore pressure
    drains; the soil's E and nu are then its drained (effective) constants."""

    permeability: float                 #: m/s, Darcy's coefficient k (isotropic)
    times: tuple[float, ...]            #: s, the times at which results are reported
    water_unit_weight: float = 9810.0   #: N/m^3
    #: the drained boundaries: "top" (the ground surface; a flexible load's loaded area
    #: too) or "top_and_bottom" (also the domain's base: a clay on sand); the foundation,
    #: the pit's sides and the far side are impervious
    drainage: str = "top"
    #: time steps per decade of time (BDF2; 10 keep Terzaghi's settlement within 0.6 %)
    steps_per_decade: int = 10


@dataclass(frozen=True)
class DomainSize:
    radius: float   #: m, outer radius of the soil domain
    depth: float    #: m, depth of the rigid base


@dataclass(frozen=True)
class MeshOptions:
    degree: int = 2            #: Lagrange degree of the soil displacement
    edge_size: float = 0.0     #: element size at the foundation edge, m (resolved default)
    growth: float = 0.2        #: rate at which the element size grows with distance
    near_size: float = 0.0     #: element size cap within 6 radii of the centre, m (resolved)


@dataclass(frozen=True)
class SolverOptions:
    method: str = "direct"      #: "direct" (MUMPS) or "iterative" (Krylov + GAMG)
    rtol: float = 1e-10         #: relative residual of the iterative solve
    max_iterations: int = 1000  #: Krylov iterations allowed per solve


@dataclass(frozen=True)
class Scene:
    soil: Soil
    load: Load
    domain: DomainSize
    mesh: MeshOptions
    plate: Plate | None = None
    wall: Wall | None = None
    interface: Interface = field(default_factory=Interface)
    ringwall: Ringwall | None = None
    solver: SolverOptions = field(default_factory=SolverOptions)
    #: time-dependent settlement of a saturated soil (None: the soil answers at once)
    consolidation: Consolidation | None = None
    title: str = "tankfx scene"
    #: a load path: the total loads analysed in order on one mesh, the interface's states
    #: carried from each to the next (``[[stages]]`` tables of a scene file, each the
    #: [load] keys that change); empty: the one load of [load]
    stages: tuple[Load, ...] = ()
    #: with [consolidation]: the time (s) at which each stage's load is reached, linearly
    #: from the stage before's (from no load at t = 0 for the first; a time equal to the
    #: one before: at once); empty without stages or without a consolidation
    stage_times: tuple[float, ...] = ()

    @property
    def foundation_radius(self) -> float:
        """Radius of the plate, or of the flexible load where there is no plate, m."""
        return self.plate.radius if self.plate is not None else self.load.load_radius

    @property
    def embedment(self) -> float:
        return self.plate.embedment if self.plate is not None else 0.0

    @property
    def Kp(self) -> float | None:
        """Relative rigidity of the plate-soil system, Eq. 21 (surface soil modulus)."""
        if self.plate is None:
            return None
        return Kp_from_thickness(self.plate.thickness, self.plate.radius, self.plate.E,
                                 self.soil.E, self.soil.nu)

    @property
    def Kt(self) -> float | None:
        """Relative rigidity of the wall-soil system, Eq. 22 (surface soil modulus)."""
        if self.wall is None:
            return None
        return Kp_from_thickness(self.wall.thickness, self.wall.radius, self.wall.E,
                                 self.soil.E, self.soil.nu)

    def unloading_stages(self) -> list[int]:
        """The load stages (counted from 1) whose vertical load is less than the largest of
        the stages before them: unloading."""
        loads = [vertical_load(ld, self.plate, self.wall, self.ringwall)
                 for ld in self.stages]
        return [k + 1 for k in range(1, len(loads)) if loads[k] < max(loads[:k]) * (1 - 1e-12)]

    def with_coarse_mesh(self) -> "Scene":
        """The same scene on a coarse mesh (edge 0.01 a, near field 0.25 a, growth 0.3):
        a quick look, as the demos' ``--coarse`` and the tests use it; a few tenths of a
        per cent on w0, a few per cent on the edge moments."""
        a = self.foundation_radius
        return self.with_changes(mesh={"edge_size": 0.01 * a, "near_size": 0.25 * a,
                                       "growth": 0.3})

    def with_changes(self, **sections: dict[str, Any]) -> "Scene":
        """A new scene with some keys of some sections changed, e.g.
        ``scene.with_changes(mesh={"degree": 1})``; a key changed to None is removed (back
        to its default, e.g. ``plate={"annular_width": None, "annular_thickness": None}``);
        the result is validated again."""
        d = self.to_dict()
        for sec, changes in sections.items():
            if isinstance(changes, dict):
                if sec == "soil" and "E" not in changes and set(E_FROM_KEYS) & set(changes):
                    d["soil"].pop("E", None)      # 1/a or K p_a: the new one's
                d.setdefault(sec, {}).update(changes)
                d[sec] = {k: v for k, v in d[sec].items() if v is not None}
            else:
                d[sec] = changes
        return Scene.from_dict(d)

    def to_dict(self) -> dict[str, Any]:
        """The scene as a plain dict, re-readable by :meth:`from_dict` (resolved values)."""
        out: dict[str, Any] = {"title": self.title}
        for name in ("soil", "plate", "wall", "ringwall", "interface", "load", "domain",
                     "mesh", "solver", "consolidation"):
            part = getattr(self, name)
            if part is not None:
                out[name] = _plain(part)
        if self.soil.layers:
            out["soil"]["layers"] = [_plain(layer) for layer in self.soil.layers]
        else:
            out["soil"].pop("layers", None)
        if self.plate is not None and not self.plate.annular_width:
            out["plate"].pop("annular_width")
        if self.ringwall is not None and self.ringwall.fill_E is None:
            out["ringwall"].pop("fill_nu")          # no fill
        if self.wall is not None:
            if self.wall.courses:       # the courses replace the one thickness
                del out["wall"]["thickness"]
                out["wall"]["courses"] = [{"height": h, "thickness": t}
                                          for h, t in self.wall.courses]
            else:
                del out["wall"]["courses"]
        if self.plate is None:
            del out["interface"]
        elif self.interface.condition != "mohr_coulomb":
            for key in ("cohesion", "tan_phi", "on_cycle", "states"):
                out["interface"].pop(key, None)
        if self.stages:
            # each stage as the [load] keys it changes, as written in a scene file: a
            # change of [load] (a sweep's axis, with_changes) then reaches every stage
            # that does not set that key itself
            out["stages"] = [{k: v for k, v in _plain(ld).items() if out["load"].get(k) != v}
                             for ld in self.stages]
            for stage, t in zip(out["stages"], self.stage_times):
                stage["time"] = t
        return out

    def to_toml(self) -> str:
        """The scene as a scene file with every value resolved (the defaults written out,
        a thickness for a Kp); :func:`load_scene` reads it back to an equal scene."""
        d = self.to_dict()
        lines = [f"title = {_toml_value(d.pop('title'))}", ""]
        stages = d.pop("stages", [])
        for name, values in d.items():
            layers = values.pop("layers", []) if name == "soil" else []
            lines += [f"[{name}]", *(f"{k} = {_toml_value(v)}" for k, v in values.items()), ""]
            for layer in layers:
                lines += ["[[soil.layers]]",
                          *(f"{k} = {_toml_value(v)}" for k, v in layer.items()), ""]
        for stage in stages:
            lines += ["[[stages]]", *(f"{k} = {_toml_value(v)}" for k, v in stage.items()), ""]
        return "\n".join(lines)

    @staticmethod
    def from_dict(data: dict[str, Any]) -> "Scene":
        return _parse_scene(data)

    @staticmethod
    def from_toml(path: str | Path) -> "Scene":
        return load_scene(path)


# --------------------------------------------------------------------------- relations
def vertical_load(load: Load, plate: Plate | None, wall: Wall | None,
                  ringwall: "Ringwall | None" = None) -> float:
    """The load's resultant, N, downward positive: the pressure on the plate (or the loaded
    circle), the liquid on the floor, the roof's weight on the wall, and the structure's
    (and a ringwall's net) weight when asked for. A gas pressure adds nothing: it presses
    the floor down as hard as it lifts the roof."""
    a = plate.radius if plate is not None else load.load_radius
    net = load.pressure * math.pi * a**2
    if wall is not None:
        net += load.liquid_unit_weight * load.liquid_height * math.pi * wall.radius**2
        net += load.roof_weight
    if load.self_weight and plate is not None:
        net += plate.unit_weight * plate.volume
        if wall is not None:
            net += wall.unit_weight * wall.volume
        if ringwall is not None:
            net += ringwall.unit_weight * ringwall.volume
    return net


def vertical_load_scale(load: Load, plate: Plate | None, wall: Wall | None,
                        ringwall: "Ringwall | None" = None) -> float:
    """The size of the vertical loads, N, for relative equilibrium errors: the resultant's,
    and a gas pressure's force on the floor, which the roof's cancels in the resultant."""
    gas = abs(load.gas_pressure) * math.pi * wall.radius**2 if wall is not None else 0.0
    return abs(vertical_load(load, plate, wall, ringwall)) + gas


def Kp_from_thickness(t: float, a: float, E: float, E_s: float, nu_s: float) -> float:
    """Eqs. 21-22: K = (1 - nu_s^2) (E / E_s) (t / a)^3."""
    return (1.0 - nu_s**2) * (E / E_s) * (t / a) ** 3


def plate_thickness_from_Kp(K: float, a: float, E: float, E_s: float, nu_s: float) -> float:
    """Inverse of Eqs. 21-22: the thickness that gives relative rigidity K."""
    return a * (K * E_s / ((1.0 - nu_s**2) * E)) ** (1.0 / 3.0)


def _toml_value(v) -> str:
    """A value as TOML writes it (the scene's values are finite: checked on reading); a list
    of tables (a wall's courses) as inline tables."""
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)        # a TOML basic string
    return repr(v)


def _plain(part) -> dict[str, Any]:
    """A section's dataclass as the dict of its set values."""
    return {f.name: getattr(part, f.name) for f in fields(part)
            if getattr(part, f.name) is not None}


# --------------------------------------------------------------------------- parsing
_SPEC: dict[str, dict[str, tuple[type, bool]]] = {
    # section: key -> (type, required)
    "soil": {"E": (float, False), "nu": (float, True), "E_gradient": (float, False),
             "model": (str, False), "hyperbolic_a": (float, False),
             "hyperbolic_b": (float, False), "tolerance": (float, False),
             "max_iterations": (int, False), "modulus_number": (float, False),
             "modulus_exponent": (float, False), "failure_ratio": (float, False),
             "cohesion": (float, False), "friction_angle": (float, False),
             "unit_weight": (float, False), "K0": (float, False),
             "atmospheric_pressure": (float, False), "water_table": (float, False),
             "water_unit_weight": (float, False), "unloading_modulus_ratio": (float, False)},
    "plate": {"radius": (float, True), "thickness": (float, False), "Kp": (float, False),
              "E": (float, True), "nu": (float, True), "embedment": (float, False),
              "unit_weight": (float, False), "annular_width": (float, False),
              "annular_thickness": (float, False)},
    "wall": {"radius": (float, True), "thickness": (float, False), "Kt": (float, False),
             "height": (float, False), "E": (float, True), "nu": (float, True),
             "unit_weight": (float, False), "courses": (list, False)},
    "ringwall": {"inner_radius": (float, True), "outer_radius": (float, True),
                 "depth": (float, True), "E": (float, True), "nu": (float, False),
                 "unit_weight": (float, False), "fill_E": (float, False),
                 "fill_nu": (float, False)},
    "interface": {"condition": (str, False), "cohesion": (float, False),
                  "tan_phi": (float, False), "friction_angle": (float, False),
                  "normal_stiffness": (float, False), "shear_stiffness": (float, False),
                  "on_cycle": (str, False), "states": (str, False)},
    "load": {"pressure": (float, False), "load_radius": (float, False),
             "liquid_unit_weight": (float, False), "liquid_height": (float, False),
             "self_weight": (bool, False), "roof_weight": (float, False),
             "gas_pressure": (float, False), "overturning_moment": (float, False),
             "base_shear": (float, False)},
    "domain": {"radius": (float, False), "depth": (float, False)},
    "mesh": {"degree": (int, False), "edge_size": (float, False), "growth": (float, False),
             "near_size": (float, False)},
    "solver": {"method": (str, False), "rtol": (float, False), "max_iterations": (int, False)},
    "consolidation": {"permeability": (float, True), "times": (list, True),
                      "water_unit_weight": (float, False), "drainage": (str, False),
                      "steps_per_decade": (int, False)},
}
#: the keys of one [[soil.layers]] table
_LAYER_SPEC: dict[str, tuple[type, bool]] = {
    "depth": (float, True), "nu": (float, True), "permeability": (float, False),
    **{key: (float, False) for key in ("E", "E_gradient", "hyperbolic_a", "hyperbolic_b",
                                       *STRATUM_DUNCAN_CHANG)}}
_SOLVER_METHODS = ("direct", "iterative")
_TOP = {"title": str}
_REQUIRED_SECTIONS = ("soil", "load")
_SOIL_MODELS = ("linear", "hyperbolic", "duncan_chang")
#: the keys of Duncan & Chang's soil, and those of them it requires
_DUNCAN_CHANG = (*STRATUM_DUNCAN_CHANG, "atmospheric_pressure", "water_table",
                 "water_unit_weight")
#: gamma_w, N/m^3
WATER_UNIT_WEIGHT = 9810.0
_DUNCAN_CHANG_REQUIRED = ("modulus_number", "modulus_exponent", "unit_weight")
#: p_a, Pa: the reference pressure of Duncan & Chang's modulus
ATMOSPHERIC_PRESSURE = 101325.0
_CONDITIONS = ("bonded", "smooth", "mohr_coulomb")
_ON_CYCLE = ("hold", "stop")
_STATES = ("element", "node")
_DRAINAGE = ("top", "top_and_bottom")


def _suggest(name: str, valid) -> str:
    close = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.5)
    return f" (did you mean '{close[0]}'?)" if close else f" (valid: {', '.join(valid)})"


class _Reader:
    """Collects every problem of a scene dict instead of stopping at the first."""

    def __init__(self, data: dict[str, Any]):
        self.data = data
        self.problems: list[str] = []

    def bad(self, msg: str) -> None:
        self.problems.append(msg)

    def choice(self, table: dict, name: str, key: str, default: str, allowed,
               meaning: str = "") -> str:
        """``table[key]`` (or ``default``), which must be one of ``allowed``: else a problem
        naming it, the nearest allowed value and, if given, what each means."""
        value = table.get(key, default)
        if value not in allowed:
            self.bad(f"{name}.{key} = {value!r}: unknown{_suggest(value, allowed)}"
                     + (f" ({meaning})" if meaning else ""))
        return value

    def section(self, name: str) -> dict[str, Any] | None:
        sec = self.data.get(name)
        if sec is None:
            return None
        if not isinstance(sec, dict):
            self.bad(f"[{name}] must be a table (a '[{name}]' header followed by keys), "
                     f"not {type(sec).__name__}")
            return None
        out = {}
        for key, value in sec.items():
            spec = _SPEC[name].get(key)
            if spec is None:
                self.bad(f"{name}.{key}: unknown key{_suggest(key, _SPEC[name])}")
                continue
            typ, _ = spec
            checked = self._typed(f"{name}.{key}", value, typ)
            if checked is not None:
                out[key] = checked
        for key, (_, required) in _SPEC[name].items():
            if required and key not in sec:
                self.bad(f"{name}.{key}: missing; add '{key} = ...' under [{name}]")
        return out

    def _typed(self, where: str, value, typ):
        if typ is list:
            return value                # checked by its section's own rules
        if typ is float:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                self.bad(f"{where}: expected a number, got {value!r}")
                return None
            if not math.isfinite(value):
                self.bad(f"{where}: must be a finite number, got {value!r}")
                return None
            return float(value)
        if typ is int:
            if isinstance(value, bool) or not isinstance(value, int):
                self.bad(f"{where}: expected an integer, got {value!r}")
                return None
            return value
        if typ is bool:
            if not isinstance(value, bool):
                self.bad(f"{where}: expected true or false, got {value!r}")
                return None
            return value
        if not isinstance(value, str):
            self.bad(f"{where}: expected a string, got {value!r}")
            return None
        return value

    def positive(self, sec: dict, name: str, key: str, *, allow_zero: bool = False) -> None:
        v = sec.get(key)
        if v is None:
            return
        if v < 0 or (v == 0 and not allow_zero):
            need = ">= 0" if allow_zero else "> 0"
            self.bad(f"{name}.{key} = {v!r}: must be {need}")

    def poisson(self, sec: dict, name: str, key: str = "nu", incompressible=False) -> None:
        """(-1, 0.5) for the shells; the soil may be incompressible (0.5, mixed form)."""
        v = sec.get(key)
        if v is None:
            return
        if incompressible and not -1.0 < v <= 0.5:
            self.bad(f"{name}.{key} = {v!r}: Poisson's ratio must lie in (-1, 0.5] (0.5: "
                     f"incompressible, e.g. undrained clay)")
        elif not incompressible and not -1.0 < v < 0.5:
            self.bad(f"{name}.{key} = {v!r}: Poisson's ratio must lie in (-1, 0.5) for a "
                     f"plate or wall (thin-shell theory; use e.g. 0.3)")


def _parse(data: dict[str, Any], empty_load: bool = False) -> Scene:
    """The scene of a dict, checked; ``empty_load``: a [load] without any load is allowed
    (a stage of a consolidation's load path: the tank emptied)."""
    if not isinstance(data, dict):
        raise SceneError([f"a scene must be a table of sections, got {type(data).__name__}"])
    if "stages" in data:
        rest = {k: v for k, v in data.items() if k != "stages"}
        raw, times = _stage_times(data["stages"], "consolidation" in data)
        scene = _parse(rest)
        stages = _parse_stages(rest, raw, scene)
        if times and max(scene.consolidation.times) < times[-1]:
            raise SceneError([f"consolidation.times: the last, {max(scene.consolidation.times)!r}"
                              f" s, is before the load path's end (the last stage's time, "
                              f"{times[-1]!r} s); report at least to the end of the path"])
        if times and len({ld.self_weight for ld in stages}) > 1:
            raise SceneError(["stages: self_weight changes along a consolidation's load "
                              "path; the structure's own weight acts from t = 0 (it is built "
                              "before it is loaded): give every stage the same self_weight"])
        return replace(scene, stages=stages, stage_times=times)
    soil_raw, raw_layers = data.get("soil"), None
    if isinstance(soil_raw, dict) and "layers" in soil_raw:
        raw_layers = soil_raw["layers"]
        data = {**data, "soil": {k: v for k, v in soil_raw.items() if k != "layers"}}
    rd = _Reader(data)
    for key, value in data.items():
        if key in _TOP:
            if not isinstance(value, _TOP[key]):
                rd.bad(f"{key}: expected a string, got {value!r}")
        elif key not in _SPEC:
            rd.bad(f"[{key}]: unknown section"
                   f"{_suggest(key, [*_SPEC, *_TOP, 'stages'])}")
    for name in _REQUIRED_SECTIONS:
        if name not in data:
            rd.bad(f"[{name}]: missing section; add a '[{name}]' table (see README)")
    secs = {name: rd.section(name) for name in _SPEC}

    soil = secs["soil"]
    layers = _check_soil(rd, soil, raw_layers, "consolidation" in data)

    plate = secs["plate"]
    if plate is not None:
        for key in ("radius", "E", "thickness", "Kp", "annular_width", "annular_thickness"):
            rd.positive(plate, "plate", key)
        rd.positive(plate, "plate", "embedment", allow_zero=True)
        rd.positive(plate, "plate", "unit_weight", allow_zero=True)
        rd.poisson(plate, "plate")
        if "thickness" in plate and "Kp" in plate:
            rd.bad("plate.thickness and plate.Kp: give one of them, not both "
                   "(Kp fixes the thickness through Eq. 21)")
        elif "thickness" not in plate and "Kp" not in plate:
            rd.bad("plate.thickness: missing; give 'thickness = ...' (m) or 'Kp = ...'")
        _check_annular_ring(rd, plate, secs["wall"])

    wall = secs["wall"]
    if wall is not None:
        for key in ("radius", "E", "thickness", "Kt", "height"):
            rd.positive(wall, "wall", key)
        rd.positive(wall, "wall", "unit_weight", allow_zero=True)
        rd.poisson(wall, "wall")
        courses = _courses(rd, wall)
        if courses is not None:
            for key in ("thickness", "Kt"):
                if key in wall:
                    rd.bad(f"wall.{key} and wall.courses: give one of them, not both (the "
                           f"courses give the wall's thickness, the bottom one its Kt)")
            total = sum(h for h, _ in courses)
            whole = courses and len(courses) == len(wall["courses"])   # every one sane
            if "height" not in wall and whole:
                wall["height"] = total           # the courses' sum
            elif whole and "height" in wall \
                    and not math.isclose(wall["height"], total, rel_tol=1e-9):
                rd.bad(f"wall.courses: their heights add up to {total!r} m, but wall.height "
                       f"= {wall['height']!r} m; make them equal, or omit wall.height (it "
                       f"is then the courses' sum)")
        elif "thickness" in wall and "Kt" in wall:
            rd.bad("wall.thickness and wall.Kt: give one of them, not both "
                   "(Kt fixes the thickness through Eq. 22)")
        elif "thickness" not in wall and "Kt" not in wall:
            rd.bad("wall.thickness: missing; give 'thickness = ...' (m), 'Kt = ...' or "
                   "'courses = [{height = ..., thickness = ...}, ...]'")
        if "height" not in wall and courses is None:   # (bad courses are reported)
            rd.bad("wall.height: missing; add 'height = ...' under [wall] (m, from the "
                   "plate up)")
        if "plate" not in data:
            rd.bad("[wall]: a wall needs a foundation plate to stand on; add a [plate] table")
        elif plate is not None and "radius" in wall and "radius" in plate \
                and wall["radius"] > plate["radius"]:
            rd.bad(f"wall.radius = {wall['radius']!r} is wider than plate.radius = "
                   f"{plate['radius']!r}: the wall must stand on the plate "
                   f"(wall.radius <= plate.radius)")

    interface = secs["interface"] or {}
    cond = rd.choice(interface, "interface", "condition", "bonded", _CONDITIONS)
    if "tan_phi" in interface and "friction_angle" in interface:
        rd.bad("interface.tan_phi and interface.friction_angle: give one of them, not both")
    rd.positive(interface, "interface", "tan_phi", allow_zero=True)
    rd.positive(interface, "interface", "cohesion", allow_zero=True)
    rd.positive(interface, "interface", "normal_stiffness")
    rd.positive(interface, "interface", "shear_stiffness")
    fa = interface.get("friction_angle")
    if fa is not None and not (0.0 <= fa < 90.0):
        rd.bad(f"interface.friction_angle = {fa!r}: degrees, must lie in [0, 90)")
    if cond == "mohr_coulomb" and "tan_phi" not in interface \
            and "friction_angle" not in interface:
        rd.bad("interface.tan_phi: missing for condition = \"mohr_coulomb\"; give tan_phi or "
               "friction_angle (degrees)")
    on_cycle = rd.choice(interface, "interface", "on_cycle", "hold", _ON_CYCLE,
                         "\"hold\": hold the alternating elements in the weaker state and "
                         "go on; \"stop\": stop with the iteration history")
    states = rd.choice(interface, "interface", "states", "element", _STATES,
                       "\"element\": one state per interface element; \"node\": one per "
                       "node")
    if cond != "mohr_coulomb":
        for key in ("cohesion", "tan_phi", "friction_angle", "on_cycle", "states"):
            if key in interface:
                rd.bad(f"interface.{key}: only used with condition = \"mohr_coulomb\"; remove "
                       f"it or change the condition")
    if "plate" not in data and "interface" in data:
        rd.bad("[interface]: an interface needs a [plate]; remove it for a flexible load")

    load = secs["load"]
    if load is not None:
        rd.positive(load, "load", "load_radius")
        rd.positive(load, "load", "liquid_unit_weight", allow_zero=True)
        rd.positive(load, "load", "liquid_height", allow_zero=True)
        rd.positive(load, "load", "roof_weight", allow_zero=True)
        if load.get("roof_weight", 0.0) > 0 and "wall" not in data:
            rd.bad("load.roof_weight: a roof needs a [wall] to stand on; add a [wall] table or "
                   "give the roof's weight as a pressure on the plate")
        if load.get("gas_pressure", 0.0) != 0 and "wall" not in data:
            rd.bad("load.gas_pressure: a gas pressure needs a closed tank, a [wall] with its "
                   "roof; add a [wall] table or give a pressure on the plate instead")
        for key in ("overturning_moment", "base_shear"):
            if load.get(key, 0.0) and "plate" not in data:
                rd.bad(f"load.{key}: overturning needs a foundation to tilt; add a [plate] "
                       f"(a flexible load has no structure to carry it)")
        if "plate" not in data:
            if "load_radius" not in load:
                rd.bad("load.load_radius: missing; without a [plate] the load is a flexible "
                       "uniform pressure on r <= load_radius; add 'load_radius = ...' (m)")
            for key in ("liquid_unit_weight", "liquid_height", "self_weight"):
                if load.get(key):
                    rd.bad(f"load.{key}: needs a [plate] (and for liquid a [wall]); remove it "
                           f"or add the structure")
        if load.get("liquid_height", 0.0) > 0 and load.get("liquid_unit_weight", 0.0) == 0:
            rd.bad("load.liquid_unit_weight: missing for a liquid of load.liquid_height; add "
                   "it (N/m^3, e.g. 9810 for water)")
        elif plate is not None and "load_radius" in load and "radius" in plate \
                and load["load_radius"] != plate["radius"]:
            rd.bad(f"load.load_radius = {load['load_radius']!r}: with a [plate] the pressure "
                   f"acts on the whole plate (radius {plate.get('radius')!r}); remove "
                   f"load.load_radius")
        if load.get("liquid_height", 0.0) > 0 and "wall" not in data:
            rd.bad("load.liquid_height: a liquid needs a [wall] to hold it; add a [wall] table")
        if wall is not None and "height" in wall \
                and load.get("liquid_height", 0.0) > wall["height"] * (1 + 1e-9):
            rd.bad(f"load.liquid_height = {load['liquid_height']!r} is higher than wall.height = "
                   f"{wall['height']!r}: the tank would overflow; lower the liquid")
        if load.get("pressure", 0.0) < 0.0 and "plate" not in data:
            rd.bad(f"load.pressure = {load['pressure']!r}: a flexible load must press "
                   f"(>= 0); an upward pressure needs a [plate] to pull on")
        if load.get("pressure", 0.0) == 0.0 and load.get("liquid_height", 0.0) * \
                load.get("liquid_unit_weight", 0.0) == 0.0 and not load.get("self_weight", False) \
                and not load.get("roof_weight", 0.0) and not load.get("gas_pressure", 0.0) \
                and not load.get("overturning_moment", 0.0) and not load.get("base_shear", 0.0) \
                and not empty_load:
            rd.bad("[load]: no load is applied; give load.pressure > 0 (Pa), a liquid, "
                   "self_weight = true, a roof_weight, a gas_pressure or an "
                   "overturning_moment")

    mesh = secs["mesh"] or {}
    # a flexible load (no plate) defaults to P3 on a mesh twice as coarse: the soil alone
    # decides its error, and there that is on the efficient front (README "Every case")
    flexible = "plate" not in data
    deg = mesh.get("degree", FLEXIBLE_DEGREE if flexible else 2)
    if deg not in (1, 2, 3):
        rd.bad(f"mesh.degree = {deg!r}: must be 1, 2 or 3 (the default: 2 under a plate, 3 "
               f"for a flexible load)")
    nus = [x.get("nu") for x in [soil or {}, *layers]]
    nus = [v for v in nus if isinstance(v, (int, float))]
    nu_s = max(nus) if nus else None
    if (soil or {}).get("model") == "duncan_chang" and nus:
        # solved in the mixed form throughout (a failed cell's nu tends to 0.5)
        if min(nus) <= 0.0:
            rd.bad(f"soil nu = {min(nus)!r}: Duncan & Chang's soil is solved in the mixed "
                   f"form, which takes 1 / lambda, infinite at nu = 0; use nu > 0")
        nu_s = 0.5
    solver = secs["solver"] or {}
    method = solver.get("method", "direct")
    if isinstance(method, str) and method not in _SOLVER_METHODS:
        rd.bad(f"solver.method = {method!r}: one of {', '.join(_SOLVER_METHODS)}"
               f"{_suggest(method, _SOLVER_METHODS)}")
    rtol = solver.get("rtol")
    if isinstance(rtol, (int, float)) and not 0.0 < rtol <= 1e-4:
        rd.bad(f"solver.rtol = {rtol!r}: must lie in (0, 1e-4] (the results are checked to "
               f"1e-6 of the load)")
    if isinstance(solver.get("max_iterations"), int) and solver["max_iterations"] < 1:
        rd.bad(f"solver.max_iterations = {solver['max_iterations']!r}: must be >= 1")
    mixed_why = ("Duncan & Chang's soil (a failed cell's nu tends to 0.5)"
                 if (soil or {}).get("model") == "duncan_chang" else f"soil nu = {nu_s!r}")
    if method == "iterative" and nu_s is not None and nu_s > MIXED_FROM_NU:
        rd.bad(f"solver.method = \"iterative\" with {mixed_why}: the mixed form of a "
               f"nearly incompressible soil (nu > {MIXED_FROM_NU}) has a zero pressure block "
               f"that GAMG cannot take; use method = \"direct\"")
    if deg == 1 and nu_s is not None and nu_s > MIXED_FROM_NU:
        rd.bad(f"mesh.degree = 1 with {mixed_why}: a nearly incompressible soil is "
               f"solved in the mixed (Taylor-Hood) form, which needs degree 2 or 3; use "
               f"degree 2 or 3")
    rd.positive(mesh, "mesh", "edge_size")
    rd.positive(mesh, "mesh", "near_size")
    g = mesh.get("growth")
    if g is not None and not (0.0 < g <= 1.0):
        rd.bad(f"mesh.growth = {g!r}: must lie in (0, 1] (element size grows by this "
               f"fraction of the distance from the foundation edge)")

    domain = secs["domain"] or {}
    rd.positive(domain, "domain", "radius")
    rd.positive(domain, "domain", "depth")
    # sizes relative to the foundation, where the foundation's size is known
    a = (plate or {}).get("radius") if "plate" in data else (load or {}).get("load_radius")
    D = (plate or {}).get("embedment", 0.0) if "plate" in data else 0.0
    if a is not None and a > 0:
        default = DEFAULT_DOMAIN_FACTOR * a
        if domain.get("radius", default) <= 2.0 * a:
            rd.bad(f"domain.radius = {domain['radius']!r} m: must exceed twice the foundation "
                   f"radius ({2 * a!r} m) for the soil to surround the structure; omit it for "
                   f"the half-space default ({default:g} m)")
        # a rigid base may lie shallower than the foundation is wide (a wide tank on a
        # thin soft layer over rock), but below the foundation
        if domain.get("depth", default) <= D:
            rd.bad(f"domain.depth = {domain.get('depth', default)!r} m: the rigid base must lie "
                   f"below the foundation's underside (embedment {D!r} m); deepen the domain "
                   f"or omit domain.depth for the half-space default ({default:g} m)")
        base = domain.get("depth", default)
        for k, layer in enumerate(layers, start=1):
            if layer.get("depth", 0.0) >= base:
                rd.bad(f"soil.layers[{k}].depth = {layer['depth']!r} m: at or below the rigid "
                       f"base (domain.depth = {base!r} m); deepen the domain or remove the "
                       f"layer")
        if mesh.get("edge_size", 0.0) > 0.5 * a:
            rd.bad(f"mesh.edge_size = {mesh['edge_size']!r} m: larger than half the foundation "
                   f"radius ({0.5 * a!r} m); the foundation would not be resolved")

    if secs["ringwall"] is not None:
        _check_ringwall(rd, secs["ringwall"], plate, wall, domain, a)
    if secs["consolidation"] is not None:
        _check_consolidation(rd, secs["consolidation"], data, soil or {}, layers, deg, method)
    else:
        for k, layer in enumerate(layers, start=1):
            if "permeability" in layer:
                rd.bad(f"soil.layers[{k}].permeability: only used with a [consolidation] "
                       f"table; remove it or add [consolidation]")

    if rd.problems:
        raise SceneError(rd.problems)

    # ---- resolve defaults, now that every value is known to be sane
    hyperbolic = soil.get("model", "linear") == "hyperbolic"
    dc = soil.get("model", "linear") == "duncan_chang"
    dc_values = {}
    if dc:
        p_a = soil.get("atmospheric_pressure", ATMOSPHERIC_PRESSURE)
        dc_values = _duncan_chang_values(soil, p_a) | {
            "atmospheric_pressure": p_a, "water_table": soil.get("water_table"),
            "water_unit_weight": soil.get("water_unit_weight", WATER_UNIT_WEIGHT)
            if "water_table" in soil else None}
    E_surface = (1.0 / soil["hyperbolic_a"] if hyperbolic else
                 dc_values["modulus_number"] * dc_values["atmospheric_pressure"] if dc
                 else soil["E"])
    soil_dc = Soil(E=E_surface, nu=soil["nu"], **dc_values,
                   E_gradient=soil.get("E_gradient", 0.0),
                   model=soil.get("model", "linear"), hyperbolic_a=soil.get("hyperbolic_a"),
                   hyperbolic_b=soil.get("hyperbolic_b"),
                   tolerance=soil.get("tolerance", 0.05) if hyperbolic or dc else None,
                   # (Duncan & Chang's failed zones settle slowly: 10-64 iterations measured)
                   max_iterations=(soil.get("max_iterations", 80 if dc else 40)
                                   if hyperbolic or dc else None),
                   unloading_modulus_ratio=soil.get("unloading_modulus_ratio"),
                   layers=tuple(_layer(x, hyperbolic, dc, dc_values) for x in layers))
    plate_dc = None
    if plate is not None:
        t = plate.get("thickness") or plate_thickness_from_Kp(
            plate["Kp"], plate["radius"], plate["E"], soil_dc.E, soil_dc.nu)
        plate_dc = Plate(radius=plate["radius"], thickness=t, E=plate["E"], nu=plate["nu"],
                         embedment=plate.get("embedment", 0.0),
                         unit_weight=plate.get("unit_weight", 0.0),
                         annular_width=plate.get("annular_width", 0.0),
                         annular_thickness=plate.get("annular_thickness"))
    wall_dc = None
    if wall is not None:
        courses = tuple(_courses(_Reader({}), wall) or ())
        t = courses[0][1] if courses else wall.get("thickness") or plate_thickness_from_Kp(
            wall["Kt"], wall["radius"], wall["E"], soil_dc.E, soil_dc.nu)
        wall_dc = Wall(radius=wall["radius"], thickness=t, height=wall["height"], E=wall["E"],
                       nu=wall["nu"], unit_weight=wall.get("unit_weight", 0.0),
                       courses=courses)
    tan_phi = interface.get("tan_phi")
    if "friction_angle" in interface:
        tan_phi = math.tan(math.radians(interface["friction_angle"]))
    interface_dc = Interface(condition=cond, cohesion=interface.get("cohesion", 0.0),
                             tan_phi=tan_phi,
                             normal_stiffness=interface.get("normal_stiffness"),
                             shear_stiffness=interface.get("shear_stiffness"),
                             on_cycle=on_cycle, states=states)
    a = plate_dc.radius if plate_dc is not None else load["load_radius"]
    load_dc = Load(pressure=load.get("pressure", 0.0), load_radius=a,
                   liquid_unit_weight=load.get("liquid_unit_weight", 0.0),
                   liquid_height=load.get("liquid_height", 0.0),
                   self_weight=load.get("self_weight", False),
                   roof_weight=load.get("roof_weight", 0.0),
                   gas_pressure=load.get("gas_pressure", 0.0),
                   overturning_moment=load.get("overturning_moment", 0.0),
                   base_shear=load.get("base_shear", 0.0))
    D = plate_dc.embedment if plate_dc is not None else 0.0
    size = DEFAULT_DOMAIN_FACTOR * a
    domain_dc = DomainSize(radius=domain.get("radius", size), depth=domain.get("depth", size))
    coarsen = FLEXIBLE_COARSENING if plate_dc is None else 1.0
    edge = mesh.get("edge_size", coarsen * DEFAULT_EDGE_SIZE * a)
    if D > 0 and "edge_size" not in mesh:
        edge = min(edge, 0.5 * D)  # the side of the pit needs at least two elements
    if interface_dc.condition == "mohr_coulomb":
        net = vertical_load(load_dc, plate_dc, wall_dc)
        if net <= 0.0:
            raise SceneError([f"[load]: the net vertical load is {net:.4g} N, upward (uplift): "
                              f"a Mohr-Coulomb interface takes no tension, so nothing would "
                              f"hold the foundation down; use condition = \"bonded\" for an "
                              f"anchored foundation, or add downward load"])
    mesh_dc = MeshOptions(degree=deg, edge_size=edge, growth=mesh.get("growth", 0.2),
                          near_size=mesh.get("near_size", coarsen * DEFAULT_NEAR_SIZE * a))
    solver = secs["solver"] or {}
    solver_dc = SolverOptions(method=solver.get("method", "direct"),
                              rtol=solver.get("rtol", 1e-10),
                              max_iterations=solver.get("max_iterations", 1000))
    return Scene(soil=soil_dc, load=load_dc, domain=domain_dc, mesh=mesh_dc, plate=plate_dc,
                 wall=wall_dc, interface=interface_dc, solver=solver_dc,
                 ringwall=None if secs["ringwall"] is None else Ringwall(**secs["ringwall"]),
                 consolidation=None if secs["consolidation"] is None else Consolidation(
                     **{**secs["consolidation"],
                        "times": tuple(float(t) for t in secs["consolidation"]["times"])}),
                 title=data.get("title", "tankfx scene"))


def _courses(rd: _Reader, wall: dict) -> list[tuple[float, float]] | None:
    """The wall's courses as (height, thickness) pairs from the bottom, checked; None if the
    wall has none."""
    raw = wall.get("courses")
    if raw is None:
        return None
    how = ("a list of tables from the bottom course up, e.g. courses = [{height = 2.4, "
           "thickness = 0.012}, {height = 2.4, thickness = 0.010}] (m)")
    if not isinstance(raw, list) or not raw or not all(isinstance(c, dict) for c in raw):
        rd.bad(f"wall.courses: {how}")
        return []
    out = []
    for k, course in enumerate(raw, start=1):
        name = f"wall.courses[{k}]"
        values = {}
        for key, value in course.items():
            if key not in ("height", "thickness"):
                rd.bad(f"{name}.{key}: unknown key{_suggest(key, ('height', 'thickness'))}")
                continue
            checked = rd._typed(f"{name}.{key}", value, float)
            if checked is not None:
                values[key] = checked
        for key in ("height", "thickness"):
            if key not in course:
                rd.bad(f"{name}.{key}: missing; each course needs its height and thickness "
                       f"(m)")
            rd.positive(values, name, key)
        if len(values) == 2 and min(values.values()) > 0:
            out.append((values["height"], values["thickness"]))
    return out


def _check_ringwall(rd: _Reader, ring: dict, plate: dict | None, wall: dict | None,
                    domain: dict, a: float | None) -> None:
    """A ringwall lies under the wall, within the ground, of a material compressible
    enough for the displacement form."""
    for key in ("outer_radius", "depth", "E", "fill_E"):
        rd.positive(ring, "ringwall", key)
    rd.positive(ring, "ringwall", "inner_radius", allow_zero=True)
    rd.positive(ring, "ringwall", "unit_weight", allow_zero=True)
    for key, typical in (("nu", "concrete's is about 0.2"), ("fill_nu", "e.g. 0.3")):
        nu = ring.get(key)
        if nu is not None and not -1.0 < nu <= MIXED_FROM_NU:
            rd.bad(f"ringwall.{key} = {nu!r}: must lie in (-1, {MIXED_FROM_NU}] ({typical})")
    if "fill_nu" in ring and "fill_E" not in ring:
        rd.bad("ringwall.fill_nu: a fill needs its modulus; add ringwall.fill_E (Pa) or "
               "remove fill_nu")
    if "fill_E" in ring and not ring.get("inner_radius", 1.0) > 0:
        rd.bad("ringwall.fill_E: a ring from the axis (inner_radius = 0) has no inside to "
               "fill; remove fill_E or give inner_radius > 0")
    if plate is None:
        rd.bad("[ringwall]: a ringwall carries a foundation plate and its wall; add a "
               "[plate] and a [wall]")
        return
    inner, outer = ring.get("inner_radius"), ring.get("outer_radius")
    if isinstance(inner, float) and isinstance(outer, float):
        if inner >= outer:
            rd.bad(f"ringwall.inner_radius = {inner!r} m is not inside ringwall.outer_radius "
                   f"= {outer!r} m; give inner_radius < outer_radius")
        elif wall is not None and isinstance(wall.get("radius"), float) \
                and not inner < wall["radius"] <= outer:
            rd.bad(f"ringwall: the wall (r = {wall['radius']:g} m) must stand on it; give "
                   f"inner_radius < {wall['radius']:g} <= outer_radius (now {inner:g} and "
                   f"{outer:g} m)")
        if a is not None and outer >= 0.5 * domain.get("radius", DEFAULT_DOMAIN_FACTOR * a):
            rd.bad(f"ringwall.outer_radius = {outer!r} m: must lie within half the domain's "
                   f"radius; widen the domain")
    depth = ring.get("depth")
    if a is not None and isinstance(depth, float):
        base = domain.get("depth", DEFAULT_DOMAIN_FACTOR * a)
        D = plate.get("embedment", 0.0)
        if D + depth >= base:
            rd.bad(f"ringwall.depth = {depth!r} m: reaches the rigid base ({base:g} m below "
                   f"the ground, the plate {D:g} m); make it shallower")


def _check_consolidation(rd: _Reader, c: dict, data: dict, soil: dict, layers: list,
                         degree, method) -> None:
    """A consolidation needs a linear, compressible (drained) soil of one stratum, the
    direct solver and Taylor-Hood elements; its times are positive and increasing."""
    rd.positive(c, "consolidation", "permeability")
    rd.positive(c, "consolidation", "water_unit_weight")
    times = c.get("times")
    if times is not None:
        if not isinstance(times, (list, tuple)) or not times or any(
                isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t)
                for t in times):
            rd.bad(f"consolidation.times = {times!r}: a list of the times (s) at which to "
                   f"report, e.g. [86400, 2592000, 31536000] for a day, a month and a year")
        elif min(times) <= 0 or any(b <= a for a, b in zip(times, times[1:])):
            rd.bad(f"consolidation.times = {times!r}: must be positive and increasing (s "
                   f"after the load is applied; t = 0, the undrained response, is always "
                   f"reported)")
    rd.choice(c, "consolidation", "drainage", "top", _DRAINAGE,
              "\"top\": the ground surface drains; \"top_and_bottom\": the domain's base too")
    n = c.get("steps_per_decade")
    if n is not None and n < 2:
        rd.bad(f"consolidation.steps_per_decade = {n!r}: must be >= 2 (10 keep Terzaghi's "
               f"settlement within 0.6 %; 20 within 0.2 %)")
    model = soil.get("model", "linear")
    if model != "linear":
        rd.bad(f"[consolidation] with soil.model = {model!r}: consolidation is solved for a "
               f"linear elastic skeleton (its E, nu the drained constants); use model = "
               f"\"linear\" or remove [consolidation]")
    for name, table in (("soil", soil), *((f"soil.layers[{k}]", x)
                                          for k, x in enumerate(layers, start=1))):
        nu = table.get("nu")
        if isinstance(nu, (int, float)) and nu > MIXED_FROM_NU:
            rd.bad(f"{name}.nu = {nu!r} with [consolidation]: nu is the drained (effective) "
                   f"Poisson's ratio, which must not exceed {MIXED_FROM_NU} (the undrained "
                   f"response, nu = 0.5, is consolidation's start; typical drained values "
                   f"0.2-0.35)")
    if method != "direct":
        rd.bad(f"solver.method = {method!r} with [consolidation]: its saddle-point system "
               f"is solved by MUMPS; use method = \"direct\"")
    if degree == 1:
        rd.bad("mesh.degree = 1 with [consolidation]: the displacement and pore pressure are "
               "Taylor-Hood pairs (the pressure one degree lower), which need degree 2 or 3")


def _check_annular_ring(rd: _Reader, plate: dict, wall: dict | None) -> None:
    """An annular ring needs both its width and thickness, must lie within the plate, and
    must carry the wall (it is the ring the wall stands on)."""
    width, thick = plate.get("annular_width"), plate.get("annular_thickness")
    if (width is None) != (thick is None):
        missing = "annular_thickness" if thick is None else "annular_width"
        rd.bad(f"plate.{missing}: missing; an annular ring needs both annular_width (m, "
               f"inward from the plate's edge) and annular_thickness (m)")
        return
    a = plate.get("radius")
    if width is None or a is None or not width > 0:
        return
    if width >= a:
        rd.bad(f"plate.annular_width = {width!r} m: the ring must be narrower than the "
               f"plate's radius ({a!r} m); for a plate of one thickness give only thickness")
    elif wall is not None and isinstance(wall.get("radius"), float) \
            and wall["radius"] <= a - width:
        rd.bad(f"plate.annular_width = {width!r} m: the ring (r > {a - width:g} m) does not "
               f"reach the wall (r = {wall['radius']:g} m); widen it beyond "
               f"{a - wall['radius']:g} m so that the wall stands on it")


def _check_soil(rd: _Reader, soil: dict | None, raw_layers,
                consolidating: bool = False) -> list[dict[str, Any]]:
    """The [soil] table's checks, its model's and its layers' (returned, checked)."""
    if soil is not None:
        rd.positive(soil, "soil", "E")
        rd.poisson(soil, "soil", incompressible=True)
        rd.positive(soil, "soil", "E_gradient", allow_zero=True)
        model = soil.get("model", "linear")
        if model not in _SOIL_MODELS:
            rd.bad(f"soil.model = {model!r}: unknown model{_suggest(model, _SOIL_MODELS)}")
        elif model == "hyperbolic":
            _kondner(rd, soil, soil, "soil", "the surface modulus of a hyperbolic soil")
        elif model == "duncan_chang":
            _duncan_chang(rd, soil)
        if model == "linear" and "E" not in soil:
            rd.bad("soil.E: missing; add 'E = ...' under [soil] (Pa)")
        for key in ("hyperbolic_a", "hyperbolic_b"):
            if key in soil and model != "hyperbolic":
                rd.bad(f"soil.{key}: only used with model = \"hyperbolic\"; remove it")
        for key in ("tolerance", "max_iterations"):
            if key in soil and model == "linear":
                rd.bad(f"soil.{key}: only used with a nonlinear soil (model = \"hyperbolic\" "
                       f"or \"duncan_chang\"); remove it")
        for key in _DUNCAN_CHANG:
            if key in soil and model != "duncan_chang":
                rd.bad(f"soil.{key}: only used with model = \"duncan_chang\"; remove it")
        tol = soil.get("tolerance")
        if tol is not None and not (0.0 < tol < 1.0):
            rd.bad(f"soil.tolerance = {tol!r}: the relative deviator misfit of Eq. 18 must "
                   f"lie in (0, 1) (the paper's 0.05 is the default)")
        if soil.get("max_iterations", 1) < 1:
            rd.bad("soil.max_iterations: must be >= 1")
        _check_unloading(rd, soil, consolidating)
    layers = _layers(rd, raw_layers, (soil or {}).get("model", "linear"),
                     (soil or {}).get("atmospheric_pressure")) \
        if raw_layers is not None else []
    if (soil or {}).get("model") == "duncan_chang" and "water_table" in soil:
        # below the water table a stratum must be heavier than water: its effective weight
        # gamma - gamma_w carries the confinement
        gamma_w = soil.get("water_unit_weight", WATER_UNIT_WEIGHT)
        tops = [0.0] + [x.get("depth", 0.0) for x in layers]
        bottoms = tops[1:] + [math.inf]
        for k, (part, bottom) in enumerate(zip([soil, *layers], bottoms)):
            g = part.get("unit_weight")
            if isinstance(g, float) and bottom > soil["water_table"] and g <= gamma_w:
                where = "soil" if k == 0 else f"soil.layers[{k}]"
                rd.bad(f"{where}.unit_weight = {g!r}: below the water table (soil.water_table "
                       f"= {soil['water_table']!r} m) a stratum's unit weight must exceed "
                       f"water's ({gamma_w:g} N/m^3); give its saturated unit weight")
    return layers


def _duncan_chang_values(part: dict, p_a: float) -> dict[str, float]:
    """Duncan & Chang's constants of a soil or layer table, defaults resolved."""
    phi = part.get("friction_angle", 0.0)
    return {"modulus_number": part["modulus_number"],
            "modulus_exponent": part["modulus_exponent"],
            "failure_ratio": part.get("failure_ratio", 0.9),
            "cohesion": part.get("cohesion", 0.0), "friction_angle": phi,
            "unit_weight": part["unit_weight"],
            "K0": part.get("K0", 1.0 - math.sin(math.radians(phi)))}


def _layer(x: dict, hyperbolic: bool, dc: bool, dc_values: dict) -> Layer:
    """A checked [[soil.layers]] table, resolved."""
    if dc:
        values = _duncan_chang_values(x, dc_values["atmospheric_pressure"])
        return Layer(depth=x["depth"], E=values["modulus_number"] *
                     dc_values["atmospheric_pressure"], nu=x["nu"], **values)
    return Layer(depth=x["depth"], E=1.0 / x["hyperbolic_a"] if hyperbolic else x["E"],
                 nu=x["nu"], E_gradient=x.get("E_gradient", 0.0),
                 hyperbolic_a=x.get("hyperbolic_a"), hyperbolic_b=x.get("hyperbolic_b"),
                 permeability=x.get("permeability"))


def _check_unloading(rd: _Reader, soil: dict, consolidating: bool) -> None:
    """soil.unloading_modulus_ratio: a nonlinear soil, E_ur >= E_i."""
    ratio = soil.get("unloading_modulus_ratio")
    if ratio is None:
        return
    if consolidating:
        rd.bad("soil.unloading_modulus_ratio: not with a [consolidation]: a consolidating "
               "skeleton is linear elastic and swells back as it was compressed (a "
               "remembering skeleton is not modelled yet); remove the key")
        return
    if soil.get("model", "linear") not in ("hyperbolic", "duncan_chang"):
        rd.bad("soil.unloading_modulus_ratio: only used with a nonlinear soil (model = "
               "\"hyperbolic\" or \"duncan_chang\"): a linear soil unloads as it loads; "
               "remove it")
        return
    if isinstance(ratio, float) and not (math.isfinite(ratio) and ratio >= 1.0):
        rd.bad(f"soil.unloading_modulus_ratio = {ratio!r}: E_ur / E_i must be a number >= 1 "
               f"(unloading is stiffer than the loading curve's start; 1 is Masing's rule, "
               f"1-3 usual); a smaller E_ur would lift the soil above where it started")


def _kondner(rd: _Reader, table: dict, given, name: str, what_E: str) -> None:
    """Kondner's a and b of the soil or a layer (``name``; ``given``: its keys as written):
    both required and positive; an E given must be 1/a (``what_E``)."""
    for key in ("hyperbolic_a", "hyperbolic_b"):
        if key not in given:
            rd.bad(f"{name}.{key}: missing for model = \"hyperbolic\"; add it (1/Pa: 1/a is "
                   f"the initial tangent modulus, 1/b the ultimate deviator stress)")
        rd.positive(table, name, key)
    a_h = table.get("hyperbolic_a")
    if "E" in table and a_h and a_h > 0 and abs(table["E"] * a_h - 1.0) > 1e-6:
        rd.bad(f"{name}.E = {table['E']!r} contradicts {name}.hyperbolic_a (1/a = "
               f"{1.0 / a_h:.6g} Pa is {what_E}); remove {name}.E")


def _duncan_chang(rd: _Reader, soil: dict, name: str = "soil",
                  p_a: float | None = None) -> None:
    """The keys of Duncan & Chang's soil (or of one of its layers, ``name``): K, n and the
    unit weight required; a strength (c or phi); E is K p_a, not given."""
    for key in _DUNCAN_CHANG_REQUIRED:
        if key not in soil:
            rd.bad(f"{name}.{key}: missing for model = \"duncan_chang\"; add it ("
                   + {"modulus_number": "K: the initial modulus is K p_a (sigma_3 / p_a)^n",
                      "modulus_exponent": "n, e.g. 0.5",
                      "unit_weight": "N/m^3: the geostatic stress sets the confinement"}[key]
                   + ")")
    for key in ("modulus_number", "unit_weight", "K0", "atmospheric_pressure",
                "water_unit_weight"):
        rd.positive(soil, name, key)
    rd.positive(soil, name, "water_table", allow_zero=True)
    rd.positive(soil, name, "cohesion", allow_zero=True)
    n = soil.get("modulus_exponent")
    if n is not None and not 0.0 <= n <= 1.0:
        rd.bad(f"{name}.modulus_exponent = {n!r}: must lie in [0, 1] (0: a modulus "
               f"independent of confinement; 1: proportional to it)")
    rf = soil.get("failure_ratio")
    if rf is not None and not 0.0 < rf <= 1.0:
        rd.bad(f"{name}.failure_ratio = {rf!r}: R_f must lie in (0, 1] (typically 0.7-0.9)")
    phi = soil.get("friction_angle")
    if phi is not None and not 0.0 <= phi < 90.0:
        rd.bad(f"{name}.friction_angle = {phi!r}: degrees, must lie in [0, 90)")
    if not soil.get("cohesion", 0.0) > 0.0 and not (phi or 0.0) > 0.0:
        rd.bad(f"{name}.cohesion, {name}.friction_angle: Duncan & Chang's soil needs a "
               f"strength; give cohesion > 0 (Pa) or friction_angle > 0 (degrees)")
    K = soil.get("modulus_number")
    p_a = p_a or soil.get("atmospheric_pressure", ATMOSPHERIC_PRESSURE)
    if "E" in soil and K and K > 0 and p_a > 0 and abs(soil["E"] / (K * p_a) - 1.0) > 1e-6:
        rd.bad(f"{name}.E = {soil['E']!r}: not used with model = \"duncan_chang\" (its "
               f"reference modulus is K p_a = {K * p_a:.6g} Pa); remove it")
    if soil.get("E_gradient", 0.0) != 0.0:
        rd.bad(f"{name}.E_gradient: not used with model = \"duncan_chang\" (the modulus "
               f"grows with the confining stress instead); remove it")


def _layers(rd: _Reader, raw, model: str, p_a: float | None = None) -> list[dict[str, Any]]:
    """The [[soil.layers]] tables, checked like [soil]; top down, each below the last."""
    if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
        rd.bad("soil.layers: a list of tables, one '[[soil.layers]]' header each, with the "
               "layer's 'depth' (m below the ground, where its top lies), 'E' and 'nu'")
        return []
    out = []
    for k, raw_layer in enumerate(raw, start=1):
        name = f"soil.layers[{k}]"
        layer = {}
        for key, value in raw_layer.items():
            spec = _LAYER_SPEC.get(key)
            if spec is None:
                rd.bad(f"{name}.{key}: unknown key{_suggest(key, _LAYER_SPEC)}")
                continue
            checked = rd._typed(f"{name}.{key}", value, spec[0])
            if checked is not None:
                layer[key] = checked
        for key, why in (("depth", "m below the ground surface, where the layer's top lies"),
                         ("nu", "its Poisson's ratio")):
            if key not in raw_layer:
                rd.bad(f"{name}.{key}: missing; add '{key} = ...' ({why})")
        rd.positive(layer, name, "depth")
        rd.positive(layer, name, "E")
        rd.positive(layer, name, "E_gradient", allow_zero=True)
        rd.positive(layer, name, "permeability")
        rd.poisson(layer, name, incompressible=True)
        for key in STRATUM_DUNCAN_CHANG:
            if key in raw_layer and model != "duncan_chang":
                rd.bad(f"{name}.{key}: only used with soil.model = \"duncan_chang\"; "
                       f"remove it")
        if model == "duncan_chang":
            _duncan_chang(rd, layer, name, p_a)
        elif model == "hyperbolic":
            # every layer has its own Kondner parameters
            _kondner(rd, layer, raw_layer, name, "the layer's modulus at its top")
        elif "E" not in raw_layer:
            rd.bad(f"{name}.E: missing; add 'E = ...' (Pa, the modulus at the layer's top)")
        for key in ("hyperbolic_a", "hyperbolic_b"):
            if key in raw_layer and model != "hyperbolic":
                rd.bad(f"{name}.{key}: only used with soil.model = \"hyperbolic\"; "
                       f"remove it")
        out.append(layer)
    depths = [x.get("depth") for x in out]
    for k in range(1, len(out)):
        if depths[k] is not None and depths[k - 1] is not None and depths[k] <= depths[k - 1]:
            rd.bad(f"soil.layers[{k + 1}].depth = {depths[k]!r} m is not below "
                   f"soil.layers[{k}].depth = {depths[k - 1]!r} m: list the layers from the "
                   f"top down, each deeper than the last")
    return out


def _stage_times(raw, consolidation: bool) -> tuple[Any, tuple[float, ...]]:
    """The stages without their ``time`` keys, and the times: each stage's (s, from the
    load's start) with a [consolidation], where every stage needs one (not before the
    stage before's); none without (where a time is refused)."""
    if not isinstance(raw, list) or not all(isinstance(st, dict) for st in raw):
        return raw, ()                   # (refused by _parse_stages, with its message)
    problems, times = [], []
    for k, stage in enumerate(raw, start=1):
        t = stage.get("time")
        if not consolidation:
            if t is not None:
                problems.append(f"stages[{k}].time: only used with a [consolidation] (the "
                                f"time at which the stage's load is reached); remove it")
            continue
        if t is None:
            problems.append(f"stages[{k}].time: missing; with a [consolidation] each stage "
                            f"says when its load is reached (s after the path starts, from "
                            f"no load at t = 0; 0 for a load applied at once)")
        elif isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t) \
                or t < 0:
            problems.append(f"stages[{k}].time = {t!r}: a time in s, >= 0")
        elif times and t < times[-1]:
            problems.append(f"stages[{k}].time = {t!r} s is before stages[{k - 1}].time = "
                            f"{times[-1]!r} s: list the stages in the order of their times")
        else:
            times.append(float(t))
    if problems:
        raise SceneError(problems)
    return [{key: v for key, v in st.items() if key != "time"} for st in raw], tuple(times)


def _parse_stages(data: dict[str, Any], raw, scene: Scene) -> tuple[Load, ...]:
    """Each stage is the scene with its [load] keys changed, and checked as such (every
    load rule applies to every stage)."""
    if not isinstance(raw, list) or not raw or not all(isinstance(st, dict) for st in raw):
        raise SceneError(["stages: a list of load tables, one '[[stages]]' header each, "
                          "followed by the [load] keys that change (e.g. 'pressure = 2e5'); "
                          "an empty table is the [load] itself"])
    problems, loads = [], []
    for k, stage in enumerate(raw, start=1):
        try:
            # (a stage may have no load along a consolidation's path, and where the soil
            # remembers: the tank emptied, the soil keeping what it keeps)
            remembers = isinstance(data.get("soil"), dict) and \
                data["soil"].get("unloading_modulus_ratio") is not None
            load = _parse({**data, "load": {**data.get("load", {}), **stage}},
                          empty_load="consolidation" in data or remembers).load
        except SceneError as e:
            problems += [f"stages[{k}] (the [load] with its keys changed): {p}"
                         for p in e.problems]
            continue
        if scene.plate is None and load.load_radius != scene.load.load_radius:
            problems.append(f"stages[{k}].load_radius = {load.load_radius!r}: a flexible "
                            f"load's circle is meshed once ({scene.load.load_radius!r} m in "
                            f"[load]); analyse another radius as another scene")
        loads.append(load)
    if problems:
        raise SceneError(problems)
    return tuple(loads)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a TOML scene file."""
    p = Path(path)
    if not p.is_file():
        raise SceneError([f"{p}: no such scene file"])
    try:
        with p.open("rb") as f:
            data = tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise SceneError([f"{p}: not valid TOML: {e}"]) from None
    return _parse_scene(data)


def _parse_scene(data: dict[str, Any]) -> Scene:
    """A whole scene (:func:`_parse`), with the checks that need its load path."""
    scene = _parse(data)
    ratio = scene.soil.unloading_modulus_ratio
    if ratio is not None and len(scene.stages) < 2:
        raise SceneError([f"soil.unloading_modulus_ratio = {ratio!r}: acts only along a load "
                          f"path of two stages or more (one load never unloads); add "
                          f"[[stages]] or remove the key"])
    return scene

