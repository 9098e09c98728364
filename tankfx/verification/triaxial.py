"""A triaxial test on a cell of saturated soil in the coupled analysis's own forms: the
rig that checks an elastoplastic law and Biot's coupling together against the closed forms
of the triaxial test (Modified Cam Clay's: tests/test_cam_clay.py).

The sample is the meridian plane's rectangle 0 <= r <= ``radius``, 0 <= z <= ``height``:
smooth rigid platens (u_z held at the base, u_z = -eps_a height at the top, u_r free), its
side free, so that the cell pressure stays at the sample's state at rest (the forms carry
only the stress's change from it: a free side is a constant total radial stress). The soil is
the analysis's: the stress, tangent and state at the quadrature points of
:class:`tankfx.model.plastic.PlasticState`, the pore pressure one degree below the
displacement and coupled to it by Biot's blocks (:func:`tankfx.laws.biot.biot_forms`). A
compression with no time (no flow: the sample's volume kept) is the undrained test.
Each axial strain is reached by Newton's method on the block system (the tangent of the
law, the coupling's blocks), as in the tank's time steps.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ..fem.blocks import OutOfBalance
from ..fem.solvers import DirectSolver
from ..laws import elasticity as soil_forms
from ..laws.biot import biot_forms
from ..laws.plasticity import IDENTITY
from .cylinder import rig_plastic_state


class TriaxialCell:
    """The sample of a law at uniform points: ``points_of(n)`` gives the point law
    (:class:`tankfx.laws.point_law.PointLaw`) of n points, its ground at rest the sample's
    state before the test (effective, uniform); ``cells`` = (n_r, n_z) rectangles of two
    triangles each, Lagrange ``degree`` for the displacement. :meth:`compress` shortens it
    undrained."""

    def __init__(self, points_of, radius: float = 1.0, height: float = 1.0, cells=(1, 1),
                 degree: int = 2, comm=MPI.COMM_WORLD):
        self.height = height
        msh = self.mesh = dmesh.create_rectangle(
            comm, [np.array([0.0, 0.0]), np.array([radius, height])], list(cells),
            dmesh.CellType.triangle)
        V = fem.functionspace(msh, ("Lagrange", degree, (2,)))
        Q = fem.functionspace(msh, ("Lagrange", degree - 1))
        self.u, self.p = fem.Function(V, name="u"), fem.Function(Q, name="pore_pressure")
        r = soil_forms.radius(msh)
        dx = ufl.Measure("dx", domain=msh,
                         metadata={"quadrature_degree": soil_forms.quadrature_degree(degree)})
        # (what the plastic state reads of a law: its points)
        law = SimpleNamespace(point_law=lambda soil, depth: points_of(len(depth)))
        self.state = rig_plastic_state(msh, self.u, r, law, None, degree)
        du, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        dp, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        # no time: no flow (the conductance dt k / gamma_w is zero), the volume kept at
        # the sample's before the test (the previous state's volume load is nil)
        no_flow = fem.Constant(msh, 0.0)
        _, a_up, a_pu, a_pp = biot_forms(du, dp, v, q, 1.0, 0.0, no_flow, r, dx)
        a = [[self.state.stiffness(du, v, r, dx), a_up], [a_pu, a_pp]]
        L = [self.state.load(v, r, dx), no_flow * q * dx]
        self._top = fem.Constant(msh, 0.0)
        bcs = [self._held(V, 0, lambda x: np.isclose(x[0], 0.0), 0.0),
               self._held(V, 1, lambda x: np.isclose(x[1], 0.0), 0.0),
               self._held(V, 1, lambda x: np.isclose(x[1], height), self._top)]
        self.solver = DirectSolver(a, L, bcs, [self.u, self.p], name="triaxial")
        self.balance = OutOfBalance(a, L, [self.u, self.p], bcs)
        w = 2.0 * math.pi * r
        volume = comm.allreduce(fem.assemble_scalar(fem.form(w * dx)))
        self._mean_p = fem.form(self.p * w / volume * dx)
        self._volume_change = fem.form(ufl.tr(soil_forms.strain(self.u, r)) * w / volume * dx)

    def _held(self, V, component, where, value):
        facets = dmesh.locate_entities_boundary(self.mesh, 1, where)
        Vc = V.sub(component)
        return fem.dirichletbc(value, fem.locate_dofs_topological(Vc, 1, facets), Vc)

    def compress(self, axial_strain: float, tolerance: float = 1e-10,
                 max_iterations: int = 30) -> int:
        """Shorten the sample to ``axial_strain`` (compression positive) from the committed
        state, undrained, by Newton; commit; returns the iterations. Converged where the
        out-of-balance force is below ``tolerance`` of the load vector, or where an
        iteration changed the displacement by less than ``tolerance`` of it (an elastic
        step: its stress is C eps to round-off, and so its load vector sigma - C eps, to
        which the out-of-balance force is relative, is round-off too)."""
        self._top.value = -axial_strain * self.height
        for it in range(1, max_iterations + 1):
            before = self.u.x.array.copy()
            self.solver.solve()
            self.state.update()
            change = np.linalg.norm(self.u.x.array - before)
            size = np.linalg.norm(self.u.x.array)
            change, size = (math.sqrt(self.mesh.comm.allreduce(x * x)) for x in (change, size))
            if self.balance() <= tolerance or change <= tolerance * size:
                self.state.commit()
                return it
        raise RuntimeError(f"the triaxial cell did not converge at an axial strain of "
                           f"{axial_strain:g}")

    def record(self) -> dict:
        """The sample's state now: the mean of its points' p' and q (Pa; compression
        positive), their spread (the largest difference from the mean, Pa: nil in a
        uniform sample), the mean excess pore pressure (Pa) and volumetric strain
        (compression negative). Collective."""
        s = self.state
        own = self.mesh.topology.index_map(2).size_local * s.n_points
        stress = (s._get(s.stress, s._dofs4, 4) + s._get(s.geostatic, s._dofs4, 4))[:own]
        p = -(stress @ IDENTITY) / 3.0
        dev = stress + p[:, None] * IDENTITY
        q = np.sqrt(1.5 * np.einsum("ij,ij->i", dev, dev))
        comm = self.mesh.comm
        count = comm.allreduce(len(p))
        means = [comm.allreduce(float(x.sum())) / count for x in (p, q)]
        spread = comm.allreduce(max(float(np.abs(p - means[0]).max(initial=0.0)),
                                    float(np.abs(q - means[1]).max(initial=0.0))), op=MPI.MAX)
        return {"p": means[0], "q": means[1], "spread": spread,
                "pore_pressure": comm.allreduce(fem.assemble_scalar(self._mean_p)),
                "volumetric_strain": comm.allreduce(fem.assemble_scalar(self._volume_change))}
