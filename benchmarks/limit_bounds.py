"""Limit analysis' bounds on the rigid circular footing's collapse load (``[analysis]
collapse = "bounds"``): each case refined to a 3 % gap, with the elastoplastic collapse
by load on the same scene, the rounds' sizes and times, and how the time grows with the
number of triangles. Whole process per case, this machine.

    python benchmarks/limit_bounds.py            # Tresca smooth/rough, c-phi 20 and 30 degrees
    python benchmarks/limit_bounds.py --quick    # the raft in the half-space, the Tresca footings
    python benchmarks/limit_bounds.py embedded   # only the cases whose names hold a word

Writes results/limit_bounds.json. Exact: N_c = 5.69 (smooth, Shield 1955) and 6.05 (rough,
Eason & Shield 1960) for Tresca soil; for the c-phi soils no published circular value was
found in the sources here (Cox, Eason & Hopkins 1961 computed the smooth ones).
"""
from __future__ import annotations

import json
import logging
import sys
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401
import numpy as np
from mpi4py import MPI

from tankfx import Scene, analyse

OUT = Path(__file__).resolve().parents[1] / "results"
say = print if MPI.COMM_WORLD.rank == 0 else (lambda *a, **k: None)
C = 10e3


def footing(condition: str, soil: dict, pressure: float, E: float = 10e6,
            embedment: float = 0.0) -> dict:
    """The rigid 1 m footing of tests/test_collapse.py, its soil's extra keys given, at the
    bottom of a pit ``embedment`` deep (its side free: no wall)."""
    return {"title": f"footing, {condition}",
            "soil": {"model": "mohr_coulomb", "E": E, "nu": 0.3, "cohesion": C, **soil},
            "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2,
                      "embedment": embedment},
            "interface": {"condition": condition}, "load": {"pressure": pressure},
            "mesh": {"edge_size": 0.01, "near_size": 0.2, "growth": 0.3, "degree": 3},
            "domain": {"radius": 5.0, "depth": 5.0},
            "analysis": {"collapse": "bounds", "bounds_gap": 0.03, "bounds_cells": 40000}}


def raft(condition: str) -> dict:
    """The scene a newcomer writes first: a 5 m raft (1 m of steel) on weightless clay of
    25 kPa, 100 kPa on it, no [domain] (the half-space) and no [mesh] (the defaults)."""
    return {"title": f"raft, {condition}, the default half-space",
            "soil": {"model": "mohr_coulomb", "E": 20e6, "nu": 0.3, "cohesion": 25e3},
            "plate": {"radius": 5.0, "thickness": 1.0, "E": 200e9, "nu": 0.3},
            "interface": {"condition": condition}, "load": {"pressure": 100e3},
            "analysis": {"collapse": "bounds"}}


CASES = [("raft, smooth, half-space", raft("smooth"), 5.69),
         ("Tresca, smooth", footing("smooth", {}, C), 5.69),
         ("Tresca, rough", footing("bonded", {}, C), 6.05),
         ("phi 20, smooth, weightless", footing("smooth", {"friction_angle": 20.0,
                                                           "dilation_angle": 20.0}, 100e3),
          None),
         ("phi 30, rough, 18 kN/m3", footing("bonded", {"friction_angle": 30.0,
                                                        "dilation_angle": 30.0,
                                                        "unit_weight": 18e3}, 200e3, E=100e6),
          None),
         # (stiffer, so that it reaches its limit before the settlement criterion of 0.1 D)
         ("Tresca, rough, embedded a/2, free pit side",
          footing("bonded", {}, 5 * C, E=100e6, embedment=0.5), None)]


def main(quick: bool) -> None:
    # (progress: the collapse search's steps and the bounds' rounds as they go)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    rows = []
    words = [w for w in sys.argv[1:] if not w.startswith("--")]
    cases = [c for c in CASES if all(w in c[0] for w in words)] if words else \
        CASES[:3] if quick else CASES
    for name, data, exact in cases:
        t = time.perf_counter()
        r = analyse(Scene.from_dict(data)).results
        b, c = r["bounds"], r["collapse"]
        q = data["load"]["pressure"] / data["soil"]["cohesion"]    # (the factors as q / c)
        rows.append({"case": name, "exact": exact, "lower": q * b["lower"],
                     "upper": q * b["upper"], "gap": b["gap"], "triangles": b["triangles"],
                     "bounds_s": b["time_s"], "elastoplastic": q * c["load_factor"],
                     "elastoplastic_failure": c["failure"], "elastoplastic_found": c["found"],
                     "elastoplastic_reason": c["reason"],
                     "elastoplastic_s": c["time_s"], "run_s": time.perf_counter() - t,
                     "rounds": b["rounds"], "check": b["lower_check"]})
        row = rows[-1]
        say(f"\n{name}: q_ult / c in [{row['lower']:.4g}, {row['upper']:.4g}] (gap "
            f"{100 * row['gap']:.2f} %, {row['triangles']} triangles, {row['bounds_s']:.0f} s)"
            + (f", exact {exact}" if exact else "")
            + f"; box {b['box']['radius']:.3g} m x {b['box']['depth']:.3g} m "
              f"(side {b['box']['side']}, base {b['box']['base']})"
            + f"; elastoplastic {row['elastoplastic']:.4g} (cubic, "
              + (f"failed by {row['elastoplastic_failure']}" if c["found"]
                 else f"a lower bound: {c['reason']}") + f", {row['elastoplastic_s']:.0f} s)")
        say(f"  {'triangles':>9s} {'lower':>9s} {'upper':>9s} {'gap %':>7s} {'lower s':>8s} "
            f"{'upper s':>8s}")
        for rd in b["rounds"]:
            say(f"  {rd['cells']:9d} {q * rd['lower']:9.4f} {q * rd['upper']:9.4f} "
                f"{100 * rd['gap']:7.2f} {rd['lower_seconds']:8.2f} {rd['upper_seconds']:8.2f}")
        big = [rd for rd in b["rounds"] if rd["cells"] >= 1000]
        if len(big) >= 2:
            n = np.log([rd["cells"] for rd in big])
            s = np.log([rd["lower_seconds"] + rd["upper_seconds"] for rd in big])
            say(f"  time ~ triangles^{np.polyfit(n, s, 1)[0]:.2f} (rounds of 1000 triangles or "
                f"more)")
    if MPI.COMM_WORLD.rank == 0:
        OUT.mkdir(exist_ok=True)
        (OUT / "limit_bounds.json").write_text(json.dumps(rows, indent=1) + "\n")
        say(f"written: {OUT / 'limit_bounds.json'}")


if __name__ == "__main__":
    main("--quick" in sys.argv)
