"""State that a stage carries (tankfx.model.history): committed and rolled back exactly, per
cell and at the quadrature points of the soil's forms, whose points are the forms' own."""
from __future__ import annotations

import numpy as np
import pytest
import ufl
from dolfinx import fem, mesh
from mpi4py import MPI

from tankfx.fem.evaluate import allsum
from tankfx.model.history import History, quadrature_measure, quadrature_space


@pytest.fixture(scope="module")
def square():
    return mesh.create_unit_square(MPI.COMM_WORLD, 6, 5, mesh.CellType.triangle)


@pytest.mark.parametrize("degree", [1, 2, 3])
def test_the_quadrature_space_holds_the_forms_points(square, degree):
    """A value at the quadrature points, integrated with the forms' measure, is the forms'
    integral of what it was sampled from: r^(2p) sampled into the space and integrated
    weighted by r gives the exact 1 / (2p + 2) of the unit square (the forms' rule is exact
    to degree 2p + 1)."""
    Q = quadrature_space(square, degree)
    x = ufl.SpatialCoordinate(square)
    f = fem.Function(Q)
    f.interpolate(fem.Expression(x[0] ** (2 * degree), Q.element.interpolation_points))
    dx = quadrature_measure(square, degree)
    value = allsum(square.comm, fem.assemble_scalar(fem.form(f * x[0] * dx)))
    assert value == pytest.approx(1.0 / (2 * degree + 2), rel=1e-13)


def test_commit_and_rollback_restore_exactly(square):
    Q = quadrature_space(square, 2, (4,))
    D = fem.functionspace(square, ("DG", 0))
    stress, modulus = fem.Function(Q), fem.Function(D)
    rng = np.random.default_rng(1)
    stress.x.array[:] = rng.standard_normal(stress.x.array.size)
    modulus.x.array[:] = 1.0 + rng.random(modulus.x.array.size)
    history = History()
    history.register("stress", stress)
    history.register("E", modulus)
    start = stress.x.array.copy(), modulus.x.array.copy()
    stress.x.array[:] *= 3.0                 # a step that fails: back to the start
    modulus.x.array[:] = 0.0
    history.rollback()
    assert np.array_equal(stress.x.array, start[0]) and np.array_equal(modulus.x.array,
                                                                       start[1])
    stress.x.array[:] += 1.0                 # a step that converges: committed
    history.commit()
    converged = stress.x.array.copy()
    stress.x.array[:] = np.nan
    history.rollback()
    assert np.array_equal(stress.x.array, converged)
    assert "stress" in history and "nu" not in history
    with pytest.raises(ValueError, match="carried already"):
        history.register("E", modulus)


def test_a_model_rolls_back_its_interface_states_and_soil_memory():
    """The model's commit and rollback carry the interface's states and coefficients and a
    remembering soil's memory: a Mohr-Coulomb tank solved from its committed stuck start
    and rolled back is stuck again, coefficient for coefficient; committed after the solve,
    it rolls back to the solved states."""
    from tankfx import Scene
    from tankfx.fem.solvers import make_solver
    from tankfx.iterations.stage import StageIterations
    from tankfx.laws.interface import ContactState
    from tankfx.mesh import build_domain
    from tankfx.model.build import build_model
    from conftest import HYPERBOLIC_SOIL, small_tank

    class Quiet:
        def info(self, *args):
            pass

    scene = Scene.from_dict(small_tank(
        soil=HYPERBOLIC_SOIL | {"unloading_modulus_ratio": 3.0},
        interface={"condition": "mohr_coulomb", "friction_angle": 10.0},
        load={"pressure": 100e3}) | {"stages": [{}, {}]})
    model = build_model(scene, build_domain(scene))
    solver = make_solver(scene.solver, model.a, model.L, model.bcs, model.unknowns,
                         entity_maps=model.entity_maps, name="rollback", symmetric=False)
    ifc, soil = model.interface, model.soil
    carried = {**ifc.history.fields, **soil.history.fields}
    assert {"status", "k_s", "mu", "was_separated", "E", "peak_strain",
            "peak_u"} <= set(carried)

    def values():
        return {n: (f if isinstance(f, np.ndarray) else f.x.array).copy()
                for n, f in carried.items()}

    model.commit()
    start = values()
    iterations = StageIterations.of(scene, model, solver)
    model.begin_stage()
    iterations.begin_stage()
    statuses = iterations.run(Quiet())
    assert statuses["soil"].converged and statuses["interface"].converged
    own = ifc.n_carrier_owned
    slipped = MPI.COMM_WORLD.allreduce(int(np.sum(ifc.status[:own] != ContactState.STICK)
                                           - np.sum(~ifc.in_contact[:own])))
    assert slipped > 0, "the test needs states that changed"
    solved = values()
    for name in ("E", "peak_strain", "k_s"):
        assert not np.array_equal(solved[name], start[name]), name
    model.rollback()
    for name, v in values().items():
        assert np.array_equal(v, start[name]), name
    assert np.all(ifc.status[ifc.in_contact] == ContactState.STICK)
    # (the solved state committed: the rollback returns to it)
    for name, field in carried.items():
        (field if isinstance(field, np.ndarray) else field.x.array)[...] = solved[name]
    model.commit()
    soil.E.x.array[:] = 0.0
    ifc.status[:] = ContactState.SEPARATED
    model.rollback()
    for name, v in values().items():
        assert np.array_equal(v, solved[name]), name
