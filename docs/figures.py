"""The figures of the tutorials and the site (docs/figures/), drawn by the demos themselves.

    python docs/figures.py [DEMO or SWEEP ...]        (make figures)

Runs each demo on its default mesh (a fresh process, from the repository's root, so that
its results go to results/<demo>/) and copies the figures the pages show into
docs/figures/ under the names the pages use. A demo that fails stops the command, and no
figure of it is copied. Then the sweeps of the user guide, whose charts.png it copies.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: demo -> {figure the demo writes in results/<demo>/: name in docs/figures/}
FIGURES = {
    "embedded_tank": {"section.png": "embedded_section.png",
                      "moments.png": "embedded_moments.png",
                      "stress_level.png": "embedded_stress_level.png",
                      "cutaway.png": "embedded_cutaway.png",
                      "contact.png": "embedded_contact.png",
                      "profiles.png": "embedded_profiles.png"},
    "flexible_load": {"section.png": "flexible_section.png",
                      "settlement.png": "flexible_settlement.png"},
    "nonlinear_soil": {"nonlinear_family.png": "nonlinear_family.png"},
    "layered_ground": {"clay_thickness.png": "layered_clay_thickness.png"},
    "tank_on_sand": {"load_path.png": "sand_load_path.png"},
    "steel_tank": {"wall.png": "steel_wall.png", "ringwall.png": "steel_ringwall.png"},
    "seismic_tank": {"overturning_foot.png": "seismic_foot.png", "tilt.png": "seismic_tilt.png"},
    "tank_on_clay": {"consolidation.png": "clay_consolidation.png",
                     "isochrones.png": "clay_isochrones.png",
                     "hydrotest.png": "clay_hydrotest.png",
                     "pore_pressure.png": "clay_pore_pressure.png"},
    "hydrotest": {"hydrotest.png": "hydrotest.png",
                  "contact_emptied.png": "hydrotest_emptied_contact.png"},
}


#: sweep file in demos/sweeps/ -> name in docs/figures/ of its charts.png
SWEEPS = {"kp_interface": "sweep_kp_interface.png", "nu_interface": "sweep_nu_interface.png"}


def main(names: list[str]) -> None:
    demos = [n for n in names if n in FIGURES]
    for k, name in enumerate(demos, 1):
        t = time.perf_counter()
        print(f"[{k}/{len(demos)}] demos/{name}.py ...", flush=True)
        proc = subprocess.run([sys.executable, f"demos/{name}.py"], cwd=ROOT,
                              capture_output=True, text=True)
        if proc.returncode != 0:
            sys.exit(f"demos/{name}.py failed:\n{proc.stdout[-3000:]}{proc.stderr[-3000:]}")
        for source, target in FIGURES.get(name, {}).items():
            shutil.copyfile(ROOT / "results" / name / source, ROOT / "docs" / "figures" / target)
        print(f"    {len(FIGURES[name])} figures in {time.perf_counter() - t:.1f} s", flush=True)
    for name in [n for n in names if n in SWEEPS]:
        t = time.perf_counter()
        print(f"demos/sweeps/{name}.toml ...", flush=True)
        out = ROOT / "results" / "sweeps" / name
        proc = subprocess.run([sys.executable, "-m", "tankfx", "sweep",
                               f"demos/sweeps/{name}.toml", "--out", str(out), "--force"],
                              cwd=ROOT, capture_output=True, text=True)
        if proc.returncode != 0:
            sys.exit(f"the sweep {name} failed:\n{proc.stderr[-3000:]}")
        shutil.copyfile(out / "charts.png", ROOT / "docs" / "figures" / SWEEPS[name])
        print(f"    its chart in {time.perf_counter() - t:.1f} s", flush=True)


if __name__ == "__main__":
    unknown = set(sys.argv[1:]) - set(FIGURES) - set(SWEEPS)
    if unknown:
        sys.exit(f"unknown name(s) {sorted(unknown)}: choose from demos {sorted(FIGURES)} "
                 f"or sweeps {sorted(SWEEPS)}")
    main(sys.argv[1:] or [*FIGURES, *SWEEPS])
