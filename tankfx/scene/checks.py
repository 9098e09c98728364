"""The rules of the scene's sections that go beyond a key's type: a soil's model and its
constants, layers, a wall's courses, an annular ring, a ringwall, a consolidation, the load
path's times. Each adds what it finds to the reader's problems.
"""
from __future__ import annotations

import math
from typing import Any

from .keys import (
    DRAINAGE,
    DUNCAN_CHANG,
    DUNCAN_CHANG_REQUIRED,
    LAYER_SPEC,
    SOIL_MODELS,
    Reader,
    suggest,
)
from .sections import (
    ATMOSPHERIC_PRESSURE,
    DEFAULT_DOMAIN_FACTOR,
    MIXED_FROM_NU,
    STRATUM_DUNCAN_CHANG,
    WATER_UNIT_WEIGHT,
    Layer,
    SceneError,
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


def check_consolidation(rd: Reader, c: dict, data: dict, soil: dict, layers: list,
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
    rd.choice(c, "consolidation", "drainage", "top", DRAINAGE,
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
    """The [soil] table's checks, its model's and its layers' (returned, checked)."""
    if soil is not None:
        rd.positive(soil, "soil", "E")
        rd.poisson(soil, "soil", incompressible=True)
        rd.positive(soil, "soil", "E_gradient", allow_zero=True)
        model = soil.get("model", "linear")
        if model not in SOIL_MODELS:
            rd.bad(f"soil.model = {model!r}: unknown model{suggest(model, SOIL_MODELS)}")
        elif model == "hyperbolic":
            read_kondner(rd, soil, soil, "soil", "the surface modulus of a hyperbolic soil")
        elif model == "duncan_chang":
            read_duncan_chang(rd, soil)
        if model == "linear" and "E" not in soil:
            rd.bad("soil.E: missing; add 'E = ...' under [soil] (Pa)")
        for key in ("hyperbolic_a", "hyperbolic_b"):
            if key in soil and model != "hyperbolic":
                rd.bad(f"soil.{key}: only used with model = \"hyperbolic\"; remove it")
        for key in ("tolerance", "max_iterations"):
            if key in soil and model == "linear":
                rd.bad(f"soil.{key}: only used with a nonlinear soil (model = \"hyperbolic\" "
                       f"or \"duncan_chang\"); remove it")
        for key in DUNCAN_CHANG:
            if key in soil and model != "duncan_chang":
                rd.bad(f"soil.{key}: only used with model = \"duncan_chang\"; remove it")
        tol = soil.get("tolerance")
        if tol is not None and not (0.0 < tol < 1.0):
            rd.bad(f"soil.tolerance = {tol!r}: the relative deviator misfit of Eq. 18 must "
                   f"lie in (0, 1) (the paper's 0.05 is the default)")
        if soil.get("max_iterations", 1) < 1:
            rd.bad("soil.max_iterations: must be >= 1")
        check_unloading(rd, soil, consolidating)
    layers = read_layers(rd, raw_layers, (soil or {}).get("model", "linear"),
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


def duncan_chang_values(part: dict, p_a: float) -> dict[str, float]:
    """Duncan & Chang's constants of a soil or layer table, defaults resolved."""
    phi = part.get("friction_angle", 0.0)
    return {"modulus_number": part["modulus_number"],
            "modulus_exponent": part["modulus_exponent"],
            "failure_ratio": part.get("failure_ratio", 0.9),
            "cohesion": part.get("cohesion", 0.0), "friction_angle": phi,
            "unit_weight": part["unit_weight"],
            "K0": part.get("K0", 1.0 - math.sin(math.radians(phi)))}


def read_layer(x: dict, hyperbolic: bool, dc: bool, dc_values: dict) -> Layer:
    """A checked [[soil.layers]] table, resolved."""
    if dc:
        values = duncan_chang_values(x, dc_values["atmospheric_pressure"])
        return Layer(depth=x["depth"], E=values["modulus_number"] *
                     dc_values["atmospheric_pressure"], nu=x["nu"], **values)
    return Layer(depth=x["depth"], E=1.0 / x["hyperbolic_a"] if hyperbolic else x["E"],
                 nu=x["nu"], E_gradient=x.get("E_gradient", 0.0),
                 hyperbolic_a=x.get("hyperbolic_a"), hyperbolic_b=x.get("hyperbolic_b"),
                 permeability=x.get("permeability"))


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
    if soil.get("model", "linear") not in ("hyperbolic", "duncan_chang"):
        rd.bad("soil.unloading_modulus_ratio: only used with a nonlinear soil (model = "
               "\"hyperbolic\" or \"duncan_chang\"): a linear soil unloads as it loads; "
               "remove it")
        return
    if isinstance(ratio, float) and not (math.isfinite(ratio) and ratio >= 1.0):
        rd.bad(f"soil.unloading_modulus_ratio = {ratio!r}: E_ur / E_i must be a number >= 1 "
               f"(unloading is stiffer than the loading curve's start; 1 is Masing's rule, "
               f"1-3 usual); a smaller E_ur would lift the soil above where it started")


def read_kondner(rd: Reader, table: dict, given, name: str, what_E: str) -> None:
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


def read_duncan_chang(rd: Reader, soil: dict, name: str = "soil",
                  p_a: float | None = None) -> None:
    """The keys of Duncan & Chang's soil (or of one of its layers, ``name``): K, n and the
    unit weight required; a strength (c or phi); E is K p_a, not given."""
    for key in DUNCAN_CHANG_REQUIRED:
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


def read_layers(rd: Reader, raw, model: str, p_a: float | None = None) -> list[dict[str, Any]]:
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
            read_duncan_chang(rd, layer, name, p_a)
        elif model == "hyperbolic":
            # every layer has its own Kondner parameters
            read_kondner(rd, layer, raw_layer, name, "the layer's modulus at its top")
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
