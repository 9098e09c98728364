"""Post-processing that is safe under MPI: every value returned here is the same on all ranks.

Point values are taken from one cell chosen the same way whatever the partition (the cell
with the lexicographically smallest midpoint among those containing the point), so that a
discontinuous field (a stress, a moment) evaluates identically in serial and in parallel.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem, geometry
from dolfinx import mesh as dmesh
from mpi4py import MPI

__all__ = ["allsum", "assemble_scalar", "evaluate_at", "nodal_values_on_facets"]


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
    """
    msh = func.function_space.mesh
    comm = msh.comm
    pts = np.zeros((len(points), 3))
    pts[:, : np.shape(points)[1]] = points
    tdim = msh.topology.dim
    n_owned = msh.topology.index_map(tdim).size_local
    candidates = np.arange(n_owned, dtype=np.int32) if cells is None else \
        np.asarray(cells, dtype=np.int32)[np.asarray(cells) < n_owned]
    vsize = func.function_space.value_size
    keys = np.full((len(pts), 2), np.inf)
    values = np.zeros((len(pts), vsize))
    if len(candidates):
        # a little padding: the boxes of the 1D cells along z = const are flat, and a point
        # at a shared vertex may sit a rounding error outside one of them
        pad = 1e-10 * max(1.0, float(np.abs(msh.geometry.x).max()))
        tree = geometry.bb_tree(msh, tdim, entities=candidates, padding=pad)
        colliding = geometry.compute_colliding_cells(
            msh, geometry.compute_collisions_points(tree, pts), pts)
        mids = dmesh.compute_midpoints(msh, tdim, candidates)[:, :2]
        mid_of = dict(zip(candidates.tolist(), map(tuple, mids)))
        allowed = set(candidates.tolist())
        chosen = np.full(len(pts), -1, dtype=np.int32)
        for i in range(len(pts)):
            found = [c for c in colliding.links(i) if c in allowed]
            if found:
                chosen[i] = min(found, key=lambda c: mid_of[c])
                keys[i] = mid_of[chosen[i]]
        here = np.flatnonzero(chosen >= 0)
        if len(here):
            # one call for all points: per-point calls cost more than the evaluation
            values[here] = np.reshape(func.eval(pts[here], chosen[here]), (len(here), vsize))
    all_keys = np.stack(comm.allgather(keys))       # (ranks, n, 2)
    all_vals = np.stack(comm.allgather(values))
    best = np.zeros(len(pts), dtype=int)
    for k in range(1, comm.size):
        better = (all_keys[k, :, 0] < all_keys[best, np.arange(len(pts)), 0]) | (
            (all_keys[k, :, 0] == all_keys[best, np.arange(len(pts)), 0])
            & (all_keys[k, :, 1] < all_keys[best, np.arange(len(pts)), 1]))
        best[better] = k
    chosen = all_keys[best, np.arange(len(pts))]
    if np.any(np.isinf(chosen[:, 0])):
        missing = pts[np.isinf(chosen[:, 0])]
        raise ValueError(f"points outside the mesh (or the given cells): "
                         f"{missing[:3, :2].tolist()}")
    return all_vals[best, np.arange(len(pts))]


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
