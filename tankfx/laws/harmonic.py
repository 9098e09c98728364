"""The first Fourier harmonic (cos theta) of soil, shells and interface: overturning.

A horizontal force or an overturning moment on an axisymmetric tank makes a displacement
field whose every component varies once around the axis:

    u_r = A(r, z) cos(theta),  u_z = Z(r, z) cos(theta),  u_theta = V(r, z) sin(theta)

(the x axis at theta = 0; a positive moment presses that side down, a positive horizontal
force pushes towards it). Linear elasticity keeps the harmonics apart, so this part solves
on the same (r, z) mesh as the axisymmetric one, with three amplitudes per node instead of
two; over the circle cos^2 and sin^2 integrate to pi, the weight of every form below
(2 pi in the axisymmetric ones).

On the axis a cos(theta) field is single-valued only if u_z = 0 and u_r + u_theta = 0 there
(a translation along x is A = 1, V = -1). The unknowns are therefore

    D = A - V   (twice the x-translation on the axis: free),
    Z,
    S = A + V   (zero on the axis),

so both conditions are Dirichlet conditions. :func:`cylindrical` turns them back into
(A, Z, V).

Shells: the Kirchhoff-Love shell of revolution with straight meridians (the elements of
:mod:`tankfx.laws.shell`), with Koiter's linear bending strains (the change of the second
fundamental form less its membrane part), so that both rigid motions of the first harmonic
(a translation along x, a rotation about y) strain nothing, exactly: Donnell's simplified
curvatures do not have that property for this harmonic. The same unknowns as in the
axisymmetric shell (the face displacement u = (A, Z), the meridian's rotation beta =
d(u.n)/ds, the multiplier Q of that constraint) and the circumferential V, as D and S.

Beyond the paper (which is axisymmetric): no equation of it is carried out here.
"""
from __future__ import annotations

import math

import basix
import basix.ufl
import ufl
from dolfinx import fem

from . import elasticity as soil_forms
from . import shell as st

#: integral of cos^2 (and sin^2) over the circle: the weight pi r of every form
WEIGHT = math.pi


def cylindrical(U):
    """(A, Z, V) amplitudes of u_r, u_z (cos) and u_theta (sin) from the unknowns (D, Z, S)."""
    return 0.5 * (U[2] + U[0]), U[1], 0.5 * (U[2] - U[0])


def soil_trace(U):
    """The (r, z) part (A, Z) of a soil amplitude field and its V."""
    A, Z, V = cylindrical(U)
    return ufl.as_vector([A, Z]), V


def soil_strain(U, r):
    """Amplitudes of the strain tensor (r, z, theta order): the normal and rz components
    go with cos(theta), the r-theta and z-theta shears with sin(theta)."""
    A, Z, V = cylindrical(U)
    e_rr, e_zz, e_tt = A.dx(0), Z.dx(1), U[2] / r          # (A + V) / r = S / r
    e_rz = 0.5 * (A.dx(1) + Z.dx(0))
    e_rt = 0.5 * (V.dx(0) - U[2] / r)                         # (dV/dr - (A + V) / r) / 2
    e_zt = 0.5 * (V.dx(1) - Z / r)
    return ufl.as_tensor([[e_rr, e_rz, e_rt],
                          [e_rz, e_zz, e_zt],
                          [e_rt, e_zt, e_tt]])


def soil_stiffness(U, W, E, nu, r, dx):
    """Bilinear form of the soil's first harmonic: sigma : eps over the circle (the cos and
    sin parts do not couple in an isotropic soil)."""
    eps = soil_strain(U, r)
    return ufl.inner(soil_forms.stress(eps, E, nu), soil_strain(W, r)) * WEIGHT * r * dx


def mixed_soil_forms(U, p, W, q, E, nu, r, dx):
    """The mixed (u, p) form of the first harmonic (p the amplitude of the pressure, cos):
    the blocks (a_uu, a_up, a_pu, a_pp) as :func:`tankfx.laws.elasticity.mixed_stiffness_forms`."""
    mu = soil_forms.lame(E, nu)[1]
    w = WEIGHT * r
    eps_u, eps_w = soil_strain(U, r), soil_strain(W, r)
    return (ufl.inner(2.0 * mu * eps_u, eps_w) * w * dx,
            -p * ufl.tr(eps_w) * w * dx,
            -q * ufl.tr(eps_u) * w * dx,
            -soil_forms.inverse_lambda(E, nu) * p * q * w * dx)


def structure_space(mesh1d, degree: int = 3):
    """Mixed space ((D, Z) in P_k^2, beta in P_{k-1}, Q in DG_{k-1}, S in P_k)."""
    cell = mesh1d.basix_cell()
    P = basix.ufl.element("Lagrange", cell, degree, shape=(2,))
    B = basix.ufl.element("Lagrange", cell, degree - 1)
    M = basix.ufl.element("DG", cell, degree - 1)
    S = basix.ufl.element("Lagrange", cell, degree)
    return fem.functionspace(mesh1d, basix.ufl.mixed_element([P, B, M, S]))


def shell_amplitudes(q, s):
    """The face displacement u = (A, Z) and V of a shell from its unknowns (D, Z) and S."""
    return ufl.as_vector([0.5 * (s + q[0]), q[1]]), 0.5 * (s - q[0])


def mid_surface_circumferential(u, V, r, t, offset):
    """V of the mid-surface, ``offset`` from the face whose displacement is (u, V): the face
    lies behind the mid-surface along -n, so the normal's rotation about the meridian,
    (n . d U / d theta) / r = -(u.n + V n_r) / r (sin), moves it by offset times that."""
    n = st.normal(t)
    return V + offset * (ufl.dot(u, n) + V * n[0]) / r


def shell_strains(u, V, beta, r, t, offset=0.0):
    """(eps_s, eps_theta, gamma, kappa_s, kappa_theta, kappa_s_theta) of the first harmonic:
    membrane strains of the mid-surface and Koiter's bending strains (physical components;
    gamma = 2 eps_s_theta and kappa_s_theta go with sin(theta), the rest with cos).

    ``u`` = (A, Z) and ``V`` are the displacements of the line the mesh follows, the face
    opposite n, ``offset`` from the mid-surface (as in :func:`tankfx.laws.shell.shell_strains`);
    beta = d(u.n)/ds. The meridian is straight (t constant on a cell): its curvature b_ss is
    0 and the parallel's is b_theta = t_z / r.
    """
    n = st.normal(t)
    un = ufl.dot(u, n)
    # the mid-surface, half a thickness from the face (the normal's rotation times offset),
    # on its own radius: with the face's, a rotation about y would shear it (by offset / r)
    um = st.mid_surface_displacement(u, beta, t, offset)
    Vm = mid_surface_circumferential(u, V, r, t, offset)
    rm = r + offset * n[0]
    eps_s = ufl.dot(st.arc_derivative(um, t), t)
    eps_th = (um[0] + Vm) / rm
    gamma = st.arc_derivative(Vm, t) - (ufl.dot(um, t) + Vm * t[0]) / rm
    # the change of the second fundamental form, n . (covariant second derivative of the
    # displacement), in physical components ...
    b_ss = st.arc_derivative(beta, t)
    b_st = -(beta + st.arc_derivative(V, t) * n[0] - t[0] / r * (un + V * n[0])) / r
    b_tt = (-un - (u[0] + 2.0 * V) * n[0] + r * t[0] * beta) / r**2
    # ... less its membrane part (Koiter): b_theta^theta = t_z / r
    kappa_th = b_tt - t[1] / r * eps_th
    kappa_st = b_st - 0.25 * t[1] / r * gamma
    return eps_s, eps_th, gamma, b_ss, kappa_th, kappa_st


def shell_resultants_of(strains, E, nu, thickness):
    """(N_s, N_theta, N_s_theta, M_s, M_theta, M_s_theta) of :func:`shell_strains`."""
    eps_s, eps_th, gamma, k_s, k_th, k_st = strains
    C = E * thickness / (1.0 - nu**2)
    D = st.flexural_rigidity(E, nu, thickness)
    return (C * (eps_s + nu * eps_th), C * (eps_th + nu * eps_s), C * 0.5 * (1.0 - nu) * gamma,
            D * (k_s + nu * k_th), D * (k_th + nu * k_s), D * (1.0 - nu) * k_st)


def shell_energy_density(e, f, E, nu, thickness):
    """The work of the resultants of strains ``e`` on strains ``f``, per unit area."""
    N_s, N_th, N_st, M_s, M_th, M_st = shell_resultants_of(e, E, nu, thickness)
    return (N_s * f[0] + N_th * f[1] + N_st * f[2]
            + M_s * f[3] + M_th * f[4] + 2.0 * M_st * f[5])


def shell_stiffness(w_trial, w_test, r, t, E, nu, thickness, dx, offset=0.0):
    """Membrane and bending energy of the first harmonic, pi r weighted; ``w_*`` are
    (q, beta, s) triples of the structure's unknowns."""
    (q, b, s), (qv, bv, sv) = w_trial, w_test
    u, V = shell_amplitudes(q, s)
    uv, Vv = shell_amplitudes(qv, sv)
    e = shell_strains(u, V, b, r, t, offset)
    f = shell_strains(uv, Vv, bv, r, t, offset)
    return shell_energy_density(e, f, E, nu, thickness) * WEIGHT * r * dx


def kirchhoff_constraint(Q, beta, u, t, r, dx):
    """Q (beta - d(u.n)/ds), pi r weighted (see :func:`tankfx.laws.shell.kirchhoff_constraint`)."""
    return Q * (beta - ufl.dot(st.arc_derivative(u, t), st.normal(t))) * WEIGHT * r * dx


def shell_resultants(w, r, t, E, nu, thickness, offset=0.0) -> dict:
    """Resultant amplitudes of a solved first-harmonic shell as cell-wise fields for point
    evaluation: N_s, N_theta, M_s, M_theta (cos) and N_s_theta, M_s_theta (sin), with the
    face displacement u = (A, Z), V and beta."""
    q, b, _, s = ufl.split(w)
    u, V = shell_amplitudes(q, s)
    res = shell_resultants_of(shell_strains(u, V, b, r, t, offset), E, nu, thickness)
    # discontinuous spaces with their points inside the cells (Gauss-Legendre's): the
    # strains' 1 / r and 1 / r^2 are never evaluated on the axis, and the polynomials give
    # there the limits (every first-harmonic amplitude vanishes on the axis)
    msh = w.function_space.mesh
    gl = basix.LagrangeVariant.gl_warped
    space = fem.functionspace(msh, basix.ufl.element("DG", msh.basix_cell(), 2,
                                                     lagrange_variant=gl))
    vec = fem.functionspace(msh, basix.ufl.element("DG", msh.basix_cell(), 3, shape=(2,),
                                                   lagrange_variant=gl))
    out = {}
    names = ("N_s", "N_theta", "N_s_theta", "M_s", "M_theta", "M_s_theta")
    for name, expr in zip(names, res):
        f = fem.Function(space, name=name)
        f.interpolate(fem.Expression(expr, space.element.interpolation_points))
        out[name] = f
    for name, expr, S in (("u", u, vec), ("V", V, space), ("beta", b, space)):
        f = fem.Function(S, name=name)
        f.interpolate(fem.Expression(expr, S.element.interpolation_points))
        out[name] = f
    return out


def interface_tractions(jump, j_theta, n, t, k_n, k_s, mu=0.0):
    """(sigma_n, tau, tau_theta) amplitudes of a jump (u, V): the interface law of
    :func:`tankfx.laws.interface.tractions` about a converged state, and k_s on the
    circumferential jump (zero where an element slips or is separated)."""
    sigma_n = k_n * ufl.dot(jump, n)
    return sigma_n, k_s * ufl.dot(jump, t) + mu * sigma_n, k_s * j_theta


def interface_form(jump, j_theta, jump_v, j_theta_v, n, t, k_n, k_s, mu, r, measure):
    """The interface's virtual work on the first harmonic, pi r weighted."""
    sigma_n, tau, tau_th = interface_tractions(jump, j_theta, n, t, k_n, k_s, mu)
    return (sigma_n * ufl.dot(jump_v, n) + tau * ufl.dot(jump_v, t) + tau_th * j_theta_v) * \
        WEIGHT * r * measure
