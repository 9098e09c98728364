"""The safe fill of a tank on a consolidating plastic soil (``[fill]``): how fast may it be
filled? The liquid rises in steps of ``step`` at ``rate``; before each step the schedule
holds the level just long enough (bisected to ``HOLD_RESOLUTION`` days) that the factor of
safety on the soil's strength at the end of that step's filling, the pore water held (a
failure is sudden: undrained), is at least ``target_factor``.

The search, on the path of :class:`tankfx.iterations.plastic_consolidation.PlasticConsolidation`
(Newton in every time step, the pore pressure beside the skeleton):

1. **Unheld**: the tank filled at the rate with no hold, from the undrained start of its own
   weight, with the factor of safety (a full strength-reduction search) at each step's end:
   the smallest is ``unheld_factor``. Where the ground fails while filling (no equilibrium,
   or the mean settlement past 0.1 D) the factor there is 1 (the strength fully mobilised).
2. **Schedule**: the unheld steps whose factor reaches the target are the schedule's (no
   hold). From the first that does not, each step starts from the state its predecessor
   left: a fill with no hold is tried first (a step after a hold may not need one); where
   its check fails, holds of 1, 2, 4, ... days are tried, the hold continued from the
   longest one tried below it (one hold is one consolidation under a constant load, its
   states reused), then the hold bisected between the longest that fails and the shortest
   that passes down to ``HOLD_RESOLUTION``. The check is the strength-reduction search
   through the target (:meth:`tankfx.iterations.collapse.CollapseSearch.by_strength`: its
   own ladder of trials, none above the target until the target is carried): it ends where
   it brackets a failure below the target; where it carries the target it goes on to the
   step's factor (``strength_factor``, at least the target). Each hold tried is in
   ``holds_tried`` with its factor.
3. Where a hold would pass ``max_days``, the schedule stops at the highest level reached
   safely and says why.
"""
from __future__ import annotations

import time
from dataclasses import replace

from .newton import criterion_words
from .plastic_consolidation import PlasticConsolidation
from .status import IterationStatus, CONVERGED, SoilFailure
from .time_stepping import DAY, RAMP_STEP, ConsolidationRun, time_steps

#: the holds are bisected until the longest that fails and the shortest that passes are
#: this close, days
HOLD_RESOLUTION = 0.5
#: the first hold tried, days (then doubled until one passes)
FIRST_HOLD = 1.0
#: a hold this many times the slowest stratum's a^2 / c_v has drained the clay under the
#: tank: a step whose check a hold as long does not pass is short of the target at its
#: rate. Measured on a rigid 1 m footing on a frictional clay (impervious under the
#: foundation, drained at the surface beside it): the next step's factor still rose by 3 %
#: between holds of 8 and 16 a^2 / c_v
DRAINED_HOLD = 20.0
#: the factor of safety of each step is bracketed to this (relative): the schedule's
#: decision is its check at the target; the factor shows the margin. The last 0.5 % of a
#: bracket costs its slowest trials (Newton near the limit)
FACTOR_BRACKET = 0.02


class FillSchedule(PlasticConsolidation):
    """The fill schedule's search on a model whose soil block holds a plastic state and a
    pore pressure. The analysis gives it its two questions: :attr:`milestone` (the factor of
    safety now: a collapse study's search by strength, also through a target: the check)
    and :attr:`study` (the findings it reports); both are asked with the pore water
    held."""

    #: the collapse study whose findings the schedule reports (set by the analysis)
    study = None

    @staticmethod
    def describe(scene) -> str:
        f = scene.fill
        return (f"in time: the safe fill to {f.height:g} m in {len(f.heights)} steps of "
                f"{f.step:g} m at {f.rate:g} m/day, each after the shortest hold (to "
                f"{HOLD_RESOLUTION:g} day) that keeps the factor of safety on the strength at "
                f"its end, undrained, at least {f.target_factor:g}; each time step by Newton's "
                f"method on the elastoplastic skeleton and the pore pressure")

    def __init__(self, model, solver):
        super().__init__(model, solver)
        #: the scene's fill, and the full tank's load (the schedule's loads are it with
        #: the liquid's height changed)
        self.fill = model.scene.fill
        self._full = model.scene.load

    # ---- the state a search returns to ---------------------------------------------------
    def _keep(self) -> dict:
        """The whole state now: the unknowns and the points' committed state, the
        time stepping's previous states, the load, the time and the history."""
        nw, soil = self.newton, self.soil
        return {"histories": [h.snapshot() for h in nw.histories()], "values": nw.values(),
                "u_n": soil.u_n.x.array.copy(), "u_nn": soil.u_nn.x.array.copy(),
                "load": self.model.scene.load, "t": self._t, "dt": self._dt_prev,
                "stretch": self._stretch, "history": list(self.history)}

    def _back(self, kept: dict) -> None:
        nw, soil = self.newton, self.soil
        for h, s in zip(nw.histories(), kept["histories"]):
            h.restore(s)
        self._set_loads(kept["load"])
        nw.restore_values(kept["values"])
        soil.u_n.x.array[:], soil.u_nn.x.array[:] = kept["u_n"], kept["u_nn"]
        self._t, self._dt_prev, self._stretch = kept["t"], kept["dt"], kept["stretch"]
        self.history = list(kept["history"])
        # (the next step restarts by backward Euler: a kept state's step before may not be
        # the next one's)
        self.divided = True

    # ---- the path ----------------------------------------------------------------------------
    def _at(self, height: float):
        return replace(self._full, liquid_height=height)

    def _segment(self, t1: float, load1) -> None:
        """From the state now (its time, its load) to t1 (s), the load linear to ``load1``:
        steps growing geometrically, ``steps_per_decade`` a decade, from RAMP_STEP times
        the shorter of this stretch and the one before (the load's rate changes, it does
        not jump)."""
        t0 = self._t
        path = [(t0, self.model.scene.load), (t1, load1)]
        first = RAMP_STEP * min(t1 - t0, self._stretch or (t1 - t0))
        t_prev, dt_prev = t0, self._dt_prev
        for k, dt in enumerate(time_steps([t1 - t0], first, self.c.steps_per_decade)):
            t = t0 + float(dt)
            _, step = self._step(t, "restart" if k == 0 else "step", None, path, t_prev,
                                 dt_prev)
            t_prev, dt_prev = t, step
        self._t, self._dt_prev, self._stretch = t1, dt_prev, t1 - t0

    def _fill_to(self, height: float) -> tuple[bool, str]:
        """The liquid raised at the rate to ``height`` from the state now: (whether the
        ground carried it, why not)."""
        rise = height - self.model.scene.load.liquid_height
        try:
            self._segment(self._t + rise / self.fill.rate * DAY, self._at(height))
        except SoilFailure as e:
            return False, f"the ground fails while the tank fills to {height:g} m: {e}"
        return True, ""

    def _checked(self) -> tuple[bool, str, dict, object]:
        """The check at the end of a step, the pore water held: the factor of safety
        searched along a ladder whose trials stop at the target on their way up (the
        search by strength ``through`` it): where it brackets a failure below the target
        it ends there, as a check; where it carries the target it goes on, and its factor
        is the step's, at least the target by construction (searched again from 1, the
        ladder may differ at the target itself: measured 1.296 against a check that had
        carried 1.3). (whether it reaches the target, why not, its record, its
        findings)."""
        self.checks += 1
        target = self.fill.target_factor
        collapse = self._factor(target)
        F = collapse.get("strength_factor")
        ok = F is not None and F >= target * (1.0 - 1e-12)
        why = "" if ok else (f"the factor of safety is {F:.4g} ({collapse.get('reason')})"
                             if F is not None else "no factor of safety was found")
        return ok, why, collapse, self.study.findings()

    def _factor(self, through: float | None = None) -> dict:
        """The factor of safety now, the pore water held: the collapse study's record
        (``through``: along the check's ladder at that factor)."""
        return (self._held(lambda: self.milestone(FACTOR_BRACKET, through))
                or {}).get("collapse", {})

    # ---- the search ----------------------------------------------------------------------------
    def run(self, inner, log):
        self._inner, self._log = inner, log
        f, t_start = self.fill, time.perf_counter()
        self._t, self._dt_prev, self._stretch, self.history = 0.0, 0.0, None, []
        self.checks, self.fills = 0, 0
        drained = self._drained(self._full)
        log.info("fill: the drained limit of the full tank w0 = %s",
                 "not carried" if drained["w0"] is None else f"{drained['w0']:.4g} m")
        # t = 0: the empty tank's own weight, at once (undrained)
        self._step(0.0, "jump", self._at(0.0), [(0.0, self._at(0.0))], 0.0, 0.0)
        start = self._milestone_state(None)
        heights = f.heights
        unheld, ends, first_short = self._unheld(heights, log)
        self._ends, self._first_short = list(ends), first_short
        schedule = [self._entry(h, 0.0, end) for h, end in zip(heights, ends)]
        reason, complete = "", True
        if first_short is not None:
            self._back(ends[first_short - 1]["kept"] if first_short else start["kept"])
            for k in range(first_short, len(heights)):
                entry, why = self._step_with_hold(k, heights, log)
                if entry is None:
                    reason, complete = why, False
                    break
                schedule.append(entry)
        reached = schedule[-1]["height"] if schedule else 0.0
        record = self._record(schedule, unheld, reached, complete, reason, t_start)
        self._finish(start, schedule, drained, record, log)
        return self.last

    def _milestone_state(self, collapse: dict | None) -> dict:
        """The state now as a milestone of the path: its record (with its factor of
        safety, where searched), its surface and isochrone, its fields for the figures, and
        the whole state kept."""
        state = self.history[-1] | {"surface": self._surface()}
        if collapse:
            state["collapse"] = collapse
        return {"state": state, "isochrone": self._isochrone(),
                "fields": self._snapshot(self._t), "kept": self._keep(),
                "findings": self.study.findings() if collapse else None}

    def _unheld(self, heights, log) -> tuple[list, list, int | None]:
        """The tank filled at the rate with no hold, the factor of safety at each step's
        end: (each step's height, end day and factor; the milestones of the steps whose
        factor reaches the target, in order, up to the first that does not; its index, or
        None where every step's does)."""
        f = self.fill
        unheld, ends, first_short = [], [], None
        for k, h in enumerate(heights):
            ok, why = self._fill_to(h)
            self.fills += 1
            if not ok:
                failed_at = self.model.scene.load.liquid_height
                unheld.append({"height": failed_at, "day": self._failed_day(),
                               "strength_factor": 1.0, "fails": True, "reason": why})
                log.info("fill, no holds: %s", why)
                first_short = len(ends) if first_short is None else first_short
                break
            collapse = self._factor()
            F = collapse.get("strength_factor")
            unheld.append({"height": h, "day": self._t / DAY, "strength_factor": F,
                           "fails": False})
            log.info("fill, no holds: %.4g m at day %.4g, factor of safety %.4g", h,
                     self._t / DAY, F)
            if first_short is None:
                if F is not None and F >= f.target_factor:
                    ends.append(self._milestone_state(collapse))
                else:
                    first_short = k
        return unheld, ends, first_short

    def _failed_day(self) -> float:
        """The day of the last step that converged before a failure."""
        return self.history[-1]["t_days"] if self.history else 0.0

    def _entry(self, height: float, hold: float, end: dict, attempts=()) -> dict:
        """One step of the schedule (``end``: its milestone)."""
        s = end["state"]
        # (its start to a nanoday: the first step's, its end less its days, was 2e-16)
        return {"height": height,
                "fill_start_day": round(s["t_days"] - self._fill_days(height), 9),
                "fill_end_day": s["t_days"], "hold_days": hold,
                "strength_factor": s.get("collapse", {}).get("strength_factor"),
                "holds_tried": list(attempts), "w0": s["w0"], "w_edge": s["w_edge"]}

    def _fill_days(self, height: float) -> float:
        """The days a step to ``height`` fills (from the height of the step before)."""
        heights = (0.0, *self.fill.heights)
        k = heights.index(height)
        return (height - heights[k - 1]) / self.fill.rate

    def _step_with_hold(self, k: int, heights, log) -> tuple[dict | None, str]:
        """Step k of the schedule from the state now: no hold where its check passes, else
        the shortest hold (doubled, then bisected) after which it does; its entry, or None
        and why where none within ``max_days`` does."""
        f, h = self.fill, heights[k]
        here = self._keep()
        t0 = self._t / DAY
        fill_days = self._fill_days(h)
        latest = f.max_days - fill_days - t0        # the longest hold max_days allows
        holds = {0.0: here}                         # hold (days) -> the state after it
        passed, failed, why, attempts = {}, [], "", []

        def attempt(hold: float) -> bool:
            nonlocal why
            base = max(x for x in holds if x <= hold)
            self._back(holds[base])
            if hold > base:
                try:
                    self._segment((t0 + hold) * DAY, self.model.scene.load)
                except SoilFailure as e:
                    why = f"the ground fails while held at {heights[k - 1] if k else 0:g} m: {e}"
                    return False
                holds[hold] = self._keep()
            ok, why = self._fill_to(h)
            self.fills += 1
            collapse = findings = None
            if ok:
                ok, why, collapse, findings = self._checked()
            F = (collapse or {}).get("strength_factor")
            log.info("fill: step to %.4g m after a hold of %.4g days (day %.4g): %s", h, hold,
                     t0 + hold, f"factor of safety {F:.4g}, at least the target" if ok
                     else why)
            attempts.append({"hold_days": hold, "passed": ok, "strength_factor": F})
            if ok:
                passed[hold] = (self._keep(), collapse, findings)
            else:
                failed.append(hold)
            return ok

        if k != self._first_short:
            if attempt(0.0):
                return self._accept(h, 0.0, passed[0.0], attempts, log), ""
        else:
            # (the unheld path's own step from this state: its factor is short)
            failed.append(0.0)
        hold = FIRST_HOLD
        drained = DRAINED_HOLD * self.slowest_time_scale / DAY
        while True:
            if max(failed) >= drained:
                return None, self._drained_short(h, max(failed), why)
            if hold > latest:
                if latest <= max(failed) or latest <= 0.0:
                    return None, self._too_long(h, t0, fill_days, why)
                hold = latest
            if attempt(hold):
                break
            hold *= 2.0
        while min(passed) - max(failed) > HOLD_RESOLUTION * (1.0 + 1e-9):
            mid = 0.5 * (min(passed) + max(failed))
            attempt(mid)
        best = min(passed)
        return self._accept(h, best, passed[best], attempts, log), ""

    def _accept(self, height: float, hold: float, end: tuple, attempts: list, log) -> dict:
        """The step that passed, from its end's state (``end``: the state, and its check's
        record and findings: its factor of safety)."""
        kept, collapse, findings = end
        self._back(kept)
        self.study.keep(findings)
        milestone = self._milestone_state(collapse)
        self._ends.append(milestone)
        entry = self._entry(height, hold, milestone, attempts)
        log.info("fill: step to %.4g m after a hold of %.4g days, filled by day %.4g; factor "
                 "of safety %.4g", height, hold, entry["fill_end_day"],
                 entry["strength_factor"] or float("nan"))
        return entry

    def _drained_short(self, height: float, hold: float, why: str) -> str:
        f = self.fill
        return (f"a hold of {hold:.4g} days ({hold * DAY / self.slowest_time_scale:.3g} times "
                f"a^2 / c_v: the clay under the tank has drained) does not give the step to "
                f"{height:g} m a factor of safety of {f.target_factor:g} at {f.rate:g} m/day "
                f"({why}): a longer hold adds nothing; fill more slowly or in smaller steps")

    def _too_long(self, height: float, t0: float, fill_days: float, why: str) -> str:
        f = self.fill
        return (f"the step to {height:g} m needs a hold beyond max_days = {f.max_days:g} "
                f"(from day {t0:.4g}, with {fill_days:.4g} days of filling, a hold of at most "
                f"{max(f.max_days - fill_days - t0, 0.0):.4g} days fits; after the longest "
                f"tried, {why}); raise fill.max_days, or fill more slowly")

    def _record(self, schedule, unheld, reached, complete, reason, t_start) -> dict:
        f = self.fill
        low = min(unheld, key=lambda u: u["strength_factor"]) if unheld else None
        return {
            "schedule": schedule, "target_factor": f.target_factor, "rate": f.rate,
            "step": f.step, "height": f.height, "max_days": f.max_days,
            "complete": complete, "reached_height": reached, "reason": reason,
            "total_days": schedule[-1]["fill_end_day"] if schedule else 0.0,
            "unheld_factor": None if low is None else low["strength_factor"],
            "unheld_height": None if low is None else low["height"],
            "unheld_fails": bool(unheld and unheld[-1]["fails"]), "unheld": unheld,
            "hold_resolution_days": HOLD_RESOLUTION,
            "checks": self.checks, "fills_tried": self.fills,
            "newton_iterations": self.iterations, "time_s": time.perf_counter() - t_start}

    def _finish(self, start, schedule, drained, record, log) -> None:
        """The model at the schedule's last accepted state; its ConsolidationRun: the
        states of the accepted path, its milestones (t = 0 and each step's end)."""
        milestones = [start, *self._ends]
        self._back(milestones[-1]["kept"])
        # (the study reports the last accepted state's factor, not the last one tried)
        self.study.keep(milestones[-1]["findings"])
        history = milestones[-1]["kept"]["history"]
        at_times = [m["state"] for m in milestones]
        run = ConsolidationRun(
            drained=drained, at_times=at_times, history=history,
            isochrones=[m["isochrone"] for m in milestones], steps=len(history) - 1,
            c_v=self.c_v, time_scale=self.time_scale, axis_depth=self.axis_depth,
            isochrone_depths=self.isochrone_depths, fields=[m["fields"] for m in milestones],
            at_stages=at_times[1:] or None, fill=record)
        nw = self.newton
        log.info("fill: %s", fill_words(record))
        self.last = IterationStatus(
            True, len(history) - 1, history, f"the fill schedule: {len(schedule)} steps",
            CONVERGED, {"converged": True, "iterations": self.iterations,
                        "time_steps": len(history) - 1,
                        "criterion": f"every time step by Newton, {criterion_words()}",
                        **nw.yielding_record()},
            data=run)


def fill_words(record: dict) -> str:
    """A fill schedule's outcome in a sentence (the log, the summary)."""
    holds = [s for s in record["schedule"] if s["hold_days"] > 0.0]
    unheld = (f"filled at {record['rate']:g} m/day without holds "
              + (f"the ground fails at {record['unheld_height']:.4g} m"
                 if record["unheld_fails"] else
                 f"the least factor of safety is {record['unheld_factor']:.3g} (at "
                 f"{record['unheld_height']:.4g} m)"))
    if not record["complete"]:
        return (f"{unheld}; safely only to {record['reached_height']:.4g} m: "
                f"{record['reason']}")
    return (f"{unheld}; the safe schedule fills to {record['height']:g} m in "
            f"{record['total_days']:.4g} days with {len(holds)} hold(s) "
            f"({', '.join(f'{s['hold_days']:g} d before {s['height']:g} m' for s in holds) or 'none'}),"
            f" every step's factor of safety at least {record['target_factor']:g}")


__all__ = ["FillSchedule", "HOLD_RESOLUTION", "fill_words"]
