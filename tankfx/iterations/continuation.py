"""The load followed past its limit: a factor F on the loads ``load_at(F)`` raised under
control of a settlement (the foundation's centre w0, or its mean settlement), each step
finding by Newton the state and the factor at which the settlement is the one prescribed
(:meth:`tankfx.iterations.newton.Newton.controlled_step`, Batoz & Dhatt's displacement
control). Past the collapse load the factor stays at its plateau (perfect plasticity),
which load steps cannot reach. The one settlement-controlled continuation: the collapse
search by load (:mod:`tankfx.iterations.collapse`) and the footing's load-settlement curve
(:func:`run_to_settlement`) both follow it."""
from __future__ import annotations

import time
from typing import Callable, Iterator

from dolfinx import fem

from ..scene.sections import load_between
from .newton import Newton, criterion_words
from .status import IterationStatus, SoilFailure


class SettlementControl:
    """The continuation from the committed state (its factor ``F``, its settlement ``w``):
    :meth:`advance` yields every converged step; :meth:`accept` takes a state converged
    otherwise (a trial under load control) as the next point."""

    def __init__(self, newton: Newton, inner, solver, load_at: Callable, measure: Callable,
                 log, factor: float = 0.0):
        self.newton, self.inner, self.solver, self.log = newton, inner, solver, log
        self.load_at, self.measure = load_at, measure
        self.F, self.w = factor, measure()
        #: Newton iterations of every step, converged or not
        self.iterations = 0
        #: why the steps stopped short of their end (empty where they reached it)
        self.stuck = ""
        #: the soil's displacement over the last converged step: the mechanism near collapse
        self.increment = None
        self._previous = newton.values()

    def advance(self, end: float, dw: float, min_dw: float, max_dw: float,
                max_steps: int | None = None) -> Iterator[dict]:
        """Steps of the settlement from ``w`` to ``end``, the first ``dw``: a step that does
        not converge is halved (down to ``min_dw``: then ``stuck`` says why and the steps
        stop), one that converged fast lets the next grow by Newton.GROWTH to ``max_dw``.
        Yields each converged step's row (its number among the tries, ``factor``,
        ``settlement``, ``slope`` (factor per settlement), Newton ``iterations``,
        ``out_of_balance``, ``plastic_points``, ``time_s``); ``max_steps`` tries at most."""
        nw, m, log = self.newton, self.newton.model, self.log
        log.info("  step  factor        settlement (m)  Newton  out-of-balance  plastic pts  "
                 "time s")
        tries = 0
        while self.w < end - 1e-12 * abs(end):
            if max_steps is not None and tries >= max_steps:
                self.stuck = f"not reached within {max_steps} settlement-controlled steps"
                return
            tries += 1
            t0 = time.perf_counter()
            target = min(self.w + dw, end)
            ok, its, residual, lam = nw.controlled_step(self.inner, self.solver, self.load_at,
                                                        self.F, target, self.measure)
            self.iterations += its
            if not ok:
                m.rollback()
                m.set_loads(self.load_at(self.F))
                dw *= 0.5
                log.info("        no convergence (out-of-balance %.2e at %.5e m): the "
                         "settlement step is halved", residual, target)
                if dw < min_dw:
                    self.stuck = (f"the settlement-controlled steps did not converge beyond "
                                  f"a settlement of {self.w:.4g} m (load factor {self.F:.4g})")
                    return
                continue
            slope = (lam - self.F) / (target - self.w)
            self._converged(lam, target)
            row = {"step": tries, "factor": lam, "settlement": target, "slope": slope,
                   "iterations": its, "out_of_balance": residual,
                   "plastic_points": nw.plastic_points(), "time_s": time.perf_counter() - t0}
            log.info("  %4d  %12.6f  %14.5e  %6d  %14.3e  %11d  %7.2f", tries, lam, target,
                     its, residual, row["plastic_points"], row["time_s"])
            yield row
            if its <= nw.FAST:
                dw = min(nw.GROWTH * dw, max_dw)

    def accept(self, factor: float) -> None:
        """The state now converged at ``factor`` (by a trial under load control) is the
        continuation's next point, at its own settlement."""
        self._converged(factor, self.measure())

    def _converged(self, factor: float, w: float) -> None:
        u = self.newton.model.soil.u
        self.increment = fem.Function(u.function_space, name="mechanism")
        self.increment.x.array[:] = u.x.array - self._previous[0]
        self.newton.commit()
        self.F, self.w = factor, w
        self._previous = self.newton.values()


def run_to_settlement(iteration, inner, solver, log, settlement: float,
                      steps: int = 20) -> IterationStatus:
    """The stage's load times a factor that the foundation's settlement w0 controls
    (``iteration``: the elastoplastic soil's :class:`NewtonIteration`): from the
    committed state (factor 0) w0 is raised in ``steps`` equal increments to
    ``settlement`` (m). The history holds the factor (``load_share``) and w0 of every
    step: the load-settlement curve. A step that does not converge is halved, to 1/64
    of the first; then SoilFailure."""
    m, nw = iteration.model, iteration.newton
    target = m.scene.load
    start = iteration.start(target)
    control = SettlementControl(nw, inner, solver,
                                lambda f: load_between(start, target, base=target, f=f),
                                nw.w0, log)
    dw = (settlement - control.w) / steps
    log.info("elastoplastic soil: settlement control to w0 = %.4g m in %d steps", settlement,
             steps)
    for row in control.advance(settlement, dw, dw / 64, 2.0 * dw):
        iteration.history.append({
            "step": len(iteration.history) + 1, "load_share": row["factor"],
            "w0": row["settlement"], "iterations": row["iterations"],
            "out_of_balance": row["out_of_balance"],
            "plastic_points": row["plastic_points"], "time_s": row["time_s"]})
    if control.stuck:
        raise SoilFailure(f"{control.stuck}: {nw.yielding_zone()}", iteration.history)
    iteration.last = IterationStatus.of({
        "converged": True, "iterations": control.iterations,
        "history": iteration.history, "steps": len(iteration.history),
        "criterion": f"w0 raised to {settlement:g} m in {len(iteration.history)} steps, "
                     f"each with {criterion_words()}"})
    return iteration.last
