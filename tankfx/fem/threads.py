"""How many threads numpy's BLAS may use when several tankfx processes share a machine.

numpy's wheels carry their own OpenBLAS, which starts one thread per core and, after each
call, keeps its threads spinning for a while before they sleep. Under ``mpiexec`` every
rank is already one core's worth of work (MUMPS's BLAS is single-threaded), so on 2 ranks
of a 2-core machine numpy's threads take the cores from the other rank's MUMPS, assembly
and collectives. Measured on the nonlinear embedded tank at 274k dofs, 2 ranks, per rank
(2026-11-22, ``OPENBLAS_NUM_THREADS`` 2 against 1): the point evaluations of w0 0.31-0.32
against 0.03 s, the Anderson steps of the soil iteration 0.25-0.29 against 0.05 s, the
matrix assemblies 2.9-3.6 against 2.4-2.6 s. A sweep's ranks (one case each) are as many
processes on the same cores.

So when more than one MPI process runs on this machine, each keeps numpy's BLAS to its
share of the cores (at least one thread). A thread count the user set in the environment
(``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS``, ``MKL_NUM_THREADS``) is left alone, and
so is a serial run (its second core is idle anyway). Without threadpoolctl (an environment
that installed tankfx's dependencies by hand) nothing is limited and the log says how to
do it at launch.
"""
from __future__ import annotations

import functools
import logging
import os

from mpi4py import MPI

USER_SETTINGS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


#: how MPI launchers tell a process how many share its machine (MPICH, Open MPI)
LAUNCHER_SETTINGS = ("MPI_LOCALNRANKS", "OMPI_COMM_WORLD_LOCAL_SIZE")


def ranks_on_this_machine() -> int:
    """The MPI processes sharing this machine, from the launcher's environment (MPICH:
    MPI_LOCALNRANKS, Open MPI: OMPI_COMM_WORLD_LOCAL_SIZE), else all of COMM_WORLD. No
    collective: a sweep's ranks call this a different number of times."""
    for key in LAUNCHER_SETTINGS:
        value = os.environ.get(key, "")
        if value.isdigit() and int(value) > 0:
            return int(value)
    return MPI.COMM_WORLD.size


def cores_per_rank(ranks: int) -> int:
    """This process's share of the machine's cores, at least one: the cores it is bound to
    where the launcher bound it to some of them (``mpiexec -bind-to``), else an equal share
    of all."""
    total = os.cpu_count() or 1
    try:
        mine = len(os.sched_getaffinity(0))
    except AttributeError:                      # (not on macOS)
        mine = total
    return max(1, mine if mine < total else total // ranks)


@functools.cache
def limit_blas_threads() -> int | None:
    """Limit numpy's BLAS to this process's share of the cores, once per process; returns
    the limit, or None where nothing was limited (serial, or the user chose)."""
    ranks = ranks_on_this_machine()
    if ranks <= 1 or any(os.environ.get(key) for key in USER_SETTINGS):
        return None
    share = cores_per_rank(ranks)
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        logging.getLogger("tankfx").warning(
            "threadpoolctl is not installed: numpy's BLAS threads are not limited on %d "
            "processes sharing this machine (slower); pip install threadpoolctl, or launch "
            "with OPENBLAS_NUM_THREADS=%d", ranks, share)
        return None
    threadpool_limits(limits=share, user_api="blas")
    return share
