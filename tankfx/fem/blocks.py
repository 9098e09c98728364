"""Block-system helpers: an empty bilinear form (a diagonal block the block assembly needs),
a DG0 field of per-cell values, and the out-of-balance force of a block system.
"""
from __future__ import annotations

import math

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
import numpy as np
import ufl
from dolfinx import fem, la
from dolfinx import mesh as dmesh


def cell_field(msh, values: np.ndarray, name: str) -> fem.Function:
    """A DG0 field of per-cell values (in cell order)."""
    f = fem.Function(fem.functionspace(msh, ("DG", 0)), name=name)
    f.x.array[f.function_space.dofmap.list[:, 0]] = values
    return f


def empty_form(space: fem.FunctionSpace):
    """A bilinear form on ``space`` x ``space`` integrated over no cells: it assembles
    nothing, but gives a block system's part a diagonal block where the block assembly
    needs one (supports on it, or a row that would be empty)."""
    msh = space.mesh
    none = dmesh.meshtags(msh, msh.topology.dim, np.empty(0, np.int32), np.empty(0, np.int32))
    dx = ufl.Measure("dx", domain=msh, subdomain_data=none)
    return fem.Constant(msh, 0.0) * ufl.inner(ufl.TrialFunction(space),
                                              ufl.TestFunction(space)) * dx(1)


class OutOfBalance:
    """||A u - f|| / ||f|| of a block system's current fields: the out-of-balance force
    relative to the load vector, over all blocks, the supports' rows left out (zero, to
    round-off, at a solution of the current coefficients). Its forms are compiled once: per
    row the actions sum_j a_ij(u_j, v_i) (each a form of its own: a row's terms integrate
    over different meshes) and the load L_i(v_i), with the supports' dofs of each block."""

    def __init__(self, a: list, L: list, unknowns: list, bcs: list, entity_maps=None):
        rows = []
        for row, load in zip(a, L):
            actions = [fem.form(ufl.action(a_ij, u_j), entity_maps=entity_maps)
                       for a_ij, u_j in zip(row, unknowns) if isinstance(a_ij, ufl.Form)]
            rows.append((actions, fem.form(load, entity_maps=entity_maps)))
        spaces = fem.extract_function_spaces([load for _, load in rows])
        self.fixed = [np.unique(np.concatenate([bc.dof_indices()[0] for bc in row_bcs]))
                      if row_bcs else np.empty(0, np.int32)
                      for row_bcs in fem.bcs_by_block(spaces, bcs)]
        self.rows, self.unknowns = rows, unknowns
        self.comm = unknowns[0].function_space.mesh.comm
        #: the blocks' names (their unknowns'): "u" the soil's equilibrium, "pore_pressure"
        #: its flow, "structure" the shells'
        self.names = [u.name for u in unknowns]
        #: relative to the largest load vector so far rather than the current one (a load
        #: path in time, which may come to no load: an empty tank, whose load vector holds
        #: only round-off)
        self.relative_to_largest = False
        self._largest = 0.0
        self._largest_blocks = np.zeros(len(rows))
        self._largest_terms = np.zeros(len(rows))

    def blocks(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per block, the norms of its out-of-balance vector A_i u - f_i, of its load vector
        f_i and of its largest term (f_i or one of the a_ij(u_j): the scale of its
        round-off, the terms cancelling in balance), each in the block's own units (N for
        the equilibria, m^3 for the flow), over all ranks; the last two the largest so far
        where ``relative_to_largest``."""
        residual, load = np.zeros(len(self.rows)), np.zeros(len(self.rows))
        squares = []            # (block, each term's sum of squares on this rank)
        for i, ((actions, L), dofs, u) in enumerate(zip(self.rows, self.fixed, self.unknowns)):
            V = u.function_space
            n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
            vecs = []
            for f in [L] + actions:
                vec = fem.assemble_vector(f)
                vec.scatter_reverse(la.InsertMode.add)
                vec.array[dofs] = 0.0
                vecs.append(vec.array[:n])
            r = sum(vecs[1:]) - vecs[0]
            residual[i], load[i] = float(r @ r), float(vecs[0] @ vecs[0])
            squares += [(i, float(v @ v)) for v in vecs]
        residual, load = self.comm.allreduce(residual), self.comm.allreduce(load)
        # (each term's norm over all ranks, then the block's largest: the same on any
        # number of ranks)
        summed = self.comm.allreduce(np.array([s for _, s in squares]))
        terms = np.zeros(len(self.rows))
        for (i, _), s in zip(squares, summed):
            terms[i] = max(terms[i], s)
        if self.relative_to_largest:
            self._largest_blocks = load = np.maximum(load, self._largest_blocks)
            self._largest_terms = terms = np.maximum(terms, self._largest_terms)
        return np.sqrt(residual), np.sqrt(load), np.sqrt(terms)

    def vectors(self, values: list | None = None) -> list[np.ndarray]:
        """Per block, its out-of-balance vector A_i u - f_i on this rank's owned dofs (the
        supports' rows zero) of the fields now; with ``values`` (one array per unknown),
        the action A_i v of the current coefficients on them instead (the tangent's, where
        the forms hold one: what a Taylor test of the residual differentiates against)."""
        kept = None
        if values is not None:
            kept = [u.x.array.copy() for u in self.unknowns]
            for u, v in zip(self.unknowns, values):
                u.x.array[:] = v
        try:
            out = []
            for (actions, L), dofs, u in zip(self.rows, self.fixed, self.unknowns):
                V = u.function_space
                n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
                vecs = []
                for f in ([] if values is not None else [L]) + actions:
                    vec = fem.assemble_vector(f)
                    vec.scatter_reverse(la.InsertMode.add)
                    vec.array[dofs] = 0.0
                    vecs.append(vec.array[:n].copy())
                out.append(sum(vecs) if values is not None else sum(vecs[1:]) - vecs[0])
            return out
        finally:
            if kept is not None:
                for u, v in zip(self.unknowns, kept):
                    u.x.array[:] = v

    def __call__(self) -> float:
        """||A u - f|| / ||f|| over all blocks together."""
        residual, load, _ = self.blocks()
        total = float(np.sum(load ** 2))
        if self.relative_to_largest:
            self._largest = total = max(total, self._largest)
        return math.sqrt(float(np.sum(residual ** 2)) / max(total, 1e-300))


class Balanced:
    """The out-of-balance measures of a model that builds its :class:`OutOfBalance` as
    ``_out_of_balance``: the whole system's, per block, and per block as vectors."""

    def out_of_balance(self) -> float:
        """||A u - f|| / ||f||: the out-of-balance force of the current fields under the
        current coefficients, relative to the load vector (over all blocks, the supports'
        rows left out; zero, to round-off, at a converged state)."""
        return self._out_of_balance()

    def block_residuals(self) -> tuple[list[str], np.ndarray, np.ndarray]:
        """Per block: its name, the norm of its out-of-balance vector and of its largest
        term (:meth:`OutOfBalance.blocks`)."""
        residual, _, terms = self._out_of_balance.blocks()
        return self._out_of_balance.names, residual, terms

    def block_vectors(self, values=None) -> list[np.ndarray]:
        """Per block, its out-of-balance vector on this rank's dofs, or the current
        coefficients' action on ``values`` (:meth:`OutOfBalance.vectors`)."""
        return self._out_of_balance.vectors(values)
