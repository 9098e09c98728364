"""Axisymmetric soil: small-strain isotropic elasticity in the (r, z) meridian plane.

Conventions: ``x[0] = r`` (radius), ``x[1] = z`` (upward, ground surface at z = 0), the soil
displacement is ``u = (u_r, u_z)``. Tensors are 3x3 in the order (r, z, theta); the hoop
strain is ``u_r / r``. Integrals carry the full ``2 pi r`` weight, so assembled loads and
reactions are true forces in newtons.

The modulus enters the forms only through ``stress(eps, E, nu)``, so that any UFL expression
can stand for it: the depth-dependent ``E (1 + lambda h)`` of a linear soil, or a DG0 secant
modulus held per cell for a nonlinear one.

The paper: its axisymmetric soil elements (their elasticity is not numbered there); the secant
modulus of Eqs. 17-19 enters as ``E`` (:mod:`tankfx.laws.kondner`).
"""
from __future__ import annotations

import math

import ufl


def quadrature_degree(degree: int) -> int:
    """Quadrature degree of the soil's forms for Lagrange elements of ``degree`` p: 2p + 1.
    The r-weighted products of gradients, times a modulus linear in depth, are polynomials
    of degree 2p, integrated exactly; the hoop term u_r v_r / r is rational, so no rule is
    exact for it. UFL's estimate (it counts 1 / r as degree 1: 2p + 3 to 2p + 4) takes twice
    the points for nothing measurable: w0 of the embedded tank at 274k dofs changes by 1e-9
    (relative), and a matrix assembly of the nonlinear tank there takes 0.39 instead of 0.66 s."""
    return 2 * degree + 1


def radius(mesh) -> ufl.core.expr.Expr:
    return ufl.SpatialCoordinate(mesh)[0]


def depth(mesh) -> ufl.core.expr.Expr:
    """Depth below the ground surface, h = -z, m."""
    return -ufl.SpatialCoordinate(mesh)[1]


def hoop_strain(u, r, on_axis: bool = False):
    """u_r / r. At r = 0 (only reached by point evaluation: quadrature points are interior)
    the limit du_r/dr is used, since u_r vanishes on the axis."""
    if on_axis:
        return ufl.conditional(ufl.gt(r, 0.0), u[0] / r, u[0].dx(0))
    return u[0] / r


def strain(u, r, on_axis: bool = False):
    """Small strain tensor of an axisymmetric displacement, (r, z, theta) order."""
    g = ufl.grad(u)
    return ufl.as_tensor([[g[0, 0], 0.5 * (g[0, 1] + g[1, 0]), 0.0],
                          [0.5 * (g[0, 1] + g[1, 0]), g[1, 1], 0.0],
                          [0.0, 0.0, hoop_strain(u, r, on_axis)]])


def tensor_components(t):
    """(rr, zz, rz, theta) of an axisymmetric tensor, as a vector (for cell fields)."""
    return ufl.as_vector([t[0, 0], t[1, 1], t[0, 1], t[2, 2]])


def lame(E, nu):
    """Lame's constants (lambda, mu) of an isotropic material."""
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def stress(eps, E, nu):
    """Isotropic linear elastic stress (tension positive, the continuum convention)."""
    lmbda, mu = lame(E, nu)
    return lmbda * ufl.tr(eps) * ufl.Identity(3) + 2.0 * mu * eps


def modulus_with_depth(E_surface, gradient, h):
    """The paper's non-homogeneous soil, E(h) = E_s (1 + lambda h)."""
    return E_surface * (1.0 + gradient * h)


def stiffness_form(u, v, E, nu, r, dx):
    """Bilinear form of the soil, integrated over the soil cells with the 2 pi r weight."""
    return ufl.inner(stress(strain(u, r), E, nu), strain(v, r)) * 2.0 * math.pi * r * dx


def inverse_lambda(E, nu):
    """1 / lambda = (1 + nu)(1 - 2 nu) / (E nu): zero for an incompressible soil."""
    return (1.0 + nu) * (1.0 - 2.0 * nu) / (E * nu)


def mixed_stress(eps, p, E, nu):
    """sigma = 2 mu eps - p I (tension positive): the stress of the mixed form."""
    return 2.0 * lame(E, nu)[1] * eps - p * ufl.Identity(3)


def mixed_stiffness_forms(u, p, v, q, E, nu, r, dx):
    """The four blocks (a_uu, a_up, a_pu, a_pp) of the mixed form, 2 pi r weighted:
    symmetric and indefinite (a_pp <= 0)."""
    w = 2.0 * math.pi * r
    mu = lame(E, nu)[1]
    return (ufl.inner(2.0 * mu * strain(u, r), strain(v, r)) * w * dx,
            -p * ufl.tr(strain(v, r)) * w * dx,
            -q * ufl.tr(strain(u, r)) * w * dx,
            -inverse_lambda(E, nu) * p * q * w * dx)


def by_stratum(indicators, inside, outside=None):
    """Per cell the expression of its stratum, by the strata's cell indicators chi_i (DG0, 1
    in the stratum's cells, 0 elsewhere): (1 - sum chi_i) outside + sum chi_i inside_i, an
    expression valid in every cell (for a form, a projection or a cell field).

    ``inside``: one expression per indicator, or one for all of them (then (sum chi_i)
    inside); ``outside``: the other cells' expression (None: nothing there)."""
    if isinstance(inside, (list, tuple)):
        out = None if outside is None else (1.0 - sum(indicators)) * outside
        for chi, expr in zip(indicators, inside):
            out = chi * expr if out is None else out + chi * expr
        return out
    chi = sum(indicators)
    return chi * inside if outside is None else (1.0 - chi) * outside + chi * inside

