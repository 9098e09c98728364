"""Newton's method on the elastoplastic soil, from its committed state: the one solve every
driver of the soil's nonlinear response uses (the load steps of a stage,
:mod:`tankfx.iterations.load_steps`; the pit's excavation, :mod:`tankfx.iterations.excavation`;
the settlement-controlled continuation, :mod:`tankfx.iterations.continuation`; the collapse
searches, :mod:`tankfx.iterations.collapse`).

Each Newton iteration solves the block system with the current tangent (``inner()``: the
linear solve, :class:`tankfx.model.plastic.PlasticState` puts the tangent and the stress into
the soil's forms), updates the stress at every quadrature point from the committed state
(the point law's ``update``), and measures the out-of-balance force of the updated state; a
step that raises it is shortened by a backtracking line search.
"""
from __future__ import annotations

import logging
import math
from typing import NamedTuple

import numpy as np
from mpi4py import MPI

from ..fem.blocks import cell_field
from ..fem.evaluate import evaluate_at
from ..fem.solvers import SolveError
from ..fem.timing import timed


class Solve(NamedTuple):
    """How one Newton solve ended: converged, its iterations, the last out-of-balance force
    (its largest block's, relative to that block's tolerance: <= 1 converged), and why not
    (empty where it converged)."""

    converged: bool
    iterations: int
    out_of_balance: float
    reason: str


#: a block's out-of-balance vector is solved at this share of its own at the solve's start:
#: the step's own change of load and flux, which a small step cannot hide behind
#: (docs/theory/plasticity.md, "Newton's convergence test")
STEP_SHARE = 1e-8
#: or at the round-off of its largest term (the terms of a block cancel in balance: a
#: block the step does not load, the flow's at an undrained step)
ROUND_OFF = 1e-12


def criterion_words() -> str:
    """The convergence test in words (a results record's ``criterion``)."""
    return (f"every block (equilibrium, flow, structure) to {STEP_SHARE:g} of its own "
            f"out-of-balance at the solve's start or {ROUND_OFF:g} of its largest term")


class Balance:
    """The convergence test of one Newton solve, block by block (the soil's equilibrium,
    its flow, the structure's), each in its own units: a block is solved where its
    out-of-balance vector is at most STEP_SHARE of its own at the start of the solve, or
    ROUND_OFF of its largest term. :meth:`ratio` is the largest block's share of its
    tolerance (converged at <= 1); :meth:`merit`, what the line search lowers, their
    root sum of squares."""

    def __init__(self, model):
        self.model = model
        self.names, self.start, _ = model.block_residuals()
        self.residual = self.start

    def measure(self) -> float:
        """The blocks' out-of-balance now (collective); returns the merit."""
        with timed("residual"):
            _, self.residual, terms = self.model.block_residuals()
        self.terms = terms
        self.tolerance = np.maximum(STEP_SHARE * self.start, ROUND_OFF * terms)
        self.tolerance = np.where(self.tolerance > 0.0, self.tolerance, 1e-300)
        return self.merit()

    def ratios(self) -> np.ndarray:
        return self.residual / self.tolerance

    def ratio(self) -> float:
        return float(np.max(self.ratios()))

    def merit(self) -> float:
        return float(np.sqrt(np.sum(self.ratios() ** 2)))

    def solved(self) -> bool:
        r = self.ratios()
        return bool(np.all(np.isfinite(r)) and np.all(r <= 1.0))

    def words(self) -> str:
        """The blocks' out-of-balance in words: each block's norm and its share of its
        tolerance."""
        return ", ".join(f"{n} {r:.3e} ({q:.2g} of its tolerance)"
                         for n, r, q in zip(self.names, self.residual, self.ratios()))


class Newton:
    """Newton's method on a model whose soil block holds a plastic state."""

    #: a step (of load, of settlement) that converged in at most this many iterations lets
    #: the next grow by GROWTH
    FAST, GROWTH = 6, 1.5
    #: a settlement-controlled step whose out-of-balance force grows past this multiple of
    #: its first iteration's is cut back at once
    DIVERGING = 4.0
    #: halvings of the line search
    LINE_SEARCH = 5
    #: further halvings where the out-of-balance force is not finite (a Newton direction
    #: of tens of per cent of strain at a point whose return, from that far outside its
    #: yield surface, does not converge: measured at a Cam Clay crust's points beside a
    #: tank's edge under a reduced strength, 74-107 % strain in one iterate)
    NOT_FINITE = 10

    def __init__(self, model):
        self.model = model
        self.plastic = model.soil.plastic
        #: Newton iterations a solve may take (soil.max_iterations)
        self.max_iterations = model.soil.setting.soil.max_iterations
        self._centre = np.array([[0.0, -model.soil.setting.embedment]])

    def _unknowns(self) -> list:
        m = self.model
        return m.unknowns if isinstance(m.unknowns, list) else [m.unknowns]

    def histories(self) -> list:
        """The histories a converged state commits: the soil block's and, where the model
        has one, the interface's."""
        m = self.model
        return [m.soil.history] + ([m.interface.history] if m.interface is not None else [])

    def values(self) -> list[np.ndarray]:
        """The unknowns' values now (a state to measure an increment from)."""
        return [u.x.array.copy() for u in self._unknowns()]

    def restore_values(self, values: list[np.ndarray]) -> None:
        """The unknowns back to ``values`` (of :meth:`values`) of the committed state, the
        points' stress and tangent as committed with them. (Not those a zero increment
        from it gives: at a yielding point that is the elastic tangent, from which the
        next step's first iterate overshoots; measured, a footing's first time step after
        a strength search from its undrained state then found no equilibrium even in 64
        parts, and converged in 14 iterations from the committed tangent.)"""
        for u, x in zip(self._unknowns(), values):
            u.x.array[:] = x
        self.plastic.update()
        self.model.rollback()
        # (and which points yield, as committed: what the results count)
        p = self.plastic
        p.yielding = p.point_values(p.plastic) > 0.5

    def commit(self) -> None:
        """The converged state becomes the committed one: the points' and the model's."""
        self.plastic.commit()
        self.model.commit()

    def w0(self) -> float:
        """The settlement of the foundation's centre (at its underside), m. Collective."""
        return float(-evaluate_at(self.model.soil.u, self._centre)[0, 1])

    def solve(self, inner, max_iterations: int | None = None,
              stall: int | None = None) -> Solve:
        """Newton from the committed state under the loads set, until every block is
        solved (:class:`Balance`). ``max_iterations`` (default the soil's); ``stall``: give
        up where the merit has not halved over that many iterations (no equilibrium near:
        a trial beyond the limit load). A solve is never accepted because its residual
        stopped falling."""
        m = self.model
        unknowns = self._unknowns()
        max_iterations = max_iterations or self.max_iterations
        balance = Balance(m)
        previous = balance.measure()
        merits = [previous]
        log = logging.getLogger("tankfx")
        if log.isEnabledFor(logging.DEBUG):
            log.debug("    Newton 0: %s; largest terms %s", balance.words(), ", ".join(
                f"{n} {t:.3e}" for n, t in zip(balance.names, balance.terms)))
        for it in range(1, max_iterations + 1):
            before = [u.x.array.copy() for u in unknowns]
            try:
                inner()
            except SolveError as e:
                return Solve(False, it, balance.ratio(), f"the linear solve failed: {e}")
            after = [u.x.array.copy() for u in unknowns]
            alpha, tried = 1.0, []
            while True:
                self.plastic.update()
                merit = balance.measure()
                if merit < (1.0 - 1e-4 * alpha) * previous or balance.solved():
                    break
                tried.append((merit, alpha))
                # (a merit that is not finite is a step too long for some point's return:
                # shorter ones are tried beyond the line search's halvings)
                if len(tried) > self.LINE_SEARCH + (
                        0 if math.isfinite(merit) else self.NOT_FINITE):
                    merit = self._least(tried, before, after, balance)
                    break
                alpha *= 0.5
                for u, a, b in zip(unknowns, before, after):
                    u.x.array[:] = a + alpha * (b - a)
            if log.isEnabledFor(logging.DEBUG):
                log.debug("    Newton %d (step %.3g): %s", it, alpha, balance.words())
            if not math.isfinite(merit):
                return Solve(False, it, merit, "the out-of-balance force is not finite")
            previous = merit
            merits.append(merit)
            if balance.solved():
                return Solve(True, it, balance.ratio(), "")
            if stall and it >= stall and merit > 0.5 * merits[-1 - stall]:
                return Solve(False, it, balance.ratio(), (
                    f"the out-of-balance force stalled at {balance.words()}: not halved in "
                    f"{stall} iterations"))
        return Solve(False, max_iterations, balance.ratio(), (
            f"the out-of-balance force after {max_iterations} iterations: "
            f"{balance.words()}"))

    def _least(self, tried, before, after, balance) -> float:
        """No step length of the line search lowered the merit: the one of the least, its
        points updated with it (the unknowns and the points' stress of one state: the next
        tangent is that state's)."""
        finite = [t for t in tried if math.isfinite(t[0])]
        # (min over tuples with a NaN first returns that one: the finite ones' least)
        _, alpha = min(finite) if finite else tried[-1]
        for u, a, b in zip(self._unknowns(), before, after):
            u.x.array[:] = a + alpha * (b - a)
        self.plastic.update()
        return balance.measure()

    def controlled_step(self, inner, solver, load_at, factor: float, target: float,
                        measure) -> tuple[bool, int, float, float]:
        """Newton for the state and the load factor at which the displacement ``measure()``
        (linear in the unknowns: w0, or a mean settlement) is ``target``, from the committed
        state at ``factor``, the loads ``load_at(factor)`` (Batoz & Dhatt's displacement
        control: per iteration two solves with one factorisation, of the current loads and
        of a unit increment of the factor): (converged, iterations, out-of-balance,
        factor)."""
        m = self.model
        unknowns = self._unknowns()
        lam = factor
        residual, first = math.inf, math.inf
        committed = [u.x.array.copy() for u in unknowns]
        balance = None
        for it in range(1, self.max_iterations + 1):
            m.set_loads(load_at(lam))
            try:
                inner()
                a = [u.x.array.copy() for u in unknowns]
                w_a = measure()
                m.set_loads(load_at(lam + 1.0))
                solver.solve_again()
            except SolveError:
                return False, it, residual, lam
            d = [u.x.array - x for u, x in zip(unknowns, a)]
            w_d = measure() - w_a
            if not (abs(w_d) > 0.0 and math.isfinite(w_d)):
                return False, it, residual, lam
            step = (target - w_a) / w_d
            if balance is None:
                # the step's own change: the committed state's out-of-balance under the
                # first iterate's load (its stress the committed one)
                for u, x in zip(unknowns, committed):
                    u.x.array[:] = x
                m.set_loads(load_at(lam + step))
                self.plastic.update()
                balance = Balance(m)
            for u, x, dx in zip(unknowns, a, d):
                u.x.array[:] = x + step * dx
            lam += step
            m.set_loads(load_at(lam))
            self.plastic.update()
            residual = balance.measure()
            if not math.isfinite(residual):
                return False, it, residual, lam
            if balance.solved():
                return True, it, balance.ratio(), lam
            first = residual if it == 1 else first
            if residual > self.DIVERGING * first:
                # (no line search here: a step whose out-of-balance force has grown so far
                # has left Newton's basin; measured, none came back)
                return False, it, residual, lam
        return False, self.max_iterations, residual, lam

    def plastic_points(self) -> int:
        """The quadrature points that yield, over all ranks. Collective."""
        own = self.model.domain.mesh.topology.index_map(2).size_local * self.plastic.n_points
        return self.model.domain.mesh.comm.allreduce(int(np.sum(self.plastic.yielding[:own])))

    def largest_plastic_shear_strain(self) -> float:
        """Over all ranks. Collective."""
        p, comm = self.plastic, self.model.domain.mesh.comm
        own = self.model.domain.mesh.topology.index_map(2).size_local
        return comm.allreduce(
            float(p.plastic_shear_strain()[:own * p.n_points].max(initial=0.0)), op=MPI.MAX)

    def yielding_record(self) -> dict:
        """What a status records of the yielding (results.json's ``soil``): the points that
        yield, the largest plastic shear strain and, where the law defines it, the
        undrained strength where the clay yields. Collective."""
        out = {"plastic_points": self.plastic_points(),
               "max_plastic_shear_strain": self.largest_plastic_shear_strain()}
        s_u = self.undrained_strength()
        if s_u is not None:
            out["undrained_strength"] = s_u
        return out

    def undrained_strength(self) -> dict | None:
        """s_u where the clay yields (a law that defines it: Cam Clay), over all ranks:
        its least, mean and largest (Pa) over the yielding points, how many, and their
        depths' range (m); None where the law has none. Collective."""
        p, comm = self.plastic, self.model.domain.mesh.comm
        s_u = p.undrained_strength()
        if s_u is None:
            return None
        own = self.model.domain.mesh.topology.index_map(2).size_local * p.n_points
        flag = p.point_values(p.plastic)[:own] > 0.5
        here = s_u[:own][flag & np.isfinite(s_u[:own])]
        depth = p.depth[:own][flag & np.isfinite(s_u[:own])]
        n = comm.allreduce(len(here))
        out = {"points": n, "axis": self._undrained_strength_on_axis(s_u)}
        if n == 0:
            return out
        return out | {
                "min": comm.allreduce(float(here.min(initial=np.inf)), op=MPI.MIN),
                "max": comm.allreduce(float(here.max(initial=-np.inf)), op=MPI.MAX),
                "mean": comm.allreduce(float(here.sum())) / n,
                "depth_min": comm.allreduce(float(depth.min(initial=np.inf)), op=MPI.MIN),
                "depth_max": comm.allreduce(float(depth.max(initial=-np.inf)), op=MPI.MAX)}

    def _undrained_strength_on_axis(self, s_u: np.ndarray) -> dict:
        """s_u down the axis (each cell's mean, Pa), from the foundation's level to 3 radii
        below it (or the base): the profile a field vane under the tank's centre reads."""
        m, p = self.model, self.plastic
        sc = m.scene
        D, a = sc.embedment, sc.foundation_radius
        depth = np.linspace(D, min(D + 3.0 * a, sc.domain.depth), 31)
        values = np.nan_to_num(s_u).reshape(len(p.cells), p.n_points) @ p.weights / \
            p.weights.sum()
        field = cell_field(m.domain.mesh, values, "undrained_strength")
        on_axis = evaluate_at(field, np.column_stack([np.zeros_like(depth), -depth]),
                              cells=m.domain.cells("soil"))[:, 0]
        return {"depth": depth.tolist(), "s_u": on_axis.tolist()}

    def yielding_zone(self) -> str:
        """Where the soil yields, in words (gathered over the ranks). Collective."""
        comm = self.model.domain.mesh.comm
        p = self.plastic
        own = self.model.domain.mesh.topology.index_map(2).size_local
        flag = p.cell_average(p.plastic, 1)[:own, 0] > 0.5
        mid = self.model.domain.cell_midpoints[:own]
        pts = np.concatenate(comm.allgather(mid[flag]))
        if len(pts) == 0:
            # (none in a converged state: where the last, unconverged, trial yielded, the
            # points that a failed first step's Newton found)
            own_points = own * p.n_points
            trial = np.asarray(p.yielding[:own_points], dtype=bool).reshape(own, p.n_points)
            at = np.concatenate(comm.allgather(mid[trial.any(axis=1)]))
            if len(at) == 0:
                return "no point of the soil had yielded"
            return (f"no point of the soil had yielded in a converged state; in the last "
                    f"trial {len(at)} cells yielded, from r = {at[:, 0].min():.3g} to "
                    f"{at[:, 0].max():.3g} m and down to {-at[:, 1].min():.3g} m below the "
                    f"ground")
        depth = -pts[:, 1]
        return (f"{len(pts)} cells yield, from r = {pts[:, 0].min():.3g} to "
                f"{pts[:, 0].max():.3g} m and down to {depth.max():.3g} m below the ground")
