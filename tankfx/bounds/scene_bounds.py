"""What a scene asks of the bounds: its soil per triangle, its foundation's load, and the
run (``[analysis] collapse = "bounds"``)."""
from __future__ import annotations

import numpy as np

from ..scene.sections import vertical_load
from .lower import Ground, Loading
from .triangles import Triangles


def ground_of(soil, tri: Triangles) -> Ground:
    """The soil of each triangle: its stratum's (read at its centroid, a triangle lying in
    one stratum) cohesion as a line in z, friction angle and unit weight. Depth is -z."""
    depth = -tri.points[tri.cells, 1].mean(axis=1)
    st = soil.at_depth(depth)
    gradient = st["cohesion_gradient"]
    # c = cohesion + gradient (depth - top) = (cohesion - gradient top) - gradient z
    return Ground(c_top=st["cohesion"] - gradient * st["top"], dc_dz=-gradient,
                  phi=np.radians(st["friction_angle"]), gamma=st["unit_weight"])


def loading_of(scene, rigid: bool) -> Loading:
    """The foundation's held (the self-weight) and variable (the rest) vertical loads."""
    full = scene.load
    held = full.held()
    H = vertical_load(held, scene.plate, scene.wall, scene.ringwall)
    V = vertical_load(full, scene.plate, scene.wall, scene.ringwall) - H
    # (a flexible load is a pressure: no shear under it)
    return Loading(variable=V, held=H, rigid=rigid,
                   rough=rigid and scene.interface.condition != "smooth",
                   smooth_side=scene.domain.side == "roller",
                   smooth_base=scene.domain.base == "smooth")


def strength_scale(soil, a: float) -> float:
    """A stress of order one for the programs: the cohesion at the surface, else gamma a."""
    top = soil.at_depth(np.array([0.0]))
    return max(float(top["cohesion"][0]), float(top["unit_weight"][0]) * a, 1.0)


def scene_bounds(scene, comm, log, elastoplastic: dict | None = None) -> tuple[dict, dict]:
    """The lower and upper bound on the factor of the scene's variable loads (``[analysis]
    collapse = "bounds"``), refined to ``analysis.bounds_gap`` or ``bounds_cells``: (the
    record for results.json, the upper bound's mechanism: ``points`` (n, 2), ``cells``
    (m, 3), ``velocity`` (n, 2) at the triangles' vertices, for a settlement rate of 1), on
    every rank (the programs are solved on rank 0). ``elastoplastic`` is the collapse by
    load of the same scene, set beside them."""
    import time

    from mpi4py import MPI

    from ..mesh import build_domain
    from .adapt import bounds
    from .program import ProgramError

    record, fields, error = None, None, None
    if comm.rank == 0:
        t0 = time.perf_counter()
        a = scene.foundation_radius
        # (a coarse start: the refinement puts the triangles where the mechanism is)
        start = scene.with_changes(mesh={"edge_size": 0.1 * a, "near_size": 0.5 * a,
                                         "growth": 0.3})
        tri = Triangles.from_mesh(build_domain(start, MPI.COMM_SELF).mesh, a)
        load = loading_of(scene, rigid=scene.plate is not None)
        log.info("bounds: the limit analysis' lower and upper bound on the variable loads' "
                 "factor, refined to a gap of %.3g %%", 100 * scene.analysis.bounds_gap)
        try:
            b = bounds(tri, lambda t: ground_of(scene.soil, t), load,
                       strength_scale(scene.soil, a), gap=scene.analysis.bounds_gap,
                       max_cells=scene.analysis.bounds_cells, log=log)
            record = _record(scene, b, time.perf_counter() - t0, elastoplastic)
            for note in record["notes"]:
                log.warning("bounds: %s", note)
            nv = len(b.triangles.points)
            fields = {"points": b.triangles.points, "cells": b.triangles.cells,
                      "velocity": b.upper.velocity[:nv]}
        except ProgramError as e:
            error = str(e)
    record, fields, error = comm.bcast((record, fields, error), root=0)
    if error is not None:
        raise ProgramError(error)
    return record, fields


def _record(scene, b, seconds: float, elastoplastic: dict | None) -> dict:
    import clarabel

    notes, associated = [], True
    for k, st in enumerate(scene.soil.strata):
        phi, psi = st.friction_angle or 0.0, st.dilation_angle or 0.0
        where = "soil" if k == 0 else f"soil.layers[{k}]"
        if psi != phi:
            associated = False
            notes.append(f"{where}: the dilation angle {psi:g} differs from the friction angle "
                         f"{phi:g}: limit analysis assumes associated flow (psi = phi), and "
                         f"these are the associated soil's bounds")
        if st.tensile_strength is not None:
            notes.append(f"{where}: the tension cut-off ({st.tensile_strength:g} Pa) is not "
                         f"taken: the bounds are Mohr-Coulomb's without it")
    out = {"lower": b.lower.factor, "upper": b.upper.factor, "gap": b.gap,
           "requested_gap": scene.analysis.bounds_gap,
           "reached": b.gap <= scene.analysis.bounds_gap,
           "triangles": len(b.triangles.cells), "rounds": b.rounds, "time_s": seconds,
           "lower_check": {"equilibrium_residual": b.lower.equilibrium_residual,
                           "yield_violation": b.lower.yield_violation},
           "foundation": "rigid" if scene.plate is not None else "flexible load",
           "contact": "smooth" if scene.interface.condition == "smooth" else "rough",
           "solver": f"Clarabel {clarabel.__version__}", "notes": notes}
    if elastoplastic is not None and elastoplastic.get("found"):
        F = elastoplastic["load_factor"]
        out["elastoplastic_factor"] = F
        out["elastoplastic_between"] = bool(b.lower.factor <= F <= b.upper.factor)
        out["elastoplastic_position"] = ("between" if out["elastoplastic_between"] else
                                         "above" if F > b.upper.factor else "below")
        out["elastoplastic_failure"] = elastoplastic.get("failure")
        out["associated"] = associated
    return out
