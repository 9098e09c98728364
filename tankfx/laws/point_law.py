"""The contract of a soil law whose state lives at the quadrature points of the soil's forms
(an elastoplastic law): what :mod:`tankfx.model.plastic` asks of it, and all it asks.

A law author writes one class that satisfies :class:`PointLaw` (a frozen dataclass of
per-point arrays, N points) and returns it from its :class:`tankfx.laws.soil_law.SoilLaw`'s
``point_law(soil, depth)``. Nothing outside the law's file names its constants: the model
calls :meth:`PointLaw.update`, the strength reduction :meth:`PointLaw.reduced`, the figures
:meth:`PointLaw.mobilised`.

Conventions
-----------
- Stresses and strains are Mandel vectors (rr, zz, sqrt 2 rz, theta), tension positive, so
  that sigma . eps is a dot product and a symmetric tangent a symmetric 4 x 4 matrix. SI.
- The model holds the stress as its change from the ground at rest (:meth:`initial_stress`):
  a deep point's total stress would carry its round-off into the out-of-balance force.
  ``update`` receives and returns changes; the law adds :meth:`initial_stress` itself where
  its yield condition needs the total.
- A law's own state beyond the stress and the strain (a hardening variable, a
  preconsolidation pressure) is named in ``state`` with its width per point, starts at
  :meth:`initial_state` (from the ground at rest), is passed to ``update`` as committed and
  comes back as the trial's; the model commits it with the rest when a step converges.
  Perfect plasticity has none.
- ``update`` is vectorised over all points (no loop per point) and pure: it changes none of
  its arguments.

Checks a law's tests make: its return lies on or inside its yield surface; the tangent is
``update``'s derivative (a Taylor test: the remainder of a first-order expansion falls as the
square of the step); ``symmetric`` is true only where the tangent is.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np


@dataclass(frozen=True)
class PointUpdate:
    """The trial state of every point after a strain increment.

    ``stress`` (N, 4): its change from the ground at rest; ``tangent`` (N, 4, 4): the
    consistent tangent d sigma / d eps; ``yielding`` (N,) bool: the points that returned to
    the yield surface; ``plastic_strain`` (N, 4): the increment's plastic strain;
    ``state``: the law's own state (its ``state`` names) after the increment."""

    stress: np.ndarray
    tangent: np.ndarray
    yielding: np.ndarray
    plastic_strain: np.ndarray
    state: dict


@runtime_checkable
class PointLaw(Protocol):
    """A soil law at N points (the arrays it holds are per point).

    Attributes
    ----------
    state : dict of str to int
        Its own state's names and widths per point (empty: perfect plasticity).
    symmetric : bool
        Its tangent is symmetric (associated flow): the linear solver may use LDL^T.
    """

    state: ClassVar[dict[str, int]]
    symmetric: bool

    def initial_stress(self) -> np.ndarray:
        """The ground at rest's stress (N, 4), effective where the soil has pore water."""

    def initial_state(self) -> dict[str, np.ndarray]:
        """Its own state at rest, each (N, width)."""

    def elastic_matrix(self, stress: np.ndarray | None = None) -> np.ndarray:
        """The elastic tangent (N, 4, 4) at the committed ``stress`` (its change from the
        ground at rest; None: at rest): unloading, the predictor. A law whose elasticity
        does not follow the stress ignores it."""

    def update(self, d_eps: np.ndarray, stress: np.ndarray, state: dict) -> PointUpdate:
        """The trial state after the strain increment ``d_eps`` (N, 4) from the committed
        ``stress`` (N, 4, its change from the ground at rest) and ``state``."""

    def reduced(self, factor: float) -> "PointLaw":
        """The same points with the strength divided by ``factor`` (the law's rule: c and
        tan phi for Mohr-Coulomb), for the strength reduction's factor of safety."""

    def elastic_where(self, mask: np.ndarray, E: np.ndarray | float,
                      nu: np.ndarray | float) -> "PointLaw":
        """The same points, those of ``mask`` (N,) elastic without limit with E and nu
        (a ringwall's, a void's): they never yield."""

    def mobilised(self, stress: np.ndarray, per: int = 1) -> np.ndarray:
        """tau / tau_f (1 on the yield surface) of total stresses (M, 4); ``per`` > 1: each
        is the mean of ``per`` consecutive points, read with their mean strength."""
