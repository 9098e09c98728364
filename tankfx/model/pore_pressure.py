"""The excess pore pressure of a consolidating soil (Biot): its blocks on the soil's
displacement (:func:`tankfx.laws.biot.biot_forms`), one degree below it, its drained
boundaries by Nitsche's method (the ground surface, a flexible load's loaded area, the base
if it drains, the faces of a ringwall's draining fill), and the fields a time step changes:
``conductance`` (dt k / gamma_w), ``step_weights`` (BDF2) and the earlier states ``u_n``,
``u_nn``.
"""
from __future__ import annotations

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ..fem.blocks import cell_field
from ..laws import biot as cf
from ..laws import elasticity as soil_forms
from ..mesh import FACET_TAGS

__all__ = ["PorePressure", "fill_faces_of"]


class PorePressure:
    """Biot's blocks of a soil block (``block``: its spaces, materials and measures)."""

    def __init__(self, block, msh):
        """Biot's blocks (tankfx.laws.biot) for the excess pore pressure, one degree
        below the displacement, with the drained boundaries by Nitsche's method; the time
        step enters through ``conductance`` (dt k / gamma_w) and ``step_weights``, the
        earlier states through ``u_n``, ``u_nn``."""
        setting = block.setting
        c, deg = setting.consolidation, setting.degree
        Q = fem.functionspace(msh, ("Lagrange", deg - 1))
        p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        #: dt_eff / gamma_w (s m^3/N), times each stratum's permeability in the forms
        self.conductance = fem.Constant(msh, 0.0)
        strata = setting.soil.strata
        k, _ = cf.stratum_coefficients(c, strata)
        # a ringwall (and its fill) has no pore pressure: k 0 there (its own materials
        # follow the ground's strata)
        k += [0.0] * (block.n_materials - len(strata))
        #: Darcy's k (m/s): one value, or per cell by stratum (layers, a ringwall)
        self.permeability = fem.Constant(msh, k[0]) if block.n_materials == 1 else \
            cell_field(msh, np.array(k)[block.stratum], "permeability")
        self.step_weights = w = cf.StepWeights(msh)
        self.u_n, self.u_nn = (fem.Function(block.V, name=n) for n in ("u_n", "u_nn"))
        flow = self.conductance * self.permeability
        #: the ground's strata: where the pore water is (not a ringwall's concrete, nor
        #: its fill, which drains)
        self.ground = block.ground
        dx_ground = block.dx_strata(self.ground)
        _, a_up, a_pu, a_pp = cf.biot_forms(block.trial, p, block.test, q, block.E, block.nu,
                                            flow, block.r, dx_ground)
        a_uu = soil_forms.stiffness_form(block.trial, block.test, block.E, block.nu, block.r,
                                         block.dx)
        drained = ["surface"] + (["contact"] if setting.contact_drains else []) + \
            (["bottom"] if c.drainage == "top_and_bottom" else [])
        ds = ufl.Measure("ds", domain=msh, subdomain_data=block.domain.facet_tags)
        a_pp += cf.drainage_form(p, q, flow, block.r,
                                 ds(tuple(FACET_TAGS[n] for n in drained)), deg - 1)
        fill_faces = fill_faces_of(block, self.ground, msh)
        if fill_faces is not None:
            # a ringwall's fill drains: the ground's faces on it are drained boundaries,
            # from the ground's side (the fill's own pore pressure is pinned to 0)
            chi = block.in_ground
            a_pp += sum(cf.drainage_form(p(side), q(side), flow(side), block.r,
                                         fill_faces, deg - 1, side=side, weight=chi(side))
                        for side in ("+", "-"))
        others = block.dx_outside(self.ground)
        if others is not None:
            # (the pressure dofs there are pinned, see pins: a zero term gives their
            # Dirichlet rows a diagonal)
            a_pp += fem.Constant(msh, 0.0) * p * q * others
        #: the displacement block (Biot's skeleton, over every material)
        self.a = a_uu
        #: (the pore pressure, its blocks (a_up, a_pu, a_pp), its load: the earlier states)
        self.block = (fem.Function(Q, name="pore_pressure"), (a_up, a_pu, a_pp),
                      cf.previous_volume_load([(w.previous, self.u_n), (w.before, self.u_nn)],
                                              q, block.r, dx_ground))


def fill_faces_of(block, ground_strata, msh):
    """The interior-facet measure of the faces between a ringwall's fill and the ground
    (None without a fill, on every rank alike)."""
    if not msh.comm.allreduce(bool(block.fill_cells.any()), op=MPI.LOR):
        return None
    tdim = msh.topology.dim
    msh.topology.create_connectivity(tdim - 1, tdim)
    f2c = msh.topology.connectivity(tdim - 1, tdim)
    n = msh.topology.index_map(tdim - 1).size_local + \
        msh.topology.index_map(tdim - 1).num_ghosts
    ground = np.isin(block.stratum, ground_strata)
    ground[block.domain.cells("void")] = False
    fill, start = block.fill_cells, f2c.offsets[:n]
    two = np.flatnonzero(np.diff(f2c.offsets)[:n] == 2)     # interior facets
    c0, c1 = f2c.array[start[two]], f2c.array[start[two] + 1]
    faces = two[(fill[c0] & ground[c1]) | (fill[c1] & ground[c0])].astype(np.int32)
    tags = dmesh.meshtags(msh, tdim - 1, faces, np.ones(len(faces), dtype=np.int32))
    return ufl.Measure("dS", domain=msh, subdomain_data=tags)(1)
