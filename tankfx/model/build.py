"""The model a scene needs: a flexible load without a plate, the tank with one."""
from __future__ import annotations

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)

from ..mesh import Domain
from ..scene.scene import Scene
from .flexible import FlexibleLoad
from .tank import TankModel


def build_model(scene: Scene, domain: Domain):
    """The model a scene needs: only the parts it uses are built."""
    if scene.plate is None:
        return FlexibleLoad(scene, domain)

    return TankModel(scene, domain)
