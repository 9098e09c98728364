"""A 1D mesh of straight segments in the (r, z) plane and supports on its vertices: the
plumbing of the standalone shells (:mod:`tankfx.verification.rigs`).
"""
from __future__ import annotations

import basix.ufl
import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ..laws.shell import PLATE


def line_mesh(comm: MPI.Comm, points: np.ndarray, tags: np.ndarray | None = None):
    """A 1D mesh in the (r, z) plane along the polyline through ``points`` (n, 2), made on
    rank 0 and distributed; ``tags`` (n - 1,) become cell tags (default PLATE)."""
    pts = np.asarray(points, dtype=np.float64)
    n = len(pts) - 1
    if comm.rank == 0:
        cells = np.column_stack([np.arange(n), np.arange(1, n + 1)]).astype(np.int64)
        x = pts
    else:
        cells = np.empty((0, 2), dtype=np.int64)
        x = np.empty((0, 2), dtype=np.float64)
    element = basix.ufl.element("Lagrange", "interval", 1, shape=(2,))
    msh = dmesh.create_mesh(comm, cells, element, x)
    # cell tags, located by the cell midpoints
    tag_of = np.full(n, PLATE, dtype=np.int32) if tags is None else np.asarray(tags, np.int32)
    mids_all = 0.5 * (pts[:-1] + pts[1:])
    ncells = msh.topology.index_map(1).size_local + msh.topology.index_map(1).num_ghosts
    mids = dmesh.compute_midpoints(msh, 1, np.arange(ncells, dtype=np.int32))[:, :2]
    d = np.linalg.norm(mids[:, None, :] - mids_all[None, :, :], axis=2)
    values = tag_of[np.argmin(d, axis=1)]
    ct = dmesh.meshtags(msh, 1, np.arange(ncells, dtype=np.int32), values)
    return msh, ct


def vertex_supports(msh, spaces: dict, supports: dict) -> list:
    """Zero Dirichlet conditions on a 1D mesh's vertices: ``supports`` maps a vertex
    predicate ``f(x) -> bool`` to the names (keys of ``spaces``, subspaces) it fixes."""
    bcs = []
    for where, comps in supports.items():
        verts = dmesh.locate_entities(msh, 0, where)
        for c in comps:
            V, _ = spaces[c].collapse()
            dofs = fem.locate_dofs_topological((spaces[c], V), 0, verts)
            bcs.append(fem.dirichletbc(fem.Function(V), dofs, spaces[c]))
    return bcs
