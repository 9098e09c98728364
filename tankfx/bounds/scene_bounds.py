"""What a scene asks of the bounds: its soil per triangle, its foundation's load, and the
run (``[analysis] collapse = "bounds"``)."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..scene.sections import load_breakdown, vertical_load
from .lower import FarField, Ground, Loading
from .triangles import Triangles


def ground_of(soil, tri: Triangles, box: "Box | None" = None) -> Ground:
    """The soil of each triangle, its law's strength for the bounds read at its centroid (a
    triangle lies in one stratum). Depth is -z. With an open ``box``, the soil beyond it
    too."""
    law = soil.law
    far = None
    if box is not None and box.open_base:
        far = FarField(rows=law.limit_strata(soil, box.depth, box.ground_depth))
    return Ground(**law.limit_strength(soil, -tri.points[tri.cells, 1].mean(axis=1)), far=far)


@dataclass(frozen=True)
class Box:
    """The part of the ground the bounds mesh, m: ``radius`` and ``depth``; a side or base
    is ``open`` where the ground goes on beyond it (the scene's domain is wider or deeper:
    the half-space by default), else the scene's own support. ``ground_depth`` is the
    ground's (the scene's domain depth, inf for the default half-space)."""

    radius: float
    depth: float
    open_side: bool
    open_base: bool
    ground_depth: float

    @classmethod
    def around(cls, scene, radius: float, depth: float) -> "Box":
        """A box of at most the scene's domain, open where it is smaller."""
        dom, a = scene.domain, scene.foundation_radius
        ground = math.inf if dom.depth >= HALF_SPACE * a else dom.depth
        return cls(radius=min(radius, dom.radius), depth=min(depth, dom.depth),
                   open_side=radius < dom.radius, open_base=depth < dom.depth,
                   ground_depth=ground)

    def grown(self, scene, side: bool, base: bool) -> "Box":
        return Box.around(scene, self.radius * (GROWTH if side else 1.0),
                          self.depth * (GROWTH if base else 1.0))

    def record(self) -> dict:
        return {"radius": self.radius, "depth": self.depth,
                "side": "open" if self.open_side else "the domain's",
                "base": "open" if self.open_base else "the domain's"}


#: a domain this many foundation radii deep is a half-space to the bounds (the default's
#: 10000 a): the column beyond an open base is checked to infinite depth
HALF_SPACE = 1000.0
#: the first box, in foundation radii: radius and depth (measured: docs/development)
FIRST_BOX = (3.0, 2.0)
#: a box whose mechanism reaches its open side or base grows by this factor there, at most
#: MAX_GROWTHS times
GROWTH = 1.5
MAX_GROWTHS = 8
#: the far field's least yield margin (in the cohesion under the foundation) below which the
#: box limits the lower bound
FAR_MARGIN = 0.05
#: ... as long as the last growth raised the lower bound (on the coarse mesh) by this share
BOX_GAIN = 0.002
#: the upper bound's mechanism reaches an open side or base where the triangles touching it
#: dissipate more than this share of the whole
REACH = 1e-3


def loading_of(scene, rigid: bool, box: Box | None = None) -> Loading:
    """The foundation's held (the self-weight) and variable (the rest) vertical loads, and
    the box's supports. A tank's (a [wall]) are pressures: the floor's (the liquid, a gas,
    a pressure; its weight held) and the shell's (the roof, less a gas's lift; its weight
    held) spread on the band :func:`ring_band` inside it."""
    full = scene.load
    held = full.held()
    H = vertical_load(held, scene.plate, scene.wall, scene.ringwall)
    V = vertical_load(full, scene.plate, scene.wall, scene.ringwall) - H
    supports = {"side": "open" if box is not None and box.open_side else scene.domain.side,
                "base": "open" if box is not None and box.open_base else scene.domain.base}
    if scene.wall is None or scene.analysis.bounds_floor == "rigid":
        # (a flexible load is a pressure: no shear under it)
        return Loading(variable=V, held=H, rigid=rigid,
                       rough=rigid and scene.interface.condition != "smooth",
                       pit_contact=(scene.embedment > 0.0 and scene.wall is not None and
                                    scene.wall.radius >= scene.plate.radius * (1 - 1e-9)),
                       **supports)
    plate, wall, ld = scene.plate, scene.wall, full
    a_p, a_w = plate.radius, wall.radius
    floor = math.pi * a_p ** 2
    inner, outer = ring_band(scene)
    band = math.pi * (outer ** 2 - inner ** 2)
    weights = load_breakdown(replace(held, self_weight=full.self_weight), plate, None)
    bands = ((0.0, a_p, ld.pressure, weights["self_weight"] / floor),
             (0.0, a_w, ld.liquid_unit_weight * ld.liquid_height + ld.gas_pressure, 0.0),
             (inner, outer, (ld.roof_weight - ld.gas_pressure * math.pi * a_w ** 2) / band,
              (wall.unit_weight * wall.volume if full.self_weight else 0.0) / band))
    return Loading(variable=V, held=H, rigid=False, rough=False, bands=bands, **supports)


def flexible_tank(scene) -> bool:
    return scene.wall is not None and scene.analysis.bounds_floor == "flexible"


def ring_band(scene) -> tuple[float, float]:
    """The radii (m) of the band inside the shell that takes its load:
    ``analysis.bounds_ring_width``, by default the annular plate's width, else
    RING_WIDTH a."""
    a_w, plate = scene.wall.radius, scene.plate
    width = scene.analysis.bounds_ring_width or min(plate.annular_width or RING_WIDTH * a_w,
                                                    0.5 * a_w)
    return a_w - width, a_w


#: the band a tank's shell load is spread on, in shell radii, where the scene gives none
#: (measured: docs/development/2026-11-28-bounds-anywhere.md)
RING_WIDTH = 0.05


def choose_box(scene, scale: float, log=None) -> Box:
    """The box the bounds are computed in: FIRST_BOX foundation radii, grown by GROWTH
    (within the scene's domain) while, on its first coarse mesh, the upper bound's mechanism
    reaches an open side or base (the triangles touching it dissipate more than REACH of
    the whole) or the lower bound's field beyond it is within FAR_MARGIN of yield (the box
    may then limit the lower bound: measured, a 2.5 a x 1.5 a box holds a smooth Tresca
    footing's lower bound at 5.36 against 5.59), the latter while the growth before raised
    the lower bound by more than BOX_GAIN."""
    from .adapt import bounds
    from .triangles import BASE, SIDE

    a = scene.foundation_radius
    box = Box.around(scene, FIRST_BOX[0] * a, FIRST_BOX[1] * a + scene.embedment)
    rigid = scene.plate is not None
    last = None
    for _ in range(MAX_GROWTHS):
        if not (box.open_side or box.open_base):
            break
        tri = box_triangles(scene, box)
        probe = bounds(tri, lambda t: ground_of(scene.soil, t, box),
                       loading_of(scene, rigid, box), scale, max_rounds=1)
        t, D = probe.triangles, probe.upper.dissipation
        share = {where: D[np.unique(t.owner[t.kind == kind])].sum() / max(D.sum(), 1e-300)
                 for where, kind in (("side", SIDE), ("base", BASE))}
        # (a far field at yield limits the lower bound only while growing the box raises it)
        gained = last is None or probe.lower.factor > (1.0 + BOX_GAIN) * last
        last = probe.lower.factor
        margin = {k: math.inf if v is None else v for k, v in probe.lower.far_margin.items()}
        grow = {where: (share[where] > REACH or (gained and margin[where] < FAR_MARGIN))
                for where in ("side", "base")}
        grow["side"] &= box.open_side
        grow["base"] &= box.open_base
        if not (grow["side"] or grow["base"]):
            break
        if log:
            log.info("  bounds: the box %.3g m x %.3g m limits them (mechanism's share at the "
                     "side %.1e, base %.1e; far field's margin %.3g, %.3g): grown",
                     box.radius, box.depth, share["side"], share["base"],
                     margin["side"], margin["base"])
        box = box.grown(scene, grow["side"], grow["base"])
    return box


def box_triangles(scene, box: Box) -> Triangles:
    """The box on a coarse graded grid (edges of 0.1 a at the foundation's edge: the
    refinement puts the triangles where the mechanism is), the layers' tops and a tank's
    shell band within it among its lines; the same in any units."""
    tops = [layer.depth for layer in scene.soil.layers if layer.depth < box.depth]
    radii = ring_band(scene) if flexible_tank(scene) else ()
    return Triangles.box(scene.foundation_radius, box.radius, box.depth, tops, radii,
                         embedment=scene.embedment)


def strength_scale(soil, a: float) -> float:
    """A stress of order one for the programs: the cohesion at the surface, else gamma a."""
    top = soil.law.limit_strength(soil, np.array([0.0]))
    return max(float(top["c_top"][0]), float(top["gamma"][0]) * a, 1.0)


@dataclass(frozen=True)
class BoundsRun:
    """What a limit analysis of a scene found, for results.json's ``bounds``
    (:func:`tankfx.results.collapse.bounds_record`): the bounds on the variable loads'
    factor and their gap, the refined mesh's triangles and rounds, the box (its record) and
    the far field's least margin at its open side and base, the lower bound's checks (its
    equilibrium residual and yield violation), the conic solver, the time (s)."""

    lower: float
    upper: float
    gap: float
    triangles: int
    rounds: int
    time_s: float
    box: dict
    far_margin: dict
    equilibrium_residual: float
    yield_violation: float
    solver: str


def scene_bounds(scene, comm, log) -> tuple[BoundsRun, dict]:
    """The lower and upper bound on the factor of the scene's variable loads (``[analysis]
    collapse = "bounds"``), refined to ``analysis.bounds_gap`` or ``bounds_cells``: (the
    run, the upper bound's mechanism: ``points`` (n, 2), ``cells`` (m, 3), ``velocity``
    (n, 2) at the triangles' vertices, for a settlement rate of 1), on every rank (the
    programs are solved on rank 0)."""
    import time

    import clarabel

    from .adapt import bounds
    from .program import ProgramError

    rigid = scene.plate is not None
    run, fields, error = None, None, None
    if comm.rank == 0:
        t0 = time.perf_counter()
        a = scene.foundation_radius
        scale = strength_scale(scene.soil, a)
        log.info("bounds: the limit analysis' lower and upper bound on the variable loads' "
                 "factor, refined to a gap of %.3g %%", 100 * scene.analysis.bounds_gap)
        try:
            box = choose_box(scene, scale, log)
            b = bounds(box_triangles(scene, box),
                       lambda t: ground_of(scene.soil, t, box), loading_of(scene, rigid, box),
                       scale, gap=scene.analysis.bounds_gap,
                       max_cells=scene.analysis.bounds_cells, log=log)
            run = BoundsRun(
                lower=b.lower.factor, upper=b.upper.factor, gap=b.gap,
                triangles=len(b.triangles.cells), rounds=b.rounds,
                time_s=time.perf_counter() - t0, box=box.record(),
                far_margin=b.lower.far_margin,
                equilibrium_residual=b.lower.equilibrium_residual,
                yield_violation=b.lower.yield_violation,
                solver=f"Clarabel {clarabel.__version__}")
            for note in scene.soil.law.limit_notes(scene.soil)[0]:
                log.warning("bounds: %s", note)
            nv = len(b.triangles.points)
            fields = {"points": b.triangles.points, "cells": b.triangles.cells,
                      "velocity": b.upper.velocity[:nv]}
        except ProgramError as e:
            error = str(e)
    run, fields, error = comm.bcast((run, fields, error), root=0)
    if error is not None:
        raise ProgramError(error)
    return run, fields
