"""The reader of a scene file: each section's keys (derived from the dataclasses' fields,
:mod:`tankfx.scene.keys`), their types, whether they are required and their limits, the
allowed values of the choice keys, and the reader that checks a section against them and
collects every problem.
"""
from __future__ import annotations

import difflib
import math
from dataclasses import fields
from typing import Any

from .keys import Key
from .plausible import implausible
from .sections import (
    ALTERNATIVE_KEYS,
    Analysis,
    Consolidation,
    DomainSize,
    Fill,
    Interface,
    Layer,
    Load,
    MeshOptions,
    Plate,
    Ringwall,
    Soil,
    SolverOptions,
    Wall,
)

#: The sections of a scene file and the dataclass each is read into
SECTIONS = {"soil": Soil, "plate": Plate, "wall": Wall, "ringwall": Ringwall,
            "interface": Interface, "load": Load, "domain": DomainSize, "mesh": MeshOptions,
            "solver": SolverOptions, "consolidation": Consolidation, "analysis": Analysis,
            "fill": Fill}
_TYPES = {"float": float, "int": int, "bool": bool, "str": str}


def keys_of(cls, extra: dict[str, Key] | None = None) -> dict[str, Key]:
    """The scene keys of a section's dataclass, in its fields' order (the fields declared
    with :func:`tankfx.scene.keys.key`), then the alternatives it also takes."""
    out = {f.name: f.metadata["key"] for f in fields(cls) if "key" in f.metadata}
    return out | (extra or {})


def type_of(cls, name: str) -> type:
    """A key's type, from its field's annotation (``float | None`` is a float; a tuple, a
    list of tables or numbers)."""
    hints = {f.name: f.type for f in fields(cls)}
    hint = str(hints.get(name, "float")).replace(" | None", "")
    return list if hint.startswith("tuple") else _TYPES[hint]


#: Every section's keys: name -> Key (type, unit, meaning, limit, default: tankfx.scene.keys)
KEYS: dict[str, dict[str, Key]] = {name: keys_of(cls, ALTERNATIVE_KEYS.get(name))
                                   for name, cls in SECTIONS.items()}
#: the keys of one [[soil.layers]] table
LAYER_KEYS: dict[str, Key] = keys_of(Layer)
#: section -> key -> (type, required), as the reader checks them
SPEC: dict[str, dict[str, tuple[type, bool]]] = {
    name: {k: (key.kind or type_of(SECTIONS[name], k), key.required) for k, key in keys.items()}
    for name, keys in KEYS.items()}
LAYER_SPEC: dict[str, tuple[type, bool]] = {k: (type_of(Layer, k), key.required)
                                            for k, key in LAYER_KEYS.items()}

SOLVER_METHODS = KEYS["solver"]["method"].choices
SOIL_MODELS = KEYS["soil"]["model"].choices
CONDITIONS = KEYS["interface"]["condition"].choices
ON_CYCLE = KEYS["interface"]["on_cycle"].choices
STATES = KEYS["interface"]["states"].choices
DRAINAGE = KEYS["consolidation"]["drainage"].choices
COLLAPSES = KEYS["analysis"]["collapse"].choices

TOP = {"title": str, "accept": list}
REQUIRED_SECTIONS = ("soil", "load")


def suggest(name: str, valid) -> str:
    close = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.5)
    return f" (did you mean '{close[0]}'?)" if close else f" (valid: {', '.join(valid)})"


class Reader:
    """Collects every problem of a scene dict instead of stopping at the first."""

    def __init__(self, data: dict[str, Any]):
        self.data = data
        self.problems: list[str] = []
        #: the keys whose implausible values the scene means (its top-level ``accept``)
        accept = data.get("accept", []) if isinstance(data, dict) else []
        self.accepted = set(accept) if isinstance(accept, list) else set()
        #: the accepted keys that are outside their plausible range, with their values
        self.accepted_outside: list[str] = []

    def bad(self, msg: str) -> None:
        self.problems.append(msg)

    def choice(self, table: dict, name: str, key: str, default: str, allowed,
               meaning: str = "") -> str:
        """``table[key]`` (or ``default``), which must be one of ``allowed``: else a problem
        naming it, the nearest allowed value and, if given, what each means."""
        value = table.get(key, default)
        if value not in allowed:
            self.bad(f"{name}.{key} = {value!r}: unknown{suggest(value, allowed)}"
                     + (f" ({meaning})" if meaning else ""))
        return value

    def section(self, name: str) -> dict[str, Any] | None:
        sec = self.data.get(name)
        if sec is None:
            return None
        if not isinstance(sec, dict):
            self.bad(f"[{name}] must be a table (a '[{name}]' header followed by keys), "
                     f"not {type(sec).__name__}")
            return None
        out = {}
        for key, value in sec.items():
            spec = SPEC[name].get(key)
            if spec is None:
                self.bad(f"{name}.{key}: unknown key{suggest(key, SPEC[name])}")
                continue
            typ, _ = spec
            checked = self._typed(f"{name}.{key}", value, typ)
            if checked is not None:
                out[key] = checked
        self.limits(out, name, KEYS[name])
        for key, (_, required) in SPEC[name].items():
            if required and key not in sec:
                self.bad(f"{name}.{key}: missing; add '{key} = ...' under [{name}]")
        return out

    def limits(self, table: dict, name: str, keys: dict[str, Key]) -> None:
        """Each number of ``table`` (a section, or a layer named ``name``) within its key's
        limit (those not ``custom``, which their section's rules check): else a problem
        naming the key, the value and the range; then within its plausible range
        (:mod:`tankfx.scene.plausible`) unless the scene accepts it."""
        kind = "layer" if name.startswith("soil.layers") else name
        for k, value in table.items():
            spec = keys.get(k)
            if spec is None or not isinstance(value, (int, float)) or isinstance(value, bool):
                continue
            if spec.limit is None or spec.custom or spec.limit.holds(value):
                if k == "E" and table.get("E_gradient", 0.0) > 0.0:
                    # a modulus growing with depth (a Gibson soil starts from almost
                    # nothing): the modulus a metre down is the one checked
                    value = value * (1.0 + table["E_gradient"])
                self.plausible(f"{name}.{k}", f"{kind}.{k}", value, spec.unit)
                continue
            if not spec.limit.holds(value):
                range_ = spec.limit.text()
                need = f"be {range_}" if spec.limit.high is None else f"lie in {range_}"
                self.bad(f"{name}.{k} = {value!r}: must {need}"
                         + (f" ({spec.why})" if spec.why else ""))

    def plausible(self, where: str, name: str, value: float, unit: str) -> None:
        """``value`` of ``where`` within the plausible range of ``name`` ("section.key"), or
        accepted (recorded), or a problem naming the likely slip."""
        problem = implausible(where, name, value, unit, ())
        if problem is None:
            return
        if where in self.accepted:
            self.accepted_outside.append(problem.split(" Give it in")[0].split("; did you")[0])
        else:
            self.bad(problem)

    def _typed(self, where: str, value, typ):
        if typ is list:
            return value                # checked by its section's own rules
        if typ is float:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                self.bad(f"{where}: expected a number, got {value!r}")
                return None
            if not math.isfinite(value):
                self.bad(f"{where}: must be a finite number, got {value!r}")
                return None
            return float(value)
        if typ is int:
            if isinstance(value, bool) or not isinstance(value, int):
                self.bad(f"{where}: expected an integer, got {value!r}")
                return None
            return value
        if typ is bool:
            if not isinstance(value, bool):
                self.bad(f"{where}: expected true or false, got {value!r}")
                return None
            return value
        if not isinstance(value, str):
            self.bad(f"{where}: expected a string, got {value!r}")
            return None
        return value

    def positive(self, sec: dict, name: str, key: str, *, allow_zero: bool = False) -> None:
        v = sec.get(key)
        if v is None:
            return
        if v < 0 or (v == 0 and not allow_zero):
            need = ">= 0" if allow_zero else "> 0"
            self.bad(f"{name}.{key} = {v!r}: must be {need}")
