"""The tank: soil, foundation plate and wall in one block system.

Block 0 is the soil displacement on the parent (r, z) mesh; block 1 the structure (u, beta, Q
of :mod:`tankfx.laws.shell`) on the facet submesh made of the plate's underside facets and, if
there is a wall, the wall's meridian facets. Plate and wall share the junction vertex, so the
joint is rigid (continuous u and beta), for a_t = a_p and for a wall inside the plate edge.

The two are tied by the interface penalty of :mod:`tankfx.laws.interface` on the plate underside
and, for an embedded tank, on the wall's outer face below the ground. Mixed-domain blocks are
integrated over the parent's facets (``ds`` where the facet is on the outside of the mesh,
``dS`` where the tank's void lies on its other side); pure structure blocks over the submesh.

The paper: Eq. 2's global stiffness of soil, structure and interface elements (here one block
system of UFL forms), and Eq. 23's p (``reference_pressure``).
"""
from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import replace
from functools import cached_property

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh

from ..fem.blocks import Balanced, OutOfBalance, empty_form
from ..fem.evaluate import allsum, evaluate_at
from ..fem.solvers import reaction_force
from ..laws import interface
from ..laws import shell as st
from ..mesh import FACET_TAGS, Domain
from ..scene.scene import Scene
from ..scene.sections import vertical_load, vertical_load_scale
from .interface import InterfaceBlock
from .soil import SoilBlock, SoilSetting
from .structure import ShellResultants
from .tank_loads import TankLoads

#: the structure submesh's cell tag of each of the parent's facet tags it is made of
_SUB_TAG = {"contact": st.PLATE, "wall": st.WALL, "wall_embedded": st.WALL_EMBEDDED}


class TankModel(Balanced):
    """Soil, plate and (optional) wall of a scene as one block system: its forms ``a``,
    ``L``, supports ``bcs`` and unknowns, the interface states, and the structure's results.
    ``face_offset=False`` puts the shells' mid-surfaces on the contact lines (only for
    measuring what the offset is worth)."""

    def __init__(self, scene: Scene, domain: Domain, face_offset: bool = True):
        self.scene, self.domain = scene, domain
        parent = domain.mesh
        self.soil = soil = SoilBlock(SoilSetting.of(scene), domain)

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
        self.W = st.structure_space(sub, 3)
        self.w = fem.Function(self.W, name="structure")
        # ---- the interface: its state carriers, stiffnesses and states
        self.interface = InterfaceBlock(
            scene.interface, scene.plate.radius,
            scene.wall is not None and scene.embedment > 0.0, domain, soil, sub,
            self.cell_tags, mid, self.w, self.entity_maps)
        self.warnings = self.interface.warnings

        # ---- spaces, unknowns, forms
        self.unknowns = soil.unknowns + [self.w]      # [u, (p,) structure]
        self.r_b = ufl.SpatialCoordinate(sub)[0]
        self.t_b = st.tangent(sub)
        self.dx_b = ufl.Measure("dx", domain=sub, subdomain_data=self.cell_tags)
        self.a = self._bilinear_forms()
        #: the load forms, their values Constants (tankfx.model.tank_loads)
        self.loads = TankLoads(self)
        self.set_loads(scene.load)
        self.L = self.loads.rows
        self.bcs = soil.bcs + self._symmetry()

    # ------------------------------------------------------------------ set-up
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
        ifc = self.interface
        i_bb = interface.interface_form(u_b, v_b, st.normal(t_b), t_b, ifc.k_n, ifc.k_s, ifc.mu,
                                        r_b, ifc.dx)
        i_ss, i_sb, i_bs = 0, 0, 0
        r = soil.r
        for _, n, t, pieces in ifc.measures():
            for measure, R in pieces:
                kn, ks, mu = R(ifc.k_n), R(ifc.k_s), R(ifc.mu)
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
        (:class:`tankfx.fem.solvers.DirectSolver`). Between the solves of a linear soil what
        changes is a Mohr-Coulomb interface (its states) and a consolidation's flow terms
        (the time step: they are proportional to the conductance); None where neither
        does. Measured on the clay tank's consolidation, 81k dofs, 57 solves: the matrix's
        assemblies 5.1 s, their whole run 20.9 s, before the split."""
        soil = self.soil
        mohr_coulomb = self.scene.interface.has_states
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
        self.scene = replace(self.scene, load=load)
        self.loads.apply(self.scene)

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
        """Start a load stage: the interface's states so far are the starting guess (see
        :meth:`InterfaceBlock.begin_stage`)."""
        self.interface.begin_stage()

    def commit(self) -> None:
        """The state now (the soil's and the interface's histories) is the one to go on
        from."""
        self.soil.history.commit()
        self.interface.history.commit()

    def rollback(self) -> None:
        """Back to the last committed state."""
        self.soil.history.rollback()
        self.interface.history.rollback()

    # ------------------------------------------------------------------ an excavation
    #: the structure's stiffness and its interface's while its pit is dug, relative to
    #: their own: it stands by, following the pit's faces without holding them. Both are
    #: scaled: the interface alone would still press the soil's faces towards the smooth
    #: shape the shell's Kirchhoff constraint allows (measured on a 10 m plate 2 m deep in
    #: clay: its moment 9e-6 off the linear soil's afterwards, whatever the shell's
    #: stiffness; both scaled by 1e-9, 4e-10 off, by 1e-12, 8e-13, the heave the same to
    #: 2e-9); 0 would make the matrix singular.
    ABSENT = 1e-9

    @contextmanager
    def structure_absent(self):
        """The structure and its interface without stiffness (and without loads) for the
        time of the block: a pit's excavation, before it is built."""
        held = [f.x.array.copy() for f in (self.E, self.interface.k_n, self.interface.k_s)]
        for f, values in zip((self.E, self.interface.k_n, self.interface.k_s), held):
            f.x.array[:] = self.ABSENT * values
        self.commit()           # (a step cut back rolls back to these)
        try:
            yield
        finally:
            for f, values in zip((self.E, self.interface.k_n, self.interface.k_s), held):
                f.x.array[:] = values

    def excavation_equilibrium(self) -> tuple[float, float]:
        """(the supports' vertical reaction, the pit's relief's upward resultant), N: at an
        excavated state in equilibrium the reaction is the relief's, downward."""
        reaction = reaction_force(self.soil_residual(), self.soil.V, 1,
                                  self.soil.supported_facets, entity_maps=self.entity_maps)
        return reaction, self.soil.pit.released()

    def place_structure(self) -> None:
        """The structure is built on the excavated ground, free of strain: every
        displacement is set to zero (what follows is measured from here), the ground's
        stress and plastic strain are kept, and the state is committed."""
        for u in self.unknowns:
            u.x.array[:] = 0.0
        self.soil.plastic.restart_strain()
        self.commit()

    @cached_property
    def _out_of_balance(self) -> OutOfBalance:
        return OutOfBalance(self.a, self.L, self.unknowns, self.bcs, self.entity_maps)

    def soil_residual(self):
        a_ss, a_sb = self.a[0][0], self.a[0][-1]
        return self.soil.residual(a_ss, self.L[0]) + ufl.action(a_sb, self.w)

    # The results' expressions and forms, compiled once per model: the results are read at
    # every step of a consolidation (and every stage of a path).
    @cached_property
    def _resultants(self) -> ShellResultants:
        return ShellResultants(self.w, self.r_b, self.t_b, self.E, self.nu, self.thickness,
                                  self.offset)

    def mean_settlement(self) -> float:
        """The plate's mean settlement, m (the area's mean of its underside's w): linear in
        the unknowns, what a collapse's settlement control raises."""
        return allsum(self.mesh.comm, fem.assemble_scalar(self._w_mean_form)) / (
            math.pi * self.scene.plate.radius ** 2)

    @cached_property
    def _w_mean_form(self):
        u_b = ufl.split(self.w)[0]
        return fem.form(-u_b[1] * 2.0 * math.pi * self.r_b * self.dx_b(st.PLATE))

    def _fields(self):
        """Structure resultants interpolated cell-wise (DG2), for point evaluation."""
        out = self._resultants()
        out["sigma_n"], out["tau"] = self.interface.contact_stresses()
        out["status"] = self.interface.status_field()
        return out

    def stations(self, cells, along: int | None = None):
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

    def foundation_results(self) -> dict:
        F = self._fields()
        #: the fields of the last solution read (the structure's results read them again)
        self.last_fields = F
        pts = self.stations(self.plate_cells, along=0)
        cells = self.plate_cells
        u = evaluate_at(F["u"], pts, cells)
        w = -u[:, 1]
        M_r = evaluate_at(F["M_s"], pts, cells)[:, 0]
        w_mean = self.mean_settlement()
        self.last_w_mean = float(w_mean)
        return {"w0": float(w[0]), "w_edge": float(w[-1]), "wd": float(w.max() - w.min()),
                "w_mean": float(w_mean), "M0": float(M_r[0])}
