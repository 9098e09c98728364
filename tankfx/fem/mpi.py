"""MPI behaviour of a tankfx process."""
from __future__ import annotations

import sys
import time
import traceback

from mpi4py import MPI


def abort_on_uncaught_exception(comm: MPI.Comm = MPI.COMM_WORLD) -> None:
    """On more than one rank, make an uncaught exception print its traceback and abort
    every rank (``MPI_Abort``), as ``python -m mpi4py`` does, instead of leaving the others
    blocked in a collective: a run under mpiexec then ends with an error, never hangs.
    Exceptions that are caught (by the CLI, by pytest) are not affected."""
    if comm.size == 1 or getattr(sys.excepthook, "_tankfx", False):
        return
    def hook(kind, value, tb):
        # one write, then a moment for mpiexec to forward it: MPI_Abort kills the ranks,
        # and output still in the launcher's pipes was measured to be lost (only the
        # traceback's first line arrived)
        text = "".join(traceback.format_exception(kind, value, tb))
        sys.stderr.write(f"{text}tankfx: uncaught {kind.__name__} on rank {comm.rank} of "
                         f"{comm.size}: aborting all ranks\n")
        sys.stderr.flush()
        time.sleep(0.5)
        comm.Abort(1)

    hook._tankfx = True
    sys.excepthook = hook
