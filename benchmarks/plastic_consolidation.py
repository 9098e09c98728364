"""The hydrotest of a 25 m tank on clay in time, and what it costs: the tank of
benchmarks/scenes/hydrotest_on_clay.toml filled to 14 m of water over 10 days in five steps
with holds, held to day 60, on an elastoplastic skeleton (c' = 20 kPa, phi' = 28 deg)
consolidating, its factor of safety searched at every stage's end.

    python benchmarks/plastic_consolidation.py [--coarse] [--no-safety]
                                               [--out results/benchmarks]

Prints each stage's state (time, liquid height, settlements, piezometers, factor of safety)
and the cost: time steps, Newton iterations of the path (their median and largest a time
step) and of the factors of safety, the times (the analysis, and the searches within it)
and the time by kind of work (assembly, factorisation, solve, the return at the points,
Newton's residual). Writes plastic_consolidation.json and
.md in --out.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)
import numpy as np

from tankfx import analyse, load_scene
from tankfx.fem import timing

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "benchmarks" / "scenes" / "hydrotest_on_clay.toml"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--coarse", action="store_true", help="the coarse mesh (--coarse of tankfx)")
    ap.add_argument("--no-safety", action="store_true",
                    help="without the factors of safety (the path alone)")
    ap.add_argument("--out", default=str(ROOT / "results" / "benchmarks"))
    args = ap.parse_args()
    # (progress: a line per time step and per trial of a factor of safety)
    log = logging.getLogger("tankfx")
    log.setLevel(logging.INFO)
    log.addHandler(logging.StreamHandler(sys.stdout))
    scene = load_scene(SCENE)
    if args.coarse:
        scene = scene.with_coarse_mesh()
    if args.no_safety:
        scene = scene.with_changes(analysis={"collapse": None})
    timing.reset()
    t0 = time.perf_counter()
    r = analyse(scene).results
    elapsed = time.perf_counter() - t0
    split = timing.split()
    c = r["consolidation"]
    # (each time step's Newton iterations, its tries and parts together)
    per_step = [s["newton_iterations"] for s in c["history"]
                if s.get("newton_iterations") is not None]
    rows = []
    for st in r["stages"]:
        col = st.get("collapse")
        rows.append({"stage": st["stage"], "t_days": st["t_days"],
                     "liquid_height": st["liquid_height"], "w0_mm": 1e3 * st["w0"],
                     "w_edge_mm": 1e3 * st["w_edge"],
                     "piezometers_kPa": [1e-3 * u for u in st.get("piezometers", [])],
                     "factor_of_safety": col["strength_factor"] if col else None,
                     "search_iterations": col["iterations"] if col else 0,
                     "search_time_s": col["time_s"] if col else 0.0})
    search_its = sum(x["search_iterations"] for x in rows)
    search_s = sum(x["search_time_s"] for x in rows)
    cost = {"unknowns": r["dofs"]["total"],
            "time_steps": c["steps"], "newton_iterations_path": r["soil"]["iterations"],
            "newton_iterations_safety": search_its, "time_s": elapsed,
            "time_safety_s": search_s, "time_path_s": elapsed - search_s,
            "iterations_per_step": per_step,
            "median_iterations": float(np.median(per_step)) if per_step else None,
            "max_iterations": max(per_step, default=None),
            "steps_over_15": sum(1 for n in per_step if n > 15), "time_split": split}
    lines = ["| stage | t (days) | H (m) | w0 (mm) | w_edge (mm) | piezometers (kPa) | F |",
             "|---|---|---|---|---|---|---|"]
    for x in rows:
        F = "-" if x["factor_of_safety"] is None else f"{x['factor_of_safety']:.3g}"
        lines.append(f"| {x['stage']} | {x['t_days']:.4g} | {x['liquid_height']:.3g} | "
                     f"{x['w0_mm']:.1f} | {x['w_edge_mm']:.1f} | "
                     f"{', '.join(f'{u:.1f}' for u in x['piezometers_kPa'])} | {F} |")
    lines += ["", f"mesh: {'coarse' if args.coarse else 'default'}; {cost['time_steps']} time "
              f"steps, {cost['newton_iterations_path']} Newton iterations on the path "
              f"({cost['time_path_s']:.0f} s), {search_its} in the factors of safety "
              f"({search_s:.0f} s); {elapsed:.0f} s in all",
              f"Newton iterations a time step: median {cost['median_iterations']}, largest "
              f"{cost['max_iterations']}, {cost['steps_over_15']} steps over 15",
              "time by kind of work (s, calls; per Newton iteration of the whole run): " +
              ", ".join(f"{k} {v['seconds']:.1f} ({v['calls']})" for k, v in split.items())]
    text = "\n".join(lines)
    print(text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "plastic_consolidation.md").write_text(text + "\n")
    (out / "plastic_consolidation.json").write_text(json.dumps(
        {"coarse": args.coarse, "safety": not args.no_safety, "stages": rows, "cost": cost},
        indent=1))


if __name__ == "__main__":
    main()
