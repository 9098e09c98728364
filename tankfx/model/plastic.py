"""The elastoplastic soil's state at the quadrature points of the soil's forms, and the forms
that read it.

Newton's method in the form the block system solves: with the tangent C and the stress
sigma of the current iterate u_k at the points, held as its change from the ground at rest
sigma_0 (its weight equilibrates sigma_0, so only the change enters the forms),

    a(du, v) = int eps(du) . C eps(v) 2 pi r dx,
    L(v)     = f(v) - int (sigma - sigma_0 - C eps(u_k)) . eps(v) 2 pi r dx,

so that a linear solve gives u_{k+1} = u_k - K_t^-1 R(u_k) (the same system the other soils
solve: the structure, the interface and the loads are unchanged), and a(u, v) - L(v) at the
updated state is the true residual. Vectors are Mandel's (rr, zz, sqrt 2 rz, theta): the
products are dot products. Before anything is loaded the residual is zero and the
displacement stays zero.

The state (:class:`tankfx.model.history.History`): the committed stress, strain, plastic
strain and plastic flag, and the tangent of the committed state; a load step commits it when
it converges and rolls back to it when it is cut back.
"""
from __future__ import annotations

import math

import basix
import numpy as np
import ufl
from dolfinx import fem

from ..fem.timing import timed
from ..laws import elasticity as soil_forms
from ..laws.plasticity import principal
from .history import quadrature_space


def mandel(t):
    """(rr, zz, sqrt 2 rz, theta) of an axisymmetric tensor (UFL)."""
    return ufl.as_vector([t[0, 0], t[1, 1], math.sqrt(2.0) * t[0, 1], t[2, 2]])


def tensor(s):
    """The 3 x 3 tensor (r, z, theta) of a Mandel vector (UFL)."""
    rz = s[2] / math.sqrt(2.0)
    return ufl.as_tensor([[s[0], rz, 0.0], [rz, s[1], 0.0], [0.0, 0.0, s[3]]])


class PlasticState:
    """The stress, tangent and history of an elastoplastic soil at its forms' quadrature
    points (``block``: the soil block, whose space, radius and measure it shares; ``law``,
    ``soil``: the law and the resolved [soil]; ``ring``: a ringwall whose cells stay elastic
    and unbroken, or None)."""

    def __init__(self, block, law, soil, degree: int, ring=None):
        msh = block.domain.mesh
        self.block, self.law = block, law
        self.S4 = quadrature_space(msh, degree, (4,))
        self.S44 = quadrature_space(msh, degree, (4, 4))
        self.S1 = quadrature_space(msh, degree)
        f = fem.Function
        #: the current iterate's stress (its change from the ground at rest: a deep point's
        #: total, of gigapascals in a half-space of kilometres, would carry its round-off
        #: into the out-of-balance force) and tangent, and the change - C eps(u) (the load's
        #: part)
        self.stress, self.tangent = f(self.S4, name="stress"), f(self.S44, name="tangent")
        self.offset = f(self.S4, name="stress_offset")
        #: the committed state's stress, strain, plastic strain and plastic flag (1: yielding)
        self.stress_n = f(self.S4, name="committed_stress")
        self.strain = f(self.S4, name="strain")
        self.plastic_strain = f(self.S4, name="plastic_strain")
        self.plastic = f(self.S1, name="plastic")
        #: the geostatic stress, at rest (its load equilibrates it)
        self.geostatic = f(self.S4, name="geostatic_stress")
        imap = msh.topology.index_map(2)
        self.cells = np.arange(imap.size_local + imap.num_ghosts, dtype=np.int32)
        points = self.S4.element.interpolation_points
        self.n_points = len(points)
        x = fem.Expression(ufl.SpatialCoordinate(msh), points).eval(msh, self.cells)
        x = x.reshape(-1, 2)
        depth = -x[:, 1]
        #: each point's depth below the ground surface, m
        self.depth = depth
        #: the law at the points (tankfx.laws.point_law.PointLaw)
        points_law = law.point_law(soil, depth)
        # the points of the cells that carry no soil (an excavation, the tank's inside)
        # never yield: their strains are no soil's
        void = np.ones(len(self.cells), dtype=bool)
        void[block.domain.cells("soil")] = False
        #: per point, whether it is the soil's (not the void's)
        self.in_soil = np.repeat(~void, self.n_points)
        points_law = points_law.elastic_where(~self.in_soil)
        if ring is not None:
            # a ringwall's (and its fill's) points: its own elasticity, never yielding
            in_ring = np.repeat(block.ringwall_cells, self.n_points)
            in_fill = np.repeat(block.fill_cells, self.n_points)
            for mask, E, nu in ((in_ring, ring.E, ring.nu), (in_fill, ring.fill_E, ring.fill_nu)):
                if mask.any():
                    points_law = points_law.elastic_where(mask, E, nu)
        self.points = points_law
        # the dofs of each point's values, in point order (cell by cell)
        dofs = self.S1.dofmap.list[self.cells].reshape(-1)
        self._dofs4 = (4 * dofs[:, None] + np.arange(4)).reshape(-1)
        self._dofs16 = (16 * dofs[:, None] + np.arange(16)).reshape(-1)
        self._dofs1 = dofs
        self._strain_expr = fem.Expression(mandel(soil_forms.strain(block.u, block.r)), points)
        self._put(self.geostatic, self.points.initial_stress(), self._dofs4)
        self._put(self.tangent, self.points.elastic_matrix().reshape(-1, 16), self._dofs16)
        #: the law's own state (committed; its trial in the update), each a field of
        #: values at the points
        self.own = {name: f(quadrature_space(msh, degree, (w,)), name=name)
                    for name, w in self.points.state.items()}
        self._dofs_w = {w: (w * dofs[:, None] + np.arange(w)).reshape(-1)
                        for w in set(self.points.state.values())}
        for name, values in self.points.initial_state().items():
            self._put(self.own[name], values, self._dofs_w[self.points.state[name]])
        #: per point, whether the current iterate yields
        self.yielding = np.zeros(len(depth), dtype=bool)
        # the rule's weights (the points' own: quadrature_space's default scheme)
        points_, self.weights = basix.make_quadrature(msh.basix_cell(),
                                                      soil_forms.quadrature_degree(degree))
        assert np.allclose(points_, points), "the rule's points are not the space's"
        T = fem.functionspace(msh, ("DG", 0, (4,)))
        self._cell_stress = fem.Function(T, name="cell_stress")
        self._cell_dofs = (4 * T.dofmap.list[self.cells, 0][:, None] + np.arange(4)).reshape(-1)
        self._trial = None

    @staticmethod
    def _put(field, values, dofs):
        field.x.array[dofs] = np.asarray(values).reshape(-1)

    def _get(self, field, dofs, width):
        return field.x.array[dofs].reshape(-1, width)

    def carried(self) -> dict:
        """What a stage carries, for the soil's history."""
        return {"stress": self.stress, "tangent": self.tangent, "stress_offset": self.offset,
                "committed_stress": self.stress_n, "strain": self.strain, "plastic_strain": self.plastic_strain,
                "plastic": self.plastic, **self.own}

    def use(self, points) -> None:
        """The law at the points from now on (the same points: a reduced strength)."""
        self.points = points

    def _own_state(self) -> dict:
        return {name: self._get(field, self._dofs_w[self.points.state[name]],
                                self.points.state[name])
                for name, field in self.own.items()}

    # ---- the forms ---------------------------------------------------------------------
    def stiffness(self, trial, test, r, dx):
        """a(du, v): the tangent's."""
        C = ufl.as_matrix([[self.tangent[i, j] for j in range(4)] for i in range(4)])
        return ufl.inner(C * mandel(soil_forms.strain(trial, r)),
                         mandel(soil_forms.strain(test, r))) * 2.0 * math.pi * r * dx

    def load(self, test, r, dx):
        """-int (sigma - sigma_0 - C eps(u_k)) . eps(v) 2 pi r dx: the stress's change from
        the ground at rest sigma_0, whose own forces the soil's weight equilibrates."""
        return -ufl.inner(self.offset, mandel(soil_forms.strain(test, r))) \
            * 2.0 * math.pi * r * dx

    def stress_tensor(self):
        """The current stress (3 x 3, UFL, tension positive), at the quadrature points."""
        return tensor(self.stress + self.geostatic)

    # ---- the update --------------------------------------------------------------------
    def update(self) -> dict:
        """The stress and tangent of the current displacement from the committed state, at
        every point (the law's :meth:`~tankfx.laws.point_law.PointLaw.update`), and the
        offset sigma - C eps(u) the next solve's load reads. Returns the count of plastic
        points."""
        with timed("return"):
            eps = self._strain_expr.eval(self.block.domain.mesh, self.cells).reshape(-1, 4)
            trial = self.points.update(eps - self._get(self.strain, self._dofs4, 4),
                                       self._get(self.stress_n, self._dofs4, 4),
                                       self._own_state())
        sigma, C = trial.stress, trial.tangent
        self._put(self.stress, sigma, self._dofs4)
        self._put(self.tangent, C.reshape(-1, 16), self._dofs16)
        self._put(self.offset, sigma - (C @ eps[..., None])[..., 0], self._dofs4)
        self.yielding = trial.yielding
        self._trial = (eps, trial)
        return {"plastic_points": int(np.sum(trial.yielding))}

    def elastic_predictor(self) -> None:
        """The next solve with the elastic stiffness from the committed state (offset
        sigma_n - D eps_n): exact where the step unloads, which the committed state's
        plastic tangent is not."""
        sigma_n = self._get(self.stress_n, self._dofs4, 4)
        D = self.points.elastic_matrix(sigma_n)
        self._put(self.tangent, D.reshape(-1, 16), self._dofs16)
        eps_n = self._get(self.strain, self._dofs4, 4)
        self._put(self.offset, sigma_n - (D @ eps_n[..., None])[..., 0], self._dofs4)

    def commit(self) -> None:
        """The current iterate is converged: its strain, stress, plastic strain and flag are
        the state to go on from."""
        eps, trial = self._trial
        self._put(self.strain, eps, self._dofs4)
        self.stress_n.x.array[:] = self.stress.x.array
        if trial is not None:
            self._put(self.plastic_strain, self._get(self.plastic_strain, self._dofs4, 4)
                      + trial.plastic_strain, self._dofs4)
            for name, values in trial.state.items():
                self._put(self.own[name], values, self._dofs_w[self.points.state[name]])
        self._put(self.plastic, self.yielding.astype(float), self._dofs1)

    def restart_strain(self) -> None:
        """The displacement is set to zero with the stress kept (a structure built on an
        excavated ground): the committed strain is zero, and the current state is the
        committed one, with its offset sigma - C eps(0) = sigma."""
        self.strain.x.array[:] = 0.0
        self.stress.x.array[:] = self.stress_n.x.array
        self.offset.x.array[:] = self.stress_n.x.array
        self._trial = (np.zeros((len(self.yielding), 4)), None)

    def point_values(self, field) -> np.ndarray:
        """A scalar field's values at every point, in point order (cell by cell)."""
        return self._get(field, self._dofs1, 1)[:, 0]

    def cell_average(self, field, width: int) -> np.ndarray:
        """Each local cell's mean of a field over its points (the rule's weights), N x
        width, in cell order."""
        values = self._get(field, {4: self._dofs4, 1: self._dofs1}[width], width)
        values = values.reshape(len(self.cells), self.n_points, width)
        return np.einsum("cpw,p->cw", values, self.weights) / self.weights.sum()

    def cell_stress(self) -> fem.Function:
        """The stress as a DG0 Mandel field (each cell's mean): what the results read."""
        self._cell_stress.x.array[self._cell_dofs] = (
            self.cell_average(self.stress, 4) + self.cell_average(self.geostatic, 4)).reshape(-1)
        return self._cell_stress

    def plastic_shear_strain(self) -> np.ndarray:
        """eps_1^p - eps_3^p per point: the committed plastic strain's largest shear."""
        vals = principal(self._get(self.plastic_strain, self._dofs4, 4))[0]
        return vals.max(axis=1) - vals.min(axis=1)

    def cell_mobilised(self) -> np.ndarray:
        """tau / tau_f of each local cell's mean stress (its strength at its mean depth)."""
        mean = self.cell_average(self.stress, 4) + self.cell_average(self.geostatic, 4)
        return self.points.mobilised(mean, per=self.n_points)

    def undrained_strength(self) -> np.ndarray | None:
        """s_u per point of the committed state, where the law defines one
        (:meth:`tankfx.laws.cam_clay_points.CamClayPoints.undrained_strength`), else None."""
        law = getattr(self.points, "undrained_strength", None)
        if law is None:
            return None
        stress = self._get(self.stress_n, self._dofs4, 4) + \
            self._get(self.geostatic, self._dofs4, 4)
        state = {name: self._get(f, self._dofs_w[self.points.state[name]],
                                 self.points.state[name]) for name, f in self.own.items()}
        return law(stress, state)

    def mobilised(self) -> np.ndarray:
        """tau / tau_f per point of the current stress (1 on the yield surface)."""
        return self.points.mobilised(self._get(self.stress, self._dofs4, 4)
                                     + self._get(self.geostatic, self._dofs4, 4))
