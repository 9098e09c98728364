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

__all__ = ["oedometric_modulus", "consolidation_coefficient", "biot_forms",
           "drainage_form", "previous_volume_load", "StepWeights", "time_steps", "Oedometer"]


def oedometric_modulus(E, nu):
    """Constrained (oedometric) modulus E (1 - nu) / ((1 + nu)(1 - 2 nu)), Pa."""
    return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))


def consolidation_coefficient(E, nu, permeability, water_unit_weight):
    """Terzaghi's c_v = k E_oed / gamma_w, m^2/s."""
    return permeability * oedometric_modulus(E, nu) / water_unit_weight


def biot_forms(u, p, v, q, E, nu, conductance, r, dx):
    """The four blocks (a_uu, a_up, a_pu, a_pp) of a backward-Euler step of Biot's
    equations, 2 pi r weighted. ``conductance`` = dt k / gamma_w (m^3 s / N . s: m^2 / Pa):
    zero for the undrained response."""
    w = 2.0 * math.pi * r
    return (soil_forms.stiffness_form(u, v, E, nu, r, dx),
            -p * ufl.tr(soil_forms.strain(v, r)) * w * dx,
            -q * ufl.tr(soil_forms.strain(u, r)) * w * dx,
            -conductance * ufl.inner(ufl.grad(p), ufl.grad(q)) * w * dx)


#: Nitsche's penalty for a drained boundary, times the square of the pressure's degree over
#: the cell diameter (coercive for Lagrange elements at about 4 k^2; the drained column's
#: pressure and settlement hardly move from 5 to 50: see tests/test_consolidation.py)
NITSCHE_PENALTY = 10.0


def drainage_form(p, q, conductance, r, ds, degree: int):
    """A drained boundary (p = 0) by Nitsche's method: its terms scale with the
    conductance like the flow's, so the undrained step (dt = 0) has none. A Dirichlet
    condition would drain the boundary's elements at t = 0 already (an immediate settlement
    of a confined column of about one element's thickness of drained strain: 0.7 % of the
    final one with 40 elements over the height)."""
    msh = p.ufl_function_space().mesh
    n, h = ufl.FacetNormal(msh), ufl.CellDiameter(msh)
    w = 2.0 * math.pi * r
    penalty = NITSCHE_PENALTY * max(degree, 1) ** 2 / h
    return conductance * (ufl.inner(ufl.grad(p), n) * q + ufl.inner(ufl.grad(q), n) * p
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
    Measured on Terzaghi's column at 10 steps a decade: BDF2 0.13 % of the final settlement
    where backward Euler is 2.4 % off (tests/test_consolidation.py)."""

    def __init__(self, msh):
        self.previous = fem.Constant(msh, 1.0)
        self.before = fem.Constant(msh, 0.0)
        self.dt = 0.0

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
    Euler's error is that of its largest steps relative to the time: uniform in log t."""
    times = np.sort(np.asarray(times, dtype=float))
    grid = [first]
    ratio = 10.0 ** (1.0 / per_decade)
    for t in times:
        while grid[-1] * ratio < t * (1.0 - 1e-9):
            grid.append(grid[-1] * ratio)
        if t > grid[-1] * (1.0 + 1e-9):
            grid.append(t)
    return np.array(grid)


class Oedometer:
    """A saturated column under a load q applied at t = 0 and held (Terzaghi's problem, in
    the axisymmetric forms above): radius ``radius``, height ``height``, laterally confined
    (u_r = 0 on both sides), fixed and impervious at the base, drained at the loaded top
    (and at the base too with ``drained_base``). For verification against
    :func:`tankfx.reference.terzaghi_settlement`, and for calibrating c_v."""

    def __init__(self, height, E, nu, permeability, q, water_unit_weight=9810.0,
                 cells: int = 40, degree: int = 2, drained_base: bool = False,
                 radius: float | None = None, comm=MPI.COMM_WORLD):
        from .solve import DirectSolver

        R = height / cells if radius is None else radius
        msh = self.mesh = dmesh.create_rectangle(
            comm, [np.array([0.0, -height]), np.array([R, 0.0])], [1, cells],
            dmesh.CellType.triangle)
        self.height, self.q = height, q
        V = fem.functionspace(msh, ("Lagrange", degree, (2,)))
        Q = fem.functionspace(msh, ("Lagrange", degree - 1))
        self.u, self.p = fem.Function(V), fem.Function(Q)
        self.u_n, self.u_nn = fem.Function(V), fem.Function(V)
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        p, s = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        r = soil_forms.radius(msh)
        dx = ufl.Measure("dx", domain=msh, metadata={
            "quadrature_degree": soil_forms.quadrature_degree(degree)})
        self.conductance = fem.Constant(msh, 0.0)
        a_uu, a_up, a_pu, a_pp = biot_forms(u, p, v, s, E, nu, self.conductance, r, dx)
        self._k_over_gamma = permeability / water_unit_weight
        top = dmesh.locate_entities_boundary(msh, 1, lambda x: np.isclose(x[1], 0.0))
        base = dmesh.locate_entities_boundary(msh, 1, lambda x: np.isclose(x[1], -height))
        sides = dmesh.locate_entities_boundary(
            msh, 1, lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], R))
        tags = dmesh.meshtags(msh, 1, top, np.ones(len(top), dtype=np.int32))
        ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)
        L_u = -q * v[1] * 2.0 * math.pi * r * ds(1)
        self.weights = StepWeights(msh)
        L_p = previous_volume_load([(self.weights.previous, self.u_n),
                                    (self.weights.before, self.u_nn)], s, r, dx)
        Vr, Vz = V.sub(0), V.sub(1)
        bcs = [fem.dirichletbc(0.0, fem.locate_dofs_topological(Vr, 1, sides), Vr),
               fem.dirichletbc(0.0, fem.locate_dofs_topological(Vz, 1, base), Vz)]
        drained = np.concatenate([top, base]) if drained_base else top
        drained_tags = dmesh.meshtags(msh, 1, np.sort(drained),
                                      np.ones(len(drained), dtype=np.int32))
        a_pp += drainage_form(p, s, self.conductance, r,
                              ufl.Measure("ds", domain=msh, subdomain_data=drained_tags)(1),
                              degree - 1)
        self.solver = DirectSolver([[a_uu, a_up], [a_pu, a_pp]], [L_u, L_p], bcs,
                                   [self.u, self.p], name="oedometer", symmetric=True)
        self._top = np.array([[0.5 * R, 0.0]])
        self._base = np.array([[0.5 * R, -height]])

    def settlement(self) -> float:
        from .post import evaluate_at

        return float(-evaluate_at(self.u, self._top)[0, 1])

    def base_pressure(self) -> float:
        from .post import evaluate_at

        return float(evaluate_at(self.p, self._base)[0, 0])

    def run(self, steps, second_order: bool = True) -> list[dict]:
        """The undrained response at t = 0, then a step to each time in ``steps`` (s,
        increasing; BDF2, or backward Euler throughout without ``second_order``): per time,
        settlement (m) and the excess pore pressure at the base (Pa)."""
        out, t_prev, dt_prev = [], 0.0, 0.0
        for t in [0.0, *steps]:
            dt = t - t_prev
            self.conductance.value = self.weights.set(dt, dt_prev, second_order) * \
                self._k_over_gamma
            self.solver.solve()
            self.u_nn.x.array[:] = self.u_n.x.array
            self.u_n.x.array[:] = self.u.x.array
            dt_prev = dt
            out.append({"t": t, "settlement": self.settlement(),
                        "base_pressure": self.base_pressure()})
            t_prev = t
        return out


#: the drained limit: one step this many times the foundation's consolidation time a^2 / c_v
#: (the excess pore pressure left is of the order of their ratio, relative to the load)
DRAINED_STEP = 1e10
#: the first time step, as a fraction of the first reported time
FIRST_STEP = 1e-2
DAY = 86400.0


class TimeStepping:
    """Consolidation of a model whose soil block has a pore pressure (SoilBlock with a
    scene's [consolidation]): its drained limit, the undrained response at t = 0, then the
    steps through the reported times. The model's fields end at the last reported time."""

    def __init__(self, model, solver, log):
        self.model, self.solver, self.log = model, solver, log
        scene = model.scene
        self.c = scene.consolidation
        self.soil = model.soil
        self.k_over_gamma = self.c.permeability / self.c.water_unit_weight
        s = scene.soil
        self.c_v = consolidation_coefficient(s.E, s.nu, self.c.permeability,
                                             self.c.water_unit_weight)
        a = scene.foundation_radius
        #: a^2 / c_v, s: the foundation's consolidation time (surface soil's c_v)
        self.time_scale = a**2 / self.c_v

    def _state(self, t: float) -> dict:
        found = self.model.foundation_results()
        p = self.soil.pore_pressure
        comm = p.function_space.mesh.comm
        n = p.function_space.dofmap.index_map.size_local
        local = float(np.max(p.x.array[:n])) if n else -np.inf
        return {"t": t, "t_days": t / DAY, **{k: found[k] for k in ("w0", "w_edge", "wd",
                                                                     "w_mean", "M0")},
                "max_pore_pressure": comm.allreduce(local, op=MPI.MAX)}

    def _solve(self, dt_eff: float) -> None:
        self.soil.conductance.value = dt_eff * self.k_over_gamma
        self.model.solve(self.solver, self.log)

    def _advance(self) -> None:
        soil = self.soil
        soil.u_nn.x.array[:] = soil.u_n.x.array
        soil.u_n.x.array[:] = soil.u.x.array

    def run(self) -> dict:
        soil, log, c = self.soil, self.log, self.c
        # the drained limit first (it does not depend on the path), from rest
        soil.step_weights.set(1.0, 0.0, False)
        self._solve(DRAINED_STEP * self.time_scale)
        # (t = infinity: null in results.json, which takes no infinities)
        drained = self._state(0.0) | {"t": None, "t_days": None}
        log.info("consolidation: drained limit w0 = %.4g m (c_v = %.3g m^2/s, a^2 / c_v = "
                 "%.3g days)", drained["w0"], self.c_v, self.time_scale / DAY)
        for f in (soil.u_n, soil.u_nn):
            f.x.array[:] = 0.0
        # t = 0: undrained (no flow in a step of no time)
        self._solve(0.0)
        history = [self._state(0.0)]
        log.info("consolidation: undrained (t = 0) w0 = %.4g m", history[0]["w0"])
        grid = time_steps(c.times, FIRST_STEP * c.times[0], c.steps_per_decade)
        reported = set(np.searchsorted(grid, c.times))
        t_prev, dt_prev = 0.0, 0.0
        for k, t in enumerate(grid):
            self._advance()
            dt = t - t_prev
            self._solve(soil.step_weights.set(dt, dt_prev, True))
            history.append(self._state(float(t)))
            if k in reported:
                log.info("consolidation: t = %.4g days, w0 = %.4g m, largest excess pore "
                         "pressure %.4g Pa (step %d of %d)", t / DAY, history[-1]["w0"],
                         history[-1]["max_pore_pressure"], k + 1, len(grid))
            t_prev, dt_prev = t, dt
        w_u, w_d = history[0]["w0"], drained["w0"]

        def degree(state):
            return (state["w0"] - w_u) / (w_d - w_u) if w_d != w_u else 1.0

        for state in history:
            state["degree"] = degree(state)
            state["Tv"] = state["t"] / self.time_scale
        at_times = [history[0]] + [history[1 + i] for i in sorted(reported)]
        drained["degree"], drained["Tv"] = 1.0, None
        return {"times": list(c.times), "undrained": history[0], "drained": drained,
                "at_times": at_times, "history": history,
                "c_v": self.c_v, "time_scale": self.time_scale,
                "steps": len(grid), "permeability": c.permeability, "drainage": c.drainage,
                "integrator": "undrained at t = 0, then backward Euler once and variable-step "
                              f"BDF2, {c.steps_per_decade} steps a decade from "
                              f"{FIRST_STEP:g} x the first reported time; the drained limit "
                              f"as one step of {DRAINED_STEP:g} a^2 / c_v"}
