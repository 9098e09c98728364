"""The public API (tankfx.__all__) and its logging."""
import logging

import dolfinx_solver  # noqa: F401  (before dolfinx / petsc4py)

import tankfx
from tankfx import Scene, analyse

from conftest import flexible_scene


def test_the_public_api_is_what_all_says():
    expected = {"Scene", "SceneError", "load_scene", "Solution", "analyse", "analyse_path",
                "SolveError", "SoilFailure", "Sweep", "load_sweep", "run_sweep", "write_json",
                "__version__"}
    assert set(tankfx.__all__) == expected
    for name in tankfx.__all__:
        assert getattr(tankfx, name) is not None, name
    assert callable(Scene.with_changes) and Scene.with_changes.__doc__
    assert issubclass(tankfx.SoilFailure, tankfx.SolveError)


def test_analyse_logs_through_logging(caplog):
    """A script that calls analyse sees its progress through the 'tankfx' logger (the CLI
    shows the same records); nothing is printed unless a handler is set."""
    scene = flexible_scene().with_coarse_mesh()
    with caplog.at_level(logging.INFO, logger="tankfx"):
        analyse(scene)
    messages = [r.getMessage() for r in caplog.records if r.name.startswith("tankfx")]
    assert any(m.startswith("mesh: ") and "cells" in m for m in messages), messages
    assert any(m.startswith("dofs: ") for m in messages), messages
