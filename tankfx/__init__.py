"""tankfx: axisymmetric analysis of a cylindrical storage tank, its foundation and the soil.

Typical use::

    from tankfx import load_scene, analyse
    solution = analyse(load_scene("scene.toml"))
    print(solution.results["w0"])
"""
import dolfinx_solver  # noqa: F401  (must be imported before dolfinx / petsc4py)

from .scene import Scene, SceneError, load_scene
from .analysis import Solution, analyse
from .solve import SolveError
from ._mpi import abort_on_uncaught_exception

# Under mpiexec, an exception that one rank does not catch (say, rank 0 failing to write a
# file) would leave the other ranks waiting in their next collective forever: abort the
# whole run instead, after the traceback is printed. A serial run is left alone.
abort_on_uncaught_exception()

__all__ = ["Scene", "SceneError", "load_scene", "Solution", "analyse", "SolveError"]
__version__ = "0.1.0"
