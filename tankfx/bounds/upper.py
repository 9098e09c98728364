"""The upper bound: a kinematically admissible velocity field, the least load factor its
dissipation allows (Makrodimopoulos & Martin 2007's six-node element, carried into axial
symmetry through the flux v = r u).

In axial symmetry the strain rate eps = (du_r/dr, du_z/dz, du_r/dz + du_z/dr, u_r / r) has
1/r in it. A quadratic velocity u would need its volume change, r div-like and quadratic,
held at six points of each triangle for Tresca's incompressibility; six conditions against
about four degrees of freedom lock (measured: 10.1 and 8.7 for N_c = 5.69). The unknown is
therefore the flux v = r u, quadratic and continuous, with u = v / r. Then

    G = r^2 eps = (r dv_r/dr - v_r, r dv_z/dz, r (dv_r/dz + dv_z/dr) - v_z, v_r)

is quadratic on each triangle, and its volume change r div v is r times a linear
function. Incompressibility is div v = 0, three conditions per triangle, as in plane
strain. The dissipation is positively homogeneous, so per radian
int D(eps) r dA = int D(G) / r dA. In G's Bernstein form G = sum_j B_j C_j, the B_j are
non-negative and sum to one, and the control points C_j are linear in the nodal fluxes.
Since D is convex,

    int c D_1(G) / r dA <= sum_j D_1(C_j) int c B_j / r dA

(D_1 the dissipation at unit cohesion). D_1 is taken in closed form: Tresca's
c (|e_1| + |e_2| + |e_3|) of an isochoric rate, Mohr-Coulomb's c cot phi tr G of a rate in
the flow cone tr G >= sin phi (|e_1| + |e_2| + |e_3|); two variables a control point. The
conic dual of the three yield cones of :mod:`tankfx.laws.limit_cones` (three cone
variables a control point; any feasible ones give an upper estimate) is kept as a check.
The weights are integrated by a 64-point collapsed Gauss rule.
On the axis v = 0, so u stays bounded and the control points there vanish.

Supports: a fixed side or base v = 0, a smooth one its normal flux 0. A rigid foundation
moves down by 1 (v_z = -r under it: the normalisation), a rough one without sliding
(v_r = 0). A flexible load's work is normalised to 1 instead.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..laws.limit_cones import mohr_coulomb_cones
from .lower import Ground, Loading
from .program import ConeProgram, ProgramError
from .triangles import AXIS, BASE, CONTACT, PIT_SIDE, SIDE, Triangles

#: the six Lagrange points of the quadratic triangle, barycentric: vertices, then the
#: midpoints of edges (0, 1), (1, 2), (2, 0)
NODES = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [.5, .5, 0], [0, .5, .5], [.5, 0, .5]])
EDGES = np.array([[0, 1], [1, 2], [2, 0]])
#: Strang & Fix's six-point rule, exact to degree 4 (barycentric points, weights summing to 1)
_A, _B = 0.445948490915965, 0.091576213509771
QUADRATURE = (np.array([[_A, _A, 1 - 2 * _A], [_A, 1 - 2 * _A, _A], [1 - 2 * _A, _A, _A],
                        [_B, _B, 1 - 2 * _B], [_B, 1 - 2 * _B, _B], [1 - 2 * _B, _B, _B]]),
              np.array([0.223381589678011] * 3 + [0.109951743655322] * 3))


@dataclass(frozen=True)
class UpperBound:
    factor: float
    velocity: np.ndarray          # (nodes, 2), P2 nodal velocities (u_z = -1 under a rigid foundation)
    nodes: np.ndarray             # (nodes, 2), their (r, z)
    dissipation: np.ndarray       # (m,) each triangle's dissipated power, W at a settlement rate of 1 m/s
    control: np.ndarray           # (m, 6, 4): the Bernstein control points of G = r^2 eps, m^2/s
    #: the field's check: the solver's record (status, duality gap, residuals), its factor
    #: ``solver_factor`` (for comparison), ``projection`` (the largest change the exact
    #: supports and div v = 0 made to a flux, relative to the largest), ``flow_violation``
    #: (<= 0: in the flow cone; None for Tresca)
    check: dict
    seconds: float
    iterations: int
    variables: int


#: the flow cone's violation, relative to the largest rate, above which a Mohr-Coulomb field
#: is refused: the interior-point solver's feasibility (its tolerance 1e-8 on the scaled
#: program; measured up to 4.9e-10 on the c-phi footings). A frictional field is checked
#: to it, not projected: its dissipation is infinite outside the cone, and the cone holds
#: at tiny-rate control points only to the solver's round-off
FLOW_TOLERANCE = 1e-8


def _admissible_flux(flux: np.ndarray, fixed: list, isochoric: np.ndarray,
                     grad_lambda: np.ndarray, cn: np.ndarray) -> tuple[np.ndarray, float]:
    """The solver's fluxes (n, 2) made kinematically admissible: the supports' values set
    exactly, then (Tresca's triangles ``isochoric``) div v = 0 at their vertices by the
    least change of the other fluxes (a minimum-norm correction: sparse normal equations,
    refined). Returns the fluxes and the largest change, relative to the largest flux."""
    from scipy import sparse
    from scipy.sparse.linalg import splu

    from ..fem.threads import limit_blas_threads
    limit_blas_threads.__wrapped__()    # (scipy's own BLAS, loaded by splu: this rank's share)
    out = flux.copy()
    free = np.ones(out.shape, bool)
    for nodes, comp, values in fixed:
        out[nodes, comp] = values
        free[nodes, comp] = False
    if len(isochoric):
        n = len(isochoric)
        rows, cols, vals = [], [], []
        for i in range(3):
            g = _basis_gradients(NODES[i], grad_lambda[isochoric])       # (n, 6, 2)
            for comp in (0, 1):
                rows.append(np.repeat(3 * np.arange(n) + i, 6))
                cols.append((2 * cn[isochoric] + comp).ravel())
                vals.append(g[..., comp].ravel())
        A = sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                     np.concatenate(cols))),
                              shape=(3 * n, out.size))
        Af = A[:, np.flatnonzero(free.ravel())]
        keep = np.flatnonzero(np.abs(Af).sum(axis=1).A1 > 0)       # (rows with free fluxes)
        Af = Af[keep]
        normal = (Af @ Af.T).tocsc()
        lu = splu(normal + sparse.identity(normal.shape[0]) * 1e-14 * normal.diagonal().max())
        flat = out.ravel()
        for _ in range(3):                     # (refined: the normal equations' round-off)
            residual = (A @ flat)[keep]
            flat[free.ravel()] -= Af.T @ lu.solve(residual)
        out = flat.reshape(out.shape)
    change = float(np.max(np.abs(out - flux))) / max(float(np.max(np.abs(out))), 1e-300)
    return out, change


def _closed_form_dissipation(G: np.ndarray, phi: np.ndarray) -> tuple[np.ndarray, float]:
    """The dissipation at unit cohesion of control points G (m, 6, 4) of triangles of
    friction angle ``phi`` (m,), in closed form: Tresca's max(rho, |G_theta|) + |G_theta|
    (rho = |(G_r - G_z, G_gamma)|) of an isochoric rate, Mohr-Coulomb's cot phi tr G of a
    rate in its flow cone tr G >= sin phi (max(|G_r + G_z|, rho) + |G_theta|). Returns it
    (m, 6) and the flow cone's largest violation, relative to the rate's size (None: no
    frictional triangle)."""
    rho = np.hypot(G[..., 0] - G[..., 1], G[..., 2])
    hoop = np.abs(G[..., 3])
    tresca = np.maximum(rho, hoop) + hoop
    trace = G[..., 0] + G[..., 1] + G[..., 3]
    s = np.sin(phi)[:, None]
    plastic = np.maximum(np.abs(G[..., 0] + G[..., 1]), rho) + hoop
    frictional = phi[:, None] > 0.0
    mc = trace / np.tan(np.where(phi > 0.0, phi, 1.0))[:, None]
    size = max(float(np.max(np.abs(G))), 1e-300)
    if not np.any(frictional):
        return tresca, None
    violation = np.where(frictional, s * plastic - trace, -np.inf)
    return np.where(frictional, mc, tresca), float(np.max(violation)) / size


def p2_nodes(tri: Triangles):
    """The quadratic triangles' nodes: (points (n, 2), cell nodes (m, 6), edge nodes (k, 3)
    of each boundary edge: its two vertices and its midpoint)."""
    nv = len(tri.points)
    pairs = np.sort(tri.cells[:, EDGES], axis=2).reshape(-1, 2)
    uniq, inverse = np.unique(pairs, axis=0, return_inverse=True)
    mids = nv + inverse.reshape(-1, 3)
    points = np.vstack([tri.points, 0.5 * (tri.points[uniq[:, 0]] + tri.points[uniq[:, 1]])])
    key = {tuple(p): i for i, p in enumerate(uniq.tolist())}
    bmid = np.array([nv + key[tuple(sorted(e))] for e in tri.edges.tolist()], dtype=np.int64)
    return points, np.column_stack([tri.cells, mids]), np.column_stack([tri.edges, bmid])


def _basis_gradients(bary: np.ndarray, grad_lambda: np.ndarray) -> np.ndarray:
    """Gradients (m, 6, 2) of the six quadratic shape functions at one barycentric point,
    from the barycentric coordinates' gradients (m, 3, 2)."""
    L = bary
    out = np.empty(grad_lambda.shape[:1] + (6, 2))
    for i in range(3):
        out[:, i] = (4 * L[i] - 1) * grad_lambda[:, i]
    for k, (i, j) in enumerate(EDGES):
        out[:, 3 + k] = 4 * (L[i] * grad_lambda[:, j] + L[j] * grad_lambda[:, i])
    return out


def _shapes(bary: np.ndarray) -> np.ndarray:
    L = bary
    return np.array([L[0] * (2 * L[0] - 1), L[1] * (2 * L[1] - 1), L[2] * (2 * L[2] - 1),
                     4 * L[0] * L[1], 4 * L[1] * L[2], 4 * L[2] * L[0]])


def _collapsed_gauss(n: int = 8):
    """A Gauss rule on the triangle from an n x n rule on the square (Duffy's collapse):
    barycentric points (n^2, 3) and weights summing to 1. Exact for polynomials of degree
    2n - 2 and accurate for the bounded B_j / r of the weights."""
    t, w = np.polynomial.legendre.leggauss(n)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    u, v = np.meshgrid(t, t, indexing="ij")
    wu, wv = np.meshgrid(w, w, indexing="ij")
    l1 = u.ravel()
    l2 = (v * (1.0 - u)).ravel()
    weights = 2.0 * (wu * wv * (1.0 - u)).ravel()
    return np.column_stack([1.0 - l1 - l2, l1, l2]), weights


def _bernstein(bary: np.ndarray) -> np.ndarray:
    """The six quadratic Bernstein polynomials at barycentric points (q, 3): (q, 6), in the
    order of NODES."""
    L = bary
    return np.column_stack([L[:, 0] ** 2, L[:, 1] ** 2, L[:, 2] ** 2, 2 * L[:, 0] * L[:, 1],
                            2 * L[:, 1] * L[:, 2], 2 * L[:, 2] * L[:, 0]])


def _shear_bound(P: ConeProgram, C: np.ndarray, dofs: np.ndarray) -> np.ndarray:
    """Two new variables (t, s) per control point (C (n, 4, 12): G's components on the dofs
    (n, 12)), t in the cone t >= |(G_r - G_z, G_gamma)|, the in-plane rates' difference
    e_1 - e_2. Returns them (n, 2)."""
    n = len(C)
    T = P.variables(2 * n).reshape(n, 2)
    # (t; G_r - G_z, G_gamma) in the cone: s = b - A x
    i = np.concatenate([3 * np.arange(n), np.repeat(3 * np.arange(n) + 1, 12),
                        np.repeat(3 * np.arange(n) + 2, 12)])
    j = np.concatenate([T[:, 0], dofs.ravel(), dofs.ravel()])
    v = np.concatenate([-np.ones(n), -(C[:, 0] - C[:, 1]).ravel(), -C[:, 2].ravel()])
    P.cones(i, j, v, np.zeros(3 * n), 3)
    return T


def _at_least_abs(P: ConeProgram, part: np.ndarray, dofs: np.ndarray,
                  var: np.ndarray) -> None:
    """var >= |part . dofs| per control point (part (n, 12), var (n,)): two rows each."""
    n = len(var)
    for sign in (1.0, -1.0):
        P.nonnegative(np.concatenate([np.repeat(np.arange(n), 12), np.arange(n)]),
                      np.concatenate([dofs.ravel(), var]),
                      np.concatenate([(sign * part).ravel(), -np.ones(n)]), np.zeros(n))


def _tresca(P: ConeProgram, C: np.ndarray, dofs: np.ndarray) -> np.ndarray:
    """Tresca's dissipation at control points C (n, 4, 12: G's components on the dofs (n,
    12)) in closed form, G isochoric (div v = 0, set per triangle by :func:`_isochoric`):
    D_1 = t + s with t >= |(G_r - G_z, G_gamma)|,
    t >= |G_theta| and s >= |G_theta| (c (|e1| + |e2| + |e3|) with e1,2 = -G_theta / 2 +- rho).
    Eight rows and two variables a point, against the three cones' thirteen and nine.
    Returns the variables (n, 2) whose sum, times the weights, is the dissipation."""
    T = _shear_bound(P, C, dofs)
    _at_least_abs(P, C[:, 3], dofs, T[:, 0])
    _at_least_abs(P, C[:, 3], dofs, T[:, 1])
    return T


def _mohr_coulomb(P: ConeProgram, C: np.ndarray, dofs: np.ndarray,
                  sine: float) -> np.ndarray:
    """Mohr-Coulomb's dissipation (phi > 0, associated) at control points C (n, 4, 12) in
    closed form: D_1 = cot phi tr G, finite where the rate lies in the flow cone
    tr G >= sin phi (|e_1| + |e_2| + |e_3|) (Chen 1975; Salencon). In axial symmetry
    |e_1| + |e_2| = max(|G_r + G_z|, |(G_r - G_z, G_gamma)|) in the plane and |e_3| = |G_theta|:
    t >= |(G_r - G_z, G_gamma)|, t >= |G_r + G_z|, s >= |G_theta| and
    tr G >= sin phi (t + s). Eight rows and two variables a point, against the three cones'
    thirteen and nine; the dissipation is then linear in the fluxes, and exact where it
    is finite (the control points lie in the cone, so G does on the whole triangle).
    ``sine`` is sin phi. Returns D_1's coefficients on the dofs (n, 12)."""
    n = len(C)
    T = _shear_bound(P, C, dofs)
    _at_least_abs(P, C[:, 0] + C[:, 1], dofs, T[:, 0])
    _at_least_abs(P, C[:, 3], dofs, T[:, 1])
    rows12 = np.repeat(np.arange(n), 12)
    trace = C[:, 0] + C[:, 1] + C[:, 3]                            # (n, 12)
    # sin phi (t + s) - tr G <= 0
    P.nonnegative(np.concatenate([rows12, np.arange(n), np.arange(n)]),
                  np.concatenate([dofs.ravel(), T[:, 0], T[:, 1]]),
                  np.concatenate([-trace.ravel(), np.full(2 * n, sine)]), np.zeros(n))
    return trace * (math.sqrt(1.0 - sine ** 2) / sine)


def _isochoric(P: ConeProgram, cells: np.ndarray, grad_lambda: np.ndarray,
               dofs: np.ndarray) -> None:
    """div v = 0 on the triangles ``cells``: div v is linear, so at their three vertices
    (three independent rows; G's volume change r div v then vanishes at every control
    point, where six rows would be dependent and slow the solver)."""
    for i in range(3):
        g = _basis_gradients(NODES[i], grad_lambda[cells])            # (n, 6, 2)
        n = len(cells)
        P.equal(np.repeat(np.arange(n), 12), dofs[cells].ravel(),
                np.concatenate([g[..., 0], g[..., 1]], axis=1).ravel(), np.zeros(n))


def _control_points(r: np.ndarray, grad_lambda: np.ndarray) -> np.ndarray:
    """The Bernstein control points of G = r^2 eps on each triangle (m, 6, 4, 12), as
    coefficients on its 12 fluxes (v_r at its six nodes, then v_z): G at the six nodes,
    then at the edges 2 G(mid) - (G_i + G_j) / 2."""
    m = len(r)
    G = np.zeros((m, 6, 4, 12))
    for k, bary in enumerate(NODES):
        g = _basis_gradients(bary, grad_lambda)                   # (m, 6, 2)
        rk = (r * bary).sum(axis=1)[:, None]
        G[:, k, 0, :6] = rk * g[..., 0]                           # r dv_r/dr
        G[:, k, 0, k] -= 1.0                                      #   - v_r
        G[:, k, 1, 6:] = rk * g[..., 1]                           # r dv_z/dz
        G[:, k, 2, :6] = rk * g[..., 1]                           # r dv_r/dz
        G[:, k, 2, 6:] = rk * g[..., 0]                           #   + r dv_z/dr
        G[:, k, 2, 6 + k] -= 1.0                                  #   - v_z
        G[:, k, 3, k] = 1.0                                       # v_r
    # Bernstein control points: the vertices' values, and 2 G(mid) - (G_i + G_j) / 2
    C = G.copy()
    for k, (i, j) in enumerate(EDGES):
        C[:, 3 + k] = 2.0 * G[:, 3 + k] - 0.5 * (G[:, i] + G[:, j])
    return C


def _weights(tri: Triangles, ground: Ground, r, z, A, scale):
    """Each control point's weight, 2 pi int c B_j / r dA (in scale a^3: r, z, A in radii),
    and which are live (m, 6): none on the axis, where v = 0 makes it vanish."""
    a, m = tri.a, len(tri.cells)
    qp, qw = _collapsed_gauss()
    rq = r @ qp.T                                                 # (m, q)
    zq = (z @ qp.T) * a
    cq = ground.cohesion(np.arange(m)[:, None], zq) / scale
    Bq = _bernstein(qp)                                           # (q, 6)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(rq > 1e-14, cq / rq, 0.0) * qw[None, :]
    w = 2.0 * math.pi * A[:, None] * (f @ Bq)                     # (m, 6)
    rC = np.column_stack([r, np.column_stack([r[:, i] + r[:, j] for i, j in EDGES]) / 2])
    on_axis_edge = np.zeros((m, 6), bool)
    for k, (i, j) in enumerate(EDGES):
        on_axis_edge[:, 3 + k] = (r[:, i] < 1e-12) & (r[:, j] < 1e-12)
    live = (rC > 1e-12) & ~on_axis_edge
    return w, live


def _fixer(P: ConeProgram, V: np.ndarray):
    """``fix(nodes, component, value)``: fluxes held (a value, or a function of the nodes),
    and the list of what it held, (nodes, component, values), to set them exactly after
    the solve."""
    fixed = []

    def fix(nodes, comp, value=0.0):
        nodes = np.unique(nodes)
        values = np.broadcast_to(value(nodes) if callable(value) else value, len(nodes))
        P.equal(np.arange(len(nodes)), V[nodes, comp], np.ones(len(nodes)), values)
        fixed.append((nodes, comp, np.asarray(values, dtype=float)))
    return fix, fixed


def _supports(fix, tri: Triangles, bn: np.ndarray, load: Loading, x: np.ndarray) -> np.ndarray:
    """The box's supports and the foundation's sides held; returns the contact's edges'
    P2 nodes (k, 3)."""
    kind = tri.kind
    for comp in (0, 1):
        fix(bn[kind == AXIS].ravel(), comp)
    # (an open box: v = 0 on it, the ground beyond at rest; the field stays admissible)
    fix(bn[kind == SIDE].ravel(), 0)
    if load.side != "roller":
        fix(bn[kind == SIDE].ravel(), 1)
    fix(bn[kind == BASE].ravel(), 1)
    if load.base != "smooth":
        fix(bn[kind == BASE].ravel(), 0)
    contact = bn[kind == CONTACT]
    if load.rough:
        fix(contact.ravel(), 0)
    # (an embedded tank's wall against the pit's side: it moves down with the foundation;
    # a plate alone leaves the pit's side free)
    pit = bn[kind == PIT_SIDE].ravel() if load.pit_contact else np.empty(0, int)
    fix(pit, 0)
    if load.rough:
        fix(pit, 1, lambda nodes: -x[nodes, 0])
    return contact


def _dissipation(P: ConeProgram, ground: Ground, live, w, C, dofs, grad_lambda,
                 three_cones: bool) -> None:
    """The dissipation's terms of the objective, per control point: in closed form (Tresca
    with div v = 0 on its triangles; Mohr-Coulomb in its flow cone), or by the three cones'
    dual (``three_cones``, a check). Each is linear in the program's variables."""
    # (each control point's dissipation is linear in the program's variables: the
    # objective's terms, kept per triangle for the refinement)
    shares = []                       # (triangles (n,), variables (n, k), coefficients (n, k))
    for phi in np.unique(ground.phi):
        sel_e, sel_j = np.nonzero(live & (ground.phi == phi)[:, None])
        ws = w[sel_e, sel_j]
        dsel = dofs[sel_e]                                        # (n, 12)
        if phi == 0.0 and not three_cones:
            _isochoric(P, np.flatnonzero(ground.phi == 0.0), grad_lambda, dofs)
            T = _tresca(P, C[sel_e, sel_j], dsel)
            shares.append((sel_e, T, np.repeat(ws[:, None], 2, axis=1)))
            continue
        if not three_cones:
            coef = _mohr_coulomb(P, C[sel_e, sel_j], dsel, math.sin(phi))
            shares.append((sel_e, dsel, ws[:, None] * coef))
            continue
        cones = mohr_coulomb_cones(float(phi))
        n = len(sel_e)
        Y = P.variables(9 * n).reshape(n, 3, 3)                   # (point, cone, component)
        P.cones(np.arange(9 * n), Y.ravel(), -np.ones(9 * n), np.zeros(9 * n), 3)
        # sum_k M_k^T y_k + C = 0: 4 rows per control point
        M = np.stack([cones.rows(k) for k in range(3)])            # (3, 3, 4)
        Csel = C[sel_e, sel_j]                                    # (n, 4, 12)
        for comp in range(4):
            rows = np.repeat(np.arange(n), 9 + 12)
            cols = np.column_stack([Y.reshape(n, 9), dsel]).ravel()
            vals = np.column_stack([np.broadcast_to(M[:, :, comp].ravel(), (n, 9)),
                                    Csel[:, comp, :]]).ravel()
            P.equal(rows, cols, vals, np.zeros(n))
        shares.append((sel_e, Y[:, :, 0], ws[:, None] * cones.beta[None, :]))
    for _, variables, coefficients in shares:
        P.minimise(variables, coefficients)


def _velocity(flux, x, r, grad_lambda, cn) -> np.ndarray:
    """The velocity u = v / r at the P2 nodes (x in radii), for drawing; on the axis its
    limit dv/dr there, the mean over the triangles at it (the limit depends on the
    direction where v's gradient has a z part)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        vel = np.where(x[:, :1] > 1e-12, flux / x[:, :1], 0.0)
    total, count = np.zeros((len(x), 2)), np.zeros(len(x))
    for i in range(3):
        at = np.flatnonzero(r[:, i] < 1e-12)
        if not len(at):
            continue
        g = _basis_gradients(NODES[i], grad_lambda[at])[..., 0]            # (n, 6) d/dr
        total_i = np.einsum("nk,nkc->nc", g, flux[cn[at]])
        np.add.at(total, cn[at, i], total_i)
        np.add.at(count, cn[at, i], 1.0)
    axis = count > 0
    vel[axis] = total[axis] / count[axis, None]
    return vel


def upper_bound(tri: Triangles, ground: Ground, load: Loading, scale: float,
                three_cones: bool = False) -> UpperBound:
    """The least factor on ``load.variable`` a kinematically admissible field allows.
    ``scale`` (Pa) makes the stresses of order one. Tresca's and Mohr-Coulomb's
    dissipations are taken in closed form (``three_cones``: by the three cones' dual
    instead, a check)."""
    a = tri.a
    points, cn, bn = p2_nodes(tri)
    x = points / a
    P = ConeProgram()
    V = P.variables(2 * len(x)).reshape(-1, 2)                # v = r u per node
    p = x[tri.cells]
    r, z = p[..., 0], p[..., 1]
    twoA = 2.0 * tri.area / a ** 2
    A = twoA / 2.0
    b = np.roll(z, -1, axis=1) - np.roll(z, -2, axis=1)
    c = np.roll(r, -2, axis=1) - np.roll(r, -1, axis=1)
    grad_lambda = np.stack([b, c], axis=2) / twoA[:, None, None]      # (m, 3, 2)
    # ---- G = r^2 eps at the six nodes, as coefficients on the element's 12 fluxes ----
    dofs = np.concatenate([V[cn, 0], V[cn, 1]], axis=1)          # (m, 12): v_r x6, v_z x6
    C = _control_points(r, grad_lambda)
    w, live = _weights(tri, ground, r, z, A, scale)
    _dissipation(P, ground, live, w, C, dofs, grad_lambda, three_cones)
    # ---- the soil's weight: + 2 pi int gamma v_z dA (in scale a^3) ----
    # (the objective's terms linear in the fluxes, kept to recompute it: (variables, coefs))
    linear = []
    qp6, qw6 = QUADRATURE
    for bary, wq in zip(qp6, qw6):
        N = _shapes(bary)
        coef = 2.0 * math.pi * wq * A * ground.gamma * a / scale              # (m,)
        linear.append((V[cn, 1].ravel(), (coef[:, None] * N[None, :]).ravel()))
    # ---- supports and the foundation ----
    fix, fixed = _fixer(P, V)
    contact = _supports(fix, tri, bn, load, x)
    norm = scale * a ** 2
    if load.rigid:
        fix(contact.ravel(), 1, lambda nodes: -x[nodes, 0])       # (u_z = -1)
        held_work = load.held / norm
    else:
        # the loads' work on the contact, 2 pi q int (-v_z) dr (Simpson: exact for P2): the
        # variable one's normalised to 1, the held one's in the objective
        L = np.abs(x[contact[:, 1], 0] - x[contact[:, 0], 0])
        simpson = 2.0 * math.pi * L[:, None] / 6.0 * np.array([1.0, 1.0, 4.0])[None, :]
        qv, qh = load.pressures(0.5 * (points[contact[:, 0], 0] + points[contact[:, 1], 0]), a)
        q = (qv / scale)[:, None]                                 # (in scale: work in scale a^3)
        P.equal(np.zeros(contact.size, int), V[contact, 1].ravel(), (-q * simpson).ravel(),
                [1.0])
        linear.append((V[contact, 1].ravel(), ((qh / scale)[:, None] * simpson).ravel()))
        held_work = 0.0
    for variables, coefficients in linear:
        P.minimise(variables, coefficients)
    sol = P.solve("the upper bound")
    # ---- the bound recomputed from the field, not the solver's objective ----
    flux, projected = _admissible_flux(sol.x[V], fixed, np.flatnonzero(ground.phi == 0.0),
                                       grad_lambda, cn)
    values = flux.ravel()                       # (V's variables are consecutive)

    def value_of(variables):
        return values[np.asarray(variables) - V[0, 0]]
    d1, outside = _closed_form_dissipation(np.einsum("mjcd,md->mjc", C, value_of(dofs)), ground.phi)
    cost = (np.where(live, w * d1, 0.0)).sum(axis=1)
    external = sum(float(value_of(j) @ v) for j, v in linear)
    if load.rigid:
        work = load.variable / norm
    else:
        work = float(value_of(V[contact, 1].ravel()) @ (-q * simpson).ravel())
    if not work > 0.0:
        raise ProgramError(f"the upper bound: the conic solver's velocity field (status "
                           f"{sol.status}) does no work against the variable loads: no valid "
                           f"upper bound on this mesh")
    factor = (cost.sum() + external - held_work) / work
    check = {**sol.record(), "solver_factor": (sol.objective - held_work) / work,
             "projection": projected, "flow_violation": outside}
    if not (np.isfinite(factor) and (outside is None or outside <= FLOW_TOLERANCE)):
        raise ProgramError(
            f"the upper bound: the conic solver's velocity field (status {sol.status}) is not "
            f"kinematically admissible (flow rule violated by {outside:.2e} of its rate after "
            f"its supports were set exactly): no valid upper bound on this mesh")
    control = np.einsum("mjcd,md->mjc", C, value_of(dofs)) * a
    return UpperBound(factor=float(factor), velocity=_velocity(flux, x, r, grad_lambda, cn),
                      nodes=points,
                      dissipation=cost * norm, control=control, check=check,
                      seconds=sol.seconds, iterations=sol.iterations, variables=sol.variables)
