"""The iteration that solves a stage of each soil law, by the name its law gives
(:attr:`tankfx.laws.soil_law.SoilLaw.iteration`): the analysis and ``tankfx check`` look it
up here, without knowing which soil they have."""
from __future__ import annotations

from .load_steps import NewtonIteration
from .secant import HyperbolicIteration

#: SoilLaw.iteration -> the iteration (None, a law solved by one linear solve, has none)
SOIL_ITERATIONS = {"secant": HyperbolicIteration, "newton": NewtonIteration}


def soil_iteration(law):
    """The iteration class of a soil law, or None where one linear solve does."""
    return None if law.iteration is None else SOIL_ITERATIONS[law.iteration]
