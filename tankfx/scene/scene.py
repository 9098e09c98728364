"""The scene: one validated description of a tank-foundation-soil problem.

A scene is read from a TOML file (see ``README.md`` for every key) into frozen dataclasses.
All checks happen here, before any mesh is built, and all problems found are reported in one
:class:`SceneError` whose message names each offending key and how to fix it.

Units are SI throughout: metres, pascals, newtons per cubic metre.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ..laws.rigidity import Kp_from_thickness, plate_thickness_from_Kp
from .checks import (
    check_annular_ring,
    check_consolidation,
    check_ringwall,
    check_soil,
    duncan_chang_values,
    read_courses,
    read_layer,
    stage_times_of,
)
from .keys import (
    CONDITIONS,
    ON_CYCLE,
    REQUIRED_SECTIONS,
    SOLVER_METHODS,
    SPEC,
    STATES,
    TOP,
    Reader,
    suggest,
)
from .sections import (
    ATMOSPHERIC_PRESSURE,
    DEFAULT_DOMAIN_FACTOR,
    DEFAULT_EDGE_SIZE,
    DEFAULT_NEAR_SIZE,
    E_FROM_KEYS,
    FLEXIBLE_COARSENING,
    FLEXIBLE_DEGREE,
    MIXED_FROM_NU,
    WATER_UNIT_WEIGHT,
    Consolidation,
    DomainSize,
    Interface,
    Load,
    MeshOptions,
    Plate,
    Ringwall,
    SceneError,
    Soil,
    SolverOptions,
    Wall,
    plain,
    toml_value,
    vertical_load,
)


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
                out[name] = plain(part)
        if self.soil.layers:
            out["soil"]["layers"] = [plain(layer) for layer in self.soil.layers]
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
            out["stages"] = [{k: v for k, v in plain(ld).items() if out["load"].get(k) != v}
                             for ld in self.stages]
            for stage, t in zip(out["stages"], self.stage_times):
                stage["time"] = t
        return out

    def to_toml(self) -> str:
        """The scene as a scene file with every value resolved (the defaults written out,
        a thickness for a Kp); :func:`load_scene` reads it back to an equal scene."""
        d = self.to_dict()
        lines = [f"title = {toml_value(d.pop('title'))}", ""]
        stages = d.pop("stages", [])
        for name, values in d.items():
            layers = values.pop("layers", []) if name == "soil" else []
            lines += [f"[{name}]", *(f"{k} = {toml_value(v)}" for k, v in values.items()), ""]
            for layer in layers:
                lines += ["[[soil.layers]]",
                          *(f"{k} = {toml_value(v)}" for k, v in layer.items()), ""]
        for stage in stages:
            lines += ["[[stages]]", *(f"{k} = {toml_value(v)}" for k, v in stage.items()), ""]
        return "\n".join(lines)

    @staticmethod
    def from_dict(data: dict[str, Any]) -> "Scene":
        return _parse_scene(data)

    @staticmethod
    def from_toml(path: str | Path) -> "Scene":
        return load_scene(path)


def _parse(data: dict[str, Any], empty_load: bool = False) -> Scene:
    """The scene of a dict, checked; ``empty_load``: a [load] without any load is allowed
    (a stage of a consolidation's load path: the tank emptied)."""
    if not isinstance(data, dict):
        raise SceneError([f"a scene must be a table of sections, got {type(data).__name__}"])
    if "stages" in data:
        rest = {k: v for k, v in data.items() if k != "stages"}
        raw, times = stage_times_of(data["stages"], "consolidation" in data)
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
    rd = Reader(data)
    for key, value in data.items():
        if key in TOP:
            if not isinstance(value, TOP[key]):
                rd.bad(f"{key}: expected a string, got {value!r}")
        elif key not in SPEC:
            rd.bad(f"[{key}]: unknown section"
                   f"{suggest(key, [*SPEC, *TOP, 'stages'])}")
    for name in REQUIRED_SECTIONS:
        if name not in data:
            rd.bad(f"[{name}]: missing section; add a '[{name}]' table (see README)")
    secs = {name: rd.section(name) for name in SPEC}

    soil = secs["soil"]
    layers = check_soil(rd, soil, raw_layers, "consolidation" in data)

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
        check_annular_ring(rd, plate, secs["wall"])

    wall = secs["wall"]
    if wall is not None:
        for key in ("radius", "E", "thickness", "Kt", "height"):
            rd.positive(wall, "wall", key)
        rd.positive(wall, "wall", "unit_weight", allow_zero=True)
        rd.poisson(wall, "wall")
        courses = read_courses(rd, wall)
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
    cond = rd.choice(interface, "interface", "condition", "bonded", CONDITIONS)
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
    on_cycle = rd.choice(interface, "interface", "on_cycle", "hold", ON_CYCLE,
                         "\"hold\": hold the alternating elements in the weaker state and "
                         "go on; \"stop\": stop with the iteration history")
    states = rd.choice(interface, "interface", "states", "element", STATES,
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
    if isinstance(method, str) and method not in SOLVER_METHODS:
        rd.bad(f"solver.method = {method!r}: one of {', '.join(SOLVER_METHODS)}"
               f"{suggest(method, SOLVER_METHODS)}")
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
        check_ringwall(rd, secs["ringwall"], plate, wall, domain, a)
    if secs["consolidation"] is not None:
        check_consolidation(rd, secs["consolidation"], data, soil or {}, layers, deg, method)
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
        dc_values = duncan_chang_values(soil, p_a) | {
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
                   layers=tuple(read_layer(x, hyperbolic, dc, dc_values) for x in layers))
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
        courses = tuple(read_courses(Reader({}), wall) or ())
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
