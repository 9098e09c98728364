"""The lower bound: a statically admissible stress field of linear triangles, the largest
load factor it carries (Sloan 1988's elements; axial symmetry after Tang et al.).

In axial symmetry equilibrium has 1/r terms, and a linear stress cannot satisfy it
pointwise. The unknowns are therefore the stresses times r, S = r (sigma_r, sigma_z,
tau_rz), linear on each triangle, and sigma_theta, constant on each. Multiplied by r, the
two equations of equilibrium become exact for them:

    d(S_r)/dr + d(T)/dz - sigma_theta = 0,     d(T)/dr + d(S_z)/dz = 0.

The soil's weight is carried by the hydrostatic field sigma0 = gamma z I (z <= 0, tension
positive), which is in equilibrium with it and free of traction at the surface; S is what is
added to it.

Across every edge the traction r t = S . n is continuous, at both of its vertices. On the free
surface it is zero there. The box's side and base are either the ground's own supports (a given ``[domain]``): a
fixed one takes any traction, a smooth one (a roller) no shear; or open, the ground going
on beyond them. Beyond an open box the field is continued to infinity in closed form, with
no shear on the box (T = 0 there) and any normal traction the box's field puts on it:

- beyond the side r = R, Lame's ring sigma_r = -sigma_theta = s(z) (R / r)^2,
  sigma_z = tau = 0, s(z) the side's sigma_r. With tau = sigma_z = 0 it is in equilibrium
  for any s(z), free at the surface, and its layers at different z may jump;
- under the base z = -D, the column of the z-independent field sigma_z(r) (the base's),
  tau = 0 and r sigma_r = S_c(r) linear on each of the base's edges with
  sigma_theta = dS_c/dr (its own unknowns): in equilibrium for any such profile; beyond
  r = R below the base, the ring again, with s = sigma_r of the column at R.

Both are admissible if the cones hold at the box's boundary vertices (the ring) and along
the column at z = -D and at each deeper stratum's top (:class:`FarField`): the excess is
convex along each edge or constant in z, the ground at rest admissible, and the yield
margin affine in z within a stratum and growing with depth. The field in the whole
half-space is then statically admissible, and the bound is the half-space's. Under a smooth foundation T = 0. The load is
the foundation's resultant, -2 pi int S_z dr.

The yield condition, multiplied by r > 0, is a cone in (S, r sigma_theta)
(:mod:`tankfx.laws.limit_cones`). Its left side is convex along the triangle and its right
side affine, except for the bilinear r z of a cohesion that grows with depth and of the
weight with friction. It is imposed at the three vertices. The bilinear term's P1
interpolation error, at most h^2 / 2 (h the longest edge), is subtracted as a margin. The
field is then admissible at every point, and the bound is rigorous. At r = 0 the cones force
S = 0, the stress bounded on the axis.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..laws.limit_cones import mohr_coulomb_cones
from .program import ConeProgram, ProgramError
from .triangles import BASE, CONTACT, PIT_SIDE, SIDE, SURFACE, Triangles


#: a lower bound's field counts where equilibrium and continuity hold to this share of their
#: largest term, and the yield condition to this share of the strength scale (round-off of
#: the interior-point solution: measured 1e-12 and 2e-9)
EQUILIBRIUM_TOLERANCE = 1e-8
YIELD_TOLERANCE = 1e-7


@dataclass(frozen=True)
class FarField:
    """The soil under an open base, where the lower bound's closed-form column (and the
    ring beyond it) must be admissible: ``rows`` (z, c, phi, gamma), the heights (m,
    z <= -D) of the base and of each deeper stratum's top, the cohesion there (Pa), the
    friction angle (radians) and the unit weight. The excess stress there is constant in z
    and the yield margin grows with depth within a stratum (non-negative cohesion
    gradient, gamma z sin phi), so its top suffices."""

    rows: np.ndarray


@dataclass(frozen=True)
class Ground:
    """What a bound needs of the soil, per triangle (m of them), SI units: its cohesion as a
    line in z, ``c_top`` (m,) at z = 0 and ``dc_dz`` (m,) its change with z (negative where
    it grows with depth), the friction angle ``phi`` (m,, radians) and the unit weight
    ``gamma`` (m,); ``far`` the soil beyond an open box."""

    c_top: np.ndarray
    dc_dz: np.ndarray
    phi: np.ndarray
    gamma: np.ndarray
    far: FarField | None = None

    def cohesion(self, e: np.ndarray, z: np.ndarray) -> np.ndarray:
        """The cohesion at heights z (m) in triangles e (linear within a stratum)."""
        return self.c_top[e] + self.dc_dz[e] * z


@dataclass(frozen=True)
class Loading:
    """The foundation's load, SI: the variable load's resultant ``variable`` (N, downward),
    the held one ``held`` (N), ``rigid`` (a rigid foundation: only the resultant is given;
    else a uniform pressure on the contact), ``rough`` (its contact takes shear), and the
    box's ``side`` ("fixed", "roller" or "open": the ground goes on) and ``base`` ("rough",
    "smooth" or "open")."""

    variable: float
    held: float
    rigid: bool
    rough: bool
    side: str = "fixed"
    base: str = "rough"
    #: an embedded foundation's pit side: in contact with it (a tank's wall there), or free
    pit_contact: bool = False
    #: a flexible load's pressures, bands (r0, r1, q_variable, q_held) (m, Pa) on the
    #: surface under the foundation; none: ``variable`` and ``held`` uniform on r <= a
    bands: tuple = ()

    def pressures(self, r: np.ndarray, a: float) -> tuple[np.ndarray, np.ndarray]:
        """A flexible load's variable and held pressures (Pa) at radii ``r`` (m)."""
        bands = self.bands or ((0.0, a, self.variable / (math.pi * a ** 2),
                                self.held / (math.pi * a ** 2)),)
        qv, qh = np.zeros_like(r), np.zeros_like(r)
        for r0, r1, v, h in bands:
            inside = (r > r0) & (r < r1)
            qv += np.where(inside, v, 0.0)
            qh += np.where(inside, h, 0.0)
        return qv, qh


@dataclass(frozen=True)
class LowerBound:
    factor: float
    stress: np.ndarray          # (m, 3, 4): sigma_r, sigma_z, tau, sigma_theta at the vertices, Pa
    S: np.ndarray               # (m, 3, 3): r (sigma_r, sigma_z, tau) beyond sigma0 at the vertices, Pa m
    sigma_theta: np.ndarray     # (m,): sigma_theta beyond sigma0, Pa
    equilibrium_residual: float  # the largest relative residual of equilibrium and continuity
    yield_violation: float       # the largest violation of the yield cones over the checks, Pa
    far_margin: dict             # the far field's least yield margin / scale, side and base
    check: dict                  # the solver's status, iterations, duality gap and residuals
    seconds: float
    iterations: int
    variables: int


def lower_bound(tri: Triangles, ground: Ground, load: Loading, scale: float) -> LowerBound:
    """The largest factor on ``load.variable`` a statically admissible field carries.
    ``scale`` (Pa) makes the stresses of order one (the cohesion under the foundation)."""
    a, m = tri.a, len(tri.cells)
    x = tri.points / a                                  # (lengths in radii)
    P = ConeProgram()
    S = P.variables(9 * m).reshape(m, 3, 3)             # S_r, S_z, T at each vertex
    st = P.variables(m)                                 # sigma_theta
    F = P.variables(1)[0]
    p = x[tri.cells]                                    # (m, 3, 2)
    r, z = p[..., 0], p[..., 1]
    # gradients of the linear shape functions times 2A: b_i = z_j - z_k, c_i = r_k - r_j
    b = np.roll(z, -1, axis=1) - np.roll(z, -2, axis=1)
    c = np.roll(r, -2, axis=1) - np.roll(r, -1, axis=1)
    twoA = 2.0 * tri.area / a ** 2
    _equilibrium(P, S, st, b, c, twoA)
    local = _local_index(tri.cells)
    _continuity(P, tri, S, x, local)
    # ---- boundaries ----
    owner = tri.owner
    # (an embedded foundation's pit: its side a contact with the tank's wall, else free)
    free = (tri.kind == SURFACE) | ((tri.kind == PIT_SIDE) & (not load.pit_contact))
    contact = tri.kind == CONTACT
    # (a smooth support takes no shear: T on the side (n = e_r) and on the base (n = -e_z);
    # nor does an open one: the far field has none)
    no_shear = ((tri.kind == SIDE) & (load.side != "fixed")) | \
        ((tri.kind == BASE) & (load.base != "rough")) | \
        ((tri.kind == PIT_SIDE) & (not load.rough) & load.pit_contact)
    bt = x[tri.edges[:, 1]] - x[tri.edges[:, 0]]
    bn = np.column_stack([bt[:, 1], -bt[:, 0]])
    for v in (0, 1):
        iv = local(owner, tri.edges[:, v])
        # (free: the whole traction zero, so S . n = -r sigma0 . n, sigma0 = gamma z I: zero
        # on the surface, not on a free pit side below it)
        sel = np.flatnonzero(free)
        rv, zv = x[tri.edges[sel, v], 0], x[tri.edges[sel, v], 1]
        at_rest = ground.gamma[owner[sel]] * a / scale * rv * zv          # r sigma0, in scale a
        for k, comp in enumerate(((0, 2), (2, 1))):
            rows = np.repeat(np.arange(len(sel)), 2)
            cols = np.column_stack([S[owner[sel], iv[sel], comp[0]],
                                    S[owner[sel], iv[sel], comp[1]]]).ravel()
            vals = bn[sel].ravel()
            P.equal(rows, cols, vals, -at_rest * bn[sel, k])
        sel = np.flatnonzero(no_shear)
        P.equal(np.arange(len(sel)), S[owner[sel], iv[sel], 2], np.ones(len(sel)),
                np.zeros(len(sel)))
        sel = np.flatnonzero(contact)
        if not load.rough:                  # (smooth: no shear under the foundation)
            P.equal(np.arange(len(sel)), S[owner[sel], iv[sel], 2], np.ones(len(sel)),
                    np.zeros(len(sel)))
        if not load.rigid:
            # (pressures F q + q_held on the pit's bottom, where the ground at rest's sigma0
            # is -gamma d: S_z = -r (F q + q_held - gamma d))
            qv, qh = load.pressures(0.5 * (tri.points[tri.edges[sel, 0], 0]
                                           + tri.points[tri.edges[sel, 1], 0]), a)
            qh = qh - ground.gamma[owner[sel]] * tri.embedment
            rv = x[tri.edges[sel, v], 0]
            P.equal(np.repeat(np.arange(len(sel)), 2),
                    np.column_stack([S[owner[sel], iv[sel], 1], np.full(len(sel), F)]).ravel(),
                    np.column_stack([np.ones(len(sel)), rv * qv / scale]).ravel(),
                    -rv * qh / scale)
    if load.rigid:
        _resultant(P, tri, ground, load, S, F, x, bt, local, scale)
    # ---- yield at every vertex: three cones; on the axis they say S = 0, set so (a cone
    # with an empty interior stalls an interior-point solver) ----
    h2 = (tri.h / a) ** 2
    on_axis = r < 1e-12
    axis = S[on_axis].ravel()
    P.equal(np.arange(len(axis)), axis, np.ones(len(axis)), np.zeros(len(axis)))
    for phi in np.unique(ground.phi):
        sel = np.flatnonzero(ground.phi == phi)
        cones = mohr_coulomb_cones(float(phi))
        for k in range(3):
            _yield_cone(P, cones, k, sel, S, st, r, z, h2, ground, a, scale, ~on_axis[sel])
    far_points = _far_field(P, tri, ground, load, S, x, scale)
    P.minimise([F], [-1.0])
    sol = P.solve("the lower bound")
    stress = _stresses(sol.x, S, st, r, z, ground, a, scale)
    out = LowerBound(factor=float(sol.x[F]), stress=stress, S=sol.x[S] * scale * a,
                     sigma_theta=sol.x[st] * scale,
                     equilibrium_residual=P.equality_residual(sol.x),
                     yield_violation=_violation(sol.x, S, st, r, z, tri, ground, a, scale),
                     far_margin=_far_margin(sol.x, far_points, scale),
                     seconds=sol.seconds, iterations=sol.iterations, variables=sol.variables,
                     check=sol.record())
    # (the field, not the solver's word, decides: a solve stopped early counts where its
    # field is admissible)
    if not (out.equilibrium_residual <= EQUILIBRIUM_TOLERANCE
            and out.yield_violation <= YIELD_TOLERANCE * scale and math.isfinite(out.factor)):
        raise ProgramError(
            f"the lower bound: the conic solver's stress field (status {sol.status}) is not "
            f"statically admissible: equilibrium off by {out.equilibrium_residual:.2e} of its "
            f"terms, the yield condition by {out.yield_violation:.3g} Pa: no valid lower bound "
            f"on this mesh")
    return out


def _resultant(P: ConeProgram, tri: Triangles, ground: Ground, load: Loading, S, F, x, bt,
               local, scale) -> None:
    """A rigid foundation's resultant, upward on it (in scale a^2): under it -2 pi int S_z dr,
    and the ground at rest's gamma d there if it is embedded d deep; on the pit's side (a
    wall there) 2 pi int T dz; = F V + H."""
    a, owner = tri.a, tri.owner
    sel = np.flatnonzero(tri.kind == CONTACT)
    side = np.flatnonzero(tri.kind == PIT_SIDE) if load.pit_contact else np.empty(0, int)
    cols, vals = [], []
    for v in (0, 1):
        iv = local(owner[sel], tri.edges[sel, v])
        cols.append(S[owner[sel], iv, 1])
        vals.append(-math.pi * np.abs(bt[sel, 0]))
        iv = local(owner[side], tri.edges[side, v])
        cols.append(S[owner[side], iv, 2])
        vals.append(math.pi * np.abs(bt[side, 1]))
    norm = scale * a ** 2
    r2 = x[tri.edges[sel], 0] ** 2
    at_rest = float(np.sum(math.pi * ground.gamma[owner[sel]] * tri.embedment
                           * np.abs(r2[:, 1] - r2[:, 0]))) / scale
    P.equal(np.zeros(len(np.concatenate(cols)) + 1, int), np.concatenate(cols + [[F]]),
            np.concatenate(vals + [[-load.variable / norm]]), [load.held / norm - at_rest])


def _equilibrium(P: ConeProgram, S, st, b, c, twoA) -> None:
    """Equilibrium in each triangle, 2 rows, scaled by 2A (b, c the shape functions'
    gradients times 2A): d(S_r)/dr + d(T)/dz - sigma_theta = 0, d(T)/dr + d(S_z)/dz = 0."""
    m = len(twoA)
    rows = np.repeat(np.arange(m), 7)
    cols = np.column_stack([S[:, :, 0], S[:, :, 2], st[:, None]]).ravel()
    vals = np.column_stack([b, c, -twoA[:, None]]).ravel()
    P.equal(rows, cols, vals, np.zeros(m))
    rows = np.repeat(np.arange(m), 6)
    cols = np.column_stack([S[:, :, 2], S[:, :, 1]]).ravel()
    vals = np.column_stack([b, c]).ravel()
    P.equal(rows, cols, vals, np.zeros(m))


def _continuity(P: ConeProgram, tri: Triangles, S, x, local) -> None:
    """The traction r t = S . n continuous across every interior edge, at both vertices."""
    pair, verts = tri.interior
    t = x[verts[:, 1]] - x[verts[:, 0]]
    n = np.column_stack([t[:, 1], -t[:, 0]])
    ef, ff = pair[:, 0], pair[:, 1]
    for v in (0, 1):
        ie = local(ef, verts[:, v])
        if_ = local(ff, verts[:, v])
        for comp in ((0, 2), (2, 1)):      # (n_r S_r + n_z T), (n_r T + n_z S_z)
            k = len(ef)
            rows = np.repeat(np.arange(k), 4)
            cols = np.column_stack([S[ef, ie, comp[0]], S[ef, ie, comp[1]],
                                    S[ff, if_, comp[0]], S[ff, if_, comp[1]]]).ravel()
            vals = np.column_stack([n[:, 0], n[:, 1], -n[:, 0], -n[:, 1]]).ravel()
            P.equal(rows, cols, vals, np.zeros(k))


def _yield_cone(P, cones, k, sel, S, st, r, z, h2, ground, a, scale, where) -> None:
    """Cone k at the vertices ``where`` (n, 3) of the triangles ``sel``: s = (beta r c +
    g . (S, r sigma_theta) + r gamma z G - margin, alpha (S_r - S_z) / 2, alpha T)."""
    al, be, g = cones.alpha[k], cones.beta[k], cones.g[k]
    G = g[0] + g[1] + g[3]                         # (the hydrostatic sigma0's share)
    n = len(sel)
    rv, zv = r[sel], z[sel]                         # (n, 3), in radii
    c = ground.cohesion(sel[:, None], zv * a) / scale
    gam = ground.gamma[sel, None] * a / scale
    kappa = np.abs(be * ground.dc_dz[sel] * a / scale) + np.abs(G) * gam[:, 0]
    const = be * rv * c + gam * rv * zv * G - (kappa * h2[sel] / 2.0)[:, None]
    groups = np.arange(3 * n)                       # one cone per (triangle, vertex)
    Sv = S[sel]                                     # (n, 3, 3)
    rows0 = np.repeat(3 * groups, 4)
    cols0 = np.column_stack([Sv[..., 0].ravel(), Sv[..., 1].ravel(), Sv[..., 2].ravel(),
                             np.repeat(st[sel], 3)]).ravel()
    vals0 = -np.column_stack([np.full(3 * n, g[0]), np.full(3 * n, g[1]), np.full(3 * n, g[2]),
                              g[3] * rv.ravel()]).ravel()
    rows1 = np.repeat(3 * groups + 1, 2)
    cols1 = np.column_stack([Sv[..., 0].ravel(), Sv[..., 1].ravel()]).ravel()
    vals1 = np.tile([-0.5 * al, 0.5 * al], 3 * n)
    rows2 = 3 * groups + 2
    cols2 = Sv[..., 2].ravel()
    vals2 = np.full(3 * n, -al)
    bvec = np.zeros(9 * n)
    bvec[0::3] = const.ravel()
    rows = np.concatenate([rows0, rows1, rows2])
    cols = np.concatenate([cols0, cols1, cols2])
    vals = np.concatenate([vals0, vals1, vals2])
    # (only the cones at the vertices ``where``: renumber their rows)
    keep = np.repeat(np.asarray(where).ravel(), 3)
    new = np.cumsum(keep) - 1
    mask = keep[rows]
    P.cones(new[rows[mask]], cols[mask], vals[mask], bvec[keep], 3)


def _far_field(P, tri: Triangles, ground: Ground, load: Loading, S, x, scale) -> None:
    """The closed-form field beyond an open box (the module's docstring): the ring's cones
    at the side's vertices, on the box's own S_r there; the column's unknowns S_c (one at
    each vertex of the base) and sigma_theta (one on each of its edges), its equilibrium,
    and its cones (and the ring's below the base) at ``ground.far``'s rows."""
    a, owner, local = tri.a, tri.owner, _local_index(tri.cells)
    points = []           # (S_r, (S_z, sigma_theta) or None for the ring, r, c, phi, gamma z)
    if load.side == "open":
        sel = np.flatnonzero(tri.kind == SIDE)
        for v in (0, 1):
            vert = tri.edges[sel, v]
            e, iv = owner[sel], local(owner[sel], vert)
            Sr = S[e, iv, 0]
            R = x[vert, 0]
            # r times (s, 0, 0, -s): (S_r, 0, 0, -S_r), at the vertex's height
            zz = x[vert, 1] * a
            for phi in np.unique(ground.phi[e]):
                k = ground.phi[e] == phi
                _cones_at(P, float(phi), np.column_stack([Sr[k], Sr[k], Sr[k], Sr[k]]),
                          np.tile([1.0, 0.0, 0.0, -1.0], (k.sum(), 1)),
                          R[k] * ground.cohesion(e[k], zz[k]) / scale,
                          R[k] * ground.gamma[e[k]] * zz[k] / scale)
            points.append((Sr, None, R, ground.cohesion(e, zz), ground.phi[e],
                           ground.gamma[e] * zz))
    if load.base != "open":
        return points
    sel = np.flatnonzero(tri.kind == BASE)
    verts = np.unique(tri.edges[sel])
    Sc = P.variables(len(verts))                  # the column's r sigma_r at the base's vertices
    st = P.variables(len(sel))                    # its sigma_theta on the base's edges
    index = np.searchsorted(verts, tri.edges[sel])            # (k, 2)
    r = x[tri.edges[sel], 0]                                  # (k, 2), in radii
    # dS_c/dr = sigma_theta on each edge
    k = len(sel)
    P.equal(np.repeat(np.arange(k), 3),
            np.column_stack([Sc[index[:, 1]], Sc[index[:, 0]], st]).ravel(),
            np.column_stack([np.ones(k), -np.ones(k), -(r[:, 1] - r[:, 0])]).ravel(),
            np.zeros(k))
    on_axis = np.flatnonzero(x[verts, 0] < 1e-12)
    P.equal(np.arange(len(on_axis)), Sc[on_axis], np.ones(len(on_axis)), np.zeros(len(on_axis)))
    outer = np.argmax(x[verts, 0])
    Rb = x[verts[outer], 0]
    for zz, c, phi, gamma in ground.far.rows:
        for v in (0, 1):
            vert = tri.edges[sel, v]
            keep = x[vert, 0] > 1e-12
            e, iv = owner[sel][keep], local(owner[sel][keep], vert[keep])
            rv = x[vert[keep], 0]
            cols = np.column_stack([Sc[index[keep, v]], S[e, iv, 1], S[e, iv, 1], st[keep]])
            coef = np.column_stack([np.ones(keep.sum()), np.ones(keep.sum()),
                                    np.zeros(keep.sum()), rv])
            _cones_at(P, phi, cols, coef, rv * c / scale, rv * gamma * zz / scale)
            n = keep.sum()
            points.append((Sc[index[keep, v]], (S[e, iv, 1], st[keep]), rv, np.full(n, c),
                           np.full(n, phi), np.full(n, gamma * zz)))
        if load.side == "open":                   # the ring below the base: s = S_c(R) / R
            _cones_at(P, phi, np.full((1, 4), Sc[outer]), np.array([[1.0, 0.0, 0.0, -1.0]]),
                      np.array([Rb * c / scale]), np.array([Rb * gamma * zz / scale]))
            points.append((Sc[[outer]], None, np.array([Rb]), np.array([c]), np.array([phi]),
                           np.array([gamma * zz])))
    return points


def _far_margin(sol_x, points, scale) -> dict:
    """The far field's least yield margin beyond the box's ``side`` (the ring) and under its
    ``base`` (the column), in units of ``scale`` (the cohesion under the foundation): near
    0 where the box's size limits the bound; None for a closed side or base."""
    from ..laws.limit_cones import admissible
    worst = {"side": math.inf, "base": math.inf}
    for Sr, col, r, c, phi, gz in points:
        sr = sol_x[Sr] / r
        zero = np.zeros_like(sr)
        if col is None:                                  # the ring: (s, 0, 0, -s)
            ex, where = np.column_stack([sr, zero, zero, -sr]), "side"
        else:
            ex, where = np.column_stack([sr, sol_x[col[0]] / r, zero, sol_x[col[1]]]), "base"
        sig = ex * scale + gz[:, None] * np.array([1.0, 1.0, 0.0, 1.0])
        for p in np.unique(phi):
            k = phi == p
            margin = float(np.min(-admissible(sig[k], c[k], float(p)))) / scale
            worst[where] = min(worst[where], margin)
    return {k: (v if math.isfinite(v) else None) for k, v in worst.items()}


def _cones_at(P, phi: float, cols: np.ndarray, coef: np.ndarray, rc: np.ndarray,
              rgz: np.ndarray) -> None:
    """Mohr-Coulomb's three cones at n points whose stress times r is sum coef x[cols] by
    component (n, 4: sigma_r, sigma_z, tau, sigma_theta), beside r c (``rc``, n) and
    r gamma z (``rgz``, n) of the ground at rest, all in the program's units."""
    cones = mohr_coulomb_cones(phi)
    n = len(cols)
    for k in range(3):
        al, be, g = cones.alpha[k], cones.beta[k], cones.g[k]
        G = g[0] + g[1] + g[3]
        # s = (be r c + r gamma z G + g . Sx, al (Sx_r - Sx_z) / 2, al Sx_tau) = b - A x
        rows = np.concatenate([np.repeat(3 * np.arange(n), 4), np.repeat(3 * np.arange(n) + 1, 2),
                               3 * np.arange(n) + 2])
        cc = np.concatenate([cols.ravel(), cols[:, :2].ravel(), cols[:, 2]])
        vals = np.concatenate([-(coef * g[None, :]).ravel(),
                               -(coef[:, :2] * np.array([0.5 * al, -0.5 * al])).ravel(),
                               -al * coef[:, 2]])
        b = np.zeros(3 * n)
        b[0::3] = be * rc + G * rgz
        P.cones(rows, cc, vals, b, 3)


def _local_index(cells: np.ndarray):
    def local(e: np.ndarray, v: np.ndarray) -> np.ndarray:
        hit = cells[e] == np.asarray(v)[:, None]
        return np.argmax(hit, axis=1)
    return local


def _stresses(x, S, st, r, z, ground, a, scale, bary=None) -> np.ndarray:
    """sigma (Pa) at each triangle's vertices (or at the points of barycentric coordinates
    ``bary`` (3,)): S / r plus sigma0 (on the axis its limit, 0 plus sigma0)."""
    Sv = x[S] * scale                                    # (m, 3, 3)
    if bary is not None:
        Sv = np.einsum("i,mic->mc", bary, Sv)[:, None, :]
        r, z = (r @ bary)[:, None], (z @ bary)[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        sig = np.where(r[..., None] > 1e-12, Sv / r[..., None], 0.0)
    p0 = ground.gamma[:, None] * z * a                   # (z in radii -> m)
    out = np.empty(sig.shape[:2] + (4,))
    out[..., 0] = sig[..., 0] + p0
    out[..., 1] = sig[..., 1] + p0
    out[..., 2] = sig[..., 2]
    out[..., 3] = x[st][:, None] * scale + p0
    return out


#: where the field's yield condition is checked after the solve: the vertices, the edges'
#: midpoints and the centroid
CHECKS = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [.5, .5, 0], [0, .5, .5], [.5, 0, .5],
                   [1 / 3, 1 / 3, 1 / 3]])


def _violation(x, S, st, r, z, tri, ground, a, scale) -> float:
    """The largest yield violation (Pa) over each triangle's CHECKS points (off the axis)."""
    from ..laws.limit_cones import admissible
    worst = -np.inf
    for bary in CHECKS:
        sig = _stresses(x, S, st, r, z, ground, a, scale, bary)[:, 0]
        rr, zz = r @ bary, (z @ bary) * a
        off = rr > 1e-9
        for phi in np.unique(ground.phi):
            sel = np.flatnonzero(off & (ground.phi == phi))
            worst = max(worst, float(np.max(admissible(sig[sel], ground.cohesion(sel, zz[sel]),
                                                        float(phi)), initial=-np.inf)))
    return worst
