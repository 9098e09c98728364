"""The tank's loads as block load forms whose values are Constants: the pressure on the plate,
the liquid on the floor and the wall, the self-weights, a roof and a gas pressure on the wall's
top edge, a ringwall's weight in excess of the soil's, and a Mohr-Coulomb interface's
cohesion. A load path changes the Constants (:meth:`TankLoads.apply`) without compiling the
forms again.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh

from ..laws import interface
from ..laws import shell as st

__all__ = ["TankLoads"]


class TankLoads:
    """The load rows of a tank model (``tank``: its structure's space, mesh, measures and
    fields, its soil and interface blocks, built before its loads): ``rows`` = the soil's
    (:meth:`tankfx.model.soil.SoilBlock.load_rows`) and the structure's; ``constants`` the
    load values by name (Pa, N/m^3, m, N/m), ``ringwall_weight`` a ringwall's unit weight
    (N/m^3) where some load has self-weight, else None."""

    def __init__(self, tank):
        s, r_b, soil = tank.scene, tank.r_b, tank.soil
        v_f, gamma, _ = ufl.TestFunctions(tank.W)
        # loads act on the mid-surface (for pressures normal to the wall or plate it is the
        # same as on the face; it matters for the wall's self-weight)
        v_b = st.mid_surface_displacement(v_f, gamma, tank.t_b, tank.offset)
        x = ufl.SpatialCoordinate(tank.mesh)
        soil_load = ufl.inner(fem.Constant(tank.domain.mesh, (0.0, 0.0)), soil.test) * soil.dx
        ring, self.ringwall_weight = s.ringwall, None
        if ring is not None and ring.unit_weight and any(ld.self_weight
                                                           for ld in (s.load, *s.stages)):
            # its weight in excess of the soil's, on its own cells (the material after the
            # ground's strata)
            self.ringwall_weight = fem.Constant(tank.domain.mesh, 0.0)
            soil_load += -self.ringwall_weight * soil.test[1] * 2.0 * math.pi * \
                soil.r * soil.dx_strata([len(s.soil.strata)])
        w = 2.0 * math.pi * r_b
        dx_p = tank.dx_b(st.PLATE)
        dx_w = tank.dx_b((st.WALL, st.WALL_EMBEDDED))
        # load values are Constants: a load path changes them without recompiling
        c = self.constants = {k: fem.Constant(tank.mesh, 0.0) for k in (
            "pressure", "liquid_unit_weight", "liquid_height", "plate_weight", "wall_weight",
            "roof_line_load", "gas_pressure")}
        # self-weight: a unit weight times the cell's thickness (a ring, courses)
        th = tank.thickness
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
            # the roof on the wall's top edge: its weight down, the gas's push on it
            # (p pi a_t^2) up
            load += -(c["roof_line_load"] - 0.5 * s.wall.radius * c["gas_pressure"]) * \
                v_b[1] * w * self._wall_top(tank.mesh, s.wall, s.embedment)
        if s.interface.has_states:
            # the cohesion carried by slipping elements, c_s (dj . t), dj = v_soil - v_face
            ifc = tank.interface
            load -= interface.interface_load(v_f, tank.t_b, ifc.c_s, r_b, ifc.dx)
            for _, n, t, pieces in ifc.measures():
                for measure, R in pieces:
                    soil_load += interface.interface_load(R(soil.test), t, R(ifc.c_s),
                                                          soil.r, measure)
        self.rows = soil.load_rows(soil_load) + [load]

    @staticmethod
    def _wall_top(sub, wall, embedment):
        """The measure of the wall's top edge, where the roof bears: a vertex of the
        structure mesh, its ds."""
        top = dmesh.locate_entities_boundary(
            sub, 0, lambda x: np.isclose(x[1], wall.height - embedment)
            & np.isclose(x[0], wall.radius))
        tags = dmesh.meshtags(sub, 0, top, np.full(len(top), 1, dtype=np.int32))
        return ufl.Measure("ds", domain=sub, subdomain_data=tags)(1)

    def apply(self, scene) -> None:
        """Set the Constants to the loads of ``scene.load`` (the forms stay)."""
        s, load, c = scene, scene.load, self.constants
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
