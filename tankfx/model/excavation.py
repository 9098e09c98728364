"""The excavation of an embedded foundation's pit in an elastoplastic soil.

The ground at rest (:func:`tankfx.laws.geostatic.geostatic_stress`) is in equilibrium with
its weight as long as nothing is taken out of it; the mesh has the pit already cut, so its
faces carry the stress at rest sigma_0 with nothing to hold it. Excavating is relieving
them: the load

    f(v) = -share x int_pit (sigma_0 n) . v 2 pi r ds,

n the soil's outward normal (up on the pit's bottom, towards the axis on its side), raised
from share = 0 (the ground at rest, the pit still full) to 1 (the pit open), in load steps
of the Newton iteration. Then it stays applied: it is the support the excavated soil no
longer gives. sigma_0 is piecewise linear in depth (strata, a water table); its pieces are
exact here (a UFL expression of the depth, not an interpolation).
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem

from ..fem.evaluate import allsum
from ..laws.geostatic import geostatic_stress
from ..mesh import FACET_TAGS

#: the pit's faces and the soil's outward normal on each (r, z): the bottom (under the
#: plate), the side under an embedded wall, and a free side (an embedded plate alone)
PIT_FACES = {"contact": (0.0, 1.0), "wall_embedded": (-1.0, 0.0),
             "embedded_face": (-1.0, 0.0)}


def at_rest_expression(soil, depth, bottom: float):
    """(sigma'_v, sigma'_h) at rest as UFL expressions of ``depth`` (m), exact down to
    ``bottom`` (m): linear between the kinks (the strata's tops, the water table), each
    piece from its end values inside it (K0 steps at a stratum's top)."""
    kinks = {0.0, bottom, *(st.depth for st in soil.strata)}
    if soil.water_table is not None:
        kinks.add(soil.water_table)
    d = np.array(sorted(k for k in kinks if 0.0 <= k <= bottom))
    sv = sh = 0.0
    for i, (lo, hi) in enumerate(zip(d[:-1], d[1:])):
        # (linear inside the piece: two points inside it give it exactly)
        q1, q3 = lo + 0.25 * (hi - lo), lo + 0.75 * (hi - lo)
        (v0, v1), (h0, h1) = geostatic_stress(soil, np.array([q1, q3]))
        t = (depth - q1) / (q3 - q1)
        # the pieces [lo, hi), the first and last open outwards: the pit's bottom at
        # ``bottom`` is its own to round-off either way
        inside = 1.0
        if i > 0:
            inside = inside * ufl.conditional(ufl.ge(depth, lo), 1.0, 0.0)
        if i < len(d) - 2:
            inside = inside * ufl.conditional(ufl.lt(depth, hi), 1.0, 0.0)
        sv += inside * (v0 + t * (v1 - v0))
        sh += inside * (h0 + t * (h1 - h0))
    return sv, sh


class PitRelease:
    """The load that relieves an excavated pit's faces of the stress at rest (the
    module's f), its ``share`` (a Constant: 0 before the excavation, 1 after) and its
    upward resultant."""

    def __init__(self, block, soil, embedment: float):
        dom = block.domain
        msh = dom.mesh
        self.share = fem.Constant(msh, 0.0)
        depth = -ufl.SpatialCoordinate(msh)[1]
        sv, sh = at_rest_expression(soil, depth, embedment)
        #: sigma'_v at the pit's bottom, Pa
        self.bottom_stress = float(geostatic_stress(soil, np.array([embedment]))[0][0])
        ds = ufl.Measure("ds", domain=msh, subdomain_data=dom.facet_tags)
        dS = ufl.Measure("dS", domain=msh, subdomain_data=dom.facet_tags)
        w = 2.0 * math.pi * block.r
        self._parts = []
        for name, n in PIT_FACES.items():
            # sigma_0 n, sigma_0 = diag(-sigma_h, -sigma_v) in (r, z) (tension positive)
            traction = ufl.as_vector([-sh * n[0], -sv * n[1]])
            pieces = [ds(FACET_TAGS[name])]
            if dom.has_void:
                pieces.append(dS(FACET_TAGS[name]))
            self._parts.append((traction, pieces))
        self._w, self._comm = w, msh.comm

    def load(self, test):
        """f(v) = -share int_pit (sigma_0 n) . v 2 pi r ds (the soil's load row)."""
        out = 0
        for traction, pieces in self._parts:
            for k, measure in enumerate(pieces):
                f = -ufl.inner(traction, test) * self._w
                out += self.share * (f("+") if k == 1 else f) * measure
        return out

    def released(self) -> float:
        """The upward resultant of the whole relief (share 1), N: on the pit's bottom,
        sigma'_v there times its area."""
        if not hasattr(self, "_resultant"):
            total = 0
            for traction, pieces in self._parts:
                for k, measure in enumerate(pieces):
                    f = -traction[1] * self._w
                    total += (f("+") if k == 1 else f) * measure
            self._resultant = fem.form(total)
        return allsum(self._comm, fem.assemble_scalar(self._resultant))
