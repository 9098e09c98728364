"""The safe fill schedule's search, and what it costs: the 25 m tank of
benchmarks/scenes/hydrotest_schedule.toml (Modified Cam Clay with a crust, 9 m of water in 3 m
steps at 1.8 m a day) on the coarse mesh, as demos/hydrotest_schedule.py runs it.

    python benchmarks/fill_schedule.py [--out results/benchmarks]

Prints, step by step: the hold chosen, each hold tried and whether its check passed, the
factor of safety; then the search's cost: checks, fills tried, factor-of-safety searches,
Newton iterations (of the path and of the searches) and the times. Writes
fill_schedule.json and .md in --out.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)

from tankfx import analyse, load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "benchmarks" / "scenes" / "hydrotest_schedule.toml"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "benchmarks"))
    args = ap.parse_args()
    # (progress: a line per time step, per hold tried and per trial of a search)
    log = logging.getLogger("tankfx")
    log.setLevel(logging.INFO)
    log.addHandler(logging.StreamHandler(sys.stdout))
    scene = load_scene(SCENE).with_coarse_mesh()
    t0 = time.perf_counter()
    r = analyse(scene).results
    elapsed = time.perf_counter() - t0
    f = r["fill"]
    searches = [s["collapse"] for s in r["stages"] if "collapse" in s]
    lines = ["| step | to (m) | hold (days) | fills (days) | factor | holds tried (+ passed) |",
             "|---|---|---|---|---|---|"]
    for k, s in enumerate(f["schedule"], start=1):
        # (each hold tried: + passed, - failed, and the factor its check found)
        tried = ", ".join(f"{h['hold_days']:g}{'+' if h['passed'] else '-'}"
                          + (f" ({h['strength_factor']:.3g})" if h["strength_factor"] else "")
                          for h in s["holds_tried"]) or "none"
        lines.append(f"| {k} | {s['height']:.3g} | {s['hold_days']:.3g} | "
                     f"{s['fill_start_day']:.4g}-{s['fill_end_day']:.4g} | "
                     f"{s['strength_factor']:.3g} | {tried} |")
    unheld = ", ".join(f"{u['height']:.3g} m: {u['strength_factor']:.3g}" for u in f["unheld"])
    cost = {"unknowns": r["dofs"]["total"], "checks": f["checks"],
            "fills_tried": f["fills_tried"], "newton_iterations": f["newton_iterations"],
            "search_newton_iterations_accepted": sum(c["iterations"] for c in searches),
            "search_time_accepted_s": sum(c["time_s"] for c in searches),
            "schedule_time_s": f["time_s"], "time_s": elapsed}
    lines += ["", f"no holds ({f['rate']:g} m/day): factors {unheld}",
              f"schedule: {f['total_days']:.4g} days "
              f"({'complete' if f['complete'] else 'stopped: ' + f['reason']})",
              f"cost: {cost['unknowns']} unknowns; {f['checks']} checks, {f['fills_tried']} "
              f"fills tried, {f['newton_iterations']} Newton iterations in time steps; the "
              f"accepted steps' searches {cost['search_newton_iterations_accepted']} "
              f"iterations ({cost['search_time_accepted_s']:.0f} s); the schedule "
              f"{f['time_s']:.0f} s, {elapsed:.0f} s in all"]
    text = "\n".join(lines)
    print(text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "fill_schedule.md").write_text(text + "\n")
    (out / "fill_schedule.json").write_text(json.dumps({"fill": f, "cost": cost}, indent=1))


if __name__ == "__main__":
    main()
