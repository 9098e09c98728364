"""Tank wall and foundation plate: thin axisymmetric shells of revolution on a 1D mesh.

The structure lives on a 1D mesh in the (r, z) plane (in an analysis, the facet submesh of
the soil's parent mesh made of the plate's underside and the wall's meridian). Each cell is a
straight meridian segment with unit tangent ``t`` (oriented towards +r on the plate and +z on
the wall) and normal ``n = (-t_z, t_r)`` (up on the plate, inward on the wall).

Unknowns: the displacement ``u = (u_r, u_z)`` of the line the mesh follows, the rotation
``beta`` of the
meridian (counter-clockwise in the (r, z) plane: one field for plate and wall, so a shared
vertex is a rigid joint), and the transverse shear force ``Q``, the Lagrange multiplier of the
Kirchhoff constraint ``beta = d(u.n)/ds``. With ``u`` in P3, ``beta`` in P2 and ``Q`` in DG2 the
constraint holds exactly, cell by cell: ``u.n`` is a C1 piecewise cubic, the thin-shell
(Kirchhoff-Love, Timoshenko's) model of the paper, with no shear locking at any thickness.

Strains of a conical shell element (Kraus 1967; plate: t = (1, 0), wall: t = (0, 1)):

    eps_s = d(u.t)/ds,  eps_theta = u_r / r,  kappa_s = d beta/ds,  kappa_theta = beta t_r / r

In a tank the mesh lines are the faces in contact with the soil (the plate's underside, the
wall's outer face), so the interface acts on ``u`` itself and the strains are those of the
mid-surface, half a thickness away (``offset``); plate and wall then meet at the outer
corner of a rigid joint, and the two faces share that corner's displacement.

Resultants per unit length: ``N = E t/(1 - nu^2) [eps_s + nu eps_theta, ...]`` and
``M = D [kappa_s + nu kappa_theta, ...]``, D = E t^3 / (12 (1 - nu^2)). A positive moment puts
the face opposite ``n`` in tension: the plate's underside (a sagging plate moment is
positive), the wall's outer face.
"""
from __future__ import annotations

import math

import basix.ufl
import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

__all__ = ["tangent", "normal", "arc_derivative", "shell_strains", "membrane_forces",
           "bending_moments", "mid_surface_displacement", "shell_stiffness", "kirchhoff_constraint",
           "structure_space", "line_mesh", "flexural_rigidity", "wall_beta", "shell_resultants",
           "StandaloneShell", "vertex_supports"]

#: Cell tags of the structure mesh.
PLATE, WALL, WALL_EMBEDDED = 1, 2, 3


def tangent(mesh1d):
    """Unit tangent of each (straight) cell, oriented so that t_r + t_z > 0."""
    J = ufl.Jacobian(mesh1d)
    t = ufl.as_vector([J[0, 0], J[1, 0]])
    t = t / ufl.sqrt(ufl.dot(t, t))
    return ufl.sign(t[0] + t[1]) * t


def normal(t):
    """The tangent turned counter-clockwise: up on the plate, inward on the wall."""
    return ufl.as_vector([-t[1], t[0]])


def arc_derivative(f, t):
    """d f / ds along the cell (f scalar or vector); t is constant on a straight cell."""
    return ufl.dot(ufl.grad(f), t)


def mid_surface_displacement(u, beta, t, offset):
    """Mid-surface displacement of a shell whose unknown ``u`` is the displacement of its face
    opposite n, ``offset`` (half the thickness) away: u_mid = u - offset beta t."""
    return u - offset * beta * t


def shell_strains(u, beta, r, t, offset=0.0, on_axis: bool = False):
    """(eps_s, eps_theta, kappa_s, kappa_theta) of the axisymmetric shell.

    ``u`` is the displacement of the line the mesh follows: the mid-surface (``offset`` 0) or
    the face opposite n, ``offset`` = thickness / 2 from the mid-surface (then the membrane
    strains are those of the mid-surface, u - offset beta t). ``on_axis`` replaces the hoop
    terms by their limits at r = 0 (u_r / r -> du_r/dr, beta / r -> d beta/dr), for point
    evaluation there; quadrature points never lie on r = 0.
    """
    um = mid_surface_displacement(u, beta, t, offset)
    kappa_s = arc_derivative(beta, t)
    eps_s = ufl.dot(arc_derivative(u, t), t) - offset * kappa_s
    if on_axis:
        eps_th = ufl.conditional(ufl.gt(r, 0.0), um[0] / r, eps_s)
        kappa_th = ufl.conditional(ufl.gt(r, 0.0), beta * t[0] / r, kappa_s * t[0] * t[0])
    else:
        eps_th = um[0] / r
        kappa_th = beta * t[0] / r
    return eps_s, eps_th, kappa_s, kappa_th


def flexural_rigidity(E, nu, thickness):
    """D = E t^3 / (12 (1 - nu^2))."""
    return E * thickness**3 / (12.0 * (1.0 - nu**2))


def membrane_forces(eps_s, eps_th, E, nu, thickness):
    """(N_s, N_theta), N/m, tension positive."""
    C = E * thickness / (1.0 - nu**2)
    return C * (eps_s + nu * eps_th), C * (eps_th + nu * eps_s)


def bending_moments(kappa_s, kappa_th, E, nu, thickness):
    """(M_s, M_theta), N m/m, positive when the face opposite n is in tension."""
    D = flexural_rigidity(E, nu, thickness)
    return D * (kappa_s + nu * kappa_th), D * (kappa_th + nu * kappa_s)


def shell_stiffness(u, beta, v, gamma, r, t, E, nu, thickness, dx, offset=0.0):
    """Bilinear form of membrane and bending energy, with the 2 pi r weight (``offset``: see
    :func:`shell_strains`)."""
    e = shell_strains(u, beta, r, t, offset)
    ev = shell_strains(v, gamma, r, t, offset)
    N_s, N_th = membrane_forces(e[0], e[1], E, nu, thickness)
    M_s, M_th = bending_moments(e[2], e[3], E, nu, thickness)
    work = N_s * ev[0] + N_th * ev[1] + M_s * ev[2] + M_th * ev[3]
    return work * 2.0 * math.pi * r * dx


def kirchhoff_constraint(Q, beta, u, t, r, dx):
    """Q (beta - d(u.n)/ds): the multiplier term that makes the shell thin (no transverse
    shear strain). Used twice (with trial and test functions) for a symmetric saddle point."""
    return Q * (beta - ufl.dot(arc_derivative(u, t), normal(t))) * 2.0 * math.pi * r * dx


def structure_space(mesh1d, degree: int = 3):
    """Mixed space (u in P_k^2, beta in P_{k-1}, Q in DG_{k-1}) on a 1D mesh in 2D."""
    cell = mesh1d.basix_cell()
    P = basix.ufl.element("Lagrange", cell, degree, shape=(2,))
    B = basix.ufl.element("Lagrange", cell, degree - 1)
    S = basix.ufl.element("DG", cell, degree - 1)
    return fem.functionspace(mesh1d, basix.ufl.mixed_element([P, B, S]))


def wall_beta(radius, thickness, nu):
    """Decay rate of the wall's bending boundary layer, beta^4 = 3 (1 - nu^2) / (R t)^2, 1/m."""
    return (3.0 * (1.0 - nu**2) / (radius * thickness) ** 2) ** 0.25


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


class StandaloneShell:
    """A plate or wall on its own, on rigid supports: for verification against plate and
    shell theory, and for benchmarks. ``supports`` maps a vertex predicate ``f(x) -> bool``
    to the constrained components among "u_r", "u_z", "beta"; ``load(v, x)`` returns the
    work density of the applied load on the test displacement v (per unit meridian area).
    ``thickness`` is a number, or a function of the cells' midpoints (n, 2) -> (n,) for a
    member whose thickness steps (a wall's courses; put the steps on vertices)."""

    def __init__(self, points, E, nu, thickness, supports, load, comm=MPI.COMM_WORLD):
        from .solve import DirectSolver

        self.mesh, self.cell_tags = line_mesh(comm, points)
        msh = self.mesh
        msh.topology.create_connectivity(0, 1)
        self.W = structure_space(msh)
        self.E, self.nu = (fem.Constant(msh, float(v)) for v in (E, nu))
        if callable(thickness):
            self.thickness = fem.Function(fem.functionspace(msh, ("DG", 0)), name="thickness")
            n = msh.topology.index_map(1).size_local + msh.topology.index_map(1).num_ghosts
            cells = np.arange(n, dtype=np.int32)
            mids = dmesh.compute_midpoints(msh, 1, cells)[:, :2]
            self.thickness.x.array[self.thickness.function_space.dofmap.list[:, 0]] = \
                thickness(mids)
        else:
            self.thickness = fem.Constant(msh, float(thickness))
        x = ufl.SpatialCoordinate(msh)
        self.r, self.t = x[0], tangent(msh)
        dx = ufl.Measure("dx", domain=msh)
        u, b, Q = ufl.TrialFunctions(self.W)
        v, g, P = ufl.TestFunctions(self.W)
        a = (shell_stiffness(u, b, v, g, self.r, self.t, self.E, self.nu, self.thickness, dx)
             + kirchhoff_constraint(Q, g, v, self.t, self.r, dx)
             + kirchhoff_constraint(P, b, u, self.t, self.r, dx))
        L = load(v, x) * 2.0 * math.pi * self.r * dx
        bcs = vertex_supports(msh, {"u_r": self.W.sub(0).sub(0), "u_z": self.W.sub(0).sub(1),
                                    "beta": self.W.sub(1)}, supports)
        self.w = fem.Function(self.W)
        DirectSolver(a, L, bcs, self.w, name="shell").solve()

    def resultants(self) -> dict:
        """M_s, M_theta, N_s, N_theta, Q (DG2 fields) and u, beta, as in the coupled model."""
        return shell_resultants(self.w, self.r, self.t, self.E, self.nu, self.thickness)


class ShellResultants:
    """The resultants of a shell ``w`` (mixed u, beta, Q) as cell-wise DG2 fields for point
    evaluation, their expressions compiled once: each call reads the current ``w`` (and the
    fields E, nu, thickness as they are then). A consolidation reads the foundation's
    results at every time step: compiling (or looking up the JIT cache for) the five
    expressions each time cost more than the step's assembly (2.0 of 22.5 s over 56 steps
    of the clay tank at 81k dofs)."""

    def __init__(self, w, r, t, E, nu, thickness, offset=0.0):
        u, b, Q = ufl.split(w)
        e = shell_strains(u, b, r, t, offset, on_axis=True)
        N_s, N_th = membrane_forces(e[0], e[1], E, nu, thickness)
        M_s, M_th = bending_moments(e[2], e[3], E, nu, thickness)
        self.w = w
        self.space = fem.functionspace(w.function_space.mesh, ("DG", 2))
        points = self.space.element.interpolation_points
        self.expressions = {name: fem.Expression(expr, points) for name, expr in
                            {"M_s": M_s, "M_theta": M_th, "N_s": N_s, "N_theta": N_th,
                             "Q": -Q}.items()}

    def __call__(self) -> dict:
        """M_s, M_theta, N_s, N_theta, the shear force Q (minus the multiplier), and the
        collapsed u and beta: new Functions at each call."""
        out = {}
        for name, expression in self.expressions.items():
            f = fem.Function(self.space, name=name)
            f.interpolate(expression)
            out[name] = f
        out["u"] = self.w.sub(0).collapse()
        out["beta"] = self.w.sub(1).collapse()
        return out


def shell_resultants(w, r, t, E, nu, thickness, offset=0.0) -> dict:
    """The resultants of a solved shell ``w`` once (see :class:`ShellResultants`)."""
    return ShellResultants(w, r, t, E, nu, thickness, offset)()
