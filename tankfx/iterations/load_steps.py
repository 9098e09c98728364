"""The elastoplastic soil's iteration of a stage: its load applied from the last converged
state in steps that grow when Newton converges fast and halve when it does not (the state
rolled back to the last converged step), until the stage's whole load is carried or the step
falls below a floor, where the soil is said to fail. Each step is one Newton solve
(:class:`tankfx.iterations.newton.Newton`), given up where its out-of-balance force stalls."""
from __future__ import annotations

import math
import time

from ..scene.sections import load_between, vertical_load
from .newton import Newton, criterion_words
from .status import IterationStatus, SoilFailure


class NewtonIteration:
    """Load-stepped Newton iteration of a model whose soil block holds a plastic state."""

    name = "soil"
    quiet_inner = False
    #: an active set inside it converges in every Newton iteration
    one_update_inside = False
    #: the first step's share of a stage's load, and the smallest step
    FIRST_STEP, MIN_STEP = 0.25, 1.0 / 512
    #: a step whose out-of-balance force has not halved in STALL Newton iterations is given
    #: up (halved) at once, not after its whole budget: near a stage's limit a trial that
    #: fails stalls there. Measured (benchmarks/failing_stage.py: a tank's stage loaded to
    #: three times what its clay carries): the failure said in 48 s instead of 166 s; the
    #: steps that would have converged slowly at the limit (20-24 iterations) are given up
    #: too, so the load carried is the one before them (116.1 kPa against 119.2). No demo
    #: scene's number moved (none of their steps stalls)
    STALL = 8

    @classmethod
    def build(cls, model, solver, how) -> "NewtonIteration":
        return cls(model)

    @staticmethod
    def describe(scene) -> str:
        pit = (f"; first the pit dug ({scene.embedment:g} m: its faces relieved of the "
               f"stress at rest), the tank then built on it"
               if scene.plate is not None and scene.embedment > 0.0 else "")
        return ("Newton's method on the elastoplastic soil (the consistent tangent), in load "
                "steps that halve where it does not converge" + pit)

    def __init__(self, model):
        self.model = model
        self.newton = Newton(model)
        #: the load of the last converged state (nothing before the first stage: the ground
        #: at rest)
        self.converged_load = None
        self.last: IterationStatus | None = None
        self.history: list[dict] = []

    def begin_stage(self) -> None:
        self.last = None
        self.history = []

    def start(self, target):
        """The load a stage starts from: the last converged one, or before the first stage
        none (the ground at rest): the target's with its amounts zero (its unit weights
        kept, so that a tank filling from empty loads in proportion to its height)."""
        if self.converged_load is not None:
            return self.converged_load
        return target.held()

    def run(self, inner, log) -> IterationStatus:
        m = self.model
        target = m.scene.load
        start = self.start(target)
        # a stage that takes load off starts each step elastically: the committed plastic
        # tangent predicts an unloading badly (measured: a floor on Tresca clay emptied from
        # 4 s_u, 25 failed iterations at the whole step, six halvings; elastically, one step)
        sc = m.scene
        unloads = vertical_load(target, sc.plate, sc.wall, sc.ringwall) < vertical_load(
            start, sc.plate, sc.wall, sc.ringwall)
        log.info("elastoplastic soil: Newton in load steps (%s)", criterion_words())

        def fail(done, share, reason):
            m.set_loads(load_between(start, target, base=target, f=done))
            return self._failure(start, target, done, share, reason)

        self.last = self.steps(
            inner, log, lambda share: m.set_loads(load_between(start, target, base=target,
                                                               f=share)),
            unloads, fail, f"the whole load carried in {{steps}} load steps, each with "
                           f"{criterion_words()}")
        self.converged_load = target
        return self.last

    def steps(self, inner, log, apply, unloads: bool, fail, criterion: str
              ) -> IterationStatus:
        """Load steps of ``apply(share)`` from 0 to 1 (the share of what is changed), each
        solved by Newton from the last converged one; a step that does not converge is
        halved, to MIN_STEP, where ``fail(done, tried, reason)`` is raised."""
        m, nw = self.model, self.newton
        done, step = 0.0, self.FIRST_STEP
        total_iterations = 0
        self.history = []
        log.info("  step  load share   w0 (m)        Newton  out-of-balance  plastic pts  "
                 "step     time s")
        t_stage = time.perf_counter()
        while done < 1.0:
            share = min(1.0, done + step)
            t0 = time.perf_counter()
            apply(share)
            if unloads:
                nw.plastic.elastic_predictor()
            ok, iterations, residual, reason = nw.solve(inner, stall=self.STALL)
            total_iterations += iterations
            if ok:
                nw.commit()
                done = share
                n_plastic = nw.plastic_points()
                row = {"step": len(self.history) + 1, "load_share": share, "w0": nw.w0(),
                       "iterations": iterations, "out_of_balance": residual,
                       "plastic_points": n_plastic, "step_size": step,
                       "time_s": time.perf_counter() - t0}
                self.history.append(row)
                log.info("  %4d  %10.4f  %12.5e  %6d  %14.3e  %11d  %6.4f  %7.2f", row["step"],
                         share, row["w0"], iterations, residual, n_plastic, step, row["time_s"])
                if iterations <= nw.FAST:
                    step = min(step * nw.GROWTH, 1.0)
                continue
            m.rollback()
            log.info("        %10.4f  no convergence (%s): the step is halved", share, reason)
            step *= 0.5
            if step < self.MIN_STEP:
                raise fail(done, share, reason)
        p = nw.plastic
        return IterationStatus.of({
            "converged": True, "iterations": total_iterations, "history": self.history,
            "steps": len(self.history),
            **nw.yielding_record(),
            "criterion": criterion.format(steps=len(self.history)),
            "time_s": time.perf_counter() - t_stage},
            # (per cell, for the fields and figures: yielding, and tau / tau_f)
            data={"plastic": p.cell_average(p.plastic, 1)[:, 0],
                  "stress_level": p.cell_mobilised()})

    def _failure(self, start, target, done: float, tried: float, reason: str) -> SoilFailure:
        """The soil cannot carry the stage's load: the last share carried and where the
        soil yields, in physical terms; ``kept["largest_load_carried"]`` the bracket."""
        m = self.model
        P = m.applied_load
        a = m.scene.foundation_radius
        where = self.newton.yielding_zone()
        sc = m.scene
        P_failed = vertical_load(load_between(start, target, base=target, f=tried), sc.plate,
                                 sc.wall, sc.ringwall)
        error = SoilFailure(
            f"the soil cannot carry the load: the load steps fell below {self.MIN_STEP:.4g} of "
            f"the stage's load at {done:.4g} of it (the vertical load {P / 1e6:.4g} MN, a mean "
            f"bearing pressure of {P / (math.pi * a ** 2) / 1e3:.4g} kPa on the foundation of "
            f"radius {a:g} m), and {tried:.4g} of it was not carried ({reason}); {where}",
            self.history)
        area = math.pi * a ** 2
        error.kept["largest_load_carried"] = {
            "fraction_carried": done, "fraction_failed": tried,
            "mean_bearing_pressure_carried": P / area,
            "mean_bearing_pressure_failed": P_failed / area}
        return error
