"""From a validated scene to results: mesh, forms, solve, post-processing.

The result keys (``results.json``) are a public contract; see README "Results".
Sign conventions: settlements ``w`` positive downward; ``u_r`` positive outward; the axis
``z`` is the depth below the ground surface (positive downward); ``sigma_zz`` is positive in
compression (the paper's and geotechnical convention).
"""
from __future__ import annotations

import logging
import math
import platform
import time
from dataclasses import dataclass
from functools import cached_property
from importlib import metadata

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from . import soil as soil_forms
from ._memory import keep_freed_memory
from ._threads import limit_blas_threads
from .mesh import CELL_TAGS, FACET_TAGS, SURFACE_GRADING, Domain, build_domain
from .post import assemble_scalar, evaluate_at, nodal_values_on_facets
from .scene import Load, Scene
from .solve import make_solver, mass_solve, reaction_force

__all__ = ["Solution", "analyse", "analyse_path", "CONVENTIONS"]

log = logging.getLogger("tankfx")

CONVENTIONS = {
    "units": "SI: m, Pa, N, N m/m",
    "w": "settlement, positive downward",
    "u_r": "radial displacement, positive outward",
    "profiles.axis.z": "depth below the ground surface, positive downward",
    "sigma_zz": "vertical soil stress, positive in compression",
    "nondim": "Eqs. 21-23 of Zaman & Mahmood: w = p a w_bar / E_s, M = p a^2 M_bar, "
              "E_s = soil modulus at the ground surface, a = plate (or load) radius, "
              "p = reference_pressure = load.pressure + liquid (and gas) pressure on the plate "
              "floor",
    "M_r, M_theta, M_z": "bending moments per unit length, positive when the plate's "
                         "underside (the wall's outer face) is in tension: sagging plate "
                         "moment positive",
    "N_theta": "hoop force per unit length, tension positive",
    "Q_r, Q": "transverse shear force per unit length on a section facing +r (plate) or +z "
              "(wall), positive upward on the plate and inward on the wall",
    "rotation": "counter-clockwise rotation of the meridian in the (r, z) plane, rad",
    "contact_normal": "interface normal stress, positive in compression, Pa",
    "contact_shear": "interface shear stress exerted by the soil on the structure, positive "
                     "outward (+r) under the plate and upward on the wall, Pa",
    "profiles.wall.z": "height above the plate underside (the wall base), m",
    "reaction": "upward force of the supports on the soil, N",
    "overturning": "first Fourier harmonic: an amplitude f is the value at theta = 0 of "
                   "f cos(theta) (f sin(theta) for u_theta and N_z_theta); theta = 0 is the "
                   "side a positive overturning_moment presses down and base_shear pushes "
                   "towards; toe / heel: the sides pressed down / lifted (axisymmetric "
                   "+ / - amplitude); tilt in rad, positive towards theta = 0",
}


@dataclass
class Solution:
    """A solved scene: the FE fields (for further post-processing) and the results dict."""

    scene: Scene
    domain: Domain
    u: fem.Function
    sigma_zz: fem.Function
    results: dict
    model: object = None
    #: the overturning's first harmonic (tankfx.rocking.RockingModel) where the load has one
    harmonic: object = None


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("tankfx", "dolfinx-solver-real", "fenics-basix", "fenics-ffcx", "fenics-ufl",
                "petsc4py", "gmsh", "numpy", "mpi4py"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            pass
    import dolfinx

    out["dolfinx"] = dolfinx.__version__
    return out


#: mesh_grading_warning: warned above lambda x edge size = GRADING_WARNING, where the
#: settlement's shortfall GRADING_ERROR (lambda h_edge)^2 passes 0.1 %
GRADING_WARNING, GRADING_ERROR = 2.0, 2.2e-4


def mesh_grading_warning(scene: Scene) -> str | None:
    """A soil whose modulus doubles within a depth 1/lambda much shorter than the elements
    the mesh can grade to there (they stop at the foundation's edge size) settles too
    little: say so, with the expected size of it and the fix. Measured on the flexible load
    at nu = 0.3 against the Riccati reference, w0 falls short by about 2.2e-4 (lambda
    h_edge)^2: 3e-5 at lambda h_edge = 0.5, 0.35 % at 4, 2 % at 10."""
    lam, h = scene.soil.E_gradient, scene.mesh.edge_size
    if lam * h <= GRADING_WARNING:
        return None
    return (f"soil.E_gradient = {lam:g} /m doubles the modulus within {1e3 / lam:.3g} mm of "
            f"the surface, but the mesh's elements there stop at mesh.edge_size = {h:.3g} m: "
            f"a compressible soil's settlement comes out about "
            f"{GRADING_ERROR * (lam * h) ** 2:.1%} too small; lower mesh.edge_size towards "
            f"{SURFACE_GRADING / lam:.3g} m (the grading's own size) for more accuracy")


def _cell_field(msh, values: np.ndarray, name: str) -> fem.Function:
    """A DG0 field of per-cell values (in cell order)."""
    f = fem.Function(fem.functionspace(msh, ("DG", 0)), name=name)
    f.x.array[f.function_space.dofmap.list[:, 0]] = values
    return f


#: Cell tags of the strata of layered ground (stratum i: STRATUM_TAG + i), clear of the
#: domain's own cell tags
STRATUM_TAG = 100


def empty_form(space: fem.FunctionSpace):
    """A bilinear form on ``space`` x ``space`` integrated over no cells: it assembles
    nothing, but gives a block system's part a diagonal block where the block assembly
    needs one (supports on it, or a row that would be empty)."""
    msh = space.mesh
    none = dmesh.meshtags(msh, msh.topology.dim, np.empty(0, np.int32), np.empty(0, np.int32))
    dx = ufl.Measure("dx", domain=msh, subdomain_data=none)
    return fem.Constant(msh, 0.0) * ufl.inner(ufl.TrialFunction(space),
                                              ufl.TestFunction(space)) * dx(1)


class SoilBlock:
    """The soil field on the parent mesh: its space, modulus, stiffness forms and supports.

    ``a`` is the displacement block (to which the interface adds its terms). A soil with
    nu > ``MIXED_FROM_NU`` is solved in the mixed form (:func:`tankfx.soil.mixed_stiffness_forms`):
    it then has a pressure too, ``unknowns`` = [u, p], and ``pressures`` = [(p, (a_up, a_pu,
    a_pp), L_p)]; otherwise ``unknowns`` = [u]. On layered ground each stratum with such a
    nu has a pressure of its own (``mixed_strata``), pinned outside its cells.
    ``stress(u)`` is the stress of either form."""

    def __init__(self, scene: Scene, domain: Domain):
        msh = domain.mesh
        self.scene, self.domain = scene, domain
        s = scene.soil
        self.V = fem.functionspace(msh, ("Lagrange", scene.mesh.degree, (2,)))
        self.u = fem.Function(self.V, name="u")
        self.r = soil_forms.radius(msh)
        h = soil_forms.depth(msh)
        strata = s.strata
        #: the strata solved in the mixed form (nu > MIXED_FROM_NU), each with a pressure
        #: of its own: p = -lambda tr(eps) jumps where lambda does, at a layer's top, which
        #: one pressure continuous over the layers cannot follow (measured: w0 1.6-1.8 %
        #: off on three layers, against 3e-5 without a mixed layer)
        # (and Duncan & Chang's soil throughout: Soil.mixed_strata)
        dc = s.model == "duncan_chang"
        self.mixed_strata = s.mixed_strata
        self.mixed = bool(self.mixed_strata)
        self.stratum = np.zeros(0, dtype=np.int32)     # per local cell (layered ground)
        #: per local cell, its stratum's constants (Soil.at_depth; layered ground and
        #: Duncan & Chang's soil, else None)
        self.cell_strata = None
        #: which local cells are a ringwall's, and its fill's (none without); the secant
        #: iteration leaves both (``linear_cells``) at their own modulus
        ring = scene.ringwall
        self.ringwall_cells = np.zeros(len(domain.cell_midpoints), dtype=bool)
        self.fill_cells = self.ringwall_cells.copy()
        #: a ringwall's cells (and its fill's) are materials of their own: the last
        #: "strata" (linear, in the displacement form), after the ground's
        self.n_materials = len(strata) + (ring is not None) + \
            (ring is not None and ring.fill_E is not None)
        if s.layers or dc or ring is not None:
            # per cell, its stratum's values (the layers' tops are lines of the mesh, so
            # no cell straddles two): E = E_top (1 + lambda (h - top)) within each; and a
            # Poisson's ratio per cell, which a failed Duncan-Chang cell changes
            depth = -domain.cell_midpoints[:, 1]
            self.stratum = s.stratum_of(depth).astype(np.int32)
            values = self.cell_strata = s.at_depth(depth)
            if ring is not None:
                self.ringwall_cells = ring.holds(*domain.cell_midpoints.T, scene.embedment)
                self.fill_cells = ring.fill_holds(*domain.cell_midpoints.T, scene.embedment)
                for k, (cells, E, nu) in enumerate(((self.ringwall_cells, ring.E, ring.nu),
                                                    (self.fill_cells, ring.fill_E,
                                                     ring.fill_nu))):
                    self.stratum[cells] = len(strata) + k
                    for key, value in (("E_top", E), ("E_gradient", 0.0), ("top", 0.0),
                                       ("nu", nu)):
                        values[key][cells] = value
            self.E_s, self.gradient, top, self.nu = (
                _cell_field(msh, values[key], key) for key in ("E_top", "E_gradient", "top",
                                                               "nu"))
            h = h - top
        else:
            # Constants rather than floats: the compiled forms are then shared by every
            # scene of the same structure (sweeps, benchmarks) instead of recompiled per
            # value.
            self.E_s = fem.Constant(msh, s.E)
            self.nu = fem.Constant(msh, s.nu)
            self.gradient = fem.Constant(msh, s.E_gradient)
        self.E = soil_forms.modulus_with_depth(self.E_s, self.gradient, h)
        if s.nonlinear:
            # the secant modulus, one value per cell, starting at the initial tangent modulus
            # (at the cell's centroid, like the paper's element modulus)
            if dc:      # at the geostatic confinement (depth: the cells', above)
                from .hyperbolic import initial_modulus

                initial = initial_modulus(s, depth, values)
                # a ringwall and its fill are no soil of this law: their own E
                initial[self.linear_cells] = values["E_top"][self.linear_cells]
                modulus = _cell_field(msh, initial, "secant_modulus")
            else:
                Q0 = fem.functionspace(msh, ("DG", 0))
                modulus = fem.Function(Q0, name="secant_modulus")
                modulus.interpolate(fem.Expression(self.E, Q0.element.interpolation_points))
            self.E = modulus
        self.trial, self.test = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        self._cell_measures(self.n_materials)
        self.unknowns = [self.u]
        #: per mixed stratum: (its pressure, (a_up, a_pu, a_pp), its zero load)
        self.pressures = []
        #: the stratum of each pressure (pinned outside its cells)
        self.pressure_strata = list(self.mixed_strata)
        #: a consolidating soil's excess pore pressure is its one pressure (Biot)
        self.consolidating = scene.consolidation is not None
        if self.consolidating:
            self.mixed_strata, self.mixed = [], True
        displacement_form = [i for i in range(self.n_materials) if i not in self.mixed_strata]
        self.a = 0
        if self.consolidating:
            self._pore_pressure(msh)
        elif displacement_form:
            self.a = soil_forms.stiffness_form(self.trial, self.test, self.E, self.nu, self.r,
                                               self.dx_strata(displacement_form))
        for i in self.mixed_strata:
            # a space of its own per pressure: Dirichlet conditions go to the blocks by
            # their space, and each pressure is pinned outside its own stratum
            Q = fem.functionspace(msh, ("Lagrange", scene.mesh.degree - 1))
            p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
            a_uu, a_up, a_pu, a_pp = soil_forms.mixed_stiffness_forms(
                self.trial, p, self.test, q, self.E, self.nu, self.r, self.dx_strata([i]))
            self.a += a_uu
            others = self.dx_outside(i)
            if others is not None:
                # a zero term elsewhere puts the pressure's pinned dofs in the sparsity
                # pattern, so that their Dirichlet rows get a diagonal
                a_pp += fem.Constant(msh, 0.0) * p * q * others
            name = "pressure" if len(strata) == 1 else f"pressure_{i}"
            self.pressures.append((fem.Function(Q, name=name), (a_up, a_pu, a_pp),
                                   fem.Constant(msh, 0.0) * q * self.dx_strata([i])))
        self.unknowns += [pr for pr, _, _ in self.pressures]
        #: each cell's most loaded state and unloading line along a load path (a nonlinear
        #: soil with an unloading modulus), else None
        self.memory = None
        if s.unloading_modulus_ratio is not None:
            from .hyperbolic import UnloadingMemory

            self.memory = UnloadingMemory(self.E, scene.mesh.degree, s.unloading_modulus_ratio,
                                          self._cell_pressure() if self.mixed else None)
        if domain.has_void:
            # A zero term over the void: it puts the void's dofs in the sparsity pattern, so
            # that their Dirichlet rows get a diagonal (it adds nothing to any value).
            self.a += fem.Constant(msh, 0.0) * ufl.inner(self.trial, self.test) * self.dx_void
        self.bcs = self._supports()
        self.supported_facets = domain.facets("far_side", "bottom")

    def _pore_pressure(self, msh) -> None:
        """Biot's blocks (tankfx.consolidation) for the excess pore pressure, one degree
        below the displacement, with the drained boundaries by Nitsche's method; the time
        step enters through ``conductance`` (dt k / gamma_w) and ``step_weights``, the
        earlier states through ``u_n``, ``u_nn``."""
        from . import consolidation as cf

        scene = self.scene
        c, deg = scene.consolidation, scene.mesh.degree
        Q = fem.functionspace(msh, ("Lagrange", deg - 1))
        p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        #: dt_eff / gamma_w (s m^3/N), times each stratum's permeability in the forms
        self.conductance = fem.Constant(msh, 0.0)
        strata = scene.soil.strata
        k, _ = cf.stratum_coefficients(scene)
        # a ringwall (and its fill) has no pore pressure: k 0 there (its own materials
        # follow the ground's strata)
        k += [0.0] * (self.n_materials - len(strata))
        #: Darcy's k (m/s): one value, or per cell by stratum (layers, a ringwall)
        self.permeability = fem.Constant(msh, k[0]) if self.n_materials == 1 else \
            _cell_field(msh, np.array(k)[self.stratum], "permeability")
        self.step_weights = w = cf.StepWeights(msh)
        self.u_n, self.u_nn = (fem.Function(self.V, name=n) for n in ("u_n", "u_nn"))
        flow = self.conductance * self.permeability
        #: the ground's strata: where the pore water is (not a ringwall's concrete, nor
        #: its fill, which drains)
        self.ground = tuple(range(len(strata)))
        dx_ground = self.dx_strata(self.ground)
        _, a_up, a_pu, a_pp = cf.biot_forms(self.trial, p, self.test, q, self.E, self.nu,
                                            flow, self.r, dx_ground)
        a_uu = soil_forms.stiffness_form(self.trial, self.test, self.E, self.nu, self.r,
                                         self.dx)
        drained = ["surface"] + (["contact"] if scene.plate is None else []) + \
            (["bottom"] if c.drainage == "top_and_bottom" else [])
        ds = ufl.Measure("ds", domain=msh, subdomain_data=self.domain.facet_tags)
        a_pp += cf.drainage_form(p, q, flow, self.r,
                                 ds(tuple(FACET_TAGS[n] for n in drained)), deg - 1)
        fill_faces = self._fill_faces(msh)
        if fill_faces is not None:
            # a ringwall's fill drains: the ground's faces on it are drained boundaries,
            # from the ground's side (the fill's own pore pressure is pinned to 0)
            chi = self.in_ground
            a_pp += sum(cf.drainage_form(p(side), q(side), flow(side), self.r,
                                         fill_faces, deg - 1, side=side, weight=chi(side))
                        for side in ("+", "-"))
        others = self.dx_outside(self.ground)
        if others is not None:
            # (the pressure dofs there are pinned, see pins: a zero term gives their
            # Dirichlet rows a diagonal)
            a_pp += fem.Constant(msh, 0.0) * p * q * others
        self.a = a_uu
        self.pressures.append((fem.Function(Q, name="pore_pressure"), (a_up, a_pu, a_pp),
                               cf.previous_volume_load([(w.previous, self.u_n),
                                                        (w.before, self.u_nn)],
                                                       q, self.r, dx_ground)))
        # one pore pressure, continuous over the strata (its flux too, naturally); none
        # in a ringwall (no flow across its faces) and none in its fill (drained: the
        # ground drains into it)
        self.pressure_strata = [self.ground]

    def _fill_faces(self, msh):
        """The interior-facet measure of the faces between a ringwall's fill and the ground
        (None without a fill, on every rank alike)."""
        if not msh.comm.allreduce(bool(self.fill_cells.any()), op=MPI.LOR):
            return None
        tdim = msh.topology.dim
        msh.topology.create_connectivity(tdim - 1, tdim)
        f2c = msh.topology.connectivity(tdim - 1, tdim)
        n = msh.topology.index_map(tdim - 1).size_local + \
            msh.topology.index_map(tdim - 1).num_ghosts
        ground = np.isin(self.stratum, self.ground)
        ground[self.domain.cells("void")] = False
        fill, start = self.fill_cells, f2c.offsets[:n]
        two = np.flatnonzero(np.diff(f2c.offsets)[:n] == 2)     # interior facets
        c0, c1 = f2c.array[start[two]], f2c.array[start[two] + 1]
        faces = two[(fill[c0] & ground[c1]) | (fill[c1] & ground[c0])].astype(np.int32)
        tags = dmesh.meshtags(msh, tdim - 1, faces, np.ones(len(faces), dtype=np.int32))
        return ufl.Measure("dS", domain=msh, subdomain_data=tags)(1)

    @cached_property
    def in_ground(self) -> fem.Function:
        """DG0: 1 in the consolidating ground's cells, 0 in a ringwall's and its fill's
        (where there is no pore pressure)."""
        return _cell_field(self.domain.mesh, np.isin(self.stratum, self.ground)
                           .astype(float), "in_ground")

    @property
    def pore_pressure(self) -> fem.Function | None:
        """The excess pore pressure (Pa, compression positive) of a consolidating soil."""
        return self.pressures[0][0] if self.consolidating else None

    @property
    def linear_cells(self) -> np.ndarray:
        """The local cells a nonlinear soil's secant iteration leaves at their modulus: a
        ringwall's and its fill's."""
        return self.ringwall_cells | self.fill_cells

    def _cell_measures(self, n_strata: int) -> None:
        """The soil's ``dx`` and the void's ``dx_void``, and per stratum those of
        :meth:`dx_strata` and :meth:`dx_outside`: all from one set of cell tags, since a
        form's cell integrals must share theirs. One stratum: the domain's tags; layered
        ground: tags by stratum (soil cells of stratum i: STRATUM_TAG + i, the void: its
        tag of the domain)."""
        msh, dom = self.domain.mesh, self.domain
        self.n_strata = n_strata
        tags, soil_ids = dom.cell_tags, (CELL_TAGS["soil"],)
        if n_strata > 1:
            tag = np.full(len(self.stratum), CELL_TAGS["void"], dtype=np.int32)
            soil = dom.cells("soil")
            tag[soil] = STRATUM_TAG + self.stratum[soil]
            cells = np.arange(len(tag), dtype=np.int32)
            tags = dmesh.meshtags(msh, 2, cells, tag)
            soil_ids = tuple(STRATUM_TAG + i for i in range(n_strata))
        self._dx_tagged = ufl.Measure("dx", domain=msh, subdomain_data=tags, metadata={
            "quadrature_degree": soil_forms.quadrature_degree(self.scene.mesh.degree)})
        self.dx = self._dx_tagged(soil_ids if n_strata > 1 else soil_ids[0])
        self.dx_void = ufl.Measure("dx", domain=msh, subdomain_data=tags)(CELL_TAGS["void"])

    def dx_strata(self, strata):
        """The measure of the soil cells of the given strata (indices into Soil.strata)."""
        if len(set(strata)) == self.n_strata:
            return self.dx
        return self._dx_tagged(tuple(STRATUM_TAG + int(i) for i in strata))

    def dx_outside(self, i):
        """The measure of every cell but stratum i's soil (or the strata in a tuple's; None
        where there is none)."""
        inside = {i} if isinstance(i, (int, np.integer)) else set(i)
        if self.n_strata == 1 or inside >= set(range(self.n_strata)):
            return self.dx_void if self.domain.has_void else None
        ids = [STRATUM_TAG + j for j in range(self.n_strata) if j not in inside]
        if self.domain.has_void:
            ids.append(CELL_TAGS["void"])
        return self._dx_tagged(tuple(ids))

    def stratum_cells(self, i) -> np.ndarray:
        """Local soil cells (owned and ghost) of stratum i (or of the strata in a tuple)."""
        soil = self.domain.cells("soil")
        return soil if self.n_strata == 1 else soil[np.isin(self.stratum[soil], i)]

    def _supports(self) -> list[fem.DirichletBC]:
        V, dom = self.V, self.domain
        fdim = dom.mesh.topology.dim - 1
        Vr = V.sub(0)
        axis = fem.locate_dofs_topological(Vr, fdim, dom.facets("axis"))
        far = fem.locate_dofs_topological(V, fdim, dom.facets("far_side", "bottom"))
        zero = np.zeros(2, dtype=np.float64)
        bcs = [fem.dirichletbc(0.0, axis, Vr),                 # symmetry: u_r = 0 on r = 0
               fem.dirichletbc(zero, far, V)]                  # rigid far boundary
        bcs += self.pins(V, [(pr.function_space, i) for i, (pr, _, _) in
                             zip(self.pressure_strata, self.pressures)])
        return bcs

    def pins(self, V, pressure_spaces) -> list[fem.DirichletBC]:
        """The supports that are not boundary conditions: the void's dofs of the
        displacement space ``V`` that touch no soil cell (it carries no stiffness), and
        each mixed stratum's pressure (``pressure_spaces``: (space, stratum index))
        everywhere outside its cells."""
        dom, bcs = self.domain, []
        if dom.has_void:
            void = fem.locate_dofs_topological(V, 2, dom.cells("void"))
            soil = fem.locate_dofs_topological(V, 2, dom.cells("soil"))
            bcs.append(fem.dirichletbc(np.zeros(V.dofmap.index_map_bs),
                                       np.setdiff1d(void, soil), V))
        for Q, i in pressure_spaces:
            imap = Q.dofmap.index_map
            every = np.arange(imap.size_local + imap.num_ghosts, dtype=np.int32)
            own = fem.locate_dofs_topological(Q, 2, self.stratum_cells(i))
            pinned = np.setdiff1d(every, own).astype(np.int32)
            if dom.mesh.comm.allreduce(len(pinned)):
                bcs.append(fem.dirichletbc(0.0, pinned, Q))
        return bcs

    def dofs(self) -> dict[str, int]:
        out = {"soil": self.V.dofmap.index_map.size_global * self.V.dofmap.index_map_bs}
        if self.mixed:
            name = "pore_pressure" if self.consolidating else "soil_pressure"
            out[name] = sum(pr.function_space.dofmap.index_map.size_global
                            for pr, _, _ in self.pressures)
        return out

    def stress(self, u=None):
        """The soil stress (3 x 3, tension positive) of a displacement (default: the
        solution, with the stress its unloading cells keep), with the solution's pressure
        in the mixed form."""
        out = self.stress_of(soil_forms.strain(self.u if u is None else u, self.r),
                             [pr for pr, _, _ in self.pressures])
        if u is None and self.memory is not None:
            out += self.initial_stress()
        return out

    def _cell_pressure(self):
        """The mixed form's pressure of each cell's own stratum (UFL; the displacement
        form's cells: 0)."""
        pressures = [pr for pr, _, _ in self.pressures]
        if self.n_strata == 1:
            return pressures[0]
        return sum(c * pr for c, pr in zip(self._in_mixed, pressures))

    @cached_property
    def _in_mixed(self) -> list[fem.Function]:
        """Per mixed stratum, its cells' indicator (DG0)."""
        return [_cell_field(self.domain.mesh, (self.stratum == i).astype(float), f"in_{i}")
                for i in self.mixed_strata]

    @cached_property
    def _nu_displacement_form(self) -> fem.Function:
        """Poisson's ratio of the displacement form's cells, 0 in the mixed form's (where
        lambda may be infinite), for an expression valid in every cell (layered ground;
        only a mixed cell's nu ever changes, a failed Duncan-Chang cell's)."""
        in_mixed = np.isin(self.stratum, self.mixed_strata)
        nu = self.nu.x.array[self.nu.function_space.dofmap.list[:, 0]]
        return _cell_field(self.domain.mesh, np.where(in_mixed, 0.0, nu),
                           "nu_displacement_form")

    def initial_stress(self):
        """The stress the unloading cells keep (tankfx.hyperbolic.UnloadingMemory): with
        their most loaded state's strain eps_p and modulus E_p (nu_p), sigma_p - D(E_ur)
        eps_p, which the displacement form writes D(E_p - E_ur) eps_p (nu fixed). The mixed
        form's pressure stays the whole pressure, p = p_p - lambda_ur tr(eps - eps_p) on
        the line (continuous over the cells, whichever branch each is on; its constraint's
        right-hand side in :meth:`load_rows`), so that its fixed part is only the shear's,
        2 (mu_p - mu_ur) eps_p."""
        m, r = self.memory, self.r
        eps_p = soil_forms.strain(m.peak_u, r)
        if not self.mixed:
            return m.unloading * soil_forms.stress(eps_p, m.peak_modulus - self.E, self.nu)
        mixed = 2.0 * (soil_forms.lame(m.peak_modulus, m.peak_nu)[1] -
                       soil_forms.lame(self.E, self.nu)[1]) * eps_p
        if self.n_strata == 1:
            return m.unloading * mixed
        # the displacement form's strata by their own law
        chi = sum(self._in_mixed)
        return m.unloading * ((1.0 - chi) * soil_forms.stress(
            eps_p, m.peak_modulus - self.E, self._nu_displacement_form) + chi * mixed)

    def stress_of(self, eps, pressures):
        """The stress of a strain tensor ``eps`` with the mixed strata's ``pressures`` (one
        per mixed stratum, in order): of this soil's materials (also for the overturning's
        first harmonic, whose strain and pressures are amplitudes)."""
        if not self.mixed:
            return soil_forms.stress(eps, self.E, self.nu)
        if self.consolidating:      # total stress: the skeleton's less the pore pressure
            p = pressures[0]
            if self.n_materials > len(self.ground):     # (none in a ringwall, its fill)
                p = p * self.in_ground
            return soil_forms.stress(eps, self.E, self.nu) - p * ufl.Identity(3)
        if self.n_strata == 1:
            return soil_forms.mixed_stress(eps, pressures[0], self.E, self.nu)
        # per cell the form of its stratum, by indicators (an expression valid in every
        # cell, for projections and cell fields)
        chi = self._in_mixed
        out = (1.0 - sum(chi)) * soil_forms.stress(eps, self.E, self._nu_displacement_form)
        for c, pr in zip(chi, pressures):
            out += c * soil_forms.mixed_stress(eps, pr, self.E, self.nu)
        return out

    def matrix_rows(self, a_uu):
        """The soil's rows of a block matrix, from its displacement block: [[a_uu]] or,
        mixed, [[a_uu, a_up_1, ...], [a_pu_1, a_pp_1, None, ...], ...]: a pressure per
        mixed stratum."""
        m = len(self.pressures)
        rows = [[a_uu] + [blocks[0] for _, blocks, _ in self.pressures]]
        for j, (_, (_, a_pu, a_pp), _) in enumerate(self.pressures):
            rows.append([a_pu] + [a_pp if k == j else None for k in range(m)])
        return rows

    def split_rows(self, a_uu_fixed, a_uu_varying=None) -> tuple[list, list]:
        """The soil's rows (:meth:`matrix_rows`) in two parts that sum to those of
        ``a_uu_fixed + a_uu_varying``, for a solver that assembles the fixed part once:
        fixed, ``a_uu_fixed``, the pressures' couplings and their own blocks unless they are
        a consolidation's flow terms (which change with the time step); varying,
        ``a_uu_varying`` and those flow terms. A diagonal block that a part lacks is an
        :func:`empty_form`."""
        fixed = self.matrix_rows(a_uu_fixed)
        m = len(self.pressures)
        varying = [[empty_form(self.V) if a_uu_varying is None else a_uu_varying] + [None] * m]
        for j, (pressure, (_, _, a_pp), _) in enumerate(self.pressures):
            varying.append([None] * (m + 1))
            if self.consolidating:
                fixed[j + 1][j + 1] = empty_form(pressure.function_space)
                varying[-1][j + 1] = a_pp
            else:
                varying[-1][j + 1] = empty_form(pressure.function_space)
        return fixed, varying

    def load_rows(self, L_u):
        """The soil's rows of a block load vector: [L_u] or, mixed, [L_u, L_p_1, ...]; the
        stress the unloading cells keep is a load of the displacement row."""
        L_p = [L for _, _, L in self.pressures]
        if self.memory is not None:
            w = 2.0 * math.pi * self.r
            L_u = L_u - ufl.inner(self.initial_stress(),
                                  soil_forms.strain(self.test, self.r)) * w * self.dx
            # mixed: on its line a cell's pressure is p_p - lambda_ur tr(eps - eps_p), so
            # that the constraint -tr(eps) - p / lambda_ur has the right-hand side
            # -tr(eps_p) - p_p / lambda_ur there
            m = self.memory
            if self.mixed:
                rhs = m.unloading * (ufl.tr(soil_forms.strain(m.peak_u, self.r)) +
                                     m.peak_p * soil_forms.inverse_lambda(self.E, self.nu))
                L_p = [L - rhs * ufl.TestFunction(pr.function_space) * w * self.dx_strata([i])
                       for L, (pr, _, _), i in zip(L_p, self.pressures, self.pressure_strata)]
        return [L_u] + L_p

    def residual(self, a_uu, L_u):
        """The displacement equations' residual a(u, v) - L(v) (support reactions)."""
        res = ufl.action(a_uu, self.u) - L_u
        for pr, (a_up, _, _), _ in self.pressures:
            res += ufl.action(a_up, pr)
        return res

    def vertical_stress(self, stress=None, name: str = "sigma_zz") -> fem.Function:
        """sigma_zz (compression positive) of the solution's stress (or of ``stress``),
        L2-projected (r-weighted) onto the continuous displacement space: point values of
        the raw stress on the axis, a boundary of the meridian plane, are noisy for nearly
        incompressible soil; the projection is not."""
        msh = self.domain.mesh
        Q = fem.functionspace(msh, ("Lagrange", self.scene.mesh.degree))
        s, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        sigma = -(self.stress() if stress is None else stress)[1, 1]
        out = fem.Function(Q, name=name)
        bcs = []
        if self.domain.has_void:
            void = fem.locate_dofs_topological(Q, 2, self.domain.cells("void"))
            soil = fem.locate_dofs_topological(Q, 2, self.domain.cells("soil"))
            bcs = [fem.dirichletbc(0.0, np.setdiff1d(void, soil), Q)]
        a = s * q * self.r * self.dx
        if self.domain.has_void:
            a += fem.Constant(msh, 0.0) * s * q * self.dx_void
        mass_solve(a, sigma * q * self.r * self.dx, bcs, out, name="stress projection")
        return out


class FlexibleLoad:
    """A uniform pressure on r <= load_radius of the bare soil (no structure)."""

    def __init__(self, scene: Scene, domain: Domain):
        self.scene, self.domain = scene, domain
        self.soil = soil = SoilBlock(scene, domain)
        # a consolidation's step changes only the flow terms (no interface here)
        self.a_split = soil.split_rows(soil.a) if soil.consolidating else None
        self.pressure = fem.Constant(domain.mesh, scene.load.pressure)
        ds = ufl.Measure("ds", domain=domain.mesh, subdomain_data=domain.facet_tags)
        self.L = -self.pressure * soil.test[1] * 2.0 * math.pi * soil.r * ds(
            FACET_TAGS["contact"])
        rows = soil.load_rows(self.L)
        self.L_u = rows[0]
        self.bcs, self.entity_maps = soil.bcs, None
        if soil.mixed:
            self.a, self.L = soil.matrix_rows(soil.a), rows
            self.unknowns = soil.unknowns
        else:
            self.a, self.L, self.unknowns = soil.a, self.L_u, soil.u

    @property
    def applied_load(self) -> float:
        """Resultant of the applied pressure, N (closed form, independent of the mesh)."""
        return self.scene.load.pressure * math.pi * self.scene.foundation_radius**2

    @property
    def reference_pressure(self) -> float:
        return self.scene.load.pressure

    #: as TankModel's: a consolidation's load path's largest load scale so far, N
    path_load_scale = 0.0

    @property
    def load_scale(self) -> float:
        """The size of the vertical loads, N, for the relative equilibrium error."""
        return max(abs(self.applied_load), self.path_load_scale)

    def dofs(self) -> dict[str, int]:
        return self.soil.dofs()

    def begin_stage(self) -> None:
        pass

    def set_loads(self, load) -> None:
        """The pressure of a later load stage (on the same, meshed, loaded circle)."""
        from dataclasses import replace

        self.scene = replace(self.scene, load=load)
        self.pressure.value = load.pressure

    def solve(self, solver, log, single_pass: bool = False) -> int:
        solver.solve()
        return 0

    def soil_residual(self):
        return self.soil.residual(self.soil.a, self.L_u)

    def foundation_results(self) -> dict:
        """w0, w_edge, wd, w_mean of the loaded area (on the soil surface)."""
        a, u = self.scene.foundation_radius, self.soil.u
        ce = evaluate_at(u, np.array([[0.0, 0.0], [a, 0.0]]))
        x, vals = nodal_values_on_facets(u, self.domain.facets("contact"))
        w = -vals[:, 1]
        ds = ufl.Measure("ds", domain=self.domain.mesh, subdomain_data=self.domain.facet_tags)
        w_mean = assemble_scalar(-u[1] * 2.0 * math.pi * self.soil.r * ds(
            FACET_TAGS["contact"]), self.domain.mesh.comm) / (math.pi * a**2)
        return {"w0": float(-ce[0, 1]), "w_edge": float(-ce[1, 1]),
                "wd": float(w.max() - w.min()), "w_mean": float(w_mean), "M0": None}


def build_model(scene: Scene, domain: Domain):
    """The model a scene needs: only the parts it uses are built."""
    if scene.plate is None:
        return FlexibleLoad(scene, domain)
    from .coupled import TankModel

    return TankModel(scene, domain)


def analyse(scene: Scene, comm: MPI.Comm = MPI.COMM_WORLD, nested: bool = False) -> Solution:
    """Mesh, solve and post-process a scene; returns the solution and its results dict (of
    the last stage of the scene's load path, with every stage's key numbers under
    ``stages``, when it has one). ``nested`` (with a hyperbolic soil and a Mohr-Coulomb
    interface): converge the interface inside every soil iteration, or (default) update both
    once per iteration, which took fewer solves on the embedded demo tank (21 against 26,
    README)."""
    return analyse_path(scene, list(scene.stages) or [scene.load], comm, nested)[-1]


def analyse_path(scene: Scene, loads: list, comm: MPI.Comm = MPI.COMM_WORLD,
                 nested: bool = False) -> list[Solution]:
    """Solve a scene under a sequence of total loads (``Load`` objects or ``[load]`` dicts),
    on one mesh, carrying the interface's element states from each stage to the next: an
    element separated at one stage and in contact at the next is reported ``rebonded``.
    (Each stage is the response to its total load, as in the paper; slip is not
    accumulated along the path.) Returns one solution per stage."""
    from dataclasses import replace

    stages = [ld if isinstance(ld, Load) else scene.with_changes(load=ld).load for ld in loads]
    if scene.consolidation is not None:
        # one analysis in time: its load path (scene.stages at scene.stage_times) is
        # followed by the time stepping (tankfx.consolidation.load_path)
        if stages not in ([scene.load], list(scene.stages)):
            raise ValueError("a consolidation's load path is its scene's [[stages]], each "
                             "with its time: give them in the scene, not as loads here")
        stages = [scene.load]
    if scene.plate is None:
        for ld in stages:
            if ld.load_radius != scene.load.load_radius:
                raise ValueError(f"load.load_radius: every load stage keeps the meshed loaded "
                                 f"circle ({scene.load.load_radius:g} m), got "
                                 f"{ld.load_radius:g} m; analyse the other radius separately")
    t_start = time.perf_counter()
    timings: dict[str, float] = {}
    log.info("scene '%s': meshing on rank 0, distributing over %d rank(s)", scene.title,
             comm.size)
    t = time.perf_counter()
    domain = build_domain(scene, comm)
    timings["mesh"] = time.perf_counter() - t
    ncells = domain.mesh.topology.index_map(2).size_global
    log.info("mesh: %d cells in %.2f s", ncells, timings["mesh"])
    for k, st in enumerate(scene.soil.strata[1:], start=1):
        log.info("  layer from %g m down: E = %.4g Pa, nu = %g%s", st.depth, st.E, st.nu,
                 " (mixed form)" if k in scene.soil.mixed_strata else "")

    t = time.perf_counter()
    model = build_model(replace(scene, load=stages[0]), domain)
    linear_soil = scene.soil.model == "linear"
    mohr_coulomb = scene.interface.condition == "mohr_coulomb"
    # one factorisation: a linear soil under a bonded or smooth interface (its load stages
    # share the matrix)
    one_shot = linear_soil and not mohr_coulomb and scene.consolidation is None
    solver = make_solver(scene, model.a, model.L, model.bcs, model.unknowns,
                         entity_maps=model.entity_maps, name="tank",
                         symmetric=not mohr_coulomb, one_shot=one_shot,
                         # on a linear soil only a Mohr-Coulomb interface's states and a
                         # consolidation's time step change the matrix: the rest is kept
                         split=model.a_split if linear_soil else None)
    timings["forms"] = time.perf_counter() - t
    warnings = list(getattr(model, "warnings", []))
    grading = mesh_grading_warning(scene)
    if grading:
        warnings.append(grading)
    unloading = scene.unloading_stages() if scene.soil.nonlinear else []
    if unloading and scene.soil.unloading_modulus_ratio is None:
        warnings.append(
            f"stages {', '.join(map(str, unloading))}: less vertical load than an earlier "
            f"stage; Kondner's secant law (the paper's) is nonlinear elastic, so the soil "
            f"unloads along its loading curve and keeps no permanent settlement: read "
            f"these stages as the same load applied afresh, not as unloading (give [soil] "
            f"unloading_modulus_ratio for a soil that remembers)")
    for w in warnings:
        log.warning("warning: %s", w)
    dofs = model.dofs()
    log.info("dofs: %s (soil P%d); assembling and solving with MUMPS",
             ", ".join(f"{k} {v}" for k, v in dofs.items()), scene.mesh.degree)
    solutions = []
    rocking = None          # the first harmonic, built by the first stage that overturns
    for k, load in enumerate(stages):
        stage_scene = replace(scene, load=load)
        if k > 0:
            log.info("load stage %d of %d", k + 1, len(stages))
            model.set_loads(load)
        if model.soil.memory is not None:
            # a remembering soil's path may unload to nothing: its equilibrium errors are
            # relative to the path's largest load so far
            model.path_load_scale = model.load_scale
        t = time.perf_counter()
        soil_iteration = None
        model.begin_stage()
        consolidation = None
        if scene.soil.nonlinear:
            from .hyperbolic import HyperbolicIteration

            soil_iteration = HyperbolicIteration(model).run(
                lambda: model.solve(solver, log, single_pass=not nested), log)
        elif scene.consolidation is not None:
            from .consolidation import TimeStepping

            consolidation = TimeStepping(model, solver, log).run()
            # (the load at the last reported time: a load path's may lie between stages)
            stage_scene = replace(scene, load=model.scene.load)
        else:
            model.solve(solver, log)
            if one_shot:
                solver.keep_matrix()       # only the load changes from stage to stage
        timings["assemble_solve"] = time.perf_counter() - t
        log.info("solved in %.2f s", timings["assemble_solve"])

        t = time.perf_counter()
        sigma_zz = model.soil.vertical_stress()
        results = _results(stage_scene, domain, model, sigma_zz)
        timings["post"] = time.perf_counter() - t
        timings["total"] = time.perf_counter() - t_start
        results["dofs"] = dofs | {"total": solver.matrix_size}
        results["timings_s"] = dict(timings)
        results["mpi_ranks"] = comm.size
        results["versions"] = _versions()
        if len(stages) > 1:
            results["stage"] = k + 1
        results["soil"] = soil_iteration or {"model": "linear", "iterations": 0}
        results["soil"]["model"] = scene.soil.model
        results["linear_solves"] = solver.solves
        results["warnings"] = list(warnings)
        held = results["soil"].get("held_on_loading_curve")
        if held:
            results["warnings"].append(
                f"{held} soil cells at their largest strain so far changed between their "
                f"loading curve and their unloading line at every iteration and were held on "
                f"the curve (the paper's law) to converge")
            log.warning("warning: %s", results["warnings"][-1])
        results["linear_solver"] = {
            "method": scene.solver.method, "solves": solver.solves,
            "factorisation": solver.factorisation, "assembly": solver.assembly,
            "scaling": solver.scaling,
            "last_relative_residual": solver.relative_residual,
            "keeps_freed_memory": keep_freed_memory(),
            "numpy_blas_threads": limit_blas_threads()}
        if scene.solver.method == "iterative":
            results["linear_solver"]["krylov_iterations"] = solver.krylov_iterations
        if consolidation is not None:
            results["consolidation"] = consolidation
        # (a consolidation's: the load at its last reported time, on the state then)
        load = stage_scene.load
        if load.overturning:
            rocking = _overturning(model, rocking, load, results, log, sigma_zz)
        solutions.append(Solution(scene=stage_scene, domain=domain, u=model.soil.u,
                                  sigma_zz=sigma_zz, results=results, model=model,
                                  harmonic=rocking if load.overturning else None))
    if len(solutions) > 1:
        solutions[-1].results["stages"] = [_stage_summary(s.results) for s in solutions]
    return solutions


def _overturning(model, rocking, load, results: dict, log, sigma_zz):
    """Solve the first harmonic of an overturning load about the stage's converged state
    and add its results (``results["overturning"]``, the planar tilt, warnings); returns the
    harmonic model for the next stage."""
    from .rocking import RockingModel, superpose

    t = time.perf_counter()
    if rocking is None:
        rocking = RockingModel(model)
    amplitudes = rocking.solve(load.overturning_moment, load.base_shear, log=log.info)
    out, warnings = superpose(results, amplitudes, model.scene, sigma_zz,
                              model.domain.cells("soil"))
    out["relative_residual"] = rocking.relative_residual
    results["overturning"] = out
    summary = results["settlement_summary"]
    summary["planar_tilt"] = out["tilt"]
    summary["note"] = ("planar tilt from the overturning load (first harmonic); the "
                       "axisymmetric settlements are those without it")
    for w in warnings:
        log.warning("warning: %s", w)
    results["warnings"] = results["warnings"] + warnings
    results["timings_s"]["overturning"] = elapsed = time.perf_counter() - t
    results["timings_s"]["total"] += elapsed
    return rocking


def _stage_summary(r: dict) -> dict:
    """A stage's key numbers, for the load path's table in the last stage's results."""
    out = {"stage": r["stage"], "load": r["scene"]["load"],
           "applied_load": r["equilibrium"]["applied_load"],
           **{k: r[k] for k in ("w0", "w_edge", "wd", "w_mean", "M0", "nondim")},
           "soil_iterations": r["soil"]["iterations"], "linear_solves": r["linear_solves"],
           "tilt": r["overturning"]["tilt"] if "overturning" in r else None}
    if "unloading_cells" in r["soil"]:
        out["unloading_cells"] = r["soil"]["unloading_cells"]
    if "interface" in r:
        out["interface"] = {k: v for k, v in r["interface"].items()
                            if k.endswith("_length") or k in ("converged", "iterations")}
    return out


def _axis_pore_pressure(model, domain: Domain, z_axis, sigma_zz) -> dict:
    """A consolidating soil's excess pore pressure down the axis and the effective vertical
    stress sigma_zz - p (both compression positive; the total sigma_zz less the pore
    water's share): what an engineer's hand calculation of consolidation starts from."""
    p = model.soil.pore_pressure
    if p is None:
        return {}
    pw = evaluate_at(p, np.column_stack([np.zeros_like(z_axis), -z_axis]),
                     cells=domain.cells("soil"))[:, 0]
    return {"pore_pressure": pw.tolist(), "sigma_zz_effective": (sigma_zz - pw).tolist()}


def _results(scene: Scene, domain: Domain, model, sigma_zz) -> dict:
    a = scene.foundation_radius
    D = scene.embedment
    p = model.reference_pressure
    E_s = scene.soil.E
    u = model.soil.u
    found = model.foundation_results()

    # ground-surface profile (the loaded area or plate underside, and the free surface out to
    # 5 a), nodal values of the soil
    x, vals = nodal_values_on_facets(u, domain.facets("contact", "surface"))
    keep = x[:, 0] <= 5.0 * a + 1e-12
    surface = {"r": x[keep, 0].tolist(), "z": x[keep, 1].tolist(),
               "w": (-vals[keep, 1]).tolist(), "u_r": vals[keep, 0].tolist()}

    # down the axis 10 a, or to the base of a shallower domain
    z_axis = np.linspace(D, min(D + 10.0 * a, scene.domain.depth), 201)
    sz = evaluate_at(sigma_zz, np.column_stack([np.zeros_like(z_axis), -z_axis]),
                     cells=domain.cells("soil"))[:, 0]

    applied = model.applied_load
    reaction = reaction_force(model.soil_residual(), model.soil.V, 1,
                              model.soil.supported_facets, entity_maps=model.entity_maps)
    # Eq. 23 scales by p: without a pressure or liquid (self-weight only) there is none,
    # and the non-dimensional measures are null rather than NaN (not valid JSON)
    w_scale, m_scale = p * a / E_s, p * a**2
    out = {
        "title": scene.title,
        "converged": True,
        **found,
        "nondim": {"w0": found["w0"] / w_scale if p > 0 else None,
                   "wd": found["wd"] / w_scale if p > 0 else None,
                   "M0": None if found["M0"] is None or p <= 0 else found["M0"] / m_scale,
                   "Kp": scene.Kp, "Kt": scene.Kt},
        "reference_pressure": p,
        "profiles": {"surface": surface,
                     "axis": {"z": z_axis.tolist(), "sigma_zz": sz.tolist(),
                              **_axis_pore_pressure(model, domain, z_axis, sz)}},
        "equilibrium": {"applied_load": applied, "reaction": reaction,
                        "relative_error": abs(reaction - applied) / model.load_scale},
        "conventions": CONVENTIONS,
        "scene": scene.to_dict(),
    }
    if hasattr(model, "structure_results"):
        extra = model.structure_results()
        out["profiles"].update(extra.pop("profiles"))
        out["equilibrium"].update(extra.pop("equilibrium"))
        out.update(extra)
    return out
