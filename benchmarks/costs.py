"""Where the time goes, and the cost ratios of the performance targets, measured in one run
on this machine:

1. ``profile``: the nonlinear embedded tank of ``make demo`` (hyperbolic soil + Mohr-Coulomb
   interface) against the linear solve of the same scene (soil of E = 1/a, bonded), each
   in a fresh process (whole-process wall time, JIT cache warm), with PETSc's event log
   (factorisations, triangular solves) beside tankfx's own timings. Target: nonlinear
   <= 5 x linear.
2. ``parallel``: the embedded tank, linear and nonlinear, refined to about 270k dofs, and
   the tank on clay's consolidation at 191k, on 1 and on 2 MPI ranks, each ``--repeat``
   times (medians). Target: 2 ranks >= 1.5 x faster. ``--near-size`` sets the refinement
   (element size within 6 radii, m): 0.35 (default) gives 274k dofs, 0.27 gives 434k, 0.2
   gives 755k (the clay tank's in proportion); ``--scenes`` picks among linear, nonlinear
   and consolidation.
3. ``sweep``: a sweep of N default cases (the surface tank over Kp and nu_s) on 1 and on 2
   ranks. Target (N = 100): >= 1.8 x faster.
4. ``iterative``: where the iterative option (``[solver] method = "iterative"``) beats MUMPS
   in time and memory: the flexible load (soil alone, CG + GAMG) and the embedded tank
   (soil + structure: GMRES, the structure condensed, GAMG on the soil's Schur complement)
   at growing mesh sizes, each a fresh process (peak memory from the operating system).

    python benchmarks/costs.py [--only profile|parallel|sweep|iterative] [--cases 100]
                               [--repeat 3] [--near-size 0.35] [--scenes ...]
                               [--out results/benchmarks]

Every measurement runs in its own process (``mpiexec -n N python ...``), so that the ranks
and the memory are those a user gets.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PY = sys.executable
MPIEXEC = shutil.which("mpiexec", path=os.path.dirname(PY)) or "mpiexec"

# One analysis in a fresh process: results and PETSc's event log as JSON on stdout.
_ANALYSIS = textwrap.dedent("""
    import json, sys, time
    t0 = time.perf_counter()
    import dolfinx_solver
    from petsc4py import PETSc
    PETSc.Log.begin()
    from mpi4py import MPI
    from tankfx import Scene, analyse, load_scene
    scene = load_scene(sys.argv[1])
    changes = json.loads(sys.argv[2])
    if changes:
        data = scene.to_dict()
        for section, values in changes.items():
            data[section] = values if section in ("soil", "interface") else \\
                {**data.get(section, {}), **values}
        scene = Scene.from_dict(data)
    r = analyse(scene).results
    import resource
    events = {}
    for name in ("MatLUFactorSym", "MatLUFactorNum", "MatCholFctrSym", "MatCholFctrNum",
                 "MatSolve", "MatAssemblyEnd"):
        info = PETSc.Log.Event(name).getPerfInfo()
        events[name] = [info["count"], MPI.COMM_WORLD.allreduce(info["time"], op=MPI.MAX)]
    if MPI.COMM_WORLD.rank == 0:
        print("RESULT " + json.dumps({"wall_s": time.perf_counter() - t0,
                                      "max_rss_gb": resource.getrusage(
                                          resource.RUSAGE_SELF).ru_maxrss / 1e6,
                                      "timings_s": r["timings_s"], "dofs": r["dofs"],
                                      "solves": r["linear_solves"], "w0": r["w0"],
                                      "soil_iterations": r["soil"].get("iterations", 0),
                                      "events": events}))
""")


def _analysis(scene: Path, changes: dict, ranks: int = 1) -> dict:
    cmd = [PY, "-c", _ANALYSIS, str(scene), json.dumps(changes)]
    if ranks > 1:
        cmd = [MPIEXEC, "-n", str(ranks), *cmd]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-3000:])
    line = [ln for ln in proc.stdout.splitlines() if ln.startswith("RESULT ")][-1]
    return json.loads(line[len("RESULT "):])


def profile(out: dict) -> None:
    scene = ROOT / "demos" / "scenes" / "embedded_tank_nonlinear.toml"
    linear = {"soil": {"E": 1 / 2.1e-7, "nu": 0.3, "E_gradient": 0.1},
              "interface": {"condition": "bonded"}}
    _analysis(scene, {})                      # JIT and disk caches warm, as for a user
    nl, li = _analysis(scene, {}), _analysis(scene, linear)
    print(f"\nProfile: {scene.name} ({nl['dofs']['total']} dofs), serial, whole process")
    print(f"{'part':34s} {'nonlinear s':>12s} {'linear s':>10s}")
    rows = [("process start, imports", nl["wall_s"] - nl["timings_s"]["total"],
             li["wall_s"] - li["timings_s"]["total"])]
    for key, label in (("mesh", "meshing (gmsh, distribution)"),
                       ("forms", "forms (JIT cache), model"),
                       ("assemble_solve", "assembly + solves + iteration"),
                       ("post", "post-processing")):
        rows.append((label, nl["timings_s"][key], li["timings_s"][key]))
    for name, label in (("MatLUFactorNum", "  of which numeric LU"),
                        ("MatCholFctrNum", "  of which numeric LDL^T"),
                        ("MatLUFactorSym", "  of which symbolic LU"),
                        ("MatCholFctrSym", "  of which symbolic LDL^T"),
                        ("MatSolve", "  of which forward/back solves")):
        a, b = nl["events"][name], li["events"][name]
        if a[0] or b[0]:
            rows.append((f"{label} ({a[0]} / {b[0]})", a[1], b[1]))
    for label, a, b in rows:
        print(f"{label:34s} {a:12.2f} {b:10.2f}")
    ratio = nl["wall_s"] / li["wall_s"]
    print(f"{'whole process':34s} {nl['wall_s']:12.2f} {li['wall_s']:10.2f}")
    print(f"nonlinear / linear = {ratio:.2f} (target <= 5); {nl['solves']} solves against 1")
    out["profile"] = {"nonlinear": nl, "linear": li, "ratio": ratio}


#: The scenes of the parallel benchmark: (scene file, its refinement as a function of the
#: ``--near-size`` of the embedded tanks). The linear embedded tank is one factorisation,
#: the nonlinear one (hyperbolic soil + Mohr-Coulomb) ~13 on one analysis, and the tank on
#: clay's consolidation ~56 (one per time step): each a larger share of work that scales.
PARALLEL_SCENES = {
    "linear": ("embedded_tank.toml",
               lambda near: {"mesh": {"near_size": near, "edge_size": 0.01}}),
    "nonlinear": ("embedded_tank_nonlinear.toml",
                  lambda near: {"mesh": {"near_size": near, "edge_size": 0.01}}),
    # (the clay tank's a is 15 m, its mesh Taylor-Hood: 0.25 m gives 191k dofs)
    "consolidation": ("tank_on_clay.toml",
                      lambda near: {"mesh": {"near_size": near * 0.25 / 0.35}}),
}


def parallel(out: dict, repeat: int, near_size: float = 0.35,
             scenes=tuple(PARALLEL_SCENES)) -> None:
    """One analysis on 1 and 2 ranks, whole process, for each of ``scenes`` (keys of
    PARALLEL_SCENES), refined by ``near_size`` (0.35 m: about 270k dofs for the embedded
    tanks, 190k for the tank on clay). This machine's timings of one run vary by 10-15 %,
    so each is run ``repeat`` times, 1 and 2 ranks alternating, and the medians are
    compared."""
    out["parallel"] = {}
    for key in scenes:
        name, refine = PARALLEL_SCENES[key]
        fine = refine(near_size)
        scene = ROOT / "demos" / "scenes" / name
        _analysis(scene, fine)
        runs = {1: [], 2: []}
        for _ in range(repeat):
            for n in (1, 2):
                runs[n].append(_analysis(scene, fine, n))
        one, two = runs[1][0], runs[2][0]
        print(f"\nParallel: {scene.name}, {one['dofs']['total']} dofs, {one['solves']} solves, "
              f"{repeat} runs each (median, and the range)")
        print(f"{'ranks':>5s} {'mesh s':>7s} {'solve s':>8s} {'post s':>7s} {'process s':>10s} "
              f"{'range s':>12s}")
        med = {}
        for n in (1, 2):
            t = {k: statistics.median(r["timings_s"][k] for r in runs[n])
                 for k in ("mesh", "assemble_solve", "post")}
            walls = [r["wall_s"] for r in runs[n]]
            med[n] = (statistics.median(walls), t["assemble_solve"])
            print(f"{n:5d} {t['mesh']:7.2f} {t['assemble_solve']:8.2f} {t['post']:7.2f} "
                  f"{med[n][0]:10.2f} {min(walls):5.2f}-{max(walls):5.2f}")
        speed, solve = med[1][0] / med[2][0], med[1][1] / med[2][1]
        print(f"speed-up on 2 ranks: {speed:.2f} (whole process, medians; target >= 1.5), "
              f"{solve:.2f} (assembly + solve); w0 {one['w0']:.9e} / {two['w0']:.9e}")
        out["parallel"][name] = {"runs": runs, "speedup": speed, "solve_speedup": solve}


def sweep(out: dict, cases: int) -> None:
    import math

    n_kp = max(1, int(round(math.sqrt(cases))))
    n_nu = max(1, cases // n_kp)
    kps = [round(10 ** (-2 + 3 * i / max(n_kp - 1, 1)), 6) for i in range(n_kp)]
    nus = [round(0.4 * i / max(n_nu - 1, 1), 6) for i in range(n_nu)]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        (tmp / "sweep.toml").write_text(
            f'base = "{ROOT / "demos" / "scenes" / "surface_tank.toml"}"\nmode = "grid"\n'
            f'[axes]\n"plate.Kp" = {kps}\n"soil.nu" = {nus}\n')
        times = {}
        for ranks in (1, 2):
            cmd = [PY, "-m", "tankfx", "sweep", str(tmp / "sweep.toml"), "--out",
                   str(tmp / f"out{ranks}")]
            if ranks > 1:
                cmd = [MPIEXEC, "-n", str(ranks), *cmd]
            t = time.perf_counter()
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=7200)
            times[ranks] = time.perf_counter() - t
            if proc.returncode != 0:
                raise RuntimeError(proc.stderr[-3000:])
    n = len(kps) * len(nus)
    speed = times[1] / times[2]
    print(f"\nSweep of {n} surface-tank cases (default meshes): {times[1]:.1f} s on 1 rank, "
          f"{times[2]:.1f} s on 2 ranks: speed-up {speed:.2f} (target >= 1.8)")
    out["sweep"] = {"cases": n, "seconds": times, "speedup": speed}


def iterative(out: dict) -> None:
    rows = []
    print("\nIterative (GAMG) against direct (MUMPS), serial, fresh processes")
    print(f"{'scene':16s} {'near_size':>9s} {'dofs':>9s} {'direct s':>9s} {'GB':>5s} "
          f"{'iterative s':>11s} {'GB':>5s} {'w0 rel diff':>11s}")
    cases = [("flexible_load", 1.0, (0.1, 0.05, 0.025, 0.0125)),
             ("embedded_tank", 10.0, (0.1, 0.05, 0.025, 0.0125))]
    for name, a, sizes in cases:
        scene = ROOT / "demos" / "scenes" / f"{name}.toml"
        for near in sizes:
            mesh = {"mesh": {"near_size": near * a}}
            _analysis(scene, mesh)           # mesh cache and JIT warm for both
            d = _analysis(scene, mesh)
            it = _analysis(scene, {**mesh, "solver": {"method": "iterative"}})
            row = {"scene": name, "near_size": near, "dofs": d["dofs"]["total"],
                   "direct_s": d["timings_s"]["assemble_solve"], "direct_gb": d["max_rss_gb"],
                   "iterative_s": it["timings_s"]["assemble_solve"],
                   "iterative_gb": it["max_rss_gb"], "w0_diff": it["w0"] / d["w0"] - 1}
            rows.append(row)
            print(f"{name:16s} {near:9.4g} {row['dofs']:9d} {row['direct_s']:9.2f} "
                  f"{row['direct_gb']:5.2f} {row['iterative_s']:11.2f} "
                  f"{row['iterative_gb']:5.2f} {row['w0_diff']:11.1e}", flush=True)
    out["iterative"] = rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", choices=["profile", "parallel", "sweep", "iterative"])
    ap.add_argument("--cases", type=int, default=100, help="cases of the sweep benchmark")
    ap.add_argument("--repeat", type=int, default=3,
                    help="runs of each parallel measurement (medians compared)")
    ap.add_argument("--near-size", type=float, default=0.35,
                    help="element size within 6 radii (m) of the parallel benchmark's meshes")
    ap.add_argument("--scenes", nargs="+", choices=list(PARALLEL_SCENES),
                    default=list(PARALLEL_SCENES), help="scenes of the parallel benchmark")
    ap.add_argument("--out", default="results/benchmarks")
    args = ap.parse_args()
    out: dict = {}
    if args.only in (None, "profile"):
        profile(out)
    if args.only in (None, "parallel"):
        parallel(out, args.repeat, args.near_size, args.scenes)
    if args.only in (None, "sweep"):
        sweep(out, args.cases)
    if args.only in (None, "iterative"):
        iterative(out)
    path = Path(args.out)
    path.mkdir(parents=True, exist_ok=True)
    (path / "costs.json").write_text(json.dumps(out, indent=1, default=str))
    print(f"\nwritten to {path / 'costs.json'}")


if __name__ == "__main__":
    main()
