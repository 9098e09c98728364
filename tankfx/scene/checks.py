"""The rules of the scene's sections that go beyond a key's type: a soil's model and its
constants, layers, a wall's courses, an annular ring, a ringwall, a consolidation, the load
path's times. Each adds what it finds to the reader's problems.
"""
from __future__ import annotations

import math
from typing import Any

from ..laws.soil_law import words
from ..laws.soil_laws import SOIL_LAWS
from .reader import (
    COLLAPSES,
    CONDITIONS,
    DRAINAGE,
    KEYS,
    LAYER_KEYS,
    LAYER_SPEC,
    ON_CYCLE,
    REQUIRED_SECTIONS,
    SOIL_MODELS,
    SOLVER_METHODS,
    SPEC,
    STATES,
    TOP,
    Reader,
    suggest,
)
from .plausible import (
    DOMAIN_WIDEST,
    PLATE_THICKEST,
    PLATE_THIN,
    WALL_THICKEST,
    WALL_THIN,
    accept_problems,
    ratio_problem,
)
from .sections import (
    DEFAULT_DOMAIN_FACTOR,
    Analysis,
    FLEXIBLE_DEGREE,
    MIXED_FROM_NU,
    Interface,
    Layer,
    STATES_CONDITION,
    SceneError,
    Soil,
    SolverOptions,
)


def read_courses(rd: Reader, wall: dict) -> list[tuple[float, float]] | None:
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
                rd.bad(f"{name}.{key}: unknown key{suggest(key, ('height', 'thickness'))}")
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


def check_ringwall(rd: Reader, ring: dict, plate: dict | None, wall: dict | None,
                    domain: dict, a: float | None) -> None:
    """A ringwall lies under the wall, within the ground, of a material compressible
    enough for the displacement form."""
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


def check_consolidation(rd: Reader, c: dict, data: dict, soil: dict, layers: list,
                         degree, method) -> None:
    """A consolidation needs a linear, compressible (drained) soil of one stratum, the
    direct solver and Taylor-Hood elements; its times are positive and increasing."""
    times = c.get("times")
    if times is None and "fill" not in data:
        rd.bad("consolidation.times: missing; add 'times = ...' under [consolidation] (s after "
               "the load starts, e.g. [86400, 2592000] for a day and a month)")
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
    piezometers = c.get("piezometers", [])
    if not isinstance(piezometers, (list, tuple)) or any(
            not isinstance(x, (list, tuple)) or len(x) != 2 or any(
                isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                for v in x) for x in piezometers):
        rd.bad(f"consolidation.piezometers = {piezometers!r}: a list of points [r, depth] "
               f"(m: r from the axis, depth below the ground surface), e.g. [[0, 5], "
               f"[12.5, 3]]")
    rd.choice(c, "consolidation", "drainage", "top", DRAINAGE,
              "\"top\": the ground surface drains; \"top_and_bottom\": the domain's base too")
    model = soil.get("model", Soil.model)
    if model in SOIL_LAWS and not SOIL_LAWS[model].consolidates:
        rd.bad(f"[consolidation] with soil.model = {model!r}: {SOIL_LAWS[model].title} has "
               f"no effective-stress meaning (its constants are fitted to the soil's whole "
               f"response), and a consolidation needs the skeleton's drained one; use model "
               f"= {words(SOIL_LAWS.values(), lambda o: o.consolidates)} or remove "
               f"[consolidation]")
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


def check_fill(rd: Reader, fill: dict, data: dict, soil: dict) -> None:
    """A fill schedule needs a tank (a plate and a wall) with a liquid, on a soil that
    consolidates and can fail, with a [consolidation] and no [[stages]] of its own; its
    whole fill at the rate fits in ``max_days``."""
    if "consolidation" not in data:
        rd.bad("[fill] without a [consolidation]: the schedule's holds are the time the clay "
               "takes to drain and grow stronger; add [consolidation] with the soil's "
               "permeability")
    law = SOIL_LAWS.get(soil.get("model", Soil.model))
    if law is not None and not (law.fails and law.consolidates and law.at_points):
        rd.bad(f"[fill] with soil.model = {law.word!r}: {law.title} has no strength that "
               f"grows as it drains (the schedule holds until the factor of safety on the "
               f"strength is reached); use soil.model = "
               f"{words(SOIL_LAWS.values(), lambda x: x.fails and x.consolidates)}")
    if "plate" not in data or "wall" not in data:
        rd.bad("[fill] needs a tank: a [plate] and a [wall] that hold the liquid")
    collapse = (data.get("analysis") or {}).get("collapse") \
        if isinstance(data.get("analysis"), dict) else None
    if collapse not in (None, "strength"):
        rd.bad(f"analysis.collapse = {collapse!r} with [fill]: the schedule's factor of safety "
               f"is on the soil's strength at each step's end; remove analysis.collapse (or "
               f"give \"strength\")")
    cons = data.get("consolidation")
    if isinstance(cons, dict) and "times" in cons:
        rd.bad("consolidation.times with [fill]: the schedule reports its own times (each "
               "step's start and end); remove consolidation.times")
    load = data.get("load") if isinstance(data.get("load"), dict) else {}
    height, rate, days = fill.get("height"), fill.get("rate"), fill.get("max_days", 365.0)
    given = load.get("liquid_height")
    if given not in (None, 0, 0.0) and height is not None and given != height:
        rd.bad(f"load.liquid_height = {given!r} with fill.height = {height!r}: the fill "
               f"ends at fill.height; remove load.liquid_height (or make them equal)")
    if not load.get("liquid_unit_weight"):
        rd.bad("[fill] without load.liquid_unit_weight: the liquid's unit weight (N/m^3) is "
               "the load the schedule raises; add e.g. 'liquid_unit_weight = 9810.0' under "
               "[load]")
    if all(isinstance(x, (int, float)) and x > 0 for x in (height, rate, days)) and \
            height / rate > days:
        rd.bad(f"fill.max_days = {days!r}: filling to {height!r} m at {rate!r} m/day takes "
               f"{height / rate:.4g} days without a hold; raise max_days or the rate")


def check_annular_ring(rd: Reader, plate: dict, wall: dict | None) -> None:
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


def check_soil(rd: Reader, soil: dict | None, raw_layers,
                consolidating: bool = False) -> list[dict[str, Any]]:
    """The [soil] table's checks, its law's (:mod:`tankfx.laws.soil_laws`) and its layers'
    (returned, checked)."""
    law = None
    if soil is not None:
        model = soil.get("model", Soil.model)
        law = SOIL_LAWS.get(model)
        if law is None:
            rd.bad(f"soil.model = {model!r}: unknown model{suggest(model, SOIL_MODELS)}")
        else:
            for problem in law.check(soil, soil, "soil"):
                rd.bad(problem)
            _other_laws_keys(rd, soil, law, "soil")
        check_unloading(rd, soil, consolidating)
    layers = read_layers(rd, raw_layers, law, (soil or {}).get("atmospheric_pressure")) \
        if raw_layers is not None else []
    if law is not None:
        for problem in law.check_ground(soil, layers):
            rd.bad(problem)
    return layers


def _other_laws_keys(rd: Reader, table: dict, law, name: str) -> None:
    """A key of a law that is not the soil's (nor of its iteration) is refused, with the
    laws it belongs to (``name``: "soil" or a layer's)."""
    layer = name != "soil"

    def keys(o):
        return o.layer_keys if layer else o.keys

    for key in dict.fromkeys(k for other in SOIL_LAWS.values() for k in keys(other)):
        if key in table and key not in keys(law):
            owners = words(SOIL_LAWS.values(), lambda o: key in keys(o))
            rd.bad(f"{name}.{key}: only used with {'soil.' if layer else ''}model = {owners}; "
                   f"remove it")
    if layer:
        return
    for key in dict.fromkeys(k for other in SOIL_LAWS.values() for k in other.iteration_keys):
        if key in table and key not in law.iteration_keys:
            owners = words(SOIL_LAWS.values(), lambda o: key in o.iteration_keys)
            rd.bad(f"soil.{key}: only used with a nonlinear soil (model = {owners}); "
                   f"remove it")


def read_layer(x: dict, law, ground: dict) -> Layer:
    """A checked [[soil.layers]] table, resolved: its E and constants by the soil's law."""
    return Layer(depth=x["depth"], nu=x["nu"], E_gradient=x.get("E_gradient", 0.0),
                 permeability=x.get("permeability"), **law.resolve_stratum(x, ground))


def check_unloading(rd: Reader, soil: dict, consolidating: bool) -> None:
    """soil.unloading_modulus_ratio: a nonlinear soil, E_ur >= E_i."""
    ratio = soil.get("unloading_modulus_ratio")
    if ratio is None:
        return
    if consolidating:
        rd.bad("soil.unloading_modulus_ratio: not with a [consolidation]: a consolidating "
               "skeleton is linear elastic and swells back as it was compressed (a "
               "remembering skeleton is not modelled yet); remove the key")
        return
    law = SOIL_LAWS.get(soil.get("model", Soil.model))
    if law is not None and not law.remembers:
        rd.bad(f"soil.unloading_modulus_ratio: only used with a nonlinear soil (model = "
               f"{words(SOIL_LAWS.values(), lambda o: o.remembers)}): {law.title} unloads as "
               f"it loads; remove it")
        return
    if isinstance(ratio, float) and not (
            math.isfinite(ratio) and KEYS["soil"]["unloading_modulus_ratio"].limit.holds(ratio)):
        rd.bad(f"soil.unloading_modulus_ratio = {ratio!r}: E_ur / E_i must be a number >= 1 "
               f"(unloading is stiffer than the loading curve's start; 1 is Masing's rule, "
               f"1-3 usual); a smaller E_ur would lift the soil above where it started")


def read_layers(rd: Reader, raw, law, p_a: float | None = None) -> list[dict[str, Any]]:
    """The [[soil.layers]] tables, checked like [soil] (by the soil's ``law``, where it is
    known); top down, each below the last."""
    if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
        rd.bad("soil.layers: a list of tables, one '[[soil.layers]]' header each, with the "
               "layer's 'depth' (m below the ground, where its top lies), 'E' and 'nu'")
        return []
    out = []
    for k, raw_layer in enumerate(raw, start=1):
        name = f"soil.layers[{k}]"
        layer = {}
        for key, value in raw_layer.items():
            spec = LAYER_SPEC.get(key)
            if spec is None:
                rd.bad(f"{name}.{key}: unknown key{suggest(key, LAYER_SPEC)}")
                continue
            checked = rd._typed(f"{name}.{key}", value, spec[0])
            if checked is not None:
                layer[key] = checked
        for key, why in (("depth", "m below the ground surface, where the layer's top lies"),
                         ("nu", "its Poisson's ratio")):
            if key not in raw_layer:
                rd.bad(f"{name}.{key}: missing; add '{key} = ...' ({why})")
        rd.limits(layer, name, LAYER_KEYS)
        if law is not None:
            # every layer has its own constants of the soil's law
            _other_laws_keys(rd, raw_layer, law, name)
            for problem in law.check(layer, raw_layer, name, p_a):
                rd.bad(problem)
        out.append(layer)
    depths = [x.get("depth") for x in out]
    for k in range(1, len(out)):
        if depths[k] is not None and depths[k - 1] is not None and depths[k] <= depths[k - 1]:
            rd.bad(f"soil.layers[{k + 1}].depth = {depths[k]!r} m is not below "
                   f"soil.layers[{k}].depth = {depths[k - 1]!r} m: list the layers from the "
                   f"top down, each deeper than the last")
    return out


def stage_times_of(raw, consolidation: bool) -> tuple[Any, tuple[float, ...]]:
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


def check_top(rd: Reader, data: dict) -> None:
    """The top level: a title, known sections, the required ones present."""
    for key, value in data.items():
        if key == "accept":
            for p in accept_problems(value, KEYS, LAYER_KEYS):
                rd.bad(p)
        elif key in TOP:
            if not isinstance(value, TOP[key]):
                rd.bad(f"{key}: expected a string, got {value!r}")
        elif key not in SPEC:
            rd.bad(f"[{key}]: unknown section"
                   f"{suggest(key, [*SPEC, *TOP, 'stages'])}")
    for name in REQUIRED_SECTIONS:
        if name not in data:
            rd.bad(f"[{name}]: missing section; add a '[{name}]' table (see docs/scene-keys.md)")


def check_plate(rd: Reader, plate: dict | None, wall: dict | None) -> None:
    """One thickness (or Kp), and an annular ring that fits."""
    if plate is None:
        return
    if "thickness" in plate and "Kp" in plate:
        rd.bad("plate.thickness and plate.Kp: give one of them, not both "
               "(Kp fixes the thickness through Eq. 21)")
    elif "thickness" not in plate and "Kp" not in plate:
        rd.bad("plate.thickness: missing; give 'thickness = ...' (m) or 'Kp = ...'")
    for key in ("thickness", "annular_thickness"):
        if isinstance(plate.get(key), float) and isinstance(plate.get("radius"), float):
            problem = ratio_problem(f"plate.{key}", plate[key], plate["radius"], PLATE_THIN,
                                    PLATE_THICKEST, "plate", rd.accepted)
            if problem:
                rd.bad(problem)
    D, H = plate.get("embedment", 0.0), (wall or {}).get("height")
    if isinstance(H, float) and isinstance(D, float) and D > H \
            and "plate.embedment" not in rd.accepted:
        rd.bad(f"plate.embedment = {D:g} m: deeper than the wall is tall (wall.height = {H:g} "
               f"m): the whole tank would lie below the ground; did you mean {D:g} mm = "
               f"{D * 1e-3:g} m? If you mean it, add \"plate.embedment\" to the scene's "
               f"top-level accept = [...]")
    check_annular_ring(rd, plate, wall)


def check_wall(rd: Reader, wall: dict | None, plate: dict | None, data: dict) -> None:
    """One thickness (Kt or courses), a height (the courses' sum if not given), a plate to
    stand on, within its radius."""
    if wall is None:
        return
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
    for t in [wall.get("thickness")] + [t for _, t in courses or ()]:
        if isinstance(t, float) and isinstance(wall.get("radius"), float):
            problem = ratio_problem("wall.thickness", t, wall["radius"], WALL_THIN,
                                    WALL_THICKEST, "shell", rd.accepted)
            if problem and not any(p.startswith("wall.thickness = ") for p in rd.problems):
                rd.bad(problem)
                break
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


def check_interface(rd: Reader, interface: dict, data: dict) -> dict[str, str]:
    """The condition, its friction (tan phi or an angle) and options; returns the choices
    (condition, on_cycle, states) as given or defaulted."""
    cond = rd.choice(interface, "interface", "condition", Interface.condition, CONDITIONS)
    if "tan_phi" in interface and "friction_angle" in interface:
        rd.bad("interface.tan_phi and interface.friction_angle: give one of them, not both")
    if cond == STATES_CONDITION and "tan_phi" not in interface \
            and "friction_angle" not in interface:
        rd.bad("interface.tan_phi: missing for condition = \"mohr_coulomb\"; give tan_phi or "
               "friction_angle (degrees)")
    on_cycle = rd.choice(interface, "interface", "on_cycle", Interface.on_cycle, ON_CYCLE,
                         "\"hold\": hold the alternating elements in the weaker state and "
                         "go on; \"stop\": stop with the iteration history")
    states = rd.choice(interface, "interface", "states", Interface.states, STATES,
                       "\"element\": one state per interface element; \"node\": one per "
                       "node")
    if cond != STATES_CONDITION:
        for key in ("cohesion", "tan_phi", "friction_angle", "on_cycle", "states"):
            if key in interface:
                rd.bad(f"interface.{key}: only used with condition = \"mohr_coulomb\"; remove "
                       f"it or change the condition")
    if "plate" not in data and "interface" in data:
        rd.bad("[interface]: an interface needs a [plate]; remove it for a flexible load")
    return {"condition": cond, "on_cycle": on_cycle, "states": states}


def check_load(rd: Reader, load: dict | None, plate: dict | None, wall: dict | None,
               data: dict, empty_load: bool) -> None:
    """What each load needs (a wall for a liquid, a roof or a gas; a plate to overturn),
    a flexible load's circle, and some load at all (``empty_load``: none is allowed)."""
    if load is None:
        return
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


def check_analysis(rd: Reader, analysis: dict, soil: dict, load: dict, plate: dict | None,
                   wall: dict | None, layers: list, ringwall: dict | None = None) -> None:
    """A collapse asked of a soil that can fail, with something to raise or reduce."""
    collapse = analysis.get("collapse")
    for name in ("bounds_gap", "bounds_cells", "bounds_floor", "bounds_ring_width"):
        if analysis.get(name, getattr(Analysis, name)) != getattr(Analysis, name) and \
                collapse != "bounds":
            rd.bad(f"analysis.{name} = {analysis[name]!r}: only used with analysis.collapse = "
                   f"\"bounds\"; remove it or ask for the bounds")
    if collapse is None:
        return
    if collapse not in COLLAPSES:
        rd.bad(f"analysis.collapse = {collapse!r}: unknown{suggest(collapse, COLLAPSES)} "
               f"(\"load\": the variable loads raised until the ground fails; \"strength\": "
               f"the soil's c and tan phi reduced until it fails; \"bounds\": the limit "
               f"analysis' lower and upper bound)")
        return
    law = SOIL_LAWS.get(soil.get("model", Soil.model))
    if law is not None and not law.fails:
        what = "no strength to reduce" if collapse == "strength" else "no collapse load"
        rd.bad(f"analysis.collapse = {collapse!r} with soil.model = {law.word!r}: {law.title} "
               f"has {what}: {law.why_it_cannot_fail}; use soil.model = "
               f"{words(SOIL_LAWS.values(), lambda x: x.fails)} (with its cohesion and "
               f"friction_angle)")
    variable = ("pressure", "liquid_height", "gas_pressure", "roof_weight")
    if collapse in ("load", "bounds") and not any(load.get(k) for k in variable):
        rd.bad(f"analysis.collapse = {collapse!r}: the [load] has no variable load to raise (a "
               "pressure, a liquid, a gas pressure or a roof's weight); give one, or ask for "
               "collapse = \"strength\"")
    if collapse == "bounds" and law is not None and law.fails and not law.has_bounds:
        rd.bad(f"analysis.collapse = \"bounds\" with soil.model = {law.word!r}: "
               f"{law.why_no_bounds}")
    elif collapse == "bounds":
        check_bounds(rd, soil, plate, wall, layers, analysis, ringwall)


def check_bounds(rd: Reader, soil: dict, plate: dict | None, wall: dict | None,
                 layers: list, analysis: dict, ringwall: dict | None) -> None:
    """What the limit analysis takes: a rigid foundation, a flexible load or a tank's floor
    and shell on the surface, and a frictional soil's weight without a water table."""
    if ringwall is not None:
        rd.bad("analysis.collapse = \"bounds\" with a [ringwall]: the limit analysis takes a "
               "rigid foundation, a flexible load or a tank's floor and shell on the ground, "
               "not yet a ringwall; ask for collapse = \"load\" or \"strength\"")
    width = analysis.get("bounds_ring_width")
    floor = analysis.get("bounds_floor")
    if floor not in (None, "rigid") and wall is None:
        rd.bad(f"analysis.bounds_floor = {floor!r}: only used with a [wall] (a tank's floor); "
               f"remove it")
    if width is not None and (wall is None or floor != "flexible"):
        rd.bad(f"analysis.bounds_ring_width = {width!r}: only used with a [wall] and "
               f"analysis.bounds_floor = \"flexible\" (the band the shell's load is spread "
               f"on); remove it")
    if width is not None and wall is not None and isinstance(wall.get("radius"), (int, float)) \
            and not 0.0 < width < wall["radius"]:
        rd.bad(f"analysis.bounds_ring_width = {width!r} m: must lie between 0 and the shell's "
               f"radius ({wall['radius']!r} m); about the annular plate's width")
    frictional = any(x.get("friction_angle") for x in [soil, *layers])
    if frictional and soil.get("water_table") is not None:
        rd.bad(f"soil.water_table = {soil['water_table']!r} with analysis.collapse = "
               f"\"bounds\" and a friction angle: the bounds take a frictional soil's weight "
               f"without pore pressure; remove the water table (give the unit weight below "
               f"it, the buoyant one) or ask for collapse = \"load\"")


def check_discretisation(rd: Reader, mesh: dict, solver: dict, soil: dict,
                         layers: list, flexible: bool) -> tuple[Any, Any]:
    """The mesh's degree and the solver against the soil: a nearly incompressible soil
    (the mixed form) needs degree 2 or 3 and the direct solver. Returns (degree, method),
    as given or defaulted."""
    # a flexible load (no plate) defaults to P3 on a mesh twice as coarse: the soil alone
    # decides its error, and there that is on the efficient front (docs/performance.md)
    deg = mesh.get("degree", FLEXIBLE_DEGREE if flexible else 2)
    if deg not in KEYS["mesh"]["degree"].choices:
        rd.bad(f"mesh.degree = {deg!r}: must be 1, 2, 3 or 4 (the default: 2 under a plate, 3 "
               f"for a flexible load)")
    nus = [x.get("nu") for x in [soil, *layers]]
    nus = [v for v in nus if isinstance(v, (int, float))]
    nu_s = max(nus) if nus else None
    law = SOIL_LAWS.get(soil.get("model", Soil.model))
    all_mixed = law is not None and law.all_mixed
    if all_mixed and nus:
        # solved in the mixed form throughout
        if min(nus) <= 0.0:
            rd.bad(f"soil nu = {min(nus)!r}: {law.title} is solved in the mixed "
                   f"form, which takes 1 / lambda, infinite at nu = 0; use nu > 0")
        nu_s = 0.5
    method = solver.get("method", SolverOptions.method)
    if isinstance(method, str) and method not in SOLVER_METHODS:
        rd.bad(f"solver.method = {method!r}: one of {', '.join(SOLVER_METHODS)}"
               f"{suggest(method, SOLVER_METHODS)}")
    mixed_why = f"{law.title} ({law.all_mixed})" if all_mixed else f"soil nu = {nu_s!r}"
    if method == "iterative" and nu_s is not None and nu_s > MIXED_FROM_NU:
        rd.bad(f"solver.method = \"iterative\" with {mixed_why}: the mixed form of a "
               f"nearly incompressible soil (nu > {MIXED_FROM_NU}) has a zero pressure block "
               f"that GAMG cannot take; use method = \"direct\"")
    if deg == 1 and nu_s is not None and nu_s > MIXED_FROM_NU:
        rd.bad(f"mesh.degree = 1 with {mixed_why}: a nearly incompressible soil is "
               f"solved in the mixed (Taylor-Hood) form, which needs degree 2 to 4; use "
               f"degree 2, 3 or 4")
    return deg, method


def check_domain(rd: Reader, domain: dict, mesh: dict, a: float | None, D: float,
                 layers: list) -> None:
    """The domain around the foundation (radius ``a``, underside at depth ``D``): wider
    than it, its base below it and below every layer's top; the mesh resolving it."""
    if a is None or not a > 0:
        return
    default = DEFAULT_DOMAIN_FACTOR * a
    if domain.get("radius", default) <= 2.0 * a:
        rd.bad(f"domain.radius = {domain['radius']!r} m: must exceed twice the foundation "
               f"radius ({2 * a!r} m) for the soil to surround the structure; omit it for "
               f"the half-space default ({default:g} m)")
    # a rigid base may lie shallower than the foundation is wide (a wide tank on a thin
    # soft layer over rock), but below the foundation
    if domain.get("depth", default) <= D:
        rd.bad(f"domain.depth = {domain.get('depth', default)!r} m: the rigid base must lie "
               f"below the foundation's underside (embedment {D!r} m); deepen the domain "
               f"or omit domain.depth for the half-space default ({default:g} m)")
    for key in ("radius", "depth"):
        if domain.get(key, default) > DOMAIN_WIDEST * a:
            rd.bad(f"domain.{key} = {domain[key]:g} m: more than {DOMAIN_WIDEST:g} foundation "
                   f"radii ({DOMAIN_WIDEST * a:g} m); the half-space's truncation error falls "
                   f"as 1/R (0.0074 % at the default {default:g} m), so a wider domain gains "
                   f"nothing but round-off: omit domain.{key} for the half-space")
    base = domain.get("depth", default)
    for k, layer in enumerate(layers, start=1):
        if layer.get("depth", 0.0) >= base:
            rd.bad(f"soil.layers[{k}].depth = {layer['depth']!r} m: at or below the rigid "
                   f"base (domain.depth = {base!r} m); deepen the domain or remove the "
                   f"layer")
    if mesh.get("edge_size", 0.0) > 0.5 * a:
        rd.bad(f"mesh.edge_size = {mesh['edge_size']!r} m: larger than half the foundation "
               f"radius ({0.5 * a!r} m); the foundation would not be resolved")
