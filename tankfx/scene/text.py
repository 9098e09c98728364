"""The scene in words: the strata, a ringwall and the members as `tankfx check` and the report
write them.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..laws.soil_laws import SOIL_LAWS


def stratum_constants(model: str, st: Mapping[str, Any]) -> str:
    """A stratum's constants of its soil law in words, as `tankfx check` and the report
    write them (``st``: a :class:`Layer` as a dict, or a stratum of results.json's scene):
    Kondner's 1/b (its 1/a is the stratum's E), or Duncan & Chang's K, n, R_f, c, phi,
    gamma and K0; nothing for a linear soil."""
    return SOIL_LAWS[model].stratum_text(st)


def ringwall_text(ring: Mapping[str, Any]) -> str:
    """A ringwall in words, as `tankfx check` and the report write it (``ring``: its table
    of :meth:`Scene.to_dict`)."""
    weight = (f", net unit weight {ring['unit_weight']:g} N/m^3" if ring.get("unit_weight")
              else "")
    if ring.get("fill_E") is not None:
        weight += (f"; a fill inside it, E = {ring['fill_E']:.4g} Pa, nu = "
                   f"{ring.get('fill_nu', 0.3):g} (linear)")
    return (f"r = {ring['inner_radius']:g} to {ring['outer_radius']:g} m, {ring['depth']:g} m "
            f"deep, E = {ring['E']:.4g} Pa, nu = {ring.get('nu', 0.2):g} (linear){weight}")


def member_text(name: str, part: Mapping[str, Any], K: float) -> str:
    """The plate's or wall's geometry in words, as `tankfx check` and the report write it
    (``part``: its table of :meth:`Scene.to_dict`; ``K``: its Kp or Kt)."""
    if name == "plate":
        ring = (f" (annular ring {part['annular_width']:g} m wide, "
                f"{part['annular_thickness']:.4g} m thick)" if part.get("annular_width") else "")
        return (f"a = {part['radius']:g} m, t = {part['thickness']:.4g} m{ring}, Kp = {K:.4g}, "
                f"embedment {part.get('embedment', 0.0):g} m")
    courses = part.get("courses")
    t = (f"{len(courses)} courses (height x thickness from the bottom: "
         + ", ".join(f"{c['height']:g} m x {1e3 * c['thickness']:.4g} mm" for c in courses)
         + ")") if courses else f"t = {part['thickness']:.4g} m"
    return (f"a_t = {part['radius']:g} m, {t}, H = {part['height']:g} m, Kt = {K:.4g}"
            + (" (bottom course)" if courses else ""))
