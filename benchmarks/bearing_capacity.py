"""The bearing capacity of a rigid circular footing on weightless Tresca soil, loaded to
collapse by the elastoplastic soil (soil.model = "mohr_coulomb"), against the exact N_c =
q_ult / s_u: 5.69 smooth (Shield 1955) and 6.05 rough (Eason & Shield 1960), for element
degrees and meshes: the unknowns, N_c, its error, the load steps, the Newton iterations and
the whole run's time side by side.

    python benchmarks/bearing_capacity.py                 # the table
    python benchmarks/bearing_capacity.py smooth 2 0.01   # one case

N_c is the largest mean bearing pressure carried over s_u: the load is applied in steps that
halve where Newton does not converge, down to 1/512 of the load (so the bracket between the
load carried and the one not carried is at most 0.2 % of it). Writes
results/bearing_capacity.json.
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

from tankfx import Scene, analyse
from tankfx.iterations.secant import SoilFailure

EXACT = {"smooth": 5.69, "bonded": 6.05}
S_U = 10e3
OUT = Path(__file__).resolve().parents[1] / "results" / "bearing_capacity.json"
say = print if MPI.COMM_WORLD.rank == 0 else (lambda *a, **k: None)


def footing(condition: str, degree: int, edge: float, near: float = 0.25) -> dict:
    """A rigid 1 m footing (Kp = 1000) under 1.3 N_c s_u, solved to its collapse."""
    data = {"title": f"footing {condition} P{degree} {edge}",
            "soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": S_U},
            "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2},
            "interface": {"condition": condition},
            "load": {"pressure": 1.3 * EXACT[condition] * S_U},
            "mesh": {"edge_size": edge, "near_size": near, "growth": 0.3, "degree": degree},
            "domain": {"radius": 5.0, "depth": 5.0}}
    t = time.perf_counter()
    try:
        analyse(Scene.from_dict(data))
        raise RuntimeError("the footing carried 1.3 N_c: no collapse")
    except SoilFailure as e:
        seconds = time.perf_counter() - t
        q, history, dofs = e.carried["mean_bearing_pressure_carried"], e.history, e.dofs
    N_c = q / S_U
    return {"condition": condition, "degree": degree, "edge_size": edge, "near_size": near,
            "dofs": dofs, "N_c": N_c, "error": N_c / EXACT[condition] - 1.0,
            "steps": len(history), "newton": sum(h["iterations"] for h in history),
            "time_s": seconds}


def main(cases) -> None:
    rows = []
    say(f"{'interface':>9s} {'P':>2s} {'edge':>6s} {'dofs':>7s} {'N_c':>7s} {'error':>8s} "
        f"{'steps':>5s} {'Newton':>6s} {'time s':>7s}")
    for case in cases:
        r = footing(*case)
        rows.append(r)
        say(f"{r['condition']:>9s} {r['degree']:2d} {r['edge_size']:6.3f} {r['dofs']:7d} "
            f"{r['N_c']:7.4f} {r['error']:+8.2%} {r['steps']:5d} {r['newton']:6d} "
            f"{r['time_s']:7.1f}", flush=True)
    if MPI.COMM_WORLD.rank == 0:
        OUT.parent.mkdir(exist_ok=True)
        OUT.write_text(json.dumps(rows, indent=1) + "\n")
        say(f"written: {OUT}")


if __name__ == "__main__":
    if len(sys.argv) > 1:
        main([(sys.argv[1], int(sys.argv[2]), float(sys.argv[3]),
               *(float(x) for x in sys.argv[4:5]))])
    else:
        main([(c, p, h) for c in ("smooth", "bonded") for p in (2, 3)
              for h in (0.04, 0.02, 0.01)])
