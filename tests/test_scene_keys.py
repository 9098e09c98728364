"""The scene's keys are declared once, on the sections' dataclasses (tankfx.scene.keys): the
reader's table, the limits it enforces and the generated reference all come from there."""
import math
import subprocess
import sys
from pathlib import Path

import pytest

from tankfx import Scene, SceneError
from tankfx.scene.keydoc import markdown
from tankfx.scene.reader import KEYS, LAYER_KEYS, LAYER_SPEC, SPEC

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "docs" / "scene-keys.md"

#: a scene with every section, for the limits' checks
FULL = {"soil": {"E": 10e6, "nu": 0.3},
        "plate": {"radius": 1.0, "thickness": 0.2, "E": 30e9, "nu": 0.2},
        "wall": {"radius": 1.0, "thickness": 0.02, "height": 3.0, "E": 200e9, "nu": 0.3},
        "ringwall": {"inner_radius": 0.8, "outer_radius": 1.2, "depth": 0.5, "E": 30e9},
        "interface": {"condition": "mohr_coulomb", "tan_phi": 0.5},
        "load": {"pressure": 50e3}, "domain": {}, "mesh": {}, "solver": {}, "analysis": {},
        "consolidation": {"permeability": 1e-9, "times": [86400.0]},
        "fill": {"height": 3.0, "step": 1.0, "rate": 1.0}}


def test_the_reference_is_generated_and_current():
    """docs/scene-keys.md is what `python -m tankfx.scene.keydoc` writes (regenerate it
    after changing a key)."""
    assert REFERENCE.read_text() == markdown()
    check = subprocess.run([sys.executable, "-m", "tankfx.scene.keydoc", "--check",
                            str(REFERENCE)], capture_output=True, text=True)
    assert check.returncode == 0, check.stderr


def test_every_key_is_in_the_reference_with_its_unit_and_meaning():
    text = REFERENCE.read_text()
    for name, keys in KEYS.items():
        section = text.split(f"## [{name}]\n", 1)[1].split("\n## ", 1)[0]
        for key, spec in keys.items():
            assert f"| `{key}` |" in section, f"{name}.{key}"
            assert spec.meaning, f"{name}.{key} has no meaning"
            assert spec.unit or SPEC[name][key][0] in (str, bool), f"{name}.{key}: no unit"
    layers = text.split("## [[soil.layers]]\n", 1)[1]
    for key in LAYER_KEYS:
        assert f"| `{key}` |" in layers, f"soil.layers.{key}"
    assert set(LAYER_KEYS) == set(LAYER_SPEC)


def _outside(limit) -> float:
    """A value just outside a limit."""
    if limit.low is not None:
        return limit.low if limit.low_open else limit.low - 1.0
    return limit.high + 1.0


LIMITED = [(name, key, spec) for name, keys in KEYS.items() for key, spec in keys.items()
           if spec.limit is not None and not spec.custom]


@pytest.mark.parametrize("name, key, spec", LIMITED, ids=[f"{n}.{k}" for n, k, _ in LIMITED])
def test_every_limit_is_enforced_with_the_key_and_the_range(name, key, spec):
    value = _outside(spec.limit)
    if SPEC[name][key][0] is int:
        value = int(math.floor(value))
    data = {sec: dict(table) for sec, table in FULL.items()}
    data[name][key] = value
    with pytest.raises(SceneError) as err:
        Scene.from_dict(data)
    assert f"{name}.{key} = {value!r}: must" in str(err.value)
    assert spec.limit.text() in str(err.value)


def test_within_the_limits_the_full_scene_reads():
    """The scene the limits are checked on is itself valid but for the consolidation's
    rules (a consolidation under a ringwall): the refusals above are the limits'."""
    ok = {sec: dict(t) for sec, t in FULL.items() if sec not in ("consolidation", "fill")}
    scene = Scene.from_dict(ok)
    assert scene.interface.tan_phi == 0.5 and scene.ringwall.nu == 0.2


#: the columns of the reference's tables
HEAD_COLUMNS = ("key", "type", "unit", "default", "allowed", "plausible", "meaning")


def _reference_meanings() -> dict[str, list[str]]:
    """Meaning -> the keys (``section.key``) whose row in the generated reference gives it,
    over every table: the top level, each section, [[soil.layers]]."""
    meanings: dict[str, list[str]] = {}
    section = None
    for line in markdown().splitlines():
        if line.startswith("## "):
            section = line[3:].strip("[]")
        elif line.startswith("| `"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            assert len(cells) == len(HEAD_COLUMNS), f"{section}: a row of {len(cells)} " \
                f"columns (a '|' in a cell?): {line}"
            meanings.setdefault(cells[-1], []).append(f"{section}.{cells[0].strip('`')}")
    return meanings


def test_every_key_has_a_meaning_of_its_own():
    """No two keys of the reference share a meaning: each says what it itself is (keys that
    belong together name their partner), and none is empty."""
    meanings = _reference_meanings()
    keys = [k for ks in meanings.values() for k in ks]
    assert len(keys) > 80, f"only {len(keys)} rows found: the parse missed tables"
    empty = [k for m, ks in meanings.items() if m in ("", "-") for k in ks]
    assert not empty, f"keys without a meaning: {empty}"
    shared = {m: ks for m, ks in meanings.items() if len(ks) > 1}
    assert not shared, "keys sharing a meaning:\n" + "\n".join(
        f"  {', '.join(ks)}: {m[:70]!r}" for m, ks in shared.items())
