"""Zero-thickness soil-structure interface as a penalty on the displacement jump.

The jump is ``j = u_soil - u_face`` (soil minus the structure's contact face). With the soil's
outward normal ``n`` (which is the structure's ``n``: up under the plate, inward on the
embedded wall) and the tangent ``t``, the interface tractions on the structure are

    sigma_n = k_n (j . n)   (positive in compression; the paper's convention)
    tau     = k_s (j . t)   (the shear the soil exerts on the structure, along +t)

``bonded`` uses both stiffnesses, ``smooth`` sets k_s = 0. The penalty stiffness defaults to
``PENALTY_FACTOR`` times the soil modulus at the facet over the facet length: the compliance
it adds is h / (factor a) of the foundation's (about 5e-5 at the default mesh), so the linear
conditions are reproduced, while the condition number grows only by the factor.
"""
from __future__ import annotations

import math

import ufl

__all__ = ["PENALTY_FACTOR", "penalty_form", "tractions"]

#: k = PENALTY_FACTOR * E_soil / h for the bonded and smooth conditions.
PENALTY_FACTOR = 1.0e3


def penalty_form(j_trial, j_test, n, t, k_n, k_s, r, measure):
    """The interface energy's bilinear form, 2 pi r weighted."""
    return (k_n * ufl.dot(j_trial, n) * ufl.dot(j_test, n)
            + k_s * ufl.dot(j_trial, t) * ufl.dot(j_test, t)) * 2.0 * math.pi * r * measure


def tractions(jump, n, t, k_n, k_s):
    """(sigma_n, tau) of a jump: normal (compression positive) and shear along t."""
    return k_n * ufl.dot(jump, n), k_s * ufl.dot(jump, t)
