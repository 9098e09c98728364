"""Error against run time for every soil-coupled verification case of the test suite, over
mesh levels and element degrees: a table, a log-log chart (error against whole-process wall
time and against dofs), and whether the defaults sit on the efficient front.

    python benchmarks/accuracy.py [--quick] [--only CASE ...] [--out results/benchmarks]

Cases (references as in tests/): the flexible load (Boussinesq: w0, w_edge, sigma_zz on the
axis), the rigid smooth punch (w0: Boussinesq; M0: the rigid plate's closed form,
tankfx.verification.reference.rigid_plate_centre_moment) and rigid bonded punch (w0:
Mossakovskii-Spence;
M0: its own finest solution), the free raft at Kp = 0.1 and 10 (Brown 1969: w0, wd, M0), the
flexible load on layered ground (three layers on a rigid base, the middle one undrained: w0 and
w_edge against Burmister's solution, tankfx.verification.reference.layered_surface_settlement), and
the rocking rigid disc (the first harmonic: its rocking stiffness against Borowicka's, and
its element-averaged contact pressure for 0.1 a < r < 0.9 a),
the nonlinear embedded tank of `make demo` (hyperbolic soil, Mohr-Coulomb interface) against
its own finest solution (P3, level 1: ``SELF_REFERENCE``). The plate and wall elements
alone are in benchmarks/structure.py (their cost is negligible beside the soil's).

Level 0 is the default mesh (edge_size 0.002 a, near_size 0.1 a); each level up halves both
sizes, each level down doubles them. Each run is a fresh process (`python -m tankfx run`), so
the time includes start-up, meshing and the (disk-cached) form compilation. The error of a
run is the largest relative error of its case's quantities. A configuration is on the
efficient front of its case when no other is both faster and more accurate.
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
P, A, E, NU = 100e3, 1.0, 10e6, 0.3
MOMENT = 1e5          #: N m, on the rocking disc
BROWN = {0.1: (1.954, 0.5572, 0.01462), 10.0: (1.588, 0.02378, 0.0747)}
#: Layered ground on a rigid base 4 a down: (thickness, E, nu) top down, as in tests/
LAYERS = [(0.5, E, NU), (1.5, 2e6, 0.5), (2.0, 30e6, 0.25)]
#: The (degree, level) of the finest solution that serves as the reference where there is no
#: closed form, and the quantities it is the reference of.
SELF_REFERENCE = (3, 1)
SELF_REFERENCED = {"rigid punch, bonded": ("M0",), "nonlinear embedded tank": ("w0", "wd", "M0")}


def _soil(degree, level, a=A):
    f = 2.0 ** (-level)
    return {"degree": degree, "edge_size": min(0.002 * f, 0.25) * a,
            "near_size": min(0.1 * f, 0.5) * a}


def is_default(case: str, degree: int, level: int) -> bool:
    """What a scene gets without [mesh] keys: P3 on a mesh twice as coarse (level -1) for the
    flexible load, P2 at level 0 under a plate."""
    from tankfx.scene.sections import FLEXIBLE_COARSENING, FLEXIBLE_DEGREE

    if case in ("flexible load", "layered ground"):
        return (degree, level) == (FLEXIBLE_DEGREE, -round(math.log2(FLEXIBLE_COARSENING)))
    return (degree, level) == (2, 0)


def scenes(degree: int, level: int) -> dict[str, dict]:
    """Every case as a scene dict at one (degree, level)."""
    mesh = _soil(degree, level)
    soil = {"E": E, "nu": NU}
    plate = {"radius": A, "E": 30e9, "nu": 0.3}
    out = {"flexible load": {"soil": soil, "load": {"pressure": P, "load_radius": A},
                             "mesh": mesh},
           "rigid punch, smooth": {"soil": soil, "plate": plate | {"Kp": 1e3},
                                   "interface": {"condition": "smooth"},
                                   "load": {"pressure": P}, "mesh": mesh},
           "rigid punch, bonded": {"soil": soil, "plate": plate | {"Kp": 1e3},
                                   "interface": {"condition": "bonded"},
                                   "load": {"pressure": P}, "mesh": mesh},
           # the first harmonic: a moment on the smooth rigid punch (no pressure: 1 Pa)
           "rigid disc, rocking": {"soil": soil, "plate": plate | {"Kp": 1e3},
                                   "interface": {"condition": "smooth"},
                                   "load": {"pressure": 1.0, "overturning_moment": MOMENT},
                                   "mesh": mesh}}
    tops = np.cumsum([0.0] + [h for h, _, _ in LAYERS])
    if degree > 1:      # its undrained layer's mixed form needs P2 or P3
        out["layered ground"] = {
            "soil": {"E": LAYERS[0][1], "nu": LAYERS[0][2],
                     "layers": [{"depth": float(d), "E": Es, "nu": nus}
                                for d, (_, Es, nus) in zip(tops[1:-1], LAYERS[1:])]},
            "load": {"pressure": P, "load_radius": A}, "domain": {"depth": float(tops[-1])},
            "mesh": mesh}
    for Kp in BROWN:
        out[f"free raft, Kp = {Kp:g}"] = {"soil": soil, "plate": plate | {"Kp": Kp},
                                          "interface": {"condition": "smooth"},
                                          "load": {"pressure": P}, "mesh": mesh}
    import tomllib

    tank = tomllib.loads((ROOT / "demos" / "scenes" / "embedded_tank_nonlinear.toml")
                         .read_text())
    tank["mesh"] = _soil(degree, level, tank["plate"]["radius"])
    out["nonlinear embedded tank"] = tank
    return out


def errors(case: str, r: dict, reference: dict | None) -> dict:
    from tankfx.verification import reference as ref

    if case == "flexible load":
        z = np.array(r["profiles"]["axis"]["z"])
        s = np.array(r["profiles"]["axis"]["sigma_zz"])
        win = (z >= 0.25 * A) & (z <= 5 * A)
        return {"w0": r["w0"] / ref.flexible_centre_settlement(P, A, E, NU) - 1,
                "w_edge": r["w_edge"] / ref.flexible_edge_settlement(P, A, E, NU) - 1,
                "sigma_zz": float(np.max(np.abs(s[win] / ref.flexible_axis_stress(
                    P, A, z[win]) - 1)))}
    if case == "layered ground":
        w0, w_edge = ref.layered_surface_settlement(P, A, [0.0, A], LAYERS, None)
        return {"w0": r["w0"] / w0 - 1, "w_edge": r["w_edge"] / w_edge - 1}
    force = P * math.pi * A**2
    if case == "rigid disc, rocking":
        o = r["overturning"]
        x, c = o["profiles"]["plate"]["r"], o["profiles"]["plate"]["contact_normal"]
        # element averages (every second station a midpoint): against the reference's
        # average over the element's ring
        contact = [c[i] / ref.ring_average(lambda s: ref.rigid_disc_rocking_pressure(
            MOMENT, A, s), x[i - 1], x[i + 1]) - 1 for i in range(1, len(x) - 1, 2)
            if 0.1 * A < x[i] < 0.9 * A]
        return {"rocking": o["rocking_stiffness"] / ref.rigid_disc_rocking_stiffness(E, NU, A)
                - 1, "contact": max(contact, key=abs)}
    if case == "rigid punch, smooth":
        return {"w0": r["w0"] / (force * (1 - NU**2) / (2 * A * E)) - 1,
                "M0": r["M0"] / ref.rigid_plate_centre_moment(P, A, NU) - 1}
    if case == "rigid punch, bonded":
        G = E / (2 * (1 + NU))
        return {"w0": r["w0"] / (force / (4 * G * A * math.log(3 - 4 * NU) /
                                           (1 - 2 * NU))) - 1,
                "M0": r["M0"] / reference["M0"] - 1}
    if case.startswith("free raft"):
        w0, wd, M0 = BROWN[float(case.split("= ")[1])]
        scale = P * A * (1 - NU**2) / E
        return {"w0": r["w0"] / scale / w0 - 1, "wd": r["wd"] / scale / wd - 1,
                "M0": r["M0"] / (P * A**2) / M0 - 1}
    return {k: r[k] / reference[k] - 1 for k in ("w0", "wd", "M0")}


def run_case(scene: dict, workdir: Path, name: str, exits: tuple = (0, 4)) -> dict:
    """One case as a fresh `tankfx run`: its results.json with the whole process's time
    ("process_s") and its exit code ("exit"). Exit 4 (it ran, but a part lies outside its
    model's range) is accepted by default: the rocking disc's nominal 1 Pa lets its heel
    lift, which does not touch the first harmonic it is measured on."""
    from tankfx import Scene

    path = workdir / f"{name}.toml"
    path.write_text(Scene.from_dict(scene).to_toml())
    out = workdir / name
    t = time.perf_counter()
    # the analysis alone: the figures and fields a run writes by default are not its cost
    proc = subprocess.run([sys.executable, "-m", "tankfx", "run", str(path), "--out", str(out),
                           "--force", "--no-figures", "--no-fields"], capture_output=True,
                          text=True)
    wall = time.perf_counter() - t
    if proc.returncode not in exits:
        raise RuntimeError(f"{name}: exit {proc.returncode}: {proc.stderr[-2000:]}")
    r = json.loads((out / "results.json").read_text())
    r["process_s"], r["exit"] = wall, proc.returncode
    return r


#: Whole-process times on the project machine repeat within about +-10 %
#: (docs/performance.md, "Where the time goes"): a difference below that is not a measured
#: difference.
TIME_NOISE = 0.1


def beats(o: dict, row: dict) -> bool:
    """Whether run ``o`` is measurably better than ``row``: faster by more than the timing
    noise and more accurate, or as fast within the noise and at least twice as accurate."""
    faster = o["process_s"] < row["process_s"] * (1 - TIME_NOISE)
    as_fast = o["process_s"] < row["process_s"] * (1 + TIME_NOISE)
    return (faster and o["error"] < row["error"]) or (as_fast and o["error"] < row["error"] / 2)


def front(rows: list[dict]) -> None:
    """Mark, per case, the configurations no other measurably beats (:func:`beats`); a
    self-referenced case's reference configuration itself is left out."""
    rows[:] = [r for r in rows if not r.get("is_reference")]
    for row in rows:
        row["on_front"] = not any(o is not row and o["case"] == row["case"] and beats(o, row)
                                  for o in rows)


def chart(rows: list[dict], path: Path) -> None:
    from tankfx.results.figures import offscreen_pyvista, save_figure

    pv = offscreen_pyvista()
    cases = list(dict.fromkeys(r["case"] for r in rows))
    colors = {1: "tab:orange", 2: "tab:blue", 3: "tab:green"}
    p = pv.Plotter(off_screen=True, window_size=(700 * 3, 450 * math.ceil(len(cases) / 3)),
                   shape=(math.ceil(len(cases) / 3), 3))
    for k, case in enumerate(cases):
        c = pv.Chart2D(x_label="log10 whole-process time [s]",
                       y_label="log10 relative error")
        c.title = case
        for deg, color in colors.items():
            pts = sorted((r["process_s"], max(r["error"], 1e-7)) for r in rows
                         if r["case"] == case and r["degree"] == deg)
            if pts:
                x, y = np.log10(np.array(pts)).T
                c.line(x, y, color=color, width=2, label=f"P{deg}")
                c.scatter(x, y, color=color, size=8)
        d = [r for r in rows if r["case"] == case and r["default"]]
        if d:
            c.scatter(np.log10([d[0]["process_s"]]), np.log10([max(d[0]["error"], 1e-7)]),
                      color="black", size=16, style="d", label="default")
        p.subplot(k // 3, k % 3)
        p.add_chart(c)
    save_figure(p, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="levels -1, 0 and P2, P3 only")
    ap.add_argument("--only", nargs="+", metavar="CASE",
                    help="only the cases whose names contain one of these (e.g. layered)")
    ap.add_argument("--out", default="results/benchmarks")
    ap.add_argument("--replot", action="store_true",
                    help="only redraw the chart from OUT/accuracy.json")
    args = ap.parse_args()
    if args.replot:
        rows = json.loads((Path(args.out) / "accuracy.json").read_text())
        for row in rows:
            row["default"] = is_default(row["case"], row["degree"], row["level"])
        report(rows)
        chart(rows, Path(args.out) / "accuracy.png")
        return
    degrees = (2, 3) if args.quick else (1, 2, 3)
    levels = (-1, 0) if args.quick else (-2, -1, 0, 1)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        # the references of the cases without a closed form: their finest solutions
        references = {}
        wanted = [c for c in scenes(2, 0)
                  if not args.only or any(w in c for w in args.only)]
        for case in [c for c in SELF_REFERENCED if c in wanted]:
            print(f"reference for the {case}: P{SELF_REFERENCE[0]}, level "
                  f"{SELF_REFERENCE[1]} ...", flush=True)
            references[case] = run_case(scenes(*SELF_REFERENCE)[case], tmp,
                                        f"reference_{len(references)}")
        run_case(scenes(2, 0)["flexible load"], tmp, "warm-up")      # JIT caches warm
        print(f"{'case':26s} {'P':>2s} {'lvl':>3s} {'dofs':>8s} {'time s':>7s} "
              f"{'error':>9s}  worst quantity")
        for degree in degrees:
            for level in levels:
                for case, scene in scenes(degree, level).items():
                    if case not in wanted:
                        continue
                    name = f"p{degree}_l{level}_{len(rows)}"
                    r = run_case(scene, tmp, name)
                    err = errors(case, r, references.get(case))
                    worst = max(err, key=lambda k: abs(err[k]))
                    row = {"case": case, "degree": degree, "level": level,
                           "dofs": r["dofs"]["total"], "process_s": r["process_s"],
                           "error": abs(err[worst]), "worst": worst, "errors": err,
                           "default": is_default(case, degree, level),
                           "is_reference": case in SELF_REFERENCED
                           and (degree, level) == SELF_REFERENCE}
                    rows.append(row)
                    print(f"{case:26s} {degree:2d} {level:3d} {row['dofs']:8d} "
                          f"{row['process_s']:7.2f} {row['error']:9.2e}  {worst}", flush=True)
    report(rows)
    (out / "accuracy.json").write_text(json.dumps(rows, indent=1))
    chart(rows, out / "accuracy.png")
    print(f"\ntable: {out / 'accuracy.json'}; chart: {out / 'accuracy.png'}")


def report(rows):
    front(rows)
    print("\nDefaults (P3 level -1 for the flexible load, P2 level 0 under a plate) against "
          "the efficient front:")
    for row in rows:
        if row["default"]:
            better = [o for o in rows if o["case"] == row["case"] and o["on_front"]
                      and o["process_s"] <= 1.5 * row["process_s"]
                      and o["error"] < row["error"]]
            note = "on the front" if row["on_front"] else "NOT on the front"
            if better:
                b = min(better, key=lambda o: o["error"])
                note += (f"; P{b['degree']} level {b['level']} is more accurate "
                         f"({b['error']:.1e}) at {b['process_s']:.1f} s")
            print(f"  {row['case']:26s} error {row['error']:.1e} in {row['process_s']:.1f} s: "
                  f"{note}")


if __name__ == "__main__":
    main()
