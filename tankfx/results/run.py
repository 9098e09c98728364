"""results.json's entries of how a stage was run: what it cost (dofs, timings, ranks, the
linear solver), how its iterations converged (the soil's record, the warnings), and a
consolidation's history and an excavation's record, from the statuses the iterations
returned."""
from __future__ import annotations

from ..fem.memory import keep_freed_memory
from ..fem.threads import limit_blas_threads
from .consolidation import consolidation_record
from .contract import versions


def run_record(results: dict, scene, solver, dofs: dict, timings: dict, ranks: int,
               warnings: list[str], stage: int | None, statuses: dict, log) -> None:
    """Add to a stage's results what the run cost and how it converged: dofs, timings,
    ranks, versions, the soil's iteration, the linear solver, the warnings, and a
    consolidation's history."""
    results["dofs"] = dofs | {"total": solver.matrix_size}
    results["timings_s"] = dict(timings)
    results["mpi_ranks"] = ranks
    results["versions"] = versions()
    if stage is not None:
        results["stage"] = stage
    # (the soil's iteration, or a consolidation's that solves the skeleton by Newton)
    soil = statuses.get("soil") or statuses.get("consolidation")
    results["soil"] = dict(soil.record) if soil is not None and soil.record else {
        "model": "linear", "iterations": 0}
    results["soil"]["model"] = scene.soil.model
    results["linear_solves"] = solver.solves
    results["warnings"] = list(warnings)
    held = results["soil"].get("held_on_loading_curve")
    if held:
        results["warnings"].append(
            f"{held} soil cells at their largest strain so far changed between their "
            f"loading curve and their unloading line at every iteration and were held on "
            f"the curve (the paper's law) to converge")
        log.warning("warning: %s", results["warnings"][-1])
    results["linear_solver"] = {
        "method": scene.solver.method, "solves": solver.solves,
        "factorisation": solver.factorisation, "assembly": solver.assembly,
        "scaling": solver.scaling,
        "last_relative_residual": solver.relative_residual,
        "keeps_freed_memory": keep_freed_memory(),
        "numpy_blas_threads": limit_blas_threads()}
    if scene.solver.method == "iterative":
        results["linear_solver"]["krylov_iterations"] = solver.krylov_iterations
    if (consolidation := statuses.get("consolidation")) is not None:
        results["consolidation"] = consolidation_record(consolidation.data,
                                                        scene.consolidation)
        if "at_stages" in results["consolidation"]:
            # (a load path in time: each stage's state when its load is reached, numbered,
            # with its piezometers and, asked for, its factor of safety)
            results["stages"] = [{"stage": k, **s} for k, s in enumerate(
                results["consolidation"]["at_stages"], start=1)]
        if consolidation.data.fill is not None:
            # (a fill schedule's plan: tankfx.iterations.fill_schedule)
            results["fill"] = consolidation.data.fill


def excavation_record(status) -> dict:
    """results.json's ``excavation``: the pit's load steps (their record), the heave of its
    bottom at its centre (m), and the check of its equilibrium: the excavated ground's
    vertical reaction against the load its faces released (N), and their relative error."""
    d = status.data
    released, reaction = d["released_load"], d["reaction"]
    return {**status.record, "heave": d["heave"], "released_load": released,
            "reaction": reaction,
            "relative_error": abs(reaction + released) / max(abs(released), 1e-300)}
