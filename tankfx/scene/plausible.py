"""What real tanks and soils span: each physical key's plausible range, and the geometry that
a shell or plate theory covers. A value outside is refused before any work, with the key,
the value, the range and the likely slip of units ("30000 Pa: did you mean 30000 kPa = 3e+07
Pa?"); a user who means it lists the key in the scene's top-level ``accept = [...]``, and the
results record it (``scene.accept`` and a warning).

The ranges are wide on purpose: they catch a slip of a factor of a thousand, not an unusual
design. Sources of the bounds: soil moduli from peat (about 0.1 MPa) to rock (tens of GPa);
structural moduli from polymers and timber (1-10 GPa) through concrete (20-40 GPa) to steel
(200 GPa); unit weights of soils 10-28 kN/m^3, of liquids from LNG (about 4.5 kN/m^3) to
molasses and liquid sulphur (about 18 kN/m^3), of structural materials 5-80 kN/m^3.
"""
from __future__ import annotations

import re

from .keys import Limit

__all__ = ["PLAUSIBLE", "implausible", "WALL_THIN", "WALL_THICKEST", "PLATE_THIN",
           "PLATE_THICKEST", "DOMAIN_WIDEST", "accept_problems", "ratio_problem",
           "geometry_warnings"]

_SOIL_E = (Limit(1e5, 1e11, low_open=False), "soil moduli span peat (about 0.1 MPa) to rock "
                                             "(up to about 100 GPa)")
_STRUCTURE_E = (Limit(5e8, 4e11, low_open=False),
                "structural moduli span polymers and timber (1-10 GPa), concrete (20-40 GPa) "
                "and steel (200 GPa)")
_STRUCTURE_GAMMA = (Limit(5e3, 1e5, low_open=False),
                    "structural materials weigh 5 (timber) to 78 (steel) kN/m^3")
_SOIL_GAMMA = (Limit(8e3, 3e4, low_open=False), "soils weigh about 10 (peat) to 28 (rock) kN/m^3")
_RADIUS = (Limit(0.2, 200.0, low_open=False),
           "tanks and rafts from 0.2 m to 200 m in radius (the largest tanks are about 50 m)")
_PERMEABILITY = (Limit(1e-13, 1.0, low_open=False),
                 "from clays (1e-11 m/s and less) to gravels (1e-1 m/s)")
_WATER = (Limit(9e3, 1.2e4, low_open=False), "water weighs 9.81 kN/m^3 (sea water 10.05)")

#: section.key -> (plausible range, where it comes from); "layer" is a [[soil.layers]]
#: table. A zero of a key that may be zero (a unit weight, a cohesion: none) is not checked.
PLAUSIBLE: dict[str, tuple[Limit, str]] = {
    "soil.E": _SOIL_E,
    "layer.E": _SOIL_E,
    "soil.hyperbolic_a": (Limit(1e-11, 1e-5, low_open=False),
                          "1/a is the initial modulus: " + _SOIL_E[1]),
    "layer.hyperbolic_a": (Limit(1e-11, 1e-5, low_open=False),
                           "1/a is the initial modulus: " + _SOIL_E[1]),
    "soil.hyperbolic_b": (Limit(1e-8, 1e-3, low_open=False),
                          "1/b is the ultimate deviator stress, 1 kPa to 100 MPa"),
    "layer.hyperbolic_b": (Limit(1e-8, 1e-3, low_open=False),
                           "1/b is the ultimate deviator stress, 1 kPa to 100 MPa"),
    "soil.modulus_number": (Limit(5.0, 2e4, low_open=False),
                            "Duncan & Chang's tables give K of about 50 to 5000"),
    "layer.modulus_number": (Limit(5.0, 2e4, low_open=False),
                             "Duncan & Chang's tables give K of about 50 to 5000"),
    "soil.unit_weight": _SOIL_GAMMA,
    "layer.unit_weight": _SOIL_GAMMA,
    "soil.cohesion": (Limit(None, 1e6), "soils' cohesion is below 1 MPa"),
    "layer.cohesion": (Limit(None, 1e6), "soils' cohesion is below 1 MPa"),
    "soil.atmospheric_pressure": (Limit(5e4, 2e5, low_open=False),
                                  "p_a is 101.325 kPa at sea level"),
    "soil.water_unit_weight": _WATER,
    "layer.permeability": _PERMEABILITY,
    "consolidation.permeability": _PERMEABILITY,
    "consolidation.water_unit_weight": _WATER,
    "plate.radius": _RADIUS,
    "plate.thickness": (Limit(1e-3, 10.0, low_open=False),
                        "from a steel tank's 5 mm bottom to a 5 m raft"),
    "plate.annular_thickness": (Limit(1e-3, 10.0, low_open=False),
                                "from a steel tank's 5 mm bottom to a 5 m raft"),
    "plate.E": _STRUCTURE_E,
    "plate.unit_weight": _STRUCTURE_GAMMA,
    "plate.Kp": (Limit(1e-6, 1e4, low_open=False),
                 "the paper's studies span Kp = 0.001 to 10; beyond 1e4 a plate is rigid"),
    "wall.radius": _RADIUS,
    "wall.thickness": (Limit(1e-3, 5.0, low_open=False),
                       "from a steel shell's few millimetres to a thick concrete wall"),
    "wall.height": (Limit(0.3, 150.0, low_open=False), "tanks and silos up to about 100 m"),
    "wall.E": _STRUCTURE_E,
    "wall.unit_weight": _STRUCTURE_GAMMA,
    "wall.Kt": (Limit(1e-8, 1e4, low_open=False),
                "the paper's studies span Kt = 0.001 to 10; beyond 1e4 a wall is rigid"),
    "ringwall.E": (Limit(1e7, 1e11, low_open=False),
                   "from a crushed-stone ringwall (about 100 MPa) to concrete (30 GPa)"),
    "ringwall.fill_E": _SOIL_E,
    "ringwall.unit_weight": (Limit(None, 1e5), "a net unit weight below 100 kN/m^3"),
    "interface.cohesion": (Limit(None, 1e6), "an interface's adhesion is below 1 MPa"),
    "load.pressure": (Limit(-1e7, 1e7, low_open=False),
                      "a foundation's pressure is far below 10 MPa, beyond any soil's bearing "
                      "capacity"),
    "load.load_radius": _RADIUS,
    "load.liquid_unit_weight": (Limit(4e3, 2.5e4, low_open=False),
                                "liquids weigh from about 4.5 (LNG) to 18 (molasses, liquid "
                                "sulphur) kN/m^3; water 9.81"),
    "load.liquid_height": (Limit(None, 150.0), "tanks hold liquid up to about 100 m"),
    "load.gas_pressure": (Limit(-1.01325e5, 1e6, low_open=False),
                          "a vacuum below -101.325 kPa is impossible; tanks hold gas pressures "
                          "up to about 100 kPa (API 620)"),
}

#: a unit's usual multiples: (factor to the SI unit, name): a value given in the multiple
#: is the SI value divided by the factor
_MULTIPLES = {
    "Pa": ((1e3, "kPa"), (1e6, "MPa"), (1e9, "GPa")),
    "m": ((1e-3, "mm"), (1e-2, "cm")),
    "N/m^3": ((1e3, "kN/m^3"),),
    "1/Pa": ((1e-3, "1/kPa"), (1e-6, "1/MPa")),
    "m/s": ((1e-2, "cm/s"),),
}

#: a wall's thickness over its radius: thin-shell theory's error is of order t/R (beyond
#: WALL_THIN: a warning); beyond WALL_THICKEST no shell theory applies (a thick-walled
#: cylinder, a solid): a thickness given so is refused (one from Kt runs, with a warning)
WALL_THIN, WALL_THICKEST = 0.1, 0.3
#: a plate's thickness over its radius: beyond PLATE_THIN a thin (Kirchhoff) plate's
#: neglect of shear strains stretches (a warning); beyond PLATE_THICKEST it is a block
PLATE_THIN, PLATE_THICKEST = 0.2, 0.5
#: the widest domain, in foundation radii: the half-space's truncation error falls as 1/R
#: (0.0074 % at the default 1e4 a), so nothing is gained beyond; measured, the mesh stays
#: well shaped to 1e8 a (smallest quality 0.6)
DOMAIN_WIDEST = 1e8


def _range_text(limit: Limit, unit: str) -> str:
    u = f" {unit}" if unit and unit != "-" else ""
    if limit.low is None:
        return f"up to {limit.high:g}{u}"
    return f"{limit.low:g} to {limit.high:g}{u}"


def implausible(where: str, name: str, value: float, unit: str, accepted) -> str | None:
    """The problem of ``value`` of the key ``name`` ("section.key", or "layer.key") written
    at ``where`` if it lies outside its plausible range and ``where`` is not accepted; None
    otherwise. The message names the likely slip of units where one multiple of the unit
    puts the value inside the range."""
    spec = PLAUSIBLE.get(name)
    if spec is None or value == 0 or where in accepted:
        return None
    limit, why = spec
    if limit.holds(value):
        return None
    u = f" {unit}" if unit and unit != "-" else ""
    slip = ""
    for factor, multiple in _MULTIPLES.get(unit, ()):
        if limit.holds(value * factor):
            slip = f"; did you mean {value:g} {multiple} = {value * factor:g}{u}?"
            break
    return (f"{where} = {value:g}{u}: outside the plausible {_range_text(limit, unit)} ({why})"
            f"{slip} Give it in{u or ' these units'}; or, if you mean it, add \"{where}\" to the "
            f"scene's top-level accept = [...]")


_ACCEPTABLE = re.compile(r"(\w+)\.(?:layers\[(\d+)\]\.)?(\w+)")


def accept_problems(accept, keys: dict, layer_keys: dict) -> list[str]:
    """The problems of a scene's ``accept`` list: a list of keys as the messages name
    them ("soil.E", "soil.layers[2].E", "wall.thickness")."""
    how = ("accept: a list of the keys whose implausible values you mean, as the messages "
           "name them, e.g. accept = [\"soil.E\", \"soil.layers[2].E\"]")
    if not isinstance(accept, list) or not all(isinstance(k, str) for k in accept):
        return [how]
    out = []
    for k in accept:
        m = _ACCEPTABLE.fullmatch(k)
        section, layer, name = m.groups() if m else (None, None, None)
        table = layer_keys if layer is not None and section == "soil" else keys.get(section)
        if table is None or name not in table:
            out.append(f"accept: {k!r} is not a scene key; {how}")
    return out


def ratio_problem(where: str, t: float, radius: float, thin: float, thickest: float,
                  member: str, accepted) -> str | None:
    """A member's thickness ``t`` over its radius beyond ``thickest``: refused (no shell
    or plate theory covers it), unless accepted."""
    if where in accepted or not (t > 0 and radius > 0) or t / radius <= thickest:
        return None
    slip = f"did you mean {t:g} mm = {t * 1e-3:g} m? " if t >= 1.0 else ""
    return (f"{where} = {t:g} m on a radius of {radius:g} m: t/R = {t / radius:.3g}, beyond "
            f"{thickest:g}, where no {member} theory applies (thin theory holds to about "
            f"{thin:g}); {slip}If you mean it, add \"{where}\" to the scene's top-level "
            f"accept = [...]")


def geometry_warnings(scene) -> list[str]:
    """The warnings of a resolved scene's members: a wall or plate thicker than thin theory
    covers well (beyond WALL_THIN, PLATE_THIN of its radius), and one given by Kt or Kp
    beyond the thickest a shell or plate theory covers (it runs: the paper's studies
    reach Kp = 10), and the values the scene accepts outside their plausible range."""
    out = []
    members = (("wall", scene.wall, WALL_THIN, WALL_THICKEST, "thin-shell"),
               ("plate", scene.plate, PLATE_THIN, PLATE_THICKEST, "thin-plate"))
    for name, part, thin, thickest, theory in members:
        if part is None:
            continue
        t = max(t for *_, t in part.course_table) if name == "wall" else \
            max(part.thickness, part.annular_thickness or 0.0)
        ratio = t / part.radius
        if ratio > thin:
            out.append(f"{name}: t/R = {ratio:.3g} ({t:.4g} m on {part.radius:g} m) is beyond "
                       f"{thin:g}, where {theory} theory's error (of order t/R) grows"
                       + (f"; beyond {thickest:g} no {theory.split('-')[1]} theory applies: "
                          f"read its moments as those of the rigid limit"
                          if ratio > thickest else ""))
    out += [f"{note}: accepted (the scene's accept list)" for note in scene.accepted]
    return out
