"""The ground's collapse (``[analysis] collapse``): the rigid footing's exact bearing
capacity by raising the load, the strength factor equal to the load factor for Tresca soil,
the two consistent for a c-phi soil, the mechanism's kind, a load that already fails, and
what is refused."""
from __future__ import annotations

import numpy as np
import pytest
from mpi4py import MPI

from tankfx import Scene, SceneError, analyse
from tankfx import SoilFailure
from tankfx.results.report import summary_table

S_U = 10e3


def footing(condition="smooth", collapse="load", soil=None, pressure=S_U,
            mesh=(0.005, 0.2)) -> dict:
    """The rigid 1 m footing of tankfx.verification.footing, with a collapse asked."""
    return {"title": f"footing, {condition}",
            "soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": S_U,
                     **(soil or {})},
            "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2},
            "interface": {"condition": condition}, "load": {"pressure": pressure},
            "mesh": {"edge_size": mesh[0], "near_size": mesh[1], "growth": 0.3},
            "domain": {"radius": 5.0, "depth": 5.0}, "analysis": {"collapse": collapse}}


# (the rough footing by load is solved, with cubic elements, by test_bounds' scene test in
# `make test`; here in `make verify`)
@pytest.mark.parametrize("condition,exact", [
    ("smooth", 5.69), pytest.param("bonded", 6.05, marks=pytest.mark.verify)])
def test_a_rigid_footing_collapses_at_its_exact_bearing_capacity(condition, exact, tmp_path):
    """collapse = "load" on weightless Tresca soil: N_c = q_ult / s_u within 1 % of 5.69
    (smooth, Shield 1955) and 6.05 (rough, Eason & Shield 1960), bracketed to 0.5 % between
    a converged and a failed state, the load-settlement curve rising to it, the whole
    footing punching in ("base"); the scene's own results stay those of its load; its
    figures drawn, the failed state labelled with how it failed."""
    from tankfx.results.charts import failure_words
    from tankfx.results.figures import write_figures

    solution = analyse(Scene.from_dict(footing(condition)))
    r = solution.results
    if condition == "smooth":       # (the figures' code is the same for both)
        written = {p.name for p in write_figures(solution, tmp_path, "stress_level")}
        if MPI.COMM_WORLD.rank == 0:
            assert {"collapse.png", "mechanism.png"} <= written
        assert failure_words(r["collapse"]["failure"]) in ("no equilibrium",
                                                          "the settlement criterion (0.1 D)")
        assert failure_words("settlement") == "the settlement criterion (0.1 D)"
    c = r["collapse"]
    lo, hi = c["bracket"]
    assert c["found"] and c["load_factor"] == lo and hi / lo - 1.0 <= 0.0051
    assert c["N_c"] == pytest.approx(exact, rel=0.01) and c["N_c"] > exact
    assert c["bearing_pressure"] == pytest.approx(lo * S_U, rel=1e-12)
    assert np.all(np.diff(c["curve"]["factor"]) > 0.0)
    assert c["mechanism"]["kind"] == "base"
    # general shear: a plateau, reached well before the settlement criterion; half a
    # per cent above it Newton finds no equilibrium, or one settled beyond the criterion
    # (measured since the line search keeps a consistent state: 5.755 and 6.123 settle
    # past 0.1 D, on the slowly rising curve of the discretised soil)
    assert (c["failure"] == "no equilibrium" and "Newton found no equilibrium" in c["reason"]) \
        or (c["failure"] == "settlement" and "settlement criterion" in c["reason"])
    assert c["curve"]["mean_settlement"][-1] < 0.5 * c["failure_settlement"]
    # the knee, where the mechanism forms, lies below the plateau
    assert c["knee_bracket"][0] == c["knee_factor"] < c["knee_bracket"][1] <= lo
    assert r["bearing_pressure"]["mean"] == pytest.approx(S_U)        # the scene's load's
    assert "factor of safety on the loads" in summary_table(r)


@pytest.mark.verify
def test_for_tresca_soil_the_strength_factor_is_the_load_factor():
    """Tresca's limit load is proportional to s_u: dividing it by F fails the footing under
    q where q F does at full strength. The two searches (different paths, different
    iterations) agree within 1 %, and their brackets overlap. (On a coarser mesh, 0.03 and
    0.5 m, they agreed within 1 % but their brackets did not overlap: 5.846 against 5.85;
    2026-12-01.)"""
    load = analyse(Scene.from_dict(footing(mesh=(0.01, 0.25)))).results["collapse"]
    strength = analyse(Scene.from_dict(footing(collapse="strength", mesh=(0.01, 0.25)))
                       ).results["collapse"]
    assert strength["found"] and strength["kind"] == "strength"
    assert strength["strength_factor"] == pytest.approx(load["load_factor"], rel=0.01)
    assert strength["bracket"][0] < load["bracket"][1]
    assert load["bracket"][0] < strength["bracket"][1]


@pytest.mark.verify
def test_a_c_phi_soil_at_its_strength_factor_carries_its_load_and_no_more():
    """c = 10 kPa, phi = 20 degrees, weightless, under 100 kPa: F from collapse = "strength";
    the same soil with c / F and tan phi / F has a load factor of 1 on 100 kPa within the
    brackets (measured: F = 1.394, then 1.002). (Analysed under 90 kPa: at its limit the
    load steps of the scene's own analysis may fail where settlement control passes.)"""
    soil = {"friction_angle": 20.0, "dilation_angle": 20.0}
    strength = analyse(Scene.from_dict(footing(collapse="strength", soil=soil,
                                               pressure=100e3, mesh=(0.03, 0.5)))
                       ).results["collapse"]
    F = strength["strength_factor"]
    reduced = {"cohesion": S_U / F, "dilation_angle": None,
               "friction_angle": float(np.degrees(np.arctan(np.tan(np.radians(20.0)) / F)))}
    reduced["dilation_angle"] = reduced["friction_angle"]
    load = analyse(Scene.from_dict(footing(soil=reduced, pressure=90e3, mesh=(0.03, 0.5)))
                   ).results["collapse"]
    width = strength["bracket"][1] / strength["bracket"][0] - 1.0
    assert 0.9 * load["load_factor"] == pytest.approx(1.0, abs=width + load["bracket_width"]
                                                      + 2e-3)


@pytest.mark.verify
def test_a_load_that_fails_is_bracketed_below_one():
    """A footing pressed with 8 s_u, beyond its capacity: the analysis fails, saying so, and
    the collapse search from the share carried brackets the factor near 5.7 / 8."""
    with pytest.raises(SoilFailure) as e:
        # (12 Newton iterations a step: the load steps' failures near the limit cost less)
        analyse(Scene.from_dict(footing(pressure=8.0 * S_U, mesh=(0.01, 0.25),
                                        soil={"max_iterations": 12})))
    c = e.value.kept["collapse"]
    assert c["found"] and c["load_factor"] < 1.0
    assert c["N_c"] == pytest.approx(5.69, rel=0.015)
    assert "load factor" in str(e.value)


@pytest.mark.parametrize("data,says", [
    ({"soil": {"E": 10e6, "nu": 0.3}}, "analysis.collapse = 'load' with soil.model = 'linear'"),
    ({"soil": {"model": "hyperbolic", "hyperbolic_a": 2.1e-7, "hyperbolic_b": 1e-5,
               "nu": 0.3}}, "Kondner's hyperbolic soil has no collapse load"),
    ({"soil": {"E": 10e6, "nu": 0.3}, "analysis": {"collapse": "strength"}},
     "has no strength to reduce"),
    ({"analysis": {"collapse": "lod"}}, "analysis.collapse = 'lod': unknown (did you mean"),
    ({"stages": [{}, {"pressure": 2e4}]}, "analysis.collapse = 'load' with [[stages]]"),
    ({"load": {"pressure": 0.0, "self_weight": True}},
     "the [load] has no variable load to raise"),
])
def test_a_collapse_that_cannot_be_computed_is_refused_before_any_mesh(data, says):
    d = footing()
    d.update(data)
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert says in str(e.value), str(e.value)


@pytest.mark.verify
@pytest.mark.mpi
@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="needs mpiexec -n 2 (make test-mpi)")
def test_serial_and_two_ranks_follow_the_same_collapse():
    """The same curve, factor and mechanism on one rank and on all (a coarse mesh: the
    search's path is what is compared, not its bracket)."""
    scene = Scene.from_dict(footing(mesh=(0.02, 0.4)))
    parallel = analyse(scene, MPI.COMM_WORLD).results["collapse"]
    serial = analyse(scene, MPI.COMM_SELF).results["collapse"]
    assert parallel["load_factor"] == pytest.approx(serial["load_factor"], rel=1e-6)
    np.testing.assert_allclose(parallel["curve"]["factor"], serial["curve"]["factor"],
                               rtol=1e-6)
    assert parallel["found"] == serial["found"]
    assert parallel["mechanism"]["kind"] == serial["mechanism"]["kind"]


def api_rp_2geo(x: float, rough: bool) -> float:
    """q_u / s_u0 of a circular footing on clay of s_u = s_u0 + k z by API RP 2GEO's design
    fit (its F of Davis & Booker's strip, times its shape factor), x = k B' / s_u0 with
    B' = sqrt(pi) a the side of the square of the circle's area, N_c = 5.14."""
    F = (2.56 + 0.457 * x - np.hypot(0.713 + 0.457 * x, 1.38)) if rough else \
        (1.372 + 0.07 * x - np.hypot(-0.128 + 0.07 * x, 0.342))
    return F * (5.14 + x / 4.0) * (1.0 + 0.18 - 0.155 * np.sqrt(x) + 0.021 * x)


def test_the_mechanisms_kind_is_read_off_the_last_increment_under_the_foundation():
    """"base" where the increment's settlement at the axis is at least half its largest
    under the foundation (the whole foundation punching in), "edge" where the ground gives
    way under the edge with the centre held back (measured on a 25 m steel tank on soft clay:
    axis share 0.005, "edge"; the rigid footing: 1.0, "base")."""
    from dolfinx import fem, mesh

    from tankfx.results.collapse import mechanism

    msh = mesh.create_rectangle(MPI.COMM_WORLD, [[0.0, -3.0], [3.0, 0.0]], [30, 30])
    V = fem.functionspace(msh, ("Lagrange", 1, (2,)))
    du = fem.Function(V)
    for profile, kind in ((lambda r: 1.0 + 0.0 * r, "base"),
                          (lambda r: np.exp(-((r - 1.0) / 0.1) ** 2), "edge"),
                          (lambda r: 0.6 + 0.4 * r, "base")):
        du.interpolate(lambda x: np.vstack([0.0 * x[0], -profile(x[0])]))
        m = mechanism(du, a=1.0, depth=0.0)
        assert m["kind"] == kind, (m, kind)
    assert m["axis_share"] == pytest.approx(0.6, rel=1e-6)
