"""Biot's consolidation of an elastoplastic skeleton: the time stepping of
:class:`tankfx.iterations.time_stepping.TimeStepping` (the undrained start, every load
applied at once, then the steps through the reported times), each step solved by Newton
(:class:`tankfx.iterations.newton.Newton`) on the coupled blocks: the skeleton's effective
stress at the quadrature points by its law (c' and phi' for Mohr-Coulomb), the excess pore
pressure beside the displacement (a Taylor-Hood pair). The pore pressure's equation is linear;
the skeleton's tangent changes as it yields. The drained limit is the path's last load
carried drained, in load steps from rest (an elastoplastic skeleton's depends on the path:
this is the proportional one)."""
from __future__ import annotations


import math
from dataclasses import replace

from ..scene.sections import load_between, vertical_load
from .load_steps import NewtonIteration
from .newton import Newton, criterion_words
from .status import AtDebug, SoilFailure
from .time_stepping import DAY, DRAINED_STEP, TimeStepping, load_at


class PlasticConsolidation(TimeStepping):
    """Consolidation of a model whose soil block holds a plastic state and a pore
    pressure."""

    #: a time step Newton does not converge in is divided in at most this many parts
    MAX_PARTS = 64
    #: the steps by their local error, the grid's steps per decade the longest
    controlled = True

    def _keep_step(self) -> dict:
        return super()._keep_step() | {
            "histories": [h.snapshot() for h in self.newton.histories()],
            "values": self.newton.values()}

    def _back_step(self, kept: dict) -> None:
        for h, s in zip(self.newton.histories(), kept["histories"]):
            h.restore(s)
        super()._back_step(kept)
        self.newton.restore_values(kept["values"])

    @staticmethod
    def describe(scene) -> str:
        return TimeStepping.describe(scene).replace(" and ", " and at least ", 1).replace(
            " (a solve each)", " (shorter ones where their local error is over "
                               f"time_tolerance = {scene.consolidation.time_tolerance:g}), "
                               "each by Newton's method on the elastoplastic skeleton and "
                               "the pore pressure (load steps for a load applied at once, a "
                               "time step divided where it does not converge)")

    def __init__(self, model, solver):
        super().__init__(model, solver)
        self.newton = Newton(model)
        #: the load steps of a step Newton does not converge in at once
        self.steps = NewtonIteration(model)
        self.steps.newton = self.newton
        #: Newton iterations of every step
        self.iterations = 0

    @property
    def converged_load(self):
        """The load its load steps last converged at (a collapse search's snapshot keeps
        it: :class:`tankfx.iterations.load_steps.NewtonIteration`)."""
        return self.steps.converged_load

    @converged_load.setter
    def converged_load(self, load) -> None:
        self.steps.converged_load = load

    def run(self, inner, log):
        """The time stepping (:meth:`TimeStepping.run`); its status's record says how the
        skeleton was solved (results.json's ``soil``): Newton iterations, the points that
        yield at the end, the largest plastic shear strain."""
        status = super().run(inner, log)
        nw = self.newton
        self.last = replace(status, record={
            "converged": True, "iterations": self.iterations,
            "time_steps": status.iterations,
            "criterion": f"every time step by Newton, {criterion_words()}",
            **nw.yielding_record()})
        return self.last

    def _set_loads(self, load) -> None:
        self._before = self.model.scene.load
        super()._set_loads(load)

    def _solve(self, dt_eff: float, t: float | None = None) -> None:
        """One step by Newton from the committed state. Where it does not converge, a load
        applied at once (undrained) is applied in load steps, and a time step is divided in
        parts; where neither converges, the soil has lost equilibrium: SoilFailure says when
        and where the skeleton yields, keeping the steps that converged. A settlement by
        compression, however large, is no failure (a clay under a wide tank settles metres
        by consolidation alone): the results' validity says where it passes small strains."""
        self.soil.conductance.value = dt_eff / self.c.water_unit_weight
        start, before = self.newton.values(), self.iterations
        if not self._converge():
            # (what follows starts from the committed state, not from the failed iterate)
            self.newton.restore_values(start)
            if dt_eff > 0.0 and t is not None:
                self._divide(t)
            else:
                self._load_steps(t)
        self._step_iterations = self.iterations - before
        if t is not None:
            # (progress: a step of an elastoplastic skeleton may take many iterations)
            self._log.info("  t = %.6g days: %d Newton iterations, %d points yield",
                           t / DAY, self._step_iterations, self.newton.plastic_points())

    def _step(self, *args) -> tuple[dict, float]:
        """:meth:`TimeStepping._step`; its state (in the history) also says the Newton
        iterations the step took (``newton_iterations``: all its tries and parts)."""
        state, dt = super()._step(*args)
        state["newton_iterations"] = self._step_iterations
        return state, dt

    def _converge(self) -> bool:
        """Newton from the committed state, committed where it converges (rolled back where
        not)."""
        # (its whole budget, no stall test: measured, the footing's first time step after
        # its undrained start converged in 14 iterations, but given up after 8 that did not
        # halve the force its parts failed down to 1/64 of it: a shorter step drains a
        # thinner layer under the footing's edge, no easier to converge)
        ok, its, _, self._why = self.newton.solve(self._inner)
        self.iterations += its
        if ok:
            self.newton.commit()
        else:
            self.model.rollback()
        return ok

    def _divide(self, t: float) -> None:
        """A time step Newton does not converge in, in parts by backward Euler (the load
        followed along the path): the first half the step; a part that converges is kept,
        and the next grows by Newton.GROWTH where it took at most Newton.FAST iterations; a
        part that does not is halved, down to 1 / MAX_PARTS of the step."""
        t0, t1, path = self.span
        soil, nw = self.soil, self.newton
        smallest = (t1 - t0) / self.MAX_PARTS
        tau, dt, parts = t0, 0.5 * (t1 - t0), 0
        while tau < t1 - 1e-9 * (t1 - t0):
            dt = min(dt, t1 - tau)
            if dt < t1 - tau < 1.5 * dt:
                # (no sliver of a part at the end: two even ones)
                dt = 0.5 * (t1 - tau)
            here, before = nw.values(), self.iterations
            self._set_loads(load_at(path, tau + dt))
            soil.conductance.value = soil.step_weights.set(dt, 0.0, False) / \
                self.c.water_unit_weight
            if self._converge():
                tau, parts = tau + dt, parts + 1
                if tau < t1 - 1e-9 * (t1 - t0):
                    self._advance()
                if self.iterations - before <= nw.FAST:
                    dt *= nw.GROWTH
                continue
            nw.restore_values(here)
            dt *= 0.5
            if dt < smallest * (1.0 - 1e-9):
                raise self._lost(
                    f"consolidation, at t = {(tau + 2.0 * dt) / DAY:.6g} days (load "
                    f"{self.model.applied_load:.6g} N): the ground fails at this rate of "
                    f"loading: the elastoplastic soil found no equilibrium in a part of the "
                    f"time step from {t0 / DAY:.6g} to {t1 / DAY:.6g} days of "
                    f"1/{self.MAX_PARTS} its length ({self._why}); {nw.yielding_zone()}",
                    load_at(path, tau), self.model.scene.load, tau)
        self.divided = True
        self._log.debug("consolidation: the step to t = %.6g days in %d parts", t / DAY, parts)

    def _lost(self, message: str, carried, failed, t: float) -> SoilFailure:
        """The soil cannot carry the path's load at t: the error, the history of the steps
        that converged, and ``kept["largest_load_carried"]``: the time (days) and the mean
        bearing pressures (Pa) of the last load carried and of the one that failed."""
        sc = self.model.scene
        area = math.pi * sc.foundation_radius ** 2
        error = SoilFailure(message, list(getattr(self, "history", [])))
        error.kept["largest_load_carried"] = {
            "t_days": t / DAY, "criterion": "equilibrium",
            "mean_bearing_pressure_carried":
                vertical_load(carried, sc.plate, sc.wall, sc.ringwall) / area,
            "mean_bearing_pressure_failed":
                vertical_load(failed, sc.plate, sc.wall, sc.ringwall) / area}
        return error

    def _load_steps(self, t: float | None) -> None:
        """A load applied at once (undrained, its flow term and the earlier states held),
        or the drained limit's, in load steps halved where Newton does not converge."""
        m = self.model
        before, target = self._before, m.scene.load
        when = "the drained limit" if t is None else f"t = {t / DAY:.6g} days"

        def fail(done, share, why):
            m.set_loads(load_between(before, target, base=target, f=done))
            return self._lost(
                f"consolidation, at {when}: the elastoplastic soil cannot carry the load "
                f"applied at once ({done:.4g} of it carried undrained, {share:.4g} not: "
                f"{why}); {self.newton.yielding_zone()}", m.scene.load,
                load_between(before, target, base=target, f=share), t or 0.0)

        status = self.steps.steps(
            self._inner, AtDebug(self._log),
            lambda share: m.set_loads(load_between(before, target, base=target, f=share)),
            False, fail, "the load in {steps} load steps")
        self.iterations += status.iterations

    def _drained(self, load) -> dict:
        """The drained limit: ``load`` carried by the skeleton alone (the pore water free to
        drain: one step of DRAINED_STEP consolidation times), in load steps from rest; the
        state back at rest afterwards."""
        soil = self.soil
        rest = [h.snapshot() for h in self.newton.histories()]
        soil.step_weights.set(1.0, 0.0, False)
        soil.conductance.value = (DRAINED_STEP * self.slowest_time_scale /
                                  self.c.water_unit_weight)
        self._set_loads(load)
        try:
            self.steps.run(self._inner, AtDebug(self._log))
            drained = self._state(0.0) | {"t": None, "t_days": None,
                                          "surface": self._surface()}
        except SoilFailure as e:
            # (the path's last load is beyond what the drained skeleton carries: the path
            # is still followed in time, to where it fails, which is what is asked)
            drained = {"t": None, "t_days": None, "w0": None, "carried": False,
                       "reason": str(e)}
            self._log.warning("warning: the drained skeleton does not carry the path's last "
                              "load (%s); the path is followed in time", e)
        self.steps.converged_load = None
        for h, s in zip(self.newton.histories(), rest):
            h.restore(s)
        # (nothing on the ground at rest: the path's first change starts from it)
        self.model.set_loads(load.held())
        unknowns = self.model.unknowns
        for f in [*(unknowns if isinstance(unknowns, list) else [unknowns]), soil.u_n,
                  soil.u_nn]:
            f.x.array[:] = 0.0
        self.newton.plastic.update()
        return drained


__all__ = ["PlasticConsolidation"]
