"""How soon a load stage the ground cannot carry is said to fail: a 16 m tank on clay
(s_u = 18 kPa + 1.5 kPa/m) filled to 10 m in two stages, then given 400 kPa more in its last
stage (about three times what the ground carries). The elastoplastic soil's load steps halve
where Newton does not converge, to 1/512 of the stage; a trial whose out-of-balance force
stalls (not halved in NewtonIteration.STALL iterations) is given up at once, else it takes its
whole budget (soil.max_iterations). Both variants in one process, one after the other:

    python benchmarks/failing_stage.py

Prints, per variant, the failing stage's time (from its start to the error), its trials
(converged and not), Newton iterations, and the load carried; writes
results/failing_stage.json.
"""
from __future__ import annotations

import json
import logging
import time
from pathlib import Path

import dolfinx_solver  # noqa: F401

from tankfx import Scene, SoilFailure, analyse
from tankfx.iterations.load_steps import NewtonIteration

OUT = Path(__file__).resolve().parents[1] / "results" / "failing_stage.json"
SCENE = {
    "title": "16 m tank on clay, overloaded in its last stage",
    "soil": {"model": "mohr_coulomb", "E": 6e6, "nu": 0.45, "cohesion": 18e3,
             "cohesion_gradient": 1.5e3, "unit_weight": 17e3, "K0": 0.8},
    "plate": {"radius": 8.0, "thickness": 0.008, "E": 200e9, "nu": 0.3},
    "wall": {"radius": 8.0, "height": 12.0, "thickness": 0.012, "E": 200e9, "nu": 0.3},
    "interface": {"condition": "bonded"},
    "load": {"liquid_unit_weight": 9810.0, "liquid_height": 10.0, "self_weight": True},
    "domain": {"radius": 48.0, "depth": 30.0},
    "stages": [{"liquid_height": 5.0}, {"liquid_height": 10.0},
               {"liquid_height": 10.0, "pressure": 400e3}],
}


class StageClock(logging.Handler):
    """The time the last stage began, from the analysis' log."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.last_stage = None

    def emit(self, record):
        if record.getMessage().startswith("load stage 3 of 3"):
            self.last_stage = time.perf_counter()


def run(stall) -> dict:
    NewtonIteration.STALL = stall
    clock = StageClock()
    log = logging.getLogger("tankfx")
    log.setLevel(logging.INFO)
    log.addHandler(clock)
    try:
        analyse(Scene.from_dict(SCENE))
        raise SystemExit("the overloaded stage was carried: the benchmark's scene is wrong")
    except SoilFailure as e:
        seconds = time.perf_counter() - clock.last_stage
        carried = e.kept["largest_load_carried"]
        steps = e.history
        return {"stall": stall, "failing_stage_s": seconds,
                "converged_steps": len(steps),
                "newton_iterations_of_converged_steps": sum(s["iterations"] for s in steps),
                "fraction_carried": carried["fraction_carried"],
                "mean_bearing_pressure_carried": carried["mean_bearing_pressure_carried"],
                "message": str(e)}
    finally:
        log.removeHandler(clock)


def main() -> None:
    default = NewtonIteration.STALL
    rows = [run(default), run(None)]
    NewtonIteration.STALL = default
    print(f"\n{'variant':28s} {'stage s':>8s} {'steps':>6s} {'carried':>8s} {'q kPa':>7s}")
    for r in rows:
        name = (f"stall test ({r['stall']} its)" if r["stall"] else "whole budget")
        print(f"{name:28s} {r['failing_stage_s']:8.1f} {r['converged_steps']:6d} "
              f"{r['fraction_carried']:8.4f} {r['mean_bearing_pressure_carried'] / 1e3:7.1f}")
    print(f"time ratio (stall test / whole budget): "
          f"{rows[0]['failing_stage_s'] / rows[1]['failing_stage_s']:.2f}")
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps({"runs": rows, "date": time.strftime("%Y-%m-%d")}, indent=1))
    print(f"written: {OUT}")


if __name__ == "__main__":
    main()
