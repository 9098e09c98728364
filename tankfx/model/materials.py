"""The soil's materials, cell by cell: which stratum of layered ground each cell is in (or a
ringwall, or its fill), that stratum's constants, and the modulus fields of the stiffness
forms: E(h) = E_top (1 + lambda (h - top)) (the paper's soil, stiffening with depth), or a
nonlinear soil's DG0 secant modulus (Eq. 19), starting at the initial tangent modulus.
"""
from __future__ import annotations

from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
import numpy as np
from dolfinx import fem

from ..fem.blocks import cell_field
from ..laws import elasticity as soil_forms
from ..mesh import Domain

__all__ = ["SoilMaterials", "soil_materials"]


@dataclass
class SoilMaterials:
    """Per local cell: ``stratum`` (index into the soil's strata, then a ringwall's and its
    fill's, the last "strata"; empty for one homogeneous soil), ``cell_strata`` (the
    stratum's constants, :meth:`tankfx.scene.sections.Soil.at_depth`; None for one
    homogeneous soil), ``ringwall_cells`` and ``fill_cells``; ``n_materials``; the fields
    ``E_s`` (the modulus at each stratum's top), ``gradient``, ``nu`` (DG0 or Constants),
    and ``E``, the modulus of the stiffness forms (a UFL expression of depth, or a
    nonlinear soil's DG0 secant modulus)."""

    stratum: np.ndarray
    cell_strata: dict | None
    ringwall_cells: np.ndarray
    fill_cells: np.ndarray
    n_materials: int
    E_s: object
    gradient: object
    nu: object
    E: object

    @property
    def linear_cells(self) -> np.ndarray:
        """The local cells a nonlinear soil's secant iteration leaves at their modulus: a
        ringwall's and its fill's."""
        return self.ringwall_cells | self.fill_cells


def soil_materials(setting, domain: Domain) -> SoilMaterials:
    """The materials of a soil (``setting``: :class:`tankfx.model.soil.SoilSetting`) on its
    mesh."""
    msh = domain.mesh
    s = setting.soil
    h = soil_forms.depth(msh)
    strata = s.strata
    stratum = np.zeros(0, dtype=np.int32)     # per local cell (layered ground)
    cell_strata = None
    #: which local cells are a ringwall's, and its fill's (none without); the secant
    #: iteration leaves both (``linear_cells``) at their own modulus
    ring = setting.ringwall
    ringwall_cells = np.zeros(len(domain.cell_midpoints), dtype=bool)
    fill_cells = ringwall_cells.copy()
    # a ringwall's cells (and its fill's) are materials of their own: the last "strata"
    # (linear, in the displacement form), after the ground's
    n_materials = len(strata) + (ring is not None) + \
        (ring is not None and ring.fill_E is not None)
    if s.layers or "nu" in s.law.state_fields or ring is not None:
        # per cell, its stratum's values (the layers' tops are lines of the mesh, so no
        # cell straddles two): E = E_top (1 + lambda (h - top)) within each; and a
        # Poisson's ratio per cell, where the law changes it (a failed Duncan-Chang cell)
        depth = -domain.cell_midpoints[:, 1]
        stratum = s.stratum_of(depth).astype(np.int32)
        values = cell_strata = s.at_depth(depth)
        if ring is not None:
            ringwall_cells = ring.holds(*domain.cell_midpoints.T, setting.embedment)
            fill_cells = ring.fill_holds(*domain.cell_midpoints.T, setting.embedment)
            for k, (cells, E, nu) in enumerate(((ringwall_cells, ring.E, ring.nu),
                                                (fill_cells, ring.fill_E, ring.fill_nu))):
                stratum[cells] = len(strata) + k
                for key, value in (("E_top", E), ("E_gradient", 0.0), ("top", 0.0),
                                   ("nu", nu)):
                    values[key][cells] = value
        E_s, gradient, top, nu = (cell_field(msh, values[key], key)
                                  for key in ("E_top", "E_gradient", "top", "nu"))
        h = h - top
    else:
        # Constants rather than floats: the compiled forms are then shared by every scene
        # of the same structure (sweeps, benchmarks) instead of recompiled per value.
        E_s = fem.Constant(msh, s.E)
        nu = fem.Constant(msh, s.nu)
        gradient = fem.Constant(msh, s.E_gradient)
    E = soil_forms.modulus_with_depth(E_s, gradient, h)
    if "E" in s.law.state_fields:
        # the secant modulus, one value per cell, starting at the initial tangent modulus
        # (at the cell's centroid, like the paper's element modulus)
        initial = None if cell_strata is None else s.law.initial_modulus(s, depth, values)
        if initial is not None:     # (the law's, e.g. at the geostatic confinement)
            # a ringwall and its fill are no soil of this law: their own E
            linear = ringwall_cells | fill_cells
            initial[linear] = values["E_top"][linear]
            modulus = cell_field(msh, initial, "secant_modulus")
        else:
            Q0 = fem.functionspace(msh, ("DG", 0))
            modulus = fem.Function(Q0, name="secant_modulus")
            modulus.interpolate(fem.Expression(E, Q0.element.interpolation_points))
        E = modulus
    return SoilMaterials(stratum, cell_strata, ringwall_cells, fill_cells, n_materials,
                         E_s, gradient, nu, E)
