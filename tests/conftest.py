"""Shared helpers. The suite runs serially (`pytest`) and, for the tests marked `mpi`, on two
ranks (`mpiexec -n 2 python -m pytest -m mpi`), as `make test` does."""
import gc
import os

import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)

import pytest
from mpi4py import MPI

from tankfx import Scene

# a figure that fails to draw fails the test that draws it (and the demos and command
# lines the tests run as processes, which inherit it), instead of warning
os.environ["TANKFX_STRICT_FIGURES"] = "1"


def flexible_scene(nu=0.3, **sections):
    """The flexible uniform load of the foundation issue: p = 100 kPa on a = 1 m, E = 10 MPa."""
    data = {"title": "flexible load", "soil": {"E": 10e6, "nu": nu},
            "load": {"pressure": 100e3, "load_radius": 1.0}}
    for name, values in sections.items():
        if isinstance(values, dict):
            data.setdefault(name, {}).update(values)
        else:
            data[name] = values           # (a top-level key: accept)
    return Scene.from_dict(data)


#: A coarse mesh for the 1 m tanks of the solver tests.
COARSE = {"edge_size": 0.01, "near_size": 0.25, "growth": 0.3}
#: The paper's hyperbolic soil (its a and b in SI units) and a water-filled tank's load.
HYPERBOLIC_SOIL = {"model": "hyperbolic", "hyperbolic_a": 2.1e-7, "hyperbolic_b": 1e-5,
                   "nu": 0.3}
WATER_LOAD = {"pressure": 30e3, "liquid_unit_weight": 9810.0, "liquid_height": 2.5}


def small_tank(**sections) -> dict:
    """A 1 m tank as a scene dict: a Kp = 1 plate 0.3 m below ground, a 3 m wall (Kt = 0.1),
    on a 10 MPa soil, bonded, under 50 kPa, on the COARSE mesh; ``sections`` replace whole
    sections (``soil``, ``interface``, ``load``, ``mesh``, ``solver``)."""
    return {"soil": {"E": 10e6, "nu": 0.3},
            "plate": {"radius": 1.0, "Kp": 1.0, "E": 30e9, "nu": 0.2, "embedment": 0.3},
            "wall": {"radius": 1.0, "Kt": 0.1, "height": 3.0, "E": 30e9, "nu": 0.2},
            "interface": {"condition": "bonded"}, "load": {"pressure": 50e3},
            "mesh": COARSE} | sections


def incompressible_hyperbolic_punch(a: float = 1e-7) -> dict:
    """A rigid 1 m plate (Kp = 1e3), smooth, on a hyperbolic soil at nu = 0.5 (the mixed
    form) of initial modulus 1/a, under 1 kPa (a thousandth of the ultimate deviator 1/b):
    the saddle-point system whose unscaled factorisation fails (tankfx.fem.solvers)."""
    return {"soil": {"model": "hyperbolic", "hyperbolic_a": a, "hyperbolic_b": 1e-6,
                     "nu": 0.5},
            "plate": {"radius": 1.0, "Kp": 1e3, "E": 30e9, "nu": 0.2},
            "interface": {"condition": "smooth"}, "load": {"pressure": 1e3}, "mesh": COARSE}


def assemble_whole_system(monkeypatch) -> None:
    """Make the direct solver re-assemble the whole matrix at every solve, instead of the
    varying part of a split one: the reference the split assembly must reproduce."""
    from dolfinx.fem import petsc as fem_petsc

    from tankfx.fem.solvers import DirectSolver

    def whole(self):
        p = self.problem
        p.A.zeroEntries()
        fem_petsc.assemble_matrix(p.A, p.a, bcs=p.bcs)
        p.A.assemble()

    monkeypatch.setattr(DirectSolver, "_assemble_split", whole)


@pytest.fixture(scope="module")
def solved():
    """``solved(scene)``: ``analyse(scene).results``, solved once per scene for the test
    module, so that tests reading the same scene share one solve (a test that changes how a
    scene is solved, with a monkeypatch, calls ``analyse`` itself). Read, never change, what
    it returns."""
    from tankfx import analyse

    cache: dict[str, dict] = {}

    def results(scene) -> dict:
        key = scene.to_toml()
        if key not in cache:
            cache[key] = analyse(scene).results
        return cache[key]
    return results


@pytest.fixture(autouse=True)
def _collect_and_barrier():
    """PETSc objects are freed collectively: on several ranks, collect garbage on all of
    them together. (On one rank nothing waits for another: a collection after every test
    cost 104 s of the serial suite's 1,935.)"""
    yield
    if MPI.COMM_WORLD.size > 1:
        gc.collect()
        MPI.COMM_WORLD.barrier()
