"""Linear solves of the (block) system with a direct solver, and the reactions they imply.

Every solver gets its own PETSc options prefix (no global options), and a failed or non-finite
solve raises :class:`SolveError` instead of handing back numbers.
"""
from __future__ import annotations

import itertools

import numpy as np
from dolfinx import fem, la
from dolfinx.fem import petsc as fem_petsc

from .post import allsum

__all__ = ["SolveError", "DirectSolver", "IterativeSolver", "make_solver", "mass_solve",
           "reaction_force"]

_ids = itertools.count()

#: Steps of iterative refinement after the LU solve.
REFINEMENT_STEPS = 2
#: A solve whose relative residual ||b - A x|| / ||b|| exceeds this is refused.
MAX_RELATIVE_RESIDUAL = 1e-6


#: Above this many unknowns a one-shot solve orders with METIS (PT-SCOTCH on > 1 rank), below
#: it with AMD (measured break-even at ~760k dofs on this project's test machine).
AMD_LIMIT = 1_000_000


def _ordering(u, one_shot: bool) -> dict:
    """MUMPS's fill-reducing ordering, chosen by how many factorisations will share it and
    by the size. One factorisation (a linear scene) of fewer than AMD_LIMIT unknowns: AMD,
    whose analysis is cheap (measured at 274k dofs: analysis 0.4 s against METIS's 2.1 s,
    numeric factorisation 2.4 s against 1.5 s on one rank; whole process times in the
    README, "Where the time goes"). Several (a nonlinear or staged scene, each iteration a
    numeric factorisation on the same analysis), or a large mesh: METIS's sparser factors
    pay back (1.5M dofs, whole process: 57.6 s against AMD's 65.1 s on one rank, 38.9 s
    against 50.6 s on two); on more than one rank its analysis runs in parallel with
    PT-SCOTCH (solve 3.7 -> 3.2 s on 2 ranks)."""
    functions = u if isinstance(u, (list, tuple)) else [u]
    size = sum(f.function_space.dofmap.index_map.size_global
               * f.function_space.dofmap.index_map_bs for f in functions)
    if one_shot and size < AMD_LIMIT:
        return {"mat_mumps_icntl_28": 1, "mat_mumps_icntl_7": 0}
    if functions[0].function_space.mesh.comm.size == 1:
        return {}
    return {"mat_mumps_icntl_28": 2, "mat_mumps_icntl_29": 1}


class SolveError(RuntimeError):
    """A solve that did not converge; its numbers must not be reported as results. ``history``
    holds the iteration history of a nonlinear solve, when there is one."""

    def __init__(self, message: str, history: list | None = None):
        super().__init__(message)
        self.history = history or []


class _LinearSolver:
    """What both solvers share: their own PETSc options prefix, the count of solves, and the
    size of the assembled system."""

    def _start(self, name: str) -> str:
        self.prefix = f"tankfx_{name}_{next(_ids)}_"
        self.solves = 0   # linear solves so far (each one an assembly and a solve)
        return self.prefix

    @property
    def matrix_size(self) -> int:
        return self.problem.A.getSize()[0]


class DirectSolver(_LinearSolver):
    """MUMPS on the monolithic system ``a u = L`` (blocks assembled with ``kind="mpi"``):
    LU, or for a ``symmetric`` system (every scene but a Mohr-Coulomb interface, whose
    friction couples the shear to the normal jump) the symmetric-indefinite LDL^T, about a
    fifth cheaper. PETSc keeps the symbolic factorisation between solves of the same
    pattern (measured: 2 analyses for 17 numeric factorisations in a nonlinear run)."""

    def __init__(self, a, L, bcs, u, entity_maps=None, name: str = "soil",
                 symmetric: bool = False, one_shot: bool = False):
        self.problem = fem_petsc.LinearProblem(
            a, L, bcs=bcs, u=u, kind="mpi" if isinstance(u, (list, tuple)) else None,
            petsc_options_prefix=self._start(name), entity_maps=entity_maps,
            petsc_options={
                # LU with MUMPS, then two steps of iterative refinement (Richardson on the
                # same factors): they recover the digits a bare LU solve loses to the
                # stiffness contrast of soil, plate, wall and interface penalty. The residual
                # is then at the round-off floor of the matrix-vector product, and is checked.
                "ksp_type": "richardson", "ksp_max_it": REFINEMENT_STEPS,
                "ksp_convergence_test": "skip", "ksp_norm_type": "unpreconditioned",
                "pc_type": "cholesky" if symmetric else "lu",
                "pc_factor_mat_solver_type": "mumps",
                # more working memory for pivoting in stiff, contrasted systems
                "mat_mumps_icntl_14": 80, **_ordering(u, one_shot)})
        self.factorisation = "LDL^T (MUMPS)" if symmetric else "LU (MUMPS)"

    def solve(self):
        self.solves += 1
        u = self.problem.solve()
        ksp = self.problem.solver
        reason = ksp.getConvergedReason()
        x = self.problem.x
        if reason < 0 or not np.isfinite(x.norm()):
            raise SolveError(f"the linear solver failed (PETSc KSP reason {reason}): the "
                             "system is singular (check the supports of the scene) or the "
                             "data overflowed")
        self.relative_residual = _checked_residual(
            self.problem, f"after {REFINEMENT_STEPS} refinement steps: the system is too "
                          f"ill-conditioned for these stiffness contrasts")
        return u


class IterativeSolver(_LinearSolver):
    """Krylov with algebraic multigrid, for meshes where a factorisation costs too much time
    or memory (``[solver] method = "iterative"``). The soil alone: conjugate gradients with
    PETSc's GAMG (Chebyshev-Jacobi smoothing). Soil and structure: the blocks are assembled
    as a PETSc nest and solved by FGMRES with a multiplicative field split: GAMG on the soil
    block (with the interface's soil side), LU (MUMPS) on the small structure block. Each
    solve must reach ``rtol`` within ``max_iterations``; the true residual is then checked
    as for a direct solve. Measured (README): the soil alone beats MUMPS in time from about
    100k dofs and in memory always; with a structure, the penalty coupling costs ~190
    field-split iterations and MUMPS stays faster at the sizes measured."""

    def __init__(self, a, L, bcs, u, entity_maps=None, name: str = "soil", rtol: float = 1e-10,
                 max_iterations: int = 1000):
        blocks = isinstance(u, (list, tuple))
        gamg = {"pc_type": "gamg", "mg_levels_ksp_type": "chebyshev",
                "mg_levels_pc_type": "jacobi"}
        if blocks:
            names = [f.name for f in u]
            opts = {"ksp_type": "fgmres", "ksp_gmres_restart": 200,
                    "pc_type": "fieldsplit", "pc_fieldsplit_type": "multiplicative"}
            for f in u:
                split = f"fieldsplit_{f.name}_"
                opts[split + "ksp_type"] = "preonly"
                if f is u[0]:
                    opts.update({split + k: v for k, v in gamg.items()})
                else:
                    opts.update({split + "pc_type": "lu",
                                 split + "pc_factor_mat_solver_type": "mumps"})
            if len(set(names)) != len(names):
                raise ValueError(f"the blocks' functions need distinct names: {names}")
        else:
            opts = {"ksp_type": "cg", **gamg}
        opts.update({"ksp_rtol": rtol, "ksp_atol": 0.0, "ksp_max_it": max_iterations,
                     "ksp_norm_type": "unpreconditioned"})
        self.problem = fem_petsc.LinearProblem(
            a, L, bcs=bcs, u=u, kind="nest" if blocks else None,
            petsc_options_prefix=self._start(name), entity_maps=entity_maps,
            petsc_options=opts)
        self.factorisation = ("FGMRES + field split (GAMG soil, LU structure)" if blocks
                              else "CG + GAMG")
        self.krylov_iterations = 0
        self.rtol, self.max_iterations = rtol, max_iterations

    def solve(self):
        self.solves += 1
        u = self.problem.solve()
        ksp = self.problem.solver
        reason, its = ksp.getConvergedReason(), ksp.getIterationNumber()
        self.krylov_iterations += its
        x = self.problem.x
        if reason < 0 or not np.isfinite(x.norm()):
            raise SolveError(f"the iterative solver did not reach the relative residual "
                             f"{self.rtol:g} in {its} iterations (PETSc KSP reason {reason}, "
                             f"residual {ksp.getResidualNorm():.3e}); raise "
                             f"solver.max_iterations or use solver.method = \"direct\"")
        self.relative_residual = _checked_residual(self.problem, "(iterative solve)")
        return u


def _checked_residual(problem, why: str) -> float:
    """||b - A x|| / ||b|| of a solved LinearProblem; above MAX_RELATIVE_RESIDUAL the
    numbers are refused (SolveError), never reported."""
    x, b, A = problem.x, problem.b, problem.A
    r = b.duplicate()
    A.mult(x, r)
    r.axpy(-1.0, b)
    bnorm = b.norm()
    rel = r.norm() / bnorm if bnorm > 0 else r.norm()
    r.destroy()
    if rel > MAX_RELATIVE_RESIDUAL:
        raise SolveError(f"the linear solve left a relative residual of {rel:.2e} "
                         f"(> {MAX_RELATIVE_RESIDUAL:g}) {why}")
    return rel


def make_solver(scene, a, L, bcs, u, entity_maps=None, name: str = "tank",
                symmetric: bool = False, one_shot: bool = False):
    """The solver a scene asks for (``[solver] method``); ``one_shot``: a single solve is
    expected (the direct solver's ordering is chosen for it)."""
    if scene.solver.method == "iterative":
        return IterativeSolver(a, L, bcs, u, entity_maps=entity_maps, name=name,
                               rtol=scene.solver.rtol,
                               max_iterations=scene.solver.max_iterations)
    return DirectSolver(a, L, bcs, u, entity_maps=entity_maps, name=name, symmetric=symmetric,
                        one_shot=one_shot)


def mass_solve(a, L, bcs, u, name: str = "projection"):
    """Solve a mass-matrix system (an L2 projection): conjugate gradients with Jacobi, which
    for a mass matrix converge in a few dozen iterations whatever the mesh (the diagonal
    takes out the element sizes and the 2 pi r weight), instead of a factorisation that
    costs as much as the analysis itself (1.4 s of 11 s at 270k dofs)."""
    prefix = f"tankfx_{name.replace(' ', '_')}_{next(_ids)}_"
    problem = fem_petsc.LinearProblem(
        a, L, bcs=bcs, u=u, petsc_options_prefix=prefix,
        petsc_options={"ksp_type": "cg", "pc_type": "jacobi", "ksp_rtol": 1e-12,
                       "ksp_atol": 0.0, "ksp_max_it": 1000})
    problem.solve()
    reason = problem.solver.getConvergedReason()
    if reason < 0 or not np.isfinite(problem.x.norm()):
        raise SolveError(f"the {name} (a mass-matrix solve by CG) did not converge: PETSc "
                         f"reason {reason} after {problem.solver.getIterationNumber()} "
                         f"iterations")
    return u


def reaction_force(residual, V: fem.FunctionSpace, component: int, facets: np.ndarray,
                   entity_maps=None) -> float:
    """Force (N) that the supports on ``facets`` exert on the body in direction ``component``.

    ``residual`` is the linear form ``a(u, v) - L(v)`` of the unconstrained equations of the
    field in ``V`` (test function v): at the constrained dofs it is the support reaction. The
    sum runs over the owned dofs of all ranks; positive means the support pushes the body in
    the +``component`` direction.
    """
    vec = fem.assemble_vector(fem.form(residual, entity_maps=entity_maps))
    vec.scatter_reverse(la.InsertMode.add)
    nodes = fem.locate_dofs_topological(V, V.mesh.topology.dim - 1, facets)
    nodes = nodes[nodes < V.dofmap.index_map.size_local]
    bs = V.dofmap.index_map_bs
    local = vec.array.reshape(-1, bs)[nodes, component].sum()
    return allsum(V.mesh.comm, local)
