"""Both bounds on one mesh, refined where the upper bound dissipates, until their gap is
below a tolerance or the mesh reaches a size limit.

The gap (upper - lower) / lower closes where both fields improve. The mechanism's shear
zones are where the upper bound's dissipation concentrates, and where the lower bound's
linear stresses are too coarse to follow the fans of the exact field. Each round marks the
fewest triangles that hold ``SHARE`` of the dissipation (Doerfler's marking) and bisects
them.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .lower import Ground, Loading, LowerBound, lower_bound
from .triangles import Triangles
from .upper import UpperBound, upper_bound

#: the share of the upper bound's dissipation whose triangles are refined each round
SHARE = 0.5


@dataclass
class Bounds:
    lower: LowerBound
    upper: UpperBound
    triangles: Triangles
    rounds: list = field(default_factory=list)   # per round: cells, lower, upper, gap, seconds

    @property
    def gap(self) -> float:
        return (self.upper.factor - self.lower.factor) / self.lower.factor


def bounds(tri: Triangles, ground_of, load: Loading, scale: float, gap: float = 0.03,
           max_cells: int = 20000, log=None) -> Bounds:
    """Lower and upper bound on ``tri``, refined until their gap is below ``gap`` or the
    next mesh would pass ``max_cells``. ``ground_of(tri)`` is the soil on a mesh."""
    rounds = []
    while True:
        t0 = time.perf_counter()
        ground: Ground = ground_of(tri)
        lo = lower_bound(tri, ground, load, scale)
        up = upper_bound(tri, ground, load, scale)
        result = Bounds(lo, up, tri, rounds)
        rounds.append({"cells": len(tri.cells), "lower": lo.factor, "upper": up.factor,
                       "gap": result.gap, "seconds": time.perf_counter() - t0,
                       "lower_seconds": lo.seconds, "upper_seconds": up.seconds})
        if log:
            log.info("  bounds: %6d triangles  lower %.5g  upper %.5g  gap %5.2f %%  (%.1f s)",
                     len(tri.cells), lo.factor, up.factor, 100 * result.gap,
                     rounds[-1]["seconds"])
        if result.gap <= gap:
            return result
        marked = doerfler(up.dissipation, SHARE)
        if len(tri.cells) + 3 * len(marked) > max_cells:
            return result
        tri = tri.refined(marked)


def doerfler(indicator: np.ndarray, share: float) -> np.ndarray:
    """The fewest indices whose indicator sums to ``share`` of the total."""
    order = np.argsort(indicator)[::-1]
    total = np.cumsum(indicator[order])
    return order[:int(np.searchsorted(total, share * total[-1])) + 1]
