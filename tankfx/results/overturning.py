"""The overturning's results: the first harmonic superposed on the axisymmetric state (toe
and heel, the planar tilt, the contact stresses around the circumference) and the heel's
uplift check, in the results.json keys of ``overturning``.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..fem.evaluate import evaluate_at
from ..verification.reference import rigid_disc_rocking_stiffness


def heel_uplift(r, sn0, sn1) -> list[dict]:
    """The contact zones of the axisymmetric state (runs of stations ``r`` where its contact
    stress ``sn0`` presses) and, per zone, the multiple of the overturning load at which its
    net force on the heel side vanishes, int (sn0 - f sn1) r dr = 0 (``sn1``: the
    amplitude, positive where it presses the toe): the zone then lifts as a whole.

    Contact opens locally before that, at a zone's edges: where a zone borders a band
    already separated, sn0 falls to zero at the border and any overturning moves the
    border (a station-wise onset there tends to zero as the mesh is refined: measured 0.17
    and 0.0018 x the earthquake on the steel tank at 1 and 2 x the default resolution,
    while the zone's onset is mesh-converged); on a rigid disc the edge opens at 3 pi / 4
    of its zone's onset (e = a / 3 against 4 a / (3 pi))."""
    r, sn0, sn1 = (np.asarray(v, dtype=float) for v in (r, sn0, sn1))
    pressed = sn0 > 0.0
    zones, k = [], 0
    while k < len(r):
        if not pressed[k]:
            k += 1
            continue
        end = k
        while end + 1 < len(r) and pressed[end + 1]:
            end += 1
        if end > k:
            sl = slice(k, end + 1)
            F0 = float(np.trapezoid(sn0[sl] * r[sl], r[sl]))
            F1 = float(np.trapezoid(sn1[sl] * r[sl], r[sl]))
            zones.append({"r_min": float(r[k]), "r_max": float(r[end]), "force": F0,
                          "force_amplitude": F1,
                          "onset_factor": F0 / F1 if F1 > 0.0 else math.inf})
        k = end + 1
    return zones


def superpose(results: dict, amplitudes: dict, scene, sigma_zz=None,
              soil_cells=None) -> tuple[dict, list[str]]:
    """The overturning's results beside the axisymmetric ones: the amplitudes, the totals on
    the side pressed down (the "toe": theta = 0 for a positive moment, axisymmetric +
    amplitude; 180 deg for a negative one) and on the other (the "heel"), the tilt and
    rocking stiffness, and whether the heel lifts; with the warnings to give."""
    prof0, prof1 = results["profiles"], amplitudes["profiles"]
    plate0, plate1 = prof0["plate"], prof1["plate"]
    # the toe's side: where the tilt presses the tank down
    side = 1.0 if amplitudes["tilt"] >= 0.0 else -1.0
    sn0 = np.asarray(plate0["contact_normal"])
    sn1 = side * np.asarray(plate1["contact_normal"])
    w0, w1 = np.asarray(plate0["w"]), side * np.asarray(plate1["w"])
    plate1.update({"w_toe": (w0 + w1).tolist(), "w_heel": (w0 - w1).tolist(),
                   "contact_normal_toe": (sn0 + sn1).tolist(),
                   "contact_normal_heel": (sn0 - sn1).tolist()})
    line = prof1.get("soil_line")
    if line is not None and sigma_zz is not None:
        # the axisymmetric vertical stress on the same line
        pts = np.column_stack([line["r"], -np.asarray(line["depth"]) - scene.embedment])
        s0 = evaluate_at(sigma_zz, pts, soil_cells)[:, 0]
        s1 = side * np.asarray(line["sigma_zz"])
        line.update({"sigma_zz_axisymmetric": s0.tolist(), "sigma_zz_toe": (s0 + s1).tolist(),
                     "sigma_zz_heel": (s0 - s1).tolist()})
    r = np.asarray(plate1["r"])
    heel = sn0 - sn1
    # the stations where the superposed heel contact pulls: locally, at a contact zone's
    # edge, already at any load where the zone borders a separated band (its edge moves);
    # what lifts as a whole is a zone whose net force vanishes (heel_uplift)
    pulled = heel < 0.0
    span = (float(r[pulled].min()), float(r[pulled].max())) if pulled.any() else None
    zones = heel_uplift(r, sn0, sn1)
    a_p = scene.plate.radius
    E_s, nu_s = scene.soil.E, scene.soil.nu
    out = {k: amplitudes[k] for k in ("moment", "shear", "tilt", "shell_settlement_amplitude",
                                      "rocking_stiffness", "equilibrium")}
    out["rocking_stiffness_rigid_disc"] = rigid_disc_rocking_stiffness(E_s, nu_s, a_p)
    # in the manner of Eqs. 21-23: on the surface soil's E_s, nu_s and the plate's radius
    # (4/3 for the rigid disc, 3 pi^2 / 16 for the flexible plate by its edge's tilt)
    K = amplitudes["rocking_stiffness"]
    out["nondim"] = {"rocking_stiffness": None if K is None else K * (1 - nu_s**2)
                     / (E_s * a_p**3)}
    out["profiles"] = prof1
    shell0 = results["settlement_summary"]["shell_settlement"]
    shell1 = side * amplitudes["shell_settlement_amplitude"]
    out["toe"] = {"theta": 0.0 if side > 0 else 180.0,
                  "max_contact_normal": float((sn0 + sn1).max()),
                  "shell_settlement": float(shell0 + shell1)}
    out["heel"] = {"theta": 180.0 if side > 0 else 0.0,
                   "min_contact_normal": float(heel.min()),
                   "shell_settlement": float(shell0 - shell1)}
    first = min(zones, key=lambda z: z["onset_factor"], default=None)
    onset = first["onset_factor"] if first else math.inf
    out["uplift"] = {"lifts": onset < 1.0, "onset_factor": onset,
                     "zone": None if first is None else [first["r_min"], first["r_max"]],
                     "zones": zones,
                     "local_tension": bool(pulled.any()), "local_tension_r_range": span}
    warnings = []
    if onset < 1.0:
        linear = not scene.interface.has_states
        warnings.append(
            f"overturning: on the heel side the contact zone r = {first['r_min']:.4g}-"
            f"{first['r_max']:.4g} m is pulled as a whole (it lifts at {onset:.3g} x this "
            f"overturning load); "
            + (f"the {scene.interface.condition} interface (two-sided) holds it, where a "
               f"real foundation lifts: " if linear else
               "a Mohr-Coulomb interface cannot hold it, the foundation lifts there: ")
            + "the superposed results there no longer hold; lower load.overturning_moment "
              "or treat the uplift separately (not modelled)")
    if "wall" in prof1 and "wall" in prof0:
        wall0, wall1 = prof0["wall"], prof1["wall"]
        N0, N1 = np.asarray(wall0["N_z"]), side * np.asarray(wall1["N_z"])
        t = np.asarray(wall0["thickness"])
        wall1.update({"N_z_toe": (N0 + N1).tolist(), "N_z_heel": (N0 - N1).tolist(),
                      "axial_stress_toe": ((N0 + N1) / t).tolist(),
                      "axial_stress_heel": ((N0 - N1) / t).tolist()})
        z = np.asarray(wall1["z"])
        foot = int(np.argmin(np.abs(z - 0.0)))
        # the joint's bending at toe and heel, and its surface stresses 6 M / t^2 (what an
        # annular plate and the bottom course are checked for in an earthquake)
        j0, j1 = results["junction"], amplitudes["junction"]
        t_wall = float(t[foot])
        t_plate = float(scene.plate.thickness_at(np.array([scene.wall.radius * (1 - 1e-9)]))[0])
        junction = {"M_wall_amplitude": j1["M_wall"], "M_plate_amplitude": j1["M_plate"]}
        for name, sgn in (("toe", side), ("heel", -side)):
            M_w = j0["M_wall"] + sgn * j1["M_wall"]
            M_p = j0["M_plate"] + sgn * j1["M_plate"]
            junction |= {f"M_wall_{name}": M_w, f"M_plate_{name}": M_p,
                         f"wall_bending_stress_{name}": 6.0 * abs(M_w) / t_wall**2,
                         f"plate_bending_stress_{name}": 6.0 * abs(M_p) / t_plate**2}
        out["junction"] = junction
        out["wall_foot"] = {"N_z_amplitude": float(side * N1[foot]),
                            "N_z_toe": float(N0[foot] + N1[foot]),
                            "N_z_heel": float(N0[foot] - N1[foot]),
                            "axial_stress_toe": float((N0[foot] + N1[foot]) / t[foot]),
                            "axial_stress_heel": float((N0[foot] - N1[foot]) / t[foot])}
    return out, warnings


def add_overturning(results: dict, amplitudes: dict, scene, sigma_zz, soil_cells,
                    relative_residual: float, started: float) -> list[str]:
    """Add the overturning's first harmonic to a stage's results: its section
    (:func:`superpose`, with the harmonic solve's relative residual), the planar tilt in
    the settlement summary, its warnings and its time (since ``started``, a
    ``time.perf_counter()``). Returns the warnings."""
    out, warnings = superpose(results, amplitudes, scene, sigma_zz, soil_cells)
    out["relative_residual"] = relative_residual
    results["overturning"] = out
    summary = results["settlement_summary"]
    summary["planar_tilt"] = out["tilt"]
    summary["note"] = ("planar tilt from the overturning load (first harmonic); the "
                       "axisymmetric settlements are those without it")
    results["warnings"] = results["warnings"] + warnings
    results["timings_s"]["overturning"] = seconds = time.perf_counter() - started
    results["timings_s"]["total"] += seconds
    return warnings
