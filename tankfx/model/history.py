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


class History:
    """Named fields (``fem.Function``: DG0 per cell, or at quadrature points) and their last
    committed values."""

    def __init__(self):
        self.fields: dict[str, fem.Function] = {}
        self._committed: dict[str, object] = {}

    def register(self, name: str, field: fem.Function) -> None:
        """Carry ``field`` under ``name``, committed as it is now."""
        if name in self.fields:
            raise ValueError(f"a field named {name!r} is carried already")
        self.fields[name] = field
        self._committed[name] = field.x.array.copy()

    def commit(self) -> None:
        """The fields as they are now are the state to go on from."""
        for name, field in self.fields.items():
            self._committed[name][:] = field.x.array

    def rollback(self) -> None:
        """Every field back to its last committed values (ghosts included: no scatter
        needed)."""
        for name, field in self.fields.items():
            field.x.array[:] = self._committed[name]

    def __contains__(self, name: str) -> bool:
        return name in self.fields
