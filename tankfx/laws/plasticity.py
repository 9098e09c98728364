"""Perfect plasticity of Mohr-Coulomb (Tresca at phi = 0) with a Rankine tension cut-off, in
principal stresses: the stress update of an axisymmetric point and its consistent tangent,
vectorised over all points (no loop per point).

Conventions: tension positive. A stress or strain is a Mandel vector (rr, zz, sqrt 2 rz,
theta), so that sigma : eps is a dot product and the tangent a symmetric 4 x 4 matrix where
the flow is associated. sigma_theta is a principal stress; the in-plane pair comes from the
2 x 2 (r, z) block.

With sigma_1 >= sigma_2 >= sigma_3 the trial's sorted principal stresses, s = sin phi,
s_psi = sin psi, the yield planes are (Clausen, Damkilde & Andersen, IJNME 66, 2006: the
return to a plane, an edge or the apex is closed form for planes)

    f_A = (sigma_1 - sigma_3) + (sigma_1 + sigma_3) s - 2 c cos phi <= 0     (the main plane)
    f_B = (sigma_2 - sigma_3) + (sigma_2 + sigma_3) s - 2 c cos phi <= 0     (edge sigma_1 = sigma_2)
    f_C = (sigma_1 - sigma_2) + (sigma_1 + sigma_2) s - 2 c cos phi <= 0     (edge sigma_2 = sigma_3)
    f_Ti = sigma_i - t <= 0,  i = 1, 2, 3                                    (tension cut-off)

with the plastic potentials of the dilation angle psi on the Mohr-Coulomb planes (the same
form, s_psi for s) and associated flow on the cut-off. A return with the active planes J is
sigma = sigma_tr - D N_J dgamma, with a_J . sigma = b_J: a |J| x |J| linear system per point.
Every candidate set (the plane, the two edges, the cut-off's planes, edges and corners) is
solved for every point, and each point takes the first (smallest) set whose multipliers are
non-negative and whose stress violates no plane. The KKT conditions decide it, not a test on
which sector the trial lies in: on a sector's boundary two sets give the same stress, so
round-off there cannot pick a wrong return.

Past the apex. Where no cut-off is given, the cut-off sits at the apex itself, t = c cot phi:
the cone lies wholly in sigma_1 <= c cot phi, so its strength is unchanged, but the apex is
now reached by a flow (the cut-off's, associated), also where psi < phi, when the six
Mohr-Coulomb potentials' flows cannot reach it (no non-negative multipliers take a trial
there). Without it such a trial could only be set to the apex by hand, its plastic strain
no flow's. Every trial then has a return whose multipliers are non-negative: of 20,000
random trial states about the apex (c 2 kPa and 0, phi 25, psi 0 and 25, cut-offs 0 and the
apex) none is left without one once the corner (A, B, T1) (sigma_1 = sigma_2 = t, sigma_3 on
A) is among the candidates. At a corner of three planes the stress is fixed and the
return's derivative is zero (perfect plasticity): its tangent is held at APEX_STIFFNESS D,
a millionth of the elastic one, so that a cell of such points leaves the matrix regular.

The consistent tangent of an isotropic function of the trial stress (de Souza Neto, Peric &
Owen, Computational Methods for Plasticity, 2008, App. A):

    C = [ sum_ab P_ab E_a (x) E_b + (sigma_I - sigma_II) / (sigma_tr_I - sigma_tr_II) S ] D

with P = I - D N (A^T D N)^-1 A^T the principal return's derivative, E_a the eigen
projections, S the in-plane spin projector and D the elastic matrix.
"""
from __future__ import annotations

import numpy as np

from .mohr_coulomb import circle_strength

SQRT2 = np.sqrt(2.0)
#: the Mandel vector of the identity
IDENTITY = np.array([1.0, 1.0, 0.0, 1.0])

#: the candidate sets of active planes (indices into the planes A, B, C, T1, T2, T3), in
#: the order they are tried
_A, _B, _C, _T1, _T2, _T3 = range(6)
CANDIDATES = ((_A,), (_T1,), (_A, _B), (_A, _C), (_A, _T1), (_T1, _T2), (_A, _C, _T1),
              (_A, _B, _T1), (_A, _T1, _T2), (_T1, _T2, _T3))
#: the tangent at a corner of three planes (the apex among them), relative to the elastic
#: one (its own is zero)
APEX_STIFFNESS = 1e-6

#: a trial is outside the surface, and a return's multipliers and planes are taken as met,
#: at this share of the trial's largest stress
YIELD_TOLERANCE = 1e-10

#: the return's code per point: -1 elastic, k the k-th candidate; APEX (len(CANDIDATES)):
#: none of them held (not met in any state measured: a guard)
ELASTIC, APEX = -1, len(CANDIDATES)


def lame(E, nu):
    """Lame's constants (lambda, G)."""
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def elastic_matrix(E, nu) -> np.ndarray:
    """D (N x 4 x 4, Mandel) of isotropic elasticity: lambda m m^T + 2 G I."""
    lmbda, G = lame(np.atleast_1d(E), np.atleast_1d(nu))
    D = lmbda[:, None, None] * np.outer(IDENTITY, IDENTITY) + 2.0 * G[:, None, None] * np.eye(4)
    return D


def principal(s) -> tuple[np.ndarray, np.ndarray]:
    """The principal values (N x 3: in-plane I >= II, then theta) of Mandel vectors ``s``
    (N x 4) and their eigen projections (N x 3 x 4, Mandel)."""
    rr, zz, rz, tt = s[:, 0], s[:, 1], s[:, 2] / SQRT2, s[:, 3]
    p, d = 0.5 * (rr + zz), 0.5 * (rr - zz)
    R = np.hypot(d, rz)
    # the in-plane eigenvector of the larger value: (cos a, sin a), tan 2a = rz / d
    a = 0.5 * np.arctan2(rz, d)
    c, s_ = np.cos(a), np.sin(a)
    E = np.zeros((len(s), 3, 4))
    E[:, 0] = np.column_stack([c * c, s_ * s_, SQRT2 * c * s_, 0.0 * c])
    E[:, 1] = np.column_stack([s_ * s_, c * c, -SQRT2 * c * s_, 0.0 * c])
    E[:, 2, 3] = 1.0
    return np.column_stack([p + R, p - R, tt]), E


def _planes(sin_phi, sin_psi, c, cos_phi, t):
    """The planes' normals a (N x 6 x 3), flows n (N x 6 x 3) and right-hand sides b (N x 6)
    in sorted principal space."""
    n = len(sin_phi)
    a = np.zeros((n, 6, 3))
    f = np.zeros((n, 6, 3))
    for k, (i, j) in enumerate(((0, 2), (1, 2), (0, 1))):     # A, B, C: max i, min j
        a[:, k, i], a[:, k, j] = 1.0 + sin_phi, -(1.0 - sin_phi)
        f[:, k, i], f[:, k, j] = 1.0 + sin_psi, -(1.0 - sin_psi)
    for i in range(3):
        a[:, 3 + i, i] = f[:, 3 + i, i] = 1.0
    b = np.empty((n, 6))
    b[:, :3] = (2.0 * c * cos_phi)[:, None]
    b[:, 3:] = t[:, None]
    return a, f, b


def principal_return(sigma_tr, E, nu, cohesion, sin_phi, sin_psi, tension=None):
    """The return of sorted principal trial stresses ``sigma_tr`` (N x 3, descending, tension
    positive) to the Mohr-Coulomb planes and the tension cut-off ``tension`` (Pa, per point;
    None or inf: none). Returns (sigma (N x 3), P = d sigma / d sigma_tr (N x 3 x 3), code
    (N: ELASTIC, the index of the candidate set, or APEX))."""
    n = len(sigma_tr)
    E, nu, c, sp, sq = (np.broadcast_to(np.asarray(v, dtype=float), (n,))
                        for v in (E, nu, cohesion, sin_phi, sin_psi))
    t = np.full(n, np.inf) if tension is None else np.broadcast_to(
        np.asarray(tension, dtype=float), (n,))
    cos_phi = np.sqrt(1.0 - sp * sp)
    lmbda, G = lame(E, nu)
    D = lmbda[:, None, None] * np.ones((3, 3)) + 2.0 * G[:, None, None] * np.eye(3)
    scale = np.max(np.abs(sigma_tr), axis=1) + c + 1.0
    tol = YIELD_TOLERANCE * scale
    # (no cut-off, or one beyond the apex: at the apex, whose strength is the cone's own
    # and whose flow reaches the apex; Tresca has none)
    apex_t = np.where(sp > 0.0, c * cos_phi / np.maximum(sp, 1e-300), np.inf)
    t = np.minimum(t, apex_t)
    a, f, b = _planes(sp, sq, c, cos_phi, t)
    has_cut = np.isfinite(t)
    phi_tr = (a @ sigma_tr[..., None])[..., 0] - b
    code = np.full(n, ELASTIC)
    sigma = sigma_tr.copy()
    P = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    todo = np.any(phi_tr > tol[:, None], axis=1)
    Df = f @ D                                           # D n_k, per plane (D symmetric)
    for k, J in enumerate(CANDIDATES):
        if not todo.any():
            break
        J = list(J)
        if any(j >= 3 for j in J):
            idx = np.flatnonzero(todo & has_cut)
        else:
            idx = np.flatnonzero(todo)
        if len(idx) == 0:
            continue
        aJ, DfJ = a[idx][:, J], Df[idx][:, J]              # (m, k, 3)
        M = aJ @ np.swapaxes(DfJ, 1, 2)                    # a_k . D n_l
        det = np.linalg.det(M)
        ok = np.abs(det) > 1e-12 * np.abs(np.einsum("mkk->m", M)) ** len(J)
        idx, aJ, DfJ, M = idx[ok], aJ[ok], DfJ[ok], M[ok]
        if len(idx) == 0:
            continue
        dgamma = np.linalg.solve(M, phi_tr[idx][:, J][..., None])[..., 0]
        s = sigma_tr[idx] - (dgamma[:, None, :] @ DfJ)[:, 0]
        residual = (a[idx] @ s[..., None])[..., 0] - b[idx]
        valid = np.all(dgamma * (2.0 * G[idx, None]) >= -tol[idx, None], axis=1) & \
            np.all(residual <= tol[idx, None], axis=1)
        hit = idx[valid]
        sigma[hit] = s[valid]
        # P = I - D N (A^T D N)^-1 A^T
        P[hit] = np.eye(3) - np.swapaxes(DfJ[valid], 1, 2) @ np.linalg.inv(M[valid]) @ aJ[valid]
        if len(J) == 3:
            # (a corner: the stress fixed, P zero; see APEX_STIFFNESS)
            P[hit] = APEX_STIFFNESS * np.eye(3)
        code[hit] = k
        todo[hit] = False
    if todo.any():
        # (a guard: no candidate held. The closest corner of the cut-off, (t, t, t), with
        # the corner's tangent)
        idx = np.flatnonzero(todo)
        sigma[idx] = np.where(np.isfinite(t[idx]), t[idx], 0.0)[:, None]
        P[idx] = APEX_STIFFNESS * np.eye(3)
        code[idx] = APEX
    return sigma, P, code



def compliance(E, nu) -> np.ndarray:
    """D^-1 (N x 4 x 4, Mandel): I / (2 G) - lambda / (2 G (3 lambda + 2 G)) m m^T."""
    lmbda, G = lame(np.atleast_1d(E), np.atleast_1d(nu))
    return (np.eye(4) / (2.0 * G[:, None, None])
            - (lmbda / (2.0 * G * (3.0 * lmbda + 2.0 * G)))[:, None, None]
            * np.outer(IDENTITY, IDENTITY))


def stress_update(d_eps, sigma_n, E, nu, cohesion, sin_phi, sin_psi, tension=None, D=None,
                  reference=None):
    """The stress after a strain increment ``d_eps`` from the committed stress ``sigma_n``
    (Mandel, N x 4), elastic predictor and return: (sigma (N x 4), the consistent tangent
    C = d sigma / d eps (N x 4 x 4), the return's code (N) and the plastic strain increment
    D^-1 (sigma_tr - sigma) (N x 4)). The material constants are floats or per point;
    ``D``, the elastic matrices (N x 4 x 4), where the caller keeps them. Only the points
    whose trial stress leaves the yield surface are returned; the others keep the trial
    and the elastic tangent.

    With a ``reference`` stress (N x 4: the ground at rest), ``sigma_n`` and the stress
    returned are changes from it: an elastic point's change is then D d_eps added to its
    change, exact, where its total (a deep point's, of gigapascals in a half-space of
    kilometres) would carry the reference's round-off into the out-of-balance force."""
    n = len(d_eps)
    E, nu, c, sp, sq = (np.broadcast_to(np.asarray(v, dtype=float), (n,))
                        for v in (E, nu, cohesion, sin_phi, sin_psi))
    t = np.full(n, np.inf) if tension is None else np.broadcast_to(
        np.asarray(tension, dtype=float), (n,))
    if D is None:
        D = elastic_matrix(E, nu)
    change = sigma_n + (D @ d_eps[..., None])[..., 0]
    s_tr = change if reference is None else reference + change
    sigma, C = change.copy(), D.copy()
    code = np.full(n, ELASTIC)
    d_eps_p = np.zeros_like(s_tr)
    # (which points leave the surface: the largest Mohr circle and the largest stress)
    vals, proj = principal(s_tr)
    top, bottom = vals.max(axis=1), vals.min(axis=1)
    f = (top - bottom) - 2.0 * circle_strength(0.5 * (top + bottom), c, sp)
    scale = np.max(np.abs(vals), axis=1) + c + 1.0
    out = np.flatnonzero((f > YIELD_TOLERANCE * scale) | (top > t + YIELD_TOLERANCE * scale))
    if len(out) == 0:
        return sigma, C, code, d_eps_p
    vals, proj, Dp = vals[out], proj[out], D[out]
    order = np.argsort(-vals, axis=1, kind="stable")
    back = np.argsort(order, axis=1)
    s_sorted, P_sorted, code_p = principal_return(
        np.take_along_axis(vals, order, axis=1), E[out], nu[out], c[out], sp[out], sq[out],
        t[out])
    s_p = np.take_along_axis(s_sorted, back, axis=1)
    # P in the (I, II, theta) order: P[a, b] = P_sorted[back[a], back[b]]
    P = np.take_along_axis(np.take_along_axis(P_sorted, back[:, :, None], axis=1),
                           back[:, None, :], axis=2)
    projT = np.swapaxes(proj, 1, 2)
    sigma_p = (projT @ s_p[..., None])[..., 0]
    T = projT @ P @ proj
    # the in-plane eigenvectors' turn: (sigma_I - sigma_II) / (sigma_tr_I - sigma_tr_II),
    # whose limit at equal values is d sigma_I / d sigma_tr_I - d sigma_I / d sigma_tr_II
    split = vals[:, 0] - vals[:, 1]
    apart = split > 1e-9 * (np.max(np.abs(vals), axis=1) + 1.0)
    ratio = np.where(apart, (s_p[:, 0] - s_p[:, 1]) / np.where(apart, split, 1.0),
                     P[:, 0, 0] - P[:, 0, 1])
    in_plane = proj[:, :2]
    S = np.diag([1.0, 1.0, 1.0, 0.0]) - np.swapaxes(in_plane, 1, 2) @ in_plane
    C[out] = (T + ratio[:, None, None] * S) @ Dp
    code[out] = code_p
    plastic = out[code_p != ELASTIC]
    # (a point whose surface test and return disagree by round-off stays elastic)
    C[out[code_p == ELASTIC]] = Dp[code_p == ELASTIC]
    sigma[plastic] = sigma_p[code_p != ELASTIC] - (0.0 if reference is None
                                                   else reference[plastic])
    d_eps_p[plastic] = (compliance(E[plastic], nu[plastic])
                        @ (change[plastic] - sigma[plastic])[..., None])[..., 0]
    return sigma, C, code, d_eps_p


def mobilised_strength(sigma, cohesion, sin_phi) -> np.ndarray:
    """tau / tau_f per point (Mandel stresses, N x 4): Mohr's largest circle's radius over
    the Mohr-Coulomb radius at its centre, (sigma_1 - sigma_3) / 2 over c cos phi -
    (sigma_1 + sigma_3) / 2 sin phi (tension positive); 1 on the yield surface."""
    vals = np.sort(principal(sigma)[0], axis=1)
    s1, s3 = vals[:, 2], vals[:, 0]
    strength = circle_strength(0.5 * (s1 + s3), cohesion, sin_phi)
    # (at the apex both vanish: a point there is at its strength)
    tiny = 1e-9 * (np.abs(vals).max(axis=1) + cohesion + 1.0)
    return np.where(strength > tiny, 0.5 * (s1 - s3) / np.maximum(strength, tiny), 1.0)
