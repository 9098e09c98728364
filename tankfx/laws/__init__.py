"""The constitutive and structural laws, as pure UFL and numpy functions with no state: the
soil's elasticity (and its mixed u-p form), the shells of the plate and the wall, their first
Fourier harmonic, Biot's consolidation, the interface (one Mohr-Coulomb limit), Kondner's
hyperbolic soil (Eqs. 17-19), Duncan & Chang's, and the relative rigidities (Eqs. 21-23).

Nothing here imports the rest of tankfx: the layers above compose these forms.
"""
