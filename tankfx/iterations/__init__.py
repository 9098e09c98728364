"""The nonlinear iterations and the time stepping: the secant (Picard) iteration of a nonlinear
soil (Eqs. 17-20), the Mohr-Coulomb active set of the interface (Eqs. 6-16), and the time
steps of Biot's consolidation. Each takes a model (the protocol) and the block it changes."""
