# %% [markdown]
# # A partially embedded liquid storage tank on nonlinear soil
#
# The tank of Zaman & Mahmood's Fig. 13, with the whole of their model: a concrete
# foundation plate 2 m below the ground, a concrete wall standing on its edge, water to
# 9 m; the soil is Kondner's hyperbolic soil (the paper's a and b) stiffening with depth,
# and the plate's underside and the wall's embedded face meet it through a Mohr-Coulomb
# interface that can stick, slip and separate.
#
# We read the scene, solve (watching the soil and interface iterations converge), check
# equilibrium and the Mohr-Coulomb condition, and draw the moments and contact stresses.
#
# Run: `python demos/embedded_tank.py` or `mpiexec -n 2 python demos/embedded_tank.py`
# (same numbers). Add `--coarse` for a quick run on a coarser mesh. Results and figures go to
# `results/embedded_tank/` (this demo's own folder; a re-run replaces them).

# %%
import sys
from pathlib import Path

import numpy as np
from mpi4py import MPI

from tankfx import analyse, load_scene, write_json
from tankfx.cli import setup_logging
from tankfx.results.figures import (plot_contact, plot_cutaway, plot_moment_diagrams, plot_section,
                                    plot_structure_profiles)
from tankfx.results.fields import soil_cell_fields, write_fields
from tankfx.results.report import summary_table

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "embedded_tank"

# %% [markdown]
# ## The scene
# One TOML file: hyperbolic soil (1/a = 4.76 MPa initial modulus growing as 1 + 0.1 h,
# 1/b = 100 kPa ultimate deviator), plate and wall, a Mohr-Coulomb interface with a friction
# angle of 26.6 degrees, and water. SI units.

# %%
scene = load_scene(Path(__file__).resolve().parent / "scenes" / "embedded_tank_nonlinear.toml")
if "--coarse" in sys.argv:
    scene = scene.with_coarse_mesh()
p_ref = scene.load.liquid_unit_weight * scene.load.liquid_height
say(f"{scene.title}: a = {scene.plate.radius:g} m, t_p = {scene.plate.thickness:.3f} m "
    f"(Kp = {scene.Kp:.3g}), t_wall = {scene.wall.thickness:.3f} m (Kt = {scene.Kt:.3g}), "
    f"embedment {scene.embedment:g} m, water pressure on the floor {p_ref / 1e3:.1f} kPa")

# %% [markdown]
# ## Solve
# The soil's secant moduli and the interface's element states are iterated in one loop:
# each line of the log is one solve of the whole block system (soil, plate, wall).

# %%
if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)
comm.barrier()
setup_logging(out, comm.rank)
solution = analyse(scene, comm)
r = solution.results

# %% [markdown]
# ## Results
# The paper's non-dimensional measures (Eqs. 21-23, p = the water pressure on the floor),
# the moments, the interface's state, and what a tank code asks of the settlements.

# %%
say("\n" + summary_table(r))
say("(an axisymmetric model gives no planar tilt of the tank)")

# %% [markdown]
# ## Checks
# Equilibrium of the water's weight with the supports and with the contact tractions; the
# Mohr-Coulomb condition at every interface station; the moments about the joint.

# %%
eq, j = r["equilibrium"], r["junction"]
plate = r["profiles"]["plate"]
tan_phi = r["scene"]["interface"]["tan_phi"]
sn, tau = np.array(plate["contact_normal"]), np.array(plate["contact_shear"])
mc_excess = float(np.max(np.abs(tau) - (scene.interface.cohesion + sn * tan_phi)))
say(f"\nweight of water {eq['applied_load'] / 1e6:.3f} MN; support reaction error "
    f"{eq['relative_error']:.1e}, contact resultant error {eq['contact_relative_error']:.1e}")
say(f"Mohr-Coulomb: largest |tau| - (c + sigma_n tan phi) = {mc_excess / 1e3:.2e} kPa, "
    f"smallest sigma_n = {sn.min() / 1e3:.2f} kPa")
say(f"moments about the joint: plate {j['M_plate_about_corner'] / 1e3:.2f}, wall "
    f"{j['M_wall_about_corner'] / 1e3:.2f} kN m/m")

# %% [markdown]
# ## Figures
# The deformed section coloured by vertical stress and by the soil's stress level, the
# moment diagrams on the structure, the profiles, and the contact stresses with the
# Mohr-Coulomb limit and the slipping and separated elements.

# %%
if comm.rank == 0:
    write_json(out / "results.json", r)
a = scene.plate.radius
figures = [
    plot_section(solution.u, solution.sigma_zz, out / "section.png", extent=1.6 * a,
                 depth_offset=scene.embedment, title=scene.title,
                 soil_cells=solution.domain.cells("soil"), structure=r),
    # Kondner's stress level q / q_ult per cell: where the soil nears its ultimate deviator
    plot_section(solution.u, soil_cell_fields(solution.model)["stress_level"],
                 out / "stress_level.png", extent=1.6 * a, depth_offset=scene.embedment,
                 title=scene.title, label="q / q_ult", scalar_scale=1.0,
                 soil_cells=solution.domain.cells("soil"), structure=r),
    plot_moment_diagrams(r, out / "moments.png", title="Embedded tank"),
    plot_structure_profiles(r, out / "profiles.png", title="Embedded tank"),
    plot_contact(r, out / "contact.png", title="Embedded tank"),
    plot_cutaway(solution.u, solution.sigma_zz, out / "cutaway.png", extent=1.6 * a,
                 depth_offset=scene.embedment, title=scene.title,
                 soil_cells=solution.domain.cells("soil"), structure=r),
]
say("\nresults: " + str(out / "results.json"))
say("figures: " + ", ".join(str(f) for f in figures if f is not None))

# %% [markdown]
# ## The fields, for ParaView
# The soil's displacement, sigma_zz and, cell by cell, the secant modulus, the deviator and
# Kondner's stress level (the share of the ultimate deviator 1/b the soil has reached: where
# it nears 1 the soil is close to failure) go to `soil.pvd`; the plate's and the wall's
# profiles to `plate.vtp` and `wall.vtp`. Open them in ParaView, colour the soil by
# `stress_level`, threshold `soil` > 0.5 to hide the tank's inside, warp all by `u`, and
# revolve with Rotational Extrusion for a 3D view. (`tankfx run` writes the same files.)

# %%
say("fields: " + ", ".join(str(f) for f in write_fields(solution, out / "fields")))

# %% [markdown]
# The demo ends with its own checks: both iterations converged, equilibrium, no tension and
# no shear beyond the Mohr-Coulomb limit at the interface.

# %%
assert r["soil"]["converged"] and r["interface"]["converged"]
assert eq["relative_error"] < 1e-6 and eq["contact_relative_error"] < 1e-6
assert sn.min() >= 0.0 and mc_excess <= 1e-9 * np.abs(sn).max()

# %% [markdown]
# ## What it shows
#
# The figures of this tank (the deformed section in vertical stress, the moment diagrams on
# the plate and wall, the soil's stress level q / q_ult, a 3D cut-away, the contact stresses
# against the Mohr-Coulomb limit, and the members' profiles):
#
# ![deformed section, vertical stress](../docs/figures/embedded_section.png)
#
# ![moment diagrams](../docs/figures/embedded_moments.png)
#
# ![the soil's stress level](../docs/figures/embedded_stress_level.png)
#
# ![3D cut-away](../docs/figures/embedded_cutaway.png)
#
# ![contact stresses](../docs/figures/embedded_contact.png)
#
# ![profiles](../docs/figures/embedded_profiles.png)
