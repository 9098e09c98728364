"""From a validated scene to results: mesh, forms, solve, post-processing.

The result keys (``results.json``) are a public contract; see README "Results".
Sign conventions: settlements ``w`` positive downward; ``u_r`` positive outward; the axis
``z`` is the depth below the ground surface (positive downward); ``sigma_zz`` is positive in
compression (the paper's and geotechnical convention).
"""
from __future__ import annotations

import logging
import math
import platform
import time
from dataclasses import dataclass
from importlib import metadata

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from . import soil as soil_forms
from .mesh import CELL_TAGS, FACET_TAGS, Domain, build_domain
from .post import assemble_scalar, evaluate_at, nodal_values_on_facets
from .scene import Scene
from .solve import DirectSolver, reaction_force

__all__ = ["Solution", "analyse", "CONVENTIONS"]

log = logging.getLogger("tankfx")

CONVENTIONS = {
    "units": "SI: m, Pa, N, N m/m",
    "w": "settlement, positive downward",
    "u_r": "radial displacement, positive outward",
    "profiles.axis.z": "depth below the ground surface, positive downward",
    "sigma_zz": "vertical soil stress, positive in compression",
    "nondim": "Eqs. 21-23 of Zaman & Mahmood: w = p a w_bar / E_s, M = p a^2 M_bar, "
              "E_s = soil modulus at the ground surface, a = plate (or load) radius",
    "reaction": "upward force of the supports on the soil, N",
}


@dataclass
class Solution:
    """A solved scene: the FE fields (for further post-processing) and the results dict."""

    scene: Scene
    domain: Domain
    u: fem.Function
    sigma_zz: fem.Function
    results: dict


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("tankfx", "dolfinx-solver-real", "fenics-basix", "fenics-ffcx", "fenics-ufl",
                "petsc4py", "gmsh", "numpy", "mpi4py"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            pass
    import dolfinx

    out["dolfinx"] = dolfinx.__version__
    return out


class SoilProblem:
    """The linear soil problem of a scene without structure: a flexible uniform load."""

    def __init__(self, scene: Scene, domain: Domain):
        msh = domain.mesh
        self.scene, self.domain = scene, domain
        s = scene.soil
        self.V = fem.functionspace(msh, ("Lagrange", scene.mesh.degree, (2,)))
        self.u = fem.Function(self.V, name="u")
        # Constants rather than floats: the compiled forms are then shared by every scene
        # of the same structure (sweeps, benchmarks) instead of recompiled per value.
        self.E_s = fem.Constant(msh, s.E)
        self.nu = fem.Constant(msh, s.nu)
        self.gradient = fem.Constant(msh, s.E_gradient)
        self.pressure = fem.Constant(msh, scene.load.pressure)
        r = soil_forms.radius(msh)
        self.r = r
        self.E = soil_forms.modulus_with_depth(self.E_s, self.gradient, soil_forms.depth(msh))
        dx = ufl.Measure("dx", domain=msh, subdomain_data=domain.cell_tags)(CELL_TAGS["soil"])
        ds = ufl.Measure("ds", domain=msh, subdomain_data=domain.facet_tags)
        w, v = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        self.a = soil_forms.stiffness_form(w, v, self.E, self.nu, r, dx)
        self.L = -self.pressure * v[1] * 2.0 * math.pi * r * ds(FACET_TAGS["contact"])
        self.bcs = self._supports()

    def _supports(self) -> list[fem.DirichletBC]:
        V, dom = self.V, self.domain
        fdim = dom.mesh.topology.dim - 1
        Vr = V.sub(0)
        axis = fem.locate_dofs_topological(Vr, fdim, dom.facets("axis"))
        far = fem.locate_dofs_topological(V, fdim, dom.facets("far_side", "bottom"))
        zero = np.zeros(2, dtype=np.float64)
        bcs = [fem.dirichletbc(0.0, axis, Vr),                 # symmetry: u_r = 0 on r = 0
               fem.dirichletbc(zero, far, V)]                  # rigid far boundary
        if dom.has_void:
            # the void carries no stiffness; pin its dofs that touch no soil cell
            void = fem.locate_dofs_topological(V, 2, dom.cells("void"))
            soil = fem.locate_dofs_topological(V, 2, dom.cells("soil"))
            bcs.append(fem.dirichletbc(zero, np.setdiff1d(void, soil), V))
        return bcs

    @property
    def applied_load(self) -> float:
        """Resultant of the applied pressure, N (closed form, independent of the mesh)."""
        a = self.scene.foundation_radius
        return self.scene.load.pressure * math.pi * a**2

    def vertical_stress(self) -> fem.Function:
        """sigma_zz (compression positive), L2-projected (r-weighted) onto the continuous
        displacement space: point values of the raw stress on the axis, a boundary of the
        meridian plane, are noisy for nearly incompressible soil; the projection is not."""
        msh = self.domain.mesh
        Q = fem.functionspace(msh, ("Lagrange", self.scene.mesh.degree))
        s, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        dx = ufl.Measure("dx", domain=msh, subdomain_data=self.domain.cell_tags)(
            CELL_TAGS["soil"])
        sigma = -soil_forms.stress(soil_forms.strain(self.u, self.r), self.E, self.nu)[1, 1]
        out = fem.Function(Q, name="sigma_zz")
        bcs = []
        if self.domain.has_void:
            void = fem.locate_dofs_topological(Q, 2, self.domain.cells("void"))
            soil = fem.locate_dofs_topological(Q, 2, self.domain.cells("soil"))
            bcs = [fem.dirichletbc(0.0, np.setdiff1d(void, soil), Q)]
        DirectSolver(s * q * self.r * dx, sigma * q * self.r * dx, bcs, out,
                     name="projection").solve()
        return out


def analyse(scene: Scene, comm: MPI.Comm = MPI.COMM_WORLD) -> Solution:
    """Mesh, solve and post-process a scene; returns the solution and its results dict."""
    t_start = time.perf_counter()
    timings: dict[str, float] = {}
    log.info("scene '%s': meshing on rank 0, distributing over %d rank(s)", scene.title,
             comm.size)
    t = time.perf_counter()
    domain = build_domain(scene, comm)
    timings["mesh"] = time.perf_counter() - t
    ncells = domain.mesh.topology.index_map(2).size_global
    log.info("mesh: %d cells in %.2f s", ncells, timings["mesh"])

    t = time.perf_counter()
    problem = SoilProblem(scene, domain)
    solver = DirectSolver(problem.a, problem.L, problem.bcs, problem.u, name="soil")
    timings["forms"] = time.perf_counter() - t
    ndofs = problem.V.dofmap.index_map.size_global * problem.V.dofmap.index_map_bs
    log.info("soil: %d dofs (P%d); assembling and solving with MUMPS", ndofs,
             scene.mesh.degree)
    t = time.perf_counter()
    solver.solve()
    timings["assemble_solve"] = time.perf_counter() - t
    log.info("solved in %.2f s", timings["assemble_solve"])

    t = time.perf_counter()
    sigma_zz = problem.vertical_stress()
    results = _results(scene, domain, problem, sigma_zz)
    timings["post"] = time.perf_counter() - t
    timings["total"] = time.perf_counter() - t_start
    results["dofs"] = {"soil": ndofs, "total": solver.matrix_size}
    results["timings_s"] = timings
    results["mpi_ranks"] = comm.size
    results["versions"] = _versions()
    return Solution(scene=scene, domain=domain, u=problem.u, sigma_zz=sigma_zz,
                    results=results)


def _results(scene: Scene, domain: Domain, problem: SoilProblem, sigma_zz) -> dict:
    a = scene.foundation_radius
    D = scene.embedment
    p = scene.load.pressure
    E_s = scene.soil.E
    u = problem.u

    centre_edge = evaluate_at(u, np.array([[0.0, -D], [a, -D]]))
    w0, w_edge = -centre_edge[0, 1], -centre_edge[1, 1]

    # ground-surface profile (the loaded area and the free surface out to 5 a), nodal values
    x, vals = nodal_values_on_facets(u, domain.facets("contact", "surface"))
    keep = x[:, 0] <= 5.0 * a + 1e-12
    r_s, w_s, ur_s = x[keep, 0], -vals[keep, 1], vals[keep, 0]
    under = r_s <= a * (1 + 1e-12)
    wd = float(w_s[under].max() - w_s[under].min())

    z_axis = np.linspace(D, D + 10.0 * a, 201)
    sz = evaluate_at(sigma_zz, np.column_stack([np.zeros_like(z_axis), -z_axis]))[:, 0]

    # mean settlement under the foundation: the tank codes' "uniform settlement"
    ds = ufl.Measure("ds", domain=domain.mesh, subdomain_data=domain.facet_tags)
    w_mean = assemble_scalar(-u[1] * 2.0 * math.pi * problem.r * ds(FACET_TAGS["contact"]),
                             domain.mesh.comm) / (math.pi * a**2)

    applied = problem.applied_load
    reaction = reaction_force(problem.a, problem.L, u, 1, domain.facets("far_side", "bottom"))
    scale = p * a / E_s if p > 0 else float("nan")
    return {
        "title": scene.title,
        "converged": True,
        "w0": float(w0),
        "w_edge": float(w_edge),
        "wd": wd,
        "w_mean": float(w_mean),
        "M0": None,
        "nondim": {"w0": float(w0 / scale), "wd": float(wd / scale), "M0": None,
                   "Kp": scene.Kp, "Kt": scene.Kt},
        "profiles": {
            "surface": {"r": r_s.tolist(), "w": w_s.tolist(), "u_r": ur_s.tolist()},
            "axis": {"z": z_axis.tolist(), "sigma_zz": sz.tolist()},
        },
        "equilibrium": {"applied_load": applied, "reaction": reaction,
                        "relative_error": abs(reaction - applied) / abs(applied)},
        "conventions": CONVENTIONS,
        "scene": scene.to_dict(),
    }
