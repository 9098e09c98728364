"""The soil block's stress: of a strain in either form (the displacement form's, the mixed
form's with its strata's pressures, Biot's total stress), the solution's (an elastoplastic
soil's from its points), the stress its unloading cells keep, and sigma_zz projected for point
values. All are UFL expressions valid in every cell, for the forms, projections and cell
fields alike.
"""
from __future__ import annotations

from functools import cached_property

import numpy as np
import ufl
from dolfinx import fem

from ..fem.blocks import cell_field
from ..fem.solvers import mass_solve
from ..laws import elasticity as soil_forms
from .plastic import tensor

__all__ = ["SoilStress"]


class SoilStress:
    """The stresses of a soil block (``block``: its materials, pressures, memory and
    measures, read as they are at each call; a consolidating block's pressure is its pore
    pressure)."""

    def __init__(self, block):
        self.block = block

    def stress(self, u=None):
        """The soil stress (3 x 3, tension positive) of a displacement (default: the
        solution, with the stress its unloading cells keep), with the solution's pressure
        in the mixed form."""
        b = self.block
        if b.plastic is not None and u is None:
            # (each cell's mean of its points' stress: the results' view of it)
            return tensor(b.plastic.cell_stress())
        out = self.stress_of(soil_forms.strain(b.u if u is None else u, b.r),
                             [pr for pr, _, _ in b.pressures])
        if u is None and b.memory is not None:
            out += self.initial_stress()
        return out

    def cell_pressure(self):
        """The mixed form's pressure of each cell's own stratum (UFL; the displacement
        form's cells: 0)."""
        pressures = [pr for pr, _, _ in self.block.pressures]
        if self.block.n_strata == 1:
            return pressures[0]
        return soil_forms.by_stratum(self._in_mixed, pressures)

    @cached_property
    def _in_mixed(self) -> list[fem.Function]:
        """Per mixed stratum, its cells' indicator (DG0)."""
        b = self.block
        return [cell_field(b.domain.mesh, (b.stratum == i).astype(float), f"in_{i}")
                for i in b.mixed_strata]

    @cached_property
    def _nu_displacement_form(self) -> fem.Function:
        """Poisson's ratio of the displacement form's cells, 0 in the mixed form's (where
        lambda may be infinite), for an expression valid in every cell (layered ground;
        only a mixed cell's nu ever changes, a failed Duncan-Chang cell's)."""
        b = self.block
        in_mixed = np.isin(b.stratum, b.mixed_strata)
        nu = b.nu.x.array[b.nu.function_space.dofmap.list[:, 0]]
        return cell_field(b.domain.mesh, np.where(in_mixed, 0.0, nu),
                          "nu_displacement_form")

    def initial_stress(self):
        """The stress the unloading cells keep (tankfx.model.memory.UnloadingMemory): with
        their most loaded state's strain eps_p and modulus E_p (nu_p), sigma_p - D(E_ur)
        eps_p, which the displacement form writes D(E_p - E_ur) eps_p (nu fixed). The mixed
        form's pressure stays the whole pressure, p = p_p - lambda_ur tr(eps - eps_p) on
        the line (continuous over the cells, whichever branch each is on; its constraint's
        right-hand side in the block's ``load_rows``), so that its fixed part is only the
        shear's, 2 (mu_p - mu_ur) eps_p."""
        b = self.block
        m, r = b.memory, b.r
        eps_p = soil_forms.strain(m.peak_u, r)
        if not b.mixed:
            return m.unloading * soil_forms.stress(eps_p, m.peak_modulus - b.E, b.nu)
        mixed = 2.0 * (soil_forms.lame(m.peak_modulus, m.peak_nu)[1] -
                       soil_forms.lame(b.E, b.nu)[1]) * eps_p
        if b.n_strata == 1:
            return m.unloading * mixed
        # the displacement form's strata by their own law
        return m.unloading * soil_forms.by_stratum(self._in_mixed, mixed, soil_forms.stress(
            eps_p, m.peak_modulus - b.E, self._nu_displacement_form))

    def stress_of(self, eps, pressures):
        """The stress of a strain tensor ``eps`` with the mixed strata's ``pressures`` (one
        per mixed stratum, in order): of the block's materials (also for the overturning's
        first harmonic, whose strain and pressures are amplitudes)."""
        b = self.block
        if not b.mixed:
            return soil_forms.stress(eps, b.E, b.nu)
        if b.consolidating:      # total stress: the skeleton's less the pore pressure
            p = pressures[0]
            if b.n_materials > len(b.ground):     # (none in a ringwall, its fill)
                p = p * b.in_ground
            return soil_forms.stress(eps, b.E, b.nu) - p * ufl.Identity(3)
        if b.n_strata == 1:
            return soil_forms.mixed_stress(eps, pressures[0], b.E, b.nu)
        # per cell the form of its stratum, by indicators (an expression valid in every
        # cell, for projections and cell fields)
        return soil_forms.by_stratum(
            self._in_mixed, [soil_forms.mixed_stress(eps, pr, b.E, b.nu) for pr in pressures],
            soil_forms.stress(eps, b.E, self._nu_displacement_form))

    def vertical_stress(self, stress=None, name: str = "sigma_zz") -> fem.Function:
        """sigma_zz (compression positive) of the solution's stress (or of ``stress``),
        L2-projected (r-weighted) onto the continuous displacement space: point values of
        the raw stress on the axis, a boundary of the meridian plane, are noisy for nearly
        incompressible soil; the projection is not."""
        b = self.block
        msh = b.domain.mesh
        Q = fem.functionspace(msh, ("Lagrange", b.setting.degree))
        s, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        sigma = -(self.stress() if stress is None else stress)[1, 1]
        out = fem.Function(Q, name=name)
        bcs = []
        if b.domain.has_void:
            void = fem.locate_dofs_topological(Q, 2, b.domain.cells("void"))
            soil = fem.locate_dofs_topological(Q, 2, b.domain.cells("soil"))
            bcs = [fem.dirichletbc(0.0, np.setdiff1d(void, soil), Q)]
        a = s * q * b.r * b.dx
        if b.domain.has_void:
            a += fem.Constant(msh, 0.0) * s * q * b.dx_void
        mass_solve(a, sigma * q * b.r * b.dx, bcs, out, name="stress projection")
        return out
