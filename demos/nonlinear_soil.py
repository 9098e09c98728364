# %% [markdown]
# # How much does the soil's nonlinearity matter? The paper's Figs. 25-27 family
#
# Zaman & Mahmood (Figs. 25-27) compare the partially embedded tank on Kondner's hyperbolic
# soil with the same tank on a linear soil of the initial tangent modulus 1/a: the nonlinear
# soil settles more (17 % more at Kp = 0.01, 7 % at Kp = 10 for a bonded plate), and it
# raises the plate's central moment of flexible plates but lowers that of rigid ones.
#
# We repeat the comparison for the Fig. 13 tank (bonded plate and embedded wall face,
# lambda = 0.1 /m, water to 9 m) over a range of plate rigidities, tabulate the excess of
# the nonlinear response over the linear one beside the paper's, and chart both families.
#
# Run: `python demos/nonlinear_soil.py` (or under `mpiexec -n 2`: each analysis then uses both
# ranks); `--coarse` for a quick run. Results and the chart go to `results/nonlinear_soil/`.

# %%
import sys
from pathlib import Path

from mpi4py import MPI

from tankfx import Scene, analyse, load_scene, write_json
from tankfx.studies.excess import first_order_excess
from tankfx.results.figures import plot_sweep

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "nonlinear_soil"
coarse = "--coarse" in sys.argv

# %% [markdown]
# ## The two soils
# The nonlinear tank is the headline demo's scene with a bonded interface; its linear twin
# has E = 1/a growing with depth in the same way (so both start from the same stiffness).

# %%
base = load_scene(Path(__file__).resolve().parent / "scenes" / "embedded_tank_nonlinear.toml")
if coarse:
    base = base.with_coarse_mesh()
rigidities = [0.01, 1.0, 10.0] if coarse else [0.01, 0.1, 1.0, 10.0]


# %%
def with_Kp(scene: Scene, Kp: float, linear: bool) -> Scene:
    data = scene.to_dict()
    data["plate"].pop("thickness", None)
    data["plate"]["Kp"] = Kp
    data["interface"] = {"condition": "bonded"}
    if linear:
        s = data["soil"]
        data["soil"] = {"E": 1.0 / s["hyperbolic_a"], "nu": s["nu"],
                        "E_gradient": s["E_gradient"]}
    return Scene.from_dict(data)


# %% [markdown]
# ## Solve both soils at every rigidity
# The plate's thickness follows Kp (Eq. 21, with the surface modulus 1/a); each line is one
# case.

# %%
rows, excess = [], {}
say(f"{'Kp':>6s} {'soil':>11s} {'w0 [mm]':>9s} {'wd [mm]':>9s} {'M0 [kN m/m]':>12s} "
    f"{'iterations':>10s}")
for Kp in rigidities:
    pair = {}
    for soil in ("hyperbolic", "linear"):
        r = analyse(with_Kp(base, Kp, soil == "linear"), comm).results
        assert r["converged"], (Kp, soil)
        pair[soil] = r
        rows.append({"plate.Kp": Kp, "soil": soil, "converged": True,
                     **{f"nondim.{k}": r["nondim"][k] for k in ("w0", "wd", "M0")}})
        say(f"{Kp:6g} {soil:>11s} {r['w0'] * 1e3:9.2f} {r['wd'] * 1e3:9.2f} "
            f"{r['M0'] / 1e3:12.2f} {r['soil'].get('iterations', 0):10d}")
    excess[Kp] = {k: pair["hyperbolic"][k] / pair["linear"][k] - 1 for k in ("w0", "wd", "M0")}

# %% [markdown]
# ## The nonlinear excess, beside the paper's
# The paper quotes only w0 ("17 % less for the linear soil at Kp = 0.01, 7 % at Kp = 10", so
# an excess of 20 % and 8 % over linear) and the sign change of the M0 excess. Its load
# level is not given; ours is 88 kPa of water on the floor against an ultimate deviator of
# 100 kPa, a heavily loaded soil: the magnitudes differ, the comparison is of trends.

# %%
say(f"\n{'Kp':>6s} {'w0 excess':>10s} {'wd excess':>10s} {'M0 excess':>10s}")
for Kp, e in excess.items():
    say(f"{Kp:6g} {e['w0']:10.1%} {e['wd']:10.1%} {e['M0']:10.1%}")
say("paper (bonded, Figs. 25-27): w0 excess ~20 % at Kp = 0.01 -> ~8 % at Kp = 10; M0 "
    "higher on nonlinear soil for flexible plates, lower for rigid ones")

# %% [markdown]
# ## Where the excess comes from
# Unlike the paper's, our excess is not monotone in Kp: it is least near Kp = 1 and grows
# again towards the rigid plate. Perturbation theory says why, without the iteration: to
# first order in b x load the excess is b dw0/db = b int E_0^2 eps_p sigma_1(u) : eps(v)
# over the soil (u the linear solution, v its adjoint for w0; `first_order_excess`, two
# solves, verified against the iteration in the tests). Its density splits the excess
# into the soil at the foundation's bottom edge (within 0.1 a of it), the rest of the soil
# below the foundation, and the soil around it. A flexible plate softens the soil below
# its centre; a rigid one draws the excess to its edge and to the soil beside it, where its
# contact stress concentrates, and that share grows faster than the central one falls.

# %%
first = {}
say(f"\n{'Kp':>6s} {'1st order':>10s} {'iterated':>9s} {'edge':>6s} {'below':>6s} "
    f"{'around':>7s}")
for Kp in rigidities:
    fo = first_order_excess(with_Kp(base, Kp, False), comm)
    first[Kp] = fo
    sh = fo["regions"]
    say(f"{Kp:6g} {fo['excess']:10.1%} {excess[Kp]['w0']:9.1%} {sh['edge']:6.0%} "
        f"{sh['below']:6.0%} {sh['around']:7.0%}")
say("(at this load the iterated excess exceeds the first-order one: the softening "
    "accelerates with the strain)")

# %%
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "nonlinear_family.json", {"rows": rows, "excess": excess,
                                               "first_order": first})
chart = plot_sweep(rows, {"plate.Kp": rigidities, "soil": ["hyperbolic", "linear"]},
                   out / "nonlinear_family.png", title="Embedded tank, bonded")
say(f"results: {out}/nonlinear_family.json; chart: {chart}")

# %% [markdown]
# ## Checks
# The nonlinear soil is softer everywhere, so every tank settles more on it; the excess of
# w0 falls from the flexible plate to Kp = 1 (the paper's trend); the central moment's excess
# changes sign from flexible to rigid plates (the paper's Fig. 27); the iterated excess
# rises or falls from Kp = 1 to 10 as the first-order one does (the shape is the linear
# fields', not the iteration's), and the edge's share grows with the rigidity.

# %%
assert all(e["w0"] > 0 for e in excess.values()), excess
assert excess[1.0]["w0"] < excess[0.01]["w0"], excess
assert excess[0.01]["M0"] > 0 > excess[10.0]["M0"], excess
assert (excess[10.0]["w0"] > excess[1.0]["w0"]) == \
    (first[10.0]["excess"] > first[1.0]["excess"]), (excess, first)
assert first[10.0]["regions"]["edge"] > first[0.01]["regions"]["edge"], first

# %% [markdown]
# ## What it shows
#
# The family: hyperbolic against linear soil over Kp:
#
# ![nonlinear family](../docs/figures/nonlinear_family.png)
