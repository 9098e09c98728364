"""Kondner's law at a material point: a soil cylinder in a homogeneous triaxial-like state,
driven through the same Picard iteration (:class:`tankfx.iterations.secant.HyperbolicIteration`)
as the half-space, must follow (s1 - s3) = e_p / (a + b e_p) at every strain level.

The cylinder (radius 0.5 m, height 1 m, axisymmetric) stands on a frictionless base and is
pressed by a uniform axial stress on its top. Two lateral conditions give two homogeneous
states with closed forms (the secant modulus E = 1 / (a + b e_p), with the paper's major
principal strain e_p = (e_max - e_min) / (1 + nu), which equals deviator / E in any
homogeneous elastic state):
- oedometer (u_r = 0 on the side): deviator q = p (1 - 2 nu) / (1 - nu), axial strain
  e_z = (1 + nu) e_p;
- unconfined (free side): q = p, e_z = e_p, radial strain -nu e_z.
Then e_p = a q / (1 - b q) closes the form; the strain level b q runs to 0.8 of the
ultimate deviator.
"""
import math
from types import SimpleNamespace

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from tankfx.laws import elasticity as soil_forms
from tankfx.iterations.secant import HyperbolicIteration
from tankfx.iterations.stage import LinearSolve
from tankfx.scene.sections import Soil
from tankfx.fem.solvers import DirectSolver

A, B, NU = 2.1e-7, 1e-5, 0.3   # the paper's constants in SI (1/Pa), as in test_hyperbolic
RADIUS, HEIGHT = 0.5, 1.0


def column(p, confined, tolerance):
    """Solve the column under an axial stress p (Pa) on the hyperbolic soil; returns the
    iteration's result, the displacement and the secant modulus."""
    comm = MPI.COMM_WORLD
    msh = dmesh.create_rectangle(comm, [[0.0, -HEIGHT], [RADIUS, 0.0]], [4, 8],
                                 dmesh.CellType.triangle)
    V = fem.functionspace(msh, ("Lagrange", 2, (2,)))
    u = fem.Function(V, name="u")
    Q0 = fem.functionspace(msh, ("DG", 0))
    E = fem.Function(Q0, name="secant_modulus")
    E.x.array[:] = 1.0 / A
    r = soil_forms.radius(msh)
    du, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    a = soil_forms.stiffness_form(du, v, E, fem.Constant(msh, NU), r, ufl.dx)
    top = dmesh.locate_entities_boundary(msh, 1, lambda x: np.isclose(x[1], 0.0))
    tags = dmesh.meshtags(msh, 1, top, np.full(len(top), 1, dtype=np.int32))
    ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)
    L = -p * v[1] * 2.0 * math.pi * r * ds(1)
    fdim = 1
    base = dmesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[1], -HEIGHT))
    axis = dmesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[0], 0.0))
    side = dmesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[0], RADIUS))
    bcs = [fem.dirichletbc(0.0, fem.locate_dofs_topological(V.sub(1), fdim, base), V.sub(1)),
           fem.dirichletbc(0.0, fem.locate_dofs_topological(V.sub(0), fdim, axis), V.sub(0))]
    if confined:
        bcs.append(fem.dirichletbc(0.0, fem.locate_dofs_topological(V.sub(0), fdim, side),
                                   V.sub(0)))
    solver = DirectSolver(a, L, bcs, u)
    n_cells = msh.topology.index_map(2).size_local + msh.topology.index_map(2).num_ghosts
    soil = Soil(E=1.0 / A, nu=NU, model="hyperbolic", hyperbolic_a=A, hyperbolic_b=B,
                tolerance=tolerance, max_iterations=60)
    model = SimpleNamespace(
        soil=SimpleNamespace(u=u, E=E, r=r, linear_cells=np.zeros(n_cells, dtype=bool),
                             setting=SimpleNamespace(soil=soil, embedment=0.0),
                             memory=None,             # (no load path: nothing to remember)
                             cell_strata=None),       # (one stratum: no per-cell constants)
        scene=SimpleNamespace(foundation_radius=RADIUS),
        domain=SimpleNamespace(
            mesh=msh, cells=lambda name: np.arange(n_cells, dtype=np.int32),
            cell_midpoints=dmesh.compute_midpoints(
                msh, 2, np.arange(n_cells, dtype=np.int32))[:, :2]))

    # (no interface here: the linear solve is the only iteration inside)
    linear = LinearSolve(solver)
    result = HyperbolicIteration(model).run(lambda: linear.run(None, _Quiet()), _Quiet())
    return result, u, E


class _Quiet:
    def info(self, *args):
        pass


def closed_form(p, confined):
    """(deviator, e_p, secant modulus, axial strain) of the homogeneous state."""
    q = p * (1 - 2 * NU) / (1 - NU) if confined else p
    e_p = A * q / (1 - B * q)
    return q, e_p, 1.0 / (A + B * e_p), (1 + NU) * e_p if confined else e_p


@pytest.mark.parametrize("confined", [True, False], ids=["oedometer", "unconfined"])
@pytest.mark.parametrize("level", [0.2, 0.5, 0.8])
def test_column_follows_kondners_hyperbola(confined, level):
    tolerance = 1e-4
    # the axial stress that brings the deviator to `level` times the ultimate 1/b
    p = level / B * ((1 - NU) / (1 - 2 * NU) if confined else 1.0)
    result, u, E = column(p, confined, tolerance)
    assert result.converged and result.iterations > 3, "a genuinely nonlinear state"
    assert result.code == "converged" and result.history[-1]["max_misfit"] <= tolerance
    q, e_p, E_closed, e_z = closed_form(p, confined)
    assert q * B == pytest.approx(level)
    # every cell carries the closed-form secant modulus (the state is homogeneous)
    np.testing.assert_allclose(E.x.array, E_closed, rtol=2 * tolerance)
    # the measured axial strain (the top's settlement over the height) ...
    x = u.function_space.tabulate_dof_coordinates()
    on_top = np.isclose(x[:, 1], 0.0)
    settlement = -u.x.array.reshape(-1, 2)[on_top, 1]
    comm = MPI.COMM_WORLD
    e_z_fe = comm.allreduce(float(settlement.max(initial=0.0)), op=MPI.MAX) / HEIGHT
    assert comm.allreduce(float(settlement.min(initial=np.inf)), op=MPI.MIN) / HEIGHT == \
        pytest.approx(e_z_fe, rel=1e-9), "uniform settlement of the top"
    assert e_z_fe == pytest.approx(e_z, rel=2 * tolerance)
    # ... read back through Kondner's law, gives the applied deviator
    eps_p = e_z_fe / (1 + NU) if confined else e_z_fe
    assert eps_p / (A + B * eps_p) == pytest.approx(q, rel=4 * tolerance)
