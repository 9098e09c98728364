"""Shared helpers. The suite runs serially (`pytest`) and, for the tests marked `mpi`, on two
ranks (`mpiexec -n 2 python -m pytest -m mpi`), as `make test` does."""
import gc

import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)

import pytest
from mpi4py import MPI

from tankfx import Scene


def flexible_scene(nu=0.3, **sections):
    """The flexible uniform load of the foundation issue: p = 100 kPa on a = 1 m, E = 10 MPa."""
    data = {"title": "flexible load", "soil": {"E": 10e6, "nu": nu},
            "load": {"pressure": 100e3, "load_radius": 1.0}}
    for name, values in sections.items():
        data.setdefault(name, {}).update(values)
    return Scene.from_dict(data)


@pytest.fixture(autouse=True)
def _collect_and_barrier():
    """PETSc objects are freed collectively: collect garbage on all ranks together."""
    yield
    gc.collect()
    MPI.COMM_WORLD.barrier()
