"""How far the numbers of tests/test_regression.py move with what legitimately varies from
one machine to another: the BLAS's threads and its kernels (OpenBLAS picks them by
processor; ``OPENBLAS_CORETYPE`` forces one), MUMPS's fill-reducing ordering, and the number
of MPI ranks. Each variant reads every scene of ``demos/scenes/`` (coarse mesh) in a fresh
process; the spread of a scene is the largest difference from the base variant over its
numbers, each relative to its quantity's scale (as the test compares them).

    python benchmarks/reproducibility.py              # every variant (about 10 minutes)
    python benchmarks/reproducibility.py base metis   # some

Prints a table (scene x variant) and writes results/reproducibility.json. The
regression test's tolerances are set from it (its docstring and
docs/development/2026-11-27-suite.md give the numbers).
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

OUT = ROOT / "results" / "reproducibility.json"
ONE_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
#: name -> (environment, MUMPS ordering forced (ICNTL(7)) or None, ranks)
VARIANTS = {
    "base": (ONE_THREAD, None, 1),
    "threads_2": ({"OPENBLAS_NUM_THREADS": "2", "OMP_NUM_THREADS": "2"}, None, 1),
    "coretype_haswell": (ONE_THREAD | {"OPENBLAS_CORETYPE": "Haswell"}, None, 1),
    "coretype_sandybridge": (ONE_THREAD | {"OPENBLAS_CORETYPE": "SandyBridge"}, None, 1),
    "coretype_prescott": (ONE_THREAD | {"OPENBLAS_CORETYPE": "Prescott"}, None, 1),
    "ordering_amd": (ONE_THREAD, 0, 1),
    "ordering_metis": (ONE_THREAD, 5, 1),
    "ordering_pord": (ONE_THREAD, 4, 1),
    "ranks_2": (ONE_THREAD, None, 2),
}

#: one variant's numbers, in a fresh process: every scene's, as the test reads them
CHILD = """
import json, sys
sys.path.insert(0, {tests!r})
import dolfinx_solver  # noqa: F401
from mpi4py import MPI
import tankfx.fem.solvers as solvers
ordering = {ordering!r}
if ordering is not None:
    # (every factorisation, one-shot or not, with this ordering, analysed on one rank)
    solvers._ordering = lambda u, one_shot=False: {{"mat_mumps_icntl_28": 1,
                                                   "mat_mumps_icntl_7": ordering}}
from test_regression import SCENES, read
out = {{s.stem: read(s) for s in SCENES}}
if MPI.COMM_WORLD.rank == 0:
    with open({target!r}, "w") as f:
        json.dump(out, f)
"""


def run(name: str, scratch: Path) -> dict:
    env, ordering, ranks = VARIANTS[name]
    target = scratch / f"{name}.json"
    code = CHILD.format(tests=str(ROOT / "tests"), ordering=ordering, target=str(target))
    cmd = [sys.executable, "-c", code]
    if ranks > 1:
        cmd = [shutil.which("mpiexec", path=os.path.dirname(sys.executable)), "-n",
               str(ranks), *cmd]
    clean = {k: v for k, v in os.environ.items()
             if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_CORETYPE")}
    subprocess.run(cmd, env=clean | env, check=True, capture_output=True, text=True)
    return json.loads(target.read_text())


def spread(a: dict, b: dict) -> float:
    """The largest difference of b from a over a scene's numbers, relative to each
    quantity's scale (the test's rule); inf where a non-number (a state) differs. An
    equilibrium's relative error is round-off itself: the test bounds it instead."""
    from test_regression import _scales, _stem

    scales = _scales(a)
    worst = 0.0
    for key, ref in a.items():
        val = b[key]
        if key.endswith("relative_error"):
            continue
        if isinstance(ref, float):
            worst = max(worst, abs(val - ref) / max(scales[_stem(key)], 1e-300))
        elif val != ref:
            return float("inf")
    return worst


def main(names: list[str]) -> None:
    from test_regression import RECORD

    scratch = ROOT / "results" / "reproducibility"
    scratch.mkdir(parents=True, exist_ok=True)
    numbers, seconds = {}, {}
    for name in names:
        t = time.perf_counter()
        numbers[name] = run(name, scratch)
        seconds[name] = time.perf_counter() - t
        print(f"  {name}: {seconds[name]:.0f} s", flush=True)
    base = numbers[names[0]]
    recorded = json.loads(RECORD.read_text())
    table = {scene: {name: spread(base[scene], numbers[name][scene]) for name in names[1:]}
             | {"recorded": spread(base[scene], recorded[scene])} for scene in base}
    cols = [*names[1:], "recorded"]
    print(f"\nspread against {names[0]!r} (largest |difference| / the quantity's scale)")
    print(f"{'scene':28s}" + "".join(f"{c[:14]:>15s}" for c in cols))
    for scene, row in table.items():
        print(f"{scene:28s}" + "".join(f"{row[c]:15.1e}" for c in cols))
    OUT.write_text(json.dumps({"base": names[0], "spread": table, "seconds": seconds,
                               "date": time.strftime("%Y-%m-%d")}, indent=1) + "\n")
    print(f"\nwritten: {OUT}")


if __name__ == "__main__":
    chosen = sys.argv[1:] or list(VARIANTS)
    unknown = set(chosen) - set(VARIANTS)
    if unknown:
        sys.exit(f"unknown variant(s) {sorted(unknown)}: choose from {list(VARIANTS)}")
    main(chosen)
