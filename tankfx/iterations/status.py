"""What an iteration's failure was, as a code a program acts on (``SolveError.code``); its
message says it to a person."""
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
