"""The summary a run prints and the report it writes (report.md): the key results, the scene
in words, the warnings.

The paper: Eq. 23's non-dimensional measures beside the dimensional results.
"""
from __future__ import annotations

import math
from pathlib import Path

from ..scene.reader import KEYS, LAYER_KEYS
from ..scene.sections import STATES_CONDITION
from .collapse import bounds_rows, collapse_rows


def summary_rows(results: dict) -> list[tuple[str, str, str]]:
    """What an engineer reads first, as (quantity, value, note) rows: whether the results
    are valid, the load by its parts, the settlements, the bearing pressure, the moments and
    the wall's forces (dimensional, in mm, kPa, kN m/m), what a tank code asks of the
    settlements; then the paper's non-dimensional set (Eq. 23, its p defined), the
    interface's state and the iterations. Only the rows the scene has (no moments without a
    plate, no interface lengths for a bonded one)."""
    return (_validity_rows(results) + _load_rows(results) + _settlement_rows(results)
            + _bearing_rows(results) + _structure_rows(results)
            + _consolidation_rows(results) + _fill_rows(results) + _overturning_rows(results)
            + collapse_rows(results) + bounds_rows(results) + _nondim_rows(results) + _iteration_rows(results)
            + _stage_rows(results))


def force(newtons: float) -> str:
    """A force in kN or MN, four significant digits."""
    return (f"{newtons / 1e6:.4g} MN" if abs(newtons) >= 1e6 else
            f"{newtons / 1e3:.4g} kN")


def stress(pascals: float) -> str:
    """A stress or pressure with the digits its size needs: MPa from 1 MPa, else kPa."""
    return (f"{pascals / 1e6:.3g} MPa" if abs(pascals) >= 1e6 else
            f"{pascals / 1e3:.3g} kPa")


def moment(newton_metres: float) -> str:
    """A moment per unit length in kN m/m, four significant digits."""
    return f"{newton_metres / 1e3:.4g} kN m/m"


def _validity_rows(r: dict) -> list[tuple[str, str, str]]:
    """Whether the results lie within the model's range (tankfx.results.validity): a row
    only where they do not, naming each part outside it."""
    v = r.get("validity")
    if v is None or v["valid"]:
        return []
    bad = [part for part, ok in v["parts"].items() if not ok]
    return [("VALIDITY", "NOT VALID: " + ", ".join(p.replace("_", " ") for p in bad),
             "; ".join(v["notes"]))]


#: the vertical load's parts, in the order and words of the summary
LOAD_PARTS = (("liquid", "liquid"), ("self_weight", "self-weight"), ("roof", "roof"),
              ("pressure", "pressure"))


def _load_rows(r: dict) -> list[tuple[str, str, str]]:
    """The vertical load and its parts (a gas pressure's force on the floor, which the
    roof carries back up, beside them)."""
    vl = r.get("vertical_load")
    if vl is None:
        return []
    parts = [f"{words} {force(vl[key])}" for key, words in LOAD_PARTS if vl[key]]
    if vl["gas"]:
        parts.append(f"gas {force(vl['gas'])} on the floor, carried back up by the roof")
    return [("vertical load", force(vl["total"]), ", ".join(parts))]


def _settlement_rows(r: dict) -> list[tuple[str, str, str]]:
    """The settlements in mm."""
    rows = [("centre settlement w0", f"{1e3 * r['w0']:.2f} mm", ""),
            ("edge settlement w_edge", f"{1e3 * r['w_edge']:.2f} mm",
             "at the plate's edge" if "plate" in r["profiles"] else "at the load's edge"),
            ("differential settlement wd", f"{1e3 * r['wd']:.2f} mm",
             "largest minus smallest under the foundation")]
    return rows


def _bearing_rows(r: dict) -> list[tuple[str, str, str]]:
    """The mean and largest bearing pressure."""
    bp = r.get("bearing_pressure")
    if bp is None:
        return []
    rows = [("bearing pressure: mean", stress(bp["mean"]),
             "vertical load over the foundation's area")]
    if "plate" in r["profiles"]:
        a = r["scene"]["plate"]["radius"]
        edge = bp["at"] >= 0.95 * a
        rows.append(("bearing pressure: largest", stress(bp["largest"]),
                     f"at r = {bp['at']:.3g} m" + (" (the edge element's average: grows as "
                                                   "the mesh is refined)" if edge else "")))
    return rows


def _structure_rows(r: dict) -> list[tuple[str, str, str]]:
    """The centre and joint moments, the wall's hoop force and courses, the settlement
    summary."""
    rows = []
    if r.get("M0") is not None:
        rows.append(("centre moment M0", moment(r["M0"]), "plate, radial"))
    if "junction" in r:
        j = r["junction"]
        rows += [("plate moment at the joint", moment(j["M_plate"]),
                  f"6 M / t^2 = {stress(j['plate_bending_stress'])}"),
                 ("wall base moment", moment(j["M_wall"]),
                  f"6 M / t^2 = {stress(j['wall_bending_stress'])}")]
    wall = r["profiles"].get("wall")
    if wall:
        rows.append(("largest wall hoop force", f"{max(wall['N_theta']) / 1e3:.4g} kN/m", ""))
    courses = r.get("courses", [])
    for k, c in enumerate(courses, start=1):
        # what a tank code checks against its allowable stress, course by course
        which = f"course {k} ({1e3 * c['thickness']:.4g} mm)" if len(courses) > 1 else "wall"
        rows.append((f"{which}: largest hoop stress", stress(c["max_hoop_stress"]),
                     f"at {c['at']:.2f} m; M_z up to {moment(c['max_abs_M_z'])} in size"))
    ss = r.get("settlement_summary")
    if ss:
        rows += [("uniform settlement (mean)", f"{1e3 * ss['uniform_settlement']:.2f} mm", ""),
                 ("settlement at the shell", f"{1e3 * ss['shell_settlement']:.2f} mm", ""),
                 ("centre-to-shell dish", f"{1e3 * ss['dish']:.2f} mm",
                  f"dish / radius = {ss['dish_over_radius']:.2e}")]
    return rows


def _nondim_rows(r: dict) -> list[tuple[str, str, str]]:
    """The paper's non-dimensional set (Eq. 23) with its p, E_s and a defined, and the
    relative rigidities (Eqs. 21-22)."""
    nd, sc = r["nondim"], r["scene"]
    a = sc["plate"]["radius"] if "plate" in sc else sc["load"]["load_radius"]
    p = r["reference_pressure"]
    if nd["w0"] is None:
        values, note = "none", "no p: Eq. 23 needs a pressure on the floor"
    else:
        values = ", ".join(f"{nd[k]:.4g}" for k in ("w0", "wd", "M0") if nd[k] is not None)
        note = (f"Eq. 23: w E_s / (p a), M / (p a^2); p = {stress(p)} (the pressure, liquid "
                f"and gas on the floor: self-weight and roof are not in p), E_s = "
                f"{stress(sc['soil']['E'])}, a = {a:g} m")
    names = "w0_bar, wd_bar" + (", M0_bar" if nd.get("M0") is not None else "")
    rows = [(names, values, note)]
    if nd.get("Kp") is not None:
        rows.append(("Kp" + (", Kt" if nd.get("Kt") is not None else ""),
                     ", ".join(f"{nd[k]:.4g}" for k in ("Kp", "Kt") if nd.get(k) is not None),
                     "Eqs. 21-22, relative rigidities"))
    return rows


def _consolidation_rows(r: dict) -> list[tuple[str, str, str]]:
    """A consolidation: undrained, at each reported time, drained."""
    rows = []
    c = r.get("consolidation")
    if c:
        rows += [("consolidation: undrained w0 (t = 0)", f"{1e3 * c['undrained']['w0']:.2f} mm",
                  f"c_v = {c['c_v']:.3g} m^2/s, a^2 / c_v = {c['time_scale'] / 86400:.4g} "
                  f"days")]
        path = "at_stages" in c        # a load path: each time's load too
        rows += [(f"  w0 at t = {s['t_days']:.4g} days", f"{1e3 * s['w0']:.2f} mm",
                  ("" if s["degree"] is None else f"U = {s['degree']:.3f}, ") +
                  f"excess pore pressure on the axis "
                  f"{s['axis_pore_pressure'] / 1e3:.3g} kPa"
                  + (f", load {s['applied_load'] / 1e6:.4g} MN" if path else ""))
                 for s in c["at_times"][1:]]
        drained = c["drained"]["w0"]
        rows.append(("  drained limit w0 (t -> infinity)",
                     "not carried" if drained is None else f"{1e3 * drained:.2f} mm",
                     f"the results above: t = {c['at_times'][-1]['t_days']:.4g} days"))
    return rows


def _fill_rows(r: dict) -> list[tuple[str, str, str]]:
    """A fill schedule: the plan, a row a step (its hold, its filling days, its factor of
    safety), its total and the fill with no hold."""
    f = r.get("fill")
    if not f:
        return []
    rows = [("fill: safe schedule" if f["complete"] else "fill: safe only to",
             f"{f['total_days']:.4g} days" if f["complete"] else f"{f['reached_height']:.4g} m",
             f"to {f['height']:g} m in steps of {f['step']:g} m at {f['rate']:g} m/day, the "
             f"factor of safety at least {f['target_factor']:g} at each step's end (holds "
             f"to {f['hold_resolution_days']:g} day)" + ("" if f["complete"] else
                                                         f": {f['reason']}"))]
    for k, s in enumerate(f["schedule"], start=1):
        F = s["strength_factor"]
        rows.append((f"  step {k}: to {s['height']:.4g} m",
                     f"hold {s['hold_days']:.4g} d" if s["hold_days"] else "no hold",
                     f"fills from day {s['fill_start_day']:.4g} to {s['fill_end_day']:.4g}; "
                     f"factor of safety {'-' if F is None else f'{F:.3g}'}, w0 "
                     f"{1e3 * s['w0']:.1f} mm, w_edge {1e3 * s['w_edge']:.1f} mm"))
    rows.append(("fill: no holds, least factor of safety",
                 f"{f['unheld_factor']:.3g}" if f["unheld_factor"] is not None else "-",
                 (f"the ground fails at {f['unheld_height']:.4g} m of liquid" if
                  f["unheld_fails"] else f"at {f['unheld_height']:.4g} m of liquid")
                 + f", filled at {f['rate']:g} m/day"))
    return rows


def _stage_note(s: dict) -> str:
    """A consolidation stage's load, piezometers and factor of safety, in words."""
    words = [f"load {s['applied_load'] / 1e6:.4g} MN"]
    if s.get("piezometers"):
        words.append("piezometers " + ", ".join(f"{u / 1e3:.3g}" for u in s["piezometers"])
                     + " kPa")
    col = s.get("collapse")
    if col is not None:
        words.append(f"factor of safety {col['strength_factor']:.3g}" if col["found"] else
                     f"factor of safety above {col['strength_factor']:.3g} (not bracketed)")
    return ", ".join(words)


def _overturning_rows(r: dict) -> list[tuple[str, str, str]]:
    """The overturning's first harmonic: tilt, toe and heel, the wall's foot."""
    rows = []
    o = r.get("overturning")
    if o:
        # the first harmonic: toe = the side pressed down (theta = 0), heel = the other
        rows += [("overturning: tilt", f"{1e3 * o['tilt']:.3f} mm/m",
                  f"M = {o['moment'] / 1e3:.4g} kN m, V = {o['shear'] / 1e3:.4g} kN"),
                 ("rocking stiffness M / tilt", "no moment" if o["rocking_stiffness"] is None
                  else f"{o['rocking_stiffness']:.4g} N m/rad",
                  "" if o["rocking_stiffness"] is None else
                  f"K (1 - nu_s^2) / (E_s a^3) = {o['nondim']['rocking_stiffness']:.4f} "
                  f"(rigid disc 4/3)"),
                 ("shell settlement toe / heel",
                  f"{1e3 * o['toe']['shell_settlement']:.2f} / "
                  f"{1e3 * o['heel']['shell_settlement']:.2f} mm", ""),
                 ("contact stress: toe max / heel min",
                  f"{o['toe']['max_contact_normal'] / 1e3:.1f} / "
                  f"{o['heel']['min_contact_normal'] / 1e3:.1f} kPa",
                  f"a heel contact zone lifts at {o['uplift']['onset_factor']:.3g} x this "
                  f"overturning load" + (" (see the warning)" if o["uplift"]["lifts"] else ""))]
        if "wall_foot" in o:
            wf, jn = o["wall_foot"], o["junction"]
            rows += [("wall foot axial stress toe / heel",
                      f"{wf['axial_stress_toe'] / 1e6:.2f} / "
                      f"{wf['axial_stress_heel'] / 1e6:.2f} MPa",
                      "N_z / t, tension positive"),
                     ("joint bending toe / heel: wall",
                      f"{jn['wall_bending_stress_toe'] / 1e6:.1f} / "
                      f"{jn['wall_bending_stress_heel'] / 1e6:.1f} MPa", "6 M / t^2"),
                     ("joint bending toe / heel: plate",
                      f"{jn['plate_bending_stress_toe'] / 1e6:.1f} / "
                      f"{jn['plate_bending_stress_heel'] / 1e6:.1f} MPa", "6 M / t^2")]
        eq = o["equilibrium"]
        error = max(eq["moment_relative_error"], eq["shear_relative_error"])
        rows.append(("overturning equilibrium error", f"{error:.1e}",
                     "moment and shear resisted by the interface"))
    return rows


def _iteration_rows(r: dict) -> list[tuple[str, str, str]]:
    """The interface's slipping and separated lengths, the iterations, equilibrium."""
    rows = []
    ifc = r.get("interface", {})
    if ifc.get("condition") == STATES_CONDITION:
        parts = [p for p in ("plate", "wall") if p in r["profiles"]]
        for state, label in (("slip", "slipping"), ("separated", "separated")):
            rows.append((f"interface {label}", ", ".join(
                f"{ifc[f'{state}_length'][p]:.2f} m {p}" for p in parts), ""))
    soil = r.get("soil", {})
    note = (f"cells at the ultimate: {soil['cells_at_ultimate']}"
            if "cells_at_ultimate" in soil else "")
    if "excavation" in r:
        # (an embedded foundation on the elastoplastic soil: its pit dug first)
        ex = r["excavation"]
        rows.append(("excavation of the pit: heave", f"{1e3 * ex['heave']:.2f} mm",
                     f"at its bottom's centre, before the tank is built on it (its "
                     f"displacements are measured from then); {ex['plastic_points']} points "
                     f"yield, {ex['steps']} load steps"))
    if "plastic_points" in soil:
        # (an elastoplastic soil: where it yields, and how far)
        rows.append(("soil yielding", f"{soil['plastic_points']} quadrature points",
                     f"largest plastic shear strain {soil['max_plastic_shear_strain']:.2e}"))
        s_u = soil.get("undrained_strength") or {}
        if s_u.get("points"):
            # (Cam Clay: the strength a field vane would measure, where the clay yields)
            rows.append(("undrained strength where the clay yields",
                         f"{s_u['min'] / 1e3:.3g} to {s_u['max'] / 1e3:.3g} kPa",
                         f"mean {s_u['mean'] / 1e3:.3g} kPa over {s_u['points']} points, "
                         f"{s_u['depth_min']:.3g} to {s_u['depth_max']:.3g} m deep "
                         f"(s_u = M/2 p' (p_c / 2p')^L: check against field vanes)"))
        note = f"{soil['time_steps']} time steps" if "time_steps" in soil else \
            f"{soil['steps']} load steps"
    rows.append(("iterations: soil, interface (solves)", f"{soil.get('iterations', 0)}, "
                 f"{ifc.get('iterations', 0)} ({r['linear_solves']})", note))
    eq = r["equilibrium"]
    rows.append(("equilibrium error", f"{eq['relative_error']:.1e}",
                 "supports' reaction against the applied load"))
    return rows


def _stage_rows(r: dict) -> list[tuple[str, str, str]]:
    """The load path's stages (the last being the rows above)."""
    rows = []
    for st in r.get("stages", []):       # the load path, the last stage being the above
        lengths = st.get("interface", {})
        note = ", ".join(f"{state} {sum(lengths[f'{state}_length'].values()):.2f} m"
                         for state in ("slip", "separated", "rebonded")
                         if f"{state}_length" in lengths)
        if st.get("unloading_cells"):
            note = ", ".join(x for x in (note, f"{st['unloading_cells']} soil cells unloading")
                             if x)
        if "t_days" in st:
            # (a consolidation's stage: its state when its load is reached)
            note = f"at t = {st['t_days']:.4g} days: {_stage_note(st)}"
        rows.append((f"stage {st['stage']}: w0", f"{1e3 * st['w0']:.2f} mm", note))
        if "settlement_kept" in st:
            # (back to an earlier load: what the ground did not give back)
            kept = st["settlement_kept"]
            since = (f"stage {kept['since']}'s load" if kept["since"] else
                     "no load, as at the start")
            rows.append((f"stage {st['stage']}: settlement kept", f"{1e3 * kept['w0']:.2f} mm",
                         f"permanent: back to {since} (mean {1e3 * kept['w_mean']:.2f} mm)"))
    return rows


def summary_table(results: dict) -> str:
    """:func:`summary_rows` as a plain-text table."""
    lines = [f"{'quantity':36s} {'value':>26s}   note"]
    lines += [f"{name:36s} {value:>26s}   {note}" for name, value, note in
              summary_rows(results)]
    return "\n".join(lines)


#: an SI unit's multiples the results are shown in, largest first
MULTIPLES = {"Pa": ((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa")), "N": ((1e6, "MN"), (1e3, "kN")),
             "N m": ((1e6, "MN m"), (1e3, "kN m")), "N/m^3": ((1e3, "kN/m^3"),)}


def quantity(value, unit: str) -> str:
    """A scene value with its unit, in the multiple that reads best (GPa for a concrete's
    modulus, kPa for a pressure, kN/m^3 for a unit weight, MN for a load)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return value
    if not isinstance(value, (int, float)):
        return str(value)
    for factor, name in MULTIPLES.get(unit, ()):
        if abs(value) >= factor:
            return f"{value / factor:.4g} {name}"
    return f"{value:.4g}" + (f" {unit}" if unit and unit != "-" else "")


def scene_rows(results: dict) -> list[tuple[str, str]]:
    """The scene as the report shows it: each section's keys with their units (the
    resolved values: a thickness from Kp too), a stratum per row, the interface's friction
    as an angle."""
    sc = results["scene"]
    rows = []
    for name, keys in KEYS.items():
        table = sc.get(name)
        if not isinstance(table, dict):
            continue
        items = [f"{k} = {quantity(v, keys[k].unit if k in keys else '')}"
                 for k, v in table.items()
                 if k in keys and not isinstance(v, (list, dict)) and v is not None
                 # (a load's parts that are not there, and a plate's own radius again)
                 and not (name == "load" and (v in (0.0, False) or
                                              (k == "load_radius" and "plate" in sc)))]
        if name == "wall" and table.get("courses"):
            items.append("courses (height x thickness, from the bottom): " + ", ".join(
                f"{c['height']:g} m x {1e3 * c['thickness']:.4g} mm" for c in table["courses"]))
        if name == "interface" and table.get("tan_phi") is not None:
            items.append(f"friction angle = {math.degrees(math.atan(table['tan_phi'])):.3g} deg")
        if name in ("plate", "wall"):
            K = "Kp" if name == "plate" else "Kt"
            items.append(f"{K} = {results['nondim'][K]:.4g}")
        rows.append((name, ", ".join(items)))
        if name == "soil":
            for k, layer in enumerate(table.get("layers", []), start=1):
                rows.append((f"soil layer {k}", ", ".join(
                    f"{key} = {quantity(v, LAYER_KEYS[key].unit)}" for key, v in layer.items()
                    if key in LAYER_KEYS and v is not None)))
    if sc.get("accept"):
        rows.append(("accepted", ", ".join(sc["accept"]) + " (outside their plausible ranges, "
                                                          "as the scene asks)"))
    if "stages" in results:
        rows.append(("load path", f"these results are the last of {len(results['stages'])} "
                                  f"stages"))
    return rows


def _cell(text: str) -> str:
    """A Markdown table cell: its pipes escaped."""
    return str(text).replace("|", "\\|")


def write_report(results: dict, figures: list[Path], path) -> Path:
    """A one-page Markdown report of a run beside its results (rank 0 only): the scene with
    its units, the summary table, the warnings, and the figures (by their file names, so
    the report and the figures move together)."""
    path = Path(path)
    r = results
    lines = [f"# {r['title']}", ""]
    lines += ["| scene | |", "|---|---|",
              *(f"| {_cell(k)} | {_cell(v)} |" for k, v in scene_rows(r)), ""]
    lines += ["| quantity | value | note |", "|---|---|---|",
              *(f"| {_cell(a)} | {_cell(b)} | {_cell(c)} |" for a, b, c in summary_rows(r)),
              ""]
    for w in r.get("warnings", []):
        lines.append(f"**Warning:** {w}")
    for f in figures:                # a paragraph each: one figure per line of the page
        lines += ["", f"![{f.stem}]({f.name})"]
    lines += ["", footer(r), ""]
    path.write_text("\n".join(lines))
    return path


def footer(r: dict) -> str:
    """How the results were computed, in a line."""
    return (f"{r['dofs']['total']} dofs, {r['mpi_ranks']} MPI rank(s), "
            f"{r['timings_s']['total']:.1f} s; tankfx {r['versions'].get('tankfx', '?')}, "
            f"DOLFINx {r['versions'].get('dolfinx', '?')}. Numbers in results.json; "
            f"conventions there under `conventions`.")
