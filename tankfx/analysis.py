"""From a validated scene to results: mesh, forms, solve, post-processing.

The result keys (``results.json``) are a public contract; see docs/guide/outputs.md.
Sign conventions: settlements ``w`` positive downward; ``u_r`` positive outward; the axis
``z`` is the depth below the ground surface (positive downward); ``sigma_zz`` is positive in
compression (the paper's and geotechnical convention).
"""
from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, replace

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
from dolfinx import fem
from mpi4py import MPI

from .collapse_study import CollapseStudy
from .fem.solvers import SolveError, make_solver
from .iterations.stage import StageIterations
from .iterations.status import IterationStatus, SoilFailure
from .mesh import (
    SURFACE_GRADING,
    Domain,
    build_domain,
    estimate,
    heartbeat,
    resource_problem,
)
from .model.build import build_model
from .model.overturning import RockingModel
from .model.protocol import Model
from .results.contract import results_of, settlement_kept, stage_summary
from .results.run import excavation_record, run_record
from .results.overturning import add_overturning
from .results.validity import validity
from .scene.plausible import geometry_warnings
from .scene.scene import Scene
from .scene.sections import Load, SceneError

log = logging.getLogger("tankfx")


@dataclass
class Solution:
    """A solved scene: the finite element fields and the results.

    Attributes
    ----------
    scene : Scene
        The scene solved.
    domain : Domain
        The distributed mesh with its named tags.
    u : dolfinx.fem.Function
        The soil's displacement (u_r, u_z), m.
    sigma_zz : dolfinx.fem.Function
        The vertical stress, projected onto the displacement's space, Pa (compression
        positive).
    results : dict
        Everything written to results.json (docs/guide/outputs.md).
    model : object
        The assembled model (soil, interface and structure blocks), or None.
    harmonic : object
        The overturning's first harmonic, where the load has one, or None.
    """

    scene: Scene
    domain: Domain
    u: fem.Function
    sigma_zz: fem.Function
    results: dict
    model: object = None
    #: the overturning's first harmonic (tankfx.model.overturning.RockingModel) where the load has
    # one
    harmonic: object = None
    #: how the stage's iterations ended, by name ("soil", "interface", "consolidation",
    #: "linear_solve"; tankfx.iterations.stage)
    statuses: dict = None
    #: with ``analysis.collapse``: the collapse's mechanism, ``increment`` (the soil's last
    #: displacement increment) and ``plastic`` (each cell's share of yielding points, DG0),
    #: at the collapse (the other fields are the scene's load's)
    collapse: dict = None
    #: with ``analysis.collapse = "bounds"``: the upper bound's mechanism, its triangles'
    #: ``points`` and ``cells`` and the ``velocity`` at their vertices
    bounds: dict = None


#: mesh_grading_warning: warned above lambda x edge size = GRADING_WARNING, where the
#: settlement's shortfall GRADING_ERROR (lambda h_edge)^2 passes 0.1 %
GRADING_WARNING, GRADING_ERROR = 2.0, 2.2e-4


def mesh_grading_warning(scene: Scene) -> str | None:
    """A soil whose modulus doubles within a depth 1/lambda much shorter than the elements
    the mesh can grade to there (they stop at the foundation's edge size) settles too
    little: say so, with the expected size of it and the fix. Measured on the flexible load
    at nu = 0.3 against the Riccati reference, w0 falls short by about 2.2e-4 (lambda
    h_edge)^2: 3e-5 at lambda h_edge = 0.5, 0.35 % at 4, 2 % at 10."""
    lam, h = scene.soil.E_gradient, scene.mesh.edge_size
    if lam * h <= GRADING_WARNING:
        return None
    return (f"soil.E_gradient = {lam:g} /m doubles the modulus within {1e3 / lam:.3g} mm of "
            f"the surface, but the mesh's elements there stop at mesh.edge_size = {h:.3g} m: "
            f"a compressible soil's settlement comes out about "
            f"{GRADING_ERROR * (lam * h) ** 2:.1%} too small; lower mesh.edge_size towards "
            f"{SURFACE_GRADING / lam:.3g} m (the grading's own size) for more accuracy")


def analyse(scene: Scene, comm: MPI.Comm = MPI.COMM_WORLD, nested: bool = False,
            allow_large: bool = False) -> Solution:
    """Mesh, solve and post-process a scene.

    Parameters
    ----------
    scene : Scene
        The validated scene (:func:`load_scene`, :meth:`Scene.from_dict`).
    comm : mpi4py.MPI.Comm, optional
        The ranks that share the analysis (default ``MPI.COMM_WORLD``). The mesh is made on
        rank 0 and distributed; every rank returns the same results.
    nested : bool, optional
        With a hyperbolic soil and a Mohr-Coulomb interface: converge the interface inside
        every soil iteration. The default updates both once per iteration, which took fewer
        solves on the embedded demo tank (21 against 26, docs/theory/method.md).
    allow_large : bool, optional
        Run a scene whose estimated memory exceeds what the machine has free (refused
        otherwise, before meshing).

    Returns
    -------
    Solution
        The solved fields and ``results``, the dictionary written to results.json. With a
        load path (``[[stages]]``), those of its last stage, with every stage's key numbers
        under ``results["stages"]``.

    Raises
    ------
    SceneError
        The scene is too large for the machine (before any meshing).
    SoilFailure
        The soil cannot carry the load: ``results`` says where and what was carried.
    SolveError
        An iteration or a linear solve failed; the message says what, in physical terms,
        and the exception carries the history.
    """
    return analyse_path(scene, list(scene.stages) or [scene.load], comm, nested,
                        allow_large)[-1]


def analyse_path(scene: Scene, loads: list, comm: MPI.Comm = MPI.COMM_WORLD,
                 nested: bool = False, allow_large: bool = False) -> list[Solution]:
    """Solve a scene under a sequence of total loads, on one mesh.

    The interface's element states (and, with an unloading modulus, the soil's memory) are
    carried from each stage to the next: an element separated at one stage and in contact
    at the next is reported ``rebonded``. Each stage is the response to its total load, as
    in the paper; slip is not accumulated along the path.

    Parameters
    ----------
    scene : Scene
        The scene whose geometry, soil and structure every stage shares.
    loads : list of Load or dict
        The stages' total loads: ``Load`` objects or ``[load]`` tables as dicts.
    comm, nested, allow_large
        As for :func:`analyse`.

    Returns
    -------
    list of Solution
        One solution per stage, in order.
    """
    stages = _load_stages(scene, loads)
    _check_resources(scene, comm, allow_large)
    t_start = time.perf_counter()
    timings: dict[str, float] = {}
    domain, model, solver, iterations = _set_up(scene, stages[0], comm, timings, nested)
    warnings = _warnings(scene, model)
    for w in warnings:
        log.warning("warning: %s", w)
    dofs = model.dofs()
    log.info("dofs: %s (soil P%d); assembling and solving with MUMPS",
             ", ".join(f"{k} {v}" for k, v in dofs.items()), scene.mesh.degree)
    excavation = _excavate(model, iterations, solver)
    study = CollapseStudy.of(scene, model, iterations, solver, comm, log)
    if study is not None and scene.consolidation is not None:
        # (in time: the factor of safety at every milestone of the path)
        iterations.at_milestones(study.at_milestone, study)
    solutions = []
    rocking = None          # the first harmonic, built by the first stage that overturns
    for k, load in enumerate(stages):
        if k > 0:
            log.info("load stage %d of %d", k + 1, len(stages))
            model.set_loads(load)
        t = time.perf_counter()
        try:
            with heartbeat("solving" + (f" load stage {k + 1}" if len(stages) > 1 else "")):
                stage_scene, statuses = _solve_stage(scene, load, model, iterations)
        except SolveError as e:
            e.dofs = solver.matrix_size        # (what the failed run cost)
            if study is not None and isinstance(e, SoilFailure):
                study.failed(e, load)
            elif len(stages) > 1:
                _stage_failed(e, k, stages, solutions, scene)
            raise
        timings["assemble_solve"] = time.perf_counter() - t
        log.info("solved in %.2f s", timings["assemble_solve"])

        t = time.perf_counter()
        sigma_zz = model.soil.vertical_stress()
        results = results_of(stage_scene, domain, model, sigma_zz, statuses)
        timings["post"] = time.perf_counter() - t
        timings["total"] = time.perf_counter() - t_start
        run_record(results, scene, solver, dofs, timings, comm.size, warnings,
                   k + 1 if len(stages) > 1 else None, statuses, log)
        if excavation is not None:
            results["excavation"] = excavation
        # (a consolidation's: the load at its last reported time, on the state then)
        load = stage_scene.load
        if load.overturning:
            rocking = _overturning(model, rocking, load, results, log, sigma_zz)
        results["validity"] = validity(results, scene.foundation_radius)
        for note in results["validity"]["notes"]:
            log.warning("not valid: %s", note)
        solutions.append(Solution(scene=stage_scene, domain=domain, u=model.soil.u,
                                  sigma_zz=sigma_zz, results=results, model=model,
                                  harmonic=rocking if load.overturning else None,
                                  statuses=statuses))
    if study is not None:
        found = study.findings() if scene.consolidation is not None else \
            study.run(stages[0])
    if study is not None and found is not None:
        last = solutions[-1]
        last.results["collapse"] = found.collapse
        if found.bounds is not None:
            last.results["bounds"] = found.bounds
        solutions[-1] = replace(last, collapse=found.fields, bounds=found.bounds_mechanism)
    if len(solutions) > 1:
        summaries = [stage_summary(s.results) for s in solutions]
        if scene.soil.law.keeps_permanent_strain:
            settlement_kept(summaries)
        solutions[-1].results["stages"] = summaries
    return solutions


def _check_resources(scene: Scene, comm: MPI.Comm, allow_large: bool) -> None:
    """Refuse, before any meshing, a scene larger than the machine has memory for."""
    est = estimate(scene, comm.size)
    log.info("estimate: %s", est.text())
    if not allow_large:
        # (rank 0's answer for all: the memory free may differ between the ranks' nodes)
        problem = comm.bcast(resource_problem(scene, est) if comm.rank == 0 else None)
        if problem:
            raise SceneError([problem])


def _excavate(model: Model, iterations: StageIterations, solver) -> dict | None:
    """An elastoplastic soil's embedded foundation: its pit dug first (its results.json
    record), else None."""
    if model.soil.pit is None:
        return None
    try:
        with heartbeat("excavating the pit"):
            status = iterations.excavate(log)
    except SolveError as e:
        e.dofs = solver.matrix_size
        raise
    record = excavation_record(status)
    log.info("the pit is dug: its bottom heaved %.4g m, %d points yield", record["heave"],
             record["plastic_points"])
    return record


def _stage_failed(e: SolveError, k: int, stages: list, solutions: list, scene: Scene) -> None:
    """A load path keeps what converged (``e.kept["converged_stages"]``), and its message
    names the stage that failed and the largest load carried (the last converged stage's)."""
    P = solutions[-1].results["equilibrium"]["applied_load"] if solutions else 0.0
    a = scene.foundation_radius
    carried = (f"; the largest load carried is stage {k}'s, {P / 1e6:.4g} MN (a mean bearing "
               f"pressure of {P / (math.pi * a**2) / 1e3:.4g} kPa)" if solutions else "")
    e.args = (f"load stage {k + 1} of {len(stages)} failed{carried}: {e}",)
    e.kept["converged_stages"] = [s.results for s in solutions]


def _load_stages(scene: Scene, loads: list) -> list[Load]:
    """The loads of a path as ``Load`` objects, checked against the scene: a consolidation
    follows its own [[stages]] in time, and a flexible load keeps its meshed circle."""
    stages = [ld if isinstance(ld, Load) else scene.with_changes(load=ld).load for ld in loads]
    if scene.consolidation is not None:
        # one analysis in time: its load path (scene.stages at scene.stage_times) is
        # followed by the time stepping (tankfx.iterations.time_stepping.load_path)
        if stages not in ([scene.load], list(scene.stages)):
            raise ValueError("a consolidation's load path is its scene's [[stages]], each "
                             "with its time: give them in the scene, not as loads here")
        stages = [scene.load]
    if scene.plate is None:
        for ld in stages:
            if ld.load_radius != scene.load.load_radius:
                raise ValueError(f"load.load_radius: every load stage keeps the meshed loaded "
                                 f"circle ({scene.load.load_radius:g} m), got "
                                 f"{ld.load_radius:g} m; analyse the other radius separately")
    return stages


def _set_up(scene: Scene, first: Load, comm: MPI.Comm, timings: dict, nested: bool) -> tuple:
    """The mesh, the model under the first load, its solver and the chain of iterations
    that solves a stage (:mod:`tankfx.iterations.stage`)."""
    log.info("scene '%s': meshing on rank 0, distributing over %d rank(s)", scene.title,
             comm.size)
    t = time.perf_counter()
    domain = build_domain(scene, comm)
    timings["mesh"] = time.perf_counter() - t
    ncells = domain.mesh.topology.index_map(2).size_global
    log.info("mesh: %d cells in %.2f s", ncells, timings["mesh"])
    for k, st in enumerate(scene.soil.strata[1:], start=1):
        log.info("  layer from %g m down: E = %.4g Pa, nu = %g%s", st.depth, st.E, st.nu,
                 " (mixed form)" if k in scene.soil.mixed_strata else "")

    t = time.perf_counter()
    model = build_model(replace(scene, load=first), domain)
    # (a soil solved by one linear solve a stage keeps its stiffness)
    stiffness_fixed = scene.soil.law.iteration is None
    mohr_coulomb = scene.interface.has_states
    # one factorisation: a linear soil under a bonded or smooth interface (its load stages
    # share the matrix)
    one_shot = stiffness_fixed and not mohr_coulomb and scene.consolidation is None
    solver = make_solver(scene.solver, model.a, model.L, model.bcs, model.unknowns,
                         entity_maps=model.entity_maps, name="tank",
                         symmetric=not mohr_coulomb and scene.soil.law.symmetric_tangent(
                             scene.soil), one_shot=one_shot,
                         # on a linear soil only a Mohr-Coulomb interface's states and a
                         # consolidation's time step change the matrix: the rest is kept
                         split=model.a_split if stiffness_fixed else None,
                         # (Newton's systems solved as corrections: tankfx.fem.solvers)
                         correction=model.soil.plastic is not None)
    timings["forms"] = time.perf_counter() - t
    return domain, model, solver, StageIterations.of(scene, model, solver, one_shot, nested)


def _warnings(scene: Scene, model: Model) -> list[str]:
    """What the set-up found: the model's (the interface's penalty), the mesh's grading
    against a soil stiffening fast with depth, and a nonlinear elastic soil unloaded."""
    warnings = list(model.warnings) + geometry_warnings(scene) + \
        scene.soil.law.ground_warnings(scene.soil, scene.domain.depth)
    grading = mesh_grading_warning(scene)
    if grading:
        warnings.append(grading)
    if scene.consolidation is not None and scene.soil.law.at_points:
        warnings.append(
            "the elastoplastic skeleton's consolidation is new: below yield it gives the "
            "linear skeleton's numbers (to 1e-12) and Terzaghi's; where the skeleton yields "
            "its factor of safety and the order of its collapse loads by the rate of "
            "loading are checked, but its settlements and pore pressures in time are not "
            "yet verified against a published solution; read them as provisional "
            "(docs/limitations.md)")
    unloading = scene.unloading_stages() if scene.soil.law.unloads_on_curve else []
    if unloading and scene.soil.unloading_modulus_ratio is None:
        warnings.append(
            f"stages {', '.join(map(str, unloading))}: less vertical load than an earlier "
            f"stage; Kondner's secant law (the paper's) is nonlinear elastic, so the soil "
            f"unloads along its loading curve and keeps no permanent settlement: read "
            f"these stages as the same load applied afresh, not as unloading (give [soil] "
            f"unloading_modulus_ratio for a soil that remembers)")
    return warnings


def _solve_stage(scene: Scene, load: Load, model: Model,
                 iterations: StageIterations) -> tuple[Scene, dict[str, IterationStatus]]:
    """Solve one stage of the path by the scene's chain of iterations. Returns the stage's
    scene (a consolidation's: its load at the last reported time, which on a load path may
    lie between stages) and the iterations' statuses by name."""
    if model.soil.remembers:
        # a remembering soil's path may unload to nothing: its equilibrium errors are
        # relative to the path's largest load so far
        model.path_load_scale = model.load_scale
    model.begin_stage()
    iterations.begin_stage()
    statuses = iterations.run(log)
    return replace(scene, load=model.scene.load), statuses


def _overturning(model, rocking, load, results: dict, log, sigma_zz):
    """Solve the first harmonic of an overturning load about the stage's converged state
    and add its results (``results["overturning"]``, the planar tilt, warnings); returns the
    harmonic model for the next stage."""

    t = time.perf_counter()
    if rocking is None:
        rocking = RockingModel(model)
    amplitudes = rocking.solve(load.overturning_moment, load.base_shear, log=log.info)
    for w in add_overturning(results, amplitudes, model.scene, sigma_zz,
                             model.domain.cells("soil"), rocking.relative_residual, t):
        log.warning("warning: %s", w)
    return rocking
