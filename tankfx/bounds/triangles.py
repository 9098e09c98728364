"""The triangles a limit analysis works on (serial, straight-sided), their boundary edges by
kind, and their refinement where marked.

The meridian (r, z), z up, the ground surface at z = 0 and the foundation on it, radius a.
A boundary edge is on the axis (r = 0), under the foundation (z = 0, r <= a), on the free
surface (z = 0, r >= a), on the domain's side (its largest r) or on its base (its lowest
z).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

AXIS, CONTACT, SURFACE, SIDE, BASE = 0, 1, 2, 3, 4
#: the triangles of the fan at the foundation's edge (and a band's ends) of a box's mesh
FAN = 24


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
    def box(cls, a: float, radius: float, depth: float, lines=(), radii=(), size: float = 0.1,
            growth: float = 0.3) -> "Triangles":
        """The box r <= radius, -depth <= z <= 0 (m) meshed by gmsh (serial), its edges
        ``size`` a long at the foundation's edge (r = a, z = 0) and growing by ``growth``
        times the distance from it (unstructured: the foundation's edge gets a fan of
        triangles, which a lower bound's stress discontinuities need there); the heights
        ``lines`` (m below the surface: layers' tops) and the radii ``radii`` (m: a load's
        band edges on the surface) among its edges. Meshed in units of a and scaled, so that
        the same box in other units is the same mesh."""
        import gmsh

        # (rounded: a box grown in other units may differ from this one in its last bit)
        R, D = round(radius / a, 9), round(depth / a, 9)
        tops = sorted({0.0, *[h / a for h in lines if 0.0 < h / a < D], D})
        marks = sorted({0.0, 1.0, *[b / a for b in radii if 0.0 < b / a < R], R})
        fans = [m for m in marks if 0.0 < m < R]
        owns = not gmsh.isInitialized()
        if owns:
            gmsh.initialize(interruptible=False)
        gmsh.option.setNumber("General.Terminal", 0)
        try:
            gmsh.model.add("tankfx-bounds-box")
            geo = gmsh.model.geo
            # the left (r = 0) and right (r = R) points of each height, the surface's marks
            left = [geo.addPoint(0.0, -h, 0.0) for h in tops]
            right = [geo.addPoint(R, -h, 0.0) for h in tops]
            top = [left[0]] + [geo.addPoint(m, 0.0, 0.0) for m in marks[1:-1]] + [right[0]]
            rows = [[geo.addLine(p, q) for p, q in zip(top[:-1], top[1:])]]
            rows += [[geo.addLine(left[k], right[k])] for k in range(1, len(tops))]
            for k in range(len(tops) - 1):
                sides = [geo.addLine(right[k], right[k + 1]), geo.addLine(left[k + 1], left[k])]
                loop = geo.addCurveLoop(rows[k] + [sides[0]] + [-c for c in rows[k + 1][::-1]]
                                        + [sides[1]])
                geo.addPlaneSurface([loop])
            # a fan of FAN triangles at each point of the surface where the load jumps: the
            # lower bound's stress fans out there, and refinement (bisection) keeps the
            # number of triangles at a point (measured: a flexible load's lower bound held
            # at 4.26 c under refinement with the fan gmsh makes)
            spokes = []
            below = min(tops[1], 0.5 * size) if len(tops) > 1 else 0.5 * size
            for m in fans:
                centre = top[marks.index(m)]
                # (within 0.4 of the distance to the next mark: two fans never meet)
                rho = min([below] + [0.4 * abs(m - o) for o in marks if o != m])
                for k in range(1, FAN):
                    t = math.pi * k / FAN
                    tip = geo.addPoint(m - rho * math.cos(t), -rho * math.sin(t), 0.0)
                    spokes.append(geo.addLine(centre, tip))
            geo.synchronize()
            if spokes:
                gmsh.model.mesh.embed(1, spokes, 2, 1)
            field = gmsh.model.mesh.field
            f = field.add("MathEval")
            field.setString(f, "F", f"{size} + {growth} * sqrt((x - 1)^2 + y^2)")
            field.setAsBackgroundMesh(f)
            for name in ("MeshSizeFromPoints", "MeshSizeFromCurvature",
                         "MeshSizeExtendFromBoundary"):
                gmsh.option.setNumber(f"Mesh.{name}", 0)
            gmsh.model.mesh.generate(2)
            _, xyz, _ = gmsh.model.mesh.getNodes()
            types, _, nodes = gmsh.model.mesh.getElements(2)
            tags, _, _ = gmsh.model.mesh.getNodes()
            index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
            index[tags.astype(np.int64)] = np.arange(len(tags))
            cells = index[np.asarray(nodes[list(types).index(2)], dtype=np.int64)].reshape(-1, 3)
            points = xyz.reshape(-1, 3)[:, :2] * a
        finally:
            gmsh.model.remove()
            if owns:
                gmsh.finalize()
        return cls.from_points(points, cells, a)

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
