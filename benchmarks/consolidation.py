"""Consolidation: error against run time over the time step and the mesh.

    python benchmarks/consolidation.py [--quick] [--out results/benchmarks]

1. Terzaghi's column (tankfx.verification.rigs.Oedometer, 40 P2 elements over 10 m, drained at
   the top): the largest error of the settlement at T_v = 0.01, 0.05, 0.2, 0.5, 1 (relative
   to the final settlement) against the steps per decade, for BDF2 (tankfx's) and backward
   Euler; the time is that of the steps (the mesh is small: the step alone decides).
2. Mandel's cylinder (tankfx.verification.rigs.MandelCylinder) against its closed form
   (tankfx.verification.reference.mandel_cylinder): the largest error of the centre's pore pressure
   (relative to its start) over cells and steps per decade.
3. The tank on soft clay of demos/tank_on_clay.py: w0 and M0 after a year against the
   finest run (the default mesh level 1, 40 steps a decade), over mesh levels and steps per
   decade, with each run's analysis time (`timings_s.total`, in this process: the forms
   are compiled once, by the first run).

Each part prints a table; all of it goes to ``consolidation.md`` and ``.json`` in --out.
"""
from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)

import numpy as np

from tankfx import analyse, load_scene
from tankfx.verification import reference as ref
from tankfx.verification.rigs import MandelCylinder, Oedometer
from tankfx.laws.biot import consolidation_coefficient
from tankfx.iterations.time_stepping import time_steps

ROOT = Path(__file__).resolve().parents[1]
E, NU, K = 5e6, 0.3, 1e-8


def column(per_decade: int, second_order: bool) -> dict:
    H, q = 10.0, 1e5
    c_v = consolidation_coefficient(E, NU, K, 9810.0)
    times = np.array([0.01, 0.05, 0.2, 0.5, 1.0]) * H**2 / c_v
    oed = Oedometer(H, E, NU, K, q, cells=40)
    steps = time_steps(times, times[0] / 1000, per_decade)
    t0 = time.perf_counter()
    history = oed.run(steps, second_order)
    elapsed = time.perf_counter() - t0
    t = np.array([h["t"] for h in history])
    s = np.array([history[int(np.argmin(abs(t - ti)))]["settlement"] for ti in times])
    final = q * H * (1 + NU) * (1 - 2 * NU) / (E * (1 - NU))
    err = np.max(np.abs(s - ref.terzaghi_settlement(q, H, E, NU, K, times))) / final
    return {"steps": len(steps), "error": float(err), "time_s": elapsed}


def cylinder(cells: int, per_decade: int) -> dict:
    a, strain = 1.0, -1e-3
    c = ref.mandel_cylinder(E, NU, K, a, strain, [1.0])["c"]
    times = np.array([0.01, 0.05, 0.2, 0.5]) * a**2 / c
    exact = ref.mandel_cylinder(E, NU, K, a, strain, times, terms=200)
    t0 = time.perf_counter()
    history = MandelCylinder(a, E, NU, K, strain, cells=cells).run(
        time_steps(times, times[0] / 100, per_decade))
    elapsed = time.perf_counter() - t0
    t = np.array([h["t"] for h in history])
    p = np.array([history[int(np.argmin(abs(t - ti)))]["centre_pressure"] for ti in times])
    return {"error": float(np.max(np.abs(p - exact["centre"])) / exact["p0"]),
            "time_s": elapsed}


def tank(level: int, per_decade: int) -> dict:
    scene = load_scene(ROOT / "demos" / "scenes" / "tank_on_clay.toml")
    a = scene.plate.radius
    f = 2.0 ** (-level)
    scene = scene.with_changes(
        mesh={"edge_size": 0.002 * f * a, "near_size": 0.1 * f * a},
        consolidation={"times": [365 * 86400.0], "steps_per_decade": per_decade})
    r = analyse(scene).results
    year = r["consolidation"]["at_times"][-1]
    return {"w0": year["w0"], "M0": year["M0"], "dofs": r["dofs"]["total"],
            "steps": r["consolidation"]["steps"], "time_s": r["timings_s"]["total"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer configurations")
    ap.add_argument("--out", default="results/benchmarks")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    lines, data = [], {}

    def say(text=""):
        print(text, flush=True)
        lines.append(text)

    say("## Terzaghi's column: settlement error (of the final) against steps per decade\n")
    say("| steps / decade | steps | BDF2 error | BDF2 time s | backward Euler error | "
        "backward Euler time s |")
    say("|---|---|---|---|---|---|")
    data["column"] = []
    for n in ((5, 10, 20) if args.quick else (5, 10, 20, 40, 80)):
        bdf, be = column(n, True), column(n, False)
        data["column"].append({"per_decade": n, "bdf2": bdf, "backward_euler": be})
        say(f"| {n}{' (default)' if n == 10 else ''} | {bdf['steps']} | {bdf['error']:.2e} | "
            f"{bdf['time_s']:.2f} | {be['error']:.2e} | {be['time_s']:.2f} |")

    say("\n## Mandel's cylinder: error of the centre's pore pressure (of its start)\n")
    decades = (10, 20) if args.quick else (10, 20, 40)
    say("| cells | " + " | ".join(f"{n} / decade: error, time s" for n in decades) + " |")
    say("|---|" + "---|" * len(decades))
    data["cylinder"] = []
    for cells in ((8, 16) if args.quick else (8, 16, 32)):
        row = [cylinder(cells, n) for n in decades]
        data["cylinder"].append({"cells": cells, "runs": row})
        say(f"| {cells} x {cells} | " + " | ".join(
            f"{x['error']:.2e}, {x['time_s']:.2f}" for x in row) + " |")

    say("\n## The tank on soft clay: w0 and M0 after a year against the finest run\n")
    levels = (-1, 0) if args.quick else (-1, 0, 1)
    per = (5, 10, 20) if args.quick else (5, 10, 20, 40)
    runs = {(lv, n): tank(lv, n) for lv in levels for n in per}
    finest = runs[max(levels), max(per)]
    say(f"reference: level {max(levels)}, {max(per)} steps a decade: w0 = "
        f"{1e3 * finest['w0']:.4f} mm, M0 = {finest['M0'] / 1e3:.4f} kN m/m\n")
    say("| mesh level | dofs | steps / decade | steps | w0 error | M0 error | time s |")
    say("|---|---|---|---|---|---|---|")
    data["tank"] = []
    for (lv, n), x in runs.items():
        ew = abs(x["w0"] / finest["w0"] - 1)
        em = abs(x["M0"] / finest["M0"] - 1)
        data["tank"].append({"level": lv, "per_decade": n, **x, "w0_error": ew,
                             "M0_error": em})
        mark = " (default)" if (lv, n) == (0, 10) else ""
        say(f"| {lv}{mark} | {x['dofs']} | {n} | {x['steps']} | "
            f"{ew:.1e} | {em:.1e} | {x['time_s']:.2f} |")
    (out / "consolidation.md").write_text("\n".join(lines) + "\n")
    (out / "consolidation.json").write_text(json.dumps(data, indent=1))
    print(f"\nwritten: {out / 'consolidation.md'}, {out / 'consolidation.json'}")
    assert all(math.isfinite(x["w0"]) for x in runs.values())


if __name__ == "__main__":
    main()
