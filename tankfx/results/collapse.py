"""The collapse's words and summary rows (results.json's ``collapse``:
:mod:`tankfx.iterations.collapse`; its chart is :func:`tankfx.results.charts.plot_collapse`)."""
from __future__ import annotations

from ..fem.failure import Failure


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
    return (f": beyond the settlement criterion, a mean settlement of "
            f"{record['failure_settlement']:.3g} m = 0.1 D, on a curve still rising slowly")


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
