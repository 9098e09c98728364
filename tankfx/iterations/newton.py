"""Newton's method for the elastoplastic soil, in load steps: each stage's load is applied
from the last converged state in steps that grow when Newton converges fast and halve when it
does not (the state rolled back to the last converged step), until the stage's whole load is
carried or the step falls below a floor, where the soil is said to fail.

Each Newton iteration solves the block system with the current tangent (``inner()``: the
linear solve, :class:`tankfx.model.plastic.PlasticState` puts the tangent and the stress into
the soil's forms), updates the stress at every quadrature point from the committed state
(the return of :mod:`tankfx.laws.plasticity`), and measures the out-of-balance force of the
updated state; a step that raises it is shortened by a backtracking line search.
"""
from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np
from mpi4py import MPI
from ..fem.evaluate import evaluate_at
from ..fem.solvers import SolveError
from ..scene.sections import load_between, vertical_load
from .status import IterationStatus, SoilFailure


class NewtonIteration:
    """Load-stepped Newton iteration of a model whose soil block holds a plastic state."""

    name = "soil"
    quiet_inner = False
    #: an active set inside it converges in every Newton iteration
    one_update_inside = False
    #: the out-of-balance force of a converged step, relative to the load vector
    TOLERANCE = 1e-8
    #: a step whose out-of-balance force is below ROUND_OFF and has stopped falling (three
    #: iterations without halving) has converged to the round-off of its state: measured on
    #: a 25 m tank's collapse at metres of settlement, steps stalled at 1.1-1.5e-8 and were
    #: cut back for nothing
    ROUND_OFF = 1e-7
    #: the first step's share of a stage's load, and the smallest step
    FIRST_STEP, MIN_STEP = 0.25, 1.0 / 512
    #: a step that converged in at most this many iterations lets the next grow by GROWTH
    FAST, GROWTH = 6, 1.5
    #: a settlement-controlled step whose out-of-balance force grows past this multiple of
    #: its first iteration's is cut back at once
    DIVERGING = 4.0
    #: halvings of the line search
    LINE_SEARCH = 5

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
        self.plastic = model.soil.plastic
        #: Newton iterations a step may take before it is cut back (soil.max_iterations)
        self.max_iterations = model.soil.setting.soil.max_iterations
        #: the load of the last converged state (nothing before the first stage: the ground
        #: at rest)
        self.converged_load = None
        self.last: IterationStatus | None = None
        self.history: list[dict] = []
        self._centre = np.array([[0.0, -model.soil.setting.embedment]])

    def begin_stage(self) -> None:
        self.last = None
        self.history = []

    def _start(self, target):
        """The load a stage starts from: the last converged one, or before the first stage
        none (the ground at rest): the target's with its amounts zero (its unit weights
        kept, so that a tank filling from empty loads in proportion to its height)."""
        if self.converged_load is not None:
            return self.converged_load
        return target.held()

    def _w0(self) -> float:
        return float(-evaluate_at(self.model.soil.u, self._centre)[0, 1])

    def run(self, inner, log) -> IterationStatus:
        m = self.model
        target = m.scene.load
        start = self._start(target)
        # a stage that takes load off starts each step elastically: the committed plastic
        # tangent predicts an unloading badly (measured: a floor on Tresca clay emptied from
        # 4 s_u, 25 failed iterations at the whole step, six halvings; elastically, one step)
        sc = m.scene
        unloads = vertical_load(target, sc.plate, sc.wall, sc.ringwall) < vertical_load(
            start, sc.plate, sc.wall, sc.ringwall)
        log.info("elastoplastic soil: Newton in load steps (tolerance %g on the out-of-balance "
                 "force)", self.TOLERANCE)

        def fail(done, share, reason):
            m.set_loads(load_between(start, target, base=target, f=done))
            return self._failure(start, target, done, share, reason)

        self.last = self._steps(
            inner, log, lambda share: m.set_loads(load_between(start, target, base=target,
                                                               f=share)),
            unloads, fail, f"the whole load carried in {{steps}} load steps, each to an "
                           f"out-of-balance force <= {self.TOLERANCE:g} of the load vector")
        self.converged_load = target
        return self.last

    def excavate(self, inner, log) -> IterationStatus:
        """The excavation of an embedded foundation's pit, before anything is built: the
        ground at rest loses the support of the soil taken out (the pit's faces are
        relieved of their stress at rest, in load steps), the structure standing by without
        stiffness; then the displacements are set to zero, the excavated ground's stress
        and plastic strain kept, and the structure is built on it free of strain. The
        status's record: the heave of the pit's bottom at its centre, the plastic points,
        the steps."""
        m, pit = self.model, self.model.soil.pit
        log.info("elastoplastic soil: the pit's excavation, in load steps")

        def fail(done, share, reason):
            pit.share.value = done
            a = m.scene.foundation_radius
            sv = pit.bottom_stress
            return SoilFailure(
                f"the pit cannot be excavated: the ground around it gives way (its bottom "
                f"heaving, or its sides sliding in) beyond {done:.4g} of the relief of its "
                f"stress at rest ({share:.4g} was not carried: {reason}); relieved in full "
                f"it would be sigma'_v = {sv / 1e3:.4g} kPa at its bottom, {m.scene.embedment:g} "
                f"m deep over a radius of {a:g} m; {self._yielding_zone()}; a shallower pit "
                f"(plate.embedment), a stronger soil, or a supported pit (not modelled)",
                self.history)

        target = m.scene.load
        m.set_loads(self._start(target))        # (nothing built yet: nothing on it)
        with m.structure_absent():
            status = self._steps(inner, log, lambda share: setattr(pit.share, "value", share),
                                 False, fail, "the pit's stress at rest relieved in {steps} "
                                              "load steps")
        heave = -status.history[-1]["w0"]
        reaction, released = m.excavation_equilibrium()
        m.place_structure()
        m.set_loads(target)
        record = {**status.record, "heave": heave, "released_load": released,
                  "reaction": reaction,
                  "relative_error": abs(reaction + released) / max(abs(released), 1e-300)}
        self.last = replace(status, record=record)
        return self.last

    def _steps(self, inner, log, apply, unloads: bool, fail, criterion: str
               ) -> IterationStatus:
        """Load steps of ``apply(share)`` from 0 to 1 (the share of what the stage changes),
        each solved by Newton from the last converged one; a step that does not converge
        is halved, to MIN_STEP, where ``fail(done, tried, reason)`` is raised."""
        m = self.model
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
                self.plastic.elastic_predictor()
            ok, iterations, residual, reason = self._newton(inner)
            total_iterations += iterations
            if ok:
                self.plastic.commit()
                m.commit()
                done = share
                n_plastic = m.domain.mesh.comm.allreduce(self._plastic_points())
                row = {"step": len(self.history) + 1, "load_share": share, "w0": self._w0(),
                       "iterations": iterations, "out_of_balance": residual,
                       "plastic_points": n_plastic, "step_size": step,
                       "time_s": time.perf_counter() - t0}
                self.history.append(row)
                log.info("  %4d  %10.4f  %12.5e  %6d  %14.3e  %11d  %6.4f  %7.2f", row["step"],
                         share, row["w0"], iterations, residual, n_plastic, step, row["time_s"])
                if iterations <= self.FAST:
                    step = min(step * self.GROWTH, 1.0)
                continue
            m.rollback()
            log.info("        %10.4f  no convergence (%s): the step is halved", share, reason)
            step *= 0.5
            if step < self.MIN_STEP:
                raise fail(done, share, reason)
        p, comm = self.plastic, m.domain.mesh.comm
        own = m.domain.mesh.topology.index_map(2).size_local
        return IterationStatus.of({
            "converged": True, "iterations": total_iterations, "history": self.history,
            "steps": len(self.history),
            "plastic_points": comm.allreduce(self._plastic_points()),
            "max_plastic_shear_strain": comm.allreduce(
                float(p.plastic_shear_strain()[:own * p.n_points].max(initial=0.0)),
                op=MPI.MAX),
            "criterion": criterion.format(steps=len(self.history)),
            "time_s": time.perf_counter() - t_stage},
            # (per cell, for the fields and figures: yielding, and tau / tau_f)
            data={"plastic": p.cell_average(p.plastic, 1)[:, 0],
                  "stress_level": p.cell_mobilised()})

    def run_to_settlement(self, inner, solver, log, settlement: float,
                          steps: int = 20) -> IterationStatus:
        """The stage's load times a factor that the foundation's settlement w0 controls:
        from the committed state (factor 0) w0 is raised in ``steps`` equal increments to
        ``settlement`` (m), and each step finds by Newton both the state and the factor
        at which w0 is the one prescribed (Batoz & Dhatt's displacement control: per
        iteration two solves with one factorisation, of the current loads and of a unit
        increment of the factor). Past the collapse load the factor stays at its plateau
        (perfect plasticity), which load steps cannot reach. The history holds the factor
        (``load_share``) and w0 of every step: the load-settlement curve. A step that does
        not converge is halved, to 1/64 of the first; then SoilFailure."""
        m = self.model
        target = m.scene.load
        start = self._start(target)
        load_at = lambda f: load_between(start, target, base=target, f=f)  # noqa: E731
        w_start = self._w0()
        dw = (settlement - w_start) / steps
        factor, w_done, size = 0.0, w_start, dw
        log.info("elastoplastic soil: settlement control to w0 = %.4g m in %d steps", settlement,
                 steps)
        log.info("  step   w0 (m)        load factor   Newton  out-of-balance  plastic pts  "
                 "time s")
        total = 0
        while w_done < settlement - 1e-12 * abs(settlement):
            t0 = time.perf_counter()
            w_target = min(w_done + size, settlement)
            ok, its, residual, lam = self.controlled_step(inner, solver, load_at, factor,
                                                          w_target, self._w0)
            total += its
            if not ok:
                m.rollback()
                m.set_loads(load_at(factor))
                size *= 0.5
                log.info("         %12.5e  no convergence: the settlement step is halved",
                         w_target)
                if size < dw / 64:
                    raise SoilFailure(
                        f"the settlement-controlled steps did not converge beyond w0 = "
                        f"{w_done:.4g} m (load factor {factor:.4g}): {self._yielding_zone()}",
                        self.history)
                continue
            self.plastic.commit()
            m.commit()
            factor, w_done = lam, w_target
            n_plastic = m.domain.mesh.comm.allreduce(self._plastic_points())
            row = {"step": len(self.history) + 1, "load_share": factor, "w0": w_done,
                   "iterations": its, "out_of_balance": residual,
                   "plastic_points": n_plastic, "time_s": time.perf_counter() - t0}
            self.history.append(row)
            log.info("  %4d  %12.5e  %12.6f  %6d  %14.3e  %11d  %7.2f", row["step"], w_done,
                     factor, its, residual, n_plastic, row["time_s"])
            if its <= self.FAST:
                size = min(size * self.GROWTH, 2.0 * dw)
        self.last = IterationStatus.of({
            "converged": True, "iterations": total, "history": self.history,
            "steps": len(self.history),
            "criterion": f"w0 raised to {settlement:g} m in {len(self.history)} steps, each to "
                         f"an out-of-balance force <= {self.TOLERANCE:g}"})
        return self.last

    def controlled_step(self, inner, solver, load_at, factor: float, target: float,
                        measure) -> tuple[bool, int, float, float]:
        """Newton for the state and the load factor at which the displacement ``measure()``
        (linear in the unknowns: w0, or a mean settlement) is ``target``, from the committed
        state at ``factor``, the loads ``load_at(factor)``: (converged, iterations,
        out-of-balance, factor)."""
        m = self.model
        unknowns = m.unknowns if isinstance(m.unknowns, list) else [m.unknowns]
        lam = factor
        residual = math.inf
        history = []
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
            for u, x, dx in zip(unknowns, a, d):
                u.x.array[:] = x + step * dx
            lam += step
            m.set_loads(load_at(lam))
            self.plastic.update()
            residual = m.out_of_balance()
            if not math.isfinite(residual):
                return False, it, residual, lam
            history.append(residual)
            if residual <= self.TOLERANCE or self._at_round_off(history):
                return True, it, residual, lam
            first = residual if it == 1 else first
            if residual > self.DIVERGING * first:
                # (no line search here: a step whose out-of-balance force has grown so far
                # has left Newton's basin; measured, none came back)
                return False, it, residual, lam
        return False, self.max_iterations, residual, lam

    def _at_round_off(self, residuals: list[float]) -> bool:
        """Below ROUND_OFF and not halved over the last three iterations."""
        return (len(residuals) > 3 and residuals[-1] <= self.ROUND_OFF
                and residuals[-1] > 0.5 * residuals[-4])

    def _plastic_points(self) -> int:
        own = self.model.domain.mesh.topology.index_map(2).size_local * self.plastic.n_points
        return int(np.sum(self.plastic.yielding[:own]))

    def _newton(self, inner, max_iterations: int | None = None,
                stall: int | None = None) -> tuple[bool, int, float, str]:
        """Newton from the committed state under the loads set: (converged, iterations,
        the last out-of-balance force, why not). ``max_iterations`` (default the soil's);
        ``stall``: stop where the out-of-balance force has not halved over that many
        iterations (no equilibrium near: a collapse search's trial beyond the limit)."""
        m = self.model
        unknowns = m.unknowns if isinstance(m.unknowns, list) else [m.unknowns]
        max_iterations = max_iterations or self.max_iterations
        previous = m.out_of_balance()
        residuals = [previous]
        for it in range(1, max_iterations + 1):
            before = [u.x.array.copy() for u in unknowns]
            try:
                inner()
            except SolveError as e:
                return False, it, previous, f"the linear solve failed: {e}"
            after = [u.x.array.copy() for u in unknowns]
            alpha = 1.0
            for _ in range(self.LINE_SEARCH + 1):
                self.plastic.update()
                residual = m.out_of_balance()
                if residual < (1.0 - 1e-4 * alpha) * previous or residual <= self.TOLERANCE:
                    break
                alpha *= 0.5
                for u, a, b in zip(unknowns, before, after):
                    u.x.array[:] = a + alpha * (b - a)
            if not math.isfinite(residual):
                return False, it, residual, "the out-of-balance force is not finite"
            previous = residual
            residuals.append(residual)
            if residual <= self.TOLERANCE or self._at_round_off(residuals):
                return True, it, residual, ""
            if stall and it >= stall and residual > 0.5 * residuals[-1 - stall]:
                return False, it, residual, (
                    f"the out-of-balance force stalled at {residual:.2e}: not halved in "
                    f"{stall} iterations")
        return False, max_iterations, residual, (
            f"out-of-balance force {residual:.2e} after {max_iterations} iterations")

    def _failure(self, start, target, done: float, tried: float, reason: str) -> SoilFailure:
        """The soil cannot carry the stage's load: the last share carried and where the
        soil yields, in physical terms."""
        m = self.model
        P = m.applied_load
        a = m.scene.foundation_radius
        where = self._yielding_zone()
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
        error.carried = {"fraction_carried": done, "fraction_failed": tried,
                         "mean_bearing_pressure_carried": P / area,
                         "mean_bearing_pressure_failed": P_failed / area}
        return error

    def _yielding_zone(self) -> str:
        """Where the soil yields, in words (gathered over the ranks)."""
        comm = self.model.domain.mesh.comm
        p = self.plastic
        own = self.model.domain.mesh.topology.index_map(2).size_local
        flag = p.cell_average(p.plastic, 1)[:own, 0] > 0.5
        mid = self.model.domain.cell_midpoints[:own]
        pts = np.concatenate(comm.allgather(mid[flag]))
        if len(pts) == 0:
            return "no point of the soil had yet yielded"
        depth = -pts[:, 1]
        return (f"{len(pts)} cells yield, from r = {pts[:, 0].min():.3g} to "
                f"{pts[:, 0].max():.3g} m and down to {depth.max():.3g} m below the ground")
