"""The results a user reads, for every scene of ``demos/scenes/`` on the coarse mesh, against
the values recorded before the package was restructured (``tests/data/regression.json``).

It guards against any unintended change of a number: a change of method that is meant to
move a result records the values again, with the reason in the commit, by::

    python tests/test_regression.py --record

Compared: w0, w_edge, wd, w_mean, M0, the non-dimensional set, the junction's moments, the
settlement summary, and the numbers of the load path's stages, of the overturning's first
harmonic and of a consolidation's history; to 1e-9 of each quantity's scale.
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
RTOL = 1e-9


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


def read(scene_file: Path) -> dict:
    results = analyse(load_scene(scene_file).with_coarse_mesh()).results
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


@pytest.mark.parametrize("scene_file", SCENES, ids=[s.stem for s in SCENES])
def test_results_unchanged(scene_file):
    recorded = json.loads(RECORD.read_text())[scene_file.stem]
    now = read(scene_file)
    assert sorted(now) == sorted(recorded), "the results' keys changed"
    scales = _scales(recorded)
    for key, ref in recorded.items():
        val = now[key]
        if isinstance(ref, float):
            tol = RTOL * max(scales[_stem(key)], 1e-300)
            assert val == pytest.approx(ref, rel=0, abs=tol), key
        else:
            assert val == ref, key


if __name__ == "__main__" and "--record" in sys.argv:
    RECORD.parent.mkdir(exist_ok=True)
    RECORD.write_text(json.dumps({s.stem: read(s) for s in SCENES}, indent=1,
                                 sort_keys=True) + "\n")
    print(f"recorded {len(SCENES)} scenes in {RECORD}")
