"""A flexible uniform load on a circle of the ground surface: the soil block alone, loaded by
``pressure`` over ``load_radius`` (the paper's verification of the soil, and the flexible
limit Kp = 0 of the plate).
"""
from __future__ import annotations

import math
from dataclasses import replace
from functools import cached_property

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
import numpy as np
import ufl
from dolfinx import fem

from ..fem.blocks import Balanced, OutOfBalance
from ..fem.evaluate import allsum, assemble_scalar, evaluate_at, nodal_values_on_facets
from ..mesh import FACET_TAGS, Domain
from ..scene.scene import Scene
from .soil import SoilBlock, SoilSetting


class FlexibleLoad(Balanced):
    """A uniform pressure on r <= load_radius of the bare soil (no structure)."""

    def __init__(self, scene: Scene, domain: Domain):
        self.scene, self.domain = scene, domain
        self.warnings: list[str] = []           # (its set-up finds none)
        self.soil = soil = SoilBlock(SoilSetting.of(scene), domain)
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

    def commit(self) -> None:
        """The soil's state now is the one to go on from."""
        self.soil.history.commit()

    def rollback(self) -> None:
        """Back to the soil's last committed state."""
        self.soil.history.rollback()

    def set_loads(self, load) -> None:
        """The pressure of a later load stage (on the same, meshed, loaded circle)."""
        self.scene = replace(self.scene, load=load)
        self.pressure.value = load.pressure

    #: no structure, so no interface
    interface = None

    @cached_property
    def _out_of_balance(self) -> OutOfBalance:
        blocks = isinstance(self.a, list)
        return OutOfBalance(self.a if blocks else [[self.a]], self.L if blocks else [self.L],
                            self.unknowns if blocks else [self.unknowns], self.bcs)

    def soil_residual(self):
        return self.soil.residual(self.soil.a, self.L_u)

    def mean_settlement(self) -> float:
        """The loaded area's mean settlement, m: linear in the unknowns, what a collapse's
        settlement control raises."""
        if not hasattr(self, "_w_mean_form"):
            ds = ufl.Measure("ds", domain=self.domain.mesh,
                             subdomain_data=self.domain.facet_tags)
            self._w_mean_form = fem.form(-self.soil.u[1] * 2.0 * math.pi * self.soil.r * ds(
                FACET_TAGS["contact"]))
        a = self.scene.foundation_radius
        return allsum(self.domain.mesh.comm, fem.assemble_scalar(self._w_mean_form)) / (
            math.pi * a ** 2)

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
