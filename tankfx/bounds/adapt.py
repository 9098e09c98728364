"""Both bounds on one mesh, refined where the upper bound dissipates, until their gap is
below a tolerance or the mesh reaches a size limit.

The gap (upper - lower) closes where both fields improve. Each triangle's share of it is
its local gap (Ciria, Peraire & Bonet 2008):

    eta_e = int_e D(eps_upper) dV - int_e sigma_lower : eps_upper dV >= 0,

the upper bound's dissipation there less the power the lower bound's stresses do on its
mechanism. Over the mesh they sum to (upper - lower) times the variable load's work. Each
round marks the fewest triangles that hold ``SHARE`` of the sum (Doerfler's marking) and
bisects them.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .lower import Ground, Loading, LowerBound, lower_bound
from .triangles import Triangles
from .upper import UpperBound, _bernstein, _collapsed_gauss, upper_bound

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
           max_cells: int = 20000, log=None, max_rounds: int = 1000) -> Bounds:
    """Lower and upper bound on ``tri``, refined until their gap is below ``gap``, the
    next mesh would pass ``max_cells`` or ``max_rounds`` are done. ``ground_of(tri)`` is the
    soil on a mesh."""
    rounds = []
    while True:
        t0 = time.perf_counter()
        ground: Ground = ground_of(tri)
        lo = lower_bound(tri, ground, load, scale)
        up = upper_bound(tri, ground, load, scale)
        result = Bounds(lo, up, tri, rounds)
        rounds.append({"cells": len(tri.cells), "lower": lo.factor, "upper": up.factor,
                       "gap": result.gap, "seconds": time.perf_counter() - t0,
                       "lower_seconds": lo.seconds, "upper_seconds": up.seconds,
                       "lower_check": lo.check, "upper_check": up.check})
        if log:
            log.info("  bounds: %6d triangles  lower %.5g  upper %.5g  gap %5.2f %%  (%.1f s)",
                     len(tri.cells), lo.factor, up.factor, 100 * result.gap,
                     rounds[-1]["seconds"])
        if result.gap <= gap or len(rounds) >= max_rounds:
            return result
        marked = doerfler(np.maximum(local_gap(tri, ground, lo, up), 0.0), SHARE)
        if len(tri.cells) + 3 * len(marked) > max_cells:
            return result
        tri = tri.refined(marked)


def doerfler(indicator: np.ndarray, share: float) -> np.ndarray:
    """The fewest indices whose indicator sums to ``share`` of the total."""
    # (ties broken by the index, the values to 1e-9 of the largest: the same marks for the
    # same mesh in other units, whose round-off differs)
    key = np.round(indicator / max(float(np.max(indicator)), 1e-300), 9)
    order = np.lexsort((np.arange(len(key)), -key))
    total = np.cumsum(indicator[order])
    return order[:int(np.searchsorted(total, share * total[-1])) + 1]


def local_gap(tri: Triangles, ground: Ground, lo: LowerBound, up: UpperBound) -> np.ndarray:
    """Each triangle's eta_e (W at a settlement rate of 1 m/s): its upper-bound dissipation
    less 2 pi int sigma : G / r dA, sigma the lower bound's stress (S / r + sigma0) and
    G = r^2 eps the upper bound's, by the collapsed Gauss rule."""
    qp, qw = _collapsed_gauss()
    p = tri.points[tri.cells]
    r = p[..., 0] @ qp.T                                      # (m, q)
    z = p[..., 1] @ qp.T
    S = np.einsum("qi,mic->mqc", qp, lo.S)                    # r sigma', (m, q, 3)
    G = np.einsum("qj,mjc->mqc", _bernstein(qp), up.control)  # (m, q, 4)
    p0 = ground.gamma[:, None] * z                            # sigma0 = gamma z I
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(r > 1e-14, 1.0 / r, 0.0)
    sig_r = S[..., 0] * inv + p0
    sig_z = S[..., 1] * inv + p0
    tau = S[..., 2] * inv
    sig_t = lo.sigma_theta[:, None] + p0
    power = (sig_r * G[..., 0] + sig_z * G[..., 1] + tau * G[..., 2] + sig_t * G[..., 3]) * inv
    work = 2.0 * np.pi * tri.area * (power @ qw)
    return up.dissipation - work
