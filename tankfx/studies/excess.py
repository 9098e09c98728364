"""The first-order excess: how much of a nonlinear soil's extra settlement the foundation's
edge zone alone explains, measured by solving again with the edge zone's moduli only.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ..fem.evaluate import allsum
from ..fem.solvers import make_solver
from ..iterations.secant import HyperbolicIteration
from ..iterations.stage import LinearSolve
from ..laws import elasticity as soil_forms
from ..mesh import build_domain
from ..model.build import build_model
from ..scene.sections import MIXED_FROM_NU

#: Regions of the first-order excess: the cells whose centroid lies within this fraction of
#: the foundation radius of the foundation's bottom corner (r = a, z = -D) form the "edge".
EDGE_ZONE = 0.1


def first_order_excess(scene, comm: MPI.Comm = MPI.COMM_WORLD) -> dict:
    """The hyperbolic soil's excess central settlement over the linear soil of E_0 = 1/a,
    to first order in b x load, and where in the soil it comes from.

    Returns ``w0`` (linear, m), ``dw0_db`` (m Pa), ``excess`` = b dw0_db / w0 (the relative
    excess at the scene's load to first order) and ``regions``: the shares of the excess
    from the soil near the foundation's bottom edge (within ``EDGE_ZONE`` a of it), the rest
    of the soil below the foundation (r < a), and the soil beside and around it. The scene
    must have a plate and a linear (bonded or smooth) interface: the derivative of a
    Mohr-Coulomb interface's states is not defined at a state change."""
    from dolfinx.fem import petsc as fem_petsc


    if not (scene.soil.law.fixed_constants and scene.soil.law.iteration == "secant"):
        raise ValueError("first_order_excess needs [soil] model = \"hyperbolic\" (Kondner's "
                         "constants fixed; Duncan & Chang's follow the stress)")
    if scene.plate is None or scene.interface.has_states:
        raise ValueError("first_order_excess needs a plate and a bonded or smooth interface")
    if scene.soil.max_nu > MIXED_FROM_NU:
        raise ValueError(f"first_order_excess needs every soil stratum's nu <= {MIXED_FROM_NU} "
                         f"(its density is the displacement form's; the mixed form's is not "
                         f"built)")
    domain = build_domain(scene, comm)
    model = build_model(scene, domain)
    solver = make_solver(scene.solver, model.a, model.L, model.bcs, model.unknowns,
                         entity_maps=model.entity_maps, name="first_order", symmetric=True)
    LinearSolve(solver).run(None, _Quiet())         # the linear solution on E_0 = 1/a
    it = HyperbolicIteration(model)
    u = model.soil.u
    # the adjoint load: a unit upward force on the plate's deflection at its centre (the
    # reported w0)
    W1, to_W = model.W.sub(0).sub(1).collapse()
    x = W1.tabulate_dof_coordinates()
    n_own = W1.dofmap.index_map.size_local
    D = scene.embedment
    at_centre = (np.abs(x[:n_own, 0]) < 1e-12) & (np.abs(x[:n_own, 1] + D) < 1e-9)
    centre = np.asarray(to_W).reshape(-1)[np.flatnonzero(at_centre)]
    if comm.allreduce(len(centre)) != 1:
        raise RuntimeError("no single plate node at the centre")
    loads = [fem.Function(f.function_space) for f in model.unknowns]
    loads[-1].x.array[centre] = -1.0
    ksp = solver.problem.solver
    rhs, adj = solver.problem.b.duplicate(), solver.problem.x.duplicate()
    fem_petsc.assign(loads, rhs)
    ksp.solve(rhs, adj)
    v = [fem.Function(f.function_space) for f in model.unknowns]
    fem_petsc.assign(adj, v)
    for f in v:
        f.x.scatter_forward()
    # E_0^2 eps_p per cell (eps_p at the centroid, as the Picard iteration takes it)
    eps_p = it.law.major_strain(*it.cell_principal_strains(), it.nu)
    weight = fem.Function(it.modulus.function_space)
    a = scene.plate.radius if scene.wall is None else scene.foundation_radius
    corner = np.hypot(it.mid[:, 0] - a, it.mid[:, 1] + D) < EDGE_ZONE * a
    below = (it.mid[:, 0] < a) & (it.mid[:, 1] < -D) & ~corner
    regions = {"edge": corner, "below": below, "around": ~corner & ~below}
    sb = model.soil
    density = ufl.inner(soil_forms.stress(soil_forms.strain(u, sb.r), weight, sb.nu),
                        soil_forms.strain(v[0], sb.r)) * 2.0 * np.pi * sb.r * sb.dx
    compiled = fem.form(density)
    parts = {}
    for name, mask in regions.items():
        weight.x.array[:] = 0.0
        # b relative to the surface soil's (1 without layers): dw0_db is then the
        # derivative under every stratum's b scaled alike
        weight.x.array[it.dof_E] = np.where(mask & it.is_soil, it.E_initial ** 2 * eps_p *
                                            it.b / scene.soil.hyperbolic_b, 0.0)
        parts[name] = allsum(comm, fem.assemble_scalar(compiled))
    w0 = -allsum(comm, float(model.w.x.array[centre].sum()))
    dw0_db = sum(parts.values())
    b = scene.soil.hyperbolic_b
    return {"w0": w0, "dw0_db": dw0_db, "excess": b * dw0_db / w0,
            "regions": {k: val / dw0_db for k, val in parts.items()}}


class _Quiet:
    def info(self, *args, **kwargs):
        pass

    warning = info
