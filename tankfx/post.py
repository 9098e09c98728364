"""Post-processing that is safe under MPI: every value returned here is the same on all ranks.

Point values are taken from one cell chosen the same way whatever the partition (the cell of
smallest original index that contains the point), so that a discontinuous field (a stress)
evaluates identically in serial and in parallel.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem, geometry
from mpi4py import MPI

__all__ = ["allsum", "assemble_scalar", "evaluate_at", "nodal_values_on_facets"]


def allsum(comm: MPI.Comm, value: float) -> float:
    """Sum of a rank-local scalar over all ranks."""
    return comm.allreduce(float(value), op=MPI.SUM)


def assemble_scalar(integrand, comm: MPI.Comm) -> float:
    """A functional assembled on every rank and summed: the same value everywhere."""
    return allsum(comm, fem.assemble_scalar(fem.form(integrand)))


def evaluate_at(func: fem.Function, points: np.ndarray) -> np.ndarray:
    """Values of ``func`` at ``points`` (shape (n, 2) or (n, 3)), on every rank.

    Raises ValueError if a point lies outside the mesh.
    """
    msh = func.function_space.mesh
    comm = msh.comm
    pts = np.zeros((len(points), 3))
    pts[:, : np.shape(points)[1]] = points
    tdim = msh.topology.dim
    n_owned = msh.topology.index_map(tdim).size_local
    tree = geometry.bb_tree(msh, tdim, entities=np.arange(n_owned, dtype=np.int32))
    candidates = geometry.compute_collisions_points(tree, pts)
    colliding = geometry.compute_colliding_cells(msh, candidates, pts)
    original = msh.topology.original_cell_index
    vsize = func.function_space.value_size
    key = np.full(len(pts), np.iinfo(np.int64).max, dtype=np.int64)
    values = np.zeros((len(pts), vsize))
    for i in range(len(pts)):
        cells = colliding.links(i)
        cells = cells[cells < n_owned]
        if len(cells) == 0:
            continue
        c = cells[np.argmin(original[cells])]
        key[i] = original[c]
        values[i] = func.eval(pts[i], np.array([c], dtype=np.int32))
    keys = comm.allgather(key)
    vals = comm.allgather(values)
    best = np.argmin(np.stack(keys), axis=0)
    if np.any(np.min(np.stack(keys), axis=0) == np.iinfo(np.int64).max):
        missing = pts[np.min(np.stack(keys), axis=0) == np.iinfo(np.int64).max]
        raise ValueError(f"points outside the mesh: {missing[:3, :2].tolist()} ...")
    return np.stack(vals)[best, np.arange(len(pts))]


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
    order = np.lexsort((x[:, 1], x[:, 0]))
    return x[order], vals[order]
