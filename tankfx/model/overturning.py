"""Overturning: the tank's first harmonic under a horizontal force and a moment.

A wind or earthquake load on a tank reaches its foundation as a base shear V and an
overturning moment M (API 650 Annex E's "ringwall moment" and base shear). Both vary as
cos(theta) around the tank, so they excite the first Fourier harmonic alone
(:mod:`tankfx.laws.harmonic`); solved on the same mesh, about the converged axisymmetric state
(the secant moduli of a nonlinear soil, the interface states of a Mohr-Coulomb interface),
it superposes on the axisymmetric result: the response at an angle theta is
``axisymmetric + cos(theta) x amplitude`` (sin for the circumferential components).

Loads (``[load] overturning_moment, base_shear``): with a wall, V is a line load on the
wall's top edge along the circle, the shear flow -V sin(theta) / (pi a_t) of a thin tube
(its resultant V towards theta = 0), and the rest of M, M - V H, a couple on that
edge (a vertical line load -(M - V H) cos(theta) / (pi a_t r_m) on the mid-surface, r_m
from the axis): at the wall's foot the shell
then carries exactly V and M, and so does the foundation; above the foot the moment is
linear in height (the real load's distribution over the height is not modelled). Without
a wall, M is a pressure 4 M r cos(theta) / (pi a^4) on the plate and V a uniform
horizontal traction on its mid-surface (the pressure then carries M less the traction's
moment about the underside). M is taken about the plate's underside at the axis.

The interface: bonded and smooth as they are; a Mohr-Coulomb interface about its
converged states (stick: bonded; slip: friction mu times the added normal stress, no
circumferential shear; separated: free). Superposition holds while the contact stays in
those states: where a contact zone's net force on the heel side vanishes it lifts, and the
results say at what multiple of the load (:func:`heel_uplift`).

Beyond the paper (axisymmetric loads only there).
"""
from __future__ import annotations

import math
import time

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh

from ..fem.evaluate import allsum, evaluate_at
from ..fem.solvers import DirectSolver
from ..laws import harmonic as hm
from ..laws import shell as st
from ..laws.elasticity import by_stratum, mixed_stress
from ..laws.elasticity import stress as elastic
from .soil import far_supports


class RockingModel:
    """The first harmonic of a :class:`tankfx.model.tank.TankModel`, on its mesh, materials and
    interface states (build it after the axisymmetric solve). ``solve(moment, shear)``
    solves for the amplitudes; ``results()`` gives the profiles and the summary."""

    def __init__(self, tank):
        self.tank = tank
        s, dom, soil = tank.scene, tank.domain, tank.soil
        self.scene, msh = s, dom.mesh
        self.V = fem.functionspace(msh, ("Lagrange", s.mesh.degree, (3,)))
        self.u = fem.Function(self.V, name="u1")
        U, W = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        r = soil.r
        # soil: the axisymmetric soil's materials (a nonlinear soil's converged secant
        # moduli), per stratum the displacement or the mixed form; a consolidating soil
        # rocks undrained (wind and earthquake load it in seconds): its shear modulus, nu =
        # 0.5, every stratum in the mixed form
        self.undrained = soil.consolidating
        if self.undrained:
            # E_u = 3 G and nu = 0.5 in the ground; a ringwall and its fill keep theirs
            mixed = list(soil.ground)
            self._ground = None
            if soil.n_materials > len(mixed):
                chi = self._ground = soil.in_ground
                self.E = soil.E * (1.0 + chi * (1.5 / (1.0 + soil.nu) - 1.0))
                self.nu = soil.nu + chi * (0.5 - soil.nu)
            else:
                self.E = soil.E * 1.5 / (1.0 + soil.nu)
                self.nu = fem.Constant(msh, 0.5)
        else:
            self.E, self.nu, mixed = soil.E, soil.nu, soil.mixed_strata
        self.pressures = []
        displacement = [i for i in range(soil.n_materials) if i not in mixed]
        a_ss = 0
        if displacement:
            a_ss = hm.soil_stiffness(U, W, self.E, self.nu, r, soil.dx_strata(displacement))
        for i in mixed:
            Q = fem.functionspace(msh, ("Lagrange", s.mesh.degree - 1))
            p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
            a_uu, a_up, a_pu, a_pp = hm.mixed_soil_forms(U, p, W, q, self.E, self.nu, r,
                                                         soil.dx_strata([i]))
            a_ss += a_uu
            others = soil.dx_outside(i)
            if others is not None:
                a_pp += fem.Constant(msh, 0.0) * p * q * others
            self.pressures.append((fem.Function(Q, name=f"p1_{i}"), (a_up, a_pu, a_pp),
                                   fem.Constant(msh, 0.0) * q * soil.dx_strata([i]), i))
        if dom.has_void:
            a_ss += fem.Constant(msh, 0.0) * ufl.inner(U, W) * soil.dx_void

        # structure on the tank's submesh, with its cell-wise properties
        sub = tank.mesh
        self.W = hm.structure_space(sub)
        self.w = fem.Function(self.W, name="structure1")
        q_, b_, Q_, s_ = ufl.TrialFunctions(self.W)
        qv, bv, P_, sv = ufl.TestFunctions(self.W)
        u_b, V_b = hm.shell_amplitudes(q_, s_)
        v_b, Vv_b = hm.shell_amplitudes(qv, sv)
        r_b, t_b, dx_b = tank.r_b, tank.t_b, tank.dx_b
        a_bb = (hm.shell_stiffness((q_, b_, s_), (qv, bv, sv), r_b, t_b, tank.E, tank.nu,
                                   tank.thickness, dx_b, tank.offset)
                + hm.kirchhoff_constraint(Q_, bv, v_b, t_b, r_b, dx_b)
                + hm.kirchhoff_constraint(P_, b_, u_b, t_b, r_b, dx_b))

        # the interface, about the tank's converged states (k_n, k_s, mu per carrier)
        kn, ks, mu = tank.interface.k_n, tank.interface.k_s, tank.interface.mu
        a_bb += hm.interface_form(-u_b, -V_b, -v_b, -Vv_b, st.normal(t_b), t_b, kn, ks, mu,
                                  r_b, tank.interface.dx)
        i_ss = i_sb = i_bs = 0
        for _, n, t, pieces in tank.interface.measures():
            for measure, R in pieces:
                us, Vs = hm.soil_trace(R(U))
                ws, Ws = hm.soil_trace(R(W))
                ub, Vb = hm.shell_amplitudes(R(q_), R(s_))
                wb, Wb = hm.shell_amplitudes(R(qv), R(sv))
                k = (R(kn), R(ks), R(mu))
                i_ss += hm.interface_form(us, Vs, ws, Ws, n, t, *k, r, measure)
                i_sb += hm.interface_form(-ub, -Vb, ws, Ws, n, t, *k, r, measure)
                i_bs += hm.interface_form(us, Vs, -wb, -Wb, n, t, *k, r, measure)
        m = len(self.pressures)
        rows = [[a_ss + i_ss] + [blocks[0] for _, blocks, _, _ in self.pressures] + [i_sb]]
        for j, (_, (_, a_pu, a_pp), _, _) in enumerate(self.pressures):
            rows.append([a_pu] + [a_pp if k == j else None for k in range(m)] + [None])
        rows.append([i_bs] + [None] * m + [a_bb])
        self.a = rows
        self.unknowns = [self.u] + [p for p, _, _, _ in self.pressures] + [self.w]
        self._load_forms(v_b, Vv_b, bv)
        self.bcs = self._supports()
        self._solver = None

    # ------------------------------------------------------------------ set-up
    def _load_forms(self, v_f, Vv_f, gamma):
        """Loads on the structure's mid-surface: per unit moment and per unit shear
        (Constants: one compiled form serves every load)."""
        tank, s = self.tank, self.scene
        msh, r_b = tank.mesh, tank.r_b
        # the mid-surface test displacement, as the axisymmetric loads use
        v_b = st.mid_surface_displacement(v_f, gamma, tank.t_b, tank.offset)
        Vv = hm.mid_surface_circumferential(v_f, Vv_f, r_b, tank.t_b, tank.offset)
        self.moment = fem.Constant(msh, 0.0)
        self.shear = fem.Constant(msh, 0.0)
        w = hm.WEIGHT * r_b
        if s.wall is not None:
            R, H = s.wall.radius, s.wall.height
            top = dmesh.locate_entities_boundary(
                msh, 0, lambda x: np.isclose(x[1], H - s.embedment) & np.isclose(x[0], R))
            tags = dmesh.meshtags(msh, 0, top, np.full(len(top), 1, dtype=np.int32))
            ds_top = ufl.Measure("ds", domain=msh, subdomain_data=tags)(1)
            # V as the shear flow a thin tube carries it with, -V sin / (pi R) along
            # e_theta (its x-resultant is V): in equilibrium with the membrane state, so the
            # free top edge does not bend under it (a uniform pull would flare it, the local
            # bending of a radial line load on a free edge)
            horizontal = -self.shear / (math.pi * R) * Vv
            # the couple M - V H: a vertical line load on the mid-surface, at r_m = R - t / 2
            # from the axis: -(M - V H) cos / (pi R r_m) per unit length of the face's circle
            r_m = R - 0.5 * s.wall.thickness_at(np.array([s.wall.height]))[0]
            couple = -(self.moment - self.shear * H) / (math.pi * R * r_m) * v_b[1]
            L_b = (horizontal + couple) * w * ds_top
        else:
            a = s.plate.radius
            dx_p = tank.dx_b(st.PLATE)
            # the traction acts on the mid-surface, t / 2 above the underside: its moment
            # about it, V / (pi a^2) times the plate's volume / 2, is taken off the pressure's
            lever = s.plate.volume / (2.0 * math.pi * a**2)
            pressure = -4.0 * (self.moment - self.shear * lever) * r_b / (math.pi * a**4) * \
                v_b[1]
            traction = self.shear / (math.pi * a**2) * (v_b[0] - Vv)
            L_b = (pressure + traction) * w * dx_p
        W = ufl.TestFunction(self.V)
        zero = fem.Constant(self.tank.domain.mesh, (0.0, 0.0, 0.0))
        self.L = [ufl.inner(zero, W) * self.tank.soil.dx] + \
            [L_p for _, _, L_p, _ in self.pressures] + [L_b]

    def _supports(self):
        tank, dom, soil = self.tank, self.tank.domain, self.tank.soil
        V = self.V
        fdim = dom.mesh.topology.dim - 1
        bcs = []
        # on the axis u_z = 0 and u_r + u_theta = 0 (Z and S)
        axis = dom.facets("axis")
        for c in (1, 2):
            dofs = fem.locate_dofs_topological(V.sub(c), fdim, axis)
            bcs.append(fem.dirichletbc(0.0, dofs, V.sub(c)))
        # (a roller side holds the horizontal amplitudes D and S: u_r = u_theta = 0)
        bcs += far_supports(V, dom, tank.scene.domain, horizontal=(0, 2), vertical=1)
        bcs += soil.pins(V, [(pr.function_space, i) for pr, _, _, i in self.pressures])
        # the plate's centre: Z = S = 0 (its slope, the tilt, is free)
        sub = tank.mesh
        centre = dmesh.locate_entities(sub, 0, lambda x: np.isclose(x[0], 0.0))
        for space in (self.W.sub(0).sub(1), self.W.sub(3)):
            Vc, _ = space.collapse()
            dofs = fem.locate_dofs_topological((space, Vc), 0, centre)
            bcs.append(fem.dirichletbc(fem.Function(Vc), dofs, space))
        return bcs

    # ------------------------------------------------------------------ solve
    def solve(self, moment: float, shear: float = 0.0, log=print) -> dict:
        """Solve for the amplitudes under the overturning ``moment`` (N m, about the plate's
        underside; at the wall's foot where there is a wall) and the horizontal ``shear``
        (N) and return :meth:`results`."""

        t0 = time.perf_counter()
        self.moment.value, self.shear.value = float(moment), float(shear)
        # LU without MUMPS's scaling (the solver falls back to it if the factorisation
        # fails), even where the system is symmetric: on a rigid plate (Kp = 1e3, smooth,
        # P1-P3 soil, meshes of 0.5-2 x the default) the scaled LDL^T left relative
        # residuals of 2-8e-6 after refinement, the scaled LU up to 8e-6, this one 1.2e-8 to
        # 3.8e-7 (measured); one factorisation, so ordered as a linear scene's (AMD: on the
        # demo's nonlinear tank the harmonic's solve 0.94 -> 0.71 s against METIS)
        # (one solver for every stage that overturns: its forms compiled once, the matrix
        # re-assembled with the stage's interface states and moduli)
        if self._solver is None:
            self._solver = DirectSolver(self.a, self.L, self.bcs, self.unknowns,
                                        entity_maps=self.tank.entity_maps, name="rocking",
                                        one_shot=True, scaled=False)
        self._solver.solve()
        self.relative_residual = self._solver.relative_residual
        log(f"overturning (first harmonic): solved in {time.perf_counter() - t0:.2f} s")
        return self.results()

    # ------------------------------------------------------------------ results
    def _contact_amplitudes(self):
        """sigma_n and tau (cos) and tau_theta (sin) amplitudes per interface carrier,
        averaged over its element as the axisymmetric contact stresses are
        (:meth:`tankfx.model.interface.InterfaceBlock.cell_averages`)."""
        ifc = self.tank.interface
        q_, _, _, s_ = ufl.split(self.w)

        def tractions(_, n, t, R):              # (the axisymmetric jump is not this one)
            us, Vs = hm.soil_trace(R(self.u))
            ub, Vb = hm.shell_amplitudes(R(q_), R(s_))
            return list(hm.interface_tractions(us - ub, Vs - Vb, n, t, R(ifc.k_n), R(ifc.k_s),
                                               R(ifc.mu)))

        out = {}
        for values, name in zip(ifc.cell_averages(ifc.cell_average_forms(tractions)),
                                ("sigma_n", "tau", "tau_theta")):
            f = fem.Function(ifc.S, name=name)
            f.x.array[:] = values
            out[name] = f
        return out

    def resistance(self) -> tuple[float, float]:
        """What the soil's tractions on the structure resist: their moment about the y axis
        through the plate's underside centre, N m (pressing theta = 0 up where the load
        presses it down: equal to the applied moment at equilibrium), and their horizontal
        force against the applied shear, N. Tractions with amplitudes (f_r, f_z) (cos) and
        f_theta (sin) at (r, z) give an x-force pi r (f_r - f_theta) and a moment about y
        pi r (r f_z - (z - z_0) (f_r - f_theta)) per unit length."""
        tank = self.tank
        q_, _, _, s_ = ufl.split(self.w)
        x = ufl.SpatialCoordinate(tank.domain.mesh)
        z0 = -self.scene.embedment
        moment = force = 0.0
        ifc = tank.interface
        for _, n, t, pieces in ifc.measures():
            for measure, R in pieces:
                us, Vs = hm.soil_trace(R(self.u))
                ub, Vb = hm.shell_amplitudes(R(q_), R(s_))
                sn, tau, tau_th = hm.interface_tractions(us - ub, Vs - Vb, n, t, R(ifc.k_n),
                                                         R(ifc.k_s), R(ifc.mu))
                f = sn * n + tau * t            # the soil's traction on the structure
                fx = (f[0] - tau_th) * hm.WEIGHT * x[0]
                moment += _assemble(f[1] * hm.WEIGHT * x[0] * x[0] - fx * (x[1] - z0),
                                    measure, tank)
                force -= _assemble(fx, measure, tank)
        return moment, force

    def vertical_stress(self) -> fem.Function:
        """The amplitude of sigma_zz (compression positive, cos theta), projected as the
        axisymmetric one is (:meth:`tankfx.analysis.SoilBlock.vertical_stress`)."""
        soil = self.tank.soil
        eps = hm.soil_strain(self.u, soil.r)
        pressures = [p for p, _, _, _ in self.pressures]
        if self.undrained:
            # 2 G eps - p I, each stratum with its own pressure (pinned to 0 outside its
            # cells: their sum is each cell's)

            stress = mixed_stress(eps, sum(pressures), self.E, self.nu)
            chi = self._ground
            if chi is not None:
                # a ringwall's cells in the displacement form (with nu 0 in the ground,
                # where its lambda would be infinite and the indicator zero)

                stress = by_stratum([chi], stress, elastic(eps, soil.E, soil.nu * (1.0 - chi)))
        else:
            stress = soil.stress_of(eps, pressures)
        return soil.vertical_stress(stress, name="sigma_zz_overturning")

    def stress_line(self) -> np.ndarray:
        """(r, z) of the vertical line in the soil under the shell (the plate's edge without
        a wall) on which the soil's vertical stress is reported: depths 0.05 to 2 radii
        below the foundation's underside."""
        s = self.scene
        r = s.wall.radius if s.wall is not None else s.plate.radius
        depth = np.linspace(0.05, 2.0, 40) * r
        return np.column_stack([np.full_like(depth, r), -s.embedment - depth])

    def results(self) -> dict:
        tank, s = self.tank, self.scene
        F = hm.shell_resultants(self.w, tank.r_b, tank.t_b, tank.E, tank.nu, tank.thickness,
                                tank.offset)
        F.update(self._contact_amplitudes())
        pts = tank.stations(tank.plate_cells, along=0)
        cells = tank.plate_cells
        u = evaluate_at(F["u"], pts, cells)
        plate = {"r": pts[:, 0].tolist(),
                 "w": (-u[:, 1]).tolist(),
                 "u_r": u[:, 0].tolist(),
                 "u_theta": evaluate_at(F["V"], pts, cells)[:, 0].tolist(),
                 "M_r": evaluate_at(F["M_s"], pts, cells)[:, 0].tolist(),
                 "M_theta": evaluate_at(F["M_theta"], pts, cells)[:, 0].tolist(),
                 "contact_normal": evaluate_at(F["sigma_n"], pts, cells)[:, 0].tolist(),
                 "contact_shear": evaluate_at(F["tau"], pts, cells)[:, 0].tolist()}
        profiles = {"plate": plate}
        at = s.wall.radius if s.wall is not None else s.plate.radius
        w_shell = float(np.interp(at, plate["r"], plate["w"]))
        M = float(self.moment.value)
        out = {"moment": M, "shear": float(self.shear.value), "profiles": profiles,
               "shell_settlement_amplitude": w_shell,
               "tilt": w_shell / at}
        # (none without a moment: a shear alone tilts the tank through its lever only)
        out["rocking_stiffness"] = M / out["tilt"] if M and out["tilt"] else None
        if s.wall is not None:
            cells = tank.wall_cells
            pts = tank.stations(cells, along=1)
            u = evaluate_at(F["u"], pts, cells)
            V = evaluate_at(F["V"], pts, cells)[:, 0]
            profiles["wall"] = {
                "z": (pts[:, 1] + s.embedment).tolist(),
                "u_r": u[:, 0].tolist(), "u_z": u[:, 1].tolist(), "u_theta": V.tolist(),
                # the horizontal displacement of the wall's neutral axis (theta = 90 deg)
                "u_x": (-V).tolist(),
                "N_z": evaluate_at(F["N_s"], pts, cells)[:, 0].tolist(),
                "N_z_theta": evaluate_at(F["N_s_theta"], pts, cells)[:, 0].tolist(),
                "M_z": evaluate_at(F["M_s"], pts, cells)[:, 0].tolist()}
        if s.wall is not None:
            # the joint's moment amplitudes: the wall's foot, the plate just inside the wall
            corner = np.array([[s.wall.radius, -s.embedment]])
            inner = tank.plate_cells[tank.cell_midpoints[tank.plate_cells, 0] < s.wall.radius]
            out["junction"] = {
                "M_wall": float(evaluate_at(F["M_s"], corner, tank.wall_cells)[0, 0]),
                "M_plate": float(evaluate_at(F["M_s"], corner, inner)[0, 0])
                if tank.mesh.comm.allreduce(len(inner)) else 0.0}
        line = self.stress_line()
        cells = tank.domain.cells("soil")
        profiles["soil_line"] = {
            "r": line[:, 0].tolist(), "depth": (-line[:, 1] - s.embedment).tolist(),
            "sigma_zz": evaluate_at(self.vertical_stress(), line, cells)[:, 0].tolist()}
        moment, force = self.resistance()
        # relative to the loads' size: the moment, or the shear's over the tank's height
        # (or radius), and the other way round
        lever = max(s.wall.height if s.wall is not None else 0.0, at)
        V = out["shear"]
        out["equilibrium"] = {
            "moment_resisted": moment, "shear_resisted": force,
            "moment_relative_error": abs(moment - M) / max(abs(M), abs(V) * lever, 1e-300),
            "shear_relative_error": abs(force - V) / max(abs(V), abs(M) / lever, 1e-300)}
        return out


def _assemble(integrand, measure, tank) -> float:
    """The integral of ``integrand`` over the parent's interface ``measure``, all ranks."""
    return allsum(tank.domain.mesh.comm, fem.assemble_scalar(
        fem.form(integrand * measure, entity_maps=tank.entity_maps)))
