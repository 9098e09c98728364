"""Where a nonlinear solve's time goes: wall seconds and counts by kind of work, summed over
a run on this rank (``TIMES``), for the benchmarks' split of a Newton iteration's time.

Kinds: ``"assembly"`` (the matrix and the right-hand side of a linear solve),
``"factorisation"`` (MUMPS's, where the matrix changed), ``"solve"`` (the triangular solves
and the solve's residual check), ``"return"`` (the stress update at the quadrature points)
and ``"residual"`` (the out-of-balance vectors Newton's test measures).
"""
from __future__ import annotations

import time
from collections import defaultdict
from contextlib import contextmanager

#: kind -> [seconds, calls]
TIMES: dict[str, list] = defaultdict(lambda: [0.0, 0])


def reset() -> None:
    TIMES.clear()


@contextmanager
def timed(kind: str):
    t0 = time.perf_counter()
    try:
        yield
    finally:
        entry = TIMES[kind]
        entry[0] += time.perf_counter() - t0
        entry[1] += 1


def split() -> dict[str, dict]:
    """{kind: {"seconds": s, "calls": n}} of the run so far."""
    return {k: {"seconds": v[0], "calls": v[1]} for k, v in TIMES.items()}
