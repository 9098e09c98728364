# # A partially embedded liquid storage tank
#
# The problem of Zaman & Mahmood's Fig. 13: a cylindrical tank whose concrete foundation
# plate sits 2 m below the ground, with its wall standing on the plate edge, full of water
# to 9 m. The soil is an elastic half-space; plate and wall are thin shells rigidly joined;
# the plate's underside and the wall's outer face below the ground are bonded to the soil.
#
# We read the scene, solve soil, plate and wall as one system, check equilibrium, and draw
# the moment diagrams and contact stresses.
#
# Run: `python demos/embedded_tank.py` or `mpiexec -n 2 python demos/embedded_tank.py`
# (same numbers). Add `--coarse` for a quick run on a coarser mesh. Results and figures go to
# `results/embedded_tank/` (this demo's own folder; a re-run replaces them).

# +
import sys
from pathlib import Path

import numpy as np
from mpi4py import MPI

from tankfx import analyse, load_scene
from tankfx.cli import setup_logging, write_json
from tankfx.plots import plot_moment_diagrams, plot_section, plot_structure_profiles

comm = MPI.COMM_WORLD
say = print if comm.rank == 0 else (lambda *a, **k: None)
out = Path("results") / "embedded_tank"
# -

# ## The scene
# One TOML file: soil, plate (`Kp` = 1 fixes its thickness by Eq. 21), wall (`Kt` = 0.1 by
# Eq. 22), bonded interface, water load. SI units.

scene = load_scene(Path(__file__).resolve().parent / "scenes" / "embedded_tank.toml")
if "--coarse" in sys.argv:
    a = scene.plate.radius
    scene = scene.with_changes(mesh={"edge_size": 0.01 * a, "near_size": 0.25 * a,
                                     "growth": 0.3})
p_ref = scene.load.liquid_unit_weight * scene.load.liquid_height
say(f"{scene.title}: a_p = {scene.plate.radius:g} m, t_p = {scene.plate.thickness:.3f} m "
    f"(Kp = {scene.Kp:.3g}), wall t = {scene.wall.thickness:.3f} m (Kt = {scene.Kt:.3g}), "
    f"embedment {scene.embedment:g} m, water pressure on the floor {p_ref / 1e3:.1f} kPa")

# ## Solve
# tankfx meshes the soil, the excavated pit and the tank's interior (a void region, so that
# the wall is a line of facets), builds the plate and wall on a facet submesh, and solves
# the coupled block system with MUMPS. Progress is logged as it goes.

if comm.rank == 0:
    out.mkdir(parents=True, exist_ok=True)
comm.barrier()
setup_logging(out, comm.rank)
solution = analyse(scene, comm)
r = solution.results

# ## Results
# The paper's non-dimensional measures (Eqs. 21-23, with p the water pressure on the floor),
# the moments at the centre and at the joint, and the hoop force in the wall.

wall = r["profiles"]["wall"]
j = r["junction"]
rows = [
    ("centre settlement w0", f"{1e3 * r['w0']:.2f} mm", f"w0_bar = {r['nondim']['w0']:.4f}"),
    ("differential settlement wd", f"{1e3 * r['wd']:.2f} mm",
     f"wd_bar = {r['nondim']['wd']:.4f}"),
    ("edge settlement", f"{1e3 * r['w_edge']:.2f} mm", ""),
    ("centre moment M0", f"{r['M0'] / 1e3:.1f} kN m/m", f"M0_bar = {r['nondim']['M0']:.5f}"),
    ("plate moment at the joint", f"{j['M_plate'] / 1e3:.1f} kN m/m", ""),
    ("wall base moment", f"{j['M_wall'] / 1e3:.1f} kN m/m", ""),
    ("largest wall hoop force", f"{max(wall['N_theta']) / 1e3:.0f} kN/m", ""),
    ("largest contact pressure", f"{max(r['profiles']['plate']['contact_normal']) / 1e3:.0f}"
     f" kPa", ""),
]
say(f"\n{'quantity':30s} {'value':>16s}   non-dimensional")
for name, value, nd in rows:
    say(f"{name:30s} {value:>16s}   {nd}")

# ## Checks
# The soil's supports carry the whole weight of water, and so do the contact tractions; the
# moments about the joint's corner balance between plate and wall.

eq = r["equilibrium"]
say(f"\nweight of water {eq['applied_load'] / 1e6:.3f} MN; support reaction error "
    f"{eq['relative_error']:.1e}, contact resultant error {eq['contact_relative_error']:.1e}")
say(f"moments about the joint: plate {j['M_plate_about_corner'] / 1e3:.2f}, wall "
    f"{j['M_wall_about_corner'] / 1e3:.2f} kN m/m")

# ## Figures
# The deformed section coloured by vertical stress, the moment diagrams on the structure,
# and the profiles of moments, contact stresses and hoop force.

if comm.rank == 0:
    write_json(out / "results.json", r)
a = scene.plate.radius
figures = [
    plot_section(solution.u, solution.sigma_zz, out / "section.png", extent=1.6 * a,
                 depth_offset=scene.embedment, title=scene.title,
                 soil_cells=solution.domain.cells("soil"), structure=r),
    plot_moment_diagrams(r, out / "moments.png", title=scene.title),
    plot_structure_profiles(r, out / "profiles.png", title=scene.title),
]
say("\nresults: " + str(out / "results.json"))
say("figures: " + ", ".join(str(f) for f in figures if f is not None))

# The demo ends with its own checks: equilibrium, and the joint's moment balance.

assert eq["relative_error"] < 1e-8 and eq["contact_relative_error"] < 1e-8
assert np.isclose(j["M_plate_about_corner"], j["M_wall_about_corner"], rtol=2e-2)
