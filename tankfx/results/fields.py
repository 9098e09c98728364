"""Post-processing that is safe under MPI: every value returned here is the same on all ranks.

Point values are taken from one cell chosen the same way whatever the partition (the cell
with the lexicographically smallest midpoint among those containing the point), so that a
discontinuous field (a stress, a moment) evaluates identically in serial and in parallel.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import ufl
from dolfinx import fem

from ..laws import elasticity as soil_forms
from ..laws.tensors import principal_strains
from ..laws.harmonic import cylindrical
from ..laws.interface import ContactState


def cellwise(expr, space) -> np.ndarray:
    """An expression's value at each cell's centroid (a DG0 interpolation), in cell order,
    as an (n_cells, value size) array."""
    f = fem.Function(space)
    f.interpolate(fem.Expression(expr, space.element.interpolation_points))
    return f.x.array.reshape(-1, space.dofmap.index_map_bs)[space.dofmap.list[:, 0]]


def soil_cell_fields(model, statuses=None) -> dict[str, fem.Function]:
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
    stresses, their E). ``statuses``: the stage's iterations' (the secant loop's carries
    the constants it converged on; without it, those of each cell's stratum)."""

    block, s = model.soil, model.scene.soil
    msh = block.u.function_space.mesh
    Q0 = fem.functionspace(msh, ("DG", 0))
    T = fem.functionspace(msh, ("DG", 0, (4,)))

    sig = cellwise(soil_forms.tensor_components(block.stress()), T)
    # principal_strains is the eigen-split of any axisymmetric tensor: here, of the stress
    s_min, s_max = principal_strains(sig[:, 0], sig[:, 1], sig[:, 2], sig[:, 3])
    values = {"modulus": cellwise(block.E, Q0)[:, 0],
              "deviator": s_max - s_min,
              "mean_stress": -(sig[:, 0] + sig[:, 1] + sig[:, 3]) / 3.0}
    if s.law.reports:
        eps = cellwise(soil_forms.tensor_components(soil_forms.strain(block.u, block.r)), T)
        eps_min, eps_max = principal_strains(eps[:, 0], eps[:, 1], eps[:, 2], eps[:, 3])
        unloading = None
        if block.memory is not None:
            unloading = cellwise(block.memory.unloading, Q0)[:, 0] > 0.5
            values["unloading"] = unloading.astype(float)
        # the law's own fields, with the constants its iteration converged on
        converged = getattr((statuses or {}).get("soil"), "data", None)
        reported = s.law.cell_reports(s, eps_min, eps_max, s_max - s_min,
                                      cellwise(soil_forms.depth(msh), Q0)[:, 0], converged,
                                      unloading)
        # (the soil's law: nothing to say of a ringwall's concrete)
        values |= {name: np.where(block.linear_cells, 0.0, v) for name, v in reported.items()}
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
STATUS_CODES = {state.label: state.vtk_code for state in ContactState}


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
                 "axis_pore_pressure": "Pa", "applied_load": "N", "liquid_height": "m"}


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
        keys = [k for k in history[0] if k != "piezometers"]
        n = len(history[0].get("piezometers", []))
        path = directory / "consolidation.csv"
        with path.open("w", newline="") as f:
            out = csv.writer(f)
            out.writerow([f"{k} [{HISTORY_UNITS[k]}]" if HISTORY_UNITS.get(k) else k
                          for k in keys] + [f"piezometer_{j} [Pa]" for j in range(1, n + 1)])
            out.writerows([s[k] for k in keys] + s.get("piezometers", []) for s in history)
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
    cells = soil_cell_fields(solution.model, solution.statuses)
    paths = [directory / "soil.pvd"]
    extra = []
    if solution.harmonic is not None:
        # the overturning's amplitudes (u_r, u_z of cos theta, u_theta of sin theta)

        V1 = solution.harmonic.u.function_space
        amplitude = fem.Function(V1, name="u_overturning")
        amplitude.interpolate(fem.Expression(ufl.as_vector(cylindrical(solution.harmonic.u)),
                                             V1.element.interpolation_points))
        extra.append(amplitude)
    pore = solution.model.soil.pore_pressure if solution.model is not None else None
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
    """A member's profile as a VTK XML polyline file (.vtp: its points in the (r, z) plane,
    a segment between each pair of neighbours, its values at the points), written here in a
    few lines rather than through PyVista, whose import (VTK) a run without figures does
    not otherwise pay."""
    n = len(x)
    arrays = {"u": np.column_stack([ux, uy, np.zeros(n)])}
    for key, v in values.items():
        if key == "contact_status":
            arrays[key] = np.array([STATUS_CODES[c] for c in v], dtype=np.int8)
        elif key not in ("r", "z"):
            arrays[key] = np.asarray(v, dtype=float)
    points = np.column_stack([x, y, np.zeros(n)])
    segments = np.column_stack([np.arange(n - 1), np.arange(1, n)])
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian">',
             "<PolyData>",
             f'<Piece NumberOfPoints="{n}" NumberOfVerts="0" NumberOfLines="{n - 1}" '
             'NumberOfStrips="0" NumberOfPolys="0">',
             "<PointData>",
             *(_data_array(values_, name) for name, values_ in arrays.items()),
             "</PointData>",
             "<Points>", _data_array(points), "</Points>",
             "<Lines>", _data_array(segments.ravel().astype(np.int64), "connectivity"),
             _data_array(2 * np.arange(1, n, dtype=np.int64), "offsets"), "</Lines>",
             "</Piece>", "</PolyData>", "</VTKFile>"]
    path.write_text("\n".join(lines) + "\n")


#: numpy's kinds as VTK names them
_VTK_TYPES = {np.dtype(np.float64): "Float64", np.dtype(np.int64): "Int64",
              np.dtype(np.int8): "Int8"}


def _data_array(values: np.ndarray, name: str | None = None) -> str:
    """One VTK XML DataArray, in ASCII (a profile has at most a few thousand numbers; floats
    to 17 digits: read back exactly)."""
    components = 1 if values.ndim == 1 else values.shape[1]
    text = " ".join(f"{v:.17g}" if values.dtype.kind == "f" else str(v)
                    for v in values.ravel())
    label = f' Name="{name}"' if name else ""
    return (f'<DataArray type="{_VTK_TYPES[values.dtype]}"{label} '
            f'NumberOfComponents="{components}" format="ascii">{text}</DataArray>')
