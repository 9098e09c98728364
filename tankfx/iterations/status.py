"""How an iteration ended: the status it returns (converged, its iterations, its history,
its reason in physical terms, a code, and its results.json record), and the codes of its
failures (``SolveError.code``), which a program acts on while the message says it to a
person."""
from __future__ import annotations

from dataclasses import dataclass

from ..fem.failure import Failure
from ..fem.solvers import SolveError


#: the code of a status whose iteration converged
CONVERGED = "converged"
#: ... and of one pass of an iteration nested in another, whose states still change
UNSETTLED = "unsettled"

__all__ = ["CONVERGED", "UNSETTLED", "AtDebug", "Failure", "IterationStatus", "SoilFailure"]


class SoilFailure(SolveError):
    """The soil cannot carry the load, whatever its law: a secant soil's cells at their
    ultimate deviator or strength, an elastoplastic soil's load steps unable to carry the
    stage's load. The message says where and under what load; a :class:`SolveError` with
    its ``history``."""

    def __init__(self, message: str, history: list | None = None):
        super().__init__(message, history, code=Failure.SOIL_FAILURE)


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


class AtDebug:
    """A logger's info at debug level, its warnings as they are (the iterations inside a
    time step: a table a step would drown the log)."""

    def __init__(self, log):
        self.info, self.debug, self.warning = log.debug, log.debug, log.warning
