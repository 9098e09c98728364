"""The results.json contract: the keys a solved stage reports, their conventions, the
non-dimensional set of Eq. 23, the load path's stage table, and the versions of the software.
The result keys are public; see docs/guide/outputs.md.
"""
from __future__ import annotations

import platform
from importlib import metadata

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
import numpy as np

from ..fem.evaluate import evaluate_at, nodal_values_on_facets
from ..fem.solvers import reaction_force
from ..laws.rigidity import nondimensional
from ..mesh import Domain
from ..model.tank import TankModel
from ..scene.scene import Scene
from ..scene.sections import load_breakdown, vertical_load
from .structure import structure_results

CONVENTIONS = {
    "units": "SI: m, Pa, N, N m/m",
    "w": "settlement, positive downward",
    "u_r": "radial displacement, positive outward",
    "profiles.axis.z": "depth below the ground surface, positive downward",
    "sigma_zz": "vertical soil stress, positive in compression",
    "nondim": "Eqs. 21-23 of Zaman & Mahmood: w = p a w_bar / E_s, M = p a^2 M_bar, "
              "E_s = soil modulus at the ground surface, a = plate (or load) radius, "
              "p = reference_pressure = load.pressure + liquid (and gas) pressure on the plate "
              "floor",
    "M_r, M_theta, M_z": "bending moments per unit length, positive when the plate's "
                         "underside (the wall's outer face) is in tension: sagging plate "
                         "moment positive",
    "N_theta": "hoop force per unit length, tension positive",
    "Q_r, Q": "transverse shear force per unit length on a section facing +r (plate) or +z "
              "(wall), positive upward on the plate and inward on the wall",
    "rotation": "counter-clockwise rotation of the meridian in the (r, z) plane, rad",
    "contact_normal": "interface normal stress, positive in compression, Pa",
    "contact_shear": "interface shear stress exerted by the soil on the structure, positive "
                     "outward (+r) under the plate and upward on the wall, Pa",
    "profiles.wall.z": "height above the plate underside (the wall base), m",
    "reaction": "upward force of the supports on the soil, N",
    "overturning": "first Fourier harmonic: an amplitude f is the value at theta = 0 of "
                   "f cos(theta) (f sin(theta) for u_theta and N_z_theta); theta = 0 is the "
                   "side a positive overturning_moment presses down and base_shear pushes "
                   "towards; toe / heel: the sides pressed down / lifted (axisymmetric "
                   "+ / - amplitude); tilt in rad, positive towards theta = 0",
}


def versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("tankfx", "dolfinx-solver-real", "fenics-basix", "fenics-ffcx", "fenics-ufl",
                "petsc4py", "gmsh", "numpy", "mpi4py"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            pass
    import dolfinx

    out["dolfinx"] = dolfinx.__version__
    return out


def stage_summary(r: dict) -> dict:
    """A stage's key numbers, for the load path's table in the last stage's results."""
    out = {"stage": r["stage"], "load": r["scene"]["load"],
           "applied_load": r["equilibrium"]["applied_load"],
           **{k: r[k] for k in ("w0", "w_edge", "wd", "w_mean", "M0", "nondim")},
           "soil_iterations": r["soil"]["iterations"], "linear_solves": r["linear_solves"],
           "tilt": r["overturning"]["tilt"] if "overturning" in r else None,
           "valid": r["validity"]["valid"],
           # (each stage's settlement profile, for the settlement figure's curve per stage)
           "surface": {k: r["profiles"]["surface"][k] for k in ("r", "w")}}
    if "unloading_cells" in r["soil"]:
        out["unloading_cells"] = r["soil"]["unloading_cells"]
    if "plastic_points" in r["soil"]:
        out["plastic_points"] = r["soil"]["plastic_points"]
    if "interface" in r:
        out["interface"] = {k: v for k, v in r["interface"].items()
                            if k.endswith("_length") or k in ("converged", "iterations")}
    return out


def settlement_kept(summaries: list[dict]) -> None:
    """Mark, on a load path of a soil that keeps a permanent strain, the settlement kept by
    each stage that returns to an earlier load after a larger one: ``settlement_kept`` =
    {"since": j, "w0": w0 - w0 of stage j, "w_mean": likewise}, j the first earlier stage
    with the same load (0: the start, where the stage's load is nothing). What the ground
    gave back elastically is out of it; what it keeps is its plastic strain's doing (a
    hydrotest's emptied tank: the permanent settlement)."""
    peak = 0.0
    for k, st in enumerate(summaries):
        load = abs(st["applied_load"])
        if peak > 0.0 and load < peak * (1.0 - 1e-9):
            same = [j for j in range(k) if summaries[j]["load"] == st["load"]]
            if same:
                before = summaries[same[0]]
                st["settlement_kept"] = {"since": before["stage"],
                                         **{w: st[w] - before[w] for w in ("w0", "w_mean")}}
            elif load <= 1e-12 * peak:
                st["settlement_kept"] = {"since": 0, "w0": st["w0"], "w_mean": st["w_mean"]}
        peak = max(peak, load)


def axis_pore_pressure(model, domain: Domain, z_axis, sigma_zz) -> dict:
    """A consolidating soil's excess pore pressure down the axis and the effective vertical
    stress sigma_zz - p (both compression positive; the total sigma_zz less the pore
    water's share): what an engineer's hand calculation of consolidation starts from."""
    p = model.soil.pore_pressure
    if p is None:
        return {}
    pw = evaluate_at(p, np.column_stack([np.zeros_like(z_axis), -z_axis]),
                     cells=domain.cells("soil"))[:, 0]
    return {"pore_pressure": pw.tolist(), "sigma_zz_effective": (sigma_zz - pw).tolist()}


def results_of(scene: Scene, domain: Domain, model, sigma_zz, statuses=None) -> dict:
    """results.json of a solved stage (``statuses``: its iterations', by name;
    :mod:`tankfx.iterations.stage`)."""
    a = scene.foundation_radius
    D = scene.embedment
    p = model.reference_pressure
    E_s = scene.soil.E
    u = model.soil.u
    found = model.foundation_results()

    # ground-surface profile (the loaded area or plate underside, and the free surface out to
    # 5 a), nodal values of the soil
    x, vals = nodal_values_on_facets(u, domain.facets("contact", "surface"))
    keep = x[:, 0] <= 5.0 * a + 1e-12
    surface = {"r": x[keep, 0].tolist(), "z": x[keep, 1].tolist(),
               "w": (-vals[keep, 1]).tolist(), "u_r": vals[keep, 0].tolist()}

    # down the axis 10 a, or to the base of a shallower domain
    z_axis = np.linspace(D, min(D + 10.0 * a, scene.domain.depth), 201)
    sz = evaluate_at(sigma_zz, np.column_stack([np.zeros_like(z_axis), -z_axis]),
                     cells=domain.cells("soil"))[:, 0]

    applied = model.applied_load
    # (an excavated pit: the ground lost the support of the soil taken out, upward)
    pit = model.soil.pit
    relieved = pit.released() if pit is not None and pit.share.value > 0.0 else 0.0
    reaction = reaction_force(model.soil_residual(), model.soil.V, 1,
                              model.soil.supported_facets, entity_maps=model.entity_maps)
    out = {
        "title": scene.title,
        "converged": True,
        **found,
        "nondim": {**nondimensional(found["w0"], found["wd"], found["M0"], p, a, E_s),
                   "Kp": scene.Kp, "Kt": scene.Kt},
        "reference_pressure": p,
        "profiles": {"surface": surface,
                     "axis": {"z": z_axis.tolist(), "sigma_zz": sz.tolist(),
                              **axis_pore_pressure(model, domain, z_axis, sz)}},
        "equilibrium": {"applied_load": applied, "reaction": reaction,
                        "relative_error": abs(reaction - applied + relieved) / model.load_scale,
                        **({"excavation_relief": relieved} if relieved else {})},
        "conventions": CONVENTIONS,
        "scene": scene.to_dict(resolved=True),
    }
    if isinstance(model, TankModel):
        extra = structure_results(model, (statuses or {}).get("interface"))
        out["profiles"].update(extra.pop("profiles"))
        out["equilibrium"].update(extra.pop("equilibrium"))
        out.update(extra)
    out["vertical_load"] = vertical_load_parts(scene)
    out["bearing_pressure"] = bearing_pressure(out, a)
    return out


def vertical_load_parts(scene: Scene) -> dict:
    """The vertical load by its parts (N, downward positive; tankfx.scene.sections.
    load_breakdown) and their resultant ``total`` (the gas's force on the floor is carried
    back up by the roof: not in it)."""
    parts = load_breakdown(scene.load, scene.plate, scene.wall, scene.ringwall)
    return parts | {"total": vertical_load(scene.load, scene.plate, scene.wall,
                                           scene.ringwall)}


def bearing_pressure(results: dict, a: float) -> dict:
    """The bearing pressure under the foundation, Pa: ``mean``, the vertical load over the
    foundation's area (a ringwall's net weight included), and, under a plate, the
    ``largest`` contact normal stress of its stations and where (``at``, m; at the plate's
    edge it is the edge element's average, which grows as the mesh is refined: the
    singularity); a flexible load's is its pressure."""
    mean = results["vertical_load"]["total"] / (np.pi * a**2)
    plate = results["profiles"].get("plate")
    if plate is None:
        return {"mean": mean, "largest": results["scene"]["load"]["pressure"], "at": 0.0}
    sn = np.asarray(plate["contact_normal"])
    k = int(np.argmax(sn))
    return {"mean": mean, "largest": float(sn[k]), "at": float(plate["r"][k])}
