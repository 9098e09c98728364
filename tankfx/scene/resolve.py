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
from ..laws.soil_laws import SOIL_LAWS
from .checks import read_courses, read_layer
from .reader import Reader
from .sections import (
    DEFAULT_DOMAIN_FACTOR,
    DEFAULT_EDGE_SIZE,
    DEFAULT_NEAR_SIZE,
    DEFAULT_TOLERANCE,
    FLEXIBLE_COARSENING,
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
    """The soil: each stratum's E and constants and the ground's values by its law (E, 1/a
    or K p_a), an iterated soil's tolerance and iterations, the layers."""
    law = SOIL_LAWS[soil.get("model", Soil.model)]
    ground = law.resolve_ground(soil)
    # (the keys of its iteration, where it has them)
    return law.finish(given(Soil, soil, **law.resolve_stratum(soil, ground), **ground,
                 tolerance=(soil.get("tolerance", DEFAULT_TOLERANCE)
                            if "tolerance" in law.iteration_keys else None),
                 max_iterations=(soil.get("max_iterations", law.max_iterations)
                                 if "max_iterations" in law.iteration_keys else None),
                 layers=tuple(read_layer(x, law, ground) for x in layers)))


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


def domain_of(domain: dict, a: float, factor: float | None = None) -> DomainSize:
    """The domain, ``factor`` (by default DEFAULT_DOMAIN_FACTOR: the soil's law may say
    less) foundation radii wide and deep by default."""
    size = (factor or DEFAULT_DOMAIN_FACTOR) * a
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
