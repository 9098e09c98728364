"""Error against run time for the flexible circular load (Boussinesq), over mesh levels and
element degrees, and the cost of truncating the half-space.

    python benchmarks/flexible_load.py [--quick] [--out results/benchmarks]

Part 1 runs each (degree, level) case in a fresh process (`python -m tankfx run`), so "whole
process" includes start-up, meshing and form compilation (JIT cached after the first run of a
form). Errors are relative, against the closed forms of tankfx.verification.reference. Level 0 is
the
default mesh (edge_size 0.002 a, near_size 0.1 a); each level up halves both sizes, each level
down doubles them.

Part 2 compares two ways of making the truncated domain act as a half-space: a graded mesh out
to a large radius R with a fixed boundary, and a small domain whose boundary is given
Boussinesq's point-load displacement (a far-field boundary condition).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

P, A, E = 100e3, 1.0, 10e6
NU = 0.45  # the hardest of the verified Poisson's ratios for the stresses
LEVELS = (-2, -1, 0, 1, 2)


def scene_toml(degree: int, level: int) -> str:
    f = 2.0 ** (-level)
    return f"""title = "benchmark P{degree} level {level}"
[soil]
E = {E}
nu = {NU}
[load]
pressure = {P}
load_radius = {A}
[mesh]
degree = {degree}
edge_size = {min(0.002 * f, 0.5) * A}
near_size = {0.1 * f * A}
"""


def run_case(degree: int, level: int, workdir: Path) -> dict:
    scene = workdir / f"p{degree}_l{level}.toml"
    scene.write_text(scene_toml(degree, level))
    out = workdir / f"p{degree}_l{level}"
    t = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "tankfx", "run", str(scene), "--out", str(out),
                           "--force"], capture_output=True, text=True)
    wall = time.perf_counter() - t
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr)
    r = json.loads((out / "results.json").read_text())
    r["process_s"] = wall
    return r


def errors(r: dict) -> dict:
    from tankfx.verification import reference as ref

    z = np.array(r["profiles"]["axis"]["z"])
    s = np.array(r["profiles"]["axis"]["sigma_zz"])
    win = (z >= 0.25 * A) & (z <= 5 * A)
    return {"w0": r["w0"] / ref.flexible_centre_settlement(P, A, E, NU) - 1,
            "w_edge": r["w_edge"] / ref.flexible_edge_settlement(P, A, E, NU) - 1,
            "w_mean": r["w_mean"] / ref.flexible_mean_settlement(P, A, E, NU) - 1,
            "sigma_zz": np.max(np.abs(s[win] / ref.flexible_axis_stress(P, A, z[win]) - 1))}


def part1(degrees, levels, out: Path) -> list[dict]:
    rows = []
    print(f"\nPart 1: flexible load, nu = {NU}, default domain (10000 a); errors vs Boussinesq")
    print(f"{'P':>2s} {'level':>5s} {'dofs':>8s} {'mesh s':>7s} {'solve s':>8s} "
          f"{'process s':>9s} {'err w0':>9s} {'err w_edge':>10s} {'err w_mean':>10s} "
          f"{'max err sigma_zz':>16s}")
    with tempfile.TemporaryDirectory() as tmp:
        for deg in degrees:
            for lev in levels:
                r = run_case(deg, lev, Path(tmp))
                e = errors(r)
                row = {"degree": deg, "level": lev, "dofs": r["dofs"]["soil"],
                       "mesh_s": r["timings_s"]["mesh"],
                       "solve_s": r["timings_s"]["assemble_solve"],
                       "process_s": r["process_s"], **{f"err_{k}": v for k, v in e.items()}}
                rows.append(row)
                print(f"{deg:2d} {lev:5d} {row['dofs']:8d} {row['mesh_s']:7.2f} "
                      f"{row['solve_s']:8.2f} {row['process_s']:9.2f} {e['w0']:+9.3%} "
                      f"{e['w_edge']:+10.3%} {e['w_mean']:+10.3%} {e['sigma_zz']:16.3%}")
    (out / "flexible_load.json").write_text(json.dumps(rows, indent=1))
    return rows


def part2(factors, out: Path) -> list[dict]:
    """Truncation: fixed boundary at R vs Boussinesq far-field displacement at R."""
    import dolfinx_solver  # noqa: F401
    from dolfinx import fem
    from mpi4py import MPI

    from tankfx import Scene
    from tankfx.verification import reference as ref
    from tankfx.model.flexible import FlexibleLoad
    from tankfx.mesh import build_domain
    from tankfx.fem.evaluate import evaluate_at
    from tankfx.fem.solvers import DirectSolver

    print("\nPart 2: truncation of the half-space, P3 fine mesh (discretisation error "
          "< 0.01 %)")
    print(f"{'R / a':>7s} {'boundary':>12s} {'dofs':>7s} {'solve s':>8s} {'err w0':>9s}")
    rows = []
    w_exact = ref.flexible_centre_settlement(P, A, E, NU)
    for R in factors:
        for kind in ("fixed", "boussinesq"):
            scene = Scene.from_dict({"soil": {"E": E, "nu": NU},
                                     "load": {"pressure": P, "load_radius": A},
                                     "domain": {"radius": R * A, "depth": R * A},
                                     "mesh": {"degree": 3, "edge_size": 0.025, "near_size": 0.05}})
            dom = build_domain(scene, MPI.COMM_WORLD)
            prob = FlexibleLoad(scene, dom)
            if kind == "boussinesq":
                far = fem.Function(prob.soil.V)
                load = prob.applied_load

                def field(x):
                    ur, w = ref.point_load_displacement(load, E, NU, x[0], np.maximum(-x[1], 0))
                    return np.vstack([ur, -w])

                far.interpolate(field)
                dofs = fem.locate_dofs_topological(prob.soil.V, 1, dom.facets("far_side", "bottom"))
                prob.bcs[1] = fem.dirichletbc(far, dofs)
            t = time.perf_counter()
            DirectSolver(prob.a, prob.L, prob.bcs, prob.soil.u).solve()
            ts = time.perf_counter() - t
            w0 = -evaluate_at(prob.soil.u, np.array([[0.0, 0.0]]))[0, 1]
            ndofs = prob.soil.V.dofmap.index_map.size_global * 2
            rows.append({"R": R, "boundary": kind, "dofs": ndofs, "solve_s": ts,
                         "err_w0": w0 / w_exact - 1})
            print(f"{R:7g} {kind:>12s} {ndofs:7d} {ts:8.2f} {w0 / w_exact - 1:+9.4%}")
    (out / "truncation.json").write_text(json.dumps(rows, indent=1))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer cases")
    ap.add_argument("--out", default="results/benchmarks")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    degrees = (2, 3) if args.quick else (1, 2, 3)
    levels = (-1, 0, 1) if args.quick else LEVELS
    part1(degrees, levels, out)
    part2((10, 100, 1000) if args.quick else (10, 100, 1000, 10000), out)
    print(f"\ntables written to {out}/")


if __name__ == "__main__":
    main()
