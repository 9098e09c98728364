"""Plate and wall elements: locking, accuracy against element count, the cost of ignoring the
plate's face offset, the coupled raft (Brown 1969) against mesh size and run time, a
wall of courses against the stepped-shell solution, and the members' first harmonic
(overturning) against plate and shell theory.

    python benchmarks/structure.py [--out results/benchmarks]
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

from tankfx import Scene, analyse
from tankfx.model.tank import TankModel
from tankfx.mesh import build_domain
from tankfx.fem.evaluate import evaluate_at
from tankfx.fem.solvers import make_solver
from tankfx.results.structure import structure_results
from tankfx.verification.rigs import StandaloneShell
from tankfx.laws.shell import flexural_rigidity, wall_beta

say = print if MPI.COMM_WORLD.rank == 0 else (lambda *a, **k: None)


def plate_locking(rows):
    say("\n1. Clamped circular plate, uniform load (Timoshenko): error against thickness and "
        "element count")
    say(f"{'t/a':>7s} {'elements':>8s} {'err w0':>9s} {'err M_r(0)':>10s} {'err M_r(a)':>10s}")
    a, q, E, nu = 1.0, 1e4, 30e9, 0.3
    for t in (0.2, 0.1, 1e-2, 1e-3, 1e-4):
        for n in (6, 12, 24):
            s = 1.0 - (1.0 - np.linspace(0, 1, n + 1)) ** 1.5
            shell = StandaloneShell(np.column_stack([s, 0 * s]), E, nu, t,
                                    {lambda x: np.isclose(x[0], 0): {"u_r", "beta"},
                                     lambda x: np.isclose(x[0], a): {"u_r", "u_z", "beta"}},
                                    lambda v, x: -q * v[1])
            F = shell.resultants()
            D = flexural_rigidity(E, nu, t)
            w0 = -evaluate_at(F["u"], np.array([[0.0, 0.0]]))[0, 1]
            M = evaluate_at(F["M_s"], np.array([[0.0, 0.0], [a, 0.0]]))[:, 0]
            e = (w0 / (q * a**4 / (64 * D)) - 1, M[0] / ((1 + nu) * q * a**2 / 16) - 1,
                 M[1] / (-q * a**2 / 8) - 1)
            rows.append({"case": "clamped plate", "t/a": t, "elements": n,
                         "err_w0": e[0], "err_M0": e[1], "err_Ma": e[2]})
            say(f"{t:7.0e} {n:8d} {e[0]:+9.2e} {e[1]:+10.2e} {e[2]:+10.2e}")


def wall_base(rows):
    say("\n2. Wall with a clamped base, full of liquid (long-shell theory)")
    say(f"{'t/R':>7s} {'beta H':>7s} {'elements':>8s} {'err M0':>9s} {'err Q0':>9s}")
    R, H, g, nu = 10.0, 8.0, 9810.0, 0.3
    for tR in (1e-2, 1e-3, 1e-4):
        t = tR * R
        beta = wall_beta(R, t, nu)
        for n in (30, 60):
            z = H * np.linspace(0, 1, n + 1) ** 2
            shell = StandaloneShell(np.column_stack([np.full(n + 1, R), z]), 200e9, nu, t,
                                    {lambda x: np.isclose(x[1], 0): {"u_r", "u_z", "beta"}},
                                    lambda v, x: g * (H - x[1]) * v[0])
            F = shell.resultants()
            M0 = evaluate_at(F["M_s"], np.array([[R, 0.0]]))[0, 0]
            Q0 = evaluate_at(F["Q"], np.array([[R, 0.0]]))[0, 0]
            e = (-M0 / (g * (H - 1 / beta) / (2 * beta**2)) - 1,
                 abs(Q0) / (g * (2 * beta * H - 1) / (2 * beta**2)) - 1)
            rows.append({"case": "clamped wall", "t/R": tR, "elements": n, "err_M0": e[0],
                         "err_Q0": e[1]})
            say(f"{tR:7.0e} {beta * H:7.1f} {n:8d} {e[0]:+9.2e} {e[1]:+9.2e}")


def offset_cost(rows):
    say("\n3. What ignoring the members' face offset costs (nu_s = 0.3): change of the result "
        "when the mid-surfaces are put on the contact lines, bonded and smooth, without and "
        "with a wall (Kt = 0.1; 2.5 m of water besides the 100 kPa)")
    say(f"{'Kp':>5s} {'wall':>5s} {'contact':>7s} {'t_p/a':>6s} {'w0':>8s} {'wd':>8s} "
        f"{'M0':>8s} {'M_wall':>8s} {'M_plate':>8s}")
    for wall in (False, True):
        for Kp in (0.1, 1.0, 10.0):
            for condition in ("bonded", "smooth"):
                d = {"soil": {"E": 10e6, "nu": 0.3},
                     "plate": {"radius": 1.0, "Kp": Kp, "E": 30e9, "nu": 0.2},
                     "interface": {"condition": condition}, "load": {"pressure": 100e3}}
                if wall:
                    d["wall"] = {"radius": 1.0, "Kt": 0.1, "height": 3.0, "E": 30e9,
                                 "nu": 0.2}
                    d["load"] |= {"liquid_unit_weight": 9810.0, "liquid_height": 2.5}
                sc = Scene.from_dict(d)
                out = []
                for offset in (True, False):
                    m = TankModel(sc, build_domain(sc), face_offset=offset)
                    m.begin_stage()      # (as an analysis does: its interface states)
                    solver = make_solver(sc.solver, m.a, m.L, m.bcs, m.unknowns,
                                         entity_maps=m.entity_maps, name="offset",
                                         symmetric=True, one_shot=True)
                    solver.solve()        # (a linear interface: one solve)
                    found = m.foundation_results()      # (before the structure's: its fields)
                    out.append(found | (structure_results(m)["junction"] if wall else {}))
                keys = ("w0", "wd", "M0") + (("M_wall", "M_plate") if wall else ())
                ch = {k: out[1][k] / out[0][k] - 1 for k in keys}
                rows.append({"case": "offset ignored", "Kp": Kp, "wall": wall,
                             "contact": condition, **ch})
                say(f"{Kp:5g} {str(wall):>5s} {condition:>7s} {sc.plate.thickness:6.3f} "
                    + " ".join(f"{ch[k]:+8.2%}" if k in ch else f"{'-':>8s}"
                               for k in ("w0", "wd", "M0", "M_wall", "M_plate")))


def brown_raft(rows):
    say("\n4. Free raft, smooth (Brown 1969, Kp = 10): error against mesh and run time")
    say(f"{'P':>2s} {'edge/a':>7s} {'near/a':>7s} {'dofs':>8s} {'time s':>7s} {'err w0':>8s} "
        f"{'err wd':>8s} {'err M0':>8s}")
    ref = (1.588, 0.02378, 0.07470)
    for deg, edge, near in ((2, 0.05, 0.1), (2, 0.01, 0.1), (2, 0.002, 0.1), (2, 0.002, 0.05),
                            (3, 0.002, 0.2), (3, 0.002, 0.1)):
        sc = Scene.from_dict({"soil": {"E": 10e6, "nu": 0.3},
                              "plate": {"radius": 1.0, "Kp": 10.0, "E": 30e9, "nu": 0.3},
                              "interface": {"condition": "smooth"}, "load": {"pressure": 1e5},
                              "mesh": {"degree": deg, "edge_size": edge, "near_size": near}})
        t = time.perf_counter()
        r = analyse(sc).results
        t = time.perf_counter() - t
        k = 1e5 * 0.91 / 10e6
        e = (r["w0"] / k / ref[0] - 1, r["wd"] / k / ref[1] - 1, r["nondim"]["M0"] / ref[2] - 1)
        rows.append({"case": "Brown raft Kp=10", "degree": deg, "edge_size": edge,
                     "near_size": near, "dofs": r["dofs"]["total"], "time_s": t,
                     "err_w0": e[0], "err_wd": e[1], "err_M0": e[2]})
        say(f"{deg:2d} {edge:7.3f} {near:7.2f} {r['dofs']['total']:8d} {t:7.2f} {e[0]:+8.2%} "
            f"{e[1]:+8.2%} {e[2]:+8.2%}")


def wall_of_courses(rows):
    say("\n5. Wall of three courses (20, 12, 8 mm), clamped, full of water: the stepped-shell "
        "solution (tankfx.verification.reference)")
    say(f"{'el./course':>10s} {'err M (of M0)':>14s} {'err w (of max)':>15s} {'time s':>7s}")
    from tankfx.verification.reference import stepped_wall_under_liquid

    courses, R, g, nu = [(2.0, 0.020), (3.0, 0.012), (3.0, 0.008)], 10.0, 9810.0, 0.3
    H = sum(h for h, _ in courses)
    tops = np.cumsum([h for h, _ in courses])
    zq = np.linspace(0.0, H, 161)
    w_ref, M_ref = stepped_wall_under_liquid(R, courses, 200e9, nu, g, H, zq)
    for n in (5, 10, 20, 40):
        t0 = time.perf_counter()
        z, base = [0.0], 0.0
        s = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, n + 1))[1:]
        for h, _ in courses:
            z += list(base + h * s)
            base += h
        shell = StandaloneShell(
            np.column_stack([np.full(len(z), R), z]), 200e9, nu,
            lambda mid: np.array([t for _, t in courses])[np.searchsorted(tops, mid[:, 1])],
            {lambda x: np.isclose(x[1], 0.0): {"u_r", "u_z", "beta"}},
            lambda v, x: g * (H - x[1]) * v[0])
        F = shell.resultants()
        pts = np.column_stack([np.full(len(zq), R), zq])
        M = evaluate_at(F["M_s"], pts)[:, 0]
        w = evaluate_at(F["u"], pts)[:, 0]
        dt = time.perf_counter() - t0
        eM = np.max(np.abs(M - M_ref)) / np.max(np.abs(M_ref))
        ew = np.max(np.abs(w - w_ref)) / np.max(np.abs(w_ref))
        rows.append({"case": "wall of courses", "elements_per_course": n, "err_M": eM,
                     "err_w": ew, "time_s": dt})
        say(f"{n:10d} {eM:14.2e} {ew:15.2e} {dt:7.2f}")


def overturning_members(rows):
    say("\n6. The first harmonic (overturning): a clamped plate under q (r/a) cos theta "
        "(Timoshenko's w, M_r), and a cylinder clamped at its foot under a couple on its top "
        "(the bending moment at the foot of a semi-infinite cylinder)")
    say(f"{'member':>9s} {'elements':>9s} {'err M':>9s} {'err w':>9s} {'time s':>7s}")
    import math

    import ufl

    from tankfx.verification import rigs as hm

    a, t, E, nu, q = 1.0, 0.02, 2e11, 0.3, 1e4
    D = flexural_rigidity(E, nu, t)
    rho = np.linspace(0, 1, 21)[1:-1]
    A = q * a**4 / (192 * D)
    f, f1, f2 = rho - 2 * rho**3 + rho**5, 1 - 6 * rho**2 + 5 * rho**4, -12 * rho + 20 * rho**3
    w_ref, M_ref = A * rho * (1 - rho**2) ** 2, -D * A / a**2 * (f2 + nu * (f1 / rho - f / rho**2))
    for n in (10, 20, 40, 80):
        t0 = time.perf_counter()
        shell = hm.StandaloneHarmonicShell(
            np.column_stack([np.linspace(0, a, n + 1), np.zeros(n + 1)]), E, nu, t,
            {lambda x: np.isclose(x[0], 0.0): ("Z", "S"),
             lambda x: np.isclose(x[0], a): ("D", "Z", "S", "beta")},
            lambda u, V, x: -q * x[0] / a * u[1])
        F = shell.resultants()
        P = np.column_stack([rho * a, 0 * rho])
        eM = np.max(np.abs(evaluate_at(F["M_s"], P)[:, 0] - M_ref)) / np.max(np.abs(M_ref))
        ew = np.max(np.abs(-evaluate_at(F["u"], P)[:, 1] - w_ref)) / np.max(w_ref)
        dt = time.perf_counter() - t0
        rows.append({"case": "harmonic clamped plate", "elements": n, "err_M": eM,
                     "err_w": ew, "time_s": dt})
        say(f"{'plate':>9s} {n:9d} {eM:9.2e} {ew:9.2e} {dt:7.2f}")
    R, H, M = 10.0, 10.0, 1e6
    qz = M / (math.pi * R**2)
    reference = nu * qz * t / (2 * math.sqrt(3 * (1 - nu**2)))
    for n in (25, 50, 100, 200):
        t0 = time.perf_counter()
        z = np.concatenate([np.linspace(0, 1.0, n + 1), np.linspace(1.0, H, 91)[1:]])
        shell = hm.StandaloneHarmonicShell(
            np.column_stack([np.full_like(z, R), z]), E, nu, t,
            {lambda x: np.isclose(x[1], 0.0): ("D", "Z", "S", "beta")},
            lambda u, V, x: 0.0 * u[0],
            edge_load=lambda u, V, x: ufl.conditional(ufl.gt(x[1], H / 2), -qz * u[1], 0.0))
        F = shell.resultants()
        eM = abs(abs(evaluate_at(F["M_s"], np.array([[R, 0.0]]))[0, 0]) / reference - 1)
        dt = time.perf_counter() - t0
        rows.append({"case": "harmonic wall foot", "elements_in_first_metre": n, "err_M": eM,
                     "time_s": dt})
        say(f"{'wall':>9s} {n:9d} {eM:9.2e} {'':>9s} {dt:7.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="results/benchmarks")
    args = ap.parse_args()
    rows: list[dict] = []
    plate_locking(rows)
    wall_base(rows)
    offset_cost(rows)
    brown_raft(rows)
    wall_of_courses(rows)
    overturning_members(rows)
    if MPI.COMM_WORLD.rank == 0:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "structure.json").write_text(json.dumps(rows, indent=1))
        say(f"\ntable written to {out / 'structure.json'}")


if __name__ == "__main__":
    main()
