"""The summary a run prints and the report it writes (report.md): the key results, the scene
in words, the warnings.

The paper: Eq. 23's non-dimensional measures beside the dimensional results.
"""
from __future__ import annotations

from pathlib import Path

from ..scene.text import member_text, ringwall_text, stratum_constants


def summary_rows(results: dict) -> list[tuple[str, str, str]]:
    """What an engineer reads first, as (quantity, value, non-dimensional / note) rows: the
    settlements and their Eq. 23 measures, the moments and the wall's hoop force, what a tank
    code asks of the settlements, the interface's state and the iterations. Only the rows
    the scene has (no moments without a plate, no interface lengths for a bonded one)."""
    return (_validity_rows(results) + _settlement_rows(results) + _structure_rows(results)
            + _consolidation_rows(results) + _overturning_rows(results)
            + _iteration_rows(results) + _stage_rows(results))


def _validity_rows(r: dict) -> list[tuple[str, str, str]]:
    """Whether the results lie within the model's range (tankfx.results.validity): a row
    only where they do not, naming each part outside it."""
    v = r.get("validity")
    if v is None or v["valid"]:
        return []
    bad = [part for part, ok in v["parts"].items() if not ok]
    return [("VALIDITY", "NOT VALID: " + ", ".join(p.replace("_", " ") for p in bad),
             "; ".join(v["notes"]))]


def _settlement_rows(r: dict) -> list[tuple[str, str, str]]:
    """w0, wd and M0 with their Eq. 23 measures."""
    nd = r["nondim"]

    def bar(key, digits):            # Eq. 23 needs p: none under self-weight alone
        return "no p for Eq. 23" if nd[key] is None else f"{key}_bar = {nd[key]:.{digits}f}"

    rows = [("centre settlement w0", f"{1e3 * r['w0']:.2f} mm", bar("w0", 4)),
            ("differential settlement wd", f"{1e3 * r['wd']:.2f} mm", bar("wd", 4))]
    if r.get("M0") is not None:
        rows.append(("centre moment M0", f"{r['M0'] / 1e3:.2f} kN m/m", bar("M0", 5)))
    return rows


def _structure_rows(r: dict) -> list[tuple[str, str, str]]:
    """The joint's moments, the wall's hoop force and courses, the settlement summary."""
    rows = []
    if "junction" in r:
        j = r["junction"]
        rows += [("plate moment at the joint", f"{j['M_plate'] / 1e3:.2f} kN m/m",
                  f"6 M / t^2 = {j['plate_bending_stress'] / 1e6:.1f} MPa"),
                 ("wall base moment", f"{j['M_wall'] / 1e3:.2f} kN m/m",
                  f"6 M / t^2 = {j['wall_bending_stress'] / 1e6:.1f} MPa")]
    wall = r["profiles"].get("wall")
    if wall:
        rows.append(("largest wall hoop force", f"{max(wall['N_theta']) / 1e3:.1f} kN/m", ""))
    courses = r.get("courses", [])
    for k, c in enumerate(courses, start=1):
        # what a tank code checks against its allowable stress, course by course
        which = f"course {k} ({1e3 * c['thickness']:.4g} mm)" if len(courses) > 1 else "wall"
        rows.append((f"{which}: largest hoop stress", f"{c['max_hoop_stress'] / 1e6:.1f} MPa",
                     f"at {c['at']:.2f} m; |M_z| up to {c['max_abs_M_z'] / 1e3:.2f} kN m/m"))
    ss = r.get("settlement_summary")
    if ss:
        rows += [("uniform settlement (mean)", f"{1e3 * ss['uniform_settlement']:.2f} mm", ""),
                 ("settlement at the shell", f"{1e3 * ss['shell_settlement']:.2f} mm", ""),
                 ("centre-to-shell dish", f"{1e3 * ss['dish']:.2f} mm",
                  f"dish / radius = {ss['dish_over_radius']:.2e}")]
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
                  f"U = {s['degree']:.3f}, excess pore pressure on the axis "
                  f"{s['axis_pore_pressure'] / 1e3:.3g} kPa"
                  + (f", load {s['applied_load'] / 1e6:.4g} MN" if path else ""))
                 for s in c["at_times"][1:]]
        rows.append(("  drained limit w0 (t -> infinity)", f"{1e3 * c['drained']['w0']:.2f} mm",
                     f"the results above: t = {c['at_times'][-1]['t_days']:.4g} days"))
    return rows


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
    if ifc.get("condition") == "mohr_coulomb":
        parts = [p for p in ("plate", "wall") if p in r["profiles"]]
        for state, label in (("slip", "slipping"), ("separated", "separated")):
            rows.append((f"interface {label}", ", ".join(
                f"{ifc[f'{state}_length'][p]:.2f} m {p}" for p in parts), ""))
    soil = r.get("soil", {})
    note = (f"cells at the ultimate: {soil['cells_at_ultimate']}"
            if soil.get("model") == "hyperbolic" else "")
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
        rows.append((f"stage {st['stage']}: w0", f"{1e3 * st['w0']:.2f} mm", note))
    return rows


def summary_table(results: dict) -> str:
    """:func:`summary_rows` as a plain-text table."""
    lines = [f"{'quantity':36s} {'value':>26s}   non-dimensional / note"]
    lines += [f"{name:36s} {value:>26s}   {note}" for name, value, note in
              summary_rows(results)]
    return "\n".join(lines)


def write_report(results: dict, figures: list[Path], path) -> Path:
    """A one-page Markdown report of a run beside its results (rank 0 only): the scene in a
    few lines, the summary table, the warnings, and the figures (by their file names, so
    the report and the figures move together)."""
    path = Path(path)
    r, sc = results, results["scene"]
    soil = sc["soil"]
    lines = [f"# {r['title']}", ""]
    model = soil.get("model", "linear")
    scene_rows = [("soil", f"{model}, E_s = {soil['E']:.4g} Pa, nu = {soil['nu']:g}, lambda = "
                           f"{soil.get('E_gradient', 0.0):g} /m{stratum_constants(model, soil)}"
                           + (f"; unloads with E_ur = {soil['unloading_modulus_ratio']:g} x E_i"
                              if soil.get("unloading_modulus_ratio") else ""))]
    for k, layer in enumerate(soil.get("layers", []), start=1):
        scene_rows.append((f"layer {k}", f"from {layer['depth']:g} m down: E = "
                                         f"{layer['E']:.4g} Pa, nu = {layer['nu']:g}, lambda = "
                                         f"{layer.get('E_gradient', 0.0):g} /m"
                                         f"{stratum_constants(model, layer)}"))
    for name, K in (("plate", "Kp"), ("wall", "Kt")):
        if name in sc:
            scene_rows.append((name, member_text(name, sc[name], r["nondim"][K])))
    if "ringwall" in sc:
        scene_rows.append(("ringwall", ringwall_text(sc["ringwall"])))
    if "interface" in sc:
        scene_rows.append(("interface", sc["interface"]["condition"]))
    path_note = f" (the last of {len(r['stages'])} stages)" if "stages" in r else ""
    scene_rows.append(("load", ", ".join(f"{k} = {v:g}" if isinstance(v, float) else
                                         f"{k} = {str(v).lower()}"
                                         for k, v in sc["load"].items()
                                         if v not in (0.0, False, None)) + path_note))
    lines += ["| scene | |", "|---|---|", *(f"| {k} | {v} |" for k, v in scene_rows), ""]
    lines += ["| quantity | value | non-dimensional / note |", "|---|---|---|",
              *(f"| {a} | {b} | {c} |" for a, b, c in summary_rows(r)), ""]
    for w in r.get("warnings", []):
        lines.append(f"**Warning:** {w}")
    for f in figures:                # a paragraph each: one figure per line of the page
        lines += ["", f"![{f.stem}]({f.name})"]
    lines += ["", f"{r['dofs']['total']} dofs, {r['mpi_ranks']} MPI rank(s), "
                  f"{r['timings_s']['total']:.1f} s; tankfx {r['versions'].get('tankfx', '?')}, "
                  f"DOLFINx {r['versions'].get('dolfinx', '?')}. Numbers in results.json; "
                  f"conventions there under `conventions`.", ""]
    path.write_text("\n".join(lines))
    return path
