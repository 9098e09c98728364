"""The scene file's keys: each section's keys, their types and whether they are required, the
allowed values of the choice keys, and the reader that checks a section against them and
collects every problem.
"""
from __future__ import annotations

import difflib
import math
from typing import Any

from .sections import STRATUM_DUNCAN_CHANG

SPEC: dict[str, dict[str, tuple[type, bool]]] = {
    # section: key -> (type, required)
    "soil": {"E": (float, False), "nu": (float, True), "E_gradient": (float, False),
             "model": (str, False), "hyperbolic_a": (float, False),
             "hyperbolic_b": (float, False), "tolerance": (float, False),
             "max_iterations": (int, False), "modulus_number": (float, False),
             "modulus_exponent": (float, False), "failure_ratio": (float, False),
             "cohesion": (float, False), "friction_angle": (float, False),
             "unit_weight": (float, False), "K0": (float, False),
             "atmospheric_pressure": (float, False), "water_table": (float, False),
             "water_unit_weight": (float, False), "unloading_modulus_ratio": (float, False)},
    "plate": {"radius": (float, True), "thickness": (float, False), "Kp": (float, False),
              "E": (float, True), "nu": (float, True), "embedment": (float, False),
              "unit_weight": (float, False), "annular_width": (float, False),
              "annular_thickness": (float, False)},
    "wall": {"radius": (float, True), "thickness": (float, False), "Kt": (float, False),
             "height": (float, False), "E": (float, True), "nu": (float, True),
             "unit_weight": (float, False), "courses": (list, False)},
    "ringwall": {"inner_radius": (float, True), "outer_radius": (float, True),
                 "depth": (float, True), "E": (float, True), "nu": (float, False),
                 "unit_weight": (float, False), "fill_E": (float, False),
                 "fill_nu": (float, False)},
    "interface": {"condition": (str, False), "cohesion": (float, False),
                  "tan_phi": (float, False), "friction_angle": (float, False),
                  "normal_stiffness": (float, False), "shear_stiffness": (float, False),
                  "on_cycle": (str, False), "states": (str, False)},
    "load": {"pressure": (float, False), "load_radius": (float, False),
             "liquid_unit_weight": (float, False), "liquid_height": (float, False),
             "self_weight": (bool, False), "roof_weight": (float, False),
             "gas_pressure": (float, False), "overturning_moment": (float, False),
             "base_shear": (float, False)},
    "domain": {"radius": (float, False), "depth": (float, False)},
    "mesh": {"degree": (int, False), "edge_size": (float, False), "growth": (float, False),
             "near_size": (float, False)},
    "solver": {"method": (str, False), "rtol": (float, False), "max_iterations": (int, False)},
    "consolidation": {"permeability": (float, True), "times": (list, True),
                      "water_unit_weight": (float, False), "drainage": (str, False),
                      "steps_per_decade": (int, False)},
}


#: the keys of one [[soil.layers]] table
LAYER_SPEC: dict[str, tuple[type, bool]] = {
    "depth": (float, True), "nu": (float, True), "permeability": (float, False),
    **{key: (float, False) for key in ("E", "E_gradient", "hyperbolic_a", "hyperbolic_b",
                                       *STRATUM_DUNCAN_CHANG)}}


SOLVER_METHODS = ("direct", "iterative")


TOP = {"title": str}


REQUIRED_SECTIONS = ("soil", "load")


SOIL_MODELS = ("linear", "hyperbolic", "duncan_chang")


#: the keys of Duncan & Chang's soil, and those of them it requires
DUNCAN_CHANG = (*STRATUM_DUNCAN_CHANG, "atmospheric_pressure", "water_table",
                 "water_unit_weight")


DUNCAN_CHANG_REQUIRED = ("modulus_number", "modulus_exponent", "unit_weight")


CONDITIONS = ("bonded", "smooth", "mohr_coulomb")


ON_CYCLE = ("hold", "stop")


STATES = ("element", "node")


DRAINAGE = ("top", "top_and_bottom")


def suggest(name: str, valid) -> str:
    close = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.5)
    return f" (did you mean '{close[0]}'?)" if close else f" (valid: {', '.join(valid)})"


class Reader:
    """Collects every problem of a scene dict instead of stopping at the first."""

    def __init__(self, data: dict[str, Any]):
        self.data = data
        self.problems: list[str] = []

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
        for key, (_, required) in SPEC[name].items():
            if required and key not in sec:
                self.bad(f"{name}.{key}: missing; add '{key} = ...' under [{name}]")
        return out

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

    def poisson(self, sec: dict, name: str, key: str = "nu", incompressible=False) -> None:
        """(-1, 0.5) for the shells; the soil may be incompressible (0.5, mixed form)."""
        v = sec.get(key)
        if v is None:
            return
        if incompressible and not -1.0 < v <= 0.5:
            self.bad(f"{name}.{key} = {v!r}: Poisson's ratio must lie in (-1, 0.5] (0.5: "
                     f"incompressible, e.g. undrained clay)")
        elif not incompressible and not -1.0 < v < 0.5:
            self.bad(f"{name}.{key} = {v!r}: Poisson's ratio must lie in (-1, 0.5) for a "
                     f"plate or wall (thin-shell theory; use e.g. 0.3)")
