"""DOLFINx plumbing that knows nothing of tanks: MPI-safe reductions and point evaluation, the
linear solvers and :class:`~tankfx.fem.solvers.SolveError`, block-system helpers, 1D line
meshes, and the process settings (MPI abort, freed memory, BLAS threads)."""
