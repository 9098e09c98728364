# %% [markdown]
# # Filling a tank on sand: a load-settlement curve with Duncan & Chang's soil
#
# The paper's embedded water tank (Fig. 13: a = 10 m, plate 2 m below ground) on a
# medium-dense sand described by Duncan & Chang's hyperbolic law: each cell's stiffness and
# strength follow its confining stress, geostatic plus the tank's. We fill the tank in six
# steps, as a hydrotest would, and draw the settlement against the water's weight.
#
# The loads are total, as in the paper: each step is the tank with that much water, its
# soil iterated from the previous step's moduli. (Kondner's and Duncan & Chang's secant laws
# are nonlinear elastic: emptying the tank again would retrace the curve; tankfx warns about
# such stages.)
#
# Run: `python demos/tank_on_sand.py` (or under `mpiexec -n 2`); `--coarse` for a quick run.
# Results and the figure go to `results/tank_on_sand/`.

# %%
import sys
from pathlib import Path

from mpi4py import MPI

from tankfx import analyse, load_scene, write_json
from tankfx.results.figures import plot_load_path

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "tank_on_sand"
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## The scene and its filling path
# `demos/scenes/tank_on_sand.toml`; the stages are the [load] with the water's height
# changed (a scene file would write them as `[[stages]]` tables).

# %%
scene = load_scene(Path(__file__).resolve().parent / "scenes" / "tank_on_sand.toml")
if "--coarse" in sys.argv:
    scene = scene.with_coarse_mesh()
heights = [1.5, 3.0, 4.5, 6.0, 7.5, 9.0]
filling = scene.with_changes(stages=[{"liquid_height": h} for h in heights])
say(f"{scene.title}: {len(heights)} stages, water to {heights[-1]:g} m")

# %% [markdown]
# ## Solve the path

# %%
r = analyse(filling, comm).results
say(f"\n{'water m':>8s} {'load MN':>8s} {'w0 mm':>7s} {'wd mm':>6s} {'M0 kN m/m':>10s} "
    f"{'secant k MN/mm':>15s} {'solves':>7s}")
for h, st in zip(heights, r["stages"]):
    say(f"{h:8.1f} {st['applied_load'] / 1e6:8.2f} {st['w0'] * 1e3:7.2f} "
        f"{st['wd'] * 1e3:6.2f} {st['M0'] / 1e3:10.1f} "
        f"{st['applied_load'] / st['w0'] / 1e9:15.3f} {st['soil_iterations']:7d}")

# %% [markdown]
# ## The figure and the results

# %%
fig = plot_load_path(r, out / "load_path.png", title=scene.title)
if comm.rank == 0:
    write_json(out / "results.json", r)
say(f"figure: {fig}; results: {out / 'results.json'}")

# %% [markdown]
# What the table says: the sand stiffens with confinement (the geostatic stress grows with
# depth, and the tank's adds to it) and softens with its stress level; at these loads, far
# below the sand's bearing capacity, the two nearly balance: the secant stiffness load / w0
# falls by 8 % from the first step to the full tank (0.86 to 0.79 MN/mm), while the plate's
# centre moment grows to 264 kN m/m. Checks: the settlement grows with every step; the
# last stage is the full tank analysed directly (total loads: the path does not matter),
# within the iterations' tolerance.

# %%
w = [st["w0"] for st in r["stages"]]
assert all(w1 > w0 for w0, w1 in zip(w, w[1:]))
full = analyse(scene, comm).results
assert abs(r["w0"] / full["w0"] - 1) < 5e-3, (r["w0"], full["w0"])
assert r["equilibrium"]["relative_error"] < 1e-8

# %% [markdown]
# ## What it shows
#
# On the sand the secant stiffness load / w0 falls by 8 % as the tank fills (0.86 to 0.79
# MN/mm): stiffening with confinement and softening with stress level nearly balance at these
# loads, far below the bearing capacity; 35 mm at the full 9 m.
#
# ![load-settlement curve on the sand](../docs/figures/sand_load_path.png)
