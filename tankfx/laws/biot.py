"""Consolidation: Biot's coupled flow and deformation of a saturated soil, in time.

A tank filled on clay settles twice: at once, as the water cannot leave the pores (the
undrained response: no change of volume), and then over months, as the excess pore
pressure drains away and the load passes to the soil's skeleton (the drained response).
With incompressible grains and water, Biot's equations for the displacement u and the
excess pore pressure p (compression positive, the hydrostatic part left out) are

    div(sigma'(u) - p I) = 0,      sigma' = drained elasticity (E', nu'),
    d/dt tr eps(u) - div((k / gamma_w) grad p) = 0      (Darcy's flow, k in m/s).

Backward Euler over a step dt gives the same saddle-point blocks as the mixed (u, p) soil
of :mod:`tankfx.laws.elasticity` (Taylor-Hood, p one degree below u), with the flow in place of the
compressibility block:

    a(u, v) - (p, tr eps(v))                   = loads
    -(q, tr eps(u)) - dt (k / gamma_w)(grad p, grad q) = -(q, tr eps(u_n))

symmetric and indefinite. dt = 0 is the undrained response (tr eps = 0, the nu = 0.5
soil of the same shear modulus); a step much longer than the consolidation time leaves
p -> 0 and the drained response (E', nu'). Every integral carries the 2 pi r weight.

Beyond the paper (which is drained or undrained at once): no equation of it is carried out
here.
"""
from __future__ import annotations

import math

import ufl
from dolfinx import fem

from . import elasticity as soil_forms


def oedometric_modulus(E, nu):
    """Constrained (oedometric) modulus E (1 - nu) / ((1 + nu)(1 - 2 nu)), Pa."""
    return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))


def consolidation_coefficient(E, nu, permeability, water_unit_weight):
    """Terzaghi's c_v = k E_oed / gamma_w, m^2/s."""
    return permeability * oedometric_modulus(E, nu) / water_unit_weight


def stratum_coefficients(consolidation, strata) -> tuple[list[float], list[float]]:
    """Per stratum of a consolidating ground (``strata``, top down), its permeability k
    (m/s: its own, else ``consolidation``'s) and its c_v (m^2/s)."""
    c = consolidation
    k = [c.permeability if st.permeability is None else st.permeability for st in strata]
    return k, [consolidation_coefficient(st.E, st.nu, k_i, c.water_unit_weight)
               for st, k_i in zip(strata, k)]


def biot_forms(u, p, v, q, E, nu, conductance, r, dx):
    """The four blocks (a_uu, a_up, a_pu, a_pp) of a backward-Euler step of Biot's
    equations, 2 pi r weighted. ``conductance`` = dt k / gamma_w (m^2/Pa): zero for the
    undrained response."""
    w = 2.0 * math.pi * r
    return (soil_forms.stiffness_form(u, v, E, nu, r, dx),
            -p * ufl.tr(soil_forms.strain(v, r)) * w * dx,
            -q * ufl.tr(soil_forms.strain(u, r)) * w * dx,
            -conductance * ufl.inner(ufl.grad(p), ufl.grad(q)) * w * dx)


#: Nitsche's penalty for a drained boundary, times the square of the pressure's degree over
#: the cell diameter (coercive for Lagrange elements at about 4 k^2; the drained column's
#: settlement moves by 9e-6 of its final value between 5 and 1000, at T_v = 0.01 where the
#: drained boundary's layer is thinnest, 1.5e-8 by T_v = 1: tests/test_consolidation.py)
NITSCHE_PENALTY = 10.0


def drainage_form(p, q, conductance, r, ds, degree: int, side: str | None = None,
                  weight=1.0):
    """A drained boundary (p = 0) by Nitsche's method: its terms scale with the
    conductance like the flow's, so the undrained step (dt = 0) has none. A Dirichlet
    condition would drain the boundary's elements at t = 0 already (an immediate settlement
    of a confined column of about one element's thickness of drained strain: 0.7 % of the
    final one with 40 elements over the height). On interior facets (``ds`` a dS), the
    terms of one ``side`` ("+" or "-": p, q, the conductance restricted to it by the
    caller), times ``weight`` (an indicator of the side that drains)."""
    msh = ufl.domain.extract_unique_domain(r)
    n, h = ufl.FacetNormal(msh), ufl.CellDiameter(msh)
    if side is not None:
        n, h, r = n(side), h(side), r(side)
    w = 2.0 * math.pi * r
    penalty = NITSCHE_PENALTY * max(degree, 1) ** 2 / h
    grad = ufl.grad
    return weight * conductance * (ufl.inner(grad(p), n) * q + ufl.inner(grad(q), n) * p
                                   - penalty * p * q) * w * ds


def previous_volume_load(history, q, r, dx):
    """The step's load on the flow equation, -(q, sum_j c_j tr eps(u_j)), 2 pi r weighted:
    ``history`` = [(c_j, u_j)] the earlier states with their weights (see
    :class:`StepWeights`)."""
    return -q * sum(c * ufl.tr(soil_forms.strain(u_j, r)) for c, u_j in history) * \
        2.0 * math.pi * r * dx


class StepWeights:
    """The time integrator's weights as Constants of the forms: a step to t_{n+1} solves
    tr eps(u_{n+1}) - sum_j c_j tr eps(u_j) = dt_eff div((k / gamma_w) grad p_{n+1}).

    Backward Euler (c = (1, 0), dt_eff = dt) from the undrained state, then the
    variable-step BDF2 (second order; zero-stable for step ratios below 1 + sqrt 2): with
    w = dt_n / dt_{n-1}, c = ((1 + w)^2, -w^2) / (1 + 2 w), dt_eff = dt (1 + w) / (1 + 2 w).
    Measured on Terzaghi's column at 10 steps a decade: BDF2 0.56 % of the final settlement
    where backward Euler is 2.2 % off (benchmarks/consolidation.py)."""

    def __init__(self, msh):
        self.previous = fem.Constant(msh, 1.0)
        self.before = fem.Constant(msh, 0.0)

    def set(self, dt: float, dt_before: float, second_order: bool) -> float:
        """Weights of a step dt after one of dt_before; returns dt_eff."""
        if not second_order or dt_before <= 0.0:
            self.previous.value, self.before.value = 1.0, 0.0
            return dt
        w = dt / dt_before
        self.previous.value = (1.0 + w) ** 2 / (1.0 + 2.0 * w)
        self.before.value = -w**2 / (1.0 + 2.0 * w)
        return dt * (1.0 + w) / (1.0 + 2.0 * w)
