# %% [markdown]
# # Will the ground under a tank on soft clay fail in its hydrotest, and by how much is it safe?
#
# Tank failures on soft clay are bearing failures, most often during the hydrotest, and
# most often at the edge, where the shell's weight and the water's pressure meet the
# ground (Duncan & D'Orazio, "Stability of steel oil storage tanks", ASCE 1984). The
# question is the factor of safety of the full fill.
#
# tankfx answers it with the elastoplastic soil (`[soil] model = "mohr_coulomb"`, Tresca
# here) and `[analysis] collapse`: `"strength"` divides the clay's strength by a factor
# until the ground fails under the full tank, `"load"` raises the water's pressure (and the
# other variable loads) until it fails. Both bracket their factor between a converged
# state and a failed one (docs/theory/plasticity.md, "The collapse"; verified against the
# exact bearing capacity of a rigid footing in tests/test_collapse.py).
#
# Run: `python demos/tank_collapse.py` (about 3 min; or under `mpiexec -n 2`); `--coarse`
# for a quick run (the load search alone, on a coarse mesh). Results and figures go to
# `results/tank_collapse/`.

# %%
import sys
from pathlib import Path

from mpi4py import MPI

from tankfx import analyse, load_scene, write_json
from tankfx.results.figures import write_figures

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "tank_collapse"
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)
coarse = "--coarse" in sys.argv

# %% [markdown]
# ## The tank and the clay
# `demos/scenes/tank_on_soft_clay.toml`: a 25 m steel tank (8 mm floor, 16 mm shell) with
# 14 m of water, on Tresca clay of s_u = 25 kPa + 1.5 kPa/m. Its settlement under the full
# tank first, then the two searches.

# %%
scene = load_scene(Path(__file__).resolve().parent / "scenes" / "tank_on_soft_clay.toml")
if coarse:
    scene = scene.with_coarse_mesh()
# ("bounds" is the search by load with the limit analysis' bounds beside it)
searches = ["bounds"] if coarse else ["strength", "bounds"]
found = {}
for kind in searches:
    solution = analyse(scene.with_changes(analysis={"collapse": kind}), comm)
    found[kind] = solution
    c = solution.results["collapse"]
    factor = c[c["kind"] + "_factor"]
    say(f"\ncollapse by {c['kind']}: factor {factor:.4g}"
        + (f" in [{c['bracket'][0]:.4g}, {c['bracket'][1]:.4g}], failed by {c['failure']}"
           if c["found"] else f" (a lower bound: {c['reason']})")
        + (f"; the mechanism forms at {c['knee_bracket'][0]:.4g}-{c['knee_bracket'][1]:.4g}"
           if c.get("knee_bracket") else "")
        + f"; mechanism: {c['mechanism']['kind']} ({c['time_s']:.0f} s)")
    if kind == "bounds":
        b = solution.results["bounds"]
        say(f"limit analysis (floor and shell rigid): the ground fails between "
            f"{b['lower']:.4g} and {b['upper']:.4g} times the water (gap {100 * b['gap']:.1f} "
            f"%, {b['time_s']:.0f} s); the elastoplastic factor lies {b['elastoplastic_position']}"
            f" them")
r = found[searches[0]].results
say(f"\nunder the full tank: w0 = {1e3 * r['w0']:.0f} mm, at the shell "
    f"{1e3 * r['w_edge']:.0f} mm; {r['soil']['plastic_points']} points of the clay yield")

# %% [markdown]
# ## What it says
# Under a flexible floor the load-settlement curve has a clear knee, where the edge
# mechanism forms (about 1.13), and then rises slowly without a plateau: the shell's edge
# punches in while the interior, still holding, takes the rest (contained plastic flow).
# Such a curve is read as a load test's is: the ground has failed at a mean settlement of a
# tenth of the diameter (De Beer; Vesic), 2.5 m here. Both searches bracket their factor
# against that criterion (`failure` is "settlement"; a rigid footing's is "no equilibrium",
# its plateau), and for Tresca's clay they agree: 1.179 by strength and 1.178 by load on
# the default mesh, so the clay could lose 15 % of its strength, or the water weigh 18 %
# more, before the ground fails. The mechanism is "edge": the last increment of the soil's displacement is under
# the shell, the centre still (`mechanism.png`). docs/development/2026-11-27-collapse.md
# has the measurements, and `python benchmarks/tank_collapse.py --coarse` the factors
# against the fill height.

# %%
load = found["bounds"].results["collapse"]
bounds = found["bounds"].results["bounds"]
# the settlement criterion stops the search below the limit the rigid body reaches
assert load["load_factor"] <= bounds["upper"]
assert load["mechanism"]["kind"] == "edge"              # the shell's edge punches in
assert load["found"] and load["failure"] == "settlement"  # no plateau: the criterion
assert load["knee_bracket"][1] <= load["load_factor"]   # the knee below what it carries
if "strength" in found:
    strength = found["strength"].results["collapse"]
    assert strength["found"]
    # Tresca: the two factors agree (the steel's weight, held, is 2 % of the load)
    assert abs(strength["strength_factor"] / load["load_factor"] - 1.0) < 0.01
for kind, solution in found.items():
    if comm.rank == 0:
        (out / kind).mkdir(exist_ok=True)
    comm.barrier()
    write_figures(solution, out / kind, "stress_level")
    if comm.rank == 0:
        write_json(out / kind / "results.json", solution.results)
say(f"figures and results.json in {out}/" + "{" + ",".join(found) + "}")
