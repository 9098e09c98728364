"""results.json's ``consolidation``: a consolidation's states in time
(:class:`tankfx.iterations.time_stepping.ConsolidationRun`) with each state's degree of
consolidation U = (w0 - w0_undrained) / (w0_drained - w0_undrained) and time factor
Tv = t c_v / a^2, the isochrones, and how it was integrated."""
from __future__ import annotations

from ..iterations.time_stepping import DRAINED_STEP, FIRST_STEP, RAMP_STEP, ConsolidationRun
from ..scene.sections import Consolidation


def consolidation_record(run: ConsolidationRun, c: Consolidation) -> dict:
    """The record of a consolidation ``run`` of the scene's [consolidation] ``c``."""
    start, drained = run.at_times[0], run.drained     # t = 0: the loads applied at once
    w_u, w_d = start["w0"], drained["w0"]

    def degree(state):
        if w_d is None:
            return None         # (the drained skeleton does not carry the last load)
        return (state["w0"] - w_u) / (w_d - w_u) if w_d != w_u else 1.0

    # (the reported states and the stages' are copies)
    for state in run.history + run.at_times + (run.at_stages or []):
        state["degree"] = degree(state)
        state["Tv"] = state["t"] / run.time_scale
    drained["degree"], drained["Tv"] = 1.0, None
    drained["applied_load"] = None
    out = {"times": list(c.times), "degree": run.at_times[-1]["degree"],
           "undrained": start, "drained": drained,
           "at_times": run.at_times, "history": run.history,
           "c_v": run.c_v, "time_scale": run.time_scale, "axis_depth": run.axis_depth,
           "isochrones": {"z": run.isochrone_depths.tolist(),
                          "t_days": [s["t_days"] for s in run.at_times],
                          "pore_pressure": run.isochrones},
           "steps": run.steps, "permeability": c.permeability,
           "drainage": c.drainage,
           "integrator": "undrained at t = 0 (and at each load applied at once), then "
                         "backward Euler once and variable-step BDF2, "
                         f"{c.steps_per_decade} steps a decade from {FIRST_STEP:g} x "
                         "the first reported time (restarted at each breakpoint of a "
                         f"load path, from {RAMP_STEP:g} x its stretch where the load "
                         "does not jump); the drained limit as one step of "
                         f"{DRAINED_STEP:g} a^2 / c_v"}
    if c.piezometers:
        out["piezometers"] = {
            "points": [list(x) for x in c.piezometers],
            "t_days": [s["t_days"] for s in run.history],
            "excess_pore_pressure": [s["piezometers"] for s in run.history]}
    if run.at_stages is not None:
        # each stage's state when its load is reached (after any jump there)
        out["at_stages"] = run.at_stages
    factors = [s for s in run.at_stages or run.at_times if "collapse" in s]
    if factors:
        # (the path's critical milestone: where the factor of safety is least)
        low = min(factors, key=lambda s: s["collapse"]["strength_factor"])
        out["min_strength_factor"] = low["collapse"]["strength_factor"]
        out["min_strength_factor_t_days"] = low["t_days"]
    return out
