"""How a tankfx process takes memory from the operating system.

Every numeric factorisation of MUMPS allocates its work arrays (hundreds of MB at 200k
dofs) and frees them when the factors are replaced. glibc's malloc serves such blocks with
``mmap`` and gives them back with ``munmap``, so each of the ~14 factorisations of a
nonlinear analysis faults its pages in afresh and the kernel zeroes them: measured on the
nonlinear embedded tank at 274k dofs (``perf``: 1.8 million page faults, 80 % in
``memset``), 6.5 s of system time in a 39.6 s run. Keeping freed blocks in the heap for the
next factorisation cut the system time to 1.0 s and the run to 33.6 s (``benchmarks/
costs.py``) at the same peak memory (0.89 GB), and the same run on 2 ranks 28.9 -> 25.6 s.

The price: memory freed inside the process is kept for reuse rather than returned, so the
process holds its peak until it ends (a notebook that runs one large analysis keeps its
peak). ``TANKFX_KEEP_FREED_MEMORY=0`` in the environment leaves malloc as it was.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import functools
import os

# glibc's mallopt parameters (malloc.h)
_M_TRIM_THRESHOLD = -1


_M_MMAP_MAX = -4


@functools.cache
def keep_freed_memory() -> bool:
    """Make glibc's malloc serve every block from the heap (no ``mmap``) and never trim it,
    once per process. Returns whether it is in effect: False where the C library is not
    glibc (macOS, musl) or the environment opts out."""
    applied = False
    if os.environ.get("TANKFX_KEEP_FREED_MEMORY", "1") != "0":
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
            mallopt = libc.mallopt
        except (OSError, AttributeError):
            mallopt = None
        if mallopt is not None:
            mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
            # glibc returns 1 on success; both or neither: a heap that is never trimmed
            # but still mmaps its large blocks would gain nothing
            applied = bool(mallopt(_M_MMAP_MAX, 0)) and bool(
                mallopt(_M_TRIM_THRESHOLD, 2**31 - 1))
    return applied
