"""The ground's collapse: the factor on the variable loads (``collapse = "load"``) or on the
soil's strength (``"strength"``) at which the ground fails, bracketed between a converged
and a failed state, from the scene's own converged analysis.

**Load.** The variable loads times a factor F (:func:`tankfx.scene.sections.factored_load`:
up to 1 as the stage applied them, beyond 1 their pressures times F; the self-weight held)
are followed under control of the foundation's mean settlement (Batoz & Dhatt's
displacement control, :mod:`tankfx.iterations.continuation`):
each step raises the mean settlement and finds the factor and the state together, so the
steps pass the limit point, where load steps cannot go. When the curve has flattened (its
slope below ``PLATEAU_SLOPE`` of its first), the factor F_c reached is tried under load
control at F_c (1 + BRACKET) from the converged state: if that fails, the collapse factor
lies in [F_c, F_c (1 + BRACKET)] (the ground carries F_c, and no equilibrium is found above
it); if it converges, the search goes on from there. A scene whose load already fails
starts from the share it carried.

**Strength.** The loads held, c and tan phi are divided by a factor F (the dilation angle
kept until the reduced friction angle reaches it, then equal to it, as PLAXIS does), each
trial solved by Newton from the last converged state: F grows while Newton converges, and
once a trial fails the bracket [converged, failed] is halved until it is narrower than
BRACKET. Its failed state is one where Newton finds no equilibrium in its iterations from
the converged one.

**Failure.** A failed state is one with no equilibrium (Newton's out-of-balance force does
not fall within its budget) or one whose equilibrium lies beyond the settlement criterion:
a mean settlement of the foundation of a tenth of its diameter (``FAILURE_SETTLEMENT``
radii; Vesic's and De Beer's ultimate load where a load test's curve has no plateau): by
load, from the ground before the load; by strength, from the state the reduction starts
from (the settlement the reduction causes). A
rigid footing or raft reaches its plateau well before it (general shear); a flexible
tank's floor, whose edge punches in, reaches the criterion on a curve that still rises
slowly (contained plastic flow carried by the interior): the factor is then the one at the
criterion, and the record says which failure bracketed it.

Both record the settlement at each step, the reason the last trial failed, and the last
increments' displacement, the mechanism.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace

from dolfinx import fem

from ..fem.failure import Failure
from ..scene.sections import Load, factored_load
from .continuation import SettlementControl
from .status import AtDebug

#: the bracket's width, relative: a collapse factor F_c is bracketed in [F_c, F_c (1 + BRACKET)]
BRACKET = 0.005


@dataclass(frozen=True)
class CollapseOutcome:
    """What a collapse search found, for results.json's ``collapse``
    (:func:`tankfx.results.collapse.collapse_record`): its ``kind`` ("load" or "strength"),
    the ``factor`` carried, the ``bracket`` [carried, failed] where ``found``, why the last
    trial failed (``reason``) and which ``failure`` it was (Failure.NO_EQUILIBRIUM or
    SETTLEMENT), the ``curve`` (factor and mean settlement at every converged point), the
    mechanism (``increment``: the soil's last displacement increment), the ``load`` at the
    factor carried, the settlement criterion (m), its cost."""

    kind: str
    factor: float
    bracket: tuple[float, float] | None
    found: bool
    reason: str
    failure: str | None
    curve: list
    increment: fem.Function | None
    load: Load
    failure_settlement: float
    iterations: int
    time_s: float
    bracket_width: float = BRACKET


class CollapseSearch:
    """The collapse search of a solved scene (its model, its chain of iterations, whose
    outermost is the elastoplastic soil's load-stepped Newton iteration, and its solver)."""

    #: the load-settlement curve is flat where its slope has fallen below this share of
    #: its first
    PLATEAU_SLOPE = 2e-3
    #: settlement-controlled steps at most
    MAX_STEPS = 120
    #: the settlement criterion of failure, in foundation radii: a mean settlement of 0.1 D
    #: from the ground before the foundation's load. Where a curve has no plateau, the
    #: ultimate load is taken at a settlement of a tenth of the width (De Beer 1967; Vesic
    #: 1975, local and punching shear); beyond it small strains no longer hold (a footing's
    #: strength trial beyond its limit "converged" at a mean settlement of 115 m)
    FAILURE_SETTLEMENT = 0.2
    #: the mean settlement the criterion is measured from: the load's search, from the
    #: ground before the foundation's load (a load test's); the strength's, from the state
    #: its reduction starts from (the settlement the reduction causes, as PLAXIS resets
    #: the displacements of its safety phase): a consolidating clay's settlement in time
    #: is no failure (measured on a 25 m tank on Cam Clay: a hold's consolidation, 0.5-1
    #: m of it, ate into the criterion, and its factor of safety rose 1.20 -> 1.24 over
    #: holds of 1 to 8 days while its undrained strength grew)
    settlement_base = 0.0
    #: strength trials at most
    MAX_TRIALS = 60
    #: a trial's Newton iterations at most, and the iterations over which its out-of-balance
    #: force must halve: near the limit Newton converges slowly (a c-phi footing 0.3 % below
    #: its limit: 42 iterations; budgets of 25 and 30 called such trials failures, 1-2 %
    #: low), beyond it the force stalls. The load's trial, 0.5 % above a plateau reached
    #: under settlement control: TRIAL_ITERATIONS, STALL. A strength trial, a step in c and
    #: tan phi from the last converged factor: twice that (with the apex's tangent near its
    #: own zero, a c-phi footing's trial 0.5 % below its limit took 62 iterations, and a
    #: stall of 50 put the strength factor 1 % low against the load factor)
    TRIAL_ITERATIONS, STALL = 100, 50
    STRENGTH_ITERATIONS, STRENGTH_STALL = 200, 100
    #: the stall test of a strength trial more than 4 brackets above the last converged one
    FAR_STALL = 15

    def __init__(self, model, chain, solver, log):
        self.model, self.solver, self.log = model, solver, log
        self.iteration = chain.iterations[0]
        self.newton = self.iteration.newton
        self.inner = chain.inner(log)
        self.curve: list[dict] = []
        self.increment = None
        self.failure: str | None = None

    # ---- the state a search starts from, given back afterwards ----------------------------
    def snapshot(self):
        """A converged state to come back to (histories, unknowns, loads, and the load
        Newton last converged at: where its next load steps start)."""
        return ([h.snapshot() for h in self.newton.histories()], self.newton.values(),
                self.model.scene.load, self.iteration.converged_load)

    def restore(self, snap) -> None:
        """Back to ``snap``: the scene's own results and figures are of that state."""
        histories, unknowns, load, self.iteration.converged_load = snap
        for h, s in zip(self.newton.histories(), histories):
            h.restore(s)
        self.model.set_loads(load)
        self.newton.restore_values(unknowns)

    # ---- load ------------------------------------------------------------------------
    def by_load(self, full) -> CollapseOutcome:
        """The factor on ``full``'s variable loads at which the ground fails, from the
        state before they are applied (the ground at rest, a pit dug): the held loads (the
        self-weight) first, then the variable ones under settlement control."""
        m, log = self.model, self.log
        t0 = time.perf_counter()
        held = full.held()

        def load_at(f):
            return factored_load(held, full, f)

        a = m.scene.foundation_radius
        m.set_loads(held)
        m.begin_stage()
        self.iteration.begin_stage()
        self.iteration.run(self.inner, AtDebug(log))          # (the self-weight alone, if any)
        control = SettlementControl(self.newton, self.inner, self.solver, load_at,
                                    m.mean_settlement, log)
        self._point(control.F, control.w, 0)
        log.info("collapse by load: the variable loads raised under control of the mean "
                 "settlement")
        w_failure = self.FAILURE_SETTLEMENT * a
        slope0, iterations, reason, bracket = None, 0, "", None
        if control.w >= w_failure:
            reason = (f"the held loads alone settle the foundation {control.w:.4g} m, beyond "
                      f"the settlement criterion of failure ({w_failure:.4g} m)")
        for row in control.advance(w_failure, max(0.1 * abs(control.w), 2e-4 * a), 1e-6 * a,
                                   0.02 * a, self.MAX_STEPS):
            slope0 = row["slope"] if slope0 is None else slope0
            self._point(control.F, control.w, row["iterations"])
            at_criterion = control.w >= w_failure * (1.0 - 1e-9)
            if row["slope"] < self.PLATEAU_SLOPE * slope0 or at_criterion:
                bracket, reason, more = self._try_above(control)
                iterations += more
                if bracket is not None:
                    break
                if at_criterion:
                    reason = (f"{control.F:.6g} was carried within a mean settlement of "
                              f"{w_failure:.4g} m: the curve is not monotonic there")
                    break
                # (carried: the curve goes on from there, its slope measured afresh)
                slope0 = None
        else:
            if control.stuck.startswith("not reached"):
                reason = f"no collapse within {self.MAX_STEPS} settlement-controlled steps"
            else:
                reason = reason or control.stuck
        self.increment = control.increment
        found = bracket is not None
        return self._outcome("load", control.F, bracket, found, reason,
                             iterations + control.iterations, t0, load=load_at(control.F),
                             failure=self.failure if found else None)

    def _small(self, ok: bool, why: str) -> tuple[bool, str]:
        """A converged trial counts only within the settlement criterion (a mean settlement
        of FAILURE_SETTLEMENT radii): beyond it, the ground has failed. Records which failure
        it was (``self.failure``)."""
        if not ok:
            self.failure = Failure.NO_EQUILIBRIUM
            return ok, why
        a = self.model.scene.foundation_radius
        w = self.model.mean_settlement()
        if w - self.settlement_base > self.FAILURE_SETTLEMENT * a * (1.0 + 1e-9):
            self.failure = Failure.SETTLEMENT
            grown = "" if not self.settlement_base else \
                f" ({w - self.settlement_base:.4g} m since the strength's reduction began)"
            return False, (f"its equilibrium lies at a mean settlement of {w:.4g} m{grown}, "
                           f"beyond the settlement criterion of failure "
                           f"({self.FAILURE_SETTLEMENT:g} radii = "
                           f"{self.FAILURE_SETTLEMENT * a:.4g} m)")
        return ok, why

    def _failed(self, why: str) -> str:
        """Why a trial failed, in words (after :meth:`_small`)."""
        return f"Newton found no equilibrium: {why}" if self.failure == Failure.NO_EQUILIBRIUM \
            else why

    def _try_above(self, control: SettlementControl):
        """Load control from the continuation's converged state at F to F (1 + BRACKET):
        (the bracket and why the failed state failed, or None where it converged, and the
        iterations)."""
        m, F = self.model, control.F
        F_try = F * (1.0 + BRACKET)
        m.set_loads(control.load_at(F_try))
        ok, its, residual, why = self.newton.solve(self.inner, self.TRIAL_ITERATIONS,
                                                   self.STALL)
        ok, why = self._small(ok, why)
        if not ok:
            m.rollback()
            m.set_loads(control.load_at(F))
            self.log.info("  the load factor %.6g is not carried (%s): collapse between %.6g "
                          "and %.6g", F_try, why, F, F_try)
            return (F, F_try), (f"at {F_try:.6g}, from the state converged at {F:.6g}, "
                                f"{self._failed(why)}"), its
        control.accept(F_try)
        self._point(F_try, control.w, its)
        self.log.info("  the load factor %.6g is carried too: the search goes on", F_try)
        return None, "", its

    # ---- strength ----------------------------------------------------------------------
    def by_strength(self, bracket: float = BRACKET,
                    through: float | None = None) -> CollapseOutcome:
        """The factor on c and tan phi at which the ground fails under the scene's load,
        from the converged state at the full strength, bracketed to ``bracket``
        (relative). With ``through``, no trial above it until it is carried, then on: a
        check (is the factor of safety at least this?) and the factor in one search,
        along the search's own ladder of trials (an elastoplastic state depends on the
        path of the reduction: measured on a Cam Clay tank, one trial from 1 to 1.3
        converged where the ladder failed at 1.12)."""
        m, nw, log = self.model, self.newton, self.log
        t0 = time.perf_counter()
        full = nw.plastic.points

        def reduce(F):
            # (the law's rule: c and tan phi for Mohr-Coulomb)
            nw.plastic.use(full.reduced(F))

        F_ok, F_fail, dF = 1.0, None, 0.1
        w_start = m.mean_settlement()
        self.settlement_base = w_start
        self._point(F_ok, w_start, 0)
        log.info("collapse by strength: c and tan phi divided by a factor under the "
                 "scene's load")
        log.info("  trial  factor     converged  Newton  mean settlement (m)  time s")
        iterations, reason, failure = 0, "", None
        previous = nw.values()
        try:
            failed_from = None          # (the converged factor the failed trial started from)
            for trial in range(1, self.MAX_TRIALS + 1):
                if F_fail is not None and F_fail / F_ok - 1.0 <= bracket:
                    if failed_from == F_ok:
                        break
                    # the failed trial started further down: try it again from the
                    # bracket's converged state, so that the failure is that state's
                    F = F_fail
                else:
                    F = F_ok + dF if F_fail is None else 0.5 * (F_ok + F_fail)
                if through is not None and F_ok < through:
                    F = min(F, through)
                ts = time.perf_counter()
                reduce(F)
                # (a trial far above the last converged one stalls soon where it fails; a
                # false failure there only brings the next trial nearer, and the bracket's
                # own failed trial is always one within 4 brackets of its converged state.
                # "Far" is measured in the finest bracket's widths, BRACKET: a check's
                # search to 2 % gave a trial 4.5 % above the converged one the long stall,
                # and it hovered 107 iterations (53 s) before it failed, measured on a Cam
                # Clay tank; its bracket's own failed trial, within 2 %, still has it)
                near = F / F_ok - 1.0 <= 4.0 * min(bracket, BRACKET)
                ok, its, residual, why = nw.solve(
                    self.inner, self.STRENGTH_ITERATIONS,
                    self.STRENGTH_STALL if near else self.FAR_STALL)
                iterations += its
                ok, why = self._small(ok, why)
                log.info("  %5d  %9.5f  %9s  %6d  %19s  %6.2f", trial, F, ok, its,
                         f"{m.mean_settlement():.5e}" if ok else "-", time.perf_counter() - ts)
                if ok:
                    self.increment = self._increment(previous)
                    nw.commit()
                    previous = nw.values()
                    F_ok = F
                    self._point(F, m.mean_settlement(), its)
                    if F_fail is not None and F >= F_fail:
                        # (the failure did not hold from nearer: search on above)
                        F_fail, dF = None, bracket * F
                    if F_fail is None and its <= nw.FAST:
                        dF *= 2.0
                else:
                    m.rollback()
                    F_fail = F if F_fail is None else min(F_fail, F)
                    failed_from = F_ok
                    reason = (f"at {F:.6g}, from the state converged at {F_ok:.6g}, "
                              f"{self._failed(why)}")
                    failure = self.failure
            else:
                reason = f"no bracket within {self.MAX_TRIALS} trials"
        finally:
            nw.plastic.use(full)
            self.settlement_base = 0.0
        found = F_fail is not None and F_fail / F_ok - 1.0 <= bracket
        return replace(self._outcome("strength", F_ok, (F_ok, F_fail) if found else None,
                                     found, reason, iterations, t0, load=m.scene.load,
                                     failure=failure if found else None),
                       bracket_width=bracket)

    # ---- what both record ------------------------------------------------------------------
    def _point(self, factor: float, w: float, iterations: int) -> None:
        self.curve.append({"factor": factor, "mean_settlement": w, "iterations": iterations})

    def _increment(self, previous):
        """The soil's displacement since ``previous`` (the unknowns' values then)."""
        u = self.model.soil.u
        du = fem.Function(u.function_space, name="mechanism")
        du.x.array[:] = u.x.array - previous[0]
        return du

    def _outcome(self, kind, F, bracket, found, reason, iterations, t0, load,
                 failure) -> CollapseOutcome:
        return CollapseOutcome(
            kind=kind, factor=F, bracket=tuple(bracket) if bracket else None, found=found,
            reason=reason, failure=failure, curve=list(self.curve), increment=self.increment,
            load=load,
            failure_settlement=self.FAILURE_SETTLEMENT * self.model.scene.foundation_radius,
            iterations=iterations, time_s=time.perf_counter() - t0)
