"""A 25 m steel tank on soft clay, its hydrotest's factor of safety: the collapse by load
and by strength (``[analysis] collapse``) of the full fill, and how the factors change with
the fill height, with the time each search takes, whole process per case.

    python benchmarks/tank_collapse.py            # default mesh: the full fill, both searches
    python benchmarks/tank_collapse.py --coarse   # coarse mesh, and the fill-height sweep

Writes results/tank_collapse.json and results/tank_collapse.png (the sweep's factors). The
tank: 8 mm floor, 16 mm wall 15 m high, its own weight, filled with 14 m of water; the clay:
Tresca, s_u = 25 kPa + 1.5 kPa/m, E = 6 MPa, nu = 0.45, 17 kN/m^3, water table 1 m down,
K0 = 0.7, in a 75 m x 40 m domain. See docs/development/2026-11-27-collapse.md for what the
load search's slowly rising tail under a flexible tank means.
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

from tankfx import Scene, analyse

OUT = Path(__file__).resolve().parents[1] / "results"
say = print if MPI.COMM_WORLD.rank == 0 else (lambda *a, **k: None)

TANK = {"title": "25 m steel tank on soft clay",
        "soil": {"model": "mohr_coulomb", "E": 6e6, "nu": 0.45, "cohesion": 25e3,
                 "cohesion_gradient": 1.5e3, "unit_weight": 17e3, "water_table": 1.0,
                 "K0": 0.7},
        "plate": {"radius": 12.5, "thickness": 0.008, "E": 200e9, "nu": 0.3},
        "wall": {"radius": 12.5, "height": 15.0, "thickness": 0.016, "E": 200e9, "nu": 0.3},
        "interface": {"condition": "bonded"},
        "load": {"liquid_unit_weight": 9810.0, "liquid_height": 14.0, "self_weight": True},
        "domain": {"radius": 75.0, "depth": 40.0}}


def case(collapse: str, height: float, coarse: bool) -> dict:
    data = json.loads(json.dumps(TANK))
    data["analysis"] = {"collapse": collapse}
    data["load"]["liquid_height"] = height
    scene = Scene.from_dict(data)
    if coarse:
        scene = scene.with_coarse_mesh()
    t = time.perf_counter()
    r = analyse(scene).results
    c = r["collapse"]
    return {"collapse": collapse, "liquid_height": height, "dofs": r["dofs"]["total"],
            "found": c["found"], "factor": c[f"{collapse}_factor"], "bracket": c["bracket"],
            "failure": c["failure"],
            "knee": c.get("knee_bracket"), "mechanism": c.get("mechanism", {}).get("kind"),
            "steps": c["steps"], "newton": c["iterations"], "search_s": c["time_s"],
            "run_s": time.perf_counter() - t, "w0_mm": 1e3 * r["w0"]}


def main(coarse: bool) -> None:
    heights = [8.0, 11.0, 14.0] if coarse else [14.0]
    rows = []
    say(f"{'search':>8s} {'H m':>5s} {'dofs':>6s} {'factor':>8s} {'bracket':>19s} "
        f"{'failed by':>14s} {'knee':>17s} {'mech.':>5s} {'steps':>5s} {'Newton':>6s} {'search s':>8s} "
        f"{'run s':>6s}")
    for height in heights:
        for collapse in ("load", "strength"):
            r = case(collapse, height, coarse)
            rows.append(r)
            br = "-" if not r["bracket"] else f"[{r['bracket'][0]:.4f}, {r['bracket'][1]:.4f}]"
            kn = "-" if not r["knee"] else f"[{r['knee'][0]:.3f}, {r['knee'][1]:.3f}]"
            say(f"{collapse:>8s} {height:5.1f} {r['dofs']:6d} "
                f"{('' if r['found'] else '>=') + format(r['factor'], '.4f'):>8s} {br:>19s} "
                f"{r['failure'] or '-':>14s} {kn:>17s} {r['mechanism'] or '-':>5s} {r['steps']:5d} {r['newton']:6d} "
                f"{r['search_s']:8.1f} {r['run_s']:6.1f}", flush=True)
    if MPI.COMM_WORLD.rank == 0:
        OUT.mkdir(exist_ok=True)
        (OUT / "tank_collapse.json").write_text(json.dumps(rows, indent=1) + "\n")
        if len(heights) > 1:
            from tankfx.results.charts import plot_curves

            def of(kind, key):
                return [next(r for r in rows if r["collapse"] == kind
                             and r["liquid_height"] == h)[key] for h in heights]

            knees = [k[0] if k else float("nan") for k in of("load", "knee")]
            plot_curves(heights, {"factor of safety": {
                "strength (c, tan phi divided)": of("strength", "factor"),
                "load: the mechanism forms (knee)": knees,
                "load (variable loads times it)": of("load", "factor")}},
                OUT / "tank_collapse.png", "water height in the hydrotest [m]",
                title=TANK["title"])
        say(f"written: {OUT / 'tank_collapse.json'}")


if __name__ == "__main__":
    main("--coarse" in sys.argv)
