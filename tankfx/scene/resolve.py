"""The section dataclasses of a checked scene dict: each key given is taken as it is, each
key left out takes its field's default (:mod:`tankfx.scene.sections`: the one place a
default is written), and the defaults that follow from other keys are resolved here (a
thickness from Kp or Kt, a nonlinear soil's E, the domain and mesh sizes from the
foundation's radius)."""
from __future__ import annotations

import math
from dataclasses import fields
from typing import Any

from ..laws.rigidity import plate_thickness_from_Kp
from .checks import duncan_chang_values, read_courses, read_layer
from .reader import Reader
from .sections import (
    ATMOSPHERIC_PRESSURE,
    DEFAULT_DOMAIN_FACTOR,
    DEFAULT_EDGE_SIZE,
    DEFAULT_NEAR_SIZE,
    DEFAULT_TOLERANCE,
    FLEXIBLE_COARSENING,
    MAX_ITERATIONS,
    WATER_UNIT_WEIGHT,
    DomainSize,
    Interface,
    Load,
    MeshOptions,
    Plate,
    Soil,
    SolverOptions,
    Wall,
)

__all__ = ["given", "soil_of", "plate_of", "wall_of", "interface_of", "load_of",
           "domain_of", "mesh_of", "solver_of"]


def given(cls, table: dict[str, Any], **resolved):
    """A section's dataclass of the keys ``table`` gives (those that are its fields), with
    the ``resolved`` values; every other field takes its default."""
    names = {f.name for f in fields(cls)}
    return cls(**{k: v for k, v in table.items() if k in names} | resolved)


def soil_of(soil: dict, layers: list) -> Soil:
    """The soil: its surface modulus (E, 1/a or K p_a), a nonlinear soil's tolerance and
    iterations, Duncan & Chang's constants resolved, the layers."""
    model = soil.get("model", Soil.model)
    hyperbolic, dc = model == "hyperbolic", model == "duncan_chang"
    dc_values = {}
    if dc:
        p_a = soil.get("atmospheric_pressure", ATMOSPHERIC_PRESSURE)
        dc_values = duncan_chang_values(soil, p_a) | {
            "atmospheric_pressure": p_a, "water_table": soil.get("water_table"),
            "water_unit_weight": soil.get("water_unit_weight", WATER_UNIT_WEIGHT)
            if "water_table" in soil else None}
    E_surface = (1.0 / soil["hyperbolic_a"] if hyperbolic else
                 dc_values["modulus_number"] * dc_values["atmospheric_pressure"] if dc
                 else soil["E"])
    nonlinear = hyperbolic or dc
    return given(Soil, soil, E=E_surface, **dc_values,
                 tolerance=soil.get("tolerance", DEFAULT_TOLERANCE) if nonlinear else None,
                 max_iterations=(soil.get("max_iterations", MAX_ITERATIONS[model])
                                 if nonlinear else None),
                 layers=tuple(read_layer(x, hyperbolic, dc, dc_values) for x in layers))


def plate_of(plate: dict | None, soil: Soil) -> Plate | None:
    """The plate, its thickness from Kp (Eq. 21) where Kp is given."""
    if plate is None:
        return None
    t = plate.get("thickness") or plate_thickness_from_Kp(
        plate["Kp"], plate["radius"], plate["E"], soil.E, soil.nu)
    return given(Plate, plate, thickness=t)


def wall_of(wall: dict | None, soil: Soil) -> Wall | None:
    """The wall, its thickness the bottom course's or from Kt (Eq. 22)."""
    if wall is None:
        return None
    courses = tuple(read_courses(Reader({}), wall) or ())
    t = courses[0][1] if courses else wall.get("thickness") or plate_thickness_from_Kp(
        wall["Kt"], wall["radius"], wall["E"], soil.E, soil.nu)
    return given(Wall, wall, thickness=t, courses=courses)


def interface_of(interface: dict, choices: dict[str, str]) -> Interface:
    """The interface, tan phi from a friction angle where one is given."""
    tan_phi = interface.get("tan_phi")
    if "friction_angle" in interface:
        tan_phi = math.tan(math.radians(interface["friction_angle"]))
    return given(Interface, interface, tan_phi=tan_phi, **choices)


def load_of(load: dict, radius: float) -> Load:
    """The load, on the plate's radius (or the flexible load's circle)."""
    return given(Load, load, load_radius=radius)


def domain_of(domain: dict, a: float) -> DomainSize:
    """The domain, DEFAULT_DOMAIN_FACTOR foundation radii wide and deep by default."""
    size = DEFAULT_DOMAIN_FACTOR * a
    return given(DomainSize, domain, radius=domain.get("radius", size),
                 depth=domain.get("depth", size))


def mesh_of(mesh: dict, degree: int, a: float, embedment: float, flexible: bool) -> MeshOptions:
    """The mesh sizes, in foundation radii by default (coarser for a flexible load), at
    least two elements down the side of an embedded foundation's pit."""
    coarsen = FLEXIBLE_COARSENING if flexible else 1.0
    edge = mesh.get("edge_size", coarsen * DEFAULT_EDGE_SIZE * a)
    if embedment > 0 and "edge_size" not in mesh:
        edge = min(edge, 0.5 * embedment)  # the side of the pit needs at least two elements
    return given(MeshOptions, mesh, degree=degree, edge_size=edge,
                 near_size=mesh.get("near_size", coarsen * DEFAULT_NEAR_SIZE * a))


def solver_of(solver: dict) -> SolverOptions:
    return given(SolverOptions, solver)
