"""Verification rigs: the structure and the soil on their own, on rigid supports, to be
compared with closed forms (:mod:`tankfx.verification.reference`): a plate or wall shell, its
first harmonic, Terzaghi's oedometer and Mandel's cylinder (Biot's consolidation).
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ..fem.evaluate import evaluate_at
from ..fem.lines import line_mesh, vertex_supports
from ..fem.solvers import DirectSolver
from ..laws import elasticity as soil_forms
from ..laws import harmonic as hm
from ..laws.biot import StepWeights, biot_forms, drainage_form, previous_volume_load
from ..laws.shell import kirchhoff_constraint, shell_stiffness, structure_space, tangent
from ..model.structure import shell_resultants


class StandaloneShell:
    """A plate or wall on its own, on rigid supports: for verification against plate and
    shell theory, and for benchmarks. ``supports`` maps a vertex predicate ``f(x) -> bool``
    to the constrained components among "u_r", "u_z", "beta"; ``load(v, x)`` returns the
    work density of the applied load on the test displacement v (per unit meridian area).
    ``thickness`` is a number, or a function of the cells' midpoints (n, 2) -> (n,) for a
    member whose thickness steps (a wall's courses; put the steps on vertices)."""

    def __init__(self, points, E, nu, thickness, supports, load, comm=MPI.COMM_WORLD):
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


class StandaloneHarmonicShell:
    """A plate or wall on its own under a first-harmonic load, on rigid supports (for
    verification, like :class:`tankfx.verification.rigs.StandaloneShell`). ``supports`` maps a
    vertex
    predicate to constrained components among "D", "Z", "S", "beta" (a clamped edge: all
    four; the axis of a plate: "Z" and "S"). ``load(u, V, x)`` is the work density of the
    applied load amplitudes on the test displacement (u = (A, Z), V) per unit area, and
    ``edge_load(u, V, x)`` (optional) that of a ring load per unit length on the mesh's end
    vertices."""

    def __init__(self, points, E, nu, thickness, supports, load, edge_load=None,
                 comm=MPI.COMM_WORLD):
        self.mesh, _ = line_mesh(comm, points)
        msh = self.mesh
        msh.topology.create_connectivity(0, 1)
        self.W = hm.structure_space(msh)
        self.E, self.nu, self.thickness = (fem.Constant(msh, float(v))
                                           for v in (E, nu, thickness))
        x = ufl.SpatialCoordinate(msh)
        self.r, self.t = x[0], tangent(msh)
        dx = ufl.Measure("dx", domain=msh)
        q, b, Q, s = ufl.TrialFunctions(self.W)
        qv, bv, P, sv = ufl.TestFunctions(self.W)
        u, _ = hm.shell_amplitudes(q, s)
        uv, Vv = hm.shell_amplitudes(qv, sv)
        a = (hm.shell_stiffness((q, b, s), (qv, bv, sv), self.r, self.t, self.E, self.nu,
                             self.thickness, dx)
             + hm.kirchhoff_constraint(Q, bv, uv, self.t, self.r, dx)
             + hm.kirchhoff_constraint(P, b, u, self.t, self.r, dx))
        L = load(uv, Vv, x) * hm.WEIGHT * self.r * dx
        if edge_load is not None:
            L += edge_load(uv, Vv, x) * hm.WEIGHT * self.r * ufl.Measure("ds", domain=msh)
        bcs = vertex_supports(msh, {"D": self.W.sub(0).sub(0), "Z": self.W.sub(0).sub(1),
                                       "beta": self.W.sub(1), "S": self.W.sub(3)}, supports)
        self.w = fem.Function(self.W)
        DirectSolver(a, L, bcs, self.w, name="harmonic_shell").solve()

    def resultants(self) -> dict:
        return hm.shell_resultants(self.w, self.r, self.t, self.E, self.nu, self.thickness)


class Sample:
    """A saturated sample on a rectangle of the meridian plane (r from 0 to ``radius``, z
    from ``bottom`` to ``top``), in Biot's forms above: its supports and loads given by the
    subclass (``_supports``, ``_load``, ``drained``: the drained edges), stepped in time by
    :meth:`run`, which records :meth:`record` per time."""

    def __init__(self, radius, bottom, top, cells, E, nu, permeability, water_unit_weight,
                 degree, comm):
        self.radius, self.bottom, self.top = radius, bottom, top
        msh = self.mesh = dmesh.create_rectangle(
            comm, [np.array([0.0, bottom]), np.array([radius, top])], list(cells),
            dmesh.CellType.triangle)
        V = fem.functionspace(msh, ("Lagrange", degree, (2,)))
        Q = fem.functionspace(msh, ("Lagrange", degree - 1))
        self.u, self.p = fem.Function(V), fem.Function(Q)
        self.u_n, self.u_nn = fem.Function(V), fem.Function(V)
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        p, s = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        self.r = r = soil_forms.radius(msh)
        self.dx = dx = ufl.Measure("dx", domain=msh, metadata={
            "quadrature_degree": soil_forms.quadrature_degree(degree)})
        self.E, self.nu = E, nu
        self.conductance = fem.Constant(msh, 0.0)
        self.load_factor = fem.Constant(msh, 1.0)
        a_uu, a_up, a_pu, a_pp = biot_forms(u, p, v, s, E, nu, self.conductance, r, dx)
        self._k_over_gamma = permeability / water_unit_weight
        self.weights = StepWeights(msh)
        L_p = previous_volume_load([(self.weights.previous, self.u_n),
                                    (self.weights.before, self.u_nn)], s, r, dx)
        drained = np.sort(np.concatenate([self.edge(name) for name in self.drained]))
        tags = dmesh.meshtags(msh, 1, drained, np.ones(len(drained), dtype=np.int32))
        a_pp += drainage_form(p, s, self.conductance, r,
                              ufl.Measure("ds", domain=msh, subdomain_data=tags)(1), degree - 1)
        self.solver = DirectSolver([[a_uu, a_up], [a_pu, a_pp]], [self._load(v), L_p],
                                   self._supports(V), [self.u, self.p], name="sample",
                                   symmetric=True)

    def edge(self, name: str) -> np.ndarray:
        """The boundary facets of an edge: "axis", "side" (r = radius), "top", "bottom"."""
        where = {"axis": (0, 0.0), "side": (0, self.radius), "top": (1, self.top),
                 "bottom": (1, self.bottom)}[name]
        return dmesh.locate_entities_boundary(self.mesh, 1,
                                              lambda x: np.isclose(x[where[0]], where[1]))

    def fix(self, V, component: int, edges, value: float = 0.0):
        """A Dirichlet condition on one displacement component along the named edges."""
        Vc = V.sub(component)
        facets = np.concatenate([self.edge(e) for e in edges])
        return fem.dirichletbc(value, fem.locate_dofs_topological(Vc, 1, facets), Vc)

    def run(self, steps, second_order: bool = True, load_factor=None) -> list[dict]:
        """The undrained response at t = 0, then a step to each time in ``steps`` (s,
        increasing; BDF2, or backward Euler throughout without ``second_order``): per time,
        ``t`` and what :meth:`record` gives. ``load_factor(t)`` (default 1) scales the
        load in time (a ramp: 0 at t = 0)."""
        out, t_prev, dt_prev = [], 0.0, 0.0
        for t in [0.0, *steps]:
            if load_factor is not None:
                self.load_factor.value = load_factor(t)
            dt = t - t_prev
            self.conductance.value = self.weights.set(dt, dt_prev, second_order) * \
                self._k_over_gamma
            self.solver.solve()
            self.u_nn.x.array[:] = self.u_n.x.array
            self.u_n.x.array[:] = self.u.x.array
            out.append({"t": t, **self.record()})
            t_prev, dt_prev = t, dt
        return out


class Oedometer(Sample):
    """A saturated column under a load q applied at t = 0 and held (Terzaghi's problem, in
    the axisymmetric forms above): ``height``, laterally confined (u_r = 0 on both sides),
    fixed and impervious at the base, drained at the loaded top (and at the base too with
    ``drained_base``). For verification against
    :func:`tankfx.verification.reference.terzaghi_settlement`, and for calibrating c_v."""

    def __init__(self, height, E, nu, permeability, q, water_unit_weight=9810.0,
                 cells: int = 40, degree: int = 2, drained_base: bool = False,
                 comm=MPI.COMM_WORLD):
        self.q = q
        self.drained = ("top", "bottom") if drained_base else ("top",)
        R = height / cells
        super().__init__(R, -height, 0.0, (1, cells), E, nu, permeability, water_unit_weight,
                         degree, comm)
        self._top = np.array([[0.5 * R, 0.0]])
        self._base = np.array([[0.5 * R, -height]])

    def _load(self, v):
        tags = dmesh.meshtags(self.mesh, 1, self.edge("top"),
                              np.ones(len(self.edge("top")), dtype=np.int32))
        ds = ufl.Measure("ds", domain=self.mesh, subdomain_data=tags)
        return -self.q * self.load_factor * v[1] * 2.0 * math.pi * self.r * ds(1)

    def _supports(self, V):
        return [self.fix(V, 0, ("axis", "side")), self.fix(V, 1, ("bottom",))]

    def record(self) -> dict:
        """The settlement (m) and the excess pore pressure at the base (Pa)."""

        return {"settlement": float(-evaluate_at(self.u, self._top)[0, 1]),
                "base_pressure": float(evaluate_at(self.p, self._base)[0, 0])}


class MandelCylinder(Sample):
    """A saturated cylinder of ``radius`` (and as high) between rigid, smooth, impervious
    plates that shorten it by ``strain`` at t = 0 and hold it, drained and free on its side
    (:func:`tankfx.verification.reference.mandel_cylinder`): a check of the consolidation's coupling
    in the hoop direction and through a drained side, where its excess pore pressure at the
    centre first rises above its start (Mandel and Cryer's effect)."""

    drained = ("side",)

    def __init__(self, radius, E, nu, permeability, strain, water_unit_weight=9810.0,
                 cells: int = 16, degree: int = 2, comm=MPI.COMM_WORLD):
        self.strain = strain
        super().__init__(radius, 0.0, radius, (cells, cells), E, nu, permeability,
                         water_unit_weight, degree, comm)
        w = 2.0 * math.pi * self.r
        sigma = soil_forms.stress(soil_forms.strain(self.u, self.r), E, nu) - \
            self.p * ufl.Identity(3)
        self._force = fem.form(-sigma[1, 1] * w / radius * self.dx)     # (uniform in z)
        self._mean = fem.form(self.p * w / (math.pi * radius**3) * self.dx)

    def _load(self, v):
        return ufl.inner(fem.Constant(self.mesh, (0.0, 0.0)), v) * self.dx

    def _supports(self, V):
        return [self.fix(V, 0, ("axis",)), self.fix(V, 1, ("bottom",)),
                self.fix(V, 1, ("top",), self.strain * self.radius)]

    def record(self) -> dict:
        """The axial force (N, compression positive), the mean and the centre's excess pore
        pressure (Pa)."""

        comm = self.mesh.comm
        return {"force": comm.allreduce(fem.assemble_scalar(self._force)),
                "mean_pressure": comm.allreduce(fem.assemble_scalar(self._mean)),
                "centre_pressure": float(evaluate_at(
                    self.p, np.array([[0.0, 0.5 * self.radius]]))[0, 0])}
