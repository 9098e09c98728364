"""Where the time goes, and the cost ratios of the performance targets, measured in one run
on this machine:

1. ``profile``: the nonlinear embedded tank of ``make demo`` (hyperbolic soil + Mohr-Coulomb
   interface) against the linear solve of the same scene (soil of E = 1/a, bonded), each
   in a fresh process (whole-process wall time, JIT cache warm), with PETSc's event log
   (factorisations, triangular solves) beside tankfx's own timings. Target: nonlinear
   <= 5 x linear.
2. ``parallel``: one scene of about 200k dofs on 1 and on 2 MPI ranks. Target: 2 ranks
   >= 1.5 x faster.
3. ``sweep``: a sweep of N default cases (the surface tank over Kp and nu_s) on 1 and on 2
   ranks. Target (N = 100): >= 1.8 x faster.

    python benchmarks/costs.py [--only profile|parallel|sweep] [--cases 100]
                               [--out results/benchmarks]

Every measurement runs in its own process (``mpiexec -n N python ...``), so that the ranks
and the memory are those a user gets.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
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
    events = {}
    for name in ("MatLUFactorSym", "MatLUFactorNum", "MatCholFctrSym", "MatCholFctrNum",
                 "MatSolve", "MatAssemblyEnd"):
        info = PETSc.Log.Event(name).getPerfInfo()
        events[name] = [info["count"], MPI.COMM_WORLD.allreduce(info["time"], op=MPI.MAX)]
    if MPI.COMM_WORLD.rank == 0:
        print("RESULT " + json.dumps({"wall_s": time.perf_counter() - t0,
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


def parallel(out: dict) -> None:
    scene = ROOT / "demos" / "scenes" / "embedded_tank.toml"
    fine = {"mesh": {"near_size": 0.35, "edge_size": 0.01}}   # about 200k dofs
    _analysis(scene, fine)
    one, two = _analysis(scene, fine, 1), _analysis(scene, fine, 2)
    print(f"\nParallel: {scene.name}, {one['dofs']['total']} dofs")
    print(f"{'ranks':>5s} {'mesh s':>7s} {'solve s':>8s} {'post s':>7s} {'process s':>10s}")
    for n, r in ((1, one), (2, two)):
        t = r["timings_s"]
        print(f"{n:5d} {t['mesh']:7.2f} {t['assemble_solve']:8.2f} {t['post']:7.2f} "
              f"{r['wall_s']:10.2f}")
    speed = one["wall_s"] / two["wall_s"]
    solve = one["timings_s"]["assemble_solve"] / two["timings_s"]["assemble_solve"]
    print(f"speed-up on 2 ranks: {speed:.2f} (whole process; target >= 1.5), "
          f"{solve:.2f} (assembly + solve); w0 {one['w0']:.9e} / {two['w0']:.9e}")
    out["parallel"] = {"one": one, "two": two, "speedup": speed, "solve_speedup": solve}


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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", choices=["profile", "parallel", "sweep"])
    ap.add_argument("--cases", type=int, default=100, help="cases of the sweep benchmark")
    ap.add_argument("--out", default="results/benchmarks")
    args = ap.parse_args()
    out: dict = {}
    if args.only in (None, "profile"):
        profile(out)
    if args.only in (None, "parallel"):
        parallel(out)
    if args.only in (None, "sweep"):
        sweep(out, args.cases)
    path = Path(args.out)
    path.mkdir(parents=True, exist_ok=True)
    (path / "costs.json").write_text(json.dumps(out, indent=1, default=str))
    print(f"\nwritten to {path / 'costs.json'}")


if __name__ == "__main__":
    main()
