"""The bearing capacity of a rigid circular footing on weightless Tresca soil, followed
through its collapse by the elastoplastic soil under settlement control
(tankfx.verification.footing), against the exact N_c = q_ult / s_u: 5.69 smooth (Shield 1955)
and 6.05 rough (Eason & Shield 1960), for element degrees and meshes: the unknowns, N_c (the
load at a settlement of 0.1 a, on its plateau), its error, the Newton iterations and the
whole run's time side by side.

    python benchmarks/bearing_capacity.py                       # the table
    python benchmarks/bearing_capacity.py smooth 2 0.005 0.2    # one case

Writes results/bearing_capacity.json.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

from tankfx.verification.footing import EXACT_N_C, collapse_curve, footing_scene

OUT = Path(__file__).resolve().parents[1] / "results" / "bearing_capacity.json"
say = print if MPI.COMM_WORLD.rank == 0 else (lambda *a, **k: None)


def main(cases) -> None:
    rows = []
    say(f"{'interface':>9s} {'P':>2s} {'edge':>6s} {'near':>5s} {'dofs':>7s} {'N_c':>7s} "
        f"{'error':>8s} {'Newton':>6s} {'time s':>7s}")
    for condition, degree, edge, near in cases:
        c = collapse_curve(footing_scene(condition, degree, edge, near))
        N = c["factor"][-1]
        r = {"condition": condition, "degree": degree, "edge_size": edge, "near_size": near,
             "dofs": c["dofs"], "N_c": N, "error": N / EXACT_N_C[condition] - 1.0,
             "newton": c["newton"], "time_s": c["time_s"]}
        rows.append(r)
        say(f"{condition:>9s} {degree:2d} {edge:6.4f} {near:5.2f} {r['dofs']:7d} {N:7.4f} "
            f"{r['error']:+8.2%} {r['newton']:6d} {r['time_s']:7.1f}", flush=True)
    if MPI.COMM_WORLD.rank == 0:
        OUT.parent.mkdir(exist_ok=True)
        OUT.write_text(json.dumps(rows, indent=1) + "\n")
        say(f"written: {OUT}")


if __name__ == "__main__":
    if len(sys.argv) > 1:
        main([(sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]))])
    else:
        main([(c, p, h, n) for c in ("smooth", "bonded")
              for p, h, n in ((2, 0.01, 0.25), (2, 0.005, 0.2), (2, 0.0025, 0.2),
                              (3, 0.02, 0.3), (3, 0.01, 0.3), (3, 0.01, 0.15),
                              (4, 0.04, 0.4), (4, 0.02, 0.4))])
