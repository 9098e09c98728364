"""A thick-walled cylinder of elastoplastic soil under internal pressure, in plane strain
(the meridian plane's rectangle a <= r <= b, its top and bottom held vertically): the rig
that checks the plastic soil's forms and Newton iteration against Hill's closed form
(:func:`tankfx.verification.reference.thick_cylinder_tresca_pressure`)."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ..fem.blocks import OutOfBalance
from ..fem.evaluate import evaluate_at
from ..fem.solvers import DirectSolver
from ..laws import elasticity as soil_forms
from ..model.plastic import PlasticState


def rig_plastic_state(msh, u, r, law, soil, degree: int) -> PlasticState:
    """The plastic state of a rig whose whole mesh is soil (no void, no ringwall): a
    :class:`tankfx.model.plastic.PlasticState` on a stand-in for the soil block (what the
    state reads of one: the mesh, its soil cells, the displacement and the radius)."""
    n = msh.topology.index_map(2).size_local + msh.topology.index_map(2).num_ghosts
    every = np.arange(n, dtype=np.int32)
    block = SimpleNamespace(domain=SimpleNamespace(mesh=msh, cells=lambda name: every),
                            u=u, r=r, ringwall_cells=np.zeros(n, bool),
                            fill_cells=np.zeros(n, bool))
    return PlasticState(block, law, soil, degree)


class ThickCylinder:
    """The cylinder a <= r <= b (height ``height``) of a resolved [soil] (``soil``: its law
    the elastoplastic one, weightless), ``cells`` = (n_r, n_z) triangles' rectangles,
    Lagrange ``degree``; :meth:`load` raises the internal pressure by Newton."""

    def __init__(self, soil, a: float, b: float, cells=(40, 2), degree: int = 2,
                 height: float = 0.1, comm=MPI.COMM_WORLD):
        self.a, self.b = a, b
        msh = dmesh.create_rectangle(comm, [np.array([a, 0.0]), np.array([b, height])],
                                     list(cells), dmesh.CellType.triangle)
        V = fem.functionspace(msh, ("Lagrange", degree, (2,)))
        self.u = fem.Function(V)
        r = soil_forms.radius(msh)
        dx = ufl.Measure("dx", domain=msh,
                         metadata={"quadrature_degree": soil_forms.quadrature_degree(degree)})
        self.state = rig_plastic_state(msh, self.u, r, soil.law, soil, degree)
        du, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        inner = dmesh.locate_entities_boundary(msh, 1, lambda x: np.isclose(x[0], a))
        tags = dmesh.meshtags(msh, 1, inner, np.ones(len(inner), dtype=np.int32))
        ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)(1)
        self.pressure = fem.Constant(msh, 0.0)
        a_form = self.state.stiffness(du, v, r, dx)
        L_form = self.state.load(v, r, dx) + self.pressure * v[0] * 2.0 * math.pi * r * ds
        ends = dmesh.locate_entities_boundary(
            msh, 1, lambda x: np.isclose(x[1], 0.0) | np.isclose(x[1], height))
        bcs = [fem.dirichletbc(0.0, fem.locate_dofs_topological(V.sub(1), 1, ends), V.sub(1))]
        self.solver = DirectSolver(a_form, L_form, bcs, self.u, name="cylinder")
        self.balance = OutOfBalance([[a_form]], [L_form], [self.u], bcs)
        self.mesh = msh

    def load(self, p: float, tolerance: float = 1e-10, max_iterations: int = 30) -> int:
        """Raise the internal pressure to ``p`` (Pa) from the committed state by Newton;
        commit; returns the iterations."""
        self.pressure.value = p
        for it in range(1, max_iterations + 1):
            self.solver.solve()
            self.state.update()
            if self.balance() <= tolerance:
                self.state.commit()
                return it
        raise RuntimeError(f"the cylinder did not converge at p = {p:g} Pa")

    def inner_displacement(self) -> float:
        return float(evaluate_at(self.u, np.array([[self.a, 0.0]]))[0, 0])

    def plastic_radius(self) -> float:
        """The largest radius of a yielding quadrature point (a, where none yields)."""
        s = self.state
        x = fem.Expression(ufl.SpatialCoordinate(self.mesh), s.S1.element.interpolation_points
                           ).eval(self.mesh, s.cells).reshape(-1, 2)
        own = self.mesh.topology.index_map(2).size_local * s.n_points
        plastic = s.yielding[:own]
        local = float(x[:own, 0][plastic].max(initial=self.a))
        return self.mesh.comm.allreduce(local, op=MPI.MAX)
