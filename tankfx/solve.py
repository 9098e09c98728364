"""Linear solves of the (block) system with a direct solver, and the reactions they imply.

Every solver gets its own PETSc options prefix (no global options), and a failed or non-finite
solve raises :class:`SolveError` instead of handing back numbers.
"""
from __future__ import annotations

import itertools

import numpy as np
import ufl
from dolfinx import fem, la
from dolfinx.fem import petsc as fem_petsc

from .post import allsum

__all__ = ["SolveError", "DirectSolver", "reaction_force"]

_ids = itertools.count()


class SolveError(RuntimeError):
    """A solve that did not converge; its numbers must not be reported as results."""


class DirectSolver:
    """MUMPS LU on the monolithic system ``a u = L`` (blocks assembled with ``kind="mpi"``)."""

    def __init__(self, a, L, bcs, u, entity_maps=None, name: str = "soil"):
        self.prefix = f"tankfx_{name}_{next(_ids)}_"
        self.problem = fem_petsc.LinearProblem(
            a, L, bcs=bcs, u=u, kind="mpi" if isinstance(u, (list, tuple)) else None,
            petsc_options_prefix=self.prefix, entity_maps=entity_maps,
            petsc_options={"ksp_type": "preonly", "pc_type": "lu",
                           "pc_factor_mat_solver_type": "mumps",
                           # MUMPS: relax pivoting-memory estimate for stiff contrasts
                           "mat_mumps_icntl_14": 80})
        self.u = u

    def solve(self):
        u = self.problem.solve()
        ksp = self.problem.solver
        reason = ksp.getConvergedReason()
        if reason <= 0:
            raise SolveError(f"the linear solver failed (PETSc KSP reason {reason}); "
                             "the matrix may be singular: check the supports of the scene")
        x = self.problem.x
        if not np.isfinite(x.norm()):
            raise SolveError("the linear solve returned non-finite values (NaN/inf): "
                             "the system is singular or the data overflowed")
        return u

    @property
    def matrix_size(self) -> int:
        return self.problem.A.getSize()[0]


def reaction_force(a, L, u: fem.Function, component: int, facets: np.ndarray) -> float:
    """Force (N) that the supports on ``facets`` exert on the body in direction ``component``.

    It is the residual ``a(u, v) - L(v)`` of the unconstrained system at the constrained
    degrees of freedom, summed over the owned dofs of all ranks: positive means the support
    pushes the body in the +``component`` direction.
    """
    V = u.function_space
    residual = fem.form(ufl.action(a, u) - L)
    vec = fem.assemble_vector(residual)
    vec.scatter_reverse(la.InsertMode.add)
    nodes = fem.locate_dofs_topological(V, V.mesh.topology.dim - 1, facets)
    nodes = nodes[nodes < V.dofmap.index_map.size_local]
    bs = V.dofmap.index_map_bs
    local = vec.array.reshape(-1, bs)[nodes, component].sum()
    return allsum(V.mesh.comm, local)

