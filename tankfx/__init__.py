"""tankfx: axisymmetric analysis of a cylindrical storage tank, its foundation and the soil.

Typical use::

    from tankfx import load_scene, analyse
    solution = analyse(load_scene("scene.toml"))
    print(solution.results["w0"])

The public API is ``__all__``; the package's layers are described in docs/architecture.md.
``analyse`` and the sweeps log through :mod:`logging` (logger ``"tankfx"``): a script that
wants to see the progress calls ``logging.basicConfig(level=logging.INFO)`` (as the
CLI does).
"""
__version__ = "0.1.0"

import dolfinx_solver  # noqa: F401,E402  (must be imported before dolfinx / petsc4py)

from .analysis import Solution, analyse, analyse_path  # noqa: E402
from .fem.mpi import abort_on_uncaught_exception  # noqa: E402
from .fem.solvers import SolveError  # noqa: E402
from .iterations.status import SoilFailure  # noqa: E402
from .results.io import write_json  # noqa: E402
from .scene import Scene, SceneError, load_scene  # noqa: E402
from .studies.sweep import Sweep, load_sweep, run_sweep  # noqa: E402

# Under mpiexec, an exception that one rank does not catch (say, rank 0 failing to write a
# file) would leave the other ranks waiting in their next collective forever: abort the
# whole run instead, after the traceback is printed. A serial run is left alone.
abort_on_uncaught_exception()

__all__ = ["Scene", "SceneError", "load_scene", "Solution", "analyse", "analyse_path",
           "SolveError", "SoilFailure", "Sweep", "load_sweep", "run_sweep", "write_json",
           "__version__"]
