"""Biot's consolidation of an elastoplastic skeleton (tankfx.iterations.plastic_consolidation):
the Mohr-Coulomb soil with a [consolidation] is an effective-stress soil, each time step
solved by Newton on the skeleton's points and the pore pressure."""
import pytest
from mpi4py import MPI

from tankfx import Scene, analyse

DAY = 86400.0
#: a 5 m flexible plate on a weightless drained skeleton (E, nu), consolidating
SCENE = {"soil": {"E": 5e6, "nu": 0.3}, "plate": {"radius": 5.0, "Kp": 1.0, "E": 30e9,
                                                  "nu": 0.2},
         "load": {"pressure": 50e3},
         "consolidation": {"permeability": 1e-8, "times": [DAY, 10 * DAY]},
         "mesh": {"edge_size": 0.5, "near_size": 2.0}}


FAR_FROM_YIELD = SCENE | {"soil": {"model": "mohr_coulomb", "E": 5e6, "nu": 0.3,
                                   "cohesion": 1e9},
                          "accept": ["soil.cohesion"]}


def test_below_yield_the_plastic_skeleton_consolidates_as_the_linear_one():
    """A Mohr-Coulomb skeleton far from yield (c' = 1 GPa) is the linear skeleton: its
    undrained start, its states at every reported time (settlements, the excess pore
    pressure on the axis and its largest, the isochrones) and its drained limit are the
    linear consolidation's to 1e-8 of each quantity (measured: 1e-12), whether each step is
    one linear solve or Newton's; and the run says the yielding path is not yet verified."""
    linear = analyse(Scene.from_dict(SCENE).with_coarse_mesh()).results
    plastic = analyse(Scene.from_dict(FAR_FROM_YIELD).with_coarse_mesh()).results
    a, b = linear["consolidation"], plastic["consolidation"]
    assert len(a["at_times"]) == len(b["at_times"]) == 3
    for one, two in zip([a["drained"], *a["at_times"]], [b["drained"], *b["at_times"]]):
        for key in ("w0", "w_edge", "wd", "M0"):
            assert two[key] == pytest.approx(one[key], rel=1e-8, abs=1e-12), key
        for key in ("axis_pore_pressure", "max_pore_pressure"):
            assert two[key] == pytest.approx(one[key], rel=1e-8), key
    scale = max(abs(p) for iso in a["isochrones"]["pore_pressure"] for p in iso)
    for one, two in zip(a["isochrones"]["pore_pressure"], b["isochrones"]["pore_pressure"]):
        assert max(abs(x - y) for x, y in zip(one, two)) <= 1e-8 * scale
    assert plastic["soil"]["model"] == "mohr_coulomb" and plastic["soil"]["iterations"] > 0
    assert plastic["soil"]["plastic_points"] == 0
    assert any("not yet verified" in w for w in plastic["warnings"])
    assert not any("not yet verified" in w for w in linear["warnings"])


@pytest.mark.mpi
@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="needs mpiexec -n 2 (make test-mpi)")
def test_serial_and_two_ranks_consolidate_the_same_plastic_skeleton():
    """The coupled Newton path (the skeleton's points beside the pore pressure, split over
    the ranks): every state of the history the same on one rank and on all, to 1e-8."""
    scene = Scene.from_dict(FAR_FROM_YIELD).with_coarse_mesh()
    parallel = analyse(scene, MPI.COMM_WORLD).results["consolidation"]
    serial = analyse(scene, MPI.COMM_SELF).results["consolidation"]
    assert len(parallel["history"]) == len(serial["history"]) > 10
    for p, s in zip([parallel["drained"], *parallel["history"]],
                    [serial["drained"], *serial["history"]]):
        for key in ("w0", "wd", "max_pore_pressure", "axis_pore_pressure"):
            assert p[key] == pytest.approx(s[key], rel=1e-8), key
