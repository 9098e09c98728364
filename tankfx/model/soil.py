"""The soil block: the soil's displacement (and, in the mixed form or a consolidation, its
pressures) on the parent (r, z) mesh, with its materials (strata, a ringwall and its fill), its
stiffness forms (linear elasticity, the mixed u-p form, Biot's), its supports and its stresses.
The paper's soil elements (its axisymmetric elasticity, not numbered there) per cell; a
nonlinear soil's secant modulus of Eq. 19 is the DG0 field ``E``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh

from ..fem.blocks import cell_field, empty_form
from ..laws import elasticity as soil_forms
from ..mesh import CELL_TAGS, Domain
from ..scene.sections import Consolidation, DomainSize, Ringwall, Soil
from .excavation import PitRelease
from .history import History
from .materials import soil_materials
from .memory import UnloadingMemory
from .plastic import PlasticState
from .pore_pressure import PorePressure
from .soil_stress import SoilStress

#: Cell tags of the strata of layered ground (stratum i: STRATUM_TAG + i), clear of the
#: domain's own cell tags
STRATUM_TAG = 100


def far_supports(V, dom: Domain, domain, horizontal: tuple[int, ...],
                 vertical: int) -> list[fem.DirichletBC]:
    """The supports of the far side and the rigid base (``domain``: the scene's
    DomainSize): every component of ``V`` fixed on a "fixed" side and a "rough" base; on a
    "roller" side only the ``horizontal`` components, on a "smooth" base only the
    ``vertical`` one."""
    fdim = dom.mesh.topology.dim - 1
    fixed = [name for name, free in (("far_side", domain.side == "roller"),
                                     ("bottom", domain.base == "smooth")) if not free]
    bcs = []
    if fixed:
        dofs = fem.locate_dofs_topological(V, fdim, dom.facets(*fixed))
        bcs.append(fem.dirichletbc(np.zeros(V.dofmap.index_map_bs), dofs, V))
    for name, components in (("far_side", horizontal if domain.side == "roller" else ()),
                             ("bottom", (vertical,) if domain.base == "smooth" else ())):
        for c in components:
            dofs = fem.locate_dofs_topological(V.sub(c), fdim, dom.facets(name))
            bcs.append(fem.dirichletbc(0.0, dofs, V.sub(c)))
    return bcs


@dataclass(frozen=True)
class SoilSetting:
    """What the soil block reads of a scene: its resolved [soil], the mesh's Lagrange
    ``degree``, the domain's ``extent`` (its supports), the foundation level
    ``embedment`` (m), a ringwall and a consolidation where the scene has them, and whether
    the loaded face drains (``contact_drains``: a flexible load, no plate on it)."""

    soil: Soil
    degree: int
    extent: DomainSize
    embedment: float = 0.0
    ringwall: Ringwall | None = None
    consolidation: Consolidation | None = None
    contact_drains: bool = False

    @classmethod
    def of(cls, scene) -> "SoilSetting":
        return cls(scene.soil, scene.mesh.degree, scene.domain, scene.embedment,
                   scene.ringwall, scene.consolidation, scene.plate is None)


class SoilBlock:
    """The soil field on the parent mesh: its space, modulus, stiffness forms and supports.

    ``a`` is the displacement block (to which the interface adds its terms). A soil with
    nu > ``MIXED_FROM_NU`` is solved in the mixed form
    (:func:`tankfx.laws.elasticity.mixed_stiffness_forms`):
    it then has a pressure too, ``unknowns`` = [u, p], and ``pressures`` = [(p, (a_up, a_pu,
    a_pp), L_p)]; otherwise ``unknowns`` = [u]. On layered ground each stratum with such a
    nu has a pressure of its own (``mixed_strata``), pinned outside its cells.
    ``stress(u)`` is the stress of either form."""

    def __init__(self, setting: SoilSetting, domain: Domain):
        msh = domain.mesh
        self.setting, self.domain = setting, domain
        s = setting.soil
        self.V = fem.functionspace(msh, ("Lagrange", setting.degree, (2,)))
        self.u = fem.Function(self.V, name="u")
        self.r = soil_forms.radius(msh)
        strata = s.strata
        #: the strata solved in the mixed form (nu > MIXED_FROM_NU), each with a pressure
        #: of its own: p = -lambda tr(eps) jumps where lambda does, at a layer's top, which
        #: one pressure continuous over the layers cannot follow (measured: w0 1.6-1.8 %
        #: off on three layers, against 3e-5 without a mixed layer)
        # (and Duncan & Chang's soil throughout: Soil.mixed_strata)
        self.mixed_strata = s.mixed_strata
        self.mixed = bool(self.mixed_strata)
        #: the materials cell by cell (strata, a ringwall and its fill) and the modulus
        #: fields: E is a nonlinear soil's DG0 secant modulus (tankfx.model.materials)
        self.materials = mat = soil_materials(setting, domain)
        self.stratum, self.cell_strata = mat.stratum, mat.cell_strata
        self.ringwall_cells, self.fill_cells = mat.ringwall_cells, mat.fill_cells
        self.n_materials = mat.n_materials
        self.E_s, self.gradient, self.nu, self.E = mat.E_s, mat.gradient, mat.nu, mat.E
        #: the fields its law's iteration changes (tankfx.laws.soil_law.SoilLaw.state_fields)
        #: and its unloading memory, committed when a stage converges and rolled back to
        #: start one again
        self.history = History()
        for name in s.law.state_fields:
            self.history.register(name, getattr(self, name))
        self.trial, self.test = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        self._cell_measures(self.n_materials)
        self.unknowns = [self.u]
        #: per mixed stratum: (its pressure, (a_up, a_pu, a_pp), its zero load)
        self.pressures = []
        #: the stratum of each pressure (pinned outside its cells)
        self.pressure_strata = list(self.mixed_strata)
        #: a consolidating soil's excess pore pressure is its one pressure (Biot)
        self.consolidating = setting.consolidation is not None
        if self.consolidating:
            self.mixed_strata, self.mixed = [], True
        displacement_form = [i for i in range(self.n_materials) if i not in self.mixed_strata]
        self.a = 0
        #: an elastoplastic soil's stress and history at the forms' quadrature points,
        #: and its embedded foundation's pit's relief (tankfx.model.excavation)
        self.plastic = self.pit = None
        if s.law.at_points:
            self.plastic = PlasticState(self, s.law, s, setting.degree, setting.ringwall)
            if self.consolidating:
                # (an effective-stress skeleton: Biot's pore pressure beside it, the
                # skeleton's block its tangent)
                self._pore_pressure(msh)
            self.a = self.plastic.stiffness(self.trial, self.test, self.r, self.dx)
            for name, field in self.plastic.carried().items():
                self.history.register(name, field)
            if setting.embedment > 0.0:
                self.pit = PitRelease(self, s, setting.embedment)
        elif self.consolidating:
            self._pore_pressure(msh)
        elif displacement_form:
            self.a = soil_forms.stiffness_form(self.trial, self.test, self.E, self.nu, self.r,
                                               self.dx_strata(displacement_form))
        for i in self.mixed_strata:
            # a space of its own per pressure: Dirichlet conditions go to the blocks by
            # their space, and each pressure is pinned outside its own stratum
            Q = fem.functionspace(msh, ("Lagrange", setting.degree - 1))
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
        #: its stresses, of either form (tankfx.model.soil_stress)
        self.stresses = SoilStress(self)
        #: each cell's most loaded state and unloading line along a load path (a nonlinear
        #: soil with an unloading modulus), else None
        self.memory = None
        if s.unloading_modulus_ratio is not None:
            self.memory = UnloadingMemory(self.E, setting.degree, s.unloading_modulus_ratio,
                                          self.stresses.cell_pressure() if self.mixed else None)
            for name, field in self.memory.carried().items():
                self.history.register(name, field)
        if domain.has_void:
            # A zero term over the void: it puts the void's dofs in the sparsity pattern, so
            # that their Dirichlet rows get a diagonal (it adds nothing to any value).
            self.a += fem.Constant(msh, 0.0) * ufl.inner(self.trial, self.test) * self.dx_void
        self.bcs = self._supports()
        self.supported_facets = domain.facets("far_side", "bottom")

    @property
    def remembers(self) -> bool:
        """Whether it keeps a state of its own from one stage to the next (an unloading
        memory, a plastic strain): a load path may then take every load off."""
        return self.memory is not None or self.plastic is not None

    def _pore_pressure(self, msh) -> None:
        """Biot's blocks for the excess pore pressure (:class:`PorePressure`): the block's
        displacement form and its one pressure, continuous over the strata (its flux too,
        naturally); none in a ringwall (no flow across its faces) and none in its fill
        (drained: the ground drains into it). A time step changes ``conductance``,
        ``step_weights`` and the earlier states ``u_n``, ``u_nn``."""
        #: the ground's strata: where the pore water is (not a ringwall's concrete, nor
        #: its fill, which drains)
        self.ground = tuple(range(len(self.setting.soil.strata)))
        pore = PorePressure(self, msh)
        self.conductance, self.permeability = pore.conductance, pore.permeability
        self.step_weights, self.u_n, self.u_nn = pore.step_weights, pore.u_n, pore.u_nn
        self.a = pore.a
        self.pressures.append(pore.block)
        self.pressure_strata = [self.ground]

    @cached_property
    def in_ground(self) -> fem.Function:
        """DG0: 1 in the consolidating ground's cells, 0 in a ringwall's and its fill's
        (where there is no pore pressure)."""
        return cell_field(self.domain.mesh, np.isin(self.stratum, self.ground)
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
            "quadrature_degree": soil_forms.quadrature_degree(self.setting.degree)})
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
        bcs = [fem.dirichletbc(0.0, axis, Vr)]                 # symmetry: u_r = 0 on r = 0
        bcs += far_supports(V, dom, self.setting.extent, horizontal=(0,), vertical=1)
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

    # ------------------------------------------------------------------ stresses
    def stress(self, u=None):
        """The soil stress (3 x 3, tension positive) of a displacement (default: the
        solution, with the stress its unloading cells keep; :meth:`SoilStress.stress`)."""
        return self.stresses.stress(u)

    def stress_of(self, eps, pressures):
        """The stress of a strain tensor ``eps`` with the mixed strata's ``pressures``, of
        this soil's materials (:meth:`SoilStress.stress_of`)."""
        return self.stresses.stress_of(eps, pressures)

    def initial_stress(self):
        """The stress the unloading cells keep (:meth:`SoilStress.initial_stress`)."""
        return self.stresses.initial_stress()

    def vertical_stress(self, stress=None, name: str = "sigma_zz") -> fem.Function:
        """sigma_zz (compression positive) of the solution's stress (or of ``stress``),
        projected for point values (:meth:`SoilStress.vertical_stress`)."""
        return self.stresses.vertical_stress(stress, name)

    # ------------------------------------------------------------------ block rows
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
        if self.plastic is not None:
            L_u = L_u + self.plastic.load(self.test, self.r, self.dx)
        if self.pit is not None:
            L_u = L_u + self.pit.load(self.test)
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
