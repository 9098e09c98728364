"""Consolidation: Biot's coupled flow and deformation of a saturated soil, in time.

A tank filled on clay settles twice: at once, as the water cannot leave the pores (the
undrained response: no change of volume), and then over months, as the excess pore
pressure drains away and the load passes to the soil's skeleton (the drained response).
With incompressible grains and water, Biot's equations for the displacement u and the
excess pore pressure p (compression positive, the hydrostatic part left out) are

    div(sigma'(u) - p I) = 0,      sigma' = drained elasticity (E', nu'),
    d/dt tr eps(u) - div((k / gamma_w) grad p) = 0      (Darcy's flow, k in m/s).

Backward Euler over a step dt gives the same saddle-point blocks as the mixed (u, p) soil
of :mod:`tankfx.soil` (Taylor-Hood, p one degree below u), with the flow in place of the
compressibility block:

    a(u, v) - (p, tr eps(v))                   = loads
    -(q, tr eps(u)) - dt (k / gamma_w)(grad p, grad q) = -(q, tr eps(u_n))

symmetric and indefinite. dt = 0 is the undrained response (tr eps = 0, the nu = 0.5
soil of the same shear modulus); a step much longer than the consolidation time leaves
p -> 0 and the drained response (E', nu'). Every integral carries the 2 pi r weight.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from . import soil as soil_forms

__all__ = ["oedometric_modulus", "consolidation_coefficient", "stratum_coefficients",
           "biot_forms",
           "drainage_form", "previous_volume_load", "StepWeights", "time_steps", "Oedometer",
           "MandelCylinder"]


def oedometric_modulus(E, nu):
    """Constrained (oedometric) modulus E (1 - nu) / ((1 + nu)(1 - 2 nu)), Pa."""
    return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))


def consolidation_coefficient(E, nu, permeability, water_unit_weight):
    """Terzaghi's c_v = k E_oed / gamma_w, m^2/s."""
    return permeability * oedometric_modulus(E, nu) / water_unit_weight


def stratum_coefficients(scene) -> tuple[list[float], list[float]]:
    """Per stratum of a consolidating scene's ground, top down: its permeability k (m/s:
    its own, else [consolidation]'s) and its c_v (m^2/s)."""
    c = scene.consolidation
    k = [c.permeability if st.permeability is None else st.permeability
         for st in scene.soil.strata]
    return k, [consolidation_coefficient(st.E, st.nu, k_i, c.water_unit_weight)
               for st, k_i in zip(scene.soil.strata, k)]


def biot_forms(u, p, v, q, E, nu, conductance, r, dx):
    """The four blocks (a_uu, a_up, a_pu, a_pp) of a backward-Euler step of Biot's
    equations, 2 pi r weighted. ``conductance`` = dt k / gamma_w (m^2/Pa): zero for the
    undrained response."""
    w = 2.0 * math.pi * r
    return (soil_forms.stiffness_form(u, v, E, nu, r, dx),
            -p * ufl.tr(soil_forms.strain(v, r)) * w * dx,
            -q * ufl.tr(soil_forms.strain(u, r)) * w * dx,
            -conductance * ufl.inner(ufl.grad(p), ufl.grad(q)) * w * dx)


#: Nitsche's penalty for a drained boundary, times the square of the pressure's degree over
#: the cell diameter (coercive for Lagrange elements at about 4 k^2; the drained column's
#: settlement moves by 9e-6 of its final value between 5 and 1000, at T_v = 0.01 where the
#: drained boundary's layer is thinnest, 1.5e-8 by T_v = 1: tests/test_consolidation.py)
NITSCHE_PENALTY = 10.0


def drainage_form(p, q, conductance, r, ds, degree: int, side: str | None = None,
                  weight=1.0):
    """A drained boundary (p = 0) by Nitsche's method: its terms scale with the
    conductance like the flow's, so the undrained step (dt = 0) has none. A Dirichlet
    condition would drain the boundary's elements at t = 0 already (an immediate settlement
    of a confined column of about one element's thickness of drained strain: 0.7 % of the
    final one with 40 elements over the height). On interior facets (``ds`` a dS), the
    terms of one ``side`` ("+" or "-": p, q, the conductance restricted to it by the
    caller), times ``weight`` (an indicator of the side that drains)."""
    msh = ufl.domain.extract_unique_domain(r)
    n, h = ufl.FacetNormal(msh), ufl.CellDiameter(msh)
    if side is not None:
        n, h, r = n(side), h(side), r(side)
    w = 2.0 * math.pi * r
    penalty = NITSCHE_PENALTY * max(degree, 1) ** 2 / h
    grad = ufl.grad
    return weight * conductance * (ufl.inner(grad(p), n) * q + ufl.inner(grad(q), n) * p
                                   - penalty * p * q) * w * ds


def previous_volume_load(history, q, r, dx):
    """The step's load on the flow equation, -(q, sum_j c_j tr eps(u_j)), 2 pi r weighted:
    ``history`` = [(c_j, u_j)] the earlier states with their weights (see
    :class:`StepWeights`)."""
    return -q * sum(c * ufl.tr(soil_forms.strain(u_j, r)) for c, u_j in history) * \
        2.0 * math.pi * r * dx


class StepWeights:
    """The time integrator's weights as Constants of the forms: a step to t_{n+1} solves
    tr eps(u_{n+1}) - sum_j c_j tr eps(u_j) = dt_eff div((k / gamma_w) grad p_{n+1}).

    Backward Euler (c = (1, 0), dt_eff = dt) from the undrained state, then the
    variable-step BDF2 (second order; zero-stable for step ratios below 1 + sqrt 2): with
    w = dt_n / dt_{n-1}, c = ((1 + w)^2, -w^2) / (1 + 2 w), dt_eff = dt (1 + w) / (1 + 2 w).
    Measured on Terzaghi's column at 10 steps a decade: BDF2 0.56 % of the final settlement
    where backward Euler is 2.2 % off (benchmarks/consolidation.py)."""

    def __init__(self, msh):
        self.previous = fem.Constant(msh, 1.0)
        self.before = fem.Constant(msh, 0.0)

    def set(self, dt: float, dt_before: float, second_order: bool) -> float:
        """Weights of a step dt after one of dt_before; returns dt_eff."""
        if not second_order or dt_before <= 0.0:
            self.previous.value, self.before.value = 1.0, 0.0
            return dt
        w = dt / dt_before
        self.previous.value = (1.0 + w) ** 2 / (1.0 + 2.0 * w)
        self.before.value = -w**2 / (1.0 + 2.0 * w)
        return dt * (1.0 + w) / (1.0 + 2.0 * w)


def time_steps(times, first: float, per_decade: int) -> np.ndarray:
    """The ends of the time steps: ``per_decade`` steps per decade of time, geometric from
    ``first`` (s), through every time in ``times`` (s), ending at the last. Backward
    Euler's error is that of its largest steps relative to the time: uniform in log t. A
    step into a time that would be less than half the step before it is merged with that
    one into two equal steps (BDF2 is zero-stable only for step ratios below 1 + sqrt 2)."""
    times = np.sort(np.asarray(times, dtype=float))
    grid = [first]
    ratio = 10.0 ** (1.0 / per_decade)
    for t in times:
        while grid[-1] * ratio < t * (1.0 - 1e-9):
            grid.append(grid[-1] * ratio)
        if t > grid[-1] * (1.0 + 1e-9):
            if len(grid) > 1 and t - grid[-1] < 0.5 * (grid[-1] - grid[-2]):
                grid.pop()
                grid.append(0.5 * (grid[-1] + t))
            grid.append(t)
    return np.array(grid)


def load_path(scene) -> list[tuple[float, object]]:
    """The load as (time, Load) breakpoints, linear between them: [load] at t = 0 (at once)
    without stages; with them, from no load at t = 0 (the structure's weight only, and
    the liquid's unit weight: a tank fills) to each stage's load at its time (a time equal
    to the one before: at once)."""
    from dataclasses import replace

    if not scene.stages:
        return [(0.0, scene.load)]
    first = scene.stages[0]
    start = replace(first, pressure=0.0, liquid_height=0.0, roof_weight=0.0,
                    gas_pressure=0.0)
    return [(0.0, start), *zip(scene.stage_times, scene.stages)]


def load_at(path, t: float):
    """The Load at time t > 0 (s) on a path of :func:`load_path`: its limit from before t
    (where the path jumps at t, the load before the jump: the jump is a step of its own)."""
    from dataclasses import fields, replace

    for (t0, a), (t1, b) in zip(path, path[1:]):
        if t0 < t <= t1:
            f = (t - t0) / (t1 - t0)
            return replace(a, **{fd.name: (1.0 - f) * getattr(a, fd.name) + f * getattr(
                b, fd.name) for fd in fields(a) if isinstance(getattr(a, fd.name), float)
                and fd.name != "load_radius"})
    return path[-1][1]


def path_steps(path, times, per_decade: int) -> list[tuple[float, str, object]]:
    """The steps of a consolidation along a load path: (t, kind, load), kind "jump" (the
    load changes at once to ``load``: an undrained step of no time), "restart" (the first
    step after a breakpoint of the path: backward Euler, the load's rate having changed) or
    "step" (BDF2; these two with ``load`` None: the path's at t). Within each stretch
    between breakpoints (and after the last, to the last reported time, which the scene
    keeps at or after the last stage's) the steps grow geometrically from it,
    ``per_decade`` a decade, the first FIRST_STEP times the shortest of the stretch, the
    stretch before and the time to the next reported time, through every reported time."""
    t_end = max(max(times), path[-1][0])
    breaks = sorted({t for t, _ in path} | {t_end})
    out = [(0.0, "jump", ld) for t, ld in path if t == 0.0]
    for i, (b, e) in enumerate(zip(breaks, breaks[1:])):
        scales = [e - b] + [t - b for t in times if t > b] + \
            ([b - breaks[i - 1]] if i > 0 else [])
        targets = [t - b for t in times if b < t <= e] + [e - b]
        steps = time_steps(targets, FIRST_STEP * min(scales), per_decade)
        out += [(b + dt, "restart" if k == 0 else "step", None)
                for k, dt in enumerate(steps)]
        # the stages reached at once at this stretch's end, in the path's order
        out += [(e, "jump", ld) for (t0, _), (t, ld) in zip(path, path[1:]) if t == t0 == e]
    return out


class _Sample:
    """A saturated sample on a rectangle of the meridian plane (r from 0 to ``radius``, z
    from ``bottom`` to ``top``), in Biot's forms above: its supports and loads given by the
    subclass (``_supports``, ``_load``, ``drained``: the drained edges), stepped in time by
    :meth:`run`, which records :meth:`record` per time."""

    def __init__(self, radius, bottom, top, cells, E, nu, permeability, water_unit_weight,
                 degree, comm):
        from .solve import DirectSolver

        self.radius, self.bottom, self.top = radius, bottom, top
        msh = self.mesh = dmesh.create_rectangle(
            comm, [np.array([0.0, bottom]), np.array([radius, top])], list(cells),
            dmesh.CellType.triangle)
        V = fem.functionspace(msh, ("Lagrange", degree, (2,)))
        Q = fem.functionspace(msh, ("Lagrange", degree - 1))
        self.u, self.p = fem.Function(V), fem.Function(Q)
        self.u_n, self.u_nn = fem.Function(V), fem.Function(V)
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        p, s = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        self.r = r = soil_forms.radius(msh)
        self.dx = dx = ufl.Measure("dx", domain=msh, metadata={
            "quadrature_degree": soil_forms.quadrature_degree(degree)})
        self.E, self.nu = E, nu
        self.conductance = fem.Constant(msh, 0.0)
        self.load_factor = fem.Constant(msh, 1.0)
        a_uu, a_up, a_pu, a_pp = biot_forms(u, p, v, s, E, nu, self.conductance, r, dx)
        self._k_over_gamma = permeability / water_unit_weight
        self.weights = StepWeights(msh)
        L_p = previous_volume_load([(self.weights.previous, self.u_n),
                                    (self.weights.before, self.u_nn)], s, r, dx)
        drained = np.sort(np.concatenate([self.edge(name) for name in self.drained]))
        tags = dmesh.meshtags(msh, 1, drained, np.ones(len(drained), dtype=np.int32))
        a_pp += drainage_form(p, s, self.conductance, r,
                              ufl.Measure("ds", domain=msh, subdomain_data=tags)(1), degree - 1)
        self.solver = DirectSolver([[a_uu, a_up], [a_pu, a_pp]], [self._load(v), L_p],
                                   self._supports(V), [self.u, self.p], name="sample",
                                   symmetric=True)

    def edge(self, name: str) -> np.ndarray:
        """The boundary facets of an edge: "axis", "side" (r = radius), "top", "bottom"."""
        where = {"axis": (0, 0.0), "side": (0, self.radius), "top": (1, self.top),
                 "bottom": (1, self.bottom)}[name]
        return dmesh.locate_entities_boundary(self.mesh, 1,
                                              lambda x: np.isclose(x[where[0]], where[1]))

    def fix(self, V, component: int, edges, value: float = 0.0):
        """A Dirichlet condition on one displacement component along the named edges."""
        Vc = V.sub(component)
        facets = np.concatenate([self.edge(e) for e in edges])
        return fem.dirichletbc(value, fem.locate_dofs_topological(Vc, 1, facets), Vc)

    def run(self, steps, second_order: bool = True, load_factor=None) -> list[dict]:
        """The undrained response at t = 0, then a step to each time in ``steps`` (s,
        increasing; BDF2, or backward Euler throughout without ``second_order``): per time,
        ``t`` and what :meth:`record` gives. ``load_factor(t)`` (default 1) scales the
        load in time (a ramp: 0 at t = 0)."""
        out, t_prev, dt_prev = [], 0.0, 0.0
        for t in [0.0, *steps]:
            if load_factor is not None:
                self.load_factor.value = load_factor(t)
            dt = t - t_prev
            self.conductance.value = self.weights.set(dt, dt_prev, second_order) * \
                self._k_over_gamma
            self.solver.solve()
            self.u_nn.x.array[:] = self.u_n.x.array
            self.u_n.x.array[:] = self.u.x.array
            out.append({"t": t, **self.record()})
            t_prev, dt_prev = t, dt
        return out


class Oedometer(_Sample):
    """A saturated column under a load q applied at t = 0 and held (Terzaghi's problem, in
    the axisymmetric forms above): ``height``, laterally confined (u_r = 0 on both sides),
    fixed and impervious at the base, drained at the loaded top (and at the base too with
    ``drained_base``). For verification against
    :func:`tankfx.reference.terzaghi_settlement`, and for calibrating c_v."""

    def __init__(self, height, E, nu, permeability, q, water_unit_weight=9810.0,
                 cells: int = 40, degree: int = 2, drained_base: bool = False,
                 comm=MPI.COMM_WORLD):
        self.q = q
        self.drained = ("top", "bottom") if drained_base else ("top",)
        R = height / cells
        super().__init__(R, -height, 0.0, (1, cells), E, nu, permeability, water_unit_weight,
                         degree, comm)
        self._top = np.array([[0.5 * R, 0.0]])
        self._base = np.array([[0.5 * R, -height]])

    def _load(self, v):
        tags = dmesh.meshtags(self.mesh, 1, self.edge("top"),
                              np.ones(len(self.edge("top")), dtype=np.int32))
        ds = ufl.Measure("ds", domain=self.mesh, subdomain_data=tags)
        return -self.q * self.load_factor * v[1] * 2.0 * math.pi * self.r * ds(1)

    def _supports(self, V):
        return [self.fix(V, 0, ("axis", "side")), self.fix(V, 1, ("bottom",))]

    def record(self) -> dict:
        """The settlement (m) and the excess pore pressure at the base (Pa)."""
        from .post import evaluate_at

        return {"settlement": float(-evaluate_at(self.u, self._top)[0, 1]),
                "base_pressure": float(evaluate_at(self.p, self._base)[0, 0])}


class MandelCylinder(_Sample):
    """A saturated cylinder of ``radius`` (and as high) between rigid, smooth, impervious
    plates that shorten it by ``strain`` at t = 0 and hold it, drained and free on its side
    (:func:`tankfx.reference.mandel_cylinder`): a check of the consolidation's coupling
    in the hoop direction and through a drained side, where its excess pore pressure at the
    centre first rises above its start (Mandel and Cryer's effect)."""

    drained = ("side",)

    def __init__(self, radius, E, nu, permeability, strain, water_unit_weight=9810.0,
                 cells: int = 16, degree: int = 2, comm=MPI.COMM_WORLD):
        self.strain = strain
        super().__init__(radius, 0.0, radius, (cells, cells), E, nu, permeability,
                         water_unit_weight, degree, comm)
        w = 2.0 * math.pi * self.r
        sigma = soil_forms.stress(soil_forms.strain(self.u, self.r), E, nu) - \
            self.p * ufl.Identity(3)
        self._force = fem.form(-sigma[1, 1] * w / radius * self.dx)     # (uniform in z)
        self._mean = fem.form(self.p * w / (math.pi * radius**3) * self.dx)

    def _load(self, v):
        return ufl.inner(fem.Constant(self.mesh, (0.0, 0.0)), v) * self.dx

    def _supports(self, V):
        return [self.fix(V, 0, ("axis",)), self.fix(V, 1, ("bottom",)),
                self.fix(V, 1, ("top",), self.strain * self.radius)]

    def record(self) -> dict:
        """The axial force (N, compression positive), the mean and the centre's excess pore
        pressure (Pa)."""
        from .post import evaluate_at

        comm = self.mesh.comm
        return {"force": comm.allreduce(fem.assemble_scalar(self._force)),
                "mean_pressure": comm.allreduce(fem.assemble_scalar(self._mean)),
                "centre_pressure": float(evaluate_at(
                    self.p, np.array([[0.0, 0.5 * self.radius]]))[0, 0])}


#: the drained limit: one step this many times the foundation's consolidation time a^2 / c_v
#: (the excess pore pressure left is of the order of their ratio, relative to the load)
DRAINED_STEP = 1e10
#: the first time step, as a fraction of the first reported time
FIRST_STEP = 1e-2
DAY = 86400.0


class _AtDebug:
    """A logger's info at debug level, its warnings as they are."""

    def __init__(self, log):
        self.info, self.warning = log.debug, log.warning


class TimeStepping:
    """Consolidation of a model whose soil block has a pore pressure (SoilBlock with a
    scene's [consolidation]): its drained limit, the undrained response at t = 0, then the
    steps through the reported times. The model's fields end at the last reported time."""

    def __init__(self, model, solver, log):
        self.model, self.solver, self.log = model, solver, log
        # (a step of the path with no load left: see the solver's relative_to_largest_load)
        solver.relative_to_largest_load = True
        scene = model.scene
        self.c = scene.consolidation
        self.soil = model.soil
        _, c_v = stratum_coefficients(scene)
        #: the surface soil's c_v, m^2/s
        self.c_v = c_v[0]
        a = scene.foundation_radius
        #: a^2 / c_v, s: the foundation's consolidation time (surface soil's c_v)
        self.time_scale = a**2 / self.c_v
        #: the slowest stratum's: the drained limit's step is a multiple of it
        self.slowest_time_scale = a**2 / min(c_v)
        #: where the pore pressure is followed: on the axis, half a radius below the
        #: foundation (halfway to the base where that is nearer). The largest excess pore
        #: pressure is also reported, but at t = 0 it sits at the foundation's edge, where
        #: the undrained stress is singular (it grows as the mesh is refined there)
        D = scene.embedment
        self.axis_depth = D + min(0.5 * a, 0.5 * (scene.domain.depth - D))
        self._axis_point = np.array([[0.0, -self.axis_depth]])
        #: the depths (m below the ground) of the isochrones: the pore pressure down the
        #: axis at each reported time, to 3 radii below the foundation (or the base)
        self.isochrone_depths = np.linspace(D, min(D + 3.0 * a, scene.domain.depth), 61)

    def _isochrone(self) -> list[float]:
        from .post import evaluate_at

        z = self.isochrone_depths
        return evaluate_at(self.soil.pore_pressure, np.column_stack([np.zeros_like(z), -z]),
                           cells=self.model.domain.cells("soil"))[:, 0].tolist()

    def _state(self, t: float) -> dict:
        found = self.model.foundation_results()
        p = self.soil.pore_pressure
        comm = p.function_space.mesh.comm
        n = p.function_space.dofmap.index_map.size_local
        local = float(np.max(p.x.array[:n])) if n else -np.inf
        from .post import evaluate_at

        axis = float(evaluate_at(p, self._axis_point,
                                 cells=self.model.domain.cells("soil"))[0, 0])
        return {"t": t, "t_days": t / DAY, **{k: found[k] for k in ("w0", "w_edge", "wd",
                                                                     "w_mean", "M0")},
                "max_pore_pressure": comm.allreduce(local, op=MPI.MAX),
                "axis_pore_pressure": axis}

    def _solve(self, dt_eff: float, t: float | None = None) -> None:
        """One step (a Mohr-Coulomb interface converged in it, its table logged at debug
        level: a table a step would drown the log); a step that does not converge says
        when, with the interface's history."""
        from .solve import SolveError

        self.soil.conductance.value = dt_eff / self.c.water_unit_weight
        try:
            self.model.solve(self.solver, _AtDebug(self.log))
        except SolveError as e:
            when = "the drained limit" if t is None else f"t = {t / DAY:.6g} days"
            raise SolveError(f"consolidation, at {when} (load {self.model.applied_load:.6g} "
                             f"N): {e}", e.history) from None

    def _advance(self) -> None:
        soil = self.soil
        soil.u_nn.x.array[:] = soil.u_n.x.array
        soil.u_n.x.array[:] = soil.u.x.array

    def _set_loads(self, load) -> None:
        model = self.model
        model.set_loads(load)
        # the equilibrium errors are relative to the path's largest load (its last may be
        # none: a tank emptied)
        model.path_load_scale = model.load_scale      # (the largest so far: see load_scale)

    def run(self) -> dict:
        soil, log, c, model = self.soil, self.log, self.c, self.model
        scene = model.scene
        path = load_path(scene)
        # the drained limit first, under the path's last load, from rest (it does not
        # depend on the path: a linear skeleton)
        self._set_loads(path[-1][1])
        soil.step_weights.set(1.0, 0.0, False)
        self._solve(DRAINED_STEP * self.slowest_time_scale)
        # (t = infinity: null in results.json, which takes no infinities)
        drained = self._state(0.0) | {"t": None, "t_days": None}
        log.info("consolidation: drained limit w0 = %.4g m (c_v = %.3g m^2/s, a^2 / c_v = "
                 "%.3g days)", drained["w0"], self.c_v, self.time_scale / DAY)
        for f in (soil.u, soil.u_n, soil.u_nn):
            f.x.array[:] = 0.0
        steps = path_steps(path, c.times, c.steps_per_decade)
        reported = {float(t) for t in c.times}
        history, at_times, isochrones, t_prev, dt_prev = [], [], [], 0.0, 0.0
        for k, (t, kind, load) in enumerate(steps):
            self._advance()
            if kind == "jump":
                # the load changes at once: undrained (no flow in a step of no time)
                self._set_loads(load)
                soil.step_weights.set(1.0, 0.0, False)
                self._solve(0.0, t)
                dt = 0.0
            else:
                self._set_loads(load_at(path, t))
                dt = t - t_prev
                self._solve(soil.step_weights.set(dt, 0.0 if kind == "restart" else dt_prev,
                                                  True), t)
            state = self._state(float(t))
            state["applied_load"] = model.applied_load
            history.append(state)
            last_at_t = k + 1 == len(steps) or steps[k + 1][0] != t
            if last_at_t and (t in reported or t == 0.0):
                at_times.append(state)
                isochrones.append(self._isochrone())
                log.info("consolidation: t = %.4g days, w0 = %.4g m, excess pore pressure "
                         "on the axis %.4g Pa (step %d of %d)", t / DAY, state["w0"],
                         state["axis_pore_pressure"], k + 1, len(steps))
            t_prev, dt_prev = t, dt
        start = at_times[0]             # t = 0, after the loads applied at once
        w_u, w_d = start["w0"], drained["w0"]

        def degree(state):
            return (state["w0"] - w_u) / (w_d - w_u) if w_d != w_u else 1.0

        for state in history:
            state["degree"] = degree(state)
            state["Tv"] = state["t"] / self.time_scale
        drained["degree"], drained["Tv"] = 1.0, None
        drained["applied_load"] = None
        out = {"times": list(c.times), "degree": at_times[-1]["degree"],
               "undrained": start, "drained": drained,
               "at_times": at_times, "history": history,
               "c_v": self.c_v, "time_scale": self.time_scale, "axis_depth": self.axis_depth,
               "isochrones": {"z": self.isochrone_depths.tolist(),
                              "t_days": [s["t_days"] for s in at_times],
                              "pore_pressure": isochrones},
               "steps": len(steps) - 1, "permeability": c.permeability,
               "drainage": c.drainage,
               "integrator": "undrained at t = 0 (and at each load applied at once), then "
                             "backward Euler once and variable-step BDF2, "
                             f"{c.steps_per_decade} steps a decade from {FIRST_STEP:g} x "
                             "the first reported time (restarted at each breakpoint of a "
                             "load path); the drained limit as one step of "
                             f"{DRAINED_STEP:g} a^2 / c_v"}
        if scene.stages:
            # each stage's state when its load is reached (after any jump there)
            out["at_stages"] = [[h for h in history if h["t"] == t][-1]
                                for t in scene.stage_times]
        return out
