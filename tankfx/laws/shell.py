"""Tank wall and foundation plate: thin axisymmetric shells of revolution on a 1D mesh.

The structure lives on a 1D mesh in the (r, z) plane (in an analysis, the facet submesh of
the soil's parent mesh made of the plate's underside and the wall's meridian). Each cell is a
straight meridian segment with unit tangent ``t`` (oriented towards +r on the plate and +z on
the wall) and normal ``n = (-t_z, t_r)`` (up on the plate, inward on the wall).

Unknowns: the displacement ``u = (u_r, u_z)`` of the line the mesh follows, the rotation
``beta`` of the
meridian (counter-clockwise in the (r, z) plane: one field for plate and wall, so a shared
vertex is a rigid joint), and the transverse shear force ``Q``, the Lagrange multiplier of the
Kirchhoff constraint ``beta = d(u.n)/ds``. With ``u`` in P3, ``beta`` in P2 and ``Q`` in DG2 the
constraint holds exactly, cell by cell: ``u.n`` is a C1 piecewise cubic, the thin-shell
(Kirchhoff-Love, Timoshenko's) model of the paper, with no shear locking at any thickness.

Strains of a conical shell element (Kraus 1967; plate: t = (1, 0), wall: t = (0, 1)):

    eps_s = d(u.t)/ds,  eps_theta = u_r / r,  kappa_s = d beta/ds,  kappa_theta = beta t_r / r

In a tank the mesh lines are the faces in contact with the soil (the plate's underside, the
wall's outer face), so the interface acts on ``u`` itself and the strains are those of the
mid-surface, half a thickness away (``offset``); plate and wall then meet at the outer
corner of a rigid joint, and the two faces share that corner's displacement.

Resultants per unit length: ``N = E t/(1 - nu^2) [eps_s + nu eps_theta, ...]`` and
``M = D [kappa_s + nu kappa_theta, ...]``, D = E t^3 / (12 (1 - nu^2)). A positive moment puts
the face opposite ``n`` in tension: the plate's underside (a sagging plate moment is
positive), the wall's outer face.

The paper: its plate and wall elements (thin shells, not numbered there); their thicknesses
from Kp and Kt are Eqs. 21-22 (:mod:`tankfx.laws.rigidity`).
"""
from __future__ import annotations

import math

import basix.ufl
import ufl
from dolfinx import fem

#: Cell tags of the structure mesh.
PLATE, WALL, WALL_EMBEDDED = 1, 2, 3


def tangent(mesh1d):
    """Unit tangent of each (straight) cell, oriented so that t_r + t_z > 0."""
    J = ufl.Jacobian(mesh1d)
    t = ufl.as_vector([J[0, 0], J[1, 0]])
    t = t / ufl.sqrt(ufl.dot(t, t))
    return ufl.sign(t[0] + t[1]) * t


def normal(t):
    """The tangent turned counter-clockwise: up on the plate, inward on the wall."""
    return ufl.as_vector([-t[1], t[0]])


def arc_derivative(f, t):
    """d f / ds along the cell (f scalar or vector); t is constant on a straight cell."""
    return ufl.dot(ufl.grad(f), t)


def mid_surface_displacement(u, beta, t, offset):
    """Mid-surface displacement of a shell whose unknown ``u`` is the displacement of its face
    opposite n, ``offset`` (half the thickness) away: u_mid = u - offset beta t."""
    return u - offset * beta * t


def shell_strains(u, beta, r, t, offset=0.0, on_axis: bool = False):
    """(eps_s, eps_theta, kappa_s, kappa_theta) of the axisymmetric shell.

    ``u`` is the displacement of the line the mesh follows: the mid-surface (``offset`` 0) or
    the face opposite n, ``offset`` = thickness / 2 from the mid-surface (then the membrane
    strains are those of the mid-surface, u - offset beta t). ``on_axis`` replaces the hoop
    terms by their limits at r = 0 (u_r / r -> du_r/dr, beta / r -> d beta/dr), for point
    evaluation there; quadrature points never lie on r = 0.
    """
    um = mid_surface_displacement(u, beta, t, offset)
    kappa_s = arc_derivative(beta, t)
    eps_s = ufl.dot(arc_derivative(u, t), t) - offset * kappa_s
    if on_axis:
        eps_th = ufl.conditional(ufl.gt(r, 0.0), um[0] / r, eps_s)
        kappa_th = ufl.conditional(ufl.gt(r, 0.0), beta * t[0] / r, kappa_s * t[0] * t[0])
    else:
        eps_th = um[0] / r
        kappa_th = beta * t[0] / r
    return eps_s, eps_th, kappa_s, kappa_th


def flexural_rigidity(E, nu, thickness):
    """D = E t^3 / (12 (1 - nu^2))."""
    return E * thickness**3 / (12.0 * (1.0 - nu**2))


def membrane_forces(eps_s, eps_th, E, nu, thickness):
    """(N_s, N_theta), N/m, tension positive."""
    C = E * thickness / (1.0 - nu**2)
    return C * (eps_s + nu * eps_th), C * (eps_th + nu * eps_s)


def bending_moments(kappa_s, kappa_th, E, nu, thickness):
    """(M_s, M_theta), N m/m, positive when the face opposite n is in tension."""
    D = flexural_rigidity(E, nu, thickness)
    return D * (kappa_s + nu * kappa_th), D * (kappa_th + nu * kappa_s)


def shell_stiffness(u, beta, v, gamma, r, t, E, nu, thickness, dx, offset=0.0):
    """Bilinear form of membrane and bending energy, with the 2 pi r weight (``offset``: see
    :func:`shell_strains`)."""
    e = shell_strains(u, beta, r, t, offset)
    ev = shell_strains(v, gamma, r, t, offset)
    N_s, N_th = membrane_forces(e[0], e[1], E, nu, thickness)
    M_s, M_th = bending_moments(e[2], e[3], E, nu, thickness)
    work = N_s * ev[0] + N_th * ev[1] + M_s * ev[2] + M_th * ev[3]
    return work * 2.0 * math.pi * r * dx


def kirchhoff_constraint(Q, beta, u, t, r, dx):
    """Q (beta - d(u.n)/ds): the multiplier term that makes the shell thin (no transverse
    shear strain). Used twice (with trial and test functions) for a symmetric saddle point."""
    return Q * (beta - ufl.dot(arc_derivative(u, t), normal(t))) * 2.0 * math.pi * r * dx


def structure_space(mesh1d, degree: int = 3):
    """Mixed space (u in P_k^2, beta in P_{k-1}, Q in DG_{k-1}) on a 1D mesh in 2D."""
    cell = mesh1d.basix_cell()
    P = basix.ufl.element("Lagrange", cell, degree, shape=(2,))
    B = basix.ufl.element("Lagrange", cell, degree - 1)
    S = basix.ufl.element("DG", cell, degree - 1)
    return fem.functionspace(mesh1d, basix.ufl.mixed_element([P, B, S]))


def wall_beta(radius, thickness, nu):
    """Decay rate of the wall's bending boundary layer, beta^4 = 3 (1 - nu^2) / (R t)^2, 1/m."""
    return (3.0 * (1.0 - nu**2) / (radius * thickness) ** 2) ** 0.25
