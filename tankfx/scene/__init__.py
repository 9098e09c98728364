"""The scene: one validated description of a tank-foundation-soil problem, read from TOML into
frozen dataclasses (SI units: m, Pa, N/m^3). No DOLFINx here: a scene is checked before any
mesh is built."""
from ..laws.rigidity import Kp_from_thickness, plate_thickness_from_Kp
from .scene import Scene, load_scene
from .sections import (
                       Consolidation,
                       DomainSize,
                       Interface,
                       Layer,
                       Load,
                       MeshOptions,
                       Plate,
                       Ringwall,
                       SceneError,
                       Soil,
                       SolverOptions,
                       Wall,
                       vertical_load,
                       vertical_load_scale,
)

__all__ = ["Scene", "load_scene", "SceneError", "Soil", "Layer", "Plate", "Wall", "Ringwall",
           "Interface", "Load", "Consolidation", "DomainSize", "MeshOptions", "SolverOptions",
           "vertical_load", "vertical_load_scale", "Kp_from_thickness",
           "plate_thickness_from_Kp"]
