"""The tank's structure results: the plate's and the wall's profiles (settlement, rotation,
moments M_r, M_theta, M_z, forces N_theta, Q, contact stresses and states), the joint's
moments, each course's largest hoop stress and moment, the settlement summary a tank code asks
for, and the interface's summary: the results.json keys ``profiles.plate``, ``profiles.wall``,
``junction``, ``courses``, ``settlement_summary`` and ``interface``.

The paper: M0 (Eq. 23c) is the plate's M_r at the centre; the interface's states (Eqs.
6-10) per part.
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI

from ..fem.evaluate import evaluate_at
from ..laws import interface
from ..laws import shell as st
from ..model.tank import TankModel
from ..scene.sections import vertical_load, vertical_load_scale

__all__ = ["structure_results"]


def contact_at(model: TankModel, F, pts, cells):
    """Interface tractions (cell averages) at the stations."""
    return (evaluate_at(F["sigma_n"], pts, cells)[:, 0],
            evaluate_at(F["tau"], pts, cells)[:, 0])


def structure_results(model: TankModel, interface_status=None) -> dict:
    """The plate's, the wall's and the interface's results of the current solution
    (``interface_status``: the stage's Mohr-Coulomb iteration's, None for a linear
    interface)."""
    F, s = model.last_fields, model.scene
    pts = model.stations(model.plate_cells, along=0)
    cells = model.plate_cells
    u = evaluate_at(F["u"], pts, cells)
    sn, tau = contact_at(model, F, pts, cells)
    plate = {"r": pts[:, 0].tolist(), "w": (-u[:, 1]).tolist(), "u_r": u[:, 0].tolist(),
             "rotation": evaluate_at(F["beta"], pts, cells)[:, 0].tolist(),
             "M_r": evaluate_at(F["M_s"], pts, cells)[:, 0].tolist(),
             "M_theta": evaluate_at(F["M_theta"], pts, cells)[:, 0].tolist(),
             "Q_r": evaluate_at(F["Q"], pts, cells)[:, 0].tolist(),
             "contact_normal": sn.tolist(), "contact_shear": tau.tolist(),
             "contact_status": status_at(model, F, pts, cells)}
    profiles = {"plate": plate}
    if s.wall is not None:
        cells = model.wall_cells
        pts = model.stations(cells, along=1)
        u = evaluate_at(F["u"], pts, cells)
        N_theta = evaluate_at(F["N_theta"], pts, cells)[:, 0]
        # (at a course joint both come from the course below)
        thickness = evaluate_at(model.thickness, pts, cells)[:, 0]
        wall = {"z": (pts[:, 1] + s.embedment).tolist(), "u_r": u[:, 0].tolist(),
                "u_z": u[:, 1].tolist(),
                "rotation": evaluate_at(F["beta"], pts, cells)[:, 0].tolist(),
                "M_z": evaluate_at(F["M_s"], pts, cells)[:, 0].tolist(),
                "N_z": evaluate_at(F["N_s"], pts, cells)[:, 0].tolist(),
                "N_theta": N_theta.tolist(), "thickness": thickness.tolist(),
                "hoop_stress": (N_theta / thickness).tolist(),
                "Q": evaluate_at(F["Q"], pts, cells)[:, 0].tolist()}
        if s.embedment > 0.0:
            sn, tau = contact_at(model, F, pts, cells)
            below = pts[:, 1] <= 1e-12
            wall["contact_normal"] = np.where(below, sn, 0.0).tolist()
            wall["contact_shear"] = np.where(below, tau, 0.0).tolist()
            wall["contact_status"] = [st_ if b else "none" for st_, b in
                                      zip(status_at(model, F, pts, cells), below)]
        profiles["wall"] = wall
    # what the interface carries: every load but a ringwall's weight, which its own
    # cells carry to the soil
    applied = vertical_load(s.load, s.plate, s.wall)
    scale = max(vertical_load_scale(s.load, s.plate, s.wall), model.path_load_scale)
    contact = model.interface.contact_resultant()
    out = {"profiles": profiles,
           "equilibrium": {"contact_resultant": contact,
                           "contact_relative_error": abs(contact - applied) / scale},
           "interface": interface_summary(model.interface, interface_status)}
    if s.wall is not None:
        out["junction"] = junction(model, F)
        out["courses"] = courses(model, F)
    out["settlement_summary"] = settlement_summary(model, plate)
    return out


def courses(model: TankModel, F) -> list[dict]:
    """Per course of the wall (one for a uniform wall), heights above its foot: the
    largest hoop stress N_theta / t (Pa; tension positive: what a tank code checks
    against its allowable stress) and where, and the largest |M_z| (N m/m) and where."""
    s = model.scene
    height = model.cell_midpoints[model.wall_cells, 1] + s.embedment
    out = []
    for bottom, top, t in s.wall.course_table:
        cells = model.wall_cells[(height > bottom) & (height < top)]
        pts = model.stations(cells)
        hoop = evaluate_at(F["N_theta"], pts, cells)[:, 0] / t
        M = evaluate_at(F["M_s"], pts, cells)[:, 0]
        z = pts[:, 1] + s.embedment
        i, j = int(np.argmax(hoop)), int(np.argmax(np.abs(M)))
        out.append({"bottom": bottom, "top": top, "thickness": t,
                    "max_hoop_stress": float(hoop[i]), "at": float(z[i]),
                    "max_abs_M_z": float(abs(M[j])), "M_at": float(z[j])})
    return out


def settlement_summary(model: TankModel, plate) -> dict:
    """What tank codes ask of the foundation (API 653 Annex B style), from the plate
    profile: the uniform (mean) settlement, the centre-to-edge dish, and the settlement
    of the shell's edge. An axisymmetric model has no planar tilt or out-of-plane
    settlement around the shell: those need a 3D model or measured data."""
    r = np.asarray(plate["r"])
    w = np.asarray(plate["w"])
    s = model.scene
    at = s.wall.radius if s.wall is not None else s.plate.radius
    w_shell = float(np.interp(at, r, w))
    return {"uniform_settlement": model.last_w_mean, "shell_settlement": w_shell,
            "dish": float(w[0] - w_shell), "dish_over_radius": float((w[0] - w_shell) / at),
            "planar_tilt": None,
            "note": "axisymmetric: no planar tilt or differential settlement around the "
                    "shell"}


def status_at(model: TankModel, F, pts, cells) -> list[str]:
    """The interface state of the element at each station (vertices: the element on the
    axis side)."""
    codes = evaluate_at(F["status"], pts, cells)[:, 0]
    return [interface.ContactState.nearest(c).label for c in codes]


def junction(model: TankModel, F) -> dict:
    """Moments at the wall-plate joint, N m/m. The mesh vertex is the joint's outer
    corner (where the faces meet); about it the membrane forces of the mid-surfaces, half
    a thickness away, add to the moments, and the members balance:
    sum over plate sides of +-(M_r - N_r t_p / 2) = M_z - N_z t_t / 2."""
    s = model.scene
    corner = np.array([[s.wall.radius, -s.embedment]])
    mids = model.cell_midpoints[model.plate_cells, 0]
    inner = model.plate_cells[mids < s.wall.radius]
    outer = model.plate_cells[mids > s.wall.radius]
    # the plate's thickness on each side of the wall (an annular ring's, if it has one)
    e_in, e_out = 0.5 * s.plate.thickness_at(s.wall.radius * np.array([1 - 1e-9,
                                                                       1 + 1e-9]))
    e_w = 0.5 * s.wall.thickness

    def about_corner(cells, e):
        if model.mesh.comm.allreduce(len(cells)) == 0:
            return 0.0, 0.0
        M = evaluate_at(F["M_s"], corner, cells)[0, 0]
        return M, M - evaluate_at(F["N_s"], corner, cells)[0, 0] * e

    M_in, Mc_in = about_corner(inner, e_in)
    M_out, Mc_out = about_corner(outer, e_out)
    M_w, Mc_w = about_corner(model.wall_cells, e_w)
    # the surface bending stresses 6 M / t^2 at the joint (Pa; what a steel tank's
    # corner is checked for), in the wall's bottom course and the plate inside it
    return {"M_plate": M_in, "M_plate_outside": M_out, "M_wall": M_w,
            "M_plate_about_corner": Mc_in - Mc_out, "M_wall_about_corner": Mc_w,
            "wall_bending_stress": 6.0 * abs(M_w) / (2 * e_w) ** 2,
            "plate_bending_stress": 6.0 * abs(M_in) / (2 * e_in) ** 2}


def interface_summary(block, status=None) -> dict:
    """The interface's results: its condition, how its iteration went (the record its
    iteration left, or a linear interface's one solve), the length in each state per part
    (plate, wall), and the range of its normal stiffness."""
    comm = block.mesh.comm
    n_owned = block.n_carrier_owned
    h = block.carrier_lengths[:n_owned]
    values = block.carrier_tag[:n_owned]
    lengths = {}
    rebonded = block.was_separated & (block.status != interface.SEPARATED)
    for code in (interface.STICK, interface.SLIP, interface.SEPARATED, interface.REBONDED):
        for part, tag in (("plate", st.PLATE), ("wall", st.WALL_EMBEDDED)):
            # (rebonded is a separated carrier closed since the stage's start: the
            # carrier's state is stick or slip)
            state = rebonded if code == interface.REBONDED else block.status == code
            mine = state[:n_owned] & (values == tag)
            lengths.setdefault(f"{code.label}_length", {})[part] = comm.allreduce(
                float(h[mine].sum()))
    res = status.record if status is not None else {
        "converged": True, "iterations": 0, "history": [],
        "criterion": "linear interface: one solve"}
    if block.settings.has_states:
        res = {**res, "states": block.settings.states}
    in_contact = block.stiffness_n[block.in_contact]
    return {"condition": block.settings.condition, **res, **lengths,
            "normal_stiffness_range": [
                comm.allreduce(float(in_contact.min(initial=np.inf)), op=MPI.MIN),
                comm.allreduce(float(in_contact.max(initial=0.0)), op=MPI.MAX)]}
