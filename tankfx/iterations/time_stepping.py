"""Time stepping of Biot's consolidation (BDF2, steps growing geometrically per decade): the
load path in time, the steps, and the loop that solves each step and records the foundation's
settlement, the excess pore pressure and the isochrones.

Beyond the paper: no equation of it is carried out here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from mpi4py import MPI

from ..fem.blocks import cell_field
from ..fem.evaluate import evaluate_at, nodal_values_on_facets
from ..fem.solvers import SolveError
from ..laws.biot import stratum_coefficients
from ..scene.sections import load_between
from .status import CONVERGED, IterationStatus


def time_steps(times, first: float, per_decade: int) -> np.ndarray:
    """The ends of the time steps: ``per_decade`` steps per decade of time, geometric from
    ``first`` (s), through every time in ``times`` (s), ending at the last. Backward
    Euler's error is that of its largest steps relative to the time: uniform in log t. A
    step into a time that would be less than half the step before it is merged with that
    one into two equal steps (BDF2 is zero-stable only for step ratios below 1 + sqrt 2)."""
    times = np.sort(np.asarray(times, dtype=float))
    grid = [first]
    ratio = 10.0 ** (1.0 / per_decade)
    for t in times:
        while grid[-1] * ratio < t * (1.0 - 1e-9):
            grid.append(grid[-1] * ratio)
        if t > grid[-1] * (1.0 + 1e-9):
            if len(grid) > 1 and t - grid[-1] < 0.5 * (grid[-1] - grid[-2]):
                grid.pop()
                grid.append(0.5 * (grid[-1] + t))
            grid.append(t)
    return np.array(grid)


def load_path(scene) -> list[tuple[float, object]]:
    """The load as (time, Load) breakpoints, linear between them: [load] at t = 0 (at once)
    without stages; with them, from no load at t = 0 (the structure's weight only, and
    the liquid's unit weight: a tank fills) to each stage's load at its time (a time equal
    to the one before: at once)."""
    if not scene.stages:
        return [(0.0, scene.load)]
    first = scene.stages[0]
    start = replace(first, pressure=0.0, liquid_height=0.0, roof_weight=0.0,
                    gas_pressure=0.0)
    return [(0.0, start), *zip(scene.stage_times, scene.stages)]


def load_at(path, t: float):
    """The Load at time t > 0 (s) on a path of :func:`load_path`: its limit from before t
    (where the path jumps at t, the load before the jump: the jump is a step of its own)."""
    for (t0, a), (t1, b) in zip(path, path[1:]):
        if t0 < t <= t1:
            return load_between(a, b, (t - t0) / (t1 - t0))
    return path[-1][1]


def path_steps(path, times, per_decade: int) -> list[tuple[float, str, object]]:
    """The steps of a consolidation along a load path: (t, kind, load), kind "jump" (the
    load changes at once to ``load``: an undrained step of no time), "restart" (the first
    step after a breakpoint of the path: backward Euler, the load's rate having changed) or
    "step" (BDF2; these two with ``load`` None: the path's at t). Within each stretch
    between breakpoints (and after the last, to the last reported time, which the scene
    keeps at or after the last stage's) the steps grow geometrically from it,
    ``per_decade`` a decade, the first FIRST_STEP times the shortest of the stretch, the
    stretch before and the time to the next reported time, through every reported time;
    RAMP_STEP times it where the load does not jump at the stretch's start (a change of
    the load's rate: the pore pressure has no boundary layer in time to resolve there)."""
    t_end = max(max(times), path[-1][0])
    breaks = sorted({t for t, _ in path} | {t_end})
    jumps = {0.0} | {t for (t0, _), (t, _) in zip(path, path[1:]) if t == t0}
    out = [(0.0, "jump", ld) for t, ld in path if t == 0.0]
    for i, (b, e) in enumerate(zip(breaks, breaks[1:])):
        scales = [e - b] + [t - b for t in times if t > b] + \
            ([b - breaks[i - 1]] if i > 0 else [])
        targets = [t - b for t in times if b < t <= e] + [e - b]
        first = FIRST_STEP if b in jumps else RAMP_STEP
        steps = time_steps(targets, first * min(scales), per_decade)
        out += [(b + dt, "restart" if k == 0 else "step", None)
                for k, dt in enumerate(steps)]
        # the stages reached at once at this stretch's end, in the path's order
        out += [(e, "jump", ld) for (t0, _), (t, ld) in zip(path, path[1:]) if t == t0 == e]
    return out


#: the drained limit: one step this many times the foundation's consolidation time a^2 / c_v
#: (the excess pore pressure left is of the order of their ratio, relative to the load)
DRAINED_STEP = 1e10


#: the first time step after a load applied at once, as a fraction of the shortest of its
#: stretch, the stretch before and the time to the next reported time
FIRST_STEP = 1e-2
#: the first time step where the load's rate changes but the load does not jump (a filling
#: begins or ends), as the same fraction
RAMP_STEP = 0.2


DAY = 86400.0


class StepError:
    """The local error of a time step, estimated from the difference between the step's
    solution x and the quadratic predictor x_P through the stretch's last three states
    (Lagrange in t): BDF2's local error is -2/9 h^3 x''' and the predictor's h^3 x'''
    (equal steps), so the step's own is 2/7 |x - x_P|. Measured in the soil's displacement
    relative to its largest value now and in the excess pore pressure relative to its
    largest so far on the path (infinity norms over the owned dofs, collective), the larger of
    the two. A step is accepted where the estimate is at most REJECT times ``tolerance``,
    and the next is the step times SAFETY (tolerance / error)^(1/3), between SHRINK and GROW
    times it (BDF2 is zero-stable for step ratios below 1 + sqrt 2). The first two steps
    of a stretch (after a jump or a change of the load's rate) have no estimate: a
    predictor across a breakpoint has no meaning."""

    SAFETY, SHRINK, GROW, REJECT = 0.9, 0.25, 2.0, 2.0
    #: BDF2's local error over the corrector-predictor difference (equal steps)
    FACTOR = 2.0 / 7.0

    def __init__(self, tolerance: float, u, p):
        self.tolerance, self.u, self.p = tolerance, u, p
        self.comm = u.function_space.mesh.comm
        self._owned = [f.function_space.dofmap.index_map.size_local
                       * f.function_space.dofmap.index_map_bs for f in (u, p)]
        self.states: list[tuple] = []
        self.p_peak = 0.0

    def _now(self) -> tuple[np.ndarray, np.ndarray]:
        return tuple(f.x.array[:n].copy() for f, n in zip((self.u, self.p), self._owned))

    def restart(self, t: float) -> None:
        """A stretch begins at t: its first state is the state now."""
        self.states = [(t, *self._now())]

    def estimate(self, t: float) -> float | None:
        """The state now's (at t) local error relative to the tolerance's measures; None
        with fewer than three states in the stretch."""
        u, p = self._now()
        self.p_peak = max(self.p_peak, self.comm.allreduce(
            float(np.max(np.abs(p))) if len(p) else 0.0, op=MPI.MAX))
        if len(self.states) < 3:
            return None
        (t0, u0, p0), (t1, u1, p1), (t2, u2, p2) = self.states[-3:]
        w = (((t - t1) * (t - t2)) / ((t0 - t1) * (t0 - t2)),
             ((t - t0) * (t - t2)) / ((t1 - t0) * (t1 - t2)),
             ((t - t0) * (t - t1)) / ((t2 - t0) * (t2 - t1)))
        out = []
        for x, xs, scale in ((u, (u0, u1, u2), None), (p, (p0, p1, p2), self.p_peak)):
            local = float(np.max(np.abs(x - sum(wk * xk for wk, xk in zip(w, xs))))) \
                if len(x) else 0.0
            big = self.comm.allreduce(local, op=MPI.MAX)
            if scale is None:
                scale = self.comm.allreduce(float(np.max(np.abs(x))) if len(x) else 0.0,
                                            op=MPI.MAX)
            out.append(big / scale if scale > 0.0 else 0.0)
        return self.FACTOR * max(out)

    def accept(self, t: float) -> None:
        self.states = [*self.states[-2:], (t, *self._now())]

    def next_step(self, dt: float, error: float | None) -> float:
        """The step after one of ``dt`` whose error was ``error`` (None: unchanged)."""
        if error is None:
            return dt * self.GROW
        f = self.SAFETY * (self.tolerance / max(error, 1e-300)) ** (1.0 / 3.0)
        return dt * min(max(f, self.SHRINK), self.GROW)


@dataclass
class ConsolidationRun:
    """What a consolidation computed (:meth:`TimeStepping.run`): the states (w0, the
    settlements, the axis's pore pressure, ... at a time) of the drained limit, of each
    reported time (with the surface's profile) and of every step, the isochrones' pore
    pressures at the reported times, the steps taken, and the soil's c_v, time scale a^2 /
    c_v, the axis's depth and the isochrones' depths; a load path's state at each stage's
    time. :func:`tankfx.results.consolidation.consolidation_record` makes it results.json's
    ``consolidation``."""

    drained: dict
    at_times: list[dict]
    history: list[dict]
    isochrones: list
    steps: int
    c_v: float
    time_scale: float
    axis_depth: float
    isochrone_depths: np.ndarray
    at_stages: list[dict] | None = None
    #: at each reported time (t = 0 first): (t, the soil's displacement, the excess pore
    #: pressure, the yielding cells' DG0 flag or None), copies for the figures
    fields: list = None
    #: a fill schedule's record (results.json's ``fill``:
    #: :class:`tankfx.iterations.fill_schedule.FillSchedule`), None without a [fill]
    fill: dict | None = None


class TimeStepping:
    """Consolidation of a model whose soil block has a pore pressure (SoilBlock with a
    scene's [consolidation]): its drained limit, the undrained response at t = 0, then the
    steps through the reported times, each solved by ``inner()``. The model's fields end at
    the last reported time. Its status's ``data`` is the :class:`ConsolidationRun`."""

    name = "consolidation"
    #: the iterations inside a time step log at debug level: a table a step would drown
    #: the log
    quiet_inner = True

    @classmethod
    def build(cls, model, solver, how) -> "TimeStepping":
        return cls(model, solver)

    @staticmethod
    def describe(scene) -> str:
        """The time stepping in words (``tankfx check``)."""
        c = scene.consolidation
        steps = len(path_steps(load_path(scene), c.times, c.steps_per_decade)) - 1
        return (f"in time: the drained limit, the undrained start and {steps} time steps to "
                f"{c.times[-1] / 86400:.4g} days (a solve each)")

    def begin_stage(self) -> None:
        self.last = None

    #: called at every milestone of the path (each stage's time; without stages t = 0 and
    #: every reported time) on its converged state, the pore water held: its dict joins
    #: that milestone's state (a collapse study's factor of safety; None: nothing)
    milestone = None

    #: whether the last step was divided in parts (by a driver whose step did not converge
    #: whole): the next then restarts by backward Euler
    divided = False

    def __init__(self, model, solver):
        self.model = model
        self.last: IterationStatus | None = None
        # (a step of the path with no load left: see the solver's relative_to_largest_load)
        solver.relative_to_largest_load = True
        model._out_of_balance.relative_to_largest = True
        scene = model.scene
        self.c = scene.consolidation
        self.soil = model.soil
        _, c_v = stratum_coefficients(scene.consolidation, scene.soil.strata)
        #: the surface soil's c_v, m^2/s
        self.c_v = c_v[0]
        a = scene.foundation_radius
        #: a^2 / c_v, s: the foundation's consolidation time (surface soil's c_v)
        self.time_scale = a**2 / self.c_v
        #: the slowest stratum's: the drained limit's step is a multiple of it
        self.slowest_time_scale = a**2 / min(c_v)
        #: where the pore pressure is followed: on the axis, half a radius below the
        #: foundation (halfway to the base where that is nearer). The largest excess pore
        #: pressure is also reported, but at t = 0 it sits at the foundation's edge, where
        #: the undrained stress is singular (it grows as the mesh is refined there)
        D = scene.embedment
        #: the piezometers' points (r, z), where the excess pore pressure is followed
        self._piezometers = np.array([[r, -depth] for r, depth in self.c.piezometers],
                                     dtype=float).reshape(-1, 2)
        self.axis_depth = D + min(0.5 * a, 0.5 * (scene.domain.depth - D))
        self._axis_point = np.array([[0.0, -self.axis_depth]])
        #: the depths (m below the ground) of the isochrones: the pore pressure down the
        #: axis at each reported time, to 3 radii below the foundation (or the base)
        self.isochrone_depths = np.linspace(D, min(D + 3.0 * a, scene.domain.depth), 61)

    def _isochrone(self) -> list[float]:
        z = self.isochrone_depths
        return evaluate_at(self.soil.pore_pressure, np.column_stack([np.zeros_like(z), -z]),
                           cells=self.model.domain.cells("soil"))[:, 0].tolist()

    def _surface(self) -> dict:
        """The ground surface's settlement now (the foundation level under the foundation),
        out to 5 radii: for the settlement figure's curve per reported time."""
        domain, a = self.model.domain, self.model.scene.foundation_radius
        x, vals = nodal_values_on_facets(self.soil.u, domain.facets("contact", "surface"))
        keep = x[:, 0] <= 5.0 * a + 1e-12
        return {"r": x[keep, 0].tolist(), "w": (-vals[keep, 1]).tolist()}

    def _state(self, t: float) -> dict:
        found = self.model.foundation_results()
        p = self.soil.pore_pressure
        comm = p.function_space.mesh.comm
        n = p.function_space.dofmap.index_map.size_local
        local = float(np.max(p.x.array[:n])) if n else -np.inf

        axis = float(evaluate_at(p, self._axis_point,
                                 cells=self.model.domain.cells("soil"))[0, 0])
        state = {"t": t, "t_days": t / DAY, **{k: found[k] for k in ("w0", "w_edge", "wd",
                                                                      "w_mean", "M0")},
                 "max_pore_pressure": comm.allreduce(local, op=MPI.MAX),
                 "axis_pore_pressure": axis}
        if len(self._piezometers):
            state["piezometers"] = evaluate_at(
                p, self._piezometers, cells=self.model.domain.cells("soil"))[:, 0].tolist()
        return state

    def _snapshot(self, t: float) -> tuple:
        """(t, copies of the soil's displacement and excess pore pressure, the yielding
        cells' flag where the soil is elastoplastic, else None) for the figures."""
        soil = self.soil
        u, p = soil.u.copy(), soil.pore_pressure.copy()
        plastic = getattr(soil, "plastic", None)
        flag = None
        if plastic is not None:
            flag = cell_field(self.model.domain.mesh,
                              plastic.cell_average(plastic.plastic, 1)[:, 0], "plastic")
        return t, u, p, flag

    def _held(self, call):
        """``call()`` on the state now with the pore water held (undrained: no flow, the
        volume of the state now kept), the time stepping's previous states given back
        afterwards."""
        soil = self.soil
        earlier = soil.u_n.x.array.copy(), soil.u_nn.x.array.copy()
        soil.u_n.x.array[:] = soil.u.x.array
        soil.step_weights.set(1.0, 0.0, False)
        soil.conductance.value = 0.0
        try:
            return call()
        finally:
            soil.u_n.x.array[:], soil.u_nn.x.array[:] = earlier

    def _solve(self, dt_eff: float, t: float | None = None) -> None:
        """One step (``inner()``: a Mohr-Coulomb interface converged in it); a step that
        does not converge says when, with the interface's history."""

        self.soil.conductance.value = dt_eff / self.c.water_unit_weight
        try:
            self._inner()
        except SolveError as e:
            when = "the drained limit" if t is None else f"t = {t / DAY:.6g} days"
            raise SolveError(f"consolidation, at {when} (load {self.model.applied_load:.6g} "
                             f"N): {e}", e.history, code=e.code) from None

    def _step(self, t: float, kind: str, load, path, t_prev: float,
              dt_prev: float) -> tuple[dict, float]:
        """One step of :func:`path_steps` to t (s) from the state at t_prev, whose step was
        dt_prev: its state (recorded in the history) and its length."""
        soil = self.soil
        self._advance()
        if kind == "jump":
            # the load changes at once: undrained (no flow in a step of no time)
            self._set_loads(load)
            soil.step_weights.set(1.0, 0.0, False)
            self._solve(0.0, t)
            dt = 0.0
        else:
            self._set_loads(load_at(path, t))
            dt = t - t_prev
            # (a step after one divided in parts restarts: its predecessor's dt is not the
            # step before's)
            restart = kind == "restart" or self.divided
            self.divided, self.span = False, (t_prev, t, path)
            self._solve(soil.step_weights.set(dt, 0.0 if restart else dt_prev, True), t)
        state = self._state(float(t))
        state["applied_load"] = self.model.applied_load
        state["liquid_height"] = self.model.scene.load.liquid_height
        self.history.append(state)
        return state, dt

    def _advance(self) -> None:
        soil = self.soil
        soil.u_nn.x.array[:] = soil.u_n.x.array
        soil.u_n.x.array[:] = soil.u.x.array

    def _set_loads(self, load) -> None:
        model = self.model
        model.set_loads(load)
        # the equilibrium errors are relative to the path's largest load (its last may be
        # none: a tank emptied)
        model.path_load_scale = model.load_scale      # (the largest so far: see load_scale)

    def _drained(self, load) -> dict:
        """The drained limit under ``load`` (the path's last), from rest; the fields back at
        rest afterwards. A linear skeleton's does not depend on the path: one step of
        DRAINED_STEP consolidation times."""
        soil = self.soil
        self._set_loads(load)
        soil.step_weights.set(1.0, 0.0, False)
        self._solve(DRAINED_STEP * self.slowest_time_scale)
        # (t = infinity: null in results.json, which takes no infinities)
        drained = self._state(0.0) | {"t": None, "t_days": None, "surface": self._surface()}
        for f in (soil.u, soil.u_n, soil.u_nn):
            f.x.array[:] = 0.0
        return drained

    #: whether the time steps are chosen by their local error (:class:`StepError`): an
    #: elastoplastic skeleton's (a linear one's grid is verified against Terzaghi's closed
    #: form at its steps per decade)
    controlled = False
    #: a step rejected this many times in a row (each at most SHRINK times the one before)
    #: is taken as it is, said in the log
    MAX_REJECTIONS = 8

    def _step_error(self) -> StepError | None:
        if not self.controlled:
            return None
        return StepError(self.c.time_tolerance, self.soil.u, self.soil.pore_pressure)

    def _unknown_fields(self) -> list:
        u = self.model.unknowns
        return u if isinstance(u, list) else [u]

    def _keep_step(self) -> dict:
        """The state before a step (what a rejected step goes back to)."""
        soil = self.soil
        return {"values": [f.x.array.copy() for f in self._unknown_fields()],
                "u_n": soil.u_n.x.array.copy(), "u_nn": soil.u_nn.x.array.copy(),
                "history": len(self.history), "divided": self.divided}

    def _back_step(self, kept: dict) -> None:
        soil = self.soil
        for f, x in zip(self._unknown_fields(), kept["values"]):
            f.x.array[:] = x
        soil.u_n.x.array[:], soil.u_nn.x.array[:] = kept["u_n"], kept["u_nn"]
        del self.history[kept["history"]:]
        self.divided = kept["divided"]

    def run(self, inner, log) -> IterationStatus:
        self._inner, self._log = inner, log
        c, model = self.c, self.model
        scene = model.scene
        path = load_path(scene)
        # the drained limit first, under the path's last load, from rest (it does not
        # depend on the path: a linear skeleton)
        drained = self._drained(path[-1][1])
        log.info("consolidation: drained limit w0 = %s (c_v = %.3g m^2/s, a^2 / c_v = "
                 "%.3g days)", "not carried" if drained["w0"] is None else
                 f"{drained['w0']:.4g} m", self.c_v, self.time_scale / DAY)
        steps = path_steps(path, c.times, c.steps_per_decade)
        reported = {float(t) for t in c.times}
        milestones = {float(t) for t in scene.stage_times} if scene.stages else \
            reported | {0.0}
        found: dict[float, dict] = {}
        history, at_times, isochrones, t_prev, dt_prev = [], [], [], 0.0, 0.0
        snapshots: list = []
        #: the states of the steps that converged (what a failed step keeps)
        self.history = history
        control = self._step_error()
        grid = {float(t) for t, _, _ in steps}
        k, proposal, rejected = 0, math.inf, 0
        while k < len(steps):
            t, kind, load = steps[k]
            if control is not None and kind == "step" and t - t_prev > proposal * (1 + 1e-9):
                # (shorter than the grid's step, by the error: a step of its own before the
                # grid's point; no sliver of one after it)
                t = t_prev + (proposal if t - t_prev > 1.5 * proposal else 0.5 * (t - t_prev))
                steps.insert(k, (t, "step", None))
            kept = self._keep_step() if control is not None else None
            state, dt = self._step(t, kind, load, path, t_prev, dt_prev)
            if control is not None:
                error = control.estimate(t) if kind == "step" else None
                if error is not None and error > control.REJECT * control.tolerance \
                        and rejected < self.MAX_REJECTIONS:
                    # (rejected: the state before it back, a shorter step tried)
                    self._back_step(kept)
                    proposal, rejected = control.next_step(dt, error), rejected + 1
                    self._log.debug("consolidation: the step to t = %.6g days rejected, its "
                                    "local error %.3g of the tolerance", t / DAY,
                                    error / control.tolerance)
                    if float(t) not in grid:
                        steps.pop(k)
                    continue
                if error is not None and error > control.REJECT * control.tolerance:
                    self._log.warning("warning: consolidation: the step to t = %.6g days taken "
                                      "after %d shorter tries, its local error %.3g of the "
                                      "tolerance", t / DAY, rejected, error / control.tolerance)
                if kind == "jump":
                    control.restart(t)
                else:
                    if kind == "restart":
                        # (the stretch begins at the step's start)
                        control.states = control.states[-1:]
                    control.accept(t)
                proposal, rejected = control.next_step(dt, error) if dt > 0.0 else math.inf, 0
            last_at_t = k + 1 == len(steps) or steps[k + 1][0] != t
            if last_at_t and t in milestones and self.milestone is not None:
                found[float(t)] = self._held(self.milestone) or {}
            if last_at_t and (t in reported or t == 0.0):
                # (the reported states also carry the surface's profile; the history not)
                state = state | {"surface": self._surface()} | found.get(float(t), {})
                at_times.append(state)
                isochrones.append(self._isochrone())
                snapshots.append(self._snapshot(float(t)))
                log.info("consolidation: t = %.4g days, w0 = %.4g m, excess pore pressure "
                         "on the axis %.4g Pa (step %d of %d)", t / DAY, state["w0"],
                         state["axis_pore_pressure"], k + 1, len(steps))
            t_prev, dt_prev = t, dt
            k += 1
        run = ConsolidationRun(
            drained=drained, at_times=at_times, history=history, isochrones=isochrones,
            steps=len(steps) - 1, c_v=self.c_v, time_scale=self.time_scale,
            axis_depth=self.axis_depth, isochrone_depths=self.isochrone_depths,
            fields=snapshots,
            at_stages=[[h for h in history if h["t"] == t][-1] | found.get(float(t), {})
                       for t in scene.stage_times] if scene.stages else None)
        self.last = IterationStatus(
            True, len(steps) - 1, history, f"{len(steps) - 1} time steps to the last reported "
            f"time", CONVERGED, {}, data=run)
        return self.last
