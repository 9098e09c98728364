"""The verification table of the documentation (docs/verification.md), from actual runs: every
case is solved, its computed quantities are set against their references (closed forms and
published values), and the page is rendered from the records, so that it is never typed.

    python docs/verification.py                 # run every case, write runs.json, render the page
    python docs/verification.py --only raft     # re-run the cases whose names contain "raft"
    python docs/verification.py --render        # render the page from runs.json, run nothing

Each case is one fresh process, whose wall time is the case's time: `python -m tankfx run
--no-figures --no-fields` for the cases that are scenes (those of benchmarks/accuracy.py at the
default mesh, and a few from the test suite), and `python docs/verification.py --case NAME
--json` for the rigs of tankfx.verification.rigs (a shell on rigid supports, Terzaghi's column,
Mandel's cylinder), so that every time includes start-up, meshing and the (disk-cached) form
compilation alike. The raw records go to docs/verification/runs.json; the page is rendered from
them alone (tests/test_verification_table.py checks that it is, that every error is within the
tolerance its test asserts, and that the cheapest cases reproduce their records).

The tolerances are those the test suite asserts for the same quantity; each record names the
test. The nonlinear embedded tank of benchmarks/accuracy.py is left out: its reference is its
own finest solution (P3, level 1), which is not cheap, and not a reference of the kind here.
"""
from __future__ import annotations

import argparse
import datetime
import importlib.util
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[1]
RUNS = ROOT / "docs" / "verification" / "runs.json"
PAGE = ROOT / "docs" / "verification.md"
MARKER = "VERIFICATION-JSON "        #: the line of a --case --json child that carries its result


def accuracy():
    """benchmarks/accuracy.py as a module (benchmarks is not a package)."""
    if "tankfx_benchmarks_accuracy" not in sys.modules:
        spec = importlib.util.spec_from_file_location("tankfx_benchmarks_accuracy",
                                                      ROOT / "benchmarks" / "accuracy.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module
        spec.loader.exec_module(module)
    return sys.modules["tankfx_benchmarks_accuracy"]


# ------------------------------------------------------------------------------ rows
def row(quantity, reference, value, reference_value, unit, tolerance, test, *, scale=None,
        scale_name=None, one_sided=False, at=None) -> dict:
    """One compared quantity. The error is (value - reference_value) / scale, the scale the
    reference value itself unless another is named (``scale_name``: what the test divides
    by); ``one_sided``: the test asserts 0 < error < tolerance."""
    value, reference_value = float(value), float(reference_value)
    scale = float(scale if scale is not None else reference_value)
    return {"quantity": quantity, "reference": reference, "value": value,
            "reference_value": reference_value, "unit": unit,
            "error": (value - reference_value) / scale, "scale": scale,
            "error_relative_to": scale_name, "tolerance": float(tolerance),
            "one_sided": one_sided, "at": at, "test": test}


def _check(case: str, rows: list[dict], expected: dict) -> None:
    """The errors computed here against benchmarks/accuracy.py's own (``expected``), so that
    the two cannot disagree on a reference: the signed ones equal, the largest-of ones (a
    profile's) in magnitude."""
    for r in rows:
        key = r["key"]
        e = expected[key]
        if not math.isclose(abs(r["error"]), abs(e), rel_tol=1e-9, abs_tol=1e-15) or \
                (r["error"] * e < 0 and key not in ("sigma_zz",)):
            raise RuntimeError(f"{case}, {key}: error {r['error']!r} here, {e!r} in "
                               "benchmarks/accuracy.py")


# ---------------------------------------------------------- the cases of accuracy.py
TF = "tests/test_flexible_load.py"
TT = "tests/test_tank.py"


def rows_flexible(r: dict) -> list[dict]:
    import numpy as np

    from tankfx.verification import reference as ref

    acc = accuracy()
    P, A, E, NU = acc.P, acc.A, acc.E, acc.NU
    z = np.array(r["profiles"]["axis"]["z"])
    s = np.array(r["profiles"]["axis"]["sigma_zz"])
    win = np.flatnonzero((z >= 0.25 * A) & (z <= 5 * A))
    exact = ref.flexible_axis_stress(P, A, z[win])
    k = win[int(np.argmax(np.abs(s[win] / exact - 1)))]
    out = [row("w0, centre settlement", "Boussinesq: 2 p a (1 - nu^2) / E",
               r["w0"], ref.flexible_centre_settlement(P, A, E, NU), "m", 2e-3,
               f"{TF}::test_centre_and_edge_settlement_at_default_settings[0.3]") | {"key": "w0"},
           row("w_edge, settlement at r = a", "Boussinesq: 4 p a (1 - nu^2) / (pi E)",
               r["w_edge"], ref.flexible_edge_settlement(P, A, E, NU), "m", 2e-3,
               f"{TF}::test_centre_and_edge_settlement_at_default_settings[0.3]")
           | {"key": "w_edge"},
           row("sigma_zz on the axis, largest error over 0.25 a <= z <= 5 a",
               "Boussinesq: p [1 - z^3 / (a^2 + z^2)^1.5]", s[k],
               float(ref.flexible_axis_stress(P, A, z[k])), "Pa", 1e-2,
               f"{TF}::test_axis_stress_within_one_percent[0.3]", at=f"z = {z[k]:.4g} m")
           | {"key": "sigma_zz"}]
    _check("flexible load", out, acc.errors("flexible load", r, None))
    return out


def rows_smooth_punch(r: dict) -> list[dict]:
    from tankfx.verification import reference as ref

    acc = accuracy()
    P, A, E, NU = acc.P, acc.A, acc.E, acc.NU
    force = P * math.pi * A**2
    out = [row("w0, settlement", "Boussinesq's rigid punch: F (1 - nu^2) / (2 a E)",
               r["w0"], force * (1 - NU**2) / (2 * A * E), "m", 1e-2,
               f"{TT}::test_rigid_limit_smooth_and_bonded_punch[0.3]") | {"key": "w0"},
           row("M0, plate's centre moment",
               "closed form: a free plate under q and the rigid punch's contact pressure "
               "q a / (2 sqrt(a^2 - r^2))",
               r["M0"], ref.rigid_plate_centre_moment(P, A, 0.3), "N m/m", 6e-3,
               f"{TT}::test_rigid_plate_centre_moment_converges_to_the_rigid_limit",
               one_sided=True) | {"key": "M0"}]
    _check("rigid punch, smooth", out, acc.errors("rigid punch, smooth", r, None))
    return out


def rows_bonded_punch(r: dict) -> list[dict]:
    acc = accuracy()
    P, A, E, NU = acc.P, acc.A, acc.E, acc.NU
    G = E / (2 * (1 + NU))
    out = [row("w0, settlement", "Mossakovskii (1954), Spence (1968): "
               "F (1 - 2 nu) / (4 G a ln(3 - 4 nu))", r["w0"],
               P * math.pi * A**2 / (4 * G * A * math.log(3 - 4 * NU) / (1 - 2 * NU)), "m",
               1e-2, f"{TT}::test_rigid_limit_smooth_and_bonded_punch[0.3]") | {"key": "w0"}]
    _check("rigid punch, bonded", out,
           acc.errors("rigid punch, bonded", r, {"M0": r["M0"]}))
    return out


def rows_rocking(r: dict) -> list[dict]:
    from tankfx.verification import reference as ref

    acc = accuracy()
    A, E, NU, M = acc.A, acc.E, acc.NU, acc.MOMENT
    o = r["overturning"]
    x, c = o["profiles"]["plate"]["r"], o["profiles"]["plate"]["contact_normal"]
    # element averages (every second station a midpoint) against the reference's ring average
    cells = [(i, ref.ring_average(lambda s: ref.rigid_disc_rocking_pressure(M, A, s),
                                  x[i - 1], x[i + 1]))
             for i in range(1, len(x) - 1, 2) if 0.1 * A < x[i] < 0.9 * A]
    i, exact = max(cells, key=lambda ie: abs(c[ie[0]] / ie[1] - 1))
    test = "tests/test_overturning.py::test_rigid_disc_rocks_as_borowickas[0.3]"
    out = [row("rocking stiffness M / tilt", "Borowicka (1943): 4 E a^3 / (3 (1 - nu^2))",
               o["rocking_stiffness"], ref.rigid_disc_rocking_stiffness(E, NU, A), "N m/rad",
               5e-3, test) | {"key": "rocking"},
           row("contact pressure (first harmonic), element averages over 0.1 a < r < 0.9 a, "
               "largest error", "Borowicka: 3 M r / (2 pi a^3 sqrt(a^2 - r^2)), averaged "
               "over the element", c[i], exact, "Pa", 4e-2, test,
               at=f"r = {x[i]:.4g} m") | {"key": "contact"}]
    _check("rigid disc, rocking", out, acc.errors("rigid disc, rocking", r, None))
    return out


def rows_layered(r: dict) -> list[dict]:
    from tankfx.verification import reference as ref

    acc = accuracy()
    w0, w_edge = ref.layered_surface_settlement(acc.P, acc.A, [0.0, acc.A], acc.LAYERS, None)
    name = "Burmister (1945): three layers on a rigid base, by Hankel transform"
    test = "tests/test_layers.py::test_flexible_load_on_layers_is_burmisters[undrained_middle]"
    out = [row("w0, centre settlement", name, r["w0"], w0, "m", 5e-4, test) | {"key": "w0"},
           row("w_edge, settlement at r = a", name, r["w_edge"], w_edge, "m", 5e-4, test)
           | {"key": "w_edge"}]
    _check("layered ground", out, acc.errors("layered ground", r, None))
    return out


def rows_raft(Kp: float) -> Callable[[dict], list[dict]]:
    def rows(r: dict) -> list[dict]:
        acc = accuracy()
        P, A, E, NU = acc.P, acc.A, acc.E, acc.NU
        w0, wd, M0 = acc.BROWN[Kp]
        scale = P * A * (1 - NU**2) / E
        test = f"{TT}::test_free_raft_against_brown_1969[{Kp}-{w0}-{wd}-{M0}]"
        name = "Brown (1969): {} q a (1 - nu^2) / E"
        out = [row("w0, centre settlement", name.format(f"{w0:g}"), r["w0"], w0 * scale,
                   "m", 2e-2, test) | {"key": "w0"},
               row("wd = w0 - w_edge, differential settlement", name.format(f"{wd:g}"),
                   r["wd"], wd * scale, "m", 2e-2, test) | {"key": "wd"},
               row("M0, centre moment", f"Brown (1969): {M0:g} q a^2", r["M0"],
                   M0 * P * A**2, "N m/m", 2e-2, test) | {"key": "M0"}]
        _check(f"free raft, Kp = {Kp:g}", out, acc.errors(f"free raft, Kp = {Kp:g}", r, None))
        return out
    return rows


# ---------------------------------------------------------- scenes from the test suite
#: PLAXIS's verification "flexible tank foundation on elastic saturated soil" (test_trust.py)
PLAXIS = {"R": 23.35, "q": 263.3e3, "E": 95.8e6, "nu": 0.499, "w0": 74.21e-3}
#: Gibson's soil as test_extreme.py has it: E = E_s (1 + lambda z), nu = 0.5, lambda a = 1e3
GIBSON = {"E": 1e4, "lam": 1e3, "p": 1e3, "a": 1.0}
#: tests/conftest.py's COARSE mesh for the 1 m scenes
COARSE = {"edge_size": 0.01, "near_size": 0.25, "growth": 0.3}


def scene_plaxis() -> dict:
    R = PLAXIS["R"]
    return {"soil": {"E": PLAXIS["E"], "nu": PLAXIS["nu"]},
            "load": {"pressure": PLAXIS["q"], "load_radius": R},
            "domain": {"radius": 5 * R, "depth": 5 * R, "side": "roller"},
            # Scene.with_coarse_mesh(), as the test solves it
            "mesh": {"edge_size": 0.01 * R, "near_size": 0.25 * R, "growth": 0.3}}


def rows_plaxis(r: dict) -> list[dict]:
    return [row("w0, centre settlement (5 R x 5 R box, roller sides, fixed base)",
                "PLAXIS 2D verification manual: flexible tank foundation on elastic saturated "
                "soil, 74.21 mm", r["w0"], PLAXIS["w0"], "m", 1e-3,
                "tests/test_trust.py::"
                "test_plaxis_flexible_tank_foundation_on_elastic_saturated_soil")]


def scene_gibson() -> dict:
    g = GIBSON
    return {"soil": {"E": g["E"], "nu": 0.5, "E_gradient": g["lam"]},
            "load": {"pressure": g["p"], "load_radius": g["a"]}, "mesh": dict(COARSE)}


def rows_gibson(r: dict) -> list[dict]:
    g = GIBSON
    m = g["E"] * g["lam"] / 3        # the shear modulus' gradient (nu = 0.5: E = 3 G)
    return [row("w0, centre settlement (E = E_s (1 + lambda z), nu = 0.5, lambda a = 1e3)",
                "Gibson (1967): p / (2 m), m = E_s lambda / 3", r["w0"], g["p"] / (2 * m),
                "m", 3.0 / (g["lam"] * g["a"]),
                "tests/test_extreme.py::test_incompressible_gibson_soil_settles_like_winkler_"
                "springs")]


# ---------------------------------------------------------- rigs (run in this process)
def _dofs(*functions) -> int:
    total = 0
    for f in functions:
        im = f.function_space.dofmap.index_map
        total += im.size_global * f.function_space.dofmap.index_map_bs
    return int(total)


PLATE = {"a": 1.0, "q": 1e4, "E": 30e9, "nu": 0.3, "t": 0.01, "elements": 24}
WALL = {"R": 10.0, "H": 8.0, "gamma": 9810.0, "E": 200e9, "nu": 0.3, "t": 0.01, "elements": 60}
BIOT = {"E": 5e6, "nu": 0.3, "k": 1e-8}


def rig_plate() -> dict:
    """The clamped circular plate under uniform load (test_structure.py's plate(), t/a =
    0.01, 24 elements graded towards the edge)."""
    import numpy as np

    from tankfx.fem.evaluate import evaluate_at
    from tankfx.laws.shell import flexural_rigidity
    from tankfx.verification.rigs import StandaloneShell

    p = PLATE
    a, q, E, nu, t, n = p["a"], p["q"], p["E"], p["nu"], p["t"], p["elements"]
    s = 1.0 - (1.0 - np.linspace(0.0, 1.0, n + 1)) ** 1.5
    shell = StandaloneShell(np.column_stack([a * s, np.zeros(n + 1)]), E, nu, t,
                            supports={lambda x: np.isclose(x[0], 0.0): {"u_r", "beta"},
                                      lambda x: np.isclose(x[0], a): {"u_r", "u_z", "beta"}},
                            load=lambda v, x: -q * v[1])
    F = shell.resultants()
    D = flexural_rigidity(E, nu, t)
    w0 = -evaluate_at(F["u"], np.array([[0.0, 0.0]]))[0, 1]
    M = evaluate_at(F["M_s"], np.array([[0.0, 0.0], [a, 0.0]]))[:, 0]
    test = "tests/test_structure.py::test_circular_plate_on_rigid_supports[clamped-0.01]"
    name = "Timoshenko & Woinowsky-Krieger (1959), Sec. 15"
    return {"dofs": _dofs(shell.w),
            "settings": {"elements": n, "thickness": t, "text": f"{n} shell elements, "
                         f"t = {t:g} m (t/a = {t / a:g})"},
            "rows": [row("w0, centre deflection", f"{name}: q a^4 / (64 D)", w0,
                         q * a**4 / (64 * D), "m", 5e-3, test),
                     row("M_r(0), centre moment", f"{name}: (1 + nu) q a^2 / 16", M[0],
                         (1 + nu) * q * a**2 / 16, "N m/m", 5e-3, test),
                     row("M_r(a), edge moment", f"{name}: -q a^2 / 8", M[1], -q * a**2 / 8,
                         "N m/m", 5e-3, test)]}


def rig_wall() -> dict:
    """The long wall clamped at its base, full of liquid (test_structure.py, t/R = 1e-3)."""
    import numpy as np

    from tankfx.fem.evaluate import evaluate_at
    from tankfx.laws.shell import wall_beta
    from tankfx.verification.rigs import StandaloneShell

    w = WALL
    R, H, gamma, t, n = w["R"], w["H"], w["gamma"], w["t"], w["elements"]
    beta = wall_beta(R, t, w["nu"])
    z = H * np.linspace(0.0, 1.0, n + 1) ** 2
    shell = StandaloneShell(np.column_stack([np.full(n + 1, R), z]), w["E"], w["nu"], t,
                            supports={lambda x: np.isclose(x[1], 0.0): {"u_r", "u_z", "beta"}},
                            load=lambda v, x: gamma * (H - x[1]) * v[0])
    F = shell.resultants()
    M0 = evaluate_at(F["M_s"], np.array([[R, 0.0]]))[0, 0]
    Q0 = evaluate_at(F["Q"], np.array([[R, 0.0]]))[0, 0]
    test = "tests/test_structure.py::test_wall_with_clamped_base_under_liquid[0.001]"
    name = "Timoshenko & Woinowsky-Krieger (1959), Sec. 117, long shell"
    return {"dofs": _dofs(shell.w),
            "settings": {"elements": n, "thickness": t, "text": f"{n} shell elements, "
                         f"R = {R:g} m, t = {t:g} m, H = {H:g} m"},
            "rows": [row("M0, base moment", f"{name}: -gamma (H - 1/beta) / (2 beta^2)", M0,
                         -gamma * (H - 1 / beta) / (2 * beta**2), "N m/m", 1e-2, test),
                     row("|Q0|, base shear", f"{name}: gamma (2 beta H - 1) / (2 beta^2)",
                         abs(Q0), gamma * (2 * beta * H - 1) / (2 * beta**2), "N/m", 1e-2,
                         test)]}


def rig_terzaghi() -> dict:
    """Terzaghi's column as test_consolidation.py's test_oedometer_against_terzaghi: 10 m,
    40 P2/P1 cells, drained at the top, 10 BDF2 steps a decade."""
    import numpy as np

    from tankfx.iterations.time_stepping import time_steps
    from tankfx.laws.biot import consolidation_coefficient
    from tankfx.verification import reference as ref
    from tankfx.verification.rigs import Oedometer

    E, NU, K = BIOT["E"], BIOT["nu"], BIOT["k"]
    H, q, cells, per_decade = 10.0, 1e5, 40, 10
    c_v = consolidation_coefficient(E, NU, K, 9810.0)
    Tv = np.array([0.01, 0.05, 0.2, 0.5, 1.0])
    times = Tv * H**2 / c_v
    oed = Oedometer(H, E, NU, K, q, cells=cells)
    history = oed.run(time_steps(times, times[0] / 1000, per_decade), True)
    t = np.array([h["t"] for h in history])
    at = [int(np.argmin(abs(t - ti))) for ti in times]
    s = np.array([history[i]["settlement"] for i in at])
    p = np.array([history[i]["base_pressure"] for i in at])
    final = q * H / (E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)))
    s_exact = ref.terzaghi_settlement(q, H, E, NU, K, times)
    p_exact = ref.terzaghi_pore_pressure(q, 1.0, Tv)
    ks = int(np.argmax(np.abs(s - s_exact)))
    kp = int(np.argmax(np.abs(p - p_exact)))
    test = "tests/test_consolidation.py::test_oedometer_against_terzaghi"
    where = "largest error at T_v = 0.01, 0.05, 0.2, 0.5, 1"
    return {"dofs": _dofs(oed.u, oed.p),
            "settings": {"cells": cells, "degree": 2, "steps_per_decade": per_decade,
                         "text": f"{cells} P2/P1 cells over {H:g} m, {per_decade} BDF2 steps "
                         "a decade"},
            "rows": [row(f"settlement, {where}", "Terzaghi (1923): series solution", s[ks],
                         s_exact[ks], "m", 7e-3, test, scale=final,
                         scale_name="the final settlement", at=f"T_v = {Tv[ks]:g}"),
                     row(f"excess pore pressure at the impervious base, {where}",
                         "Terzaghi (1923): series solution", p[kp],
                         p_exact[kp], "Pa", 1e-2, test, scale=q, scale_name="the load q",
                         at=f"T_v = {Tv[kp]:g}")]}


def rig_mandel() -> dict:
    """Mandel's cylinder as test_consolidation.py's test_mandel_cylinder: 16 x 16 P2/P1
    cells, 20 BDF2 steps a decade."""
    import numpy as np

    from tankfx.iterations.time_stepping import time_steps
    from tankfx.verification import reference as ref
    from tankfx.verification.rigs import MandelCylinder

    E, NU, K = BIOT["E"], BIOT["nu"], BIOT["k"]
    a, strain, cells, per_decade = 1.0, -1e-3, 16, 20
    c = ref.mandel_cylinder(E, NU, K, a, strain, [1.0])["c"]
    T = np.array([0.01, 0.05, 0.2, 0.5])
    times = T * a**2 / c
    exact = ref.mandel_cylinder(E, NU, K, a, strain, times, terms=200)
    rig = MandelCylinder(a, E, NU, K, strain, cells=cells)
    history = rig.run(time_steps(times, times[0] / 100, per_decade))
    t = np.array([h["t"] for h in history])
    at = [int(np.argmin(abs(t - ti))) for ti in times]
    centre = np.array([history[i]["centre_pressure"] for i in at])
    force = np.array([history[i]["force"] for i in at])
    kc = int(np.argmax(np.abs(centre - exact["centre"])))
    kf = int(np.argmax(np.abs(force - exact["force"])))
    test = "tests/test_consolidation.py::test_mandel_cylinder"
    name = "Mandel (1953): closed form, by Laplace transform"
    where = "largest error at c t / a^2 = 0.01, 0.05, 0.2, 0.5"
    return {"dofs": _dofs(rig.u, rig.p),
            "settings": {"cells": [cells, cells], "degree": 2, "steps_per_decade": per_decade,
                         "text": f"{cells} x {cells} P2/P1 cells, {per_decade} BDF2 steps a "
                         "decade"},
            "rows": [row(f"excess pore pressure at the centre, {where}", name, centre[kc],
                         exact["centre"][kc], "Pa", 5e-3, test, scale=exact["p0"],
                         scale_name="the initial pore pressure", at=f"c t / a^2 = {T[kc]:g}"),
                     row(f"axial force, {where}", name, force[kf], exact["force"][kf], "N",
                         3e-4, test, scale=exact["force"][0], scale_name="the initial force",
                         at=f"c t / a^2 = {T[kf]:g}")]}


# ------------------------------------------------------------------------------ cases
class Case:
    """A verification case: a scene (run by `tankfx run`) with ``rows`` of its results.json,
    or a ``rig`` run in a `--case NAME --json` child, which returns {"rows", "dofs",
    "settings"}. ``note``: what the page says of the case below the table; ``exits``: the
    exit codes of `tankfx run` it accepts."""

    def __init__(self, name: str, scene: Callable[[], dict] | None = None,
                 rows: Callable[[dict], list[dict]] | None = None,
                 rig: Callable[[], dict] | None = None, exits: tuple = (0,), note=None):
        self.name, self.scene, self.rows, self.rig = name, scene, rows, rig
        self.exits, self.note = exits, note


def _accuracy_scene(case: str) -> Callable[[], dict]:
    """The case of benchmarks/accuracy.py at its default (degree, level)."""
    def scene() -> dict:
        acc = accuracy()
        degree, level = next((d, lv) for d in (1, 2, 3) for lv in (-2, -1, 0, 1)
                             if acc.is_default(case, d, lv))
        return acc.scenes(degree, level)[case]
    return scene


#: its scene has a nominal 1 Pa besides the moment (benchmarks/accuracy.py's), so the
#: superposed results fall outside the model's range and `tankfx run` exits 4 (not valid)
ROCKING_NOTE = ("its scene carries a nominal 1 Pa besides the moment, so the superposed "
                "(axisymmetric plus first-harmonic) results are outside the model's range and "
                "`tankfx run` exits 4; the quantities compared are the first harmonic's alone, "
                "which is linear, as the test compares them")
CASES = [
    Case("flexible load", _accuracy_scene("flexible load"), rows_flexible),
    Case("rigid punch, smooth", _accuracy_scene("rigid punch, smooth"), rows_smooth_punch),
    Case("rigid punch, bonded", _accuracy_scene("rigid punch, bonded"), rows_bonded_punch),
    Case("rigid disc, rocking", _accuracy_scene("rigid disc, rocking"), rows_rocking,
         exits=(0, 4), note=ROCKING_NOTE),
    Case("layered ground", _accuracy_scene("layered ground"), rows_layered),
    Case("free raft, Kp = 0.1", _accuracy_scene("free raft, Kp = 0.1"), rows_raft(0.1)),
    Case("free raft, Kp = 10", _accuracy_scene("free raft, Kp = 10"), rows_raft(10.0)),
    Case("PLAXIS tank foundation box", scene_plaxis, rows_plaxis),
    Case("Gibson soil", scene_gibson, rows_gibson),
    Case("Terzaghi column", rig=rig_terzaghi),
    Case("Mandel cylinder", rig=rig_mandel),
    Case("clamped circular plate", rig=rig_plate),
    Case("wall clamped at its base, full of liquid", rig=rig_wall)]


def find(name: str) -> Case:
    return next(c for c in CASES if c.name == name)


def _slug(name: str) -> str:
    return "".join(ch if ch.isalnum() else "_" for ch in name).strip("_")


def _mesh_settings(mesh: dict) -> dict:
    text = f"P{mesh['degree']}, edge {mesh['edge_size']:g} m, near field {mesh['near_size']:g} m"
    if mesh.get("growth") is not None:
        text += f", growth {mesh['growth']:g}"
    return {**mesh, "text": text}


def measure(case: Case, workdir: Path) -> dict:
    """Run one case in a fresh process: {"rows", "dofs", "settings", "time_s"}."""
    if case.scene is not None:
        r = accuracy().run_case(case.scene(), workdir, _slug(case.name), case.exits)
        out = {"rows": case.rows(r), "dofs": int(r["dofs"]["total"]),
               "settings": _mesh_settings(r["scene"]["mesh"]), "time_s": r["process_s"]}
        if r["exit"] != 0:
            out["exit"] = r["exit"]
            out["validity"] = r["validity"]["notes"]
        return out
    t = time.perf_counter()
    proc = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--case", case.name,
                           "--json"], capture_output=True, text=True)
    wall = time.perf_counter() - t
    if proc.returncode != 0:
        raise RuntimeError(f"{case.name}: {proc.stderr[-2000:]}")
    line = next(ln for ln in reversed(proc.stdout.splitlines()) if ln.startswith(MARKER))
    return json.loads(line[len(MARKER):]) | {"time_s": wall}


def run_rig(name: str) -> dict:
    """A rig's rows in this process (what the --case --json child runs)."""
    import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)

    return find(name).rig()


# ---------------------------------------------------------------------- provenance
def provenance() -> dict:
    import tankfx

    def git(*args):
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True,
                              text=True).stdout.strip()

    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"date": datetime.date.today().isoformat(), "tankfx": tankfx.__version__,
            "commit": git("rev-parse", "--short", "HEAD") or "unknown",
            # uncommitted changes to the code that computes the results
            "uncommitted": bool(git("status", "--porcelain", "--", "tankfx", "benchmarks")),
            "machine": f"{model} ({os.cpu_count()} cores)"}


def records(case: Case, measured: dict, prov: dict) -> list[dict]:
    extra = {k: measured[k] for k in ("exit", "validity") if k in measured}
    if case.note:
        extra["note"] = case.note
    return [{"case": case.name, **{k: v for k, v in r.items() if k != "key"},
             "time_s": measured["time_s"], "dofs": measured["dofs"],
             "settings": measured["settings"], **extra, **prov} for r in measured["rows"]]


# -------------------------------------------------------------------------- the page
def _num(x: float, digits: int = 5) -> str:
    """x to ``digits`` significant digits; 1.2e-4, not 1.2e-04."""
    if x == 0:
        return "0"
    if 1e-3 <= abs(x) < 1e5:
        return f"{x:#.{digits}g}".rstrip(".")
    m, e = f"{x:.{digits - 1}e}".split("e")
    return f"{m}e{int(e)}"


def _err(x: float) -> str:
    m, e = f"{x:.1e}".split("e")
    return f"{m}e{int(e)}"


def _tol(r: dict) -> str:
    m, e = f"{r['tolerance']:.0e}".split("e")
    t = f"{m}e{int(e)}"
    return f"0 < e < {t}" if r["one_sided"] else f"\u00b1{t}"


def within(r: dict) -> bool:
    e, t = r["error"], r["tolerance"]
    return 0 < e < t if r["one_sided"] else abs(e) <= t


def _cell(text) -> str:
    return str(text).replace("|", "\\|")


def render(data: dict) -> str:
    recs = data["records"]
    dates = sorted({r["date"] for r in recs})
    date = dates[0] if len(dates) == 1 else f"{dates[0]} to {dates[-1]}"
    versions = ", ".join(sorted({r["tankfx"] for r in recs}))
    commits = ", ".join(sorted({r["commit"] + (" (with uncommitted changes to tankfx/ or "
                                               "benchmarks/)" if r["uncommitted"] else "")
                                for r in recs}))
    machines = "; ".join(sorted({r["machine"] for r in recs}))
    lines = [
        "# Verification", "",
        "Each row checks one computed quantity of a verification case against its reference "
        "(a closed form or a published value): the computed and reference values in SI "
        "units, the signed relative error, (computed - reference) / reference unless the "
        "quantity names another scale, and the tolerance the test suite asserts for it, in "
        "the test of the last column. Each case is one run in a fresh process: its time is "
        "that whole process's wall time (start-up, meshing, the disk-cached form "
        "compilation, the solve) and its unknowns are those of its solve, at the default "
        "mesh for the scenes of `benchmarks/accuracy.py` and at the settings shown for the "
        "others; both are on the case's first row.", "",
        f"Generated by `python docs/verification.py` (or `make verification`) from "
        f"`docs/verification/runs.json` on {date}, tankfx {versions}, commit {commits}, "
        f"on {machines}, one MPI rank. Do not edit this page by hand: re-run the command "
        "(`--only NAME` re-runs some cases, `--render` only re-renders the page).", "",
        "| case | quantity | reference | computed | reference value | error | tolerance "
        "| process time (s) | unknowns | settings | asserted in |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---|---|"]
    previous = None
    for r in recs:
        first = r["case"] != previous
        previous = r["case"]
        quantity = r["quantity"]
        if r.get("at"):
            quantity += f" ({r['at']})"
        if r.get("error_relative_to"):
            quantity += f"; error relative to {r['error_relative_to']}"
        error = _err(r["error"]) if within(r) else f"**{_err(r['error'])}** (beyond)"
        test_file, _, test_name = r["test"].partition("::")
        cells = [r["case"] if first else "", quantity, r["reference"],
                 f"{_num(r['value'])} {r['unit']}", f"{_num(r['reference_value'])} {r['unit']}",
                 error, _tol(r), f"{r['time_s']:.1f}" if first else "",
                 str(r["dofs"]) if first else "", r["settings"]["text"] if first else "",
                 f"`{Path(test_file).name}` `{test_name}`"]
        lines.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    notes = {}
    for r in recs:
        if r.get("note") or r.get("exit"):
            text = r.get("note", f"`tankfx run` exited {r['exit']}")
            if r.get("validity"):
                text += " (" + "; ".join(r["validity"]) + ")"
            notes[r["case"]] = text
    if notes:
        lines += [""] + [f"*{case}*: {text}." for case, text in notes.items()]
    total = sum({r["case"]: r["time_s"] for r in recs}.values())
    lines += ["", f"{len(recs)} quantities of {len({r['case'] for r in recs})} cases, "
              f"{total:.0f} s of runs in all. The tests that assert each case are those of the "
              "last column, in `tests/` (the file and the test function); the tolerances are "
              "theirs. Where a test solves a case at other settings than the row's (the "
              "rocking disc's test: a coarser mesh, 10 kPa of pressure), the tolerance is the "
              "one it asserts. `tests/test_verification_table.py` checks that this page is the "
              "rendering of `docs/verification/runs.json`, that every error is within its "
              "tolerance, and that the cheapest cases re-run to their recorded values.", ""]
    return "\n".join(lines)


def load() -> dict:
    return json.loads(RUNS.read_text()) if RUNS.exists() else {"records": []}


def write(data: dict) -> None:
    RUNS.parent.mkdir(parents=True, exist_ok=True)
    RUNS.write_text(json.dumps(data, indent=1) + "\n")
    PAGE.write_text(render(data))


# -------------------------------------------------------------------------- the command
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", nargs="+", metavar="NAME",
                    help="only the cases whose names contain one of these (merged into "
                    "runs.json)")
    ap.add_argument("--render", action="store_true",
                    help="only render docs/verification.md from docs/verification/runs.json")
    ap.add_argument("--case", help="(internal) run one rig case in this process")
    ap.add_argument("--json", action="store_true", help="(internal) with --case: print JSON")
    ap.add_argument("--list", action="store_true", help="list the cases")
    args = ap.parse_args(argv)
    if args.list:
        for c in CASES:
            print(c.name)
        return 0
    if args.case:
        out = run_rig(args.case)
        print((MARKER if args.json else "") + json.dumps(out))
        return 0
    if args.render:
        PAGE.write_text(render(load()))
        print(f"verification: {PAGE.relative_to(ROOT)} rendered from "
              f"{RUNS.relative_to(ROOT)}")
        return 0
    wanted = [c for c in CASES if not args.only or any(w in c.name for w in args.only)]
    if not wanted:
        print(f"verification: no case matches {args.only}", file=sys.stderr)
        return 2
    prov = provenance()
    new, start = {}, time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for k, case in enumerate(wanted, 1):
            print(f"[{k}/{len(wanted)}] {case.name} ...", end=" ", flush=True)
            m = measure(case, Path(tmp))
            new[case.name] = records(case, m, prov)
            worst = max(m["rows"], key=lambda r: abs(r["error"]) / r["tolerance"])
            print(f"{m['time_s']:.1f} s, {m['dofs']} unknowns, largest error "
                  f"{_err(worst['error'])} ({worst['quantity'].split(',')[0]}, tolerance "
                  f"{_tol(worst)})", flush=True)
    old: dict[str, list] = {}
    for r in load()["records"] if args.only else []:      # --only: merged into the records
        old.setdefault(r["case"], []).append(r)
    merged = old | new
    data = {"records": [r for c in CASES if c.name in merged for r in merged[c.name]]}
    write(data)
    beyond = [r for recs in new.values() for r in recs if not within(r)]
    print(f"verification: {len(wanted)} case(s) in {time.perf_counter() - start:.0f} s; "
          f"{RUNS.relative_to(ROOT)} and {PAGE.relative_to(ROOT)} written")
    for r in beyond:
        print(f"verification: {r['case']}, {r['quantity']}: error {_err(r['error'])} beyond "
              f"{_tol(r)}", file=sys.stderr)
    return 1 if beyond else 0


if __name__ == "__main__":
    sys.exit(main())
