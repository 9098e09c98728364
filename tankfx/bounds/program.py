"""A sparse conic program, assembled row block by row block and solved by Clarabel.

    minimise q . x   subject to   A x + s = b,   s in K,

K a product of zero cones (equalities), nonnegative cones and second-order cones
(s_0 >= |s_1..|), in the order the blocks were added. A bound's program is assembled
directly as triplets (a modelling layer is slow at 10^5 variables), and Clarabel's status
becomes words: an engineer never reads a solver's code alone.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..fem.failure import Failure
from ..fem.solvers import SolveError


#: Clarabel's sparse factorisation
SOLVE_METHOD = "qdldl"
#: Clarabel's equilibration passes at most
EQUILIBRATION_PASSES = 50


class ProgramError(SolveError):
    """A conic program that could not be solved, said in words (a SolveError: the run
    fails as any unsolved analysis does, its numbers not reported)."""

    def __init__(self, message: str):
        super().__init__(message, code=Failure.LIMIT_ANALYSIS)


@dataclass
class ConeProgram:
    """Variables are added in named blocks (:meth:`variables`); constraint rows in blocks of
    one cone kind (:meth:`equal`, :meth:`nonnegative`, :meth:`cones`)."""

    n: int = 0
    rows: list = field(default_factory=list)      # (i, j, value) triplet arrays per block
    rhs: list = field(default_factory=list)
    kinds: list = field(default_factory=list)     # ("zero", m) / ("nonneg", m) / ("soc", d, count)
    starts: list = field(default_factory=list)   # the first row of each block
    m: int = 0
    cost: list = field(default_factory=list)     # (indices, coefficients) pairs
    verbose: bool = False

    def variables(self, count: int) -> np.ndarray:
        """``count`` new variables' indices."""
        out = np.arange(self.n, self.n + count)
        self.n += count
        return out

    def _add(self, i, j, v, b, kind) -> None:
        i, j, v = (np.asarray(a).ravel() for a in (i, j, v))
        keep = v != 0.0
        self.starts.append(self.m)
        self.rows.append((i[keep] + self.m, j[keep], v[keep]))
        self.rhs.append(np.asarray(b, dtype=float).ravel())
        self.kinds.append(kind)
        self.m += len(self.rhs[-1])

    def equal(self, i, j, v, b) -> None:
        """Rows sum_j v x_j = b (``i`` the row within this block)."""
        self._add(i, j, v, b, ("zero", len(np.ravel(b))))

    def nonnegative(self, i, j, v, b) -> None:
        """Rows sum_j v x_j <= b."""
        self._add(i, j, v, b, ("nonneg", len(np.ravel(b))))

    def cones(self, i, j, v, b, dim: int) -> None:
        """Consecutive ``dim``-row groups each in the second-order cone: s = b - A x with
        s_0 >= |(s_1, .., s_dim-1)|."""
        count = len(np.ravel(b)) // dim
        self._add(i, j, v, b, ("soc", dim, count))

    def minimise(self, j, v) -> None:
        """Add sum v x_j to the objective."""
        j, v = np.broadcast_arrays(np.ravel(j), np.ravel(v))
        self.cost.append((j.astype(np.int64), v.astype(float)))

    def equality_residual(self, x: np.ndarray) -> float:
        """The largest residual of the equality rows at ``x``, relative to the largest term
        in any of them."""
        worst, size = 0.0, 1e-300
        for (i, j, v), b, kind, start in zip(self.rows, self.rhs, self.kinds, self.starts):
            if kind[0] != "zero" or not len(b):
                continue
            res = np.bincount(i - start, weights=v * x[j], minlength=len(b)) - b
            worst = max(worst, float(np.max(np.abs(res))))
            size = max(size, float(np.max(np.abs(v * x[j]), initial=0.0)),
                       float(np.max(np.abs(b))))
        return worst / size

    def solve(self, what: str, tolerance: float = 1e-8, log=None) -> "Solved":
        """Solve with Clarabel; a ProgramError in words where it is not solved."""
        import clarabel
        from scipy import sparse

        i = np.concatenate([r[0] for r in self.rows])
        j = np.concatenate([r[1] for r in self.rows])
        v = np.concatenate([r[2] for r in self.rows])
        A = sparse.csc_matrix((v, (i, j)), shape=(self.m, self.n))
        b = np.concatenate(self.rhs)
        q = np.zeros(self.n)
        for jj, vv in self.cost:
            np.add.at(q, jj, vv)
        P = sparse.csc_matrix((self.n, self.n))
        cones = []
        for kind in self.kinds:
            if kind[0] == "zero":
                cones.append(clarabel.ZeroConeT(kind[1]))
            elif kind[0] == "nonneg":
                cones.append(clarabel.NonnegativeConeT(kind[1]))
            else:
                cones += [clarabel.SecondOrderConeT(kind[1])] * kind[2]
        settings = clarabel.DefaultSettings()
        settings.verbose = bool(self.verbose)
        settings.tol_gap_abs = settings.tol_gap_rel = tolerance
        settings.tol_feas = tolerance
        settings.max_iter = 200
        # (Ruiz equilibration to convergence, not Clarabel's 10 passes: the lower bound's
        # rows mix triangles of 1e-3 and 1 a^2 with the far field's; measured on a c-phi
        # footing with weight: AlmostSolved, duality gaps to 1.6e-5 and lower bounds 0.1 %
        # apart between units, against Solved to 5e-9)
        settings.equilibrate_max_iter = EQUILIBRATION_PASSES
        settings.direct_solve_method = SOLVE_METHOD
        t0 = time.perf_counter()
        sol = clarabel.DefaultSolver(P, q, A, b, cones, settings).solve()
        seconds = time.perf_counter() - t0
        status = str(sol.status).split(".")[-1]
        # (a bound holds at any admissible field, optimal or not: a solve that stopped
        # early is returned, and the bound recomputes its field, checks it and keeps it only
        # where it is admissible; its status and duality gap are recorded)
        stopped = status in ("NumericalError", "InsufficientProgress", "MaxIterations") and \
            np.all(np.isfinite(sol.x))
        if status not in ("Solved", "AlmostSolved") and not stopped:
            raise ProgramError(_words(status, what))
        gap = abs(sol.obj_val - sol.obj_val_dual) / max(abs(sol.obj_val), 1e-300)
        return Solved(x=np.asarray(sol.x), s=np.asarray(sol.s), z=np.asarray(sol.z),
                      objective=float(sol.obj_val), status=status, iterations=sol.iterations,
                      seconds=seconds, variables=self.n, rows=self.m, duality_gap=gap,
                      primal_residual=float(sol.r_prim), dual_residual=float(sol.r_dual))

    @staticmethod
    def words(status: str, what: str) -> str:
        return _words(status, what)


@dataclass(frozen=True)
class Solved:
    x: np.ndarray
    s: np.ndarray
    z: np.ndarray
    objective: float
    status: str
    iterations: int
    seconds: float
    variables: int
    rows: int
    #: |primal - dual| / |primal| objective: how far from optimal (not from feasible)
    duality_gap: float
    primal_residual: float
    dual_residual: float

    def record(self) -> dict:
        """What results.json keeps of the solve."""
        return {"status": self.status, "iterations": self.iterations,
                "duality_gap": self.duality_gap, "primal_residual": self.primal_residual,
                "dual_residual": self.dual_residual}


def _words(status: str, what: str) -> str:
    if status in ("DualInfeasible", "AlmostDualInfeasible"):
        return (f"{what}: unbounded (the conic solver's status {status}): no load makes the "
                f"ground fail: a soil that cannot fail (no cohesion and no friction "
                f"resisting it) or a load that only lifts the foundation")
    if status in ("PrimalInfeasible", "AlmostPrimalInfeasible"):
        return (f"{what}: infeasible (the conic solver's status {status}): the soil cannot "
                f"carry even the held loads (the self-weight) with no variable load")
    return (f"{what}: the conic solver stopped with status {status} before its tolerance "
            f"(numerical trouble: try a coarser or finer mesh)")
