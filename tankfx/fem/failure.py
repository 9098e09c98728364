"""The one encoding of failure: why a solve, an iteration, a collapse search or a limit
analysis stopped without a result, as a code a program acts on (the message says it to a
person). A ``StrEnum``: its values are results.json's words."""
from __future__ import annotations

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
    #: a collapse search's failed state: Newton found no equilibrium at a load (or strength)
    NO_EQUILIBRIUM = "no equilibrium"
    #: ... or the equilibrium it found lies beyond the settlement criterion (0.1 D)
    SETTLEMENT = "settlement"
