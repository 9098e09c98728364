"""Axisymmetric tensors as numpy arrays of their (rr, zz, rz, theta) components, per point or
cell (no UFL: the scene's checks and the laws' updates read them)."""
from __future__ import annotations

import numpy as np


def principal_strains(e_rr, e_zz, e_rz, e_tt):
    """(smallest, largest) principal value of axisymmetric tensors per point or cell (numpy:
    their (rr, zz, rz, theta) components; theta is a principal direction): a strain's, or
    a stress's (tension positive)."""
    centre = 0.5 * (e_rr + e_zz)
    radius = np.sqrt((0.5 * (e_rr - e_zz)) ** 2 + e_rz**2)
    eig = np.stack([centre - radius, centre + radius, e_tt])
    return eig.min(axis=0), eig.max(axis=0)
