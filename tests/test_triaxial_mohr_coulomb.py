"""The undrained triaxial test of a Mohr-Coulomb clay through a cell of the coupled analysis
(tankfx.verification.triaxial: the skeleton's effective stress at the quadrature points and
Biot's blocks with no flow, the sample's side free under its cell pressure). It checks what
a consolidation whose skeleton yields stands on: the pore pressure's sign in the effective
stress and the plastic volume change in the storage equation (a dilating skeleton sucks the
water in)."""
import math

import numpy as np
import pytest

from tankfx.laws.mohr_coulomb_soil import MohrCoulombPoints
from tankfx.verification.triaxial import TriaxialCell

P0, C, PHI = 100e3, 10e3, math.radians(25.0)
S = math.sin(PHI)


def _cell(psi: float) -> TriaxialCell:
    """The sample from an isotropic p'_0 = 100 kPa (c' 10 kPa, phi' 25 deg, E' 10 MPa,
    nu' 0.3, no cut-off)."""
    def points_of(n):
        full = np.ones(n)
        return MohrCoulombPoints(
            E=10e6 * full, nu=0.3 * full, cohesion=C * full, sin_phi=S * full,
            sin_psi=math.sin(psi) * full, tension=np.inf * full,
            sigma0=np.tile([-P0, -P0, 0.0, -P0], (n, 1)))
    return TriaxialCell(points_of, cells=(1, 1))


def _strength(p):
    """q at Mohr-Coulomb's strength in triaxial compression at mean effective stress p:
    6 (c cos phi + p sin phi) / (3 - sin phi)."""
    return 6.0 * (C * math.cos(PHI) + p * S) / (3.0 - S)


@pytest.mark.mpi
def test_undrained_without_dilation_the_mean_effective_stress_stays():
    """psi = 0: no volume change at all (no water flows, none is made plastically), so p'
    stays p'_0; the sample fails at q_f = 6 (c cos phi + p'_0 sin phi) / (3 - sin phi) and
    its excess pore pressure is q_f / 3 (the cell pressure held, the total mean stress up
    by q / 3). Within 1e-9 (measured 1e-15), on one rank and on two. A pore pressure of the
    wrong sign in the effective stress, or a storage equation blind to the skeleton's
    volume, moves p' off p'_0 at once."""
    cell = _cell(0.0)
    q_f = _strength(P0)
    elastic_limit = q_f / (3.0 * 10e6 / (2.0 * 1.3))       # the axial strain q_f / (3 G)
    for eps in np.linspace(0.0, 2.5 * elastic_limit, 11)[1:]:
        cell.compress(eps)
        got = cell.record()
        assert got["p"] == pytest.approx(P0, rel=1e-9)
        assert got["pore_pressure"] == pytest.approx(got["q"] / 3.0, rel=1e-9)
        assert abs(got["volumetric_strain"]) < 1e-12
    assert got["q"] == pytest.approx(q_f, rel=1e-9)
    assert got["spread"] < 1e-9 * P0


@pytest.mark.mpi
def test_undrained_with_associated_flow_the_water_is_sucked_in_and_the_strength_grows():
    """psi = phi: past yield the skeleton dilates, and as no water can enter, the elastic
    volume shrinks by as much: p' rises along the strength line (q = q_f(p') at every
    yielding step), the excess pore pressure p'_0 + q / 3 - p' falls and turns to suction,
    and the strength grows without bound. Only the plastic volume change in the storage
    equation makes p' move; with it left out the sample would fail at q_f(p'_0) as with
    psi = 0."""
    cell = _cell(PHI)
    q_f0 = _strength(P0)
    elastic_limit = q_f0 / (3.0 * 10e6 / (2.0 * 1.3))
    previous = None
    for eps in np.linspace(1.2, 8.0, 6) * elastic_limit:
        cell.compress(eps)
        got = cell.record()
        assert got["q"] == pytest.approx(_strength(got["p"]), rel=1e-9)
        assert got["pore_pressure"] == pytest.approx(P0 + got["q"] / 3.0 - got["p"], rel=1e-9,
                                                     abs=1e-9 * P0)
        assert abs(got["volumetric_strain"]) < 1e-12
        if previous is not None:
            assert got["p"] > previous["p"] and got["q"] > previous["q"]
            assert got["pore_pressure"] < previous["pore_pressure"]
        previous = got
    assert got["q"] > 1.2 * q_f0 and got["pore_pressure"] < 0.0
