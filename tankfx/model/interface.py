"""The interface block (Eqs. 6-16): the zero-thickness penalty interface between the soil and
the structure, where its states live (one per element, the paper's Eqs. 11-12, or one per node),
its stiffnesses (Eq. 9's k_n, k_s) and the traction coefficients of each carrier's state, the
facet measures it acts on, and the per-carrier averages of its jumps and tractions.

The law itself (the tractions of each state, the Mohr-Coulomb decision) is
:mod:`tankfx.laws.interface`; the active-set iteration that changes the states is
:mod:`tankfx.iterations.active_set`.
"""
from __future__ import annotations

import math
from functools import cached_property

import basix
import basix.ufl
import numpy as np
import ufl
from dolfinx import fem, la
from mpi4py import MPI

from ..fem.evaluate import allsum
from ..laws import interface
from ..laws import shell as st
from ..mesh import FACET_TAGS, Domain
from ..scene.sections import Interface
from .history import History
from .soil import SoilBlock

__all__ = ["InterfaceBlock", "POLLUTION_WARNING", "OVERSTIFF_WARNING", "CONDITIONING_WARNING"]

#: Warn when the interface compliance adds more than this fraction to the settlement ...
POLLUTION_WARNING = 1e-3
#: ... when the penalty exceeds the soil element's stiffness E / h by more than this: it then
#: ties the soil's quadratic trace to the structure's cubic one point by point (measured on
#: a bonded plate, Kp = 1: M0 -0.5 % at 10 x the default 1e3 E / h, -2.1 % at 100 x) ...
OVERSTIFF_WARNING = 3e4
#: ... and when it costs more than half of the solve's 16 digits.
CONDITIONING_WARNING = 1e8

#: Soil-side facet tags that carry the interface, with the soil's outward normal n and the
#: tangent t there (the structure's n and t on those cells).
_INTERFACE = {"contact": ((0.0, 1.0), (1.0, 0.0)), "wall_embedded": ((-1.0, 0.0), (0.0, 1.0))}


class InterfaceBlock:
    """The interface of a tank: its state carriers (elements or nodes) on the structure's
    submesh, their stiffnesses ``stiffness_n``, ``stiffness_s`` and states ``status``, the
    traction coefficients ``k_n``, ``k_s``, ``mu``, ``c_s`` (fields on the carriers' space
    ``S``) that realise the states in the forms, and the facet measures it acts on.

    ``settings`` is the scene's [interface], ``plate_radius`` (m) the foundation's (the
    scale of the penalty's pollution), ``embedded_wall`` whether a wall's outer face below
    ground is in contact; ``mesh`` is the structure's submesh, ``cell_tags`` its plate /
    wall tags, ``w`` the structure's unknown (its displacement is the interface's structure
    side) and ``soil`` the soil block (its displacement, the soil side; its setting gives
    the soil's modulus at the interface)."""

    def __init__(self, settings: Interface, plate_radius: float, embedded_wall: bool,
                 domain: Domain, soil: SoilBlock, sub, cell_tags, cell_midpoints,
                 w: fem.Function, entity_maps: list):
        self.domain, self.soil = domain, soil
        self.plate_radius, self.embedded_wall = plate_radius, embedded_wall
        self.entity_maps = entity_maps
        self.settings = settings
        self.mesh, self.cell_tags, self.cell_midpoints, self.w = sub, cell_tags, \
            cell_midpoints, w
        Q0 = fem.functionspace(sub, ("DG", 0))
        # ---- where the interface states live (their "carrier"): one per element (DG0, the
        # paper's Eqs. 11-12), or one per node of the soil's trace (DG_k with its nodes at the
        # k + 1 Gauss-Lobatto points of each facet, integrated by that rule: each state then
        # acts at exactly one quadrature point)
        ifc = settings
        self.node_states = ifc.has_states and ifc.states == "node"
        self.carrier_name = "node" if self.node_states else "element"
        if self.node_states:
            k = soil.setting.degree
            self.qmeta = {"quadrature_rule": "GLL", "quadrature_degree": 2 * k - 1}
            element = basix.ufl.element("Lagrange", sub.basix_cell(), k, discontinuous=True,
                                        lagrange_variant=basix.LagrangeVariant.gll_warped)
            self.S = fem.functionspace(sub, element)
        else:
            self.qmeta = {}
            self.S = Q0
        dofs = self.S.dofmap.list
        self.n_carrier = self.S.dofmap.index_map.size_local + \
            self.S.dofmap.index_map.num_ghosts
        self.n_carrier_owned = self.S.dofmap.index_map.size_local
        self.carrier_cell = np.empty(self.n_carrier, dtype=np.int32)
        self.carrier_cell[dofs.ravel()] = np.repeat(np.arange(len(dofs), dtype=np.int32),
                                                    dofs.shape[1])
        self.k_n, self.k_s, self.mu, self.c_s = self._penalty(cell_tags.values)
        # the node on the axis and its neighbour in its element (see cell_averages)
        x = self.S.tabulate_dof_coordinates()[:, 0]
        self.axis_carriers = np.flatnonzero(self.node_states & (np.abs(x) < 1e-12
                                                                * plate_radius))
        nearest = []
        for d in self.axis_carriers:
            others = [o for o in dofs[self.carrier_cell[d]] if o != d]
            nearest.append(min(others, key=lambda o: x[o]))
        self.axis_neighbours = np.array(nearest, dtype=np.int32)

        self.dx = ufl.Measure("dx", domain=sub, subdomain_data=cell_tags)(
            (st.PLATE, st.WALL_EMBEDDED), metadata=self.qmeta)
        self._jump_forms = None
        self.was_separated = np.zeros(self.n_carrier, dtype=bool)
        #: the carriers' states and the coefficients that realise them, and which were
        #: separated at the stage's start: committed with a converged stage, rolled back
        #: to start one again
        self.history = History()
        for name in ("status", "k_n", "k_s", "mu", "c_s", "was_separated"):
            self.history.register(name, getattr(self, name))

    @property
    def mohr_coulomb(self) -> bool:
        """Whether the interface has states to iterate (a Mohr-Coulomb interface)."""
        return self.settings.has_states

    def begin_stage(self) -> None:
        """Start a load stage: the states so far are the starting guess, and the carriers
        separated now are the ones that can be reported ``rebonded`` later."""
        self.was_separated[:] = self.status == interface.SEPARATED

    def set_stuck(self) -> None:
        """Every carrier in contact stuck, with the elastic stiffnesses: the states of a
        fresh analysis."""
        self.status[:] = np.where(self.in_contact, interface.STICK, interface.ContactState.NONE)
        for f, v in zip((self.k_n, self.k_s, self.mu, self.c_s),
                        (self.stiffness_n, self.stiffness_s, 0.0, 0.0)):
            f.x.array[:] = np.where(self.in_contact, v, 0.0)

    def status_field(self) -> fem.Function:
        """The states as a field on the carriers (rebonded where separated at the stage's
        start and closed now)."""
        status = fem.Function(self.S, name="status")
        closed = (self.status == interface.STICK) | (self.status == interface.SLIP)
        status.x.array[:] = np.where(self.was_separated & closed, interface.REBONDED,
                                     self.status)
        return status

    def _penalty(self, values):
        """Interface stiffnesses of the contact cells, per state carrier, and the traction
        coefficients (k_n, k_s, mu, c_s of :mod:`tankfx.laws.interface`) of their current state."""
        s, sub = self.soil.setting, self.mesh
        cells = np.arange(len(values), dtype=np.int32)
        mid = self.cell_midpoints
        h = sub.h(1, cells)
        # the soil's modulus at the facet (on a layer's top: that layer's, the soil below;
        # on a ringwall's top: the ringwall's)
        E_soil = s.soil.at_depth(-mid[:, 1])["E"]
        if s.ringwall is not None:
            # (the structure's facets lie on the soil's boundary: those inside the ring's
            # outline are on its top)
            ring = s.ringwall
            E_soil = np.where(ring.holds(mid[:, 0], mid[:, 1], s.embedment), ring.E, E_soil)
            E_soil = np.where(ring.fill_holds(mid[:, 0], mid[:, 1], s.embedment),
                              ring.fill_E or 0.0, E_soil)
        in_contact = (values == st.PLATE) | (values == st.WALL_EMBEDDED)
        default = interface.PENALTY_FACTOR * E_soil / h
        ifc = self.settings
        kn = np.full(len(values), ifc.normal_stiffness) if ifc.normal_stiffness else default
        ks = np.full(len(values), ifc.shear_stiffness) if ifc.shear_stiffness else kn
        self.warnings = self._penalty_warnings(E_soil, h, in_contact, kn, ks)
        # per carrier: the values of its cell
        cc = self.carrier_cell
        self.carrier_tag = values[cc]
        self.in_contact = in_contact[cc]
        self.stiffness_n = np.where(self.in_contact, kn[cc], 0.0)
        self.stiffness_s = np.where(self.in_contact, ks[cc], 0.0)
        fields = [fem.Function(self.S, name=n) for n in ("k_n", "k_s", "mu", "c_s")]
        fields[0].x.array[:] = self.stiffness_n
        fields[1].x.array[:] = 0.0 if ifc.condition == "smooth" else self.stiffness_s
        self.status = np.where(self.in_contact, interface.STICK, interface.ContactState.NONE)
        return fields

    def _penalty_warnings(self, E_soil, h, in_contact, stiffness_n, stiffness_s) -> list[str]:
        """Where the interface stiffness spoils the result: its own compliance 1/k adds about
        E / (k a) of the settlement p a / E (pollution); a stiffness far above the soil
        element's E / h over-constrains the structure to the soil's coarser trace, and costs
        about log10(k h / E) of the 16 digits of the solve."""
        comm = self.mesh.comm
        n_owned = self.mesh.topology.index_map(1).size_local
        on = in_contact[:n_owned]
        out = []
        for name, k in (("normal", stiffness_n), ("shear", stiffness_s)):
            if self.settings.condition == "smooth" and name == "shear":
                continue
            k = k[:n_owned][on]
            if comm.allreduce(len(k)) == 0:
                continue
            E, hh = E_soil[:n_owned][on], h[:n_owned][on]
            pollution = comm.allreduce(float(np.max(E / (k * self.plate_radius), initial=0.0)),
                                       op=MPI.MAX)
            contrast = comm.allreduce(float(np.max(k * hh / E, initial=0.0)), op=MPI.MAX)
            key = f"interface.{name}_stiffness"
            if pollution > POLLUTION_WARNING:
                out.append(f"{key}: the interface's own compliance adds about "
                           f"{pollution:.1%} of the foundation's settlement (E / (k a)); raise "
                           f"it, or leave it out for the default {interface.PENALTY_FACTOR:g} "
                           f"E / h")
            if OVERSTIFF_WARNING < contrast <= CONDITIONING_WARNING:
                out.append(f"{key}: {contrast:.1e} times the soil element's stiffness E / h: "
                           f"the interface ties the soil to the structure point by point and "
                           f"the moments shift (by -2 % at 100 times the default, on a bonded "
                           f"plate); lower it, or leave it out for the default "
                           f"{interface.PENALTY_FACTOR:g} E / h")
            if contrast > CONDITIONING_WARNING:
                out.append(f"{key}: {contrast:.1e} times the soil element's stiffness E / h: "
                           f"the solve loses about {np.log10(contrast):.0f} of its 16 digits "
                           f"(the residual check guards the result); lower it, or leave it "
                           f"out for the default")
        return out

    def measures(self):
        """(tag name, normal, tangent, [(measure, restriction)]) of each interface part."""
        msh, dom = self.domain.mesh, self.domain
        ds = ufl.Measure("ds", domain=msh, subdomain_data=dom.facet_tags, metadata=self.qmeta)
        dS = ufl.Measure("dS", domain=msh, subdomain_data=dom.facet_tags, metadata=self.qmeta)
        parts = []
        for name, (n, t) in _INTERFACE.items():
            if name == "wall_embedded" and not self.embedded_wall:
                continue
            tag = FACET_TAGS[name]
            pieces = [(ds(tag), lambda f: f)]
            if dom.has_void:
                pieces.append((dS(tag), lambda f: f("+")))
            parts.append((name, ufl.as_vector(n), ufl.as_vector(t), pieces))
        return parts

    def contact_resultant(self) -> float:
        """Upward resultant of the interface tractions on the structure, N."""
        total = 0.0
        u_b, beta, _ = ufl.split(self.w)
        for _, n, t, pieces in self.measures():
            for measure, R in pieces:
                jump = R(self.soil.u) - R(u_b)
                sn, tau = interface.tractions(jump, n, t, R(self.k_n), R(self.k_s), R(self.mu),
                                              R(self.c_s))
                fz = sn * n[1] + tau * t[1]
                total += fem.assemble_scalar(fem.form(fz * 2.0 * math.pi * self.soil.r *
                                                      measure, entity_maps=self.entity_maps))
        return allsum(self.domain.mesh.comm, total)

    @cached_property
    def _traction_forms(self) -> list:
        def traction(jump, n, t, R):
            return list(interface.tractions(jump, n, t, R(self.k_n), R(self.k_s), R(self.mu),
                                            R(self.c_s)))
        return self.cell_average_forms(traction)

    def cell_average_forms(self, integrands) -> list:
        """Compiled forms whose assembled vectors are, per structure cell, the integrals over
        its interface facet of ``integrands(jump, n, t, R)`` (a list of expressions; R is
        the facet restriction), followed by the facet's (2 pi r weighted) area."""
        q = ufl.TestFunction(self.k_n.function_space)
        u_b = ufl.split(self.w)[0]
        sums = None
        for _, n, t, pieces in self.measures():
            for measure, R in pieces:
                # nodes: the lumped rule gives each node's value exactly, also at r = 0
                w = R(q) if self.node_states else 2.0 * math.pi * self.soil.r * R(q)
                terms = integrands(R(self.soil.u) - R(u_b), n, t, R) + [1.0]
                parts = [term * w * measure for term in terms]
                sums = parts if sums is None else [a + b for a, b in zip(sums, parts)]
        return [fem.form(f, entity_maps=self.entity_maps) for f in sums]

    def jump_forms(self) -> list:
        """The cell-average forms of the normal and tangential jump, compiled once per model
        (a soil iteration may start many interface iterations)."""
        if self._jump_forms is None:
            self._jump_forms = self.cell_average_forms(
                lambda jump, n, t, R: [ufl.dot(jump, n), ufl.dot(jump, t)])
        return self._jump_forms

    def cell_averages(self, forms) -> list[np.ndarray]:
        """Assemble :meth:`cell_average_forms` and divide by the areas: one value per local
        structure cell (0 away from the interface)."""
        values = []
        for f in forms:
            vec = fem.assemble_vector(f)
            vec.scatter_reverse(la.InsertMode.add)
            vec.scatter_forward()
            values.append(vec.array[:self.n_carrier].copy())
            # a node on the axis carries no force (2 pi r = 0), so nothing ties its jump:
            # it takes the value (and so the state) of the next node of its element
            values[-1][self.axis_carriers] = values[-1][self.axis_neighbours]
        area = values.pop()
        return [np.where(area > 0, v / np.where(area > 0, area, 1.0), 0.0) for v in values]

    def contact_stresses(self):
        """Interface tractions averaged over each structure cell (DG0 fields sigma_n, tau):
        the resultant of each facet exactly, without the point-wise wiggles of a penalty jump
        between the soil's and the structure's different polynomial traces."""
        out = []
        for values, name in zip(self.cell_averages(self._traction_forms), ("sigma_n", "tau")):
            f = fem.Function(self.S, name=name)
            f.x.array[:] = values
            out.append(f)
        return out

    @cached_property
    def carrier_lengths(self) -> np.ndarray:
        """The interface length each state carrier stands for: its element's length, or a
        node's Gauss-Lobatto weight times its element's length (computed once per model)."""
        if not self.node_states:
            return self.mesh.h(1, self.carrier_cell)
        q = ufl.TestFunction(self.S)
        vec = fem.assemble_vector(fem.form(q * self.dx))
        vec.scatter_reverse(la.InsertMode.add)
        vec.scatter_forward()
        return vec.array[:self.n_carrier].copy()
