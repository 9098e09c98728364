"""Drucker-Prager's elastoplastic soil: linear elastic (E(h), nu) inside the cone, perfectly
plastic on it,

    f = sqrt(J2) + eta p - xi c <= 0,      g = sqrt(J2) + eta_bar p,

tension positive, p = tr(sigma) / 3, J2 = s : s / 2 (s the deviator), c = cohesion +
cohesion_gradient x (h - top), g the flow's potential (eta_bar from the dilation angle psi).
The cone is matched to Mohr-Coulomb's c and phi by ``drucker_prager_match`` (Chen & Mizuno
1990; de Souza Neto, Peric & Owen 2008, Sec. 6.4.4):

- ``"compression"`` (the default): through Mohr-Coulomb's compression meridian (the outer
  cone), eta = 6 sin phi / (sqrt 3 (3 - sin phi)), xi = 6 cos phi / (sqrt 3 (3 - sin phi));
- ``"extension"``: through its extension meridian (the inner cone), 3 + sin phi for 3 - sin phi;
- ``"plane_strain"``: the same collapse as Mohr-Coulomb in plane strain,
  eta = 3 tan phi / sqrt(9 + 12 tan^2 phi), xi = 3 / sqrt(9 + 12 tan^2 phi).

At phi = 0 it is von Mises' soil: sqrt(J2) <= xi c, a triaxial strength of sqrt 3 xi c
(2 c matched in compression or extension, sqrt 3 c in plane strain).

The return (de Souza Neto et al. 2008, Box 8.9, perfect plasticity): to the cone's smooth
part, dgamma = f_tr / (G + K eta eta_bar), s = s_tr (1 - G dgamma / sqrt(J2_tr)),
p = p_tr - K eta_bar dgamma; where that would turn s over (sqrt(J2_tr) < G dgamma), to the
apex p = xi c / eta. Its consistent tangent (n = s_tr / |s_tr|, beta = sqrt 2 G dgamma / |s_tr|,
A = G + K eta eta_bar, m the identity, I_d = I - m m^T / 3):

    C = 2 G (1 - beta) I_d + 2 G beta n n^T + K m m^T
        - (sqrt 2 G n + K eta_bar m)(sqrt 2 G n + K eta m)^T / A,

symmetric where the flow is associated (eta_bar = eta). At the apex the tangent is a
millionth of the elastic one (as Mohr-Coulomb's). Vectorised over the points.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .geostatic import geostatic_stress
from .mohr_coulomb_soil import FrictionalPoints, MohrCoulombSoil
from .plasticity import APEX_STIFFNESS, IDENTITY, compliance, lame
from .point_law import PointUpdate

#: how the cone is laid on Mohr-Coulomb's pyramid (the module's docstring)
MATCHES = ("compression", "extension", "plane_strain")
_DEVIATORIC = np.eye(4) - np.outer(IDENTITY, IDENTITY) / 3.0


def cone(sin_angle, match: str):
    """(eta, xi) of the cone matched to Mohr-Coulomb's angle of sine ``sin_angle`` (per
    point) by ``match``; eta alone is the flow's eta_bar for the dilation angle's sine."""
    s = np.asarray(sin_angle, dtype=float)
    cos = np.sqrt(1.0 - s * s)
    if match == "plane_strain":
        tan = s / cos
        root = np.sqrt(9.0 + 12.0 * tan * tan)
        return 3.0 * tan / root, 3.0 / root
    denominator = math.sqrt(3.0) * (3.0 - s if match == "compression" else 3.0 + s)
    return 6.0 * s / denominator, 6.0 * cos / denominator


def drucker_prager_update(d_eps, stress, E, nu, strength, eta, eta_bar, reference, D):
    """The stress after the strain increment ``d_eps`` (N, 4) from the committed ``stress``
    (its change from ``reference``, the ground at rest), the cone sqrt(J2) + eta p <= strength
    (= xi c, Pa; inf: never yields) and the flow's eta_bar: (the stress's change, the
    consistent tangent, which points yield, the plastic strain increment)."""
    change = stress + (D @ d_eps[..., None])[..., 0]
    total = reference + change
    p_tr = total @ IDENTITY / 3.0
    s_tr = total - p_tr[:, None] * IDENTITY
    norm = np.sqrt(np.einsum("ij,ij->i", s_tr, s_tr))
    f = norm / math.sqrt(2.0) + eta * p_tr - strength
    scale = np.abs(total).max(axis=1) + np.where(np.isfinite(strength), strength, 0.0) + 1.0
    out = np.flatnonzero(f > 1e-10 * scale)
    sigma, C = change.copy(), D.copy()
    yielding = np.zeros(len(d_eps), dtype=bool)
    d_eps_p = np.zeros_like(change)
    if len(out) == 0:
        return sigma, C, yielding, d_eps_p
    lmbda, G = lame(E[out], nu[out])
    K = lmbda + 2.0 * G / 3.0
    e, eb = eta[out], eta_bar[out]
    A = G + K * e * eb
    dgamma = f[out] / A
    smooth = norm[out] / math.sqrt(2.0) - G * dgamma >= 0.0
    n = s_tr[out] / np.maximum(norm[out], 1e-300)[:, None]
    beta = math.sqrt(2.0) * G * dgamma / np.maximum(norm[out], 1e-300)
    new = (s_tr[out] * (1.0 - beta)[:, None]
           + (p_tr[out] - K * eb * dgamma)[:, None] * IDENTITY)
    a = math.sqrt(2.0) * G[:, None] * n
    Ct = (2.0 * G * (1.0 - beta))[:, None, None] * _DEVIATORIC \
        + (2.0 * G * beta)[:, None, None] * np.einsum("ni,nj->nij", n, n) \
        + K[:, None, None] * np.outer(IDENTITY, IDENTITY) \
        - np.einsum("ni,nj->nij", a + (K * eb)[:, None] * IDENTITY,
                    a + (K * e)[:, None] * IDENTITY) / A[:, None, None]
    # past the apex (eta > 0): the apex itself, xi c / eta
    apex = ~smooth
    with np.errstate(divide="ignore", invalid="ignore"):
        p_apex = np.where(e > 0.0, strength[out] / e, np.nan)
    new[apex] = p_apex[apex, None] * IDENTITY
    Ct[apex] = APEX_STIFFNESS * D[out][apex]
    sigma[out] = new - reference[out]
    C[out] = Ct
    yielding[out] = True
    d_eps_p[out] = (compliance(E[out], nu[out]) @ (change[out] - sigma[out])[..., None])[..., 0]
    return sigma, C, yielding, d_eps_p


@dataclass(frozen=True)
class DruckerPragerPoints(FrictionalPoints):
    """Drucker-Prager at N points (:class:`tankfx.laws.point_law.PointLaw`): per point ``E``,
    ``nu``, the ``cohesion`` (inf: never yields), ``sin_phi``, ``sin_psi`` and the ground at
    rest ``sigma0`` (N, 4), the cone laid by ``match``; its strength reduced through c and
    tan phi (:class:`~tankfx.laws.mohr_coulomb_soil.FrictionalPoints`)."""

    E: np.ndarray
    nu: np.ndarray
    cohesion: np.ndarray
    sin_phi: np.ndarray
    sin_psi: np.ndarray
    sigma0: np.ndarray
    match: str = "compression"

    def __post_init__(self):
        # (the cone of the Mohr-Coulomb constants, matched again after a reduction)
        super().__post_init__()
        eta, xi = cone(self.sin_phi, self.match)
        object.__setattr__(self, "_eta", eta)
        object.__setattr__(self, "_strength", xi * self.cohesion)
        object.__setattr__(self, "_eta_bar", cone(self.sin_psi, self.match)[0])

    def update(self, d_eps, stress, state) -> PointUpdate:
        sigma, C, yielding, d_eps_p = drucker_prager_update(
            d_eps, stress, self.E, self.nu, self._strength, self._eta, self._eta_bar,
            self.sigma0, self._D)
        return PointUpdate(stress=sigma, tangent=C, yielding=yielding,
                           plastic_strain=d_eps_p, state={})

    def mobilised(self, stress, per: int = 1) -> np.ndarray:
        """sqrt(J2) over the cone's radius xi c - eta p at the stress's p: 1 on the cone."""
        strength, eta = self._strength, self._eta
        if per > 1:
            strength = strength.reshape(-1, per).mean(axis=1)
            eta = eta.reshape(-1, per)[:, 0]
        return _mobilised(stress, strength, eta)


def _mobilised(stress, strength, eta):
    p = stress @ IDENTITY / 3.0
    s = stress - p[:, None] * IDENTITY
    radius = strength - eta * p
    j = np.sqrt(0.5 * np.einsum("ij,ij->i", s, s))
    tiny = 1e-9 * (np.abs(stress).max(axis=1) + np.where(np.isfinite(strength), strength, 0.0)
                   + 1.0)
    return np.where(radius > tiny, j / np.maximum(radius, tiny), 1.0)


class DruckerPragerSoil(MohrCoulombSoil):
    """Drucker-Prager's cone on Mohr-Coulomb's constants, with a geostatic start: the
    elastoplastic soil of many codes, its cone laid on the pyramid by
    ``drucker_prager_match``. No tension cut-off; no bounds (the limit analysis takes
    Mohr-Coulomb's cones)."""

    word = "drucker_prager"
    title = "an elastoplastic Drucker-Prager soil"
    layer_keys = ("cohesion", "friction_angle", "dilation_angle", "cohesion_gradient",
                  "unit_weight", "K0")
    keys = (*layer_keys, "water_table", "water_unit_weight", "drucker_prager_match")
    own_keys = {"drucker_prager_match": dict(
        type=str, default="compression", choices=MATCHES,
        meaning="for model = \"drucker_prager\": the Mohr-Coulomb meridian its cone passes "
                "through (\"compression\": the outer cone, the triaxial strength of "
                "`cohesion` and `friction_angle`; \"extension\": the inner cone; "
                "\"plane_strain\": Mohr-Coulomb's collapse in plane strain)")}
    stress_level_label = "sqrt(J2) / (xi c - eta p)"
    has_bounds = False
    why_no_bounds = ("the limit analysis takes Mohr-Coulomb's cones, not Drucker-Prager's; "
                     "ask for collapse = \"load\" or \"strength\", or model = "
                     "\"mohr_coulomb\"")

    @classmethod
    def stratum_text(cls, st):
        text = super().stratum_text(st)
        return text.replace("Tresca s_u", "von Mises c")

    @classmethod
    def ground_text(cls, soil) -> str:
        return f", the cone through Mohr-Coulomb's {soil.drucker_prager_match} meridian"

    @classmethod
    def check(cls, table, given, name, p_a=None):
        """Mohr-Coulomb's checks of c, phi, psi, E and nu; ``drucker_prager_match`` one of
        MATCHES."""
        out = super().check(table, given, name, p_a)
        match = table.get("drucker_prager_match", "compression")
        if name == "soil" and match not in MATCHES:
            out.append(f"soil.drucker_prager_match = {match!r}: one of "
                       + ", ".join(f'"{m}"' for m in MATCHES)
                       + " (the Mohr-Coulomb meridian the cone passes through)")
        return out

    @classmethod
    def resolve_ground(cls, soil):
        return {**super().resolve_ground(soil),
                "drucker_prager_match": soil.get("drucker_prager_match", "compression")}

    @classmethod
    def resolve_stratum(cls, table, ground):
        out = super().resolve_stratum(table, ground)
        out["tensile_strength"] = None
        return out

    @classmethod
    def point_law(cls, soil, depth) -> DruckerPragerPoints:
        k = cls.point_constants(soil, depth)
        return DruckerPragerPoints(E=k["E"], nu=k["nu"], cohesion=k["cohesion"],
                                   sin_phi=k["sin_phi"], sin_psi=k["sin_psi"],
                                   sigma0=cls.initial_stress(soil, depth),
                                   match=soil.drucker_prager_match)

    @classmethod
    def limit_strength(cls, soil, depth):
        raise NotImplementedError(cls.why_no_bounds)

    @classmethod
    def limit_strata(cls, soil, top, bottom):
        raise NotImplementedError(cls.why_no_bounds)

    @classmethod
    def undrained_strength(cls, soil, depth: float) -> float | None:
        """von Mises' (phi = 0 everywhere): the triaxial s_u, sqrt 3 xi c / 2."""
        if any(st.friction_angle for st in soil.strata):
            return None
        xi = cone(np.zeros(1), soil.drucker_prager_match)[1][0]
        c = float(cls.point_constants(soil, np.array([depth]))["cohesion"][0])
        return 0.5 * math.sqrt(3.0) * xi * c

    @classmethod
    def _at_rest_outside(cls, soil, bottom: float) -> list[str]:
        """The ground at rest inside the cone down to ``bottom`` (m), checked at the depths
        where its stresses kink and between them."""
        tops = [st.depth for st in soil.strata]
        wt = [soil.water_table] if soil.water_table is not None else []
        d = np.unique(np.concatenate([np.linspace(0.0, bottom, 2001), tops, wt,
                                      [t + 1e-9 * (1.0 + t) for t in tops]]))
        d = d[d <= bottom]
        sv, sh = geostatic_stress(soil, d)
        sigma = np.column_stack([-sh, -sv, 0.0 * sv, -sh])
        pts = cls.point_law(soil, d)
        level = pts.mobilised(sigma)
        bad = level > 1.0 + 1e-9
        if not bad.any():
            return []
        h = float(d[np.flatnonzero(bad)[0]])
        k = int(soil.stratum_of(np.array([h]))[0])
        where = "soil" if k == 0 else f"soil.layers[{k}]"
        return [f"{where}: the ground at rest lies outside the Drucker-Prager cone from "
                f"{h:.4g} m down (its K0 sigma'_v differs from sigma'_v by more than the "
                f"cone of {where}.cohesion, cohesion_gradient and friction_angle allows); "
                f"raise the strength or give a K0 nearer 1"]
