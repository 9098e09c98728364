"""The contract of a secant soil law (``SoilLaw.iteration == "secant"``): what the Picard
iteration on the DG0 secant modulus (:class:`tankfx.iterations.secant.HyperbolicIteration`)
asks of a law, and all it asks. Kondner's hyperbolic soil (:mod:`tankfx.laws.kondner`) and
Duncan & Chang's (:mod:`tankfx.laws.duncan_chang`) satisfy it.

Everything is per cell, in cell order, numpy arrays; SI units. A law's constants of the cells
live in the dict its :meth:`SecantLaw.secant_start` returns (its own names: Kondner's ``a``
and ``b``), which the iteration hands back to it unread.
"""
from __future__ import annotations

from typing import Any, Callable, ClassVar, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class SecantLaw(Protocol):
    """A soil law solved by secant (Picard) iterations.

    Attributes
    ----------
    modulus_floor : float
        The least secant modulus, a fraction of the initial one.
    needs_stress : bool
        The secant step reads the cells' stress (a confinement-dependent law), not only
        their strains.
    anderson_depth : int
        Depth of the Anderson acceleration of the secant update (0: plain Picard).
    """

    modulus_floor: ClassVar[float]
    needs_stress: ClassVar[bool]
    anderson_depth: ClassVar[int]

    @staticmethod
    def major_strain(eps_min: np.ndarray, eps_max: np.ndarray, nu: np.ndarray) -> np.ndarray:
        """The strain measure its deviator follows, of the principal strains and nu."""

    @classmethod
    def secant_start(cls, soil, depth: np.ndarray, cell_strata) -> dict[str, Any]:
        """The cells' constants before the first iteration (``nu`` and ``nu_intact``, the
        one its strain measure reads, among them)."""

    @classmethod
    def secant_step(cls, soil, start: dict, nu, E, eps_min, eps_max, stress, is_soil
                    ) -> dict[str, Any]:
        """One secant step: the new moduli ``E``, their ``misfit`` (Eq. 18), the cells at
        their strength (``ultimate``), and the law's constants as they now are."""

    @classmethod
    def next_moduli(cls, step: dict, E_new, E, nu, nu_intact, E_initial, floor,
                    accelerate: Callable) -> tuple:
        """The next iteration's (E, nu or None where the law keeps nu)."""

    @classmethod
    def unloading_modulus(cls, soil, start: dict, E_initial, E, stress, peak_stress, ratio,
                          is_soil) -> np.ndarray:
        """Each cell's unloading line's modulus (``soil.unloading_modulus_ratio``)."""

    @classmethod
    def start_text(cls, soil, tol: float) -> str:
        """The iteration's first log line: the law's constants and the tolerance."""

    @classmethod
    def strength_text(cls, soil) -> str:
        """The law's strength in words, for a failure's message."""

    @classmethod
    def exhausted_text(cls, n_ult, where, max_it, worst, du_rel) -> str | None:
        """The iteration's failure in the law's own words, where it has them (None: the
        soil cannot carry its load)."""
