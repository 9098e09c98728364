# %% [markdown]
# # A hydrotest on Kondner's soil: what does the tank keep when it is emptied?
#
# Before service a tank is filled with water, watched and emptied: the hydrotest. A soil
# that has been loaded does not give all its settlement back: unloaded, it is several times
# stiffer than on its first loading (Duncan & Chang's unloading-reloading modulus E_ur, 1.2
# to 3 times the initial one), and it keeps a permanent strain. Filled again, it comes back
# stiffly along that unloading line to the state it left, and only then settles further.
#
# The paper's secant law is nonlinear elastic: its soil would unload along its loading
# curve and give everything back. With `[soil] unloading_modulus_ratio` (E_ur over the
# initial modulus 1/a) each soil cell of Kondner's law remembers its most loaded state along
# a load path and below it follows the unloading line through that state (docs/theory/method.md;
# verified in tests/test_unloading.py: a confined layer against the closed form, the
# rebound of a flexible load against the linear soil of E_ur).
#
# Here: the paper's Fig. 13 tank (embedded 2 m, hyperbolic soil growing stiffer with depth,
# Mohr-Coulomb interface), with its concrete's weight, filled to 3, 6 and 9 m, emptied and
# filled to 9 m again, against the same path on the paper's law.
#
# Run: `python demos/hydrotest.py` (or under `mpiexec -n 2`); `--coarse` for a quick run.
# Results and figures go to `results/hydrotest/`.

# %%
import sys
from pathlib import Path

from mpi4py import MPI

from tankfx import Scene, analyse_path, load_scene, write_json
from tankfx.results.figures import plot_contact, plot_curves

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "hydrotest"
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## The tank and its load path
# `demos/scenes/hydrotest.toml`: the tank of `embedded_tank_nonlinear.toml` with concrete
# of 24 kN/m^3 in its plate and wall (its own weight stays on at every stage). Each
# `[[stages]]` table is the [load] keys it changes: first the tank alone, then the water at
# 3, 6, 9 m, emptied in the same steps, and filled again. E_ur = 3 / a: the stiff end of
# Duncan & Chang's range, where the permanent settlement is largest. The paper's law is
# the same scene without `unloading_modulus_ratio`.

# %%
remembering = load_scene(Path(__file__).resolve().parent / "scenes" / "hydrotest.toml")
data = remembering.to_dict()
if "--coarse" in sys.argv:
    # a quick look: the coarse mesh, and the path in 9 m steps (the tank alone, full,
    # emptied, full again)
    data = remembering.with_coarse_mesh().to_dict()
    data["stages"] = [st for st in data["stages"] if st.get("liquid_height", 0.0) in (0, 9)]
    remembering = Scene.from_dict(data)
heights = [ld.liquid_height for ld in remembering.stages]
del data["soil"]["unloading_modulus_ratio"]
paper = Scene.from_dict(data)
# the first full stage, the emptied one after it, and the last (full again)
i_full = heights.index(max(heights))
i_empty = heights.index(0.0, i_full)

# %%
path = [s.results for s in analyse_path(remembering, list(remembering.stages), comm)]
elastic = [s.results for s in analyse_path(paper, list(paper.stages), comm)]

# %% [markdown]
# ## Stage by stage
# The settlement at the centre and the edge, the plate's dish (wd) and its centre moment,
# how many soil cells follow their unloading line, and how much of the plate has lifted off
# the soil. While the tank fills, a few cells already unload: those whose strain falls as
# the load spreads differently (the water's thrust on the wall, the interface slipping);
# the paper's law takes them back down their loading curve, so the two paths part a little
# even before the tank is emptied.

# %%
say(f"{remembering.title}: E_ur / E_i = {remembering.soil.unloading_modulus_ratio:g}\n")
say(f"{'stage':>5s} {'water m':>7s} {'w0 mm':>7s} {'w_edge':>7s} {'wd mm':>6s} "
    f"{'M0 kNm/m':>9s} {'unloading':>9s} {'lifted m':>8s} | {'paper w0':>8s} {'M0':>7s}")
for k, (r, e, h) in enumerate(zip(path, elastic, heights), start=1):
    lifted = r["interface"]["separated_length"]["plate"]
    say(f"{k:5d} {h:7.1f} {1e3 * r['w0']:7.2f} {1e3 * r['w_edge']:7.2f} {1e3 * r['wd']:6.2f} "
        f"{r['M0'] / 1e3:9.1f} {r['soil']['unloading_cells']:9d} {lifted:8.2f} | "
        f"{1e3 * e['w0']:8.2f} {e['M0'] / 1e3:7.1f}")
full, emptied, again = path[i_full], path[i_empty], path[-1]
kept = emptied["w0"] - path[0]["w0"]
say(f"\nemptied, the tank keeps {1e3 * kept:.1f} mm of the {1e3 * (full['w0'] - path[0]['w0']):.1f}"
    f" mm the water caused ({kept / (full['w0'] - path[0]['w0']):.0%}); on the paper's law "
    f"{1e3 * (elastic[i_empty]['w0'] - elastic[0]['w0']):.2g} mm")
say(f"filled again: w0 {1e3 * again['w0']:.2f} mm against {1e3 * full['w0']:.2f} mm the first "
    f"time ({again['w0'] / full['w0'] - 1:+.1e}: the soil iteration's tolerance)")
# Emptied, the soil keeps most of its settlement, and most of all under the plate's edge,
# where it was strained the most: the plate springs back with the soil under its middle and
# lifts off over its outer half metre or so (the "lifted" column), the wall's weight now
# hanging from it: it hogs (M0 far below its value full). Filled again, the water presses
# it back: the element states come back as they were (reported "rebonded"), and so do the
# settlements and moments.

# %% [markdown]
# ## Figures
# The settlement and the plate's centre moment against the water height, both paths: the
# paper's law goes up and down one curve; the remembering soil comes down a stiffer line and
# goes back up it. And the contact stresses of the emptied tank.

# %%
# (the paper's drawn last, over the shared loading curve: the line apart is the other's)
labels = ("E_ur = 3 / a (down its line, back up)", "paper's law (back down its curve)")
plot_curves(heights, {
    "w0 [mm]": {labels[0]: [1e3 * r["w0"] for r in path],
                labels[1]: [1e3 * r["w0"] for r in elastic]},
    "M0 [kN m/m]": {labels[0]: [r["M0"] / 1e3 for r in path],
                    labels[1]: [r["M0"] / 1e3 for r in elastic]}},
    out / "hydrotest.png", "water height [m] (filled, emptied, filled)",
    title=remembering.title, legend_left=True)
plot_contact(emptied, out / "contact_emptied.png", title=f"{remembering.title}: emptied")
if comm.rank == 0:
    write_json(out / "results.json", path[-1])
say(f"figures and results.json in {out}/")

# %% [markdown]
# ## Checks
# Filling settles more at every step, and on both laws alike (within 0.5 %: a few cells
# unload while the tank fills, where the load spreads differently as it grows; the first
# stage, the tank's own weight, is the same on both); emptied, the remembering soil keeps a
# permanent settlement and the paper's returns to the tank's own weight; filled again, the
# tank is back where it was (within the soil iteration's tolerance); every stage balances
# its load.

# %%
for a, b in zip(path[:i_full], path[1:i_full + 1]):
    assert b["w0"] > a["w0"]
assert abs(path[0]["w0"] / elastic[0]["w0"] - 1) < 1e-9
for r, e in zip(path[1:i_full + 1], elastic[1:i_full + 1]):
    assert abs(r["w0"] / e["w0"] - 1) < 5e-3
assert emptied["w0"] > path[0]["w0"] + 0.2 * (full["w0"] - path[0]["w0"])
assert abs(elastic[i_empty]["w0"] / elastic[0]["w0"] - 1) < 2e-3
assert abs(again["w0"] / full["w0"] - 1) < 2e-3 and abs(again["M0"] / full["M0"] - 1) < 1e-2
assert full["soil"]["unloading_cells"] < 0.05 * emptied["soil"]["unloading_cells"]
assert all(r["equilibrium"]["relative_error"] < 1e-8 for r in path + elastic)

# %% [markdown]
# ## What it shows
#
# In the hydrotest on Kondner's soil (`demos/hydrotest.py`, default mesh, 20 stages of two
# paths: 31 s), with E_ur = 3 / a the water settles the tank 336 mm beyond its own weight's
# 43 mm; emptied it keeps 297 mm of that (88 %: at 9 m of water the soil under the tank is
# near its ultimate deviator, its secant modulus a fraction of E_ur), where the paper's law
# gives it all back. The emptied plate lifts off the soil at its edge, over its outer 0.76 m
# (the soil kept most settlement there, where it was strained most), the wall's weight
# hanging from it, and hogs (M0 -264 against -36 kN m/m full); filled again, the tank is back
# at 379.13
# mm (7e-8 from the first filling), its elements reported rebonded. While it fills, up to
# 212 of the soil's 13.7k cells already unload (where the load spreads differently as it
# grows): the two laws part by 0.1 % before the tank is emptied.
#
# ![w0 and M0 along the path](../docs/figures/hydrotest.png)
#
# ![the emptied tank's contact stresses](../docs/figures/hydrotest_emptied_contact.png)
