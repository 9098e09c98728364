"""Zero-thickness soil-structure interface: a penalty on the displacement jump, with the
paper's Mohr-Coulomb law (Eqs. 6-16) as an active set per interface element.

The jump is ``j = u_soil - u_face`` (soil minus the structure's contact face). With the soil's
outward normal ``n`` (which is the structure's ``n``: up under the plate, inward on the
embedded wall) and the tangent ``t``, the traction the soil exerts on the structure is
``T = sigma_n n + tau t`` with

    stick      sigma_n = k_n (j.n)   tau = k_s (j.t)                    (Eq. 6)
    slip       sigma_n = k_n (j.n)   tau = s (c + sigma_n tan phi)      (Eqs. 7-8, 13)
    separated  sigma_n = 0           tau = 0                            (Eq. 9)

``sigma_n`` is positive in compression (the paper's convention); ``s`` is the sign of the
trial shear. Every case is ``sigma_n = k_n (j.n)``, ``tau = k_s (j.t) + mu sigma_n + c_s`` with
per-element coefficients (k_n, k_s, mu, c_s), so one pair of compiled forms serves all
states: ``bonded`` is stick everywhere, ``smooth`` is k_s = 0 everywhere, and the Mohr-Coulomb
iteration only changes the coefficients.

With ``states = "element"`` (the default), as in the paper (Eqs. 11-12), the state belongs
to an interface element (a facet): it is decided from the element's average normal and
tangential jump. With ``states = "node"`` it belongs to each node of the soil's trace, where
the interface is integrated by the Gauss-Lobatto rule on those nodes (the same functions
decide it, from the node's jump; the coefficients are then DG_k fields with the nodes at
the Gauss-Lobatto points, see :class:`tankfx.model.tank.TankModel`). The stiffnesses default to
``PENALTY_FACTOR`` times the soil modulus at the facet over the facet length: the compliance
this adds is h / (factor a) of the foundation's (about 2e-6 at the default mesh), so the
bonded and smooth limits are reproduced; ``normal_stiffness`` / ``shear_stiffness`` of the
scene (Pa/m) replace them.
"""
from __future__ import annotations

import math
from enum import IntEnum

import numpy as np
import ufl

from .mohr_coulomb import shear_strength

#: k = PENALTY_FACTOR * E_soil / h when the scene gives no interface stiffness.
PENALTY_FACTOR = 1.0e3


class ContactState(IntEnum):
    """The state of an interface carrier (an element, or a node), the one encoding used by
    the law, the iterations, the fields and the results (``contact_status``: its ``label``).

    NONE marks a carrier off the interface (no soil facing it). REBONDED is reported only: a
    carrier separated at a stage's start and closed at its end (the law itself knows stick,
    slip and separated). The numbers are stored in fields and evaluated at stations, where
    they are rounded back to a state: they must not change.
    """
    NONE = -1
    STICK = 0
    SLIP = 1
    SEPARATED = 2
    REBONDED = 3

    @property
    def label(self) -> str:
        """The state's name in results.json and the reports ("stick", "none", ...)."""
        return self.name.lower()

    @property
    def vtk_code(self) -> int:
        """Its number in the VTK files, 0 for none upward (a viewer's colour map starts at
        0)."""
        return int(self) + 1

    @classmethod
    def nearest(cls, value: float) -> "ContactState":
        """The state a field's value at a point stands for (rounded: an interpolated value
        between carriers); NONE for anything else."""
        code = int(round(value))
        return cls(code) if cls.NONE <= code <= cls.REBONDED else cls.NONE


STICK, SLIP, SEPARATED, REBONDED = (ContactState.STICK, ContactState.SLIP,
                                    ContactState.SEPARATED, ContactState.REBONDED)


def tractions(jump, n, t, k_n, k_s, mu=0.0, c=0.0):
    """(sigma_n, tau) of a jump: normal (compression positive) and shear along t."""
    sigma_n = k_n * ufl.dot(jump, n)
    return sigma_n, k_s * ufl.dot(jump, t) + mu * sigma_n + c


def interface_form(j_trial, j_test, n, t, k_n, k_s, mu, r, measure):
    """The jump-dependent part of the interface's virtual work, T(j) . dj, 2 pi r weighted
    (not symmetric where mu != 0: the friction couples the shear to the normal jump)."""
    sigma_n, tau = tractions(j_trial, n, t, k_n, k_s, mu)
    return (sigma_n * ufl.dot(j_test, n) + tau * ufl.dot(j_test, t)) * 2.0 * math.pi * r * \
        measure


def interface_load(j_test, t, c, r, measure):
    """The constant part, c_s (dj . t), moved to the right-hand side."""
    return -c * ufl.dot(j_test, t) * 2.0 * math.pi * r * measure


def element_states(jn, jt, k_n, k_s, cohesion, tan_phi):
    """Mohr-Coulomb state of each interface element from its average jump (numpy arrays).

    An opening jump (j.n < 0) separates the element (no tension); a closed one sticks if the
    trial shear k_s (j.t) is within c + sigma_n tan phi, and slips on that limit otherwise.
    Returns (status, sign): the state and the sign of the trial shear (the slip direction).
    """
    sigma_n = k_n * jn
    trial = k_s * jt
    limit = shear_strength(sigma_n, cohesion, tan_phi)        # Eq. 13
    status = np.where(jn < 0.0, SEPARATED, np.where(np.abs(trial) <= limit, STICK, SLIP))
    return status, np.sign(trial)


def state_coefficients(status, sign, k_n, k_s, cohesion, tan_phi):
    """The traction coefficients (k_n, k_s, mu, c_s) that realise each element's state."""
    kn = np.where(status == SEPARATED, 0.0, k_n)
    ks = np.where(status == STICK, k_s, 0.0)
    mu = np.where(status == SLIP, sign * tan_phi, 0.0)
    c = np.where(status == SLIP, sign * cohesion, 0.0)
    return kn, ks, mu, c
