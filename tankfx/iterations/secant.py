"""The secant (Picard) iteration of a nonlinear soil, Eqs. 17-20: solve with the current
secant moduli, read each cell's principal strains, set the modulus of Eq. 19 where the
deviator misfit of Eq. 18 exceeds the tolerance, until no cell changes (Eq. 20) and the
displacement update is small; Anderson acceleration, the unloading memory of a load path, and
the soil's failure said in physical terms (:class:`SoilFailure`).
"""
from __future__ import annotations

import time

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from ..fem.evaluate import allsum, evaluate_at
from ..fem.solvers import SolveError
from ..laws import elasticity as soil_forms
from ..laws.tensors import principal_strains
from ..model.memory import MAX_SWITCHES, unloading_cells
from .status import Failure, IterationStatus, SoilFailure

#: The global criterion: the relative displacement update of the last iteration must be
#: below this times the Eq. 18 tolerance.
DISPLACEMENT_TOLERANCE_RATIO = 0.02


class HyperbolicIteration:
    """Picard iteration on the DG0 secant modulus of a model's soil block, of any law that
    declares the secant steps (``SoilLaw.iteration == "secant"``: Kondner's, Duncan &
    Chang's): its start, its secant step, its next moduli, its unloading line and its words
    (:class:`tankfx.laws.kondner.Kondner`)."""

    name = "soil"
    quiet_inner = False
    #: an active set inside it may update its states once per soil iteration
    one_update_inside = True

    @classmethod
    def build(cls, model, solver, how) -> "HyperbolicIteration":
        return cls(model)

    @staticmethod
    def describe(scene) -> str:
        """The iteration in words, with the scene's settings (``tankfx check``)."""
        soil = scene.soil
        return (f"Picard on the secant modulus (tolerance {soil.tolerance:g}, at most "
                f"{soil.max_iterations})")

    def __init__(self, model):
        self.model = model
        soil = model.soil
        self.modulus = soil.E          # the DG0 secant modulus (a fem.Function)
        V = self.modulus.function_space
        msh = V.mesh
        n_cells = msh.topology.index_map(2).size_local + msh.topology.index_map(2).num_ghosts
        self.n_cells = n_cells
        self.n_owned = msh.topology.index_map(2).size_local
        # everything below is in cell order; V's and T's dofs are mapped through their maps
        self.dof_E = V.dofmap.list[:, 0]
        self.mid = model.domain.cell_midpoints
        #: the soil's law
        self.law = model.soil.setting.soil.law
        if "nu" in self.law.state_fields:
            # a failed cell's Poisson's ratio, in the soil's per-cell field
            self.nu_field = soil.nu
            self.dof_nu = soil.nu.function_space.dofmap.list[:, 0]
        self.is_soil = np.zeros(n_cells, dtype=bool)
        self.is_soil[model.domain.cells("soil")] = True
        # a ringwall's cells (and its fill's) are no soil of this law: they keep their
        # modulus
        self.is_soil[soil.linear_cells] = False
        T = fem.functionspace(msh, ("DG", 0, (4,)))
        self.dof_T = T.dofmap.list[:, 0]
        self.strain = fem.Function(T)
        self.strain_expr = fem.Expression(
            soil_forms.tensor_components(soil_forms.strain(soil.u, soil.r)),
            T.element.interpolation_points)
        if self.law.needs_stress:
            self.stress = fem.Function(T)
            self.stress_expr = fem.Expression(soil_forms.tensor_components(soil.stress()),
                                              T.element.interpolation_points)
        #: the cells' unloading memory along a load path (None: the paper's law)
        self.memory = soil.memory
        self.anderson_depth = self.law.anderson_depth
        self.begin_stage()

    def begin_stage(self) -> None:
        """A new stage: the law's constants per cell as the iteration starts, and no
        history (the moduli themselves start from the last stage's)."""
        s = self.model.soil.setting.soil
        self.start = self.law.secant_start(s, -self.mid[:, 1], self.model.soil.cell_strata)
        self.a, self.b = self.start["a"], self.start["b"]
        # (the law's strain measure reads the intact Poisson's ratio: a failed Duncan-Chang
        # cell's is not its law's)
        self.nu, self.nu_intact = self.start["nu"], self.start["nu_intact"]
        self.E_initial = 1.0 / self.a
        #: the cells' stress of the current iteration, where the law reads it (else None)
        self._stress = None
        #: per cell, how often it has changed between its curve and its line this stage
        self._switches = np.zeros(self.n_cells, dtype=int)
        self.history: list[dict] = []
        self._x_hist, self._f_hist, self._g_hist = [], [], []
        #: the status of the stage's last run (None before it)
        self.last: IterationStatus | None = None

    def run(self, inner, log) -> IterationStatus:
        """Iterate: ``inner()`` solves the model with the current moduli (its status
        ``unsettled``: how many interface elements changed state), then every soil cell takes the secant
        modulus of its strains (Eqs. 17-19, or Duncan & Chang's; a remembering soil's
        unloading line), until no cell's misfit exceeds the tolerance (Eq. 20), the
        displacement update is small and the interface has settled. Returns its status
        (its results.json record ``record``); raises SoilFailure (or SolveError) with the
        history otherwise."""
        m, s = self.model, self.model.soil.setting.soil
        comm = m.domain.mesh.comm
        tol, max_it = s.tolerance, s.max_iterations
        du_tol = DISPLACEMENT_TOLERANCE_RATIO * tol
        u = m.soil.u
        n_u = u.function_space.dofmap.index_map.size_local * u.function_space.dofmap.index_map_bs
        previous = u.x.array[:n_u].copy()
        centre = np.array([[0.0, -m.soil.setting.embedment]])
        w0_hist = []
        own = np.flatnonzero(self.is_soil[: self.n_owned])
        log.info(self.law.start_text(s, tol))
        log.info("  it  changing  max misfit  at ultimate  du/u        time s")
        for it in range(1, max_it + 1):
            t0 = time.perf_counter()
            try:
                # (interface elements that changed state, with one update per iteration)
                unsettled = inner().unsettled
            except SolveError as e:
                # the stiffness left by the soil at its ultimate no longer solves: say so in
                # the soil's terms, with the history so far
                raise self._collapse(s, it, e) from None
            eps_min, eps_max = self.cell_principal_strains()
            E = self.modulus.x.array[self.dof_E]
            # (the cells' stress where the law reads it, for this iteration's steps)
            self._stress = self._cell_stress()
            step = self.law.secant_step(s, self.start, self.nu, E, eps_min, eps_max,
                                        self._stress, self.is_soil)
            self.a, self.b = step["a"], step["b"]
            self.E_initial = 1.0 / self.a
            E_new, misfit, ultimate = step["E"], step["misfit"], step["ultimate"]
            self._ultimate = ultimate
            switched = unloading = None
            if self.memory is not None:
                E_new, misfit, ultimate, unloading, switched = self._unloading(
                    E, E_new, ultimate, eps_min, eps_max, tol)
            changing = (misfit > tol) & self.is_soil
            if switched is not None:
                changing |= switched
            n_changing = comm.allreduce(int(changing[own].sum()))
            n_ult = comm.allreduce(int((ultimate & self.is_soil)[own].sum()))
            worst = comm.allreduce(float(misfit[own].max(initial=0.0)), op=MPI.MAX)
            du = u.x.array[:n_u] - previous
            du_rel = np.sqrt(allsum(comm, float(du @ du)) /
                             max(allsum(comm, float(u.x.array[:n_u] @ u.x.array[:n_u])), 1e-300))
            previous = u.x.array[:n_u].copy()
            w0_hist.append(-evaluate_at(u, centre)[0, 1])
            row = {"iteration": it, "changing": n_changing, "interface_changed": unsettled,
                   **({} if unloading is None else
                      {"unloading": comm.allreduce(int(unloading[own].sum()))}),
                   "max_misfit": worst,
                   "at_ultimate": n_ult, "displacement_update": du_rel, "w0": w0_hist[-1],
                   "time_s": time.perf_counter() - t0}
            self.history.append(row)
            log.info("  %2d %9d %11.3e %12d  %10.3e %8.2f", it, n_changing, worst, n_ult,
                     du_rel, row["time_s"])
            if n_changing == 0 and du_rel <= du_tol and not unsettled:
                self.last = self._converged(it, row, tol, worst, du_rel, du_tol, n_ult, w0_hist,
                                            E, eps_min, eps_max, unloading, own)
                return self.last
            self._update(E, E_new, step, unloading, switched, own)
        self._fail(s, n_ult, ultimate, max_it, worst, du_rel, tol)

    def _cell_stress(self):
        """The cells' current stress ((rr, zz, rz, theta), tension positive, in cell order),
        where the law reads it; else None."""
        if not self.law.needs_stress:
            return None
        self.stress.interpolate(self.stress_expr)
        return self.stress.x.array.reshape(-1, 4)[self.dof_T]

    def _unloading(self, E, E_new, ultimate, eps_min, eps_max, tol) -> tuple:
        """A remembering soil: the cells below their most loaded state follow their
        unloading line (E_ur). Returns (E_new, misfit, ultimate, unloading, switched)."""
        # cells below their most loaded state follow their unloading line: E_ur
        was = self.memory.unloading_mask
        unloading = self.is_soil & unloading_cells(
            self.law.major_strain(eps_min, eps_max, self.nu_intact), self.memory.peak_strain,
            was, tol)
        # (none on a line or going there, as while a path first loads: no E_ur to find,
        # which for Duncan & Chang's soil is a bisection over the cells)
        E_ur = self._unloading_modulus(E) if (unloading | was).any() else E
        # a cell leaves its line only once its modulus there has settled: passing its
        # largest strain under a modulus that is still moving (Duncan & Chang's E_ur
        # follows the confinement, which lags at a stage's start) is no reloading past it
        unloading |= was & self.is_soil & (np.abs(E - E_ur) > tol * E)
        # a cell at the kink of its law (its strain at its largest, neither loading nor
        # unloading) can flip between the soft curve and the stiff line at every
        # iteration: after MAX_SWITCHES it is held on the curve (the paper's law)
        self._switches += unloading != was
        unloading &= self._switches < MAX_SWITCHES
        switched = unloading != was
        E_new = np.where(unloading, E_ur, E_new)
        misfit = np.abs(E - E_new) / E
        return E_new, misfit, ultimate & ~unloading, unloading, switched

    def _converged(self, it, row, tol, worst, du_rel, du_tol, n_ult, w0_hist, E, eps_min,
                   eps_max, unloading, own) -> IterationStatus:
        """The record of a converged iteration, with the converged Kondner constants of
        each cell (``data``: a, b, nu, for the stress level); a remembering soil commits its
        new peaks."""
        comm = self.model.domain.mesh.comm
        extra = {}
        if self.memory is not None:
            # the cells on the loading curve past their largest strain are at their most
            # loaded state so far (a held cell below it keeps its own)
            eps_p = self.law.major_strain(eps_min, eps_max, self.nu_intact)
            self.memory.commit(self.model.soil.u, eps_p, E, self.nu, self.is_soil & ~unloading &
                               (eps_p >= self.memory.peak_strain),
                               self._stress)
            held = self.is_soil & (self._switches >= MAX_SWITCHES)
            extra = {"unloading_cells": row["unloading"],
                     "held_on_loading_curve": comm.allreduce(int(held[own].sum())),
                     "unloading_modulus_ratio": self.memory.ratio}
        return IterationStatus.of({
            "converged": True, "iterations": it, "history": self.history, **extra,
            "criterion": f"no cell's deviator misfit exceeds {tol:g} (Eq. 20; largest "
                         f"{worst:.2e}) and the displacement update is {du_rel:.1e} <= "
                         f"{du_tol:g}",
            "cells_at_ultimate": n_ult, "error_estimate": _error_estimate(w0_hist)},
            data={"a": self.a, "b": self.b, "nu": self.nu_intact})

    def _update(self, E, E_new, step, unloading, switched, own) -> None:
        """Every soil cell takes its secant modulus (the paper updates only the cells
        outside the tolerance; that freezes a misfit of up to the tolerance, worth 2.5 % of
        w0 at the paper's 0.05 in the flexible-load test), floored, Anderson-accelerated."""
        comm = self.model.domain.mesh.comm
        floor = self.law.modulus_floor * self.E_initial
        if switched is not None and comm.allreduce(int(switched[own].sum())):
            # the map itself changed: its history no longer fits it
            del self._x_hist[:], self._f_hist[:], self._g_hist[:]

        def accelerate(x, x_new, low, high):
            return self._anderson(x, x_new, low, own, ceiling=high) if self.anderson_depth \
                else x_new

        new, nu_new = self.law.next_moduli(step, E_new, E, self.nu, self.nu_intact,
                                           self.E_initial, floor, accelerate)
        if unloading is not None:
            # on its unloading line a cell is intact, of modulus E_ur (above the loading
            # curve's ceiling, 1/a)
            new = np.where(unloading, E_new, new)
            if nu_new is not None:
                nu_new = np.where(unloading, self.nu_intact, nu_new)
            self.memory.set_unloading(unloading)
        if nu_new is not None:
            self.nu = np.where(self.is_soil, nu_new, self.nu_intact)
            self.nu_field.x.array[self.dof_nu] = self.nu
        self.modulus.x.array[self.dof_E] = np.where(self.is_soil, new, E)

    def _load_text(self) -> str:
        """The stage's load in words: the vertical load and its mean bearing pressure."""
        m = self.model
        a = m.scene.foundation_radius
        P = m.applied_load
        return (f"the vertical load {P / 1e6:.4g} MN, a mean bearing pressure of "
                f"{P / (np.pi * a**2) / 1e3:.4g} kPa on the foundation (radius {a:g} m)")

    def _soil_failure(self, message: str) -> SoilFailure:
        """A SoilFailure that says what the secant law's failure is: the model's, not the
        ground's."""
        return SoilFailure(
            f"{message}. This is where the secant iteration of {self.law.title} stops, which "
            f"is the model's limit ({self.law.why_it_cannot_fail}); for the ground's bearing "
            f"capacity use soil.model = \"mohr_coulomb\" with [analysis] collapse = \"load\"",
            self.history)

    def _collapse(self, s, it: int, error: SolveError) -> SoilFailure:
        """A linear solve failed inside the iteration (the soil so softened that the system
        is singular to round-off): what failed, where and under what load."""
        comm = self.model.domain.mesh.comm
        mask = getattr(self, "_ultimate", np.zeros(len(self.is_soil), dtype=bool)) & \
            self.is_soil
        n = comm.allreduce(int(mask[: self.n_owned].sum()))
        where = (f"{n} cells of the soil {self._where(mask)} had reached "
                 f"{self.law.strength_text(s)}" if n else "no cell had yet reached the soil's "
                 "strength")
        return self._soil_failure(
            f"the soil cannot carry {self._load_text()}: at iteration {it} {where}, and the "
            f"stiffness left could not be solved ({error})")

    def _fail(self, s, n_ult, ultimate, max_it, worst, du_rel, tol) -> None:
        """No converged state in max_iterations: what failed, in physical terms."""
        own_words = n_ult > 0 and self.law.exhausted_text(
            n_ult, self._where(ultimate & self.is_soil), max_it, worst, du_rel)
        if own_words:
            raise self._soil_failure(own_words)
        if n_ult > 0:
            raise self._soil_failure(
                f"the soil cannot carry {self._load_text()}: {n_ult} cells of the soil "
                f"{self._where(ultimate & self.is_soil)} reached {self.law.strength_text(s)} "
                f"and no converged state was found in {max_it} iterations")
        raise SolveError(f"the hyperbolic soil iteration did not converge in {max_it} "
                         f"iterations (largest deviator misfit {worst:.3g} > {tol:g})",
                         self.history, code=Failure.MAX_ITERATIONS)

    def _unloading_modulus(self, E) -> np.ndarray:
        """Per cell, the modulus of its unloading line, by the law (``E``: the cells'
        current modulus)."""
        return self.law.unloading_modulus(
            self.model.soil.setting.soil, self.start, self.E_initial, E,
            self._stress,
            self.memory.peak_stress, self.memory.ratio, self.is_soil)

    def cell_principal_strains(self) -> tuple[np.ndarray, np.ndarray]:
        """The smallest and largest principal strain of the current displacement at each
        cell's centroid, in cell order."""
        self.strain.interpolate(self.strain_expr)
        e = self.strain.x.array.reshape(-1, 4)[self.dof_T]
        return principal_strains(e[:, 0], e[:, 1], e[:, 2], e[:, 3])

    def _anderson(self, E, G, floor, own, ceiling):
        """Anderson acceleration (type II, depth ``anderson_depth``) of the secant map
        E -> G of a modulus, on log E: x_{k+1} = g_k - dG gamma, gamma the least-squares fit
        of the residual f_k = g_k - x_k by its recent differences. Inner products are summed
        over the owned cells of all ranks, so every rank takes the same step; the result is
        kept between the floor and the ceiling (per cell)."""
        comm = self.model.domain.mesh.comm
        # only soil cells take part; the others (inside the tank, above the ground, where
        # E(h) of a steep gradient is negative) are given 1 so that log stays quiet
        x, g = (np.log(np.where(self.is_soil, v, 1.0)) for v in (E, G))
        f = g - x
        self._x_hist.append(x)
        self._f_hist.append(f)
        self._g_hist.append(g)
        del self._x_hist[:-self.anderson_depth - 1], self._f_hist[:-self.anderson_depth - 1]
        del self._g_hist[:-self.anderson_depth - 1]
        if len(self._f_hist) < 2:
            return G
        dF = np.stack([b - a for a, b in zip(self._f_hist, self._f_hist[1:])], axis=1)
        dG = np.stack([b - a for a, b in zip(self._g_hist, self._g_hist[1:])], axis=1)
        mask = np.zeros(len(f), dtype=bool)
        mask[own] = True
        FtF = comm.allreduce(dF[mask].T @ dF[mask])
        Ftf = comm.allreduce(dF[mask].T @ f[mask])
        try:
            gamma = np.linalg.lstsq(FtF, Ftf, rcond=1e-10)[0]
        except np.linalg.LinAlgError:
            return G
        x_new = g - dG @ gamma
        out = np.exp(np.clip(x_new, np.log(floor), np.log(ceiling)))
        return np.where(self.is_soil & np.isfinite(out), out, G)

    def _where(self, mask) -> str:
        """Where the failing cells are, in words (gathered over the ranks)."""
        comm = self.model.domain.mesh.comm
        pts = np.concatenate(comm.allgather(self.mid[: self.n_owned][mask[: self.n_owned]]))
        a = self.model.scene.foundation_radius
        D = self.model.soil.setting.embedment
        r, z = pts[:, 0].mean(), -pts[:, 1].mean()
        place = "under the foundation's edge" if abs(r - a) < 0.5 * a else \
            ("under the foundation" if r < a else "beside the foundation")
        return f"{place} (around r = {r:.3g} m, depth {z:.3g} m; foundation level {D:g} m)"


def _error_estimate(w0_hist) -> float:
    """Relative error of w0 left by stopping: the geometric tail of the last updates,
    sum_k>n d_k ~ d_n rho / (1 - rho), rho the ratio of the last two updates (at least the
    last update itself)."""
    if len(w0_hist) < 2:
        return 0.0
    d1 = abs(w0_hist[-1] - w0_hist[-2])
    rho = 0.5
    if len(w0_hist) >= 3:
        d0 = abs(w0_hist[-2] - w0_hist[-3])
        if d0 > 0:
            rho = min(d1 / d0, 0.9)
    return max(d1, d1 * rho / (1.0 - rho)) / max(abs(w0_hist[-1]), 1e-300)
