"""The tank: soil, foundation plate and wall in one block system.

Block 0 is the soil displacement on the parent (r, z) mesh; block 1 the structure (u, beta, Q
of :mod:`tankfx.structure`) on the facet submesh made of the plate's underside facets and, if
there is a wall, the wall's meridian facets. Plate and wall share the junction vertex, so the
joint is rigid (continuous u and beta), for a_t = a_p and for a wall inside the plate edge.

The two are tied by the interface penalty of :mod:`tankfx.interface` on the plate underside
and, for an embedded tank, on the wall's outer face below the ground. Mixed-domain blocks are
integrated over the parent's facets (``ds`` where the facet is on the outside of the mesh,
``dS`` where the tank's void lies on its other side); pure structure blocks over the submesh.
"""
from __future__ import annotations

import math
from functools import cached_property

import basix
import basix.ufl
import numpy as np
import ufl
from dolfinx import fem, la
from dolfinx import mesh as dmesh
from mpi4py import MPI

from . import interface
from . import structure as st
from .analysis import SoilBlock, empty_form
from .mesh import FACET_TAGS, Domain
from .mohr_coulomb import InterfaceIteration
from .post import allsum, evaluate_at
from .scene import Scene, vertical_load, vertical_load_scale
from .solve import SolveError

__all__ = ["TankModel", "POLLUTION_WARNING", "CONDITIONING_WARNING"]

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
_SUB_TAG = {"contact": st.PLATE, "wall": st.WALL, "wall_embedded": st.WALL_EMBEDDED}


class TankModel:
    """Soil, plate and (optional) wall of a scene as one block system: its forms ``a``,
    ``L``, supports ``bcs`` and unknowns, the interface states, and the structure's results.
    ``face_offset=False`` puts the shells' mid-surfaces on the contact lines (only for
    measuring what the offset is worth)."""

    def __init__(self, scene: Scene, domain: Domain, face_offset: bool = True):
        self.scene, self.domain = scene, domain
        parent = domain.mesh
        self.soil = soil = SoilBlock(scene, domain)

        # ---- structure submesh and its cell tags (plate / wall / embedded wall)
        names = ["contact"] + (["wall", "wall_embedded"] if scene.wall is not None else [])
        facets = domain.facets(*names)
        sub, emap, _, _ = dmesh.create_submesh(parent, 1, facets)
        sub.topology.create_connectivity(0, 1)
        self.mesh, self.entity_maps = sub, [emap]
        n_sub = sub.topology.index_map(1).size_local + sub.topology.index_map(1).num_ghosts
        parent_facets = emap.sub_topology_to_topology(np.arange(n_sub, dtype=np.int32), False)
        ftag = np.zeros(parent.topology.index_map(1).size_local
                        + parent.topology.index_map(1).num_ghosts, dtype=np.int32)
        ftag[domain.facet_tags.indices] = domain.facet_tags.values
        by_value = {FACET_TAGS[k]: v for k, v in _SUB_TAG.items()}
        values = np.array([by_value[v] for v in ftag[parent_facets]], dtype=np.int32)
        self.cell_tags = dmesh.meshtags(sub, 1, np.arange(n_sub, dtype=np.int32), values)
        self.plate_cells = self.cell_tags.find(st.PLATE)
        self.wall_cells = np.sort(np.concatenate([self.cell_tags.find(st.WALL),
                                                  self.cell_tags.find(st.WALL_EMBEDDED)]))

        # ---- properties per structure cell (DG0): plate and wall differ
        Q0 = fem.functionspace(sub, ("DG", 0))
        self.cell_dof = Q0.dofmap.list[:, 0]   # DG0 dof of each local cell

        def cellwise(plate_value, wall_value, name):
            f = fem.Function(Q0, name=name)
            f.x.array[self.cell_dof[self.plate_cells]] = plate_value
            f.x.array[self.cell_dof[self.wall_cells]] = wall_value
            return f

        pl, wa = scene.plate, scene.wall
        wall_or = (lambda attr: getattr(wa, attr)) if wa is not None else (lambda attr: 0.0)
        self.E = cellwise(pl.E, wall_or("E"), "E")
        self.nu = cellwise(pl.nu, wall_or("nu"), "nu")
        # thickness by position: an annular ring, a wall's courses (the mesh has vertices
        # where it steps)
        #: (r, z) of every local structure cell's midpoint, in cell order
        self.cell_midpoints = mid = dmesh.compute_midpoints(
            sub, 1, np.arange(n_sub, dtype=np.int32))[:, :2]
        t_plate = pl.thickness_at(mid[self.plate_cells, 0])
        t_wall = wa.thickness_at(mid[self.wall_cells, 1] + scene.embedment) \
            if wa is not None else 0.0
        self.thickness = cellwise(t_plate, t_wall, "thickness")
        # the mesh lines are the faces in contact with the soil (outer faces flush where the
        # wall's courses step); the mid-surfaces lie half a thickness inside
        # (face_offset=False puts them on the mesh lines, for comparison)
        self.offset = cellwise(0.5 * t_plate if face_offset else 0.0,
                               0.5 * t_wall if face_offset else 0.0, "offset")
        # ---- where the interface states live (their "carrier"): one per element (DG0, the
        # paper's Eqs. 11-12), or one per node of the soil's trace (DG_k with its nodes at the
        # k + 1 Gauss-Lobatto points of each facet, integrated by that rule: each state then
        # acts at exactly one quadrature point)
        ifc = scene.interface
        self.node_states = ifc.condition == "mohr_coulomb" and ifc.states == "node"
        self.carrier_name = "node" if self.node_states else "element"
        if self.node_states:
            k = scene.mesh.degree
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
        self.k_n, self.k_s, self.mu, self.c_s = self._penalty(values)
        # the node on the axis and its neighbour in its element (see cell_averages)
        x = self.S.tabulate_dof_coordinates()[:, 0]
        self.axis_carriers = np.flatnonzero(self.node_states & (np.abs(x) < 1e-12
                                                                * scene.plate.radius))
        nearest = []
        for d in self.axis_carriers:
            others = [o for o in dofs[self.carrier_cell[d]] if o != d]
            nearest.append(min(others, key=lambda o: x[o]))
        self.axis_neighbours = np.array(nearest, dtype=np.int32)

        # ---- spaces, unknowns, forms
        self.W = st.structure_space(sub, 3)
        self.w = fem.Function(self.W, name="structure")
        self.unknowns = soil.unknowns + [self.w]      # [u, (p,) structure]
        self.r_b = ufl.SpatialCoordinate(sub)[0]
        self.t_b = st.tangent(sub)
        self.dx_b = ufl.Measure("dx", domain=sub, subdomain_data=self.cell_tags)
        self.dx_interface = self.dx_b((st.PLATE, st.WALL_EMBEDDED), metadata=self.qmeta)
        self.a = self._bilinear_forms()
        self.L = self._loads()
        self.bcs = soil.bcs + self._symmetry()
        self._jump_forms = None

    # ------------------------------------------------------------------ set-up
    def _penalty(self, values):
        """Interface stiffnesses of the contact cells, per state carrier, and the traction
        coefficients (k_n, k_s, mu, c_s of :mod:`tankfx.interface`) of their current state."""
        s, sub = self.scene, self.mesh
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
        ifc = s.interface
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
        self.status = np.where(self.in_contact, interface.STICK, -1)
        return fields

    def _penalty_warnings(self, E_soil, h, in_contact, stiffness_n, stiffness_s) -> list[str]:
        """Where the interface stiffness spoils the result: its own compliance 1/k adds about
        E / (k a) of the settlement p a / E (pollution); a stiffness far above the soil
        element's E / h over-constrains the structure to the soil's coarser trace, and costs
        about log10(k h / E) of the 16 digits of the solve."""
        s, comm = self.scene, self.mesh.comm
        n_owned = self.mesh.topology.index_map(1).size_local
        on = in_contact[:n_owned]
        out = []
        for name, k in (("normal", stiffness_n), ("shear", stiffness_s)):
            if s.interface.condition == "smooth" and name == "shear":
                continue
            k = k[:n_owned][on]
            if comm.allreduce(len(k)) == 0:
                continue
            E, hh = E_soil[:n_owned][on], h[:n_owned][on]
            pollution = comm.allreduce(float(np.max(E / (k * s.plate.radius), initial=0.0)),
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

    def _interface_measures(self):
        """(tag name, normal, tangent, [(measure, restriction)]) of each interface part."""
        msh, dom = self.domain.mesh, self.domain
        ds = ufl.Measure("ds", domain=msh, subdomain_data=dom.facet_tags, metadata=self.qmeta)
        dS = ufl.Measure("dS", domain=msh, subdomain_data=dom.facet_tags, metadata=self.qmeta)
        parts = []
        for name, (n, t) in _INTERFACE.items():
            if name == "wall_embedded" and (self.scene.wall is None
                                            or self.scene.embedment == 0.0):
                continue
            tag = FACET_TAGS[name]
            pieces = [(ds(tag), lambda f: f)]
            if dom.has_void:
                pieces.append((dS(tag), lambda f: f("+")))
            parts.append((name, ufl.as_vector(n), ufl.as_vector(t), pieces))
        return parts

    def _bilinear_forms(self):
        soil, r_b, t_b = self.soil, self.r_b, self.t_b
        u_b, beta, Q = ufl.TrialFunctions(self.W)
        v_b, gamma, P = ufl.TestFunctions(self.W)
        th = self.thickness
        # structure: shell energy and Kirchhoff constraint
        a_bb = (st.shell_stiffness(u_b, beta, v_b, gamma, r_b, t_b, self.E, self.nu, th,
                                   self.dx_b, self.offset)
                + st.kirchhoff_constraint(Q, gamma, v_b, t_b, r_b, self.dx_b)
                + st.kirchhoff_constraint(P, beta, u_b, t_b, r_b, self.dx_b))
        # the interface on the structure's side, -u_b in the jump; the soil's side and the
        # cross terms are integrated over the parent's facets below
        i_bb = interface.interface_form(u_b, v_b, st.normal(t_b), t_b, self.k_n, self.k_s,
                                        self.mu, r_b, self.dx_interface)
        i_ss, i_sb, i_bs = 0, 0, 0
        r = soil.r
        for _, n, t, pieces in self._interface_measures():
            for measure, R in pieces:
                kn, ks, mu = R(self.k_n), R(self.k_s), R(self.mu)
                i_ss += interface.interface_form(R(soil.trial), R(soil.test), n, t, kn, ks, mu,
                                                 r, measure)
                i_sb -= interface.interface_form(R(u_b), R(soil.test), n, t, kn, ks, mu, r,
                                                 measure)
                i_bs -= interface.interface_form(R(soil.trial), R(v_b), n, t, kn, ks, mu, r,
                                                 measure)
        self.a_split = self._split_forms(a_bb, (i_ss, i_sb, i_bs, i_bb))
        return self._block_rows(soil.matrix_rows(soil.a + i_ss), i_sb, i_bs, a_bb + i_bb)

    @staticmethod
    def _block_rows(soil_rows, a_sb, a_bs, a_bb) -> list:
        """The soil's rows (with its pressures', in the mixed form), then the structure's."""
        rows = [row + [a_sb if i == 0 else None] for i, row in enumerate(soil_rows)]
        rows.append([a_bs] + [None] * (len(soil_rows) - 1) + [a_bb])
        return rows

    def _split_forms(self, a_bb, interface_blocks):
        """(fixed, varying): block forms that sum to the model's matrix, for a direct solver
        that assembles the fixed part once and only the varying one at every solve
        (:class:`tankfx.solve.DirectSolver`). Between the solves of a linear soil what
        changes is a Mohr-Coulomb interface (its states) and a consolidation's flow terms
        (the time step: they are proportional to the conductance); None where neither
        does. Measured on the clay tank's consolidation, 81k dofs, 57 solves: the matrix's
        assemblies 5.1 s, their whole run 20.9 s, before the split."""
        soil = self.soil
        mohr_coulomb = self.scene.interface.condition == "mohr_coulomb"
        if not (mohr_coulomb or soil.consolidating):
            return None
        i_ss, i_sb, i_bs, i_bb = interface_blocks
        if mohr_coulomb:
            fixed, varying = soil.split_rows(soil.a, i_ss)
            return (self._block_rows(fixed, None, None, a_bb),
                    self._block_rows(varying, i_sb, i_bs, i_bb))
        fixed, varying = soil.split_rows(soil.a + i_ss)
        return (self._block_rows(fixed, i_sb, i_bs, a_bb + i_bb),
                self._block_rows(varying, None, None, empty_form(self.W)))

    def _loads(self):
        s, r_b = self.scene, self.r_b
        v_f, gamma, _ = ufl.TestFunctions(self.W)
        # loads act on the mid-surface (for pressures normal to the wall or plate it is the
        # same as on the face; it matters for the wall's self-weight)
        v_b = st.mid_surface_displacement(v_f, gamma, self.t_b, self.offset)
        x = ufl.SpatialCoordinate(self.mesh)
        soil_load = ufl.inner(fem.Constant(self.domain.mesh, (0.0, 0.0)), self.soil.test) * \
            self.soil.dx
        ring, self.ringwall_weight = s.ringwall, None
        if ring is not None and ring.unit_weight and any(ld.self_weight
                                                           for ld in (s.load, *s.stages)):
            # its weight in excess of the soil's, on its own cells (the material after the
            # ground's strata)
            self.ringwall_weight = fem.Constant(self.domain.mesh, 0.0)
            soil_load += -self.ringwall_weight * self.soil.test[1] * 2.0 * math.pi * \
                self.soil.r * self.soil.dx_strata([len(s.soil.strata)])
        w = 2.0 * math.pi * r_b
        dx_p = self.dx_b(st.PLATE)
        dx_w = self.dx_b((st.WALL, st.WALL_EMBEDDED))
        # load values are Constants: a load path changes them without recompiling
        c = self.load_constants = {k: fem.Constant(self.mesh, 0.0) for k in (
            "pressure", "liquid_unit_weight", "liquid_height", "plate_weight", "wall_weight",
            "roof_line_load", "gas_pressure")}
        self.set_loads(s.load)
        # self-weight: a unit weight times the cell's thickness (a ring, courses)
        th = self.thickness
        load = -(c["pressure"] + c["plate_weight"] * th) * v_b[1] * w * dx_p
        if s.wall is not None:
            inside = ufl.conditional(ufl.lt(r_b, s.wall.radius), 1.0, 0.0)
            gl, hl = c["liquid_unit_weight"], c["liquid_height"]
            load += -gl * hl * inside * v_b[1] * w * dx_p
            height = x[1] + s.embedment          # above the wall base
            load += gl * ufl.max_value(hl - height, 0.0) * v_b[0] * w * dx_w  # outward
            load += -c["wall_weight"] * th * v_b[1] * w * dx_w
            # a gas pressure: on the floor inside the wall and on the whole wall, outward
            load += -c["gas_pressure"] * inside * v_b[1] * w * dx_p
            load += c["gas_pressure"] * v_b[0] * w * dx_w
        if s.wall is not None and any(ld.roof_weight or ld.gas_pressure
                                      for ld in (s.load, *s.stages)):
            # the roof on the wall's top edge (a vertex of the structure mesh: its ds): its
            # weight down, the gas's push on it (p pi a_t^2) up
            top = dmesh.locate_entities_boundary(
                self.mesh, 0, lambda x: np.isclose(x[1], s.wall.height - s.embedment)
                & np.isclose(x[0], s.wall.radius))
            tags = dmesh.meshtags(self.mesh, 0, top, np.full(len(top), 1, dtype=np.int32))
            ds_top = ufl.Measure("ds", domain=self.mesh, subdomain_data=tags)(1)
            load += -(c["roof_line_load"] - 0.5 * s.wall.radius * c["gas_pressure"]) * \
                v_b[1] * w * ds_top
        if s.interface.condition == "mohr_coulomb":
            # the cohesion carried by slipping elements, c_s (dj . t), dj = v_soil - v_face
            load -= interface.interface_load(v_f, self.t_b, self.c_s, r_b, self.dx_interface)
            for _, n, t, pieces in self._interface_measures():
                for measure, R in pieces:
                    soil_load += interface.interface_load(R(self.soil.test), t, R(self.c_s),
                                                          self.soil.r, measure)
        return self.soil.load_rows(soil_load) + [load]

    def _symmetry(self):
        """u_r = 0 and beta = 0 at the plate centre."""
        sub = self.mesh
        centre = dmesh.locate_entities(sub, 0, lambda x: np.isclose(x[0], 0.0))
        bcs = []
        for space in (self.W.sub(0).sub(0), self.W.sub(1)):
            V, _ = space.collapse()
            dofs = fem.locate_dofs_topological((space, V), 0, centre)
            bcs.append(fem.dirichletbc(fem.Function(V), dofs, space))
        return bcs

    def set_loads(self, load) -> None:
        """Apply the loads of a ``Load`` (the forms stay; their Constants change)."""
        from dataclasses import replace

        s = self.scene = replace(self.scene, load=load)
        c = self.load_constants
        c["pressure"].value = load.pressure
        c["liquid_unit_weight"].value = load.liquid_unit_weight if s.wall is not None else 0.0
        c["liquid_height"].value = load.liquid_height
        # unit weights (N/m^3), times each cell's thickness in the load form
        c["plate_weight"].value = s.plate.unit_weight if load.self_weight else 0.0
        c["wall_weight"].value = s.wall.unit_weight \
            if (load.self_weight and s.wall is not None) else 0.0
        c["roof_line_load"].value = load.roof_weight / (2 * math.pi * s.wall.radius) \
            if s.wall is not None else 0.0
        c["gas_pressure"].value = load.gas_pressure if s.wall is not None else 0.0
        if self.ringwall_weight is not None:
            self.ringwall_weight.value = s.ringwall.unit_weight if load.self_weight else 0.0

    # ------------------------------------------------------------------ quantities
    @property
    def reference_pressure(self) -> float:
        """p of Eq. 23: the uniform pressure on the plate, plus the liquid's and a gas's on
        its floor."""
        ld = self.scene.load
        gas = ld.gas_pressure if self.scene.wall is not None else 0.0
        return ld.pressure + ld.liquid_unit_weight * ld.liquid_height + gas

    @property
    def applied_load(self) -> float:
        """Downward resultant of all applied loads, N (closed form): those on the structure
        and a ringwall's net weight."""
        s = self.scene
        return vertical_load(s.load, s.plate, s.wall, s.ringwall)

    #: the largest load scale of a consolidation's load path so far, N (its last load may
    #: be none: a tank emptied); 0 otherwise
    path_load_scale = 0.0

    @property
    def load_scale(self) -> float:
        """The size of the vertical loads, N, for the relative equilibrium error (along a
        consolidation's load path, its largest so far)."""
        s = self.scene
        return max(vertical_load_scale(s.load, s.plate, s.wall, s.ringwall),
                   self.path_load_scale)

    def dofs(self) -> dict[str, int]:
        im = self.W.dofmap.index_map
        return self.soil.dofs() | {"structure": im.size_global * self.W.dofmap.index_map_bs}

    def begin_stage(self) -> None:
        """Start a load stage: the element states so far are the starting guess, and the
        elements separated now are the ones that can be reported ``rebonded`` later."""
        self.interface_result = None
        self.was_separated = self.status == interface.SEPARATED
        self._passes = None

    def solve(self, solver, log, single_pass: bool = False) -> int:
        """One linear solve for bonded and smooth contact; the Mohr-Coulomb iteration
        otherwise (a scene that does not need the return does not run it). With
        ``single_pass`` the interface makes one solve and one state update only (for a soil
        iteration that converges both at once); returns the number of elements that changed
        state (0 when the interface is converged)."""
        if self.scene.interface.condition != "mohr_coulomb":
            solver.solve()
            return 0
        if not single_pass or self.node_states:
            # node states are converged inside every soil iteration: updated once per soil
            # iteration they oscillate with the secant moduli (measured: a period-2 cycle,
            # no convergence in 40 iterations, where the nested loop takes 6 solves)
            self.interface_result = self._iterate_interface(solver, log)
            return 0
        if self._passes is None:
            self._passes = InterfaceIteration(self)
        changed = self._passes.single_pass(solver)
        self.interface_result = {"converged": changed == 0,
                                 "iterations": len(self._passes.history),
                                 "history": self._passes.history,
                                 "frozen_elements": self._passes.history[-1]["frozen"],
                                 "reversed_slips": self._passes.reversed_slips(),
                                 "criterion": "one state update per soil iteration, until no "
                                              "element changes state"}
        return changed

    #: solves of the Mohr-Coulomb iteration from a previous solution's states before it
    #: starts again from stuck ones (see _iterate_interface)
    CARRIED_STATES_SOLVES = 20
    #: how many Mohr-Coulomb iterations of this analysis started again from stuck states
    interface_restarts = 0

    def _iterate_interface(self, solver, log) -> dict:
        """The Mohr-Coulomb iteration from the states so far (a load path's or a time step's
        last); where it fails from them, once more from the states of a fresh analysis
        (every carrier in contact stuck). The law holds no slip from one solution to the
        next (total loading), so the states so far are only a starting guess, and a poor
        one where the load fell: the small tank's consolidation emptied to 5 % of its load
        cycled its reversed slips for 50 solves from the full tank's states, and converged
        in 4 from stuck ones. The first try has CARRIED_STATES_SOLVES solves."""
        # (a stuck carrier's coefficients are those of its state: the states say it all;
        # every rank takes the same branch, the iteration's solves being collective)
        fresh = np.all(self.status[self.in_contact] == interface.STICK)
        if self.mesh.comm.allreduce(int(fresh), op=MPI.MIN):
            return InterfaceIteration(self).run(solver, log)
        carried = InterfaceIteration(self)
        # (from a good guess it takes a few solves; a fresh start, a handful more)
        carried.max_iterations = self.CARRIED_STATES_SOLVES
        try:
            return carried.run(solver, log)
        except SolveError as first:
            if self.scene.interface.on_cycle == "stop" and "cycles" in str(first):
                raise
            log.info("Mohr-Coulomb interface: no converged state from the previous states "
                     "(%s); once more from every element stuck", first)
            self.status[:] = np.where(self.in_contact, interface.STICK, -1)
            for f, v in zip((self.k_n, self.k_s, self.mu, self.c_s),
                            (self.stiffness_n, self.stiffness_s, 0.0, 0.0)):
                f.x.array[:] = np.where(self.in_contact, v, 0.0)
            try:
                result = InterfaceIteration(self).run(solver, log)
            except SolveError as second:
                raise SolveError(f"{second} (and from the previous states: {first})",
                                 first.history + second.history) from None
            self.interface_restarts += 1
            return result

    @cached_property
    def _out_of_balance(self):
        """Compiled forms of the block system's rows: per row the actions sum_j a_ij(u_j, v_i)
        (each a form of its own: a row's terms integrate over different meshes) and the load
        L_i(v_i), with the supports' dofs of each block."""
        rows = []
        for row, L in zip(self.a, self.L):
            actions = [fem.form(ufl.action(a_ij, u_j), entity_maps=self.entity_maps)
                       for a_ij, u_j in zip(row, self.unknowns) if isinstance(a_ij, ufl.Form)]
            rows.append((actions, fem.form(L, entity_maps=self.entity_maps)))
        spaces = fem.extract_function_spaces([load for _, load in rows])
        fixed = [np.unique(np.concatenate([bc.dof_indices()[0] for bc in bcs])) if bcs
                 else np.empty(0, np.int32) for bcs in fem.bcs_by_block(spaces, self.bcs)]
        return rows, fixed

    def out_of_balance(self) -> float:
        """||A u - f|| / ||f||: the out-of-balance force of the current fields under the
        current interface coefficients, relative to the load vector (over all blocks, the
        supports' rows left out; zero, to round-off, at a converged state)."""
        rows, fixed = self._out_of_balance
        residual = load = 0.0
        for (actions, L), dofs, u in zip(rows, fixed, self.unknowns):
            V = u.function_space
            n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
            vecs = []
            for f in [L] + actions:
                vec = fem.assemble_vector(f)
                vec.scatter_reverse(la.InsertMode.add)
                vec.array[dofs] = 0.0
                vecs.append(vec.array[:n])
            r = sum(vecs[1:]) - vecs[0]
            residual += float(r @ r)
            load += float(vecs[0] @ vecs[0])
        comm = self.mesh.comm
        return math.sqrt(comm.allreduce(residual) / max(comm.allreduce(load), 1e-300))

    def soil_residual(self):
        a_ss, a_sb = self.a[0][0], self.a[0][-1]
        return self.soil.residual(a_ss, self.L[0]) + ufl.action(a_sb, self.w)

    def contact_resultant(self) -> float:
        """Upward resultant of the interface tractions on the structure, N."""
        total = 0.0
        u_b, beta, _ = ufl.split(self.w)
        for _, n, t, pieces in self._interface_measures():
            for measure, R in pieces:
                jump = R(self.soil.u) - R(u_b)
                sn, tau = interface.tractions(jump, n, t, R(self.k_n), R(self.k_s), R(self.mu),
                                              R(self.c_s))
                fz = sn * n[1] + tau * t[1]
                total += fem.assemble_scalar(fem.form(fz * 2.0 * math.pi * self.soil.r *
                                                      measure, entity_maps=self.entity_maps))
        return allsum(self.domain.mesh.comm, total)

    # The results' expressions and forms, compiled once per model: the results are read at
    # every step of a consolidation (and every stage of a path).
    @cached_property
    def _resultants(self) -> st.ShellResultants:
        return st.ShellResultants(self.w, self.r_b, self.t_b, self.E, self.nu, self.thickness,
                                  self.offset)

    @cached_property
    def _traction_forms(self) -> list:
        def traction(jump, n, t, R):
            return list(interface.tractions(jump, n, t, R(self.k_n), R(self.k_s), R(self.mu),
                                            R(self.c_s)))
        return self.cell_average_forms(traction)

    @cached_property
    def _w_mean_form(self):
        u_b = ufl.split(self.w)[0]
        return fem.form(-u_b[1] * 2.0 * math.pi * self.r_b * self.dx_b(st.PLATE))

    def _fields(self):
        """Structure resultants interpolated cell-wise (DG2), for point evaluation."""
        out = self._resultants()
        out["sigma_n"], out["tau"] = self.contact_stresses()
        status = fem.Function(self.S, name="status")
        closed = (self.status == interface.STICK) | (self.status == interface.SLIP)
        status.x.array[:] = np.where(self.was_separated & closed, interface.REBONDED,
                                     self.status)
        out["status"] = status
        return out

    def _stations(self, cells, along: int | None = None):
        """Gathered vertex and midpoint coordinates of the given structure cells, sorted (by
        the coordinate ``along``: 0 for r, 1 for z)."""
        sub = self.mesh
        owned = cells[cells < sub.topology.index_map(1).size_local]
        conn = sub.topology.connectivity(1, 0)
        verts = np.unique(np.concatenate([conn.links(c) for c in owned])) if len(owned) \
            else np.empty(0, dtype=np.int32)
        x = dmesh.compute_midpoints(sub, 0, verts.astype(np.int32))[:, :2] if len(verts) \
            else np.empty((0, 2))
        mids = dmesh.compute_midpoints(sub, 1, owned)[:, :2] if len(owned) \
            else np.empty((0, 2))
        pts = np.concatenate(self.mesh.comm.allgather(np.concatenate([x, mids])))
        pts = np.unique(np.round(pts, 12), axis=0)
        pts = pts[np.lexsort((pts[:, 0], pts[:, 1]))] if len(pts) else pts
        return pts if along is None else pts[np.argsort(pts[:, along])]

    def cell_average_forms(self, integrands) -> list:
        """Compiled forms whose assembled vectors are, per structure cell, the integrals over
        its interface facet of ``integrands(jump, n, t, R)`` (a list of expressions; R is
        the facet restriction), followed by the facet's (2 pi r weighted) area."""
        q = ufl.TestFunction(self.k_n.function_space)
        u_b = ufl.split(self.w)[0]
        sums = None
        for _, n, t, pieces in self._interface_measures():
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

    def _contact(self, F, pts, cells):
        """Interface tractions (cell averages) at the stations."""
        return (evaluate_at(F["sigma_n"], pts, cells)[:, 0],
                evaluate_at(F["tau"], pts, cells)[:, 0])

    def foundation_results(self) -> dict:
        F = self._fields()
        self._F = F
        s = self.scene
        pts = self._stations(self.plate_cells, along=0)
        cells = self.plate_cells
        u = evaluate_at(F["u"], pts, cells)
        w = -u[:, 1]
        M_r = evaluate_at(F["M_s"], pts, cells)[:, 0]
        ap = s.plate.radius
        w_mean = allsum(self.mesh.comm, fem.assemble_scalar(self._w_mean_form)) / \
            (math.pi * ap**2)
        self._w_mean = float(w_mean)
        return {"w0": float(w[0]), "w_edge": float(w[-1]), "wd": float(w.max() - w.min()),
                "w_mean": float(w_mean), "M0": float(M_r[0])}

    def structure_results(self) -> dict:
        F, s = self._F, self.scene
        pts = self._stations(self.plate_cells, along=0)
        cells = self.plate_cells
        u = evaluate_at(F["u"], pts, cells)
        sn, tau = self._contact(F, pts, cells)
        plate = {"r": pts[:, 0].tolist(), "w": (-u[:, 1]).tolist(), "u_r": u[:, 0].tolist(),
                 "rotation": evaluate_at(F["beta"], pts, cells)[:, 0].tolist(),
                 "M_r": evaluate_at(F["M_s"], pts, cells)[:, 0].tolist(),
                 "M_theta": evaluate_at(F["M_theta"], pts, cells)[:, 0].tolist(),
                 "Q_r": evaluate_at(F["Q"], pts, cells)[:, 0].tolist(),
                 "contact_normal": sn.tolist(), "contact_shear": tau.tolist(),
                 "contact_status": self._status_at(F, pts, cells)}
        profiles = {"plate": plate}
        if s.wall is not None:
            cells = self.wall_cells
            pts = self._stations(cells, along=1)
            u = evaluate_at(F["u"], pts, cells)
            N_theta = evaluate_at(F["N_theta"], pts, cells)[:, 0]
            # (at a course joint both come from the course below)
            thickness = evaluate_at(self.thickness, pts, cells)[:, 0]
            wall = {"z": (pts[:, 1] + s.embedment).tolist(), "u_r": u[:, 0].tolist(),
                    "u_z": u[:, 1].tolist(),
                    "rotation": evaluate_at(F["beta"], pts, cells)[:, 0].tolist(),
                    "M_z": evaluate_at(F["M_s"], pts, cells)[:, 0].tolist(),
                    "N_z": evaluate_at(F["N_s"], pts, cells)[:, 0].tolist(),
                    "N_theta": N_theta.tolist(), "thickness": thickness.tolist(),
                    "hoop_stress": (N_theta / thickness).tolist(),
                    "Q": evaluate_at(F["Q"], pts, cells)[:, 0].tolist()}
            if s.embedment > 0.0:
                sn, tau = self._contact(F, pts, cells)
                below = pts[:, 1] <= 1e-12
                wall["contact_normal"] = np.where(below, sn, 0.0).tolist()
                wall["contact_shear"] = np.where(below, tau, 0.0).tolist()
                wall["contact_status"] = [st_ if b else "none" for st_, b in
                                          zip(self._status_at(F, pts, cells), below)]
            profiles["wall"] = wall
        # what the interface carries: every load but a ringwall's weight, which its own
        # cells carry to the soil
        applied = vertical_load(s.load, s.plate, s.wall)
        scale = max(vertical_load_scale(s.load, s.plate, s.wall), self.path_load_scale)
        contact = self.contact_resultant()
        out = {"profiles": profiles,
               "equilibrium": {"contact_resultant": contact,
                               "contact_relative_error": abs(contact - applied) / scale},
               "interface": self._interface_summary()}
        if s.wall is not None:
            out["junction"] = self._junction(F)
            out["courses"] = self._courses(F)
        out["settlement_summary"] = self._settlement_summary(plate)
        return out

    def _courses(self, F) -> list[dict]:
        """Per course of the wall (one for a uniform wall), heights above its foot: the
        largest hoop stress N_theta / t (Pa; tension positive: what a tank code checks
        against its allowable stress) and where, and the largest |M_z| (N m/m) and where."""
        s = self.scene
        height = self.cell_midpoints[self.wall_cells, 1] + s.embedment
        out = []
        for bottom, top, t in s.wall.course_table:
            cells = self.wall_cells[(height > bottom) & (height < top)]
            pts = self._stations(cells)
            hoop = evaluate_at(F["N_theta"], pts, cells)[:, 0] / t
            M = evaluate_at(F["M_s"], pts, cells)[:, 0]
            z = pts[:, 1] + s.embedment
            i, j = int(np.argmax(hoop)), int(np.argmax(np.abs(M)))
            out.append({"bottom": bottom, "top": top, "thickness": t,
                        "max_hoop_stress": float(hoop[i]), "at": float(z[i]),
                        "max_abs_M_z": float(abs(M[j])), "M_at": float(z[j])})
        return out

    def _settlement_summary(self, plate) -> dict:
        """What tank codes ask of the foundation (API 653 Annex B style), from the plate
        profile: the uniform (mean) settlement, the centre-to-edge dish, and the settlement
        of the shell's edge. An axisymmetric model has no planar tilt or out-of-plane
        settlement around the shell: those need a 3D model or measured data."""
        r = np.asarray(plate["r"])
        w = np.asarray(plate["w"])
        s = self.scene
        at = s.wall.radius if s.wall is not None else s.plate.radius
        w_shell = float(np.interp(at, r, w))
        return {"uniform_settlement": self._w_mean, "shell_settlement": w_shell,
                "dish": float(w[0] - w_shell), "dish_over_radius": float((w[0] - w_shell) / at),
                "planar_tilt": None,
                "note": "axisymmetric: no planar tilt or differential settlement around the "
                        "shell"}

    def _status_at(self, F, pts, cells) -> list[str]:
        """The interface state of the element at each station (vertices: the element on the
        axis side)."""
        codes = evaluate_at(F["status"], pts, cells)[:, 0]
        return [interface.STATUS_NAMES.get(int(round(c)), "none") for c in codes]

    @cached_property
    def carrier_lengths(self) -> np.ndarray:
        """The interface length each state carrier stands for: its element's length, or a
        node's Gauss-Lobatto weight times its element's length (computed once per model)."""
        if not self.node_states:
            return self.mesh.h(1, self.carrier_cell)
        q = ufl.TestFunction(self.S)
        vec = fem.assemble_vector(fem.form(q * self.dx_interface))
        vec.scatter_reverse(la.InsertMode.add)
        vec.scatter_forward()
        return vec.array[:self.n_carrier].copy()

    def _interface_summary(self) -> dict:
        """Lengths in each state (per part), iterations and history of the interface."""
        comm = self.mesh.comm
        n_owned = self.n_carrier_owned
        h = self.carrier_lengths[:n_owned]
        values = self.carrier_tag[:n_owned]
        lengths = {}
        rebonded = self.was_separated & (self.status != interface.SEPARATED)
        for name, code in (("stick", interface.STICK), ("slip", interface.SLIP),
                           ("separated", interface.SEPARATED), ("rebonded", -2)):
            for part, tag in (("plate", st.PLATE), ("wall", st.WALL_EMBEDDED)):
                state = rebonded if code == -2 else self.status == code
                mine = state[:n_owned] & (values == tag)
                lengths.setdefault(f"{name}_length", {})[part] = comm.allreduce(
                    float(h[mine].sum()))
        res = self.interface_result or {"converged": True, "iterations": 0, "history": [],
                                        "criterion": "linear interface: one solve"}
        if self.scene.interface.condition == "mohr_coulomb":
            res = {**res, "states": self.scene.interface.states,
                   "restarts_from_stuck": self.interface_restarts}
        return {"condition": self.scene.interface.condition, **res, **lengths,
                "normal_stiffness_range": [
                    comm.allreduce(float(self.stiffness_n[self.in_contact].min(initial=np.inf)),
                                   op=MPI.MIN),
                    comm.allreduce(float(self.stiffness_n[self.in_contact].max(initial=0.0)),
                                   op=MPI.MAX)]}

    def _junction(self, F) -> dict:
        """Moments at the wall-plate joint, N m/m. The mesh vertex is the joint's outer
        corner (where the faces meet); about it the membrane forces of the mid-surfaces, half
        a thickness away, add to the moments, and the members balance:
        sum over plate sides of +-(M_r - N_r t_p / 2) = M_z - N_z t_t / 2."""
        s = self.scene
        corner = np.array([[s.wall.radius, -s.embedment]])
        mids = self.cell_midpoints[self.plate_cells, 0]
        inner = self.plate_cells[mids < s.wall.radius]
        outer = self.plate_cells[mids > s.wall.radius]
        # the plate's thickness on each side of the wall (an annular ring's, if it has one)
        e_in, e_out = 0.5 * s.plate.thickness_at(s.wall.radius * np.array([1 - 1e-9,
                                                                           1 + 1e-9]))
        e_w = 0.5 * s.wall.thickness

        def about_corner(cells, e):
            if self.mesh.comm.allreduce(len(cells)) == 0:
                return 0.0, 0.0
            M = evaluate_at(F["M_s"], corner, cells)[0, 0]
            return M, M - evaluate_at(F["N_s"], corner, cells)[0, 0] * e

        M_in, Mc_in = about_corner(inner, e_in)
        M_out, Mc_out = about_corner(outer, e_out)
        M_w, Mc_w = about_corner(self.wall_cells, e_w)
        # the surface bending stresses 6 M / t^2 at the joint (Pa; what a steel tank's
        # corner is checked for), in the wall's bottom course and the plate inside it
        return {"M_plate": M_in, "M_plate_outside": M_out, "M_wall": M_w,
                "M_plate_about_corner": Mc_in - Mc_out, "M_wall_about_corner": Mc_w,
                "wall_bending_stress": 6.0 * abs(M_w) / (2 * e_w) ** 2,
                "plate_bending_stress": 6.0 * abs(M_in) / (2 * e_in) ** 2}
