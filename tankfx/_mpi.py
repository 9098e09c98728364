"""MPI behaviour of a tankfx process."""
from __future__ import annotations

import sys

from mpi4py import MPI

__all__ = ["abort_on_uncaught_exception"]


def abort_on_uncaught_exception(comm: MPI.Comm = MPI.COMM_WORLD) -> None:
    """On more than one rank, make an uncaught exception print its traceback and abort
    every rank (``MPI_Abort``), as ``python -m mpi4py`` does, instead of leaving the others
    blocked in a collective: a run under mpiexec then ends with an error, never hangs.
    Exceptions that are caught (by the CLI, by pytest) are not affected."""
    if comm.size == 1 or getattr(sys.excepthook, "_tankfx", False):
        return
    previous = sys.excepthook

    def hook(kind, value, traceback):
        previous(kind, value, traceback)
        sys.stderr.write(f"tankfx: uncaught {kind.__name__} on rank {comm.rank} of "
                         f"{comm.size}: aborting all ranks\n")
        sys.stderr.flush()
        comm.Abort(1)

    hook._tankfx = True
    sys.excepthook = hook
