"""Line charts of the results, drawn with matplotlib (its object API on the Agg canvas: no
pyplot, no global state, no display).

Why matplotlib and not PyVista's charts for these: an engineer reads a line chart by its
axes, and matplotlib gives full control of them (units on every axis, ticks at round
numbers, axes of their own for quantities of different size, limits set from the data
with nothing clipped unless said), annotations (a clipped peak's value, the Mohr-Coulomb
limit, a stated scale) and print-quality text; it is already installed with PyVista. The
section and the 3D views stay PyVista's (tankfx.results.figures).

Every chart is built on rank 0 from the gathered results (``results.json``'s dict) and
returned as a matplotlib ``Figure`` by a ``*_chart`` function (which the tests inspect),
and written by the matching ``plot_*`` function, a no-op on the other ranks.

Robust ranges: a contact stress has a singular peak at the plate's edge, which would set
the axis and flatten the rest. Its axis stops at :func:`robust_limit` (a stated level
above the body of the values); a value beyond is drawn at the axis, marked, and its value
written beside it.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from ..fem.failure import Failure
from ..laws.mohr_coulomb import shear_strength
from ..scene.sections import STATES_CONDITION
from .figure_choices import CHARTABLE, DEFAULT_CHARTS, numeric_axes
from .report import MULTIPLES

#: the charts' size per panel, inches, and resolution
PANEL = (6.0, 4.2)
DPI = 130
COLORS = ["tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple", "tab:brown",
          "tab:pink", "tab:gray", "tab:olive", "tab:cyan"]
#: a robust limit is this many times the 95th percentile of the values' sizes, where the
#: largest exceeds it (else the largest: nothing is clipped)
ROBUST_FACTOR = 1.5
ROBUST_PERCENTILE = 95.0


def _rank0() -> bool:
    from mpi4py import MPI

    return MPI.COMM_WORLD.rank == 0


def figure(panels: int = 1, rows: int = 1, sharey: bool = False,
           size=PANEL) -> tuple[Figure, list]:
    """A figure of ``panels`` axes side by side (``rows`` rows of them)."""
    cols = int(np.ceil(panels / rows))
    # (at least 8 inches wide: a figure of one column reads as well as one of several)
    width, height = max(size[0] * cols, 8.0), size[1] * rows
    fig = Figure(figsize=(width, height), dpi=DPI)
    FigureCanvasAgg(fig)
    # fixed margins, in inches, for the labels (a layout engine draws every figure twice:
    # it took 40 % of a chart's time)
    left, right, bottom, top, gap_w, gap_h = 0.85, 0.4, 0.62, 0.42, 0.95, 0.8
    axes_w = (width - left - right - (cols - 1) * gap_w) / cols
    axes_h = (height - bottom - top - (rows - 1) * gap_h) / rows
    fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height,
                        top=1 - top / height, wspace=gap_w / axes_w, hspace=gap_h / axes_h)
    axes = fig.subplots(rows, cols, sharey=sharey, squeeze=False).ravel().tolist()
    for ax in axes[panels:]:
        ax.set_visible(False)
    for ax in axes[:panels]:
        ax.grid(True, color="0.9")
        ax.xaxis.set_major_locator(MaxNLocator(6))
        ax.yaxis.set_major_locator(MaxNLocator(6))
    return fig, axes[:panels]


def save(fig: Figure, path) -> Path:
    path = Path(path)
    fig.savefig(path, dpi=DPI)
    return path


def robust_limit(values) -> tuple[float, bool]:
    """The axis limit for the sizes of ``values`` and whether it clips any: the largest
    size, unless it exceeds ROBUST_FACTOR x the ROBUST_PERCENTILE-th percentile (a
    singular peak at an edge), which is then the limit."""
    size = np.abs(np.asarray(values, dtype=float))
    size = size[np.isfinite(size)]
    if size.size == 0:
        return 1.0, False
    largest = float(size.max())
    level = ROBUST_FACTOR * float(np.percentile(size, ROBUST_PERCENTILE))
    if level > 0.0 and largest > level:
        return level, True
    return largest or 1.0, False


def clipped_line(ax, x, y, limit: float, label: str, color: str, unit: str,
                 **kwargs) -> None:
    """Plot y(x) within +-limit: values beyond are drawn at the limit, marked with a
    triangle, and the largest of them written beside it ("peak 1,210 kPa, clipped")."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    shown = np.clip(y, -limit, limit)
    ax.plot(x, shown, color=color, label=label, **kwargs)
    over = np.abs(y) > limit
    if over.any():
        ax.plot(x[over], shown[over], linestyle="none", marker="^", color=color, ms=6)
        k = int(np.argmax(np.abs(np.where(over, y, 0.0))))
        ax.annotate(f"peak {y[k]:,.0f} {unit}\n(clipped at {np.sign(y[k]) * limit:,.0f})",
                    xy=(x[k], shown[k]), xytext=(-8, -6 if y[k] > 0 else 6),
                    textcoords="offset points", ha="right",
                    va="top" if y[k] > 0 else "bottom", fontsize=8, color=color)


def _margin(lo: float, hi: float, zero: bool = True) -> tuple[float, float]:
    """Axis limits around [lo, hi] with a margin (through zero where ``zero``)."""
    if zero:
        lo, hi = min(lo, 0.0), max(hi, 0.0)
    span = (hi - lo) or max(abs(hi), 1.0)
    return lo - 0.06 * span, hi + 0.06 * span


def settlement_chart(results: dict, title: str = "") -> Figure:
    """The settlement profile w(r) (mm) along the foundation and the ground beyond it out to
    5 radii, the undeformed line, the plate (where there is one) and the wall's foot; for a
    load path, one curve per stage; for a consolidation, one per reported time and the
    drained limit."""
    fig, (ax,) = figure(1, size=(8.0, 4.6))
    sc = results["scene"]
    surf = results["profiles"]["surface"]
    r, w = np.asarray(surf["r"]), 1e3 * np.asarray(surf["w"])
    ax.axhline(0.0, color="0.4", lw=1, ls="--", label="undeformed ground")
    drawn = [w]

    def curve(profile, label, **style):
        values = 1e3 * np.asarray(profile["w"])
        ax.plot(profile["r"], values, label=label, **style)
        drawn.append(values)

    stages = results.get("stages") or []
    for k, st in enumerate(stages[:-1]):
        if "surface" in st:
            curve(st["surface"], f"stage {st['stage']}", color=COLORS[k % len(COLORS)],
                  lw=1.2, alpha=0.8)
    c = results.get("consolidation")
    if c:
        # a consolidation: the surface at each reported time, and the drained limit
        for k, state in enumerate(c["at_times"][:-1]):
            if "surface" in state:
                curve(state["surface"], f"t = {state['t_days']:.3g} days",
                      color=COLORS[k % len(COLORS)], lw=1.2)
        if "surface" in c["drained"]:
            curve(c["drained"]["surface"], "drained limit", color="0.3", lw=1.2, ls=":")
    last = (f" (stage {stages[-1]['stage']})" if stages else
            f" (t = {c['at_times'][-1]['t_days']:.4g} days)" if c else "")
    ax.plot(r, w, color="black", lw=2, label="ground surface" + last)
    if "plate" in results["profiles"]:
        curve(results["profiles"]["plate"], "plate", color="tab:blue", lw=3, alpha=0.6)
    if "wall" in sc:
        at = sc["wall"]["radius"]
        foot = float(np.interp(at, r, w))
        ax.plot([at], [foot], marker="s", color="tab:red", ms=8, ls="none",
                label=f"wall's foot, {foot:.1f} mm")
    values = np.concatenate(drawn)
    ax.set_ylim(*_margin(float(values.min()), float(values.max()))[::-1])   # down is down
    ax.set_xlim(0.0, float(r.max()))
    ax.set_xlabel("r [m]")
    ax.set_ylabel("settlement w [mm] (down)")
    ax.set_title(f"{title}: settlement" if title else "settlement")
    ax.legend(fontsize=8, loc="lower right")
    return fig


def plot_settlement(results: dict, path, title: str = "") -> Path | None:
    return save(settlement_chart(results, title), path) if _rank0() else None


def plot_surface_settlement(results: dict, path, *, reference=None,
                            title: str = "") -> Path | None:
    """The settlement profile (as :func:`plot_settlement`), with an optional reference
    curve ``reference(r) -> w`` (m) beside it."""
    if not _rank0():
        return None
    fig = settlement_chart(results, title)
    if reference is not None:
        ax = fig.axes[0]
        rr = np.linspace(0.0, max(results["profiles"]["surface"]["r"]), 60)
        ax.plot(rr, 1e3 * np.asarray(reference(rr)), ls="none", marker="o", ms=4,
                color="tab:red", label="closed form")
        ax.legend(fontsize=8, loc="lower right")
    return save(fig, path)


def contact_chart(results: dict, title: str = "") -> Figure:
    """The contact normal and shear stress (kPa) along the plate's underside (and the
    embedded wall's face), each on its own axes: the normal stress's edge peak clipped at a
    stated level with its value written; the shear beside the Mohr-Coulomb limit c +
    sigma_n tan phi; slipping, separated and rebonded stations marked."""
    sc = results["scene"]
    ifc = sc.get("interface", {})
    mc = ifc.get("condition") == STATES_CONDITION
    parts = [("plate", "r [m]", "r", "plate underside")]
    if "contact_status" in results["profiles"].get("wall", {}):
        parts.append(("wall", "height above the base z [m]", "z", "embedded wall face"))
    fig, axes = figure(2 * len(parts), rows=2)
    cols = len(parts)
    for col, (part, xlabel, xkey, where) in enumerate(parts):
        prof = results["profiles"][part]
        status = np.asarray(prof["contact_status"])
        keep = status != "none"
        x = np.asarray(prof[xkey], dtype=float)[keep]
        sn = np.asarray(prof["contact_normal"], dtype=float)[keep] / 1e3
        tau = np.asarray(prof["contact_shear"], dtype=float)[keep] / 1e3
        status = status[keep]
        top, bottom = axes[col], axes[cols + col]
        limit, _ = robust_limit(sn)
        clipped_line(top, x, sn, limit, "normal (compression +)", "tab:green", "kPa", lw=2)
        top.set_ylim(*_margin(max(-limit, sn.min()), min(limit, sn.max())))
        top.set_ylabel("normal stress [kPa]")
        top.set_title(f"{title}: {where}" if title else where)
        shear_values = [tau]
        if mc:
            c = ifc.get("cohesion", 0.0) / 1e3
            bound = shear_strength(np.clip(sn, -limit, limit), c, ifc["tan_phi"])
            bottom.plot(x, bound, color="black", lw=1, ls="--", label="c + sigma_n tan phi")
            bottom.plot(x, -bound, color="black", lw=1, ls="--")
            shear_values.append(bound)
        t_limit, _ = robust_limit(np.concatenate(shear_values))
        clipped_line(bottom, x, tau, t_limit, "shear", "tab:purple", "kPa", lw=2)
        values = np.clip(np.concatenate(shear_values), -t_limit, t_limit)
        bottom.set_ylim(*_margin(values.min(), values.max()))
        bottom.set_ylabel("shear stress [kPa]")
        for state, color in (("slip", "tab:orange"), ("separated", "tab:gray"),
                             ("rebonded", "tab:cyan")):
            sel = status == state
            if sel.any():
                for ax in (top, bottom):
                    ax.plot(x[sel], np.zeros(sel.sum()), ls="none", marker="o", ms=5,
                            color=color, label=f"{state} ({sel.sum()} stations)"
                            if ax is bottom else None)
        for ax in (top, bottom):
            ax.set_xlabel(xlabel)
            ax.set_xlim(float(x.min()), float(x.max()))
            ax.legend(fontsize=8, loc="best")
    return fig


def plot_contact(results: dict, path, title: str = "") -> Path | None:
    return save(contact_chart(results, title), path) if _rank0() else None


def structure_chart(results: dict, title: str = "") -> Figure:
    """The plate's moments M_r, M_theta against r, and the wall's moment M_z, hoop force
    N_theta (for a wall of courses also its hoop stress) and shear Q against the height,
    each on axes of their own."""
    plate = results["profiles"]["plate"]
    wall = results["profiles"].get("wall")
    courses = len(results.get("courses", [])) > 1
    n = 1 + (0 if wall is None else 3 + courses)
    fig, axes = figure(n, rows=2 if n > 3 else 1)
    ax = axes[0]
    r = np.asarray(plate["r"])
    ax.plot(r, np.asarray(plate["M_r"]) / 1e3, color="tab:blue", lw=2, label="M_r")
    ax.plot(r, np.asarray(plate["M_theta"]) / 1e3, color="tab:orange", lw=2, label="M_theta")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel("r [m]")
    ax.set_ylabel("plate moment [kN m/m] (sagging +)")
    ax.set_title(f"{title}: plate" if title else "plate")
    ax.set_xlim(0.0, float(r.max()))
    ax.legend(fontsize=8)
    if wall is not None:
        z = np.asarray(wall["z"])
        series = [("M_z [kN m/m] (outer face in tension +)", np.asarray(wall["M_z"]) / 1e3,
                   "tab:blue"),
                  ("N_theta [kN/m] (tension +)", np.asarray(wall["N_theta"]) / 1e3, "tab:red"),
                  ("Q [kN/m]", np.asarray(wall["Q"]) / 1e3, "tab:green")]
        if courses:
            series.insert(2, ("hoop stress N_theta / t [MPa]",
                              np.asarray(wall["hoop_stress"]) / 1e6, "tab:purple"))
        for ax, (label, values, color) in zip(axes[1:], series):
            ax.plot(values, z, color=color, lw=2)
            ax.axvline(0.0, color="0.5", lw=0.8)
            ax.set_xlabel(label)
            ax.set_ylabel("height above the base z [m]")
            ax.set_ylim(0.0, float(z.max()))
            ax.set_xlim(*_margin(float(values.min()), float(values.max())))
            ax.set_title("wall")
    return fig


def plot_structure_profiles(results: dict, path, title: str = "") -> Path | None:
    return save(structure_chart(results, title), path) if _rank0() else None


def curves_chart(x, panels: dict[str, dict[str, np.ndarray]], x_label: str,
                 title: str = "", log_x: bool = False, legend_left: bool = False,
                 second: dict[str, tuple[str, np.ndarray]] | None = None) -> Figure:
    """Side-by-side line charts against one x: ``panels`` maps each panel's y label to its
    curves (label -> y values, NaN where a curve has none; a curve of one value is drawn
    as a dashed level across the chart, e.g. a limit). ``second`` maps a panel's y label
    to a curve on its second (right) axis: (that axis' label, y values), drawn grey."""
    x = np.asarray(x, dtype=float)
    fig, axes = figure(len(panels))
    for col, (ax, (y_label, curves)) in enumerate(zip(axes, panels.items())):
        if second and y_label in second:
            label, y = second[y_label]
            right = ax.twinx()
            right.plot(x, np.asarray(y, dtype=float), color="0.55", lw=1.5, ls="--")
            right.set_ylabel(f"{label} (dashed)", color="0.4")
        lo, hi = np.inf, -np.inf
        for k, (name, y) in enumerate(curves.items()):
            y = np.asarray(y, dtype=float)
            color = COLORS[k % len(COLORS)]
            if y.size == 1:
                ax.axhline(float(y[0]), color=color, lw=1.2, ls="--", label=name)
                values = y
            else:
                ok = np.isfinite(y)
                ax.plot(x[ok], y[ok], color=color, lw=2, marker="o" if ok.sum() < 25 else None,
                        ms=4, label=name)
                values = y[ok]
            if values.size:
                lo, hi = min(lo, float(values.min())), max(hi, float(values.max()))
        if np.isfinite(lo):
            ax.set_ylim(*_margin(lo, hi, zero=False))
        if log_x:
            ax.set_xscale("log")
        ax.set_xlabel(x_label)
        ax.set_ylabel(y_label)
        ax.set_title(f"{title}" if col == 0 and title else "")
        ax.legend(fontsize=8, loc="upper left" if legend_left else "best")
    return fig


def plot_curves(x, panels: dict[str, dict[str, np.ndarray]], path, x_label: str,
                title: str = "", log_x: bool = False, legend_left: bool = False,
                second: dict[str, tuple[str, np.ndarray]] | None = None) -> Path | None:
    """:func:`curves_chart` written to ``path`` (rank 0)."""
    if not _rank0():
        return None
    return save(curves_chart(x, panels, x_label, title, log_x, legend_left, second), path)


def axis_scale(values, unit: str) -> tuple[float, str]:
    """The factor and unit a scene key's values are shown in (Pa in MPa for moduli)."""
    largest = max((abs(float(v)) for v in values), default=0.0)
    for factor, name in MULTIPLES.get(unit, ()):
        if largest >= factor:
            return 1.0 / factor, name
    return 1.0, "" if unit in ("", "-") else unit


def sweep_chart(rows: list[dict], axes: dict, x_key: str, y_keys, x_unit: str = "",
                title: str = "") -> Figure:
    """The results ``y_keys`` against the sweep's axis ``x_key`` (in its unit, scaled to a
    readable multiple; logarithmic over two decades or more), one curve per value of the
    other axes, every point inside its axes."""
    others = [k for k in axes if k != x_key]
    groups: dict[tuple, list[dict]] = {}
    for row in rows:
        if row.get("converged"):
            groups.setdefault(tuple(row[k] for k in others), []).append(row)
    values = np.asarray(axes[x_key], dtype=float)
    use_log = bool(np.all(values > 0) and values.max() / values.min() >= 100)
    factor, unit = axis_scale(values, x_unit)
    fig, panels = figure(len(y_keys))
    for col, (ax, key) in enumerate(zip(panels, y_keys)):
        what, y_factor, y_unit = CHARTABLE[key]
        lo, hi = np.inf, -np.inf
        for g, (group, members) in enumerate(sorted(groups.items(), key=lambda kv: str(kv[0]))):
            members = sorted((m for m in members if m.get(key) is not None),
                             key=lambda m: m[x_key])
            if not members:
                continue
            x = np.array([m[x_key] for m in members], dtype=float) * factor
            y = np.array([m[key] for m in members], dtype=float) * y_factor
            name = ", ".join(f"{k} = {v}" for k, v in zip(others, group)) or None
            ax.plot(x, y, color=COLORS[g % len(COLORS)], lw=2, marker="o", ms=5, label=name)
            lo, hi = min(lo, float(y.min())), max(hi, float(y.max()))
        if np.isfinite(lo):
            ax.set_ylim(*_margin(lo, hi, zero=False))
        if use_log:
            ax.set_xscale("log")
            ax.set_xlim(values.min() * factor / 1.3, values.max() * factor * 1.3)
        else:
            ax.set_xlim(*_margin(values.min() * factor, values.max() * factor, zero=False))
        ax.set_xlabel(f"{x_key}" + (f" [{unit}]" if unit else ""))
        ax.set_ylabel(what + (f" [{y_unit}]" if y_unit else ""))
        if col == 0 and title:
            ax.set_title(title)
        if others:
            ax.legend(fontsize=8)
    return fig


def plot_sweep(rows: list[dict], axes: dict, path, title: str = "", x_key: str | None = None,
               y_keys=None, x_unit: str = "") -> Path | None:
    """The sweep's chart (rank 0): ``y_keys`` (default DEFAULT_CHARTS, and the tilt where
    the cases overturn) against ``x_key`` (default the first numeric axis); None when no
    axis is numeric."""
    if not _rank0() or not rows:
        return None
    numeric = numeric_axes(axes)
    x_key = x_key or (numeric[0] if numeric else None)
    if x_key is None:
        return None
    if y_keys is None:
        y_keys = list(DEFAULT_CHARTS)
        if any(row.get("M0") is None for row in rows if row.get("converged")):
            y_keys.remove("M0")
        if any(row.get("overturning.tilt") is not None for row in rows):
            y_keys.append("overturning.tilt")
    return save(sweep_chart(rows, axes, x_key, y_keys, x_unit, title), path)


def plot_collapse(results: dict, path: str | Path, title: str = "") -> Path | None:
    """The factor against the foundation's mean settlement along the collapse search, and
    the bracket's failed factor as what it is: a dashed level labelled with the failure (no
    equilibrium found, or the settlement criterion), not a curve. Rank 0 writes the PNG."""
    c = results.get("collapse")
    if not c or not _rank0():
        return None
    x = 1e3 * np.asarray(c["curve"]["mean_settlement"])
    label = "load factor" if c["kind"] == "load" else "strength factor (c, tan phi divided)"
    fig, (ax,) = figure(1)
    ax.plot(x, np.asarray(c["curve"]["factor"]), marker="o", markersize=3, label=label)
    if c["found"]:
        ax.axhline(c["bracket"][1], color="C3", linestyle="--", linewidth=1.0,
                   label=f"failed at {c['bracket'][1]:.4g}: {failure_words(c.get('failure'))}")
    ax.set_xlabel("mean settlement of the foundation [mm]")
    ax.set_ylabel("factor [-]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right", fontsize="small")
    if title:
        ax.set_title(title)
    return save(fig, path)


def fill_chart(results: dict, title: str = "") -> Figure:
    """A fill schedule (results.json's ``fill``): the liquid's height against days, the
    safe schedule (its holds flat) beside the fill at the rate with no hold; and the factor
    of safety at each step's end, both ways, against the target."""
    f = results["fill"]
    history = results["consolidation"]["history"]
    fig, (ax_h, ax_f) = figure(2)
    days = [s["t_days"] for s in history]
    ax_h.plot(days, [s["liquid_height"] for s in history], color=COLORS[0], lw=2,
              label=f"safe schedule ({f['total_days']:.4g} days)" if f["complete"] else
              f"safe schedule (to {f['reached_height']:.4g} m)")
    unheld = f["unheld"]
    ax_h.plot([0.0] + [u["day"] for u in unheld], [0.0] + [u["height"] for u in unheld],
              color=COLORS[1], lw=1.5, ls="--", marker="o", ms=4,
              label=f"no holds, {f['rate']:g} m/day" + (" (fails)" if f["unheld_fails"]
                                                        else ""))
    ax_h.set_xlabel("time [days]")
    ax_h.set_ylabel("liquid height [m]")
    ax_h.legend(fontsize=8, loc="lower right")
    if title:
        ax_h.set_title(title)
    steps = [s for s in f["schedule"] if s["strength_factor"] is not None]
    ax_f.plot([s["fill_end_day"] for s in steps], [s["strength_factor"] for s in steps],
              color=COLORS[0], lw=2, marker="o", ms=5, label="safe schedule, each step's end")
    ax_f.plot([u["day"] for u in unheld], [u["strength_factor"] for u in unheld],
              color=COLORS[1], lw=1.5, ls="--", marker="x", ms=6,
              label="no holds (1: the ground fails)")
    ax_f.axhline(f["target_factor"], color=COLORS[2], lw=1.2, ls="--",
                 label=f"target {f['target_factor']:g}")
    ax_f.axhline(1.0, color="0.5", lw=1.0, ls=":")
    ax_f.set_xlabel("time [days]")
    ax_f.set_ylabel("factor of safety on the strength, undrained [-]")
    ax_f.legend(fontsize=8, loc="best")
    return fig


def plot_fill(results: dict, path, title: str = "") -> Path | None:
    """:func:`fill_chart` written to ``path`` (rank 0); None without a fill schedule."""
    if "fill" not in results or not _rank0():
        return None
    return save(fill_chart(results, title), path)


def failure_words(failure: str | None) -> str:
    """How a collapse search's failed trial failed, for a legend."""
    return {Failure.SETTLEMENT: "the settlement criterion (0.1 D)",
            Failure.NO_EQUILIBRIUM: "no equilibrium"}.get(failure, failure or "failed")


def plot_bounds(results: dict, mechanism: dict, path: str | Path, extent: float,
                title: str = "", elastoplastic=None) -> Path | None:
    """The limit analysis: the elastoplastic collapse mechanism (its last increment,
    ``elastoplastic`` at the mechanism's points, where given) beside the upper bound's (each
    scaled to its largest speed, over the refined triangles), and the two bounds against
    the number of triangles with the elastoplastic factor. Rank 0 writes the PNG."""
    b = results.get("bounds")
    if not b or mechanism is None or not _rank0():
        return None
    import matplotlib.tri as mtri

    views = ([("elastoplastic: the last increment", np.asarray(elastoplastic))]
             if elastoplastic is not None else [])
    views.append(("upper bound's mechanism", np.asarray(mechanism["velocity"])))
    fig, axes = figure(len(views) + 1)
    pts, cells = mechanism["points"], mechanism["cells"]
    grid = mtri.Triangulation(pts[:, 0], pts[:, 1], cells)
    for ax, (name, u) in zip(axes, views):
        speed = np.hypot(*u.T)
        top = robust_limit(speed)[0] or 1.0
        shade = ax.tripcolor(grid, speed / top, shading="gouraud", cmap="viridis",
                             vmin=0.0, vmax=1.0)
        ax.triplot(grid, color="white", linewidth=0.15, alpha=0.4)
        ax.set_xlim(0.0, extent)
        ax.set_ylim(-extent, 0.0)
        ax.set_aspect("equal")
        ax.set_xlabel("r [m]")
        ax.set_ylabel("z [m]")
        ax.set_title(f"{name}: |u| / its largest", fontsize=9)
    fig.colorbar(shade, ax=axes[len(views) - 1], shrink=0.8)
    ax2 = axes[-1]
    rounds = b["rounds"]
    n = [r["cells"] for r in rounds]
    ax2.plot(n, [r["upper"] for r in rounds], "v-", color=COLORS[0], label="upper bound")
    ax2.plot(n, [r["lower"] for r in rounds], "^-", color=COLORS[1], label="lower bound")
    if "elastoplastic_factor" in b:
        ax2.axhline(b["elastoplastic_factor"], color=COLORS[2], linestyle="--",
                    label="elastoplastic (by load)")
    ax2.set_xscale("log")
    ax2.set_xlabel("triangles")
    ax2.set_ylabel("factor on the variable loads")
    ax2.legend(fontsize=8)
    ax2.set_title(f"the bounds refined: gap {100 * b['gap']:.3g} %", fontsize=9)
    if title:
        fig.suptitle(title, fontsize=10)
    return save(fig, path)
