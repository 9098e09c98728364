"""How a stage is solved: the iterations the scene needs, outermost first, each run with the
next one inside it.

Every iteration has one signature, ``run(inner, log) -> IterationStatus``: it calls
``inner()`` (the iteration inside it; None for the innermost, the linear solve) as often as
it needs and returns its status (:class:`tankfx.iterations.status.IterationStatus`), or
raises a ``SolveError`` with a code. Besides it has ``name`` (its key among a stage's
statuses), ``begin_stage()`` (the stage's per-stage state reset; what it carries over the
analysis, kept), ``last`` (the status of its last run), ``describe(scene)`` (its words for
``tankfx check``) and ``build(model, solver, how)``.

A stage's chain is, outermost first: the soil law's iteration (the secant loop of
Kondner's and Duncan & Chang's soils) or the consolidation's time stepping; the Mohr-Coulomb
interface's active set where the interface has one; and the linear solve. The chain is
read off the scene by :func:`stage_plan`, which knows no soil by name: the law names its
iteration (:mod:`tankfx.iterations.by_law`).
"""
from __future__ import annotations

from dataclasses import dataclass

from .active_set import ActiveSet
from .by_law import soil_iteration
from .continuation import run_to_settlement
from .excavation import excavate
from .fill_schedule import FillSchedule
from .plastic_consolidation import PlasticConsolidation
from .status import CONVERGED, AtDebug, IterationStatus
from .time_stepping import TimeStepping


class LinearSolve:
    """One linear solve with the model's current coefficients: the innermost iteration.
    With ``keep_matrix`` the solver keeps its factorisation for the next stage (a linear
    soil under a bonded or smooth interface: only the load changes)."""

    name = "linear_solve"
    quiet_inner = False

    def __init__(self, solver, keep_matrix: bool = False):
        self.solver, self.keep_matrix = solver, keep_matrix
        self.last: IterationStatus | None = None

    @classmethod
    def build(cls, model, solver, how) -> "LinearSolve":
        return cls(solver, keep_matrix=how.one_shot)

    @staticmethod
    def describe(scene) -> str:
        return "one linear solve"

    def begin_stage(self) -> None:
        self.last = None

    def run(self, inner, log) -> IterationStatus:
        self.solver.solve()
        if self.keep_matrix:
            self.solver.keep_matrix()
        self.last = IterationStatus(True, 1, [], "one linear solve", CONVERGED, {})
        return self.last


@dataclass(frozen=True)
class Composition:
    """How the iterations of a chain are built: ``one_shot``, the linear solve keeps its
    matrix between stages; ``one_update``, an active set inside a soil iteration makes one
    state update per soil iteration (converging both at once)."""

    one_shot: bool = False
    one_update: bool = False


def stage_plan(scene) -> list[type]:
    """The classes of the iterations that solve a stage of ``scene``, outermost first (no
    mesh needed: ``tankfx check`` describes them)."""
    plan = []
    if scene.fill is not None:
        # (the safe fill: the elastoplastic skeleton's consolidation along a schedule it
        # searches)
        plan.append(FillSchedule)
    elif scene.consolidation is not None and scene.soil.law.at_points:
        # (the elastoplastic skeleton's consolidation: Newton in every time step)
        plan.append(PlasticConsolidation)
    elif (soil := soil_iteration(scene.soil.law)) is not None:
        plan.append(soil)
    elif scene.consolidation is not None:
        plan.append(TimeStepping)
    if scene.plate is not None and scene.interface.has_states:
        plan.append(ActiveSet)
    plan.append(LinearSolve)
    return plan


class StageIterations:
    """The chain of iterations of a stage (built once for an analysis, begun at every
    stage): :meth:`run` solves the stage and returns every iteration's status by its name.
    """

    def __init__(self, iterations: list):
        self.iterations = iterations

    @classmethod
    def of(cls, scene, model, solver, one_shot: bool = False,
           nested: bool = False) -> "StageIterations":
        """The chain of :func:`stage_plan` for a built model and its solver. ``nested``: a
        soil iteration converges the interface's active set in every one of its
        iterations (else both are updated once per iteration)."""
        plan = stage_plan(scene)
        how = Composition(one_shot=one_shot,
                          one_update=not nested and getattr(plan[0], "one_update_inside",
                                                            False))
        return cls([c.build(model, solver, how) for c in plan])

    def begin_stage(self) -> None:
        for it in self.iterations:
            it.begin_stage()

    def run(self, log) -> dict[str, IterationStatus]:
        """Solve the stage: the outermost iteration, with each inside the one before."""
        self._call(0, log)()
        return {it.name: it.last for it in self.iterations}

    def excavate(self, log) -> IterationStatus:
        """An embedded foundation's pit dug before the first stage, by the soil's iteration
        (the elastoplastic soil's load steps: :mod:`tankfx.iterations.excavation`), with the rest of the chain inside."""
        self.begin_stage()
        return excavate(self.iterations[0], self._call(1, log), log)

    def run_to_settlement(self, solver, log, settlement: float, steps: int):
        """The stage's load under settlement control
        (:func:`tankfx.iterations.continuation.run_to_settlement`), with the rest of the chain inside (an interface's active
        set converged in every iteration)."""
        return run_to_settlement(self.iterations[0], self._call(1, log), solver, log,
                                 settlement, steps)

    def at_milestones(self, call, study=None) -> None:
        """``call()`` at every milestone of a consolidation's path (its outermost
        iteration's :attr:`TimeStepping.milestone`); a fill schedule's collapse study
        (:attr:`tankfx.iterations.fill_schedule.FillSchedule.study`), whose checks and
        findings it uses."""
        self.iterations[0].milestone = call
        self.iterations[0].study = study

    def inner(self, log):
        """The chain inside the outermost iteration, as one call (a collapse search drives
        the soil's iteration itself)."""
        return self._call(1, log)

    def _call(self, k: int, log):
        """``inner`` of the k-th iteration's caller: a call of its ``run``."""
        if k == len(self.iterations):
            return None
        it = self.iterations[k]
        inner = self._call(k + 1, AtDebug(log) if it.quiet_inner else log)
        return lambda: it.run(inner, log)
