"""The reversed slips of the Mohr-Coulomb iteration: a slip whose direction reverses against
the states last solved (the friction, imposed along the trial shear, drove it the other way)
follows a secant shear law, tau = (c + sigma_n tan phi) j_t / |j_t| (Eq. 13's limit along its
own jump), converged with the out-of-balance force rather than as a discrete state; its
stiffness comes from each element's response line through its last two solves."""
from __future__ import annotations

import numpy as np
from dolfinx import fem

from ..laws import interface as law
from ..laws.mohr_coulomb import shear_strength
from ..model.interface import InterfaceBlock

__all__ = ["ReversedSlips"]


class ReversedSlips:
    """Which carriers of an interface block reversed their slip (``secant``), which may
    first be solved stuck (``stick_first``: not separated during this iteration), the slip
    direction of the states last solved (``slip_sign``), and the secant stiffness of each
    (:meth:`stiffness`). ``owned``: the block's owned carriers in contact."""

    def __init__(self, interface: InterfaceBlock, owned: np.ndarray, tan_phi: float):
        self.interface, self.owned, self.tan_phi = interface, owned, tan_phi
        n = interface.n_carrier
        self.secant = np.zeros(n, dtype=bool)
        self.stick_first = interface.status != law.SEPARATED
        self.slip_sign = np.where(interface.status == law.SLIP, np.sign(
            interface.mu.x.array[:n] + interface.c_s.x.array[:n]), 0.0)
        #: the last solve's (tractions, shear jumps, secant mask, states) for the fit
        self._prev = None

    def track(self, status, sign) -> np.ndarray:
        """Mark the slips whose direction reversed against the states last solved: the
        friction, imposed along the trial shear, drove the slip the other way (the carrier
        sits where the slip stops or turns). From then on its slip traction follows its own
        jump, tau = (c + sigma_n tan phi) j_t / |j_t| (a secant shear stiffness, converged
        with the out-of-balance force, not a discrete state). Returns the new reversals."""
        slip_sign = np.where(status == law.SLIP, sign, 0.0)
        self.stick_first &= status != law.SEPARATED
        reversed_ = (slip_sign * self.slip_sign < 0) & ~self.secant
        self.secant |= reversed_
        self.slip_sign = slip_sign
        return reversed_

    def count(self) -> int:
        """How many state carriers reversed their slip and took the secant law."""
        return self.interface.mesh.comm.allreduce(int(np.sum(self.secant[self.owned])))

    def stiffness(self, secant, jn, jt, k_used, tau_used, solved_states) -> tuple:
        """The secant shear stiffness of the elements whose slip reversed, k = (c + sigma_n
        tan phi) / |j_t| (at most the elastic k_s), and the one to solve with next.

        A reversal says the friction imposed was more than the element needed: it is first
        solved stuck (k = k_s; not where it has been separated during this iteration, at a
        contact zone's edge, where that was measured to make the states chatter). Then each
        element's next stiffness comes from its own response: to the rest of a linear system
        an element is a spring in series, so that its jump and the shear traction it
        applies are related by j = j_free - C tau (j_free its jump free of shear, C the
        rest's compliance at it), whatever the element's law. Fitted through its last two
        solves (stuck, slipping or secant), that line gives the element's state directly:
        stuck where the stuck traction k_s j_free / (1 + C k_s) is within the limit L = c +
        sigma_n tan phi, else slipping with tau = L along j_free and k = L / |j_free - C L|.
        Where the fit says nothing (C <= 0: the two solves' other elements moved more than
        this one, or an element so stiff that its traction did not change) and the traction
        is above 2 L, the stiffness drops a hundredfold; otherwise the plain secant k = L /
        |j|. The fit is not made across a solve where another carrier changed state (the
        rest was another system then: on the demo tank at tan phi = 0.1, node states, such
        a fit took 7 solves instead of 5). Measured
        (docs/development/performance-record.md, 2026-11-25): the
        small tank at tan phi = 0.01 / 0.02 / 0.03 from rest, two coupled reversed
        elements, 10 / 13 / 10 solves, where a secant root of the misfit k |j| - L took
        14 / 23 / 39 (its updates crawled down from k_s while the misfit stayed flat)."""
        m, ifc = self.interface, self.interface.settings
        limit = shear_strength(m.stiffness_n * jn, ifc.cohesion, self.tan_phi)
        ks = np.where(m.stiffness_s > 0, m.stiffness_s, 1.0)
        g = np.minimum(1.0, limit / np.maximum(np.abs(jt) * ks, 1e-300))   # k / k_s
        x = np.where(secant, k_used / ks, g)          # what the last solve used
        prev = self._prev
        new = np.where(secant & self.stick_first, 1.0, g)
        if prev is not None:
            tau0, jt0, was_secant, states0 = prev
            # (the line is the rest's response: not across a change of another's state)
            same_rest = not m.mesh.comm.allreduce(
                int(np.any((states0 != solved_states)[self.owned])))
            fitted = secant & was_secant & (tau0 != tau_used) & same_rest
            C = -(jt - jt0) / np.where(fitted, tau_used - tau0, 1.0)
            ok = fitted & (C > 0)
            C = np.where(ok, C, 0.0)                  # (the rest take g or the drop below)
            j_free = jt + C * tau_used
            stuck = ks * np.abs(j_free) / (1.0 + C * ks) <= limit
            j_slip = np.maximum(np.abs(j_free) - C * limit, 1e-300)
            fit = np.where(stuck, 1.0, limit / (j_slip * ks))
            too_stiff = secant & was_secant & ~ok & (x * np.abs(jt) * ks > 2.0 * limit)
            new = np.where(ok, np.clip(fit, 1e-2 * x, 1.0), np.where(too_stiff, 1e-2 * x, g))
            new = np.where(secant & ~was_secant & self.stick_first, 1.0, new)
        self._prev = (tau_used, jt.copy(), secant.copy(), solved_states)
        # ghost carriers take their owner's values
        out = []
        for values in (g, new):
            field = fem.Function(m.S)
            field.x.array[:] = values
            field.x.scatter_forward()
            out.append(field.x.array[:m.n_carrier] * ks)
        return tuple(out)
