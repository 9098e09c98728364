"""Layered ground (`[[soil.layers]]`): the flexible load against Burmister's layered
solution (Hankel transform, `tankfx.verification.reference.layered_surface_settlement`), against the
oedometer where the load is wide, and against the homogeneous ground where the layers are
alike; nearly incompressible layers in the mixed form, one pressure per layer; the mesh
follows the layers' tops; a tank on layers in equilibrium; a hyperbolic soil reading each
layer's Kondner parameters; and the scene's checks."""
import numpy as np
import pytest

from conftest import HYPERBOLIC_SOIL, flexible_scene, small_tank
from tankfx import Scene, SceneError, analyse
from tankfx.verification import reference as ref

P, A = 100e3, 1.0


# --------------------------------------------------------------------------- the reference
def test_reference_alike_layers_are_boussinesq():
    """Layers of one material over a half-space of it: Boussinesq's flexible load, to
    round-off (the layered system and its transform are then exercised for nothing)."""
    E, nu, r = 10e6, 0.3, np.array([0.0, 0.5, 1.0, 2.5])
    w = ref.layered_surface_settlement(P, A, r, [(0.4, E, nu), (1.3, E, nu)], (E, nu))
    np.testing.assert_allclose(w, ref.flexible_surface_settlement(P, A, E, nu, r), rtol=1e-9)
    k = np.geomspace(1e-4, 1e3, 9)
    np.testing.assert_allclose(ref.layered_surface_compliance(k, [(1.0, E, nu)], (E, nu)),
                               2 * (1 - nu**2) / (E * k), rtol=1e-10)


def test_reference_wide_load_is_oedometric():
    """A load a thousand times wider than the layers on a rigid base compresses them as in
    the oedometer, sum of p h / M."""
    layers = [(1.0, 10e6, 0.3), (2.0, 2e6, 0.45)]
    w = ref.layered_surface_settlement(P, 1000.0, [0.0], layers, None)[0]
    assert w == pytest.approx(ref.one_dimensional_settlement(P, layers), rel=1e-8)


def test_reference_integral_is_converged():
    """Twice the Gauss panels and points change the settlement by less than 1e-10."""
    layers, base = [(0.5, 10e6, 0.3), (1.5, 2e6, 0.5)], (30e6, 0.25)
    w1 = ref.layered_surface_settlement(P, A, [0.0, 1.0], layers, base)
    w2 = ref.layered_surface_settlement(P, A, [0.0, 1.0], layers, base,
                                        panels_per_period=4, points=32)
    np.testing.assert_allclose(w1, w2, rtol=1e-10)


# --------------------------------------------------------------------------- the solver
CASES = {
    # stiff crust over a soft half-space
    "crust": ({"E": 10e6, "nu": 0.3, "layers": [{"depth": 1.0, "E": 2e6, "nu": 0.3}]},
              None, [(1.0, 10e6, 0.3)], (2e6, 0.3)),
    # an undrained clay layer (mixed form) between two drained ones, on a rigid base
    "undrained_middle": ({"E": 10e6, "nu": 0.3, "layers": [
        {"depth": 0.5, "E": 2e6, "nu": 0.5}, {"depth": 2.0, "E": 30e6, "nu": 0.25}]},
        4.0, [(0.5, 10e6, 0.3), (1.5, 2e6, 0.5), (2.0, 30e6, 0.25)], None),
    # every layer nearly incompressible: three pressures, each jumping at the layers' tops
    "all_mixed": ({"E": 10e6, "nu": 0.46, "layers": [
        {"depth": 0.5, "E": 2e6, "nu": 0.5}, {"depth": 2.0, "E": 30e6, "nu": 0.46}]},
        4.0, [(0.5, 10e6, 0.46), (1.5, 2e6, 0.5), (2.0, 30e6, 0.46)], None),
}


@pytest.mark.parametrize("case", list(CASES))
def test_flexible_load_on_layers_is_burmisters(case):
    """Default mesh: the centre and edge settlements within 0.05 % of the layered elastic
    solution (measured: 1.8e-4 and less, most of it the half-space's truncation; one
    pressure continuous over the mixed layers was 1.6-1.8 % off), in equilibrium."""
    soil, base_depth, layers, base = CASES[case]
    extra = {"domain": {"depth": base_depth}} if base_depth else {}
    scene = flexible_scene(soil=soil, **extra)
    r = analyse(scene).results
    w = ref.layered_surface_settlement(P, A, [0.0, A], layers, base)
    assert r["w0"] == pytest.approx(w[0], rel=5e-4)
    assert r["w_edge"] == pytest.approx(w[1], rel=5e-4)
    assert r["equilibrium"]["relative_error"] < 1e-8
    expected_pressures = sum(nu > 0.45 for _, _, nu in layers)
    assert ("soil_pressure" in r["dofs"]) == (expected_pressures > 0)


def test_thin_layer_is_resolved():
    """A soft layer 0.03 a thick under a 10 m load: its elements are no larger than its
    thickness over the near field (not slivers of the near field's size), so the edge
    settlement stays within 0.05 % of Burmister (measured 1.5e-4; 3.3e-3 before)."""
    a, t = 10.0, 0.3
    scene = Scene.from_dict({"soil": {"E": 2e6, "nu": 0.3, "layers": [
        {"depth": t, "E": 20e6, "nu": 0.3}]}, "load": {"pressure": P, "load_radius": a}})
    r = analyse(scene).results
    w = ref.layered_surface_settlement(P, a, [0.0, a], [(t, 2e6, 0.3)], (20e6, 0.3))
    assert r["w0"] == pytest.approx(w[0], rel=5e-4)
    assert r["w_edge"] == pytest.approx(w[1], rel=5e-4)


@pytest.mark.parametrize("base", [1e3, 1e11])
def test_extreme_layer_contrast(base):
    """A 10 MPa crust 0.5 a thick over a base 1e-4 or 1e4 times as stiff: Burmister within
    0.2 % (measured -7.3e-4 and +5e-7; the soft base's error is the truncated domain's,
    whose settlement it dominates), the solve's residual and equilibrium checked."""
    scene = flexible_scene(soil={"layers": [{"depth": 0.5, "E": base, "nu": 0.3}]},
                           accept=["soil.layers[1].E"])     # (the contrast is the test)
    r = analyse(scene).results
    w = ref.layered_surface_settlement(P, A, [0.0, A], [(0.5, 10e6, 0.3)], (base, 0.3))
    assert r["w0"] == pytest.approx(w[0], rel=2e-3)
    assert r["w_edge"] == pytest.approx(w[1], rel=2e-3)
    assert r["linear_solver"]["last_relative_residual"] < 1e-6
    assert r["equilibrium"]["relative_error"] < 1e-6


def test_shallow_rigid_base_is_burmisters():
    """One soil 1.5 m deep on a rigid base under a 10 m load (the base shallower than the
    near field's elements): Burmister's layer on a rigid base within 0.05 % (measured
    -5e-7 and -9.2e-5; the edge -4.5e-4 before the thin-stratum rule reached it)."""
    a, H = 10.0, 1.5
    scene = Scene.from_dict({"soil": {"E": 10e6, "nu": 0.3}, "domain": {"depth": H},
                             "load": {"pressure": P, "load_radius": a}})
    r = analyse(scene).results
    w = ref.layered_surface_settlement(P, a, [0.0, a], [(H, 10e6, 0.3)], None)
    assert r["w0"] == pytest.approx(w[0], rel=5e-4)
    assert r["w_edge"] == pytest.approx(w[1], rel=5e-4)


def test_wide_load_on_layers_is_oedometric():
    """A load 50 times wider than two layers on a rigid base at 3 m: the centre settles as
    in the oedometer (closed form, independent of the transform) within 0.1 %."""
    a = 50.0
    scene = Scene.from_dict({
        "soil": {"E": 10e6, "nu": 0.3, "layers": [{"depth": 1.0, "E": 2e6, "nu": 0.45}]},
        "load": {"pressure": P, "load_radius": a}, "domain": {"depth": 3.0, "radius": 4 * a},
        "mesh": {"edge_size": 0.05, "near_size": 0.5}})
    w0 = analyse(scene).results["w0"]
    assert w0 == pytest.approx(ref.one_dimensional_settlement(
        P, [(1.0, 10e6, 0.3), (2.0, 2e6, 0.45)]), rel=1e-3)


def test_alike_layers_are_the_homogeneous_ground():
    """Layers of the soil's own material change only the mesh: w0 and w_edge within 5e-5
    (measured 2e-7 and 1.7e-5: the edge's elements move with the layers' lines)."""
    plain = analyse(flexible_scene()).results
    alike = analyse(flexible_scene(soil={"layers": [{"depth": 0.7, "E": 10e6, "nu": 0.3},
                                                    {"depth": 3.0, "E": 10e6, "nu": 0.3}]}))
    for key in ("w0", "w_edge"):
        assert alike.results[key] == pytest.approx(plain[key], rel=5e-5)


def test_layers_continuing_a_gradient_are_the_gradient_soil():
    """Layers whose E_top and E_gradient continue E_s (1 + lambda h) (E_top = E_s (1 +
    lambda d), E_gradient = lambda / (1 + lambda d)) are the soil stiffening with depth:
    w0 within 1e-6 (measured 1.6e-7), w_edge within 2e-4 (5.5e-5: the edge's elements move
    with the layers' lines; 1.4e-6 on a mesh twice as fine)."""
    lam, E_s = 0.5, 10e6
    plain = analyse(flexible_scene(soil={"E_gradient": lam})).results
    layers = [{"depth": d, "E": E_s * (1 + lam * d), "nu": 0.3,
               "E_gradient": lam / (1 + lam * d)} for d in (0.6, 2.5)]
    layered = analyse(flexible_scene(soil={"E_gradient": lam, "layers": layers})).results
    assert layered["w0"] == pytest.approx(plain["w0"], rel=1e-6)
    assert layered["w_edge"] == pytest.approx(plain["w_edge"], rel=2e-4)


def test_mesh_follows_the_layers():
    """No soil cell straddles a layer's top, whether the top lies above the embedded plate's
    underside, on it, or below it; the tops are tagged facets."""
    from dolfinx import mesh as dmesh

    from tankfx.mesh import FACET_TAGS, build_domain

    tops = (0.1, 0.3, 1.0)
    scene = Scene.from_dict(small_tank(soil={"E": 10e6, "nu": 0.3, "layers": [
        {"depth": d, "E": 10e6 * (k + 2), "nu": 0.3} for k, d in enumerate(tops)]}))
    dom = build_domain(scene)
    msh = dom.mesh
    cells = dom.cells("soil")
    # per cell, its nodes' depths
    depth = -msh.geometry.x[dmesh.entities_to_geometry(msh, 2, cells), 1]
    lo, hi = depth.min(axis=1), depth.max(axis=1)
    for t in tops:
        assert not np.any((lo < t - 1e-9) & (hi > t + 1e-9)), t
    assert np.any(np.isclose(hi, 1.0)) and np.any(np.isclose(lo, 1.0))
    assert np.count_nonzero(dom.facet_tags.values == FACET_TAGS["layer_top"]) > 0


def test_tank_on_layers_in_equilibrium():
    """The 1 m embedded tank on a soft layer at the plate's level over a stiffer one, a
    Mohr-Coulomb interface: converged, in equilibrium, settling more than on the stiffer
    ground alone and less than on the soft one."""
    def w0(soil):
        s = small_tank(soil=soil, interface={"condition": "mohr_coulomb", "tan_phi": 0.5})
        return analyse(Scene.from_dict(s)).results

    layered = w0({"E": 10e6, "nu": 0.3, "layers": [{"depth": 0.3, "E": 4e6, "nu": 0.35},
                                                   {"depth": 1.5, "E": 20e6, "nu": 0.3}]})
    assert layered["equilibrium"]["relative_error"] < 1e-8
    assert layered["equilibrium"]["contact_relative_error"] < 1e-6
    soft, stiff = w0({"E": 4e6, "nu": 0.35}), w0({"E": 20e6, "nu": 0.3})
    assert stiff["w0"] < layered["w0"] < soft["w0"]


def test_hyperbolic_layers_use_their_own_parameters(tmp_path):
    """A hyperbolic soil with a weaker layer below the plate: converged; each cell's secant
    modulus and stress level obey Eq. 17 with its own layer's a and b (q_m b = 1 - E_sec /
    E_initial, deviator x b = stress level, to the Eq. 18 tolerance), read back from the
    fields file."""
    import pyvista as pv

    from tankfx.results.fields import write_fields

    a2, b2, top = 5e-7, 4e-5, 0.8
    soil = dict(HYPERBOLIC_SOIL, layers=[{"depth": top, "hyperbolic_a": a2,
                                          "hyperbolic_b": b2, "nu": 0.35}])
    scene = Scene.from_dict(small_tank(soil=soil, load={"pressure": 100e3}))
    solution = analyse(scene)
    assert solution.results["soil"]["converged"]
    grid = pv.read(write_fields(solution, tmp_path)[0])
    grid = grid if isinstance(grid, pv.UnstructuredGrid) else grid.combine()
    soil_cells = grid.cell_data["soil"] > 0.5
    depth = -grid.cell_centers().points[soil_cells, 1]
    lower = depth > top
    a = np.where(lower, a2, HYPERBOLIC_SOIL["hyperbolic_a"])
    b = np.where(lower, b2, HYPERBOLIC_SOIL["hyperbolic_b"])
    np.testing.assert_array_equal(grid.cell_data["stratum"][soil_cells], lower.astype(float))
    E = grid.cell_data["modulus"][soil_cells]
    level = grid.cell_data["stress_level"][soil_cells]
    deviator = grid.cell_data["deviator"][soil_cells]
    tol = scene.soil.tolerance
    assert np.max(np.abs(level - (1.0 - E * a))) <= tol
    assert np.all(np.abs(deviator * b - level) <= tol * deviator * b + 1e-12)
    assert level[lower].max() > 0.05 and level[~lower].max() > 0.05


def test_hyperbolic_alike_layers_are_the_homogeneous_soil():
    """Layers with the soil's own a, b and nu: the same nonlinear settlement within 1e-4."""
    plain = analyse(Scene.from_dict(small_tank(soil=HYPERBOLIC_SOIL))).results
    alike = dict(HYPERBOLIC_SOIL, layers=[{"depth": 0.9, "hyperbolic_a": 2.1e-7,
                                           "hyperbolic_b": 1e-5, "nu": 0.3}])
    layered = analyse(Scene.from_dict(small_tank(soil=alike))).results
    assert layered["w0"] == pytest.approx(plain["w0"], rel=1e-4)


# --------------------------------------------------------------------------- the scene
def _layers_scene(layers, **soil):
    return {"soil": {"E": 10e6, "nu": 0.3, "layers": layers, **soil},
            "load": {"pressure": P, "load_radius": A}}


def test_layers_round_trip_and_strata():
    scene = Scene.from_dict(_layers_scene([{"depth": 1.0, "E": 2e6, "nu": 0.5},
                                           {"depth": 3.0, "E": 5e6, "nu": 0.3,
                                            "E_gradient": 0.2}]))
    assert Scene.from_dict(scene.to_dict()) == scene
    s = scene.soil
    assert [st.depth for st in s.strata] == [0.0, 1.0, 3.0] and s.max_nu == 0.5
    np.testing.assert_array_equal(s.stratum_of([-1.0, 0.0, 0.99, 1.0, 2.0, 3.0, 50.0]),
                                  [0, 0, 0, 1, 1, 2, 2])
    np.testing.assert_allclose(s.at_depth([0.5, 1.0, 5.0])["E"], [10e6, 2e6, 5e6 * 1.4])
    # without layers, the strata are the one soil
    assert Scene.from_dict(flexible_scene().to_dict()).soil.strata[0].E == 10e6


@pytest.mark.parametrize("layers, soil, expected", [
    ([{"depth": 1.0, "E": 2e6, "nu": 0.3, "thickness": 1.0}], {}, "soil.layers[1].thickness"),
    ([{"E": 2e6, "nu": 0.3}], {}, "soil.layers[1].depth: missing"),
    ([{"depth": 1.0, "nu": 0.3}], {}, "soil.layers[1].E: missing"),
    ([{"depth": 1.0, "E": 2e6}], {}, "soil.layers[1].nu: missing"),
    ([{"depth": 1.0, "E": 2e6, "nu": 0.6}], {}, "soil.layers[1].nu = 0.6"),
    ([{"depth": -1.0, "E": 2e6, "nu": 0.3}], {}, "soil.layers[1].depth = -1.0"),
    ([{"depth": 1.0, "E": -2e6, "nu": 0.3}], {}, "soil.layers[1].E = -2000000.0"),
    ([{"depth": 1.0, "E": float("nan"), "nu": 0.3}], {}, "soil.layers[1].E: must be a finite"),
    ([{"depth": 2.0, "E": 2e6, "nu": 0.3}, {"depth": 1.0, "E": 2e6, "nu": 0.3}], {},
     "soil.layers[2].depth = 1.0 m is not below"),
    ([{"depth": 1.0, "E": 2e6, "nu": 0.3, "hyperbolic_a": 1e-7}], {},
     "soil.layers[1].hyperbolic_a: only used"),
    ([{"depth": 1.0, "nu": 0.3, "hyperbolic_a": 1e-7}],
     {"model": "hyperbolic", "hyperbolic_a": 1e-7, "hyperbolic_b": 1e-5},
     "soil.layers[1].hyperbolic_b: missing"),
    ({"depth": 1.0}, {}, "soil.layers: a list of tables"),
    ([{"depth": 1.0, "E": 2e6, "nu": 0.49}], {"nu": 0.3}, "mesh.degree = 1 with soil nu"),
])
def test_bad_layers_are_refused(layers, soil, expected):
    data = _layers_scene(layers, **soil)
    if "model" in soil:
        data["soil"].pop("E")
    if expected.startswith("mesh.degree"):
        data["mesh"] = {"degree": 1}
    with pytest.raises(SceneError, match=None) as err:
        Scene.from_dict(data)
    assert expected in str(err.value), str(err.value)


def test_layer_below_the_rigid_base_is_refused():
    data = _layers_scene([{"depth": 5.0, "E": 2e6, "nu": 0.3}])
    data["domain"] = {"depth": 5.0}
    with pytest.raises(SceneError, match=r"soil.layers\[1\].depth = 5.0 m: at or below"):
        Scene.from_dict(data)


def test_iterative_solver_refuses_a_mixed_layer():
    data = _layers_scene([{"depth": 1.0, "E": 2e6, "nu": 0.5}])
    data["solver"] = {"method": "iterative"}
    with pytest.raises(SceneError, match="solver.method"):
        Scene.from_dict(data)


def test_figures_of_layered_ground(tmp_path):
    """`tankfx run`'s figures of a layered scene: the section with the layers' tops drawn
    (sampled from the deformed soil), and the settlement profile."""
    from tankfx.results.figures import write_figures

    scene = flexible_scene(soil={"layers": [{"depth": 0.5, "E": 2e6, "nu": 0.5},
                                            {"depth": 2.0, "E": 30e6, "nu": 0.3}]})
    paths = write_figures(analyse(scene.with_coarse_mesh()), tmp_path)
    assert [p.name for p in paths] == ["section.png", "settlement.png"]
    assert all(p.stat().st_size > 10_000 for p in paths)


def test_iterative_solver_on_layered_ground():
    """The iterative solver (GAMG on the soil's Schur complement) on a tank over three
    layers of contrast 15: the direct solution to 1e-8."""
    soil = {"E": 10e6, "nu": 0.3, "layers": [{"depth": 0.5, "E": 2e6, "nu": 0.45},
                                             {"depth": 2.0, "E": 30e6, "nu": 0.25}]}
    scene = Scene.from_dict(small_tank(soil=soil))
    direct = analyse(scene).results
    iterative = analyse(scene.with_changes(solver={"method": "iterative"})).results
    for key in ("w0", "wd", "M0"):
        assert iterative[key] == pytest.approx(direct[key], rel=1e-8), key
