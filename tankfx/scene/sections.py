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


DEFAULT_NEAR_SIZE = 0.1


#: A flexible load (no plate: the soil alone decides the error) defaults to P3 on a mesh
#: FLEXIBLE_COARSENING times coarser: measured, largest error 1.5e-3 -> 1.9e-4 (sigma_zz on
#: the axis) at the same whole-process time (README "Every case").
FLEXIBLE_DEGREE = 3


FLEXIBLE_COARSENING = 2.0


#: Above this soil Poisson's ratio the soil is solved in the mixed displacement-pressure
#: (Taylor-Hood) form, chosen automatically: the displacement form's stresses lock (measured
#: on the flexible load: sigma_zz on the axis off by 0.5 % of p at 0.45, 2.6 % at 0.49,
#: 17.6 % at 0.499), and it cannot take 0.5 at all.
MIXED_FROM_NU = 0.45


class SceneError(ValueError):
    """A scene that cannot be run; the message lists every problem and its fix."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        lines = "\n".join(f"  - {p}" for p in self.problems)
        super().__init__(f"the scene has {len(self.problems)} problem(s):\n{lines}")


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


#: gamma_w, N/m^3
WATER_UNIT_WEIGHT = 9810.0


#: p_a, Pa: the reference pressure of Duncan & Chang's modulus
ATMOSPHERIC_PRESSURE = 101325.0
