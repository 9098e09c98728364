"""State that a stage carries: fields that persist across load stages and load steps, with
an explicit commit (the step converged: this is the state to go on from) and rollback (the
step failed or is cut back: start it again from the last committed state).

A field of state at the quadrature points of the soil's forms lives in
:func:`quadrature_space`: the points and weights of the ``dx`` the forms integrate with
(the same degree, the default scheme). A state on other points than the forms' would be
read at the wrong places without any error, so the space is made here, from the same
degree, and nowhere else.
"""
from __future__ import annotations

import basix.ufl
import numpy as np
import ufl
from dolfinx import fem

from ..laws.elasticity import quadrature_degree


def quadrature_space(mesh, mesh_degree: int, shape: tuple[int, ...] = ()) -> fem.FunctionSpace:
    """The space of values at the quadrature points of the soil's forms on a mesh of
    Lagrange ``mesh_degree`` (:func:`tankfx.laws.elasticity.quadrature_degree`), of
    ``shape`` per point (() a scalar, (4,) a stress's (rr, zz, rz, theta))."""
    element = basix.ufl.quadrature_element(mesh.basix_cell(), value_shape=shape,
                                           degree=quadrature_degree(mesh_degree))
    return fem.functionspace(mesh, element)


def quadrature_measure(mesh, mesh_degree: int) -> ufl.Measure:
    """The ``dx`` whose points :func:`quadrature_space` holds."""
    return ufl.Measure("dx", domain=mesh,
                       metadata={"quadrature_degree": quadrature_degree(mesh_degree)})


def _values(field) -> np.ndarray:
    """The array a carried field's values are in (a Function's, or the array itself)."""
    return field if isinstance(field, np.ndarray) else field.x.array


class History:
    """Named fields (``fem.Function``: DG0 per cell, or at quadrature points; or a numpy
    array per local cell or carrier, changed in place) and their last committed values."""

    def __init__(self):
        self.fields: dict[str, object] = {}
        self._committed: dict[str, np.ndarray] = {}

    def register(self, name: str, field) -> None:
        """Carry ``field`` under ``name``, committed as it is now."""
        if name in self.fields:
            raise ValueError(f"a field named {name!r} is carried already")
        self.fields[name] = field
        self._committed[name] = _values(field).copy()

    def commit(self) -> None:
        """The fields as they are now are the state to go on from."""
        for name, field in self.fields.items():
            self._committed[name][...] = _values(field)

    def rollback(self) -> None:
        """Every field back to its last committed values (ghosts included: no scatter
        needed)."""
        for name, field in self.fields.items():
            _values(field)[...] = self._committed[name]

    def snapshot(self) -> dict[str, np.ndarray]:
        """A copy of the committed values, to return to with :meth:`restore` past later
        commits (a collapse search run from a stage's converged state)."""
        return {name: v.copy() for name, v in self._committed.items()}

    def restore(self, snapshot: dict[str, np.ndarray]) -> None:
        """The fields and their committed values as ``snapshot`` holds them."""
        for name, values in snapshot.items():
            self._committed[name][...] = values
        self.rollback()

    def __contains__(self, name: str) -> bool:
        return name in self.fields
