"""The rigid circular footing on weightless Tresca soil, followed through its collapse by
settlement control: the verification rig of the elastoplastic soil's bearing capacity
(exact N_c = q_ult / s_u: 5.69 smooth, Shield 1955; 6.05 rough, Eason & Shield 1960)."""
from __future__ import annotations

import logging
import time

from mpi4py import MPI

from ..fem.solvers import make_solver
from ..iterations.stage import StageIterations
from ..mesh import build_domain
from ..model.build import build_model
from ..scene.scene import Scene

#: the exact N_c of a rigid circular footing on weightless Tresca soil, by interface
EXACT_N_C = {"smooth": 5.69, "bonded": 6.05}
#: Tresca's s_u of the rig, Pa
S_U = 10e3


def footing_scene(condition: str, degree: int = 2, edge: float = 0.005,
                  near: float = 0.2) -> dict:
    """A rigid 1 m footing (Kp = 1000) on weightless Tresca soil (E = 10 MPa, nu = 0.3,
    s_u = 10 kPa) in a 5 m x 5 m domain, its reference load 1 s_u: the scene as a dict."""
    return {"title": f"rigid footing, {condition}",
            "soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": S_U},
            "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2},
            "interface": {"condition": condition}, "load": {"pressure": S_U},
            "mesh": {"edge_size": edge, "near_size": near, "growth": 0.3, "degree": degree},
            "domain": {"radius": 5.0, "depth": 5.0}}


def collapse_curve(data: dict, settlement: float = 0.1, steps: int = 10,
                   comm=MPI.COMM_WORLD, log=None) -> dict:
    """The load-settlement curve of a scene's first stage under settlement control to
    ``settlement`` (m): ``factor`` (the load's multiple per step), ``w0``, and the run's
    ``dofs``, ``newton`` iterations and ``time_s``."""
    log = log or logging.getLogger("tankfx")
    t = time.perf_counter()
    scene = Scene.from_dict(data)
    model = build_model(scene, build_domain(scene, comm))
    solver = make_solver(scene.solver, model.a, model.L, model.bcs, model.unknowns,
                         entity_maps=model.entity_maps, name="collapse",
                         symmetric=scene.soil.law.symmetric_tangent(scene.soil),
                         correction=True)
    chain = StageIterations.of(scene, model, solver)
    model.begin_stage()
    chain.begin_stage()
    status = chain.run_to_settlement(solver, log, settlement, steps)
    return {"factor": [h["load_share"] for h in status.history],
            "w0": [h["w0"] for h in status.history], "dofs": solver.matrix_size,
            "newton": status.iterations, "time_s": time.perf_counter() - t}
