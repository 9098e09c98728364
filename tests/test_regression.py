"""The results a user reads, for every scene of ``demos/scenes/`` on the coarse mesh, against
the values recorded before the package was restructured (``tests/data/regression.json``).

It guards against any unintended change of a number: a change of method that is meant to
move a result records the values again, with the reason in the commit, by::

    python tests/test_regression.py --record

Compared: w0, w_edge, wd, w_mean, M0, the non-dimensional set, the junction's moments, the
settlement summary, and the numbers of the load path's stages, of the overturning's first
harmonic and of a consolidation's history; each to a tolerance relative to its quantity's
scale (a list's largest magnitude), by the kind of scene.

The tolerances come from the numerics, not from one machine. ``benchmarks/reproducibility.py``
solved every scene again with what legitimately varies between machines: 2 BLAS threads,
OpenBLAS's kernels of three other processors (``OPENBLAS_CORETYPE`` Haswell, SandyBridge,
Prescott), MUMPS's AMD, METIS and PORD orderings, and 2 MPI ranks. The largest difference from
the base run, over each scene's numbers (2026-11-26, AMD EPYC, 2 cores):

==========================  ========  ========  ==========  ========  =========
scene                       threads   kernels   orderings   2 ranks   recorded
==========================  ========  ========  ==========  ========  =========
flexible_load               0         7.2e-14   9.2e-14     3.4e-14   2.3e-13
embedded_tank               0         3.7e-10   5.1e-11     1.6e-11   5.0e-11
layered_tank                0         3.6e-10   4.4e-10     3.5e-10   1.9e-10
surface_tank                0         7.3e-10   5.3e-10     1.4e-10   3.3e-10
steel_tank                  0         5.7e-11   1.5e-10     1.2e-10   1.3e-10
steel_tank_seismic          0         5.3e-10   5.1e-10     7.5e-10   1.0e-09
rebonding                   0         2.3e-10   2.4e-10     3.2e-10   2.1e-10
tank_on_clay                0         1.2e-09   2.2e-10     6.1e-10   1.0e-09
embedded_tank_nonlinear     0         1.3e-09   2.4e-09     6.7e-10   1.1e-09
tank_on_sand                0         1.1e-09   0           3.1e-10   5.0e-10
hydrotest                   0         7.6e-08   6.1e-08     1.8e-08   6.6e-08
==========================  ========  ========  ==========  ========  =========

("recorded": this machine against ``regression.json``, recorded on another; the old test's
single 1e-9 failed hydrotest, tank_on_clay, embedded_tank_nonlinear and steel_tank_seismic
there. Two BLAS threads gave the same numbers to the last bit.)
A scene solved once, or by an active set or time steps whose every step is a linear solve,
differs by round-off amplified by its conditioning: at most 1.2e-9. A scene whose soil is
iterated by the secant (Picard) loop runs the same iterations everywhere, each carrying the
last one's round-off on: at most 7.6e-8 (hydrotest's ten stages with the soil's memory). The
tolerances are these with a margin of about a hundred: ``TOLERANCE``. A change of 1e-4 in a
modulus moves w0 by 1e-4, 1000 times the linear tolerance and 10 times the secant one
(``test_a_change_of_a_modulus_by_one_in_ten_thousand_is_caught``).

An equilibrium's relative error (the overturning's ``*_relative_error``, about 1e-11) is
round-off itself, and its digits differ by 40-190 % between those runs: it is checked to be
below ``EQUILIBRIUM`` instead of compared.
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)

import pytest

from tankfx import analyse, load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = sorted((ROOT / "demos" / "scenes").glob("*.toml"))
RECORD = Path(__file__).with_name("data") / "regression.json"
#: the results read, and the sections whose numbers (scalars and lists) are read whole
KEYS = ("w0", "w_edge", "wd", "w_mean", "M0", "nondim", "junction", "settlement_summary",
        "stages", "overturning", "consolidation")
#: numbers that are costs, not results
SKIP = {"timings_s", "linear_solves", "solves", "iterations", "history", "relative_residual",
        "last_relative_residual", "krylov_iterations"}
#: the tolerance of a scene's numbers, relative to each quantity's scale, by how it is
#: solved: its measured spread (the table above) times about a hundred
#: ("newton": the elastoplastic soil's load steps, each converged to 1e-8 of the load vector,
#: carry their round-off on as the secant loop's iterations do: the secant's tolerance)
TOLERANCE = {"linear": 1e-7, "secant": 1e-5, "newton": 1e-5}
#: an equilibrium's relative error (round-off itself) must stay below this
EQUILIBRIUM = 1e-8


def kind(scene) -> str:
    """How a scene is solved, as far as its numbers' reproducibility goes: "secant" where
    the soil is iterated by the secant (Picard) loop, else "linear" (one solve, an active set
    or time steps, each step a linear solve)."""
    return scene.soil.law.iteration or "linear"


def numbers(value, path: str = "") -> dict[str, float | None]:
    """The numbers of a results entry, flattened to {dotted path: value} (lists by index);
    strings and booleans kept as they are (a state's name, ``converged``)."""
    out: dict = {}
    if isinstance(value, dict):
        for k, v in value.items():
            if k not in SKIP:
                out.update(numbers(v, f"{path}.{k}" if path else k))
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            out.update(numbers(v, f"{path}[{i}]"))
    else:
        out[path] = value
    return out


def read(scene_file: Path, **changes) -> dict:
    """The numbers compared of a scene file's analysis on its coarse mesh (with ``changes``,
    as Scene.with_changes takes them)."""
    scene = load_scene(scene_file).with_coarse_mesh()
    results = analyse(scene.with_changes(**changes) if changes else scene).results
    return numbers({k: results[k] for k in KEYS if k in results})


def _stem(key: str) -> str:
    """A list entry's list (``a.b[3]`` -> ``a.b``); a scalar is its own."""
    return key.split("[", 1)[0]


def _scales(recorded: dict) -> dict[str, float]:
    """Each quantity's scale: the largest magnitude of its list (so a moment that passes
    through zero is compared to its peak), or of itself."""
    out: dict[str, float] = {}
    for k, v in recorded.items():
        if isinstance(v, float) and math.isfinite(v):
            out[_stem(k)] = max(out.get(_stem(k), 0.0), abs(v))
    return out


def mismatches(recorded: dict, now: dict, tolerance: float) -> list[str]:
    """Where ``now`` differs from ``recorded``: a key added or lost, a state changed, a
    number beyond ``tolerance`` of its quantity's scale, an equilibrium error beyond
    EQUILIBRIUM; each with the values."""
    if sorted(now) != sorted(recorded):
        return [f"the results' keys changed: {sorted(set(now) ^ set(recorded))[:10]}"]
    scales = _scales(recorded)
    out = []
    for key, ref in recorded.items():
        val = now[key]
        if key.endswith("relative_error"):
            if not abs(val) <= EQUILIBRIUM:
                out.append(f"{key} = {val:.3g}, above {EQUILIBRIUM:g}")
        elif isinstance(ref, float):
            scale = max(scales[_stem(key)], 1e-300)
            if not abs(val - ref) <= tolerance * scale:
                out.append(f"{key} = {val!r}, recorded {ref!r} (difference "
                           f"{abs(val - ref) / scale:.2g} of its scale, tolerance {tolerance:g})")
        elif val != ref:
            out.append(f"{key} = {val!r}, recorded {ref!r}")
    return out


@pytest.mark.parametrize("scene_file", SCENES, ids=[s.stem for s in SCENES])
def test_results_unchanged(scene_file):
    recorded = json.loads(RECORD.read_text())[scene_file.stem]
    tolerance = TOLERANCE[kind(load_scene(scene_file))]
    problems = mismatches(recorded, read(scene_file), tolerance)
    assert not problems, f"{len(problems)} number(s) changed:\n" + "\n".join(problems[:20])


@pytest.mark.parametrize("scene_file, changes", [
    (SCENES[0].with_name("embedded_tank.toml"), {"soil": {"E": 10e6 * (1 + 1e-4)}}),
    pytest.param(SCENES[0].with_name("hydrotest.toml"),
                 {"soil": {"hyperbolic_a": 2.1e-7 * (1 - 1e-4)}}, marks=pytest.mark.verify),
], ids=["linear", "secant"])
def test_a_change_of_a_modulus_by_one_in_ten_thousand_is_caught(scene_file, changes):
    """The tolerances still see a real change: the soil's modulus (the hydrotest's initial
    modulus 1/a) raised by 1e-4 moves w0 by 1e-4 and fails the comparison, at five times its
    tolerance too."""
    scene = load_scene(scene_file)
    section, = changes
    (name, value), = changes[section].items()
    assert value == pytest.approx(getattr(scene.soil, name), rel=2e-4)   # the file's, changed
    tolerance = TOLERANCE[kind(scene)]
    recorded = json.loads(RECORD.read_text())[scene_file.stem]
    changed = read(scene_file, **changes)
    assert mismatches(recorded, changed, tolerance)
    assert mismatches(recorded, changed, 5 * tolerance)      # (measured: 10x and 1000x)


if __name__ == "__main__" and "--record" in sys.argv:
    RECORD.parent.mkdir(exist_ok=True)
    RECORD.write_text(json.dumps({s.stem: read(s) for s in SCENES}, indent=1,
                                 sort_keys=True) + "\n")
    print(f"recorded {len(SCENES)} scenes in {RECORD}")
