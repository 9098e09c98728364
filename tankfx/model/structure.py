"""The structure's resultants as fields: the shell of :mod:`tankfx.laws.shell` solved, its
membrane forces, moments and shear force interpolated cell-wise (DG2) for point evaluation,
their expressions compiled once per model.
"""
from __future__ import annotations

import ufl
from dolfinx import fem

from ..laws.shell import bending_moments, membrane_forces, shell_strains


class ShellResultants:
    """The resultants of a shell ``w`` (mixed u, beta, Q) as cell-wise DG2 fields for point
    evaluation, their expressions compiled once: each call reads the current ``w`` (and the
    fields E, nu, thickness as they are then). A consolidation reads the foundation's
    results at every time step: compiling (or looking up the JIT cache for) the five
    expressions each time cost more than the step's assembly (2.0 of 22.5 s over 56 steps
    of the clay tank at 81k dofs)."""

    def __init__(self, w, r, t, E, nu, thickness, offset=0.0):
        u, b, Q = ufl.split(w)
        e = shell_strains(u, b, r, t, offset, on_axis=True)
        N_s, N_th = membrane_forces(e[0], e[1], E, nu, thickness)
        M_s, M_th = bending_moments(e[2], e[3], E, nu, thickness)
        self.w = w
        self.space = fem.functionspace(w.function_space.mesh, ("DG", 2))
        points = self.space.element.interpolation_points
        self.expressions = {name: fem.Expression(expr, points) for name, expr in
                            {"M_s": M_s, "M_theta": M_th, "N_s": N_s, "N_theta": N_th,
                             "Q": -Q}.items()}

    def __call__(self) -> dict:
        """M_s, M_theta, N_s, N_theta, the shear force Q (minus the multiplier), and the
        collapsed u and beta: new Functions at each call."""
        out = {}
        for name, expression in self.expressions.items():
            f = fem.Function(self.space, name=name)
            f.interpolate(expression)
            out[name] = f
        out["u"] = self.w.sub(0).collapse()
        out["beta"] = self.w.sub(1).collapse()
        return out


def shell_resultants(w, r, t, E, nu, thickness, offset=0.0) -> dict:
    """The resultants of a solved shell ``w`` once (see :class:`ShellResultants`)."""
    return ShellResultants(w, r, t, E, nu, thickness, offset)()
