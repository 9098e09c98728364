"""Studies made of many analyses: parameter sweeps (over MPI, resumable) and the first-order
excess of a nonlinear soil."""
