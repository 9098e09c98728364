"""Post-processing that is safe under MPI: every value returned here is the same on all ranks.

Point values are taken from one cell chosen the same way whatever the partition (the cell
with the lexicographically smallest midpoint among those containing the point), so that a
discontinuous field (a stress, a moment) evaluates identically in serial and in parallel.
"""
from __future__ import annotations

import weakref
from pathlib import Path

import numpy as np
import ufl
from dolfinx import fem, geometry
from dolfinx import mesh as dmesh
from mpi4py import MPI

from .scene import member_text, ringwall_text, stratum_constants

__all__ = ["allsum", "assemble_scalar", "evaluate_at", "nodal_values_on_facets",
           "soil_cell_fields", "write_fields", "FIELD_FILES", "STATUS_CODES", "summary_rows",
           "write_profiles", "PROFILE_FILES",
           "summary_table", "write_report"]


def allsum(comm: MPI.Comm, value: float) -> float:
    """Sum of a rank-local scalar over all ranks."""
    return comm.allreduce(float(value), op=MPI.SUM)


def assemble_scalar(integrand, comm: MPI.Comm) -> float:
    """A functional assembled on every rank and summed: the same value everywhere."""
    return allsum(comm, fem.assemble_scalar(fem.form(integrand)))


def evaluate_at(func, points: np.ndarray, cells: np.ndarray | None = None) -> np.ndarray:
    """Values of the Function ``func`` at ``points``
    (shape (n, 2) or (n, 3)), the same on every rank.

    ``cells`` restricts the search to those (local) cells, e.g. the plate's cells only at the
    wall-plate junction. Where several cells contain a point, the one whose midpoint is
    lexicographically smallest is used, on whatever rank it lives: the choice does not depend
    on the partition. Raises ValueError if a point lies in none of the cells.

    Where the points lie is found once per mesh, points and cells and kept (an iteration
    that reads w0 every pass, or the profiles' several fields at the same stations, then
    pay only for the evaluation: the search over a 270k-dof mesh costs 0.08 s a call).
    """
    msh = func.function_space.mesh
    pts = np.zeros((len(points), 3))
    pts[:, : np.shape(points)[1]] = points
    chosen, mine = _located(msh, pts, cells)
    vsize = func.function_space.value_size
    values = np.zeros((len(pts), vsize))
    here = np.flatnonzero(mine)
    if len(here):
        # one call for all points: per-point calls cost more than the evaluation
        values[here] = np.reshape(func.eval(pts[here], chosen[here]), (len(here), vsize))
    # exactly one rank holds each point's value, the others zeros
    return msh.comm.allreduce(values, op=MPI.SUM)


# mesh -> {(points, cells): (chosen cell per point, whether this rank evaluates it)}
_LOCATED: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _located(msh, pts: np.ndarray, cells) -> tuple[np.ndarray, np.ndarray]:
    key = (pts.tobytes(), None if cells is None else np.asarray(cells, np.int32).tobytes())
    cache = _LOCATED.setdefault(msh, {})
    # the search is collective, and the cells are local: every rank must agree to reuse
    if not msh.comm.allreduce(key in cache, op=MPI.LAND):
        cache[key] = _locate(msh, pts, cells)
    return cache[key]


def _locate(msh, pts: np.ndarray, cells) -> tuple[np.ndarray, np.ndarray]:
    """For each point, the local cell that contains it (-1 if none) and whether this rank's
    cell is the one chosen over all ranks (lexicographically smallest midpoint)."""
    comm = msh.comm
    tdim = msh.topology.dim
    n_owned = msh.topology.index_map(tdim).size_local
    candidates = np.arange(n_owned, dtype=np.int32) if cells is None else \
        np.asarray(cells, dtype=np.int32)[np.asarray(cells) < n_owned]
    keys = np.full((len(pts), 2), np.inf)
    chosen = np.full(len(pts), -1, dtype=np.int32)
    if len(candidates):
        # a little padding: the boxes of the 1D cells along z = const are flat, and a point
        # at a shared vertex may sit a rounding error outside one of them
        pad = 1e-10 * max(1.0, float(np.abs(msh.geometry.x).max()))
        tree = geometry.bb_tree(msh, tdim, entities=candidates, padding=pad)
        colliding = geometry.compute_colliding_cells(
            msh, geometry.compute_collisions_points(tree, pts), pts)
        # a mask over the local cells, not np.isin per point (0.05 s of a 1 s analysis)
        allowed = np.zeros(msh.topology.index_map(tdim).size_local
                           + msh.topology.index_map(tdim).num_ghosts, dtype=bool)
        allowed[candidates] = True
        for i in range(len(pts)):
            found = colliding.links(i)
            found = found[allowed[found]]
            if len(found):
                mids = dmesh.compute_midpoints(msh, tdim, found.astype(np.int32))[:, :2]
                k = np.lexsort((mids[:, 1], mids[:, 0]))[0]
                chosen[i], keys[i] = found[k], mids[k]
    all_keys = np.stack(comm.allgather(keys))       # (ranks, n, 2)
    best = np.zeros(len(pts), dtype=int)
    for k in range(1, comm.size):
        better = (all_keys[k, :, 0] < all_keys[best, np.arange(len(pts)), 0]) | (
            (all_keys[k, :, 0] == all_keys[best, np.arange(len(pts)), 0])
            & (all_keys[k, :, 1] < all_keys[best, np.arange(len(pts)), 1]))
        best[better] = k
    outside = np.isinf(all_keys[best, np.arange(len(pts)), 0])
    if np.any(outside):
        missing = pts[outside]
        raise ValueError(f"points outside the mesh (or the given cells): "
                         f"{missing[:3, :2].tolist()}")
    return chosen, (best == comm.rank) & (chosen >= 0)


def nodal_values_on_facets(func: fem.Function, facets: np.ndarray):
    """Coordinates and values of the degrees of freedom of ``func`` on the given facets,
    gathered from all ranks and sorted by (r, z). Returns (coords (n, 2), values (n, bs))."""
    V = func.function_space
    comm = V.mesh.comm
    nodes = fem.locate_dofs_topological(V, V.mesh.topology.dim - 1, facets)
    nodes = nodes[nodes < V.dofmap.index_map.size_local]
    bs = V.dofmap.index_map_bs
    x = V.tabulate_dof_coordinates()[nodes, :2]
    vals = func.x.array.reshape(-1, bs)[nodes]
    x = np.concatenate(comm.allgather(x))
    vals = np.concatenate(comm.allgather(vals))
    # coordinates tabulated from different cells differ by round-off: sort on rounded ones,
    # so that every partition lists the nodes in the same order
    scale = max(1.0, float(np.abs(x).max())) if len(x) else 1.0
    key = np.round(x / scale, 12)
    order = np.lexsort((key[:, 1], key[:, 0]))
    return x[order], vals[order]


def _cellwise(expr, space) -> np.ndarray:
    """An expression's value at each cell's centroid (a DG0 interpolation), in cell order,
    as an (n_cells, value size) array."""
    f = fem.Function(space)
    f.interpolate(fem.Expression(expr, space.element.interpolation_points))
    return f.x.array.reshape(-1, space.dofmap.index_map_bs)[space.dofmap.list[:, 0]]


def soil_cell_fields(model) -> dict[str, fem.Function]:
    """The soil's state cell by cell (DG0: each cell's centroid), for viewing.

    ``modulus``: Young's modulus, Pa (E(h), or a hyperbolic soil's secant modulus);
    ``deviator``: sigma_1 - sigma_3, Pa; ``mean_stress``: -(sigma_rr + sigma_zz +
    sigma_theta) / 3, Pa, compression positive like ``sigma_zz``; for a hyperbolic soil
    ``stress_level``: the deviator Kondner's law gives the cell's strain (Eq. 17) over the
    ultimate 1/b, 1 at failure (converged, it equals deviator x b to the Eq. 18 tolerance;
    a cell on its unloading line, its deviator x b), and with an unloading modulus
    ``unloading``: 1 on the cells that follow their unloading line;
    ``soil``: 1 on soil cells, 0 where the foundation took the soil's place; on layered
    ground ``stratum``: 0 in the surface soil, k in the k-th layer; with a ringwall
    ``ringwall``: 1 in its cells, 2 in its fill's (which the other fields cover too: their
    stresses, their E)."""
    from . import hyperbolic
    from . import soil as soil_forms

    block, s = model.soil, model.scene.soil
    msh = block.u.function_space.mesh
    Q0 = fem.functionspace(msh, ("DG", 0))
    T = fem.functionspace(msh, ("DG", 0, (4,)))

    sig = _cellwise(soil_forms.tensor_components(block.stress()), T)
    # principal_strains is the eigen-split of any axisymmetric tensor: here, of the stress
    s_min, s_max = hyperbolic.principal_strains(sig[:, 0], sig[:, 1], sig[:, 2], sig[:, 3])
    values = {"modulus": _cellwise(block.E, Q0)[:, 0],
              "deviator": s_max - s_min,
              "mean_stress": -(sig[:, 0] + sig[:, 1] + sig[:, 3]) / 3.0}
    if s.nonlinear:
        eps = _cellwise(soil_forms.tensor_components(soil_forms.strain(block.u, block.r)), T)
        # Kondner's constants of each cell: as the iteration converged on them (Duncan &
        # Chang's follow the stress), else those of its stratum
        a, b, nu = getattr(block, "kondner", None) or hyperbolic.kondner_parameters(
            s, _cellwise(soil_forms.depth(msh), Q0)[:, 0])
        eps_min, eps_max = hyperbolic.principal_strains(eps[:, 0], eps[:, 1], eps[:, 2],
                                                        eps[:, 3])
        # (Kondner's law is the soil's: nothing to say of a ringwall's concrete)
        level = hyperbolic.stress_level(eps_min, eps_max, nu, a, b)
        if block.memory is not None:
            # a cell on its unloading line is below its loading curve: its deviator's
            unloading = _cellwise(block.memory.unloading, Q0)[:, 0] > 0.5
            level = np.where(unloading, (s_max - s_min) * b, level)
            values["unloading"] = unloading.astype(float)
        values["stress_level"] = np.where(block.linear_cells, 0.0, level)
    if s.layers:
        # which stratum each cell is in (0: the surface soil, k: the k-th layer)
        values["stratum"] = block.stratum.astype(float)
    if model.scene.ringwall is not None:
        # 1 in the ringwall, 2 in its fill
        values["ringwall"] = block.ringwall_cells + 2.0 * block.fill_cells
    is_soil = np.zeros(len(Q0.dofmap.list))
    is_soil[model.domain.cells("soil")] = 1.0
    # the other cells (the foundation's excavation, the tank's inside) carry no soil
    values = {name: np.where(is_soil > 0, v, 0.0) for name, v in values.items()}
    values["soil"] = is_soil
    fields = {}
    for name, v in values.items():
        f = fem.Function(Q0, name=name)
        f.x.array[Q0.dofmap.list[:, 0]] = v
        fields[name] = f
    return fields


#: The files :func:`write_fields` writes into its directory (the structure's only with a
#: plate, the wall's only with a wall).
FIELD_FILES = ("soil.pvd", "plate.vtp", "wall.vtp")
#: Interface states as numbers in the structure's files (VTK point data are numeric).
STATUS_CODES = {"none": 0, "stick": 1, "slip": 2, "separated": 3, "rebonded": 4}


#: The profiles :func:`write_profiles` writes, one CSV file each where the results have it.
PROFILE_FILES = ("surface.csv", "axis.csv", "plate.csv", "wall.csv", "overturning_plate.csv",
                 "overturning_wall.csv", "overturning_soil_line.csv", "consolidation.csv")
#: The SI unit of each profile column (results.json's ``conventions`` say the signs).
PROFILE_UNITS = {"r": "m", "z": "m", "w": "m", "u_r": "m", "u_z": "m", "rotation": "rad",
                 "M_r": "N m/m", "M_theta": "N m/m", "M_z": "N m/m", "Q_r": "N/m", "Q": "N/m",
                 "N_z": "N/m", "N_theta": "N/m", "thickness": "m", "hoop_stress": "Pa",
                 "sigma_zz": "Pa", "contact_normal": "Pa", "contact_shear": "Pa",
                 "contact_status": "",
                 # the overturning's first harmonic (amplitudes; toe and heel totals)
                 "u_theta": "m", "u_x": "m", "N_z_theta": "N/m", "w_toe": "m", "w_heel": "m",
                 "contact_normal_toe": "Pa", "contact_normal_heel": "Pa", "N_z_toe": "N/m",
                 "N_z_heel": "N/m", "axial_stress_toe": "Pa", "axial_stress_heel": "Pa",
                 "depth": "m", "sigma_zz_axisymmetric": "Pa", "sigma_zz_toe": "Pa",
                 "sigma_zz_heel": "Pa", "pore_pressure": "Pa", "sigma_zz_effective": "Pa"}


#: The unit of each column of a consolidation's history (``consolidation.csv``).
HISTORY_UNITS = {"t": "s", "t_days": "days", "w0": "m", "w_edge": "m", "wd": "m",
                 "w_mean": "m", "M0": "N m/m", "max_pore_pressure": "Pa",
                 "axis_pore_pressure": "Pa", "applied_load": "N"}


def write_profiles(results: dict, directory) -> list[Path]:
    """The results' profiles (ground surface, axis, plate, wall, and an overturning load's
    plate and wall; a consolidation's history, ``consolidation.csv``) as CSV files in
    ``directory``, a column per quantity with its unit in the header, for a spreadsheet
    (rank 0 only; the numbers are those of results.json)."""
    import csv

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    if "consolidation" in results:
        history = results["consolidation"]["history"]
        keys = list(history[0])
        path = directory / "consolidation.csv"
        with path.open("w", newline="") as f:
            out = csv.writer(f)
            out.writerow([f"{k} [{HISTORY_UNITS[k]}]" if HISTORY_UNITS.get(k) else k
                          for k in keys])
            out.writerows([s[k] for k in keys] for s in history)
        written.append(path)
    overturning = results.get("overturning", {}).get("profiles", {})
    for name in PROFILE_FILES:
        member = name.removesuffix(".csv")
        prof = overturning.get(member.removeprefix("overturning_")) \
            if member.startswith("overturning_") else results["profiles"].get(member)
        if not prof:
            continue
        keys = list(prof)
        path = directory / name
        with path.open("w", newline="") as f:
            out = csv.writer(f)
            out.writerow([f"{k} [{PROFILE_UNITS[k]}]" if PROFILE_UNITS.get(k) else k
                          for k in keys])
            out.writerows(zip(*(prof[k] for k in keys)))
        written.append(path)
    return written


def write_fields(solution, directory) -> list[Path]:
    """The solution for ParaView, in ``directory``; coordinates x = r, y = elevation above
    the ground surface, m; SI units. Collective: every rank calls it; returns the paths (the
    same on every rank).

    ``soil.pvd`` (beside it one .pvtu and a .vtu per rank): the displacement ``u`` (u_r,
    u_z) and ``sigma_zz`` (compression positive, the field of the results' axis profile) at
    the nodes of the soil's elements (higher-order VTK cells), and per cell
    :func:`soil_cell_fields`; with an overturning load also ``u_overturning``, its first
    harmonic's amplitudes (u_r, u_z of cos theta, u_theta of sin theta). With a plate,
    ``plate.vtp`` and (with a wall) ``wall.vtp``: the members as lines through the stations
    of the results' profiles, carrying their values (``u`` the displacement vector, for
    warping like the soil's; ``contact_status`` as :data:`STATUS_CODES`; an overturning's
    profiles as ``overturning_`` + their keys)."""
    from dolfinx import io

    directory = Path(directory)
    comm = solution.u.function_space.mesh.comm
    if comm.rank == 0:
        directory.mkdir(parents=True, exist_ok=True)
    comm.barrier()
    cells = soil_cell_fields(solution.model)
    paths = [directory / "soil.pvd"]
    extra = []
    if solution.harmonic is not None:
        # the overturning's amplitudes (u_r, u_z of cos theta, u_theta of sin theta)
        from .harmonic import cylindrical

        V1 = solution.harmonic.u.function_space
        amplitude = fem.Function(V1, name="u_overturning")
        amplitude.interpolate(fem.Expression(ufl.as_vector(cylindrical(solution.harmonic.u)),
                                             V1.element.interpolation_points))
        extra.append(amplitude)
    pore = getattr(solution.model.soil, "pore_pressure", None) \
        if solution.model is not None else None
    if pore is not None:
        # (on the nodes of sigma_zz's space: one VTK cell type for every nodal field)
        p_w = fem.Function(solution.sigma_zz.function_space, name="excess_pore_pressure")
        p_w.interpolate(pore)
        extra.append(p_w)
    with io.VTKFile(comm, str(paths[0]), "w") as f:
        f.write_function([solution.u, solution.sigma_zz, *cells.values(), *extra], 0.0)
    profiles, base = solution.results["profiles"], -solution.scene.embedment
    members = []
    if "plate" in profiles:
        pl = profiles["plate"]
        members.append(("plate.vtp", pl["r"], np.full(len(pl["r"]), base), pl,
                        (pl["u_r"], -np.asarray(pl["w"]))))
    if "wall" in profiles:
        wa = profiles["wall"]
        members.append(("wall.vtp", np.full(len(wa["z"]), solution.scene.wall.radius),
                        base + np.asarray(wa["z"]), wa, (wa["u_r"], wa["u_z"])))
    overturning = solution.results.get("overturning", {}).get("profiles", {})
    for name, x, y, values, (ux, uy) in members:
        # (an overturning's amplitudes and toe / heel totals beside, "overturning_" + key)
        values = values | {f"overturning_{k}": v for k, v in
                           overturning.get(name.removesuffix(".vtp"), {}).items()
                           if k not in ("r", "z")}
        paths.append(directory / name)
        if comm.rank == 0:          # the profiles are gathered already: one writer
            _write_member(paths[-1], x, y, values, ux, uy)
    comm.barrier()
    return paths


def _write_member(path: Path, x, y, values: dict, ux, uy) -> None:
    import pyvista

    points = np.column_stack([x, y, np.zeros(len(x))])
    line = pyvista.lines_from_points(points)
    line.point_data["u"] = np.column_stack([ux, uy, np.zeros(len(x))])
    for key, v in values.items():
        if key == "contact_status":
            line.point_data[key] = np.array([STATUS_CODES[c] for c in v], dtype=np.int8)
        elif key not in ("r", "z"):
            line.point_data[key] = np.asarray(v, dtype=float)
    line.save(path)


def summary_rows(results: dict) -> list[tuple[str, str, str]]:
    """What an engineer reads first, as (quantity, value, non-dimensional / note) rows: the
    settlements and their Eq. 23 measures, the moments and the wall's hoop force, what a tank
    code asks of the settlements, the interface's state and the iterations. Only the rows
    the scene has (no moments without a plate, no interface lengths for a bonded one)."""
    r, nd = results, results["nondim"]

    def bar(key, digits):            # Eq. 23 needs p: none under self-weight alone
        return "no p for Eq. 23" if nd[key] is None else f"{key}_bar = {nd[key]:.{digits}f}"

    rows = [("centre settlement w0", f"{1e3 * r['w0']:.2f} mm", bar("w0", 4)),
            ("differential settlement wd", f"{1e3 * r['wd']:.2f} mm", bar("wd", 4))]
    if r.get("M0") is not None:
        rows.append(("centre moment M0", f"{r['M0'] / 1e3:.2f} kN m/m", bar("M0", 5)))
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
