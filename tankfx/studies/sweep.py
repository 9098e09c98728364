"""Parametric studies: ``tankfx sweep SWEEP.toml --out DIR``.

A sweep file names a base scene and the keys to vary::

    base = "embedded_tank.toml"          # relative to the sweep file
    mode = "grid"                        # every combination ("grid") or one list ("zip")
    [axes]
    "plate.Kp" = [0.01, 0.1, 1.0, 10.0]
    "interface.condition" = ["bonded", "smooth"]

Every case is validated before any is run (a bad key or value refuses the whole sweep).
Under ``mpiexec -n N`` the cases are dealt out over the ranks, each solved on its own
communicator (``MPI.COMM_SELF``). Each case's results are written atomically to
``DIR/cases/NNNN.json`` as it finishes; a sweep started again skips the cases already
written, so an interrupted sweep resumes without redoing or losing any. At the end rank 0
writes ``DIR/table.csv`` (one row a case: its axis values and the results) and
``DIR/charts.png``: the results a ``[charts]`` table names against its axis, in their units
(by default w0, wd and M0, in mm and kN m/m, against the first numeric axis)::

    [charts]
    x = "soil.E"                            # an axis of the sweep
    y = ["w0", "wd", "nondim.w0"]           # results (tankfx.results.figure_choices.CHARTABLE)
"""
from __future__ import annotations

import csv
import itertools
import json
import logging
import re
import time
from dataclasses import dataclass
from pathlib import Path

from mpi4py import MPI

from ..analysis import analyse
from ..fem.solvers import SolveError
from ..results.figure_choices import CHARTABLE, numeric_axes
from ..results.io import write_json
from ..scene.scene import Scene, load_scene, read_toml
from ..scene.reader import KEYS, LAYER_KEYS, suggest
from ..scene.sections import E_FROM_KEYS, SceneError

log = logging.getLogger("tankfx")


#: Result columns of table.csv, after the axes.
COLUMNS = ("converged", "validity.valid", "w0", "wd", "M0", "nondim.w0", "nondim.wd",
           "nondim.M0", "nondim.Kp", "nondim.Kt", "w_edge", "w_mean", "junction.M_wall",
           "junction.M_plate")


@dataclass(frozen=True)
class Sweep:
    """A parametric study: a base scene and the values of the keys it varies.

    Attributes
    ----------
    base : Scene
        The scene every case starts from.
    axes : dict of str to list
        Each varied scene key (``"plate.Kp"``, ``"soil.layers[1].depth"``) and its values.
    cases : list of dict
        One dict of axis values per case (a grid of the axes, or their zipped lists).
    scenes : list of Scene
        The validated scene of each case.
    chart_x : str or None
        The chart's horizontal axis (``[charts] x``; None: the first numeric axis).
    chart_y : tuple of str or None
        The results charted (``[charts] y``; None: w0, wd and M0).
    """

    base: Scene
    axes: dict[str, list]
    cases: list[dict]          # one dict of axis values per case
    scenes: list[Scene]
    #: the chart's axis and results ([charts] x and y; None: the defaults)
    chart_x: str | None = None
    chart_y: tuple[str, ...] | None = None


def _charts(table, axes: dict) -> tuple[list[str], str | None, tuple[str, ...] | None]:
    """The problems of a sweep's [charts] table, its x and its y."""
    if table is None:
        return [], None, None
    if not isinstance(table, dict):
        return ["[charts]: a table with x (an axis) and y (a list of results)"], None, None
    problems = [f"charts.{k}: unknown key (valid: x, y)" for k in table if k not in ("x", "y")]
    x, y = table.get("x"), table.get("y")
    numeric = numeric_axes(axes)
    if x is not None and x not in numeric:
        problems.append(f"charts.x = {x!r}: must be a numeric axis of the sweep "
                        f"({', '.join(numeric) or 'none'})")
    if y is not None:
        if not isinstance(y, list) or not y or not all(isinstance(k, str) for k in y):
            problems.append("charts.y: a list of results, e.g. [\"w0\", \"M0\"]")
            y = None
        else:
            for k in y:
                if k not in CHARTABLE:
                    problems.append(f"charts.y: {k!r} is not a result a chart can show"
                                    f"{suggest(k, CHARTABLE)}")
    return problems, x, None if y is None else tuple(y)


def scene_with(scene: Scene, values: dict) -> Scene:
    data = scene.to_dict()
    for key, value in values.items():
        section, _, name = key.partition(".")
        layer = re.fullmatch(r"layers\[(\d+)\]\.(\w+)", name) if section == "soil" else None
        if layer:
            # a key of one of the base scene's [[soil.layers]], counted from 1
            layers = data["soil"].get("layers", [])
            k = int(layer[1])
            if not 1 <= k <= len(layers):
                raise SceneError([f"{key}: the base scene has {len(layers)} soil layer(s); "
                                  f"count them from 1"])
            layers[k - 1][layer[2]] = value
            if layer[2] in E_FROM_KEYS:
                layers[k - 1].pop("E", None)          # 1/a or K p_a: the new one's
            continue
        if section == "soil" and name in E_FROM_KEYS:
            data["soil"].pop("E", None)               # 1/a or K p_a: the new one's
        if section in ("plate", "wall") and name in ("Kp", "Kt") and section in data:
            data[section].pop("thickness", None)      # Kp / Kt replace the thickness
        if section in ("plate", "wall") and name == "thickness" and section in data:
            data[section].pop("Kp" if section == "plate" else "Kt", None)
        data.setdefault(section, {})[name] = value
    return Scene.from_dict(data)


def load_sweep(path: str | Path) -> Sweep:
    """Read and validate a sweep file and every case it makes.

    Parameters
    ----------
    path : str or pathlib.Path
        The sweep file (TOML): ``base``, ``mode``, ``[axes]`` and ``[charts]``.

    Returns
    -------
    Sweep

    Raises
    ------
    SceneError
        A bad key, axis or value, naming the case and the key, before any case runs.
    """
    p = Path(path)
    data = read_toml(p, "sweep")
    problems = [f"{k}: unknown sweep key (valid: base, mode, axes, charts)" for k in data
                if k not in ("base", "mode", "axes", "charts")]
    if "base" not in data:
        problems.append("base: missing; give the scene file the sweep varies")
    axes = data.get("axes", {})
    if not axes or not isinstance(axes, dict):
        problems.append("[axes]: missing; add e.g. \"plate.Kp\" = [0.1, 1.0]")
    for key, values in axes.items() if isinstance(axes, dict) else []:
        if "." not in key:
            problems.append(f"axes.{key}: name a scene key as \"section.key\", e.g. "
                            f"\"plate.Kp\"")
        if not isinstance(values, list) or not values:
            problems.append(f"axes.{key}: give a non-empty list of values")
    chart_problems, chart_x, chart_y = _charts(data.get("charts"), axes if isinstance(
        axes, dict) else {})
    problems += chart_problems
    mode = data.get("mode", "grid")
    if mode not in ("grid", "zip"):
        problems.append(f"mode = {mode!r}: \"grid\" (every combination) or \"zip\" (lists "
                        f"taken together)")
    if problems:
        raise SceneError(problems)
    base = load_scene(p.parent / data["base"])
    keys = list(axes)
    if mode == "zip":
        lengths = {len(v) for v in axes.values()}
        if len(lengths) != 1:
            raise SceneError([f"[axes]: with mode = \"zip\" every list needs the same length "
                              f"(got {sorted(lengths)})"])
        combos = list(zip(*axes.values()))
    else:
        combos = list(itertools.product(*axes.values()))
    cases = [dict(zip(keys, c)) for c in combos]
    scenes, problems = [], []
    for k, case in enumerate(cases):
        try:
            scenes.append(scene_with(base, case))
        except SceneError as e:
            problems += [f"case {k} {case}: {msg}" for msg in e.problems]
    if problems:
        raise SceneError(problems)
    return Sweep(base=base, axes=axes, cases=cases, scenes=scenes, chart_x=chart_x,
                 chart_y=chart_y)


#: ... and, for results with an overturning load, these
OVERTURNING_COLUMNS = ("overturning.tilt", "overturning.rocking_stiffness",
                       "overturning.heel.min_contact_normal", "overturning.uplift.onset_factor")


#: ... and, for a consolidation, these (its top-level w0, M0 are the last reported time's)
CONSOLIDATION_COLUMNS = ("consolidation.degree", "consolidation.undrained.w0",
                         "consolidation.drained.w0", "consolidation.undrained.M0",
                         "consolidation.drained.M0", "consolidation.c_v")
#: ... and, for a consolidation with a factor of safety at its milestones, these
SAFETY_IN_TIME_COLUMNS = ("consolidation.min_strength_factor",
                          "consolidation.min_strength_factor_t_days")


#: ... and, with a collapse search, these
COLLAPSE_COLUMNS = ("collapse.load_factor", "collapse.strength_factor", "collapse.found",
                    "collapse.failure", "collapse.knee_factor",
                    "collapse.N_c", "collapse.bearing_pressure", "collapse.mechanism.kind")
#: ... and, with the limit analysis' bounds, these
BOUNDS_COLUMNS = ("bounds.lower", "bounds.upper", "bounds.gap", "bounds.triangles")


def _flatten(results: dict, extra=()) -> dict:
    out = {}
    for col in COLUMNS + (OVERTURNING_COLUMNS if "overturning" in results else ()) + \
            (CONSOLIDATION_COLUMNS if "consolidation" in results else ()) + \
            (SAFETY_IN_TIME_COLUMNS if "min_strength_factor" in results.get(
                "consolidation", {}) else ()) + \
            (COLLAPSE_COLUMNS if "collapse" in results else ()) + \
            (BOUNDS_COLUMNS if "bounds" in results else ()) + \
            tuple(c for c in extra if c not in COLUMNS):
        value = results
        for part in col.split("."):
            value = value.get(part) if isinstance(value, dict) else None
        out[col] = value
    return out


def _canonical(scene: Scene) -> str:
    return json.dumps(scene.to_dict(), sort_keys=True, default=str)


def key_unit(name: str) -> str:
    """The unit of a sweep's axis ("soil.E", "soil.layers[1].depth"), '' if unknown."""
    section, _, key = name.partition(".")
    layer = re.fullmatch(r"layers\[\d+\]\.(\w+)", key)
    spec = LAYER_KEYS.get(layer[1]) if layer else KEYS.get(section, {}).get(key)
    return spec.unit if spec is not None else ""


def case_text(case: dict) -> str:
    """A case's parameters as its log line names them: "soil.nu = 0.3, plate.Kp = 1"."""
    return ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
                     for k, v in case.items())


def finished_cases(sweep: Sweep, out: Path) -> list[int]:
    """The cases already written in ``out/cases``. A case file that is not valid JSON (a
    run stopped while the disk was full, a file cut short) is computed again; one written
    for a different scene (the sweep file or its base changed since) is refused: resuming
    would mix two studies in one table."""
    done, stale = [], []
    for k, scene in enumerate(sweep.scenes):
        path = out / "cases" / f"{k:04d}.json"
        if not path.exists():
            continue
        try:
            record = json.loads(path.read_text())
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
            log.warning("sweep: %s is not a valid case file (%s): case %d is computed again",
                        path, e, k)
            continue
        if not isinstance(record, dict):
            log.warning("sweep: %s is not a case record: case %d is computed again", path, k)
            continue
        if json.dumps(record.get("scene"), sort_keys=True, default=str) != _canonical(scene):
            stale.append(f"{path}: computed for a different scene than case {k} of this sweep")
        else:
            done.append(k)
    if stale:
        raise SceneError(stale[:5] + [f"... and {len(stale) - 5} more"] * (len(stale) > 5) +
                         [f"{out} holds another study's cases: use another --out, or add "
                          f"--force to discard them and start afresh"])
    return done


def run_sweep(sweep: Sweep, out: Path, comm: MPI.Comm = MPI.COMM_WORLD) -> list[dict] | None:
    """Run the cases not yet written in ``out/cases``, spread over the ranks of ``comm``.

    Each case runs on one rank and is written atomically to ``out/cases/NNNN.json`` as it
    finishes, so that a sweep started again resumes. The end: ``out/table.csv`` and
    ``out/charts.png``.

    Parameters
    ----------
    sweep : Sweep
        The study (:func:`load_sweep`).
    out : pathlib.Path
        The output directory.
    comm : mpi4py.MPI.Comm, optional
        The ranks the cases are dealt out over (default ``MPI.COMM_WORLD``).

    Returns
    -------
    list of dict or None
        The table's rows on rank 0; None on the other ranks.

    Raises
    ------
    SceneError
        On every rank, before any case runs, if ``out/cases`` holds cases of another study.
    """

    cases_dir = out / "cases"
    error = None
    if comm.rank == 0:
        cases_dir.mkdir(parents=True, exist_ok=True)
        try:
            done = finished_cases(sweep, out)
        except SceneError as e:
            error, done = e.problems, []
    else:
        done = None
    error, done = comm.bcast((error, done), root=0)
    if error:
        raise SceneError(error)
    n = len(sweep.cases)
    todo = [k for k in range(n) if k not in set(done)]
    mine = todo[comm.rank::comm.size]
    if comm.rank == 0:
        log.info("sweep: %d cases, %d already done, %d to run on %d rank(s)", n, n - len(todo),
                 len(todo), comm.size)
    t0 = time.perf_counter()
    for i, k in enumerate(mine):
        scene = sweep.scenes[k]
        try:
            results = analyse(scene, MPI.COMM_SELF).results
        except SolveError as e:
            results = {"converged": False, "error": str(e), "history": e.history}
        except SceneError as e:         # too large for this machine (validated otherwise)
            results = {"converged": False, "error": str(e), "history": []}
        record = {"case": k, "axes": sweep.cases[k],
                  "scene": json.loads(_canonical(scene)), "results": results}
        write_json(cases_dir / f"{k:04d}.json", record)
        elapsed = time.perf_counter() - t0
        eta = elapsed / (i + 1) * (len(mine) - i - 1)
        print(f"tankfx sweep [rank {comm.rank}]: case {k + 1} of {n} ({case_text(sweep.cases[k])})"
              f" {'done' if results.get('converged') else 'FAILED'} ({i + 1}/{len(mine)} of "
              f"this rank's, ETA {eta:.0f} s)", flush=True)
    comm.barrier()
    if comm.rank != 0:
        return None
    rows = []
    for k in range(n):
        record = json.loads((cases_dir / f"{k:04d}.json").read_text())
        if k in todo:           # (the log names each case run now, on any rank)
            r = record["results"]
            log.info("sweep: case %d of %d (%s): %s", k + 1, n, case_text(sweep.cases[k]),
                     "converged" if r.get("converged") else f"FAILED: {r.get('error')}")
        rows.append({"case": k, **record["axes"],
                     **_flatten(record["results"], sweep.chart_y or ())})
    with (out / "table.csv").open("w", newline="") as f:
        # (a failed case has no overturning columns: the union of every row's, in order)
        writer = csv.DictWriter(f, fieldnames=list(dict.fromkeys(k for row in rows
                                                                  for k in row)))
        writer.writeheader()
        writer.writerows(rows)

    # (matplotlib is imported here, where the chart is drawn: not by `import tankfx`)
    from ..results.charts import plot_sweep

    x_key = sweep.chart_x or next(iter(numeric_axes(sweep.axes)), None)
    chart = plot_sweep(rows, sweep.axes, out / "charts.png", title=sweep.base.title,
                       x_key=x_key, y_keys=list(sweep.chart_y) if sweep.chart_y else None,
                       x_unit=key_unit(x_key) if x_key else "")
    log.info("sweep: table written to %s%s", out / "table.csv",
             f", charts to {chart}" if chart else "")
    return rows
