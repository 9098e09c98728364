"""The Mohr-Coulomb interface on the embedded demo tank: iterations and time against the
linear (bonded, smooth) interfaces, over friction, with the states per element (the paper's,
the default) and per node.

    python benchmarks/interface.py [--out results/benchmarks]
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

from tankfx import analyse, load_scene
from tankfx.fem.solvers import SolveError

say = print if MPI.COMM_WORLD.rank == 0 else (lambda *a, **k: None)
SCENE = Path(__file__).resolve().parents[1] / "demos" / "scenes" / "embedded_tank.toml"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/benchmarks")
    args = ap.parse_args()
    base = load_scene(SCENE)
    cases = [("bonded", {"condition": "bonded"}), ("smooth", {"condition": "smooth"})] + [
        (f"MC {states} tan_phi={tp:g}", {"condition": "mohr_coulomb", "tan_phi": tp,
                                         "states": states})
        for states in ("node", "element") for tp in (0.001, 0.1, 0.3, 0.6, 10.0)]
    analyse(base)   # compile every form once: the times below are solves, not JIT
    say(f"\n{base.title} (a = {base.plate.radius:g} m, D = {base.embedment:g} m, Kp = "
        f"{base.Kp:.3g}, Kt = {base.Kt:.3g}, water to {base.load.liquid_height:g} m)")
    say(f"{'interface':28s} {'iters':>5s} {'solve s':>8s} {'total s':>8s} {'w0_bar':>8s} "
        f"{'wd_bar':>8s} {'M0_bar':>8s} {'slip m':>7s} {'sep m':>6s} {'held':>4s} {'rev.':>4s}")
    rows = []
    for name, ifc in cases:
        scene = base.with_changes(interface=ifc)
        t = time.perf_counter()
        try:
            r = analyse(scene).results
        except SolveError as err:
            total = time.perf_counter() - t
            rows.append({"interface": name, "refused": str(err), "total_s": total,
                         "iterations": len(err.history)})
            say(f"{name:28s} {len(err.history):5d} {'':8s} {total:8.2f}  refused: "
                f"{str(err)[:60]}...")
            continue
        total = time.perf_counter() - t
        i, nd = r["interface"], r["nondim"]
        slip = i["slip_length"]["plate"] + i["slip_length"]["wall"]
        sep = i["separated_length"]["plate"] + i["separated_length"]["wall"]
        row = {"interface": name, "iterations": i["iterations"],
               "solve_s": r["timings_s"]["assemble_solve"], "total_s": total,
               "w0_bar": nd["w0"], "wd_bar": nd["wd"], "M0_bar": nd["M0"],
               "slip_length": slip, "separated_length": sep,
               "held": i.get("frozen_elements", 0),
               "reversed_slips": i.get("reversed_slips", 0)}
        rows.append(row)
        say(f"{name:28s} {row['iterations']:5d} {row['solve_s']:8.2f} {total:8.2f} "
            f"{nd['w0']:8.4f} {nd['wd']:8.4f} {nd['M0']:8.5f} {slip:7.3f} {sep:6.3f} "
            f"{row['held']:4d} {row['reversed_slips']:4d}")
    if MPI.COMM_WORLD.rank == 0:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "interface.json").write_text(json.dumps(rows, indent=1))
        say(f"\ntable written to {out / 'interface.json'}")


if __name__ == "__main__":
    main()
