# %% [markdown]
# # A tank on layered ground: soft clay over dense sand
#
# The paper's soil is one material whose stiffness may grow with depth. Real sites are
# layered: here a steel tank on a concrete raft stands on soft clay, loaded quickly
# (undrained: nu = 0.5, solved in the mixed form), over dense sand. How much of the tank's
# settlement and of its raft's bending comes from the clay, and how thick must the clay be
# before the sand stops mattering?
#
# First the method is checked where the answer is known: a flexible load on layered ground,
# against Burmister's layered elastic solution (evaluated by Hankel transform in
# `tankfx.verification.reference`). Then the tank is solved for clay layers from none to very thick.
#
# Run: `python demos/layered_ground.py` (or under `mpiexec -n 2`); `--coarse` for a quick
# run. Results and figures go to `results/layered_ground/`.

# %%
import sys
from pathlib import Path

import numpy as np
from mpi4py import MPI

from tankfx import Scene, analyse, load_scene, write_json
from tankfx.verification import reference as ref
from tankfx.results.figures import plot_curves, plot_moment_diagrams

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
coarse = "--coarse" in sys.argv
out = Path("results") / "layered_ground"
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## The check: a flexible load on an undrained clay layer over sand
# p = 100 kPa on a = 1 m; 1 m of clay (E = 5 MPa, nu = 0.5) over a half-space of sand
# (E = 50 MPa, nu = 0.3). The clay's pressure is an unknown of its own, which jumps at the
# sand's top as lambda does.

# %%
check = Scene.from_dict({
    "title": "flexible load on a clay layer",
    "soil": {"E": 5e6, "nu": 0.5, "layers": [{"depth": 1.0, "E": 50e6, "nu": 0.3}]},
    "load": {"pressure": 100e3, "load_radius": 1.0}})
if coarse:
    check = check.with_coarse_mesh()
r = analyse(check, comm).results
burmister = ref.layered_surface_settlement(100e3, 1.0, [0.0, 1.0], [(1.0, 5e6, 0.5)],
                                           (50e6, 0.3))
say(f"\n{check.title}: {r['dofs']['total']} dofs")
say(f"{'':10s} {'tankfx mm':>10s} {'Burmister mm':>13s} {'error':>9s}")
for name, w, w_ref in (("centre", r["w0"], burmister[0]), ("edge", r["w_edge"], burmister[1])):
    say(f"{name:10s} {w * 1e3:10.4f} {w_ref * 1e3:13.4f} {w / w_ref - 1:+9.2e}")
assert abs(r["w0"] / burmister[0] - 1) < 2e-3

# %% [markdown]
# ## The tank
# `demos/scenes/layered_tank.toml`: a 10 m raft, 0.5 m thick, a 12 m steel wall, 10 m of
# water, on 5 m of clay over sand. We vary the clay's thickness H from none (the raft on the
# sand) to very thick (the clay alone), keeping the same raft (its thickness, not Kp: Kp
# is defined on the surface soil, which changes between the limits). The clay twice: just
# after filling (undrained, nu = 0.5) and in the long term (drained, nu' = 0.3), with the
# same shear modulus G = E_u / 3, which drainage does not change: E' = 2 (1 + nu') G.

# %%
tank = load_scene(Path(__file__).resolve().parent / "scenes" / "layered_tank.toml")
if coarse:
    tank = tank.with_coarse_mesh()
undrained = tank.to_dict()["soil"]
sand = undrained.pop("layers")[0]
sand.pop("depth")
drained = {"E": 2.0 * 1.3 * undrained["E"] / 3.0, "nu": 0.3}
clays = {"undrained": undrained, "drained": drained}
a = tank.plate.radius
thicknesses = [0.25 * a, 0.5 * a, a, 2.0 * a] if not coarse else [0.25 * a, a]


# %%
def tank_on(soil: dict, layers: list) -> dict:
    return analyse(tank.with_changes(soil=soil | {"layers": layers}), comm).results


# %%
sand_only = tank_on(sand, [])
results = {name: {"limit": tank_on(clay, []),
                  "layered": [tank_on(clay, [sand | {"depth": H}]) for H in thicknesses]}
           for name, clay in clays.items()}

# %% [markdown]
# ## Settlement and bending against the clay's thickness

# %%
say(f"\n{tank.title}: a = {a:g} m, raft t = {tank.plate.thickness:g} m, water "
    f"{tank.load.liquid_height:g} m")
say(f"{'':24s} {'w0 mm':>8s} {'wd mm':>8s} {'M0 kN m/m':>10s} {'M_wall kN m/m':>14s}")


# %%
def row(name, res):
    say(f"{name:24s} {res['w0'] * 1e3:8.2f} {res['wd'] * 1e3:8.2f} {res['M0'] / 1e3:10.1f} "
        f"{res['junction']['M_wall'] / 1e3:14.2f}")


# %%
row("sand only", sand_only)
for name, res in results.items():
    for H, r_H in zip(thicknesses, res["layered"]):
        row(f"{name} clay, H = {H:g} m", r_H)
    row(f"{name} clay only", res["limit"])

# %%
x = np.array(thicknesses) / a
panels = {}
for key, label, scale in (("w0", "w0 [mm]", 1e3), ("wd", "wd [mm]", 1e3),
                          ("M0", "M0 [kN m/m]", 1e-3)):
    curves = {f"{name} clay over sand": [r_H[key] * scale for r_H in res["layered"]]
              for name, res in results.items()}
    curves |= {f"{name} clay only": [res["limit"][key] * scale]
               for name, res in results.items()}
    panels[label] = curves | {"sand only": [sand_only[key] * scale]}
figs = [plot_curves(x, panels, out / "clay_thickness.png", "H / a (clay thickness)",
                    title="Tank on clay over sand"),
        plot_moment_diagrams(results["undrained"]["layered"][1], out / "moments.png",
                             title=f"{tank.title}, H = {thicknesses[1]:g} m, undrained")]
if comm.rank == 0:
    write_json(out / "results.json", {"thicknesses": thicknesses, "sand_only": sand_only,
                                      **results})
say("figures: " + ", ".join(str(f) for f in figs if f is not None))

# %% [markdown]
# What the table says: in the long term the tank settles more the thicker the clay, from
# the sand's settlement towards the clay's. Just after filling, a thin undrained layer
# settles no more than the sand it replaces (33.0 against 33.2 mm at H = 2.5 m): it cannot
# change volume, and squeezing it out from under a raft eight times wider than it is thick
# takes much force; the raft then hardly bends (M0 5 against 73 kN m/m on sand).
# Checks: the drained clay: more clay, more settlement, between the two limits; undrained
# settles less than drained at every thickness (same G, a larger nu); every case in
# equilibrium.

# %%
w = [r_H["w0"] for r_H in results["drained"]["layered"]]
assert sand_only["w0"] < w[0] and all(w1 > w0 for w0, w1 in zip(w, w[1:]))
assert w[-1] < results["drained"]["limit"]["w0"]
for u, d in zip(results["undrained"]["layered"], results["drained"]["layered"]):
    assert u["w0"] < d["w0"]
for res in [sand_only, *(r for v in results.values() for r in [v["limit"], *v["layered"]])]:
    assert res["equilibrium"]["contact_relative_error"] < 1e-8

# %% [markdown]
# ## What it shows
#
# A thin undrained clay layer (H = a/4) settles no more than the sand it replaces (33.0
# against 33.2 mm) and the raft hardly bends (M0 5 against 73 kN m/m): it cannot change
# volume, and squeezing it out from under a raft eight times wider than it is thick takes
# much force; drained, the same layer more than doubles the settlement (73 mm).
#
# ![settlement, differential settlement and centre moment against the clay's
# thickness](../docs/figures/layered_clay_thickness.png)
