"""What a scene asks of the bounds: its soil per triangle, its foundation's load, and the
run (``[analysis] collapse = "bounds"``)."""
from __future__ import annotations

import math

import numpy as np

from ..scene.sections import vertical_load
from .lower import Ground, Loading
from .triangles import Triangles


def ground_of(soil, tri: Triangles) -> Ground:
    """The soil of each triangle: its stratum's (read at its centroid, a triangle lying in
    one stratum) cohesion as a line in z, friction angle and unit weight. Depth is -z."""
    depth = -tri.points[tri.cells, 1].mean(axis=1)
    st = soil.at_depth(depth)
    gradient = st["cohesion_gradient"]
    # c = cohesion + gradient (depth - top) = (cohesion - gradient top) - gradient z
    return Ground(c_top=st["cohesion"] - gradient * st["top"], dc_dz=-gradient,
                  phi=np.radians(st["friction_angle"]), gamma=st["unit_weight"])


def loading_of(scene, rigid: bool) -> Loading:
    """The foundation's held (the self-weight) and variable (the rest) vertical loads."""
    full = scene.load
    held = full.held()
    H = vertical_load(held, scene.plate, scene.wall, scene.ringwall)
    V = vertical_load(full, scene.plate, scene.wall, scene.ringwall) - H
    return Loading(variable=V, held=H, rigid=rigid,
                   rough=scene.interface.condition != "smooth",
                   smooth_side=scene.domain.side == "roller",
                   smooth_base=scene.domain.base == "smooth")


def strength_scale(soil, a: float) -> float:
    """A stress of order one for the programs: the cohesion at the surface, else gamma a."""
    c = float(soil.at_depth(np.array([0.0]))["cohesion"][0])
    g = float(soil.at_depth(np.array([0.0]))["unit_weight"][0])
    return max(c, g * a, 1.0)


def area(a: float) -> float:
    return math.pi * a ** 2
