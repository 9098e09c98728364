"""How an iteration ended: the status it returns (converged, its iterations, its history,
its reason in physical terms, a code, and its results.json record), and the codes of its
failures (``SolveError.code``), which a program acts on while the message says it to a
person."""
from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


class Failure(StrEnum):
    """The reasons an iteration stops without a converged state."""

    #: a linear solve failed (the default of tankfx.fem.solvers.SolveError)
    LINEAR_SOLVE = "linear_solve"
    #: no converged state within the iterations allowed
    MAX_ITERATIONS = "max_iterations"
    #: the soil cannot carry the load (cells at its strength)
    SOIL_FAILURE = "soil_failure"
    #: the interface's active set repeats its states
    CYCLES = "cycles"
    #: the interface separated everywhere: nothing holds the foundation
    SEPARATED = "separated_everywhere"
    #: no state changes but the out-of-balance force stays: the solve lost accuracy
    LOST_ACCURACY = "lost_accuracy"
    #: carriers held separated are pressed into by the soil
    HELD_PENETRATION = "held_penetration"
    #: a limit analysis' conic program not solved (tankfx.bounds.program.ProgramError)
    LIMIT_ANALYSIS = "limit_analysis"


#: the code of a status whose iteration converged
CONVERGED = "converged"
#: ... and of one pass of an iteration nested in another, whose states still change
UNSETTLED = "unsettled"


@dataclass(frozen=True)
class IterationStatus:
    """How an iteration ended (a failure raises a ``SolveError`` with its code instead).

    Attributes
    ----------
    converged : bool
    iterations : int
    history : list of dict
        A row per iteration, as the log shows it.
    reason : str
        Why it stopped, in physical terms (results.json's ``criterion``).
    code : str
        CONVERGED, or UNSETTLED for a pass whose states still change.
    record : dict
        Its entry of results.json.
    unsettled : int
        How many of its states still changed (a pass of an iteration nested in another:
        the outer one is not converged while they do).
    data : object
        What it computed beyond its record, for ``tankfx.results`` to report (the secant
        loop's converged constants per cell, a consolidation's ``ConsolidationRun``).
    """

    converged: bool
    iterations: int
    history: list
    reason: str
    code: str
    record: dict
    unsettled: int = 0
    data: object = None

    @classmethod
    def of(cls, record: dict, unsettled: int = 0, data: object = None) -> "IterationStatus":
        """The status of an iteration's record (``converged``, ``iterations``,
        ``history``, ``criterion`` and what else it reports)."""
        return cls(record["converged"], record["iterations"], record["history"],
                   record["criterion"], CONVERGED if record["converged"] else UNSETTLED,
                   record, unsettled, data)
