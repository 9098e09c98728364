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
