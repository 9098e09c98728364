"""Linear solves of the (block) system with a direct solver, and the reactions they imply.

Every solver gets its own PETSc options prefix (no global options), and a failed or non-finite
solve raises :class:`SolveError` instead of handing back numbers.
"""
from __future__ import annotations

import itertools

import numpy as np
from dolfinx import fem, la
from dolfinx.fem import petsc as fem_petsc

from .failure import Failure
from petsc4py import PETSc

from .evaluate import allsum
from .memory import keep_freed_memory
from .threads import limit_blas_threads
from .timing import timed

_ids = itertools.count()


#: What a solve re-assembles (``results["linear_solver"]["assembly"]``).
WHOLE_ASSEMBLY = "the whole system at every solve"


SPLIT_ASSEMBLY = ("the fixed part once; at every solve only what changes (a Mohr-Coulomb "
                  "interface's states, a consolidation's flow terms)")


KEPT_ASSEMBLY = "once, factorised once: every load stage has the same matrix"


#: Steps of iterative refinement after the LU solve.
REFINEMENT_STEPS = 2


#: A solve whose relative residual ||b - A x|| / ||b|| exceeds this is refused.
MAX_RELATIVE_RESIDUAL = 1e-6


#: MUMPS's row and column scaling (``results["linear_solver"]["scaling"]``).
AUTOMATIC_SCALING = "MUMPS's automatic scaling"


NO_SCALING = "none (iterative refinement recovers the digits)"


RESCALED = "MUMPS's automatic scaling, after an unscaled factorisation failed"


#: Repeated factorisations (nonlinear and Mohr-Coulomb iterations) skip MUMPS's scaling
#: (DirectSolver); False scales every factorisation.
UNSCALED_REFACTORISATIONS = True


#: Above this many unknowns a one-shot solve orders with METIS (PT-SCOTCH on > 1 rank), below
#: it with AMD (measured break-even at ~760k dofs on this project's test machine).
AMD_LIMIT = 1_000_000


#: GAMG's graph threshold: edges weaker than this are dropped before aggregation, so the
#: aggregates follow the strong couplings of the graded mesh and of the interface. Measured
#: (2026-11-22, rtol 1e-10): P3 flexible load at 272k dofs 89 -> 59 CG iterations (8.0 ->
#: 6.4 s; 0.1: 43 iterations but 9.7 s, denser coarse levels); embedded tank at 494k dofs
#: 80 -> 45 Krylov iterations (15.3 -> 11.3 s).
GAMG_THRESHOLD = 0.05


def _ordering(u, one_shot: bool) -> dict:
    """MUMPS's fill-reducing ordering, chosen by how many factorisations will share it and
    by the size. One factorisation (a linear scene) of fewer than AMD_LIMIT unknowns: AMD,
    whose analysis is cheap (measured at 274k dofs: analysis 0.4 s against METIS's 2.1 s,
    numeric factorisation 2.4 s against 1.5 s on one rank; whole process times in
    docs/development/performance-record.md). Several (a nonlinear or staged scene, each iteration a
    numeric factorisation on the same analysis): METIS, whose sparser factors pay back, with
    its analysis on one rank whatever the number of ranks: PT-SCOTCH's parallel analysis is
    faster (on 2 ranks, 274k / 755k dofs: 1.7 / 4.9 s against 2.1 / 6.5 s) but its ordering
    costs more flops in every factorisation (LU: 22.2 / 99.8 against 18.2 / 93.5 GFlop),
    which a nonlinear tank pays ~13 times (274k on 2 ranks: its 13 numeric factorisations
    13.9-14.3 s -> median 12.6 s of 10 runs (10.4-13.3), the whole run 25.6-26.0 s -> median
    24.6 s). One large factorisation (a linear scene of AMD_LIMIT unknowns or more):
    METIS's sparser factors pay back too (1.5M dofs, whole process: 57.6 s against AMD's
    65.1 s on one rank, 38.9 s against 50.6 s on two), and on more than one rank its
    analysis runs in parallel with PT-SCOTCH (solve 3.7 -> 3.2 s on 2 ranks)."""
    functions = u if isinstance(u, (list, tuple)) else [u]
    size = sum(f.function_space.dofmap.index_map.size_global
               * f.function_space.dofmap.index_map_bs for f in functions)
    if one_shot and size < AMD_LIMIT:
        return {"mat_mumps_icntl_28": 1, "mat_mumps_icntl_7": 0}
    if not one_shot or functions[0].function_space.mesh.comm.size == 1:
        return {"mat_mumps_icntl_28": 1, "mat_mumps_icntl_7": 5}      # METIS, on one rank
    return {"mat_mumps_icntl_28": 2, "mat_mumps_icntl_29": 1}


class SolveError(RuntimeError):
    """A solve that did not converge: its numbers must not be reported as results.

    Attributes
    ----------
    history : list
        The iteration history of a nonlinear solve up to the failure (empty when there is
        none).
    code : str
        What failed, for a program to act on (the message says it for a person):
        ``Failure.LINEAR_SOLVE`` unless the iteration that raised it says more
        (:class:`tankfx.fem.failure.Failure`).
    """

    def __init__(self, message: str, history: list | None = None,
                 code: str = Failure.LINEAR_SOLVE):
        super().__init__(message)
        self.history = history or []
        self.code = code
        #: what converged before the failure, as results.json's entries of the failed
        #: analysis (set by the layer that knows it: the load carried, a collapse search, a
        #: load path's converged stages): a failed solve keeps what converged
        self.kept: dict = {}
        #: the unknowns of the system that failed (set by the analysis), or None
        self.dofs: int | None = None


class _LinearSolver:
    """What both solvers share: their own PETSc options prefix, the count of solves, and the
    size of the assembled system."""

    #: MUMPS's scaling (direct solver; None for the iterative one)
    scaling: str | None = None
    #: the residual checked relative to the largest right-hand side solved so far, not the
    #: current one (a consolidation: a step of no load still has the pore water's volume
    #: terms, tiny beside the forces whose round-off the residual then carries)
    relative_to_largest_load: bool = False
    reference_norm: float = 0.0

    def _start(self, name: str) -> str:
        self.prefix = f"tankfx_{name}_{next(_ids)}_"
        self.solves = 0   # linear solves so far (each one an assembly and a solve)
        self._matrix_kept = False
        return self.prefix

    def keep_matrix(self) -> None:
        """The matrix will not change any more (the next load stages of a linear soil under
        a bonded or smooth interface): the direct solver then assembles only the right-hand
        side and reuses its factorisation. (The iterative solver re-assembles, and rebuilds
        its preconditioner only if PETSc sees a changed matrix.)"""
        self._matrix_kept = True

    def solve_again(self):
        """Solve for the current right-hand side with the matrix of the last solve (its
        factorisation kept: a second load on the same system, as a settlement-controlled
        step needs)."""
        return self.solve()

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
                 symmetric: bool = False, one_shot: bool = False, split=None,
                 scaled: bool | None = None, correction: bool = False):
        # (``scaled``: MUMPS's scaling; by default for a single factorisation only)
        unscaled = (UNSCALED_REFACTORISATIONS and not one_shot) if scaled is None \
            else not scaled
        self._options = {
            # LU with MUMPS, then two steps of iterative refinement (Richardson on the
            # same factors): they recover the digits a bare LU solve loses to the
            # stiffness contrast of soil, plate, wall and interface penalty. The residual
            # is then at the round-off floor of the matrix-vector product, and is checked.
            "ksp_type": "richardson", "ksp_max_it": REFINEMENT_STEPS,
            "ksp_convergence_test": "skip", "ksp_norm_type": "unpreconditioned",
            "pc_type": "cholesky" if symmetric else "lu",
            "pc_factor_mat_solver_type": "mumps",
            # more working memory for pivoting in stiff, contrasted systems
            "mat_mumps_icntl_14": 80, **_ordering(u, one_shot),
            **({"mat_mumps_icntl_8": 0} if unscaled else {})}
        self.problem = fem_petsc.LinearProblem(
            a, L, bcs=bcs, u=u, kind="mpi" if isinstance(u, (list, tuple)) else None,
            petsc_options_prefix=self._start(name), entity_maps=entity_maps,
            petsc_options=self._options)
        self.factorisation = "LDL^T (MUMPS)" if symmetric else "LU (MUMPS)"
        # Repeated factorisations (a nonlinear or Mohr-Coulomb iteration) skip MUMPS's
        # scaling: it is recomputed at every numeric factorisation and does not scale over
        # ranks (nonlinear tank, 274k dofs, its 13 numeric factorisations: 17.2-18.6 ->
        # 15.2-16.7 s on one rank, 12.1-12.2 -> 8.8-11.2 s on two, over two batches;
        # docs/development/performance-record.md), while the two refinement steps bring
        # the residual to the same floor (2.6e-8 against 2.2-2.7e-8; w0 to 1e-9). A
        # factorisation that fails unscaled (a saddle-point system of a nearly
        # incompressible soil) is redone scaled, and the solver stays scaled (see
        # _rescale). A single factorisation keeps the scaling: it is paid once there.
        self.scaling = NO_SCALING if unscaled else AUTOMATIC_SCALING
        # (fixed, varying): block forms that sum to ``a``, of which only ``varying`` changes
        # between solves; the fixed part is then assembled once and copied
        self._split = None if split is None else tuple(
            fem.form(forms, entity_maps=entity_maps) for forms in split)
        self._fixed_matrix = None
        #: the fields' values the last solve started from (its x_k)
        self._start = None
        #: each solve a correction of the fields' values (see _solve_assembled): Newton's
        #: systems, whose right-hand side holds the whole state's forces. (Not the others':
        #: a floating structure's singular system under no load keeps the null space's share
        #: of the fields' values then, where a solve from nothing has none: measured, a
        #: Mohr-Coulomb interface restarted from stuck states at t = 0 then found itself
        #: separated everywhere)
        self.correction = correction

    @property
    def assembly(self) -> str:
        """What a solve re-assembles (see :meth:`solve`)."""
        if self._matrix_kept and self.solves > 1:
            return KEPT_ASSEMBLY
        return SPLIT_ASSEMBLY if self._split else WHOLE_ASSEMBLY

    def _assemble_split(self):
        """A = fixed + varying, with the fixed part assembled at the first solve only. Both
        parts skip the supports' rows and columns and set their diagonal to 1 (an insertion,
        so the sum keeps 1)."""
        p, (fixed, varying) = self.problem, self._split
        if self._fixed_matrix is None:
            # the whole assembled once, so that its copy keeps every entry of the pattern
            # (an assembly compresses out the entries it did not reach)
            p.A.zeroEntries()
            fem_petsc.assemble_matrix(p.A, p.a, bcs=p.bcs)
            p.A.assemble()
            self._fixed_matrix = p.A.duplicate()
            self._fixed_matrix.zeroEntries()
            fem_petsc.assemble_matrix(self._fixed_matrix, fixed, bcs=p.bcs)
            self._fixed_matrix.assemble()
        self._fixed_matrix.copy(p.A, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
        fem_petsc.assemble_matrix(p.A, varying, bcs=p.bcs)
        p.A.assemble()

    def _solve_keeping(self, assemble_matrix):
        """LinearProblem.solve with the matrix assembled by ``assemble_matrix`` (or, None,
        left as it is: PETSc then keeps its factorisation)."""
        p = self.problem
        with timed("assembly"):
            if assemble_matrix is not None:
                assemble_matrix()
            with p.b.localForm() as b:
                b.set(0.0)
            fem_petsc.assemble_vector(p.b, p.L)
            if isinstance(p.u, (list, tuple)):                     # blocks, kind="mpi"
                spaces = fem.extract_function_spaces(p.a, 1)
                fem_petsc.apply_lifting(p.b, p.a, bcs=fem.bcs_by_block(spaces, p.bcs))
                p.b.ghostUpdate(PETSc.InsertMode.ADD, PETSc.ScatterMode.REVERSE)
                fem_petsc.set_bc(p.b, fem.bcs_by_block(fem.extract_function_spaces(p.L),
                                                       p.bcs))
            else:
                fem_petsc.apply_lifting(p.b, [p.a], bcs=[p.bcs])
                p.b.ghostUpdate(PETSc.InsertMode.ADD, PETSc.ScatterMode.REVERSE)
                fem_petsc.set_bc(p.b, p.bcs)
        return self._solve_assembled()

    def _assemble_whole(self):
        """A assembled whole (the supports' rows and columns skipped, their diagonal 1)."""
        p = self.problem
        p.A.zeroEntries()
        fem_petsc.assemble_matrix(p.A, p.a, bcs=p.bcs)
        p.A.assemble()

    def _start_from_fields(self, again: bool) -> bool:
        """x_k into the solution vector: the fields' values now, kept for a solve redone
        (``again``: the last one's). Whether it is not zero. Collective."""
        p = self.problem
        if again:
            self._start.copy(p.x)
        else:
            fem_petsc.assign(p.u, p.x)
            if self._start is None:
                self._start = p.x.duplicate()
            p.x.copy(self._start)
        return p.x.norm() > 0.0

    def _solve_assembled(self, again: bool = False):
        """Solve the assembled system for the assembled right-hand side into ``u`` (with
        ``correction``: as a correction of the fields' values now, x_k: A dx = b - A x_k,
        x = x_k + dx). It is
        the same solution, but the factorisation's relative error falls on the
        correction's right-hand side instead of the whole load's: a Newton iteration on
        this system (whose b holds the whole state's forces) then reduces its
        out-of-balance force below the 1e-8 of the load vector that a solve for the whole
        state leaves (the refinement steps' floor). ``again``: from the same x_k as the last
        solve (a factorisation redone: the fields hold the failed one's result)."""
        p = self.problem
        try:
            # (the factorisation where the matrix changed, timed apart from the solves)
            with timed("factorisation"):
                p.solver.getPC().setUp()
            if self.correction and self._start_from_fields(again):
                r, dx = p.b.duplicate(), p.x.duplicate()
                p.A.mult(p.x, r)
                r.aypx(-1.0, p.b)
                with timed("solve"):
                    p.solver.solve(r, dx)
                p.x.axpy(1.0, dx)
                r.destroy()
                dx.destroy()
            else:
                with timed("solve"):
                    p.solver.solve(p.b, p.x)
        except PETSc.Error as e:
            # (MUMPS refusing a solve after a factorisation it could not complete: a
            # SolveError, which the iterations know how to take)
            raise SolveError(f"the linear solver failed (PETSc error {e.ierr}: the "
                             f"factorisation of a singular or ill-conditioned system)") from e
        p.x.ghostUpdate(PETSc.InsertMode.INSERT, PETSc.ScatterMode.FORWARD)
        fem_petsc.assign(p.x, p.u)
        return p.u

    def solve(self):
        self.solves += 1
        if self._matrix_kept and self.solves > 1:
            u = self._solve_keeping(None)
        elif self._split:
            u = self._solve_keeping(self._assemble_split)
        else:
            u = self._solve_keeping(self._assemble_whole)
        if self.scaling == NO_SCALING:
            try:
                self.relative_residual = self._checked()
                return u
            except SolveError:
                u = self._rescale()
        self.relative_residual = self._checked()
        return u

    def solve_again(self):
        """Solve for the current right-hand side with the last solve's matrix and its
        factorisation (only the right-hand side is assembled)."""
        self.solves += 1
        u = self._solve_keeping(None)
        self.relative_residual = self._checked()
        return u

    def _checked(self) -> float:
        """The relative residual of the last solve; SolveError if it failed."""
        reason = self.problem.solver.getConvergedReason()
        if reason < 0 or not np.isfinite(self.problem.x.norm()):
            raise SolveError(f"the linear solver failed (PETSc KSP reason {reason}): the "
                             "system is singular (check the supports of the scene) or the "
                             "data overflowed")
        rel = _checked_residual(
            self.problem, f"after {REFINEMENT_STEPS} refinement steps: the system is too "
                          f"ill-conditioned for these stiffness contrasts",
            self.reference_norm if self.relative_to_largest_load else 0.0)
        self.reference_norm = max(self.reference_norm, self.problem.b.norm())
        return rel

    def _rescale(self):
        """Factorise the same matrix again with MUMPS's scaling, solve the same right-hand
        side, and keep the scaling for the solves to come."""
        p = self.problem
        self.scaling = RESCALED
        # a MUMPS instance whose numeric factorisation failed refuses the next ones: a new
        # one (analysis included) with the same options but the scaling
        self._options = {**self._options, "mat_mumps_icntl_8": 77}
        opts = PETSc.Options()
        opts.prefixPush(self.prefix)
        for key, value in self._options.items():
            opts[key] = value
        opts.prefixPop()
        p.solver.getPC().reset()          # (which forgets the operator too)
        p.solver.setOperators(p.A)
        p.solver.setFromOptions()
        for key in self._options:
            del opts[self.prefix + key]
        return self._solve_assembled(again=True)


def _dense_rows(csr, row_numbers, rows, cols) -> np.ndarray:
    """A PETSc matrix's owned rows (``csr`` from getValuesCSR, global numbers
    ``row_numbers``) restricted to the sorted global ``rows`` x ``cols``, as a dense array
    (zeros where the matrix has none)."""
    ip, jp, vp = csr
    r = np.repeat(row_numbers, np.diff(ip))
    keep = np.isin(r, rows) & np.isin(jp, cols)
    out = np.zeros((len(rows), len(cols)))
    np.add.at(out, (np.searchsorted(rows, r[keep]), np.searchsorted(cols, jp[keep])),
              vp[keep])
    return out


class StructureSchur:
    """Preconditioner of the soil + structure block system [[A_ss, A_sp], [A_ps, A_pp]]
    (a PETSc nest; a petsc4py "python" PC): the structure is condensed exactly, and GAMG
    works on the soil's Schur complement S = A_ss - A_sp A_pp^-1 A_ps.

    The structure has a few thousand dofs at most and touches the soil only on the interface,
    so A_pp is factorised whole on every rank and S differs from A_ss only in a dense block on
    the interface's soil dofs. Each application is the block factorisation: y_p = A_pp^-1
    b_p, y_s = GAMG(S)(b_s - A_sp y_p), y_p = A_pp^-1 (b_p - A_ps y_s). The stiff interface
    penalty, which made a field split of the two blocks take ~300 Krylov iterations, is
    then inside S (measured on the embedded tank: 40-50 iterations at 149k-494k dofs)."""

    def setUp(self, pc):
        self._release(keep_multigrid=True)   # a new operator (the next solve of an iteration)
        A = pc.getOperators()[0]
        comm = A.getComm().tompi4py()
        A_ss, A_sp = A.getNestSubMatrix(0, 0), A.getNestSubMatrix(0, 1)
        A_ps, A_pp = A.getNestSubMatrix(1, 0), A.getNestSubMatrix(1, 1)
        self.blocks = (A_sp, A_ps)
        self.comm = comm
        n_p = A_pp.getSize()[0]
        self.p_range = A_pp.getOwnershipRange()
        # the structure block, whole on every rank, factorised there (its dense inverse
        # would need threaded BLAS calls, which fight the other ranks for the cores)
        rows = np.arange(*self.p_range)
        ip, jp, vp = A_pp.getValuesCSR()
        lengths = np.concatenate(comm.allgather(np.diff(ip)))
        csr = (np.concatenate([[0], np.cumsum(lengths)]).astype(PETSc.IntType),
               np.concatenate(comm.allgather(jp)).astype(PETSc.IntType),
               np.concatenate(comm.allgather(vp)))
        self.A_pp = PETSc.Mat().createAIJ((n_p, n_p), csr=csr, comm=PETSc.COMM_SELF)
        self.lu = PETSc.KSP().create(comm=PETSc.COMM_SELF)
        self.lu.setOperators(self.A_pp)
        self.lu.setType("preonly")
        self.lu.getPC().setType("lu")
        # (MUMPS: the mixed shell element's shear unknowns leave zeros on the diagonal)
        self.lu.getPC().setFactorSolverType("mumps")
        self.lu.setUp()
        self.b_p, self.x_p = self.A_pp.createVecs()
        # the interface's soil dofs: the soil columns of A_ps (global numbers)
        csr_ps = A_ps.getValuesCSR()
        iface = np.unique(np.concatenate(comm.allgather(np.unique(csr_ps[1]))))
        coupling = comm.allreduce(                            # A_ps[:, iface], dense
            _dense_rows(csr_ps, rows, np.arange(n_p), iface))
        # this rank's rows of the correction A_sp A_pp^-1 A_ps, on its interface rows
        s0, s1 = A_ss.getOwnershipRange()
        mine = iface[(iface >= s0) & (iface < s1)]
        left = _dense_rows(A_sp.getValuesCSR(), np.arange(s0, s1), mine, np.arange(n_p))
        B = PETSc.Mat().createDense((n_p, len(iface)), array=coupling, comm=PETSc.COMM_SELF)
        X = PETSc.Mat().createDense((n_p, len(iface)), comm=PETSc.COMM_SELF)
        X.setUp()
        self.lu.getPC().getFactorMatrix().matSolve(B, X)
        if len(mine):
            Lm = PETSc.Mat().createDense((len(mine), n_p), array=left, comm=PETSc.COMM_SELF)
            correction = Lm.matMult(X).getDenseArray().copy()
            Lm.destroy()
        else:
            correction = np.zeros((0, len(iface)))
        for m in (B, X):
            m.destroy()
        nnz = np.zeros(s1 - s0, dtype=PETSc.IntType)
        nnz[mine - s0] = len(iface)
        C = PETSc.Mat().createAIJ(A_ss.getSizes(), nnz=(nnz, nnz), comm=A_ss.getComm())
        C.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
        C.setValues(mine.astype(PETSc.IntType), iface.astype(PETSc.IntType),
                    -correction.ravel())
        C.assemble()
        S = A_ss.duplicate(copy=True)
        S.axpy(1.0, C, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        if self.gamg is not None and np.array_equal(iface, self._iface):
            # The next solve of a nonlinear iteration: S has the last one's pattern (the
            # same interface dofs), so GAMG keeps its interpolation and only recomputes its
            # coarse operators (bonded hyperbolic tank at 494k dofs: 79.8 -> 64.7 s for 7
            # solves, 300 -> 301 iterations). The interpolation thus comes from the first
            # solve, where every interface element sticks (the Mohr-Coulomb iteration's
            # start) and S is symmetric; rebuilt on the unsymmetric S of a slipping
            # interface it took 2.5-4 x the iterations (nonlinear demo tank: 236 against 57
            # a solve, 84 against 25 s)
            S.copy(self.S, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
            S.destroy()
        else:
            for old in (self.gamg, self.S):
                if old is not None:
                    old.destroy()
            self.S, self._iface = S, iface
            # GAMG with its default smoother (Chebyshev-Jacobi) and the soil's threshold
            self.gamg = PETSc.PC().create(comm=A_ss.getComm())
            self.gamg.setType("gamg")
            prefix = f"{pc.getOptionsPrefix() or ''}schur_"
            self.gamg.setOptionsPrefix(prefix)
            options = PETSc.Options()
            values = {"pc_gamg_threshold": GAMG_THRESHOLD, "pc_gamg_reuse_interpolation": True}
            for key, value in values.items():
                options.setValue(prefix + key, value)
            self.gamg.setOperators(self.S)
            self.gamg.setFromOptions()
            for key in values:
                options.delValue(prefix + key)
        self.gamg.setUp()
        # work vectors of apply()
        self.r_s, self.t_p = A_ss.createVecLeft(), A_ps.createVecLeft()

    gamg = S = _iface = None

    def _release(self, keep_multigrid: bool = False):
        """Free the PETSc objects; ``keep_multigrid``: all but GAMG and its operator S."""
        for name in ("gamg", "S", "lu", "A_pp", "b_p", "x_p", "r_s", "t_p"):
            obj = getattr(self, name, None)
            if obj is not None and not (keep_multigrid and name in ("gamg", "S")):
                obj.destroy()
                setattr(self, name, None)

    def destroy(self, pc):
        self._release()

    def _structure_solve(self, local):
        """A_pp^-1 b for b given by its owned part on each rank; returns the owned part."""
        self.b_p.setArray(np.concatenate(self.comm.allgather(local)))
        self.lu.solve(self.b_p, self.x_p)
        return self.x_p.getArray()[self.p_range[0]: self.p_range[1]].copy()

    def apply(self, pc, x, y):
        A_sp, A_ps = self.blocks
        x_s, x_p = x.getNestSubVecs()
        y_s, y_p = y.getNestSubVecs()
        b_p = x_p.getArray().copy()
        y_p.setArray(self._structure_solve(b_p))
        A_sp.mult(y_p, self.r_s)
        self.r_s.aypx(-1.0, x_s)                             # b_s - A_sp y_p
        self.gamg.apply(self.r_s, y_s)
        A_ps.mult(y_s, self.t_p)
        y_p.setArray(self._structure_solve(b_p - self.t_p.getArray()))


class IterativeSolver(_LinearSolver):
    """Krylov with algebraic multigrid, for meshes where a factorisation costs too much time
    or memory (``[solver] method = "iterative"``). The soil alone: conjugate gradients with
    PETSc's GAMG (Chebyshev-Jacobi smoothing). Soil and structure: the blocks are assembled
    as a PETSc nest and solved by GMRES, right-preconditioned by :class:`StructureSchur` (the
    structure condensed exactly, GAMG on the soil's Schur complement). Each solve must
    reach ``rtol`` within ``max_iterations``; the true residual is then checked as for a
    direct solve. Measured: docs/performance.md,
    "Direct and iterative solvers"."""

    assembly = WHOLE_ASSEMBLY

    def __init__(self, a, L, bcs, u, entity_maps=None, name: str = "soil", rtol: float = 1e-10,
                 max_iterations: int = 1000):
        blocks = isinstance(u, (list, tuple))
        gamg = {"pc_type": "gamg", "mg_levels_ksp_type": "chebyshev",
                "mg_levels_pc_type": "jacobi", "pc_gamg_threshold": GAMG_THRESHOLD}
        if blocks:
            if len(u) != 2:
                # (the scene refuses an iterative solve of the mixed (u, p) soil)
                raise ValueError("the iterative solver takes the soil displacement and the "
                                 f"structure, not {len(u)} blocks")
            # soil displacement + structure: the structure condensed exactly, GAMG on the
            # soil's Schur complement (StructureSchur). That preconditioner is one fixed
            # linear operator (exact structure solves, GAMG with its Chebyshev bounds fixed
            # at set-up), so plain GMRES serves, preconditioned on the right (its residual
            # is the true one): it keeps one basis where FGMRES keeps two (494k dofs:
            # 1.34 -> 1.00 GB, the same iterations).
            opts = {"ksp_type": "gmres", "ksp_pc_side": "right", "ksp_gmres_restart": 200,
                    "pc_type": "python", "pc_python_type": f"{__name__}.StructureSchur"}
        else:
            opts = {"ksp_type": "cg", **gamg}
        opts.update({"ksp_rtol": rtol, "ksp_atol": 0.0, "ksp_max_it": max_iterations,
                     "ksp_norm_type": "unpreconditioned"})
        self.problem = fem_petsc.LinearProblem(
            a, L, bcs=bcs, u=u, kind="nest" if blocks else None,
            petsc_options_prefix=self._start(name), entity_maps=entity_maps,
            petsc_options=opts)
        self.factorisation = ("GMRES + structure condensed, GAMG on the soil's Schur "
                              "complement" if blocks else "CG + GAMG")
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


def _checked_residual(problem, why: str, reference: float = 0.0) -> float:
    """||b - A x|| / ||b|| of a solved LinearProblem (or relative to ``reference``, where
    that is larger); above MAX_RELATIVE_RESIDUAL the numbers are refused (SolveError),
    never reported."""
    x, b, A = problem.x, problem.b, problem.A
    r = b.duplicate()
    A.mult(x, r)
    r.axpy(-1.0, b)
    bnorm = max(b.norm(), reference)
    rel = r.norm() / bnorm if bnorm > 0 else r.norm()
    r.destroy()
    if rel > MAX_RELATIVE_RESIDUAL:
        raise SolveError(f"the linear solve left a relative residual of {rel:.2e} "
                         f"(> {MAX_RELATIVE_RESIDUAL:g}) {why}")
    return rel


def make_solver(options, a, L, bcs, u, entity_maps=None, name: str = "tank",
                symmetric: bool = False, one_shot: bool = False, split=None,
                correction: bool = False):
    """The solver ``options`` ask for: its ``method`` ("direct" or "iterative") and, for an
    iterative one, ``rtol`` and ``max_iterations`` (a scene's [solver] section);
    ``one_shot``: a single factorisation is expected, shared by all solves (the direct
    solver's ordering is chosen for it); ``split``: (fixed, varying) block forms summing to
    ``a``, the fixed part assembled once by the direct solver."""
    keep_freed_memory()        # factorisations reuse the pages of the last one (memory)
    limit_blas_threads()       # numpy's BLAS threads leave the cores to the ranks (threads)
    if options.method == "iterative":
        return IterativeSolver(a, L, bcs, u, entity_maps=entity_maps, name=name,
                               rtol=options.rtol, max_iterations=options.max_iterations)
    return DirectSolver(a, L, bcs, u, entity_maps=entity_maps, name=name, symmetric=symmetric,
                        one_shot=one_shot, split=split, correction=correction)


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
