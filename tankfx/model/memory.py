"""A nonlinear soil's memory along a load path: the cells whose strain falls below the largest
they have had unload along a line of the unloading modulus E_ur and keep their permanent
strain; what each cell remembers between the stages.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem

#: A cell that has changed between its loading curve and its unloading line this many times
#: in one stage's iteration is held on the curve. Measured on the Fig. 13 tank filled in
#: steps (coarse mesh), with a margin of 1e-3 to rejoin the curve (see unloading_cells): a
#: few far-field cells (strains of 2e-7) whose strain barely moved from one stage to the
#: next flipped at every iteration, 5 % either side of their largest, and the iteration did
#: not converge in 40. With the margin at the tolerance none flips there at 0.05, a few at
#: 0.002 (tests/test_unloading.py).
MAX_SWITCHES = 4


def unloading_cells(eps_p, eps_p_max, unloading, margin):
    """Per cell, whether it follows its unloading line: a cell on the loading curve unloads
    where its eps_p falls below its largest so far; an unloading cell stays on its line
    until eps_p passes that largest by the fraction ``margin`` (a cell never loaded stays
    on the curve).

    The margin is the iteration's tolerance (Eq. 18): a cell's most loaded state is known
    to that precision (its modulus within the tolerance of its law), so a reloading to the
    same load lands within about as much of it. Without it (a margin of 1e-3 was tried)
    the iterates of a reloading overshoot their cells' old states by a few per cent, those
    cells move to the softer curve and stay there: Duncan & Chang's tank filled again then
    did not converge, or settled 0.24 % short with 2163 cells held."""
    below = eps_p < eps_p_max * np.where(unloading, 1.0 + margin, 1.0)
    return below & (eps_p_max > 0.0)


class UnloadingMemory:
    """Each soil cell's most loaded state along a load path, and the fields that put its
    unloading line into the forms (the soil block's ``initial_stress``): ``peak_modulus``
    E_p, ``peak_nu`` and ``unloading`` (1 on the line, 0 on the loading curve) as DG0
    fields, ``peak_u`` the displacement of each cell's most loaded state (discontinuous:
    cells reach theirs at different stages) and, for the mixed form (``pressure``: the
    expression of each cell's pressure), ``peak_p`` its pressure (discontinuous, a degree
    below)."""

    def __init__(self, modulus: fem.Function, degree: int, ratio: float, pressure=None):
        Q = modulus.function_space
        msh = Q.mesh
        self.ratio = ratio
        self.peak_modulus = fem.Function(Q, name="peak_secant_modulus")
        self.peak_nu = fem.Function(Q, name="peak_poisson_ratio")
        self.unloading = fem.Function(Q, name="unloading")
        V = fem.functionspace(msh, ("DG", degree, (2,)))
        self.peak_u = fem.Function(V, name="peak_displacement")
        self._u = fem.Function(V)
        n = msh.topology.index_map(2).size_local + msh.topology.index_map(2).num_ghosts
        #: per local cell (cell order): the largest eps_p so far, and the stress then at
        #: the centroid ((rr, zz, rz, theta); Duncan & Chang's soil)
        self.peak_strain = np.zeros(n)
        self.peak_stress = np.zeros((n, 4))
        self._dof_Q = Q.dofmap.list[:, 0]
        self._dofs_V = _cell_dofs(V, n)
        self.peak_p = self._p = self._p_expr = None
        if pressure is not None:
            P = fem.functionspace(msh, ("DG", degree - 1))
            self.peak_p, self._p = fem.Function(P, name="peak_pressure"), fem.Function(P)
            self._p_expr = fem.Expression(pressure, P.element.interpolation_points)
            self._dofs_P = _cell_dofs(P, n)

    def carried(self) -> dict:
        """What it remembers, by name, for the soil's history to commit and roll back."""
        fields = {"peak_modulus": self.peak_modulus, "peak_nu": self.peak_nu,
                  "unloading": self.unloading, "peak_u": self.peak_u,
                  "peak_strain": self.peak_strain, "peak_stress": self.peak_stress}
        if self.peak_p is not None:
            fields["peak_p"] = self.peak_p
        return fields

    @property
    def unloading_mask(self) -> np.ndarray:
        return self.unloading.x.array[self._dof_Q] > 0.5

    def set_unloading(self, mask: np.ndarray) -> None:
        self.unloading.x.array[self._dof_Q] = mask.astype(float)

    def commit(self, u: fem.Function, eps_p: np.ndarray, E: np.ndarray, nu: np.ndarray,
               cells, stress: np.ndarray | None = None) -> None:
        """A converged stage: the cells ``cells`` (bool, cell order) on the loading curve
        have reached their most loaded state so far; remember it (their strain measure,
        modulus, Poisson's ratio, displacement and pressure; and their stress at the
        centroid, ``stress``, which Duncan & Chang's unloading modulus reads)."""
        if stress is not None:
            self.peak_stress[cells] = stress[cells]
        self._u.interpolate(u)
        self.peak_strain[cells] = eps_p[cells]
        self.peak_modulus.x.array[self._dof_Q[cells]] = E[cells]
        self.peak_nu.x.array[self._dof_Q[cells]] = np.broadcast_to(nu, E.shape)[cells]
        dofs = self._dofs_V[cells].reshape(-1)
        self.peak_u.x.array[dofs] = self._u.x.array[dofs]
        if self._p is not None:
            self._p.interpolate(self._p_expr)
            dofs = self._dofs_P[cells].reshape(-1)
            self.peak_p.x.array[dofs] = self._p.x.array[dofs]


def _cell_dofs(V, n_cells: int) -> np.ndarray:
    """Per local cell, the indices into a function's array of its dofs (blocks unrolled)."""
    bs = V.dofmap.index_map_bs
    return (bs * V.dofmap.list[:, :, None] + np.arange(bs)).reshape(n_cells, -1)
