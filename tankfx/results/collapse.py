"""results.json's ``collapse`` and ``bounds``, from what the collapse search
(:mod:`tankfx.iterations.collapse`) and the limit analysis (:mod:`tankfx.bounds`) found, and
their words and summary rows (the chart is :func:`tankfx.results.charts.plot_collapse`)."""
from __future__ import annotations

import math

import numpy as np

from ..fem.evaluate import evaluate_at
from ..fem.failure import Failure
from ..scene.sections import vertical_load

#: the knee of a collapse's curve: where its slope has fallen below this share of its first
KNEE_SLOPE = 0.05
#: the mechanism is "base" where the last increment's settlement at the axis is at least
#: this share of its largest under the foundation, else "edge"
BASE_SHARE = 0.5


def collapse_record(outcome, scene) -> dict:
    """results.json's ``collapse`` of a collapse search's outcome
    (:class:`tankfx.iterations.collapse.CollapseOutcome`): the factor and its bracket, the
    knee of the curve, why the last trial failed, the curve, the bearing pressure at the
    factor (and N_c = q / s_u where the law has an undrained strength), the mechanism.
    Collective (the mechanism is evaluated on every rank)."""
    o, a = outcome, scene.foundation_radius
    knee = curve_knee(o.curve)
    out = {"kind": o.kind, "found": o.found,
           f"{o.kind}_factor": o.factor, "bracket": list(o.bracket) if o.bracket else None,
           "knee_factor": knee[0] if knee else None, "knee_bracket": knee,
           "reason": o.reason, "bracket_width": o.bracket_width,
           # (which failure bracketed it: no equilibrium, or the settlement criterion)
           "failure": o.failure,
           "failure_settlement": o.failure_settlement,
           "curve": {k: [p[k] for p in o.curve] for k in ("factor", "mean_settlement")},
           "steps": len(o.curve) - 1, "iterations": o.iterations, "time_s": o.time_s}
    q = vertical_load(o.load, scene.plate, scene.wall, scene.ringwall) / (math.pi * a ** 2)
    out["bearing_pressure"] = q
    s_u = scene.soil.law.undrained_strength(scene.soil, scene.embedment)
    if s_u is not None and o.kind == "load":
        out["N_c"] = q / s_u
        out["undrained_strength"] = s_u
    if o.increment is not None:
        out["mechanism"] = mechanism(o.increment, a, scene.embedment)
    return out


def curve_knee(curve: list[dict]) -> list[float] | None:
    """The two factors of a collapse's curve between which its slope (factor per mean
    settlement) first falls below KNEE_SLOPE of its first: where the ground's mechanism
    has formed (a flexible tank's edge punching in), what its slowly rising tail
    (contained plastic flow) carries beyond; None where it does not fall so far."""
    F = np.array([p["factor"] for p in curve])
    w = np.array([p["mean_settlement"] for p in curve])
    if len(F) < 3:
        return None
    slope = np.diff(F) / np.maximum(np.diff(w), 1e-300)
    low = np.flatnonzero(slope < KNEE_SLOPE * slope[0])
    return [float(F[low[0]]), float(F[low[0] + 1])] if len(low) else None


def mechanism(increment, a: float, depth: float) -> dict:
    """The collapse mechanism's kind from the last increment of the soil's displacement
    under the foundation (r from 0 to a at its underside): "base" where the settlement
    increment at the axis is at least BASE_SHARE of its largest there (the whole foundation
    punches in), else "edge" (the ground gives way under its edge, its centre held back:
    the plastic zone that fails does not reach the axis). Collective."""
    r = np.linspace(0.0, a, 41)
    dw = -evaluate_at(increment, np.column_stack([r, np.full_like(r, -depth)]))[:, 1]
    largest = float(np.max(dw))
    share = float(dw[0] / largest) if largest > 0.0 else 0.0
    return {"kind": "base" if share >= BASE_SHARE else "edge", "axis_share": share,
            "largest_at_r": float(r[int(np.argmax(dw))]),
            "rule": f"base where the last increment's settlement at the axis is at least "
                    f"{BASE_SHARE:g} of its largest under the foundation, else edge"}


def bounds_record(scene, run, elastoplastic: dict | None) -> dict:
    """results.json's ``bounds`` of a limit analysis' run
    (:class:`tankfx.bounds.scene_bounds.BoundsRun`), with the elastoplastic collapse by
    load of the same scene (its record) set beside them."""
    notes, associated = scene.soil.law.limit_notes(scene.soil)
    out = {"lower": run.lower, "upper": run.upper, "gap": run.gap,
           "requested_gap": scene.analysis.bounds_gap,
           "reached": run.gap <= scene.analysis.bounds_gap,
           "triangles": run.triangles, "rounds": run.rounds, "time_s": run.time_s,
           "box": {**run.box, "far_margin": run.far_margin},
           "lower_check": {"equilibrium_residual": run.equilibrium_residual,
                           "yield_violation": run.yield_violation},
           "foundation": (f"tank, its floor {scene.analysis.bounds_floor}"
                          if scene.wall is not None else
                          "rigid" if scene.plate is not None else "flexible load"),
           "contact": "smooth" if scene.interface.condition == "smooth" else "rough",
           "solver": run.solver, "notes": notes}
    if elastoplastic is not None and elastoplastic.get("found"):
        F = elastoplastic["load_factor"]
        out["elastoplastic_factor"] = F
        out["elastoplastic_between"] = bool(run.lower <= F <= run.upper)
        out["elastoplastic_position"] = ("between" if out["elastoplastic_between"] else
                                         "above" if F > run.upper else "below")
        out["elastoplastic_failure"] = elastoplastic.get("failure")
        out["associated"] = associated
    return out


def collapse_factor(record: dict) -> float:
    """The factor a collapse search found (on the loads, or on the strength)."""
    return record[f"{record['kind']}_factor"]


def collapse_words(record: dict) -> str:
    """One sentence: the factor, its bracket, the mechanism (or why none was found)."""
    kind = record["kind"]
    what = "load factor" if kind == "load" else "strength factor"
    F = collapse_factor(record)
    if not record["found"]:
        knee = (f"; the curve's knee at {record['knee_factor']:.4g}"
                if record.get("knee_factor") else "")
        return (f"no collapse bracketed ({record['reason']}); the {what} {F:.4g} was carried, "
                f"a lower bound{knee}")
    lo, hi = record["bracket"]
    out = f"{what} {lo:.4g} (the ground carries {lo:.4g}, fails at {hi:.4g}{_how(record)})"
    if "N_c" in record:
        out += f", N_c = q / s_u = {record['N_c']:.3f}"
    if "mechanism" in record:
        out += f", mechanism: {record['mechanism']['kind']}"
    return out


def _how(record: dict) -> str:
    """How the failed state failed, where it was the settlement criterion."""
    if record.get("failure") != Failure.SETTLEMENT:
        return ""
    since = " more than where the reduction began" if record.get("kind") == "strength" else ""
    return (f": beyond the settlement criterion, a mean settlement of "
            f"{record['failure_settlement']:.3g} m = 0.1 D{since}, on a curve still rising "
            f"slowly")


def _knee_row(c: dict, tail: str) -> list[tuple[str, str, str]]:
    """The knee's row, where the curve has one."""
    if not c.get("knee_bracket"):
        return []
    lo, hi = c["knee_bracket"]
    return [("the ground's mechanism forms at", f"{lo:.4g}",
             f"the curve's knee: its slope falls below 5 % of its first between {lo:.4g} and "
             f"{hi:.4g}; beyond it, contained plastic flow{tail}")]


def collapse_rows(r: dict) -> list[tuple[str, str, str]]:
    """The summary's rows of a collapse search."""
    c = r.get("collapse")
    if not c:
        return []
    kind = c["kind"]
    name = "factor of safety on the loads" if kind == "load" else \
        "factor of safety on the strength"
    F = collapse_factor(c)
    if not c["found"]:
        rows = [(name, f">= {F:.4g}", f"a lower bound, not bracketed: {c['reason']}")]
        rows += _knee_row(c, "")
        if "mechanism" in c:
            rows.append(("collapse mechanism", c["mechanism"]["kind"], c["mechanism"]["rule"]))
        return rows
    lo, hi = c["bracket"]
    rows = [(name, f"{lo:.4g}", f"carried at {lo:.4g}, not at {hi:.4g}{_how(c)} "
                                f"({'c and tan phi divided by it' if kind == 'strength' else 'variable loads times it, self-weight held'})")]
    if c.get("failure") == Failure.SETTLEMENT:
        rows += _knee_row(c, " up to the settlement criterion")
    rows.append(("bearing pressure at collapse", f"{c['bearing_pressure'] / 1e3:.4g} kPa",
                 "mean, vertical load over the foundation's area"
                 + (f"; N_c = q / s_u = {c['N_c']:.3f} (s_u = "
                    f"{c['undrained_strength'] / 1e3:.4g} kPa at its level)" if "N_c" in c
                    else "")))
    if "mechanism" in c:
        m = c["mechanism"]
        rows.append(("collapse mechanism", m["kind"],
                     f"the last increment's settlement at the axis is {m['axis_share']:.2f} of "
                     f"its largest (at r = {m['largest_at_r']:.3g} m); {m['rule']}"))
    return rows


def bounds_words(b: dict) -> str:
    """One sentence: the bracket of limit analysis, and the elastoplastic factor in it."""
    out = (f"the ground fails between {b['lower']:.4g} and {b['upper']:.4g} times the variable "
           f"loads (gap {100 * b['gap']:.2g} %, {b['triangles']} triangles)")
    if "elastoplastic_factor" in b:
        out += (f"; the elastoplastic analysis says {b['elastoplastic_factor']:.4g}"
                + elastoplastic_against_bounds(b))
    return out


def elastoplastic_against_bounds(b: dict) -> str:
    """Where the elastoplastic factor lies against the bounds, and why where it is not
    between them (a clause, empty where it is)."""
    where = b["elastoplastic_position"]
    if where == "between":
        return ""
    if where == "above":
        return (", above the upper bound: its displacement elements overestimate the "
                "collapse load on this mesh (a finer mesh.edge_size and near_size, or a "
                "higher mesh.degree, brings it down)")
    if b.get("elastoplastic_failure") == Failure.SETTLEMENT:
        return (", below the lower bound: it failed by the settlement criterion (0.1 D) "
                "before the plastic limit")
    if not b.get("associated", True):
        return (", below the lower bound: its soil's flow is not associated (psi < phi), "
                "and such a soil fails below the associated one's limit")
    return ", below the lower bound"


def bounds_rows(r: dict) -> list[tuple[str, str, str]]:
    """The summary's rows of the limit analysis' bounds."""
    b = r.get("bounds")
    if not b:
        return []
    rows = [("collapse factor, lower bound", f"{b['lower']:.4g}",
             "limit analysis: a statically admissible stress field carries it"),
            ("collapse factor, upper bound", f"{b['upper']:.4g}",
             "limit analysis: a kinematically admissible mechanism fails at it"),
            ("gap of the bounds", f"{100 * b['gap']:.3g} %",
             f"(upper - lower) / lower on {b['triangles']} triangles, asked "
             f"{100 * b['requested_gap']:.3g} %" + ("" if b["reached"] else ": not reached "
                                                    "within analysis.bounds_cells"))]
    if "elastoplastic_factor" in b:
        rows.append(("elastoplastic factor against the bounds",
                     f"{b['elastoplastic_factor']:.4g}",
                     elastoplastic_against_bounds(b).lstrip(", ") or "between them"))
    rows += [("bounds: note", "-", note) for note in b["notes"]]
    return rows
