# %% [markdown]
# # A tank on soft clay: settlement now, and over the months after the hydrotest
#
# A tank on saturated clay settles twice. When it is filled the water in the clay's pores
# cannot leave at once: the clay deforms at constant volume (undrained), and the load is
# carried partly by an *excess pore pressure*. Over the following months that pressure
# drains away, to the ground surface and to any sand beneath, and the clay's skeleton takes
# the load: the settlement grows to the drained one. Which share of the final settlement,
# and of the differential settlement and the plate's moments, comes at once, and how soon
# the rest follows, decides how a hydrotest is held and when the tank may be put into
# service.
#
# tankfx solves Biot's consolidation (`[consolidation]` in a scene: the clay's permeability
# and the times to report) on the same axisymmetric mesh as the tank's other analyses: the
# undrained response at t = 0, time steps of BDF2, and the drained limit. Its forms are
# verified against Terzaghi's column and its limits against the undrained (nu = 0.5) and
# drained analyses of the same tank (tests/test_consolidation.py).
#
# Run: `python demos/tank_on_clay.py` (or under `mpiexec -n 2`); `--coarse` for a quick
# run. Results and figures go to `results/tank_on_clay/`.

# %%
import sys
from pathlib import Path

from mpi4py import MPI

from tankfx import analyse, load_scene, write_json
from tankfx.verification import reference as ref
from tankfx.results.figures import plot_consolidation, plot_isochrones, plot_section
from tankfx.results.fields import write_profiles

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "tank_on_clay"
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## The tank and the clay
# `demos/scenes/tank_on_clay.toml`: a 30 m concrete tank filled with 10 m of water, on
# 10 m of soft clay (drained E' = 5 MPa, nu' = 0.3, k = 1e-9 m/s) over sand, which drains
# it from below as the ground surface does from above.

# %%
scene = load_scene(Path(__file__).resolve().parent / "scenes" / "tank_on_clay.toml")
if "--coarse" in sys.argv:
    # a quick look: the coarse mesh and half the time steps (5 a decade)
    scene = scene.with_coarse_mesh().with_changes(consolidation={"steps_per_decade": 5})
c = scene.consolidation
solution = analyse(scene, comm)
r = solution.results
cons = r["consolidation"]
DAY = 86400.0

# %% [markdown]
# ## Settlement against time
# The clay's coefficient of consolidation c_v = k E_oed / gamma_w sets the pace. Terzaghi's
# one-dimensional theory gives the classical estimates, and here two bounds: the concrete
# plate is impervious, so the clay under it drains only downwards, a drainage path of the
# whole 10 m; beyond the tank's edge it drains both ways, 5 m. The tank's degree of
# consolidation (its settlement's progress from the undrained start to the drained limit)
# lies between the two: the pore water under the plate also leaves sideways.

# %%
H = scene.domain.depth
say(f"{scene.title}: c_v = {cons['c_v']:.3g} m^2/s; undrained w0 = "
    f"{1e3 * cons['undrained']['w0']:.1f} mm, drained limit "
    f"{1e3 * cons['drained']['w0']:.1f} mm "
    f"({cons['undrained']['w0'] / cons['drained']['w0']:.0%} at once)\n")
say(f"{'t days':>8s} {'w0 mm':>8s} {'wd mm':>7s} {'M0 kNm/m':>9s} {'U tank':>7s} "
    f"{'U 1D 10 m':>9s} {'U 1D 5 m':>9s} {'u_e kPa':>8s}")
bounds = []
for s in cons["at_times"]:
    U_slow, U_fast = (ref.terzaghi_degree(cons["c_v"] * s["t"] / H_dr**2)[0]
                      if s["t"] > 0 else 0.0 for H_dr in (H, 0.5 * H))
    bounds.append((U_slow, s["degree"], U_fast))
    say(f"{s['t_days']:8.4g} {1e3 * s['w0']:8.2f} {1e3 * s['wd']:7.2f} {s['M0'] / 1e3:9.2f} "
        f"{s['degree']:7.3f} {U_slow:9.3f} {U_fast:9.3f} {s['axis_pore_pressure'] / 1e3:8.1f}")
d = cons["drained"]
say(f"{'drained':>8s} {1e3 * d['w0']:8.2f} {1e3 * d['wd']:7.2f} {d['M0'] / 1e3:9.2f} "
    f"{1.0:7.3f} {1.0:9.3f} {1.0:9.3f} {0.0:8.1f}\n")
say(f"(u_e: the excess pore pressure on the axis, {cons['axis_depth']:.3g} m below the plate)")
# The plate's centre moment changes sign: hogging at once (the undrained clay is stiff
# under the plate's middle against its edge, where the wall's weight and the water's
# thrust meet), sagging as the clay under the middle consolidates.

# %% [markdown]
# ## Figures
# The settlements, the plate's centre moment and the largest excess pore pressure against
# time (log scale), between the undrained start and the drained limit; the isochrones (the
# excess pore pressure down the axis at each reported time: the clay drains to the sand at
# 10 m as well as upwards); and the section at the last reported time, coloured by the
# excess pore pressure that is still to drain.

# %%
if comm.rank == 0:
    write_json(out / "results.json", r)
    write_profiles(r, out)
plot_consolidation(r, out / "consolidation.png", title=scene.title)
plot_isochrones(r, out / "isochrones.png", title=scene.title)
pore = solution.model.soil.pore_pressure
plot_section(solution.u, pore, out / "pore_pressure.png", extent=1.6 * scene.plate.radius,
             label="pore pressure [kPa]", soil_cells=solution.domain.cells("soil"),
             structure=r, title=f"{scene.title}: t = {c.times[-1] / DAY:.4g} days")
say(f"figures and results.json in {out}/")

# %% [markdown]
# ## The hydrotest: filled over ten days, held, emptied
# A tank is not filled at once: a hydrotest fills it at about a metre a day, holds it full
# while the settlement is watched, and empties it. As a load path in time, each stage the
# [load] keys that change and the time its load is reached (linearly from the stage
# before): full on day 10, still full on day 60, empty on day 65. The clay consolidates
# while the tank fills, so the settlement at day 10 lies above the undrained response to
# the full tank; emptied, the clay swells back only as its pore water returns: the
# settlement recovered at once is the undrained response, the rest comes over years.

# %%
day = 86400.0
hydrotest = scene.with_changes(
    stages=[{"liquid_height": 10.0, "time": 10 * day},
            {"liquid_height": 10.0, "time": 60 * day},
            {"liquid_height": 0.0, "time": 65 * day}],
    consolidation={"times": [d * day for d in (5, 10, 30, 60, 65, 365, 1095)]})
path = analyse(hydrotest, comm).results
hc = path["consolidation"]
say(f"\nhydrotest: {'t days':>8s} {'load MN':>8s} {'w0 mm':>8s} {'wd mm':>7s} "
    f"{'u_e kPa':>8s}")
for s in hc["at_times"]:
    say(f"           {s['t_days']:8.4g} {s['applied_load'] / 1e6:8.2f} {1e3 * s['w0']:8.2f} "
        f"{1e3 * s['wd']:7.2f} {s['axis_pore_pressure'] / 1e3:8.1f}")
full, emptied = hc["at_stages"][1], hc["at_stages"][2]
say(f"held full 50 days: w0 {1e3 * hc['at_stages'][0]['w0']:.1f} -> {1e3 * full['w0']:.1f} mm; "
    f"emptied: {1e3 * emptied['w0']:.1f} mm left, {1e3 * hc['at_times'][-1]['w0']:.1f} mm "
    f"after three years")
plot_consolidation(path, out / "hydrotest.png", title=f"{scene.title}: hydrotest")

# %% [markdown]
# ## Checks
# The drained limit settles more than the undrained start, the consolidation rises
# monotonically towards it between Terzaghi's two bounds, the excess pore pressure falls,
# and the tank balances its load.

# %%
U = [s["degree"] for s in cons["at_times"]]
assert cons["drained"]["w0"] > cons["undrained"]["w0"] > 0
assert all(b > a for a, b in zip(U, U[1:])) and U[-1] < 1.0
assert all(slow < tank < fast for slow, tank, fast in bounds[1:]), bounds
u_e = [s["axis_pore_pressure"] for s in cons["at_times"]]
assert all(b < a for a, b in zip(u_e, u_e[1:])) and abs(cons["drained"]["axis_pore_pressure"]) \
    < 1e-6 * u_e[0]
assert r["equilibrium"]["relative_error"] < 1e-8
# the hydrotest: filled over ten days, it settles more by day 10 than the full tank does at
# once, and less than the full tank after ten days; it keeps settling while held full;
# emptied, it rebounds, then swells back towards nothing (its drained limit: no load)
at_once = {round(s["t_days"], 6): s["w0"] for s in cons["history"]}
w10 = hc["at_stages"][0]["w0"]
assert cons["undrained"]["w0"] < w10 < min(w for t, w in at_once.items() if t >= 10.0)
assert full["w0"] > w10 and emptied["w0"] < full["w0"]
assert 0 < hc["at_times"][-1]["w0"] < emptied["w0"] and abs(hc["drained"]["w0"]) < 1e-12
assert path["equilibrium"]["relative_error"] < 1e-8

# %% [markdown]
# ## What it shows
#
# On soft clay (`demos/tank_on_clay.py`: a 30 m tank, 10 m of water, 10 m of clay with E' =
# 5 MPa, nu' = 0.3, k = 1e-9 m/s, c_v = 6.9e-7 m^2/s, on sand) the tank settles 45.5 mm at
# once, 31 % of its drained 149.1 mm, and the rest over years: 65 mm after a month, 116 mm
# after a year, 145 mm after three. Its degree of consolidation lies between Terzaghi's for
# the whole layer drained downwards (the impervious plate) and for both faces (beyond it):
# 0.68 after a year against 0.52 and 0.90. The raft's centre moment changes sign, -6 kN m/m
# (hogging) at once to +187 kN m/m in the drained limit: the consolidating clay under its
# middle lets it sag. (Default mesh, 19.6k dofs, 56 solves: 3.9 s.) In a hydrotest, filled at
# a metre a day, the tank has settled 53 mm by day 10 (the full tank at once: 45 mm, then
# 57 mm after ten days) and 72 mm after fifty days held full; emptied in five days, it
# keeps 22 mm, which the elastic skeleton gives back over years as the clay swells (a real
# clay would keep most of it).
#
# ![settlements, excess pore pressure and centre moment against
# time](../docs/figures/clay_consolidation.png)
#
# ![isochrones down the axis](../docs/figures/clay_isochrones.png)
#
# ![the hydrotest](../docs/figures/clay_hydrotest.png)
