# %% [markdown]
# # How fast may a tank on soft clay be filled? The safe hydrotest schedule
#
# A new tank is hydrotested: filled with water, watched, emptied. On soft clay the water
# is the largest load the ground will ever see, and it comes fast: the clay answers
# undrained while the water rises, with the strength it has now. Held at a level, the clay
# drains under the tank, its effective stress grows, and so does its undrained strength:
# the next step is carried with more margin. Engineers plan the test as fill steps and
# holds (Duncan & D'Orazio 1984; the Fredrikstad tank failed at its edge during its test,
# Bjerrum & Overland). The question is the schedule: how long to hold before each step?
#
# tankfx answers it with `[fill]` (docs/guide/consolidation.md, "The safe fill"): the clay
# is Modified Cam Clay, its undrained strength an outcome of its effective stress and its
# history, the pore pressure coupled to the skeleton (Biot). First the tank is filled at
# the rate with no hold, the factor of safety on the strength searched at each step's end
# (the pore water held: a failure is sudden). Where a step's factor falls short of the
# target, the schedule holds the level before it just long enough (to half a day) that it
# does not.
#
# Run: `python demos/hydrotest_schedule.py`; `--coarse` for a quick look at the method on
# a small tank (about a minute). Results and figures go to
# `results/hydrotest_schedule/`.

# %%
import sys
import time
from pathlib import Path

from mpi4py import MPI

from tankfx import Scene, analyse, load_scene, write_json
from tankfx.cli import setup_logging
from tankfx.iterations.fill_schedule import FACTOR_BRACKET, HOLD_RESOLUTION
from tankfx.results.figures import write_figures

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "hydrotest_schedule"
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## The tank and the clay
# `benchmarks/scenes/hydrotest_schedule.toml`: a 25 m welded steel tank (8 mm floor, 16 mm
# shell, its own weight on) on 15 m of normally consolidated soft clay with a dried crust
# (POP = 25 kPa) over dense sand, the water table 1 m down, vertical drains giving the clay
# an equivalent permeability of 3e-7 m/s, drained at the surface and at the sand; the shell
# on a crushed-stone ringwall 1.2 m wide and 1 m deep. Filled to 9 m of water in 3 m steps
# at 1.8 m a day: 5 days without a hold. The schedule is searched on the coarse mesh (edge
# 0.01 a, near field 0.25 a): every hold tried is a consolidation and every check a search
# by strength. About 5 minutes.

# %%
# (the scene lives with the benchmarks: its schedule is a long search, too long for the
# regression test that runs every scene of demos/scenes)
scene = load_scene(Path(__file__).resolve().parents[1] / "benchmarks" / "scenes" /
                   "hydrotest_schedule.toml").with_coarse_mesh()
if "--coarse" in sys.argv:
    # a quick look at the method (about a minute, for the test suite): a rigid 2 m tank on
    # a frictional clay (c' = 10 kPa, phi' = 20 deg, a^2 / c_v = 0.1 day) filled to 8 m in
    # two steps at 80 m/day, target 1.22: the scene of tests/test_fill_schedule.py
    scene = Scene.from_dict({
        "title": "2 m tank on a frictional clay: the safe fill (quick look)",
        "soil": {"model": "mohr_coulomb", "E": 10e6, "nu": 0.3, "cohesion": 10e3,
                 "friction_angle": 20.0},
        "plate": {"radius": 1.0, "Kp": 1000.0, "E": 30e9, "nu": 0.2},
        "wall": {"radius": 1.0, "height": 20.0, "thickness": 0.05, "E": 30e9, "nu": 0.2},
        "interface": {"condition": "bonded"}, "load": {"liquid_unit_weight": 9810.0},
        "mesh": {"edge_size": 0.05, "near_size": 0.5, "growth": 0.3},
        "domain": {"radius": 5.0, "depth": 5.0},
        "consolidation": {"permeability": 8.43e-8, "steps_per_decade": 4,
                          "piezometers": [[0.0, 0.5]]},
        "fill": {"height": 8.0, "step": 4.0, "rate": 80.0, "target_factor": 1.22}})
comm.barrier()
# (progress: a line per time step, per hold tried and per trial of a search)
setup_logging(out, comm.rank)
t0 = time.perf_counter()
solution = analyse(scene, comm)
elapsed = time.perf_counter() - t0
r = solution.results
f = r["fill"]

# %% [markdown]
# ## Filled in 5 days, with no hold
# The factor of safety at each step's end, and the settlements there.

# %%
say(f"{scene.title}: to {f['height']:g} m of water in {f['step']:g} m steps at "
    f"{f['rate']:g} m/day, target factor of safety {f['target_factor']:g}\n")
say("filled with no hold:")
say(f"{'height m':>9s} {'day':>6s} {'factor':>7s}")
for u in f["unheld"]:
    say(f"{u['height']:9.3g} {u['day']:6.3g} {u['strength_factor']:7.3g}"
        + ("  the ground fails here" if u["fails"] else ""))
say(f"the least factor of safety {f['unheld_factor']:.3g} at {f['unheld_height']:.3g} m"
    + (" (the ground fails)" if f["unheld_fails"] else ""))

# %% [markdown]
# ## The safe schedule
# Each step: the hold before it, its filling days, its factor of safety at the end, the
# settlement of the centre and the edge, and the holds tried to find it.

# %%
say(f"\nthe safe schedule ({'complete' if f['complete'] else 'stopped: ' + f['reason']}):")
say(f"{'step':>4s} {'to m':>5s} {'hold d':>7s} {'fills from':>10s} {'to day':>7s} "
    f"{'factor':>7s} {'w0 mm':>7s} {'w_edge':>7s}  holds tried")
for k, s in enumerate(f["schedule"], start=1):
    # (each hold tried: + passed, - failed, and the factor its check found)
    tried = ", ".join(f"{h['hold_days']:g}{'+' if h['passed'] else '-'}"
                      + (f" ({h['strength_factor']:.3g})" if h["strength_factor"] else "")
                      for h in s["holds_tried"]) or "none"
    say(f"{k:4d} {s['height']:5.3g} {s['hold_days']:7.3g} {s['fill_start_day']:10.4g} "
        f"{s['fill_end_day']:7.4g} {s['strength_factor']:7.3g} {1e3 * s['w0']:7.1f} "
        f"{1e3 * s['w_edge']:7.1f}  {tried}")
say(f"total: {f['total_days']:.4g} days to {f['reached_height']:.3g} m "
    f"({f['checks']} checks, {f['fills_tried']} fills tried, {f['newton_iterations']} Newton "
    f"iterations; {elapsed:.0f} s)")
if not r["validity"]["valid"]:
    # (the floor's slope where the clay under it settles past the ringwall: said, not hidden)
    say("outside the model's range at the end: " + "; ".join(r["validity"]["notes"]))
s_u = r["soil"].get("undrained_strength", {})
if s_u.get("points"):
    say(f"undrained strength where the clay yields at the end: {s_u['min'] / 1e3:.3g} to "
        f"{s_u['max'] / 1e3:.3g} kPa (mean {s_u['mean'] / 1e3:.3g})")

# %% [markdown]
# ## Figures
# `fill.png`: the liquid's height and the factor of safety against days, the schedule
# beside the fill with no hold. `consolidation.png`: the settlement of the centre and the
# edge with the liquid's height, the excess pore pressure at the piezometers (under the
# centre and under the shell, 5 m deep), the factor of safety at each step's end.

# %%
figures = write_figures(solution, out)
if comm.rank == 0:
    write_json(out / "results.json", r)
say(f"figures and results.json in {out}/")

# %% [markdown]
# ## Checks
# Filled with no hold, a step falls short of the target; the schedule holds before it and
# every step of it reaches the target (to its 2 % bracket); a hold raised the factor at its
# step's height above the no-hold one (the clay drained and grew stronger); the hold is the
# shortest to half a day (a hold half a day shorter failed its check); the days add up.

# %%
target = f["target_factor"]
assert f["unheld_factor"] < target
assert f["complete"] and f["total_days"] > f["height"] / f["rate"]
unheld = {u["height"]: u["strength_factor"] for u in f["unheld"]}
for s in f["schedule"]:
    assert s["strength_factor"] >= target * (1.0 - FACTOR_BRACKET)
    if s["hold_days"] > 0.0:
        assert s["strength_factor"] > unheld.get(s["height"], 1.0)
        failed = [h["hold_days"] for h in s["holds_tried"] if not h["passed"]] + [0.0]
        assert s["hold_days"] - max(failed) <= HOLD_RESOLUTION * (1 + 1e-9)
    assert abs(s["fill_end_day"] - s["fill_start_day"] - f["step"] / f["rate"]) < 1e-9 \
        or s["height"] == f["height"]
assert any(s["hold_days"] > 0.0 for s in f["schedule"])
assert r["equilibrium"]["relative_error"] < 1e-6

# %% [markdown]
# ## What it shows
#
# The 25 m tank (about 2 minutes on this project's 2-core machine, one process): filled
# with no hold in 5 days, the factors of safety at the steps' ends are 3.1 (3 m), 1.77
# (6 m) and 1.28 (9 m), short of 1.3 at the last step. Held at 6 m, the clay under the
# tank drains: holds of 1 and half a day carry 1.3 at the last step. The safe schedule
# holds half a day at 6 m and is full on day 5.5 instead of 5; the centre has settled
# 0.32 m and the edge 0.17 m, the piezometer under the centre reads 71 kPa of excess pore
# pressure. (The factors are searched to 2 %, and 1.28 lies within that of 1.3: the hold is
# decided to that precision. With Newton's time steps accepted before they were solved,
# as before 2026-12-01, the holds needed read 3 days.) The undrained strength where the clay yields is an outcome: 16 kPa on
# average. The floor is 0.40 m down at r = 10 m and 0.17 m on the ringwall: its slope
# there reaches 0.15 rad, beyond small rotations, and tankfx says so (the results are
# marked not valid at the end; a tank's edge settlement is checked as API 653's Annex B
# does, not with a plate of small rotations). The factors of safety are the clay's
# mechanism, under and beyond the ring. With `--coarse` (the 2 m tank, about a minute): with no hold the second step's
# factor is 1.21 against 1.22; held half a day at 4 m it reaches 1.22-1.25.
