"""The triangles a limit analysis works on (serial, straight-sided), their boundary edges by
kind, and their refinement where marked.

The meridian (r, z), z up, the ground surface at z = 0 and the foundation on it, radius a.
A boundary edge is on the axis (r = 0), under the foundation (z = 0, r <= a), on the free
surface (z = 0, r >= a), on the domain's side (its largest r) or on its base (its lowest
z).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

AXIS, CONTACT, SURFACE, SIDE, BASE = 0, 1, 2, 3, 4


@dataclass(frozen=True)
class Triangles:
    """``points`` (n, 2) (r, z), ``cells`` (m, 3) counterclockwise, ``edges`` (k, 2) the
    boundary edges (their two vertices), ``kind`` (k,) and ``owner`` (k,) (its triangle) of
    each, ``a`` the foundation's radius."""

    points: np.ndarray
    cells: np.ndarray
    edges: np.ndarray
    kind: np.ndarray
    owner: np.ndarray
    a: float

    @classmethod
    def from_points(cls, points: np.ndarray, cells: np.ndarray, a: float) -> "Triangles":
        points = np.asarray(points, dtype=float)[:, :2]
        cells = np.asarray(cells, dtype=np.int64)
        # (counterclockwise, so that outward normals follow from the edge's direction)
        p = points[cells]
        area2 = ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                 - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
        cells = np.where((area2 < 0)[:, None], cells[:, [0, 2, 1]], cells)
        used = np.unique(cells)
        renumber = np.full(len(points), -1)
        renumber[used] = np.arange(len(used))
        points, cells = points[used], renumber[cells]
        edges, owner = _edges(cells)[:2]
        size = np.ptp(points, axis=0).max()
        tol = 1e-9 * size
        mid = 0.5 * (points[edges[:, 0]] + points[edges[:, 1]])
        top = points[:, 1].max()
        kind = np.full(len(edges), -1)
        kind[np.abs(mid[:, 0] - points[:, 0].max()) < tol] = SIDE
        kind[np.abs(mid[:, 1] - points[:, 1].min()) < tol] = BASE
        on_top = np.abs(mid[:, 1] - top) < tol
        kind[on_top & (mid[:, 0] < a)] = CONTACT
        kind[on_top & (mid[:, 0] > a)] = SURFACE
        kind[np.abs(mid[:, 0]) < tol] = AXIS
        if np.any(kind < 0):
            raise ValueError("a boundary edge off the axis, the surface, the side and the base: "
                             "limit analysis takes a foundation on the surface of a box")
        return cls(points, cells, edges, kind, owner, a)

    @classmethod
    def box(cls, a: float, radius: float, depth: float, lines=(), size: float = 0.1,
            growth: float = 1.3) -> "Triangles":
        """A graded grid of the box r <= radius, -depth <= z <= 0 (m), its cells split in
        a checkerboard of diagonals: edges of ``size`` a at the foundation's edge (r = a,
        z = 0), growing by ``growth`` away from it; the heights ``lines`` (m, z < 0: the
        layers' tops) among its grid lines. Built in units of a and scaled, so that the
        same box in other units is the same mesh."""
        r = np.union1d(1.0 - _graded(1.0, size, growth), 1.0 + _graded(radius / a - 1.0, size,
                                                                        growth))
        z = -_graded(depth / a, size, growth, breaks=[-h / a for h in lines])
        R, Z = np.meshgrid(r, z, indexing="ij")
        points = np.column_stack([R.ravel(), Z.ravel()]) * a
        nz = len(z)
        i, j = np.meshgrid(np.arange(len(r) - 1), np.arange(nz - 1), indexing="ij")
        i, j = i.ravel(), j.ravel()
        p00, p10, p01, p11 = i * nz + j, (i + 1) * nz + j, i * nz + j + 1, (i + 1) * nz + j + 1
        flip = (i + j) % 2 == 1
        first = np.where(flip[:, None], np.column_stack([p00, p10, p01]),
                         np.column_stack([p00, p10, p11]))
        second = np.where(flip[:, None], np.column_stack([p10, p11, p01]),
                          np.column_stack([p00, p11, p01]))
        return cls.from_points(points, np.vstack([first, second]), a)

    @classmethod
    def from_mesh(cls, msh, a: float) -> "Triangles":
        """The straight triangles of a DOLFINx mesh on one process (its cells' vertices)."""
        import dolfinx.mesh as dmesh

        tdim = msh.topology.dim
        msh.topology.create_connectivity(tdim, 0)
        cells = np.arange(msh.topology.index_map(tdim).size_local, dtype=np.int32)
        nodes = dmesh.entities_to_geometry(msh, tdim, cells)[:, :3]
        return cls.from_points(msh.geometry.x, nodes, a)

    @functools.cached_property
    def interior(self) -> tuple[np.ndarray, np.ndarray]:
        """The interior edges: for each, its two triangles (e, f) and its vertices as e
        orders them."""
        return _edges(self.cells)[2:]

    @property
    def h(self) -> np.ndarray:
        """Each triangle's longest edge."""
        p = self.points[self.cells]
        return np.max([np.linalg.norm(p[:, i] - p[:, (i + 1) % 3], axis=1) for i in range(3)],
                      axis=0)

    @property
    def area(self) -> np.ndarray:
        p = self.points[self.cells]
        return 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                      - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))

    def refined(self, marked: np.ndarray) -> "Triangles":
        """The mesh with the marked triangles (indices) bisected, conforming (DOLFINx's
        Plaza refinement of their edges, on this process alone)."""
        import basix.ufl
        import dolfinx.mesh as dmesh
        from mpi4py import MPI

        element = basix.ufl.element("Lagrange", "triangle", 1, shape=(2,))
        msh = dmesh.create_mesh(MPI.COMM_SELF, self.cells, element, self.points)
        msh.topology.create_connectivity(2, 1)
        # (create_mesh reorders the cells: marks go through its original index)
        original = msh.topology.original_cell_index
        local = np.argsort(original)[np.asarray(marked, dtype=np.int64)]
        c2e = msh.topology.connectivity(2, 1)
        edges = np.unique(np.concatenate([c2e.links(c) for c in local])).astype(np.int32)
        fine, _, _ = dmesh.refine(msh, edges)
        return Triangles.from_mesh(fine, self.a)


def _graded(length: float, size: float, growth: float, breaks=()) -> np.ndarray:
    """Points from 0 to ``length`` (> 0), the first interval ``size``, each next ``growth``
    times the one before, with the points ``breaks`` among them (a point of the grading
    within 0.4 of its interval from one is dropped)."""
    pts, h = [0.0], size
    while pts[-1] + h < length:
        pts.append(pts[-1] + h)
        h *= growth
    pts = np.array(pts)
    if length - pts[-1] < 0.4 * h / growth and len(pts) > 1:
        pts = pts[:-1]
    pts = np.append(pts, length)
    for b in breaks:
        if 0.0 < b < length:
            step = np.diff(pts)[np.clip(np.searchsorted(pts, b) - 1, 0, len(pts) - 2)]
            pts = np.union1d(pts[np.abs(pts - b) > 0.4 * step], [b])
    return pts


def _edges(cells: np.ndarray):
    """The boundary edges (k, 2) (in their triangle's counterclockwise order) and their
    triangles (k,), and the interior edges: for each, its two triangles (e, f) and its
    vertices as e orders them."""
    m = len(cells)
    local = np.array([[0, 1], [1, 2], [2, 0]])
    pairs = cells[:, local].reshape(-1, 2)                    # (3m, 2), ccw per triangle
    owner = np.repeat(np.arange(m), 3)
    key = np.sort(pairs, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    k = key[order]
    same = np.all(k[1:] == k[:-1], axis=1)
    first = order[:-1][same]
    second = order[1:][same]
    paired = np.zeros(len(pairs), bool)
    paired[first] = paired[second] = True
    return (pairs[~paired], owner[~paired], np.column_stack([owner[first], owner[second]]),
            pairs[first])
