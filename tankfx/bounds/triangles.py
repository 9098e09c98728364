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

AXIS, CONTACT, SURFACE, SIDE, BASE, PIT_SIDE = 0, 1, 2, 3, 4, 5
#: the triangles of the fan at the foundation's edge (and a band's ends) of a box's mesh
FAN = 24


@dataclass(frozen=True)
class Triangles:
    """``points`` (n, 2) (r, z), ``cells`` (m, 3) counterclockwise, ``edges`` (k, 2) the
    boundary edges (their two vertices), ``kind`` (k,) and ``owner`` (k,) (its triangle) of
    each, ``a`` the foundation's radius, ``embedment`` its underside's depth (m): the
    contact is then the pit's bottom (z = -embedment, r < a), and its side (r = a above it,
    PIT_SIDE) a contact with the foundation's edge."""

    points: np.ndarray
    cells: np.ndarray
    edges: np.ndarray
    kind: np.ndarray
    owner: np.ndarray
    a: float
    embedment: float = 0.0

    @classmethod
    def from_points(cls, points: np.ndarray, cells: np.ndarray, a: float,
                    embedment: float = 0.0) -> "Triangles":
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
        bottom = np.abs(mid[:, 1] - (top - embedment)) < tol
        kind[bottom & (mid[:, 0] < a)] = CONTACT
        kind[on_top & (mid[:, 0] > a)] = SURFACE
        if embedment > 0.0:
            kind[(np.abs(mid[:, 0] - a) < tol) & (mid[:, 1] > top - embedment)] = PIT_SIDE
        kind[np.abs(mid[:, 0]) < tol] = AXIS
        if np.any(kind < 0):
            raise ValueError("a boundary edge off the axis, the surface, the pit, the side and "
                             "the base: limit analysis takes a foundation in a box")
        return cls(points, cells, edges, kind, owner, a, embedment)

    @classmethod
    def box(cls, a: float, radius: float, depth: float, lines=(), radii=(), size: float = 0.1,
            growth: float = 0.3, embedment: float = 0.0) -> "Triangles":
        """The box r <= radius, -depth <= z <= 0 (m), less the pit r < a, z > -embedment,
        meshed by gmsh (serial), its edges ``size`` a long at the foundation's edge
        (r = a, z = -embedment) and growing by ``growth`` times the distance from it; the
        heights ``lines`` (m below the surface: layers' tops) and the radii ``radii`` (m: a
        load's band edges under the foundation) among its edges. At each point where the
        surface's load jumps (the foundation's edge, a band's ends, the pit's rim) a fan
        of triangles: the lower bound's stress fans out there, and bisection keeps the
        number of triangles at a point. Meshed in units of a and scaled, so that the same
        box in other units is the same mesh."""
        import gmsh

        # (rounded: a box grown in other units may differ from this one in its last bit)
        R, D, P = (round(v / a, 9) for v in (radius, depth, embedment))
        marks = sorted({1.0, *[b / a for b in radii if 0.0 < b / a < 1.0]})
        owns = not gmsh.isInitialized()
        if owns:
            gmsh.initialize(interruptible=False)
        gmsh.option.setNumber("General.Terminal", 0)
        try:
            gmsh.model.add("tankfx-bounds-box")
            occ = gmsh.model.occ
            ground = [(2, occ.addRectangle(0.0, -D, 0.0, R, D))]
            if P > 0.0:
                ground, _ = occ.cut(ground, [(2, occ.addRectangle(0.0, -P, 0.0, 1.0, P))])
            tools = []
            for h in lines:
                h = h / a
                if 0.0 < h < D and abs(h - P) > 1e-9:
                    x0 = 1.0 if h < P else 0.0
                    tools.append((1, occ.addLine(occ.addPoint(x0, -h, 0.0),
                                                 occ.addPoint(R, -h, 0.0))))
            # the fans: at each mark on the contact the soil's half plane below it (and the
            # pit's side beyond the bottom's edge: three quarters); at the pit's rim a quarter
            fans = [(m, -P, math.pi, (1.5 if (P > 0.0 and m == 1.0) else 1.0) * math.pi)
                    for m in marks]
            if P > 0.0:
                fans.append((1.0, 0.0, 1.5 * math.pi, 0.5 * math.pi))
            below = 0.5 * size
            for m, zc, start, span in fans:
                others = [abs(m - o) for o in marks if o != m] + ([P] if P > 0.0 else [])
                rho = min([below] + [0.4 * d for d in others if d > 0.0])
                n = max(2, int(round(FAN * span / math.pi)))
                centre = occ.addPoint(m, zc, 0.0)
                tools.append((0, centre))
                for k in range(1, n):
                    t = start + span * k / n
                    tip = occ.addPoint(m + rho * math.cos(t), zc + rho * math.sin(t), 0.0)
                    tools.append((1, occ.addLine(centre, tip)))
            occ.fragment(ground, tools)
            occ.synchronize()
            field = gmsh.model.mesh.field
            f = field.add("MathEval")
            field.setString(f, "F", f"{size} + {growth} * sqrt((x - 1)^2 + (y + {P})^2)")
            field.setAsBackgroundMesh(f)
            for name in ("MeshSizeFromPoints", "MeshSizeFromCurvature",
                         "MeshSizeExtendFromBoundary"):
                gmsh.option.setNumber(f"Mesh.{name}", 0)
            gmsh.model.mesh.generate(2)
            tags, xyz, _ = gmsh.model.mesh.getNodes()
            types, _, nodes = gmsh.model.mesh.getElements(2)
            index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
            index[tags.astype(np.int64)] = np.arange(len(tags))
            cells = np.concatenate([index[np.asarray(nd, dtype=np.int64)].reshape(-1, 3)
                                    for tp, nd in zip(types, nodes) if tp == 2])
            points = xyz.reshape(-1, 3)[:, :2] * a
        finally:
            gmsh.model.remove()
            if owns:
                gmsh.finalize()
        return cls.from_points(points, cells, a, embedment)

    @classmethod
    def from_mesh(cls, msh, a: float, embedment: float = 0.0) -> "Triangles":
        """The straight triangles of a DOLFINx mesh on one process (its cells' vertices)."""
        import dolfinx.mesh as dmesh

        tdim = msh.topology.dim
        msh.topology.create_connectivity(tdim, 0)
        cells = np.arange(msh.topology.index_map(tdim).size_local, dtype=np.int32)
        nodes = dmesh.entities_to_geometry(msh, tdim, cells)[:, :3]
        return cls.from_points(msh.geometry.x, nodes, a, embedment)

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
        return Triangles.from_mesh(fine, self.a, self.embedment)


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
