"""The Mohr-Coulomb interface's iteration (Eqs. 6-16): the active set of stick, slip and
separation of a tank's interface (:class:`tankfx.model.interface.InterfaceBlock`), solved to a
fixed point.

:mod:`tankfx.laws.interface` holds the law (the tractions of each state and the decision from a
jump); this module drives it: solve, decide every element's (or node's) state from its jump,
set the traction coefficients, and repeat until no state changes and the out-of-balance
force is negligible, with the reversed-slip secant law and the holds of a cycling active set
that make it terminate. :mod:`tankfx.laws.kondner` is its counterpart for the soil.
"""
from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ..fem.solvers import SolveError
from ..laws import interface as law
from ..model.interface import InterfaceBlock
from ..model.protocol import Model
from .reversed_slips import ReversedSlips
from .status import Failure, IterationStatus


#: added to a carrier's state in a cycle's key where its slip reversed
REVERSED = 4          # (beyond NONE, STICK, SLIP and SEPARATED, which the law decides)


class InterfaceIteration:
    """The Mohr-Coulomb active-set iteration of a model's interface block (Eqs. 6-16).

    Each pass solves the linear system with the current states, then re-decides every
    element's state from its average jump (:func:`tankfx.laws.interface.element_states`), or
    every node's from its own jump (``states = "node"``; "element" below reads "node"), and
    computes the out-of-balance force of the solution under the new states (the paper's
    excess forces, Eqs. 14-16; the paper re-solves with them on a fixed stiffness, here the
    element's traction law changes instead, which reaches the fixed point in a handful of
    solves). A slip that reversed its direction takes a secant law (see
    :class:`~tankfx.iterations.reversed_slips.ReversedSlips`). The iteration stops when no
    element changes state and the out-of-balance force is below ``MAX_OUT_OF_BALANCE`` of
    the load (every element then satisfies |tau| <= c + sigma_n tan phi and sigma_n >= 0,
    its friction along its slip);
    a state that recurs (a cycling active set) is held in the weaker state
    (``on_cycle = "hold"``) or refused (``"stop"``); after ``max_iterations`` solves, a
    fourth cycle, or separation everywhere it raises :class:`~tankfx.fem.solvers.SolveError`
    with the history.
    """

    max_iterations = 50
    #: a converged state's out-of-balance force, relative to the load vector, at most
    MAX_OUT_OF_BALANCE = 1e-6
    #: state changes after which a carrier is held: in single_pass, and for node states in
    #: run() (element states in run() are held when the whole active set repeats)
    MAX_FLIPS = 4
    #: a carrier held separated may be pressed into by the soil by at most this fraction of
    #: the largest soil displacement: a hold at a contact zone's edge leaves it unloaded
    #: with a jump near zero, while a hold of carriers whose tractions no state decides (an
    #: interface far stiffer than the soil) leaves the soil pressing through it
    MAX_HELD_PENETRATION = 0.02

    def __init__(self, model: Model, interface: InterfaceBlock):
        self.model, self.interface = model, interface
        self.forms = interface.jump_forms()
        self.owned = np.flatnonzero(interface.in_contact[:interface.n_carrier_owned])
        # a partition-independent order of the carriers: position, then the element's
        # midpoint (a node is shared by two elements)
        x = interface.S.tabulate_dof_coordinates()[self.owned, :2]
        mids = dmesh.compute_midpoints(interface.mesh, 1,
                                       interface.carrier_cell[self.owned])[:, :2]
        keys = np.concatenate(interface.mesh.comm.allgather(np.round(np.hstack([x, mids]),
                                                                     12)))
        self.order = np.lexsort((keys[:, 3], keys[:, 2], keys[:, 1], keys[:, 0]))
        self.history: list[dict] = []
        ifc = interface.settings
        self.tan_phi = ifc.tan_phi if ifc.tan_phi is not None else 0.0
        # reversed slips (tankfx.iterations.reversed_slips): which carriers are on the
        # secant law, which may restart stuck, and the slip direction of the states last
        # solved
        n = interface.n_carrier
        self.slips = ReversedSlips(interface, self.owned, self.tan_phi)
        # slips on the secant law in the states this iteration starts from (a load path's,
        # a time step's or a soil iteration's last solution: k_s > 0 and no friction
        # coefficient): re-decided, they take the plain slip law along their jump (the
        # secant law's converged form), a change of law that the state does not show
        self.carried_secant = interface.mesh.comm.allreduce(int(np.any(
            ((interface.status == law.SLIP) & (interface.k_s.x.array[:n] > 0))[self.owned])))
        # single_pass: state changes per carrier, and the state it is held in (NONE: none)
        self.flips = np.zeros(n, dtype=int)
        self.held = np.full(n, law.ContactState.NONE)

    def _applied_tractions(self, jn, jt) -> tuple:
        """The normal and shear tractions (sigma, tau) of each carrier under the model's
        current coefficients: those the last solve applied, for its jumps."""
        m = self.interface
        kn, ks, mu, c = (f.x.array[:m.n_carrier] for f in (m.k_n, m.k_s, m.mu, m.c_s))
        sigma = kn * jn
        return sigma, ks * jt + mu * sigma + c

    def _set_states(self, status, sign, jn, jt):
        """Make ``status`` the model's states and set the traction coefficients that realise
        them, the secant ones on the reversed slips (from the jumps ``jn``, ``jt`` of the
        last solve, under the coefficients still set). Returns (mask of secant carriers, the
        secant stiffnesses to solve with next) or None when there are none."""
        m, ifc = self.interface, self.interface.settings
        # what the last solve used, before the coefficients change
        k_used = m.k_s.x.array[:m.n_carrier].copy()
        tau_used = self._applied_tractions(jn, jt)[1]
        solved_states = m.status.copy()
        m.status[:] = status
        for f, v in zip((m.k_n, m.k_s, m.mu, m.c_s), law.state_coefficients(
                status, sign, m.stiffness_n, m.stiffness_s, ifc.cohesion, self.tan_phi)):
            f.x.array[:] = np.where(m.in_contact, v, 0.0)
        secant = self.slips.secant & (status == law.SLIP)
        if not m.mesh.comm.allreduce(int(np.any(secant[self.owned]))):
            return None
        k_sec, k_next = self.slips.stiffness(secant, jn, jt, k_used, tau_used, solved_states)
        m.k_s.x.array[:] = np.where(secant, k_sec, m.k_s.x.array)
        m.mu.x.array[:] = np.where(secant, 0.0, m.mu.x.array)
        m.c_s.x.array[:] = np.where(secant, 0.0, m.c_s.x.array)
        return secant, k_next

    def _decide(self, jn, jt) -> tuple:
        """The Mohr-Coulomb state of every carrier from its jumps (NONE off the interface),
        and the sign of its trial shear."""
        m, ifc = self.interface, self.interface.settings
        status, sign = law.element_states(jn, jt, m.stiffness_n, m.stiffness_s,
                                                ifc.cohesion, self.tan_phi)
        return np.where(m.in_contact, status, law.ContactState.NONE), sign

    def _state_key(self) -> tuple:
        """The model's states with their slip directions, partition-independent: what a
        cycle repeats."""
        # (a slip that reversed counts as a state of its own: beyond every ContactState)
        return self._global_status(self.interface.status + REVERSED * (self.slips.slip_sign < 0))

    def element_jumps(self):
        """Normal and tangential jump of each state carrier: an element's average, or a
        node's value (an axis node takes its neighbour's)."""
        return self.interface.cell_averages(self.forms)

    def _global_status(self, status) -> tuple:
        """The state of every interface element, in an order independent of the partition
        (by element midpoint), on every rank."""
        vals = np.concatenate(self.interface.mesh.comm.allgather(status[self.owned]))
        return tuple(vals[self.order].tolist())

    def single_pass(self, inner) -> int:
        """One solve (``inner()``) and one state update (no cycle handling); returns how
        many elements changed state."""
        m = self.interface
        inner()
        jn, jt = self.element_jumps()
        status, sign = self._decide(jn, jt)
        # a slip that reversed takes the secant law, as in run(); its stiffness converges
        # with the soil's iteration
        n_reversed = m.mesh.comm.allreduce(int(np.sum(
            self.slips.track(status, sign)[self.owned])))
        # an element that keeps changing state sits at the edge of a zone inside it: after
        # MAX_FLIPS changes it is held in the weaker of its last two states, as in run()
        held = self.held != law.ContactState.NONE
        hold, weaker = self._flip_holds(status, held, " during the soil iteration")
        self.held = np.where(hold, weaker, self.held)
        status = np.where(held, self.held, status)
        changed = n_reversed + m.mesh.comm.allreduce(
            int(np.sum(status[self.owned] != m.status[self.owned])))
        self._set_states(status, sign, jn, jt)
        held = m.mesh.comm.allreduce(int(np.sum(self.held[self.owned] >= 0)))
        self.history.append({"iteration": len(self.history) + 1, "changed": changed,
                             "frozen": held})
        if changed == 0:
            self._check_holds(self.held == law.SEPARATED, jn)
        return changed

    def _flip_holds(self, status, exempt, where: str = "") -> tuple:
        """Count each carrier's state changes against the model's states (not those in
        ``exempt``, already held); returns the carriers that reach MAX_FLIPS now and the
        weaker of their last two states (separated, else slip). With on_cycle = "stop" such
        a carrier is refused instead."""
        m = self.interface
        flipped = (status != m.status) & ~exempt
        self.flips += flipped
        hold = flipped & (self.flips >= self.MAX_FLIPS)
        n_hold = m.mesh.comm.allreduce(int(np.sum(hold[self.owned])))
        if n_hold and m.settings.on_cycle == "stop":
            raise SolveError(
                f"the interface's active set cycles: {n_hold} {m.carrier_name}(s) changed "
                f"state {self.MAX_FLIPS} times{where}; interface.on_cycle = \"hold\" holds "
                f"them in the weaker state and goes on", self.history, code=Failure.CYCLES)
        weaker = np.where((status == law.SEPARATED) | (m.status == law.SEPARATED),
                          law.SEPARATED, law.SLIP)
        return hold, weaker

    def _check_holds(self, held_separated, jn) -> None:
        """Refuse a converged state whose carriers held separated are pressed into by the
        soil by more than MAX_HELD_PENETRATION of the largest soil displacement."""
        m = self.interface
        comm = m.mesh.comm
        into = np.where(held_separated, jn, 0.0)[self.owned]
        deepest = comm.allreduce(float(np.max(into, initial=0.0)), op=MPI.MAX)
        scale = comm.allreduce(float(np.max(np.abs(self.model.soil.u.x.array),
                                            initial=0.0)),
                               op=MPI.MAX)
        if deepest <= self.MAX_HELD_PENETRATION * scale:
            return
        what = m.carrier_name
        n = comm.allreduce(int(np.sum(into > self.MAX_HELD_PENETRATION * scale)))
        raise SolveError(
            f"the interface iteration held {n} {what}(s) in the separated state although the "
            f"soil presses into them, by up to {deepest:.2e} m ({deepest / scale:.0%} of the "
            f"largest soil displacement): their tractions change sign from one solve to "
            f"the next, which no state at a contact zone's edge explains. The usual cause is "
            f"an interface far stiffer than the soil (interface.normal_stiffness, "
            f"interface.shear_stiffness): lower them, leave them out for the default, or "
            f"take a state per node (interface.states = \"node\"), whose tractions do not "
            f"oscillate so", self.history, code=Failure.HELD_PENETRATION)

    def reversed_slips(self) -> int:
        """How many state carriers reversed their slip and took the secant law."""
        return self.slips.count()

    def run(self, inner, log) -> IterationStatus:
        """Solve (``inner()``), re-decide the states, until none changes and the
        out-of-balance force is negligible (see the class); returns its status, or raises
        SolveError with the history."""
        m = self.interface
        comm = m.mesh.comm
        self._seen = {self._state_key(): 0}
        self._states = {0: m.status.copy()}
        self._frozen = np.zeros(len(m.status), dtype=bool)
        self._forced = m.status.copy()
        self._freezes = 0
        previous = None
        log.info("Mohr-Coulomb interface: c = %g Pa, tan phi = %g; iterating on the element "
                 "states", m.settings.cohesion, self.tan_phi)
        log.info("  it  changed   stick    slip  separ.  frozen  traction change  "
                 "out-of-balance   time s")
        for it in range(1, self.max_iterations + 1):
            t0 = time.perf_counter()
            inner()
            jn, jt = self.element_jumps()
            previous, change = self._traction_change(jn, jt, previous)
            status, sign = self._redecide(jn, jt)
            reversed_ = self.slips.track(status, sign)
            moved_ = (status != m.status)[self.owned]
            moved = comm.allreduce(int(np.sum(moved_)))
            changed = comm.allreduce(int(np.sum(moved_ | reversed_[self.owned])))
            secant = self._set_states(status, sign, jn, jt)
            # the out-of-balance force of this solution under the re-decided states (and
            # secant stiffnesses): the paper's excess forces (Eqs. 14-16); zero to round-off
            # once nothing changes
            excess = self.model.out_of_balance()
            if secant is not None:  # the next solve takes the secant stiffnesses extrapolated
                m.k_s.x.array[:] = np.where(secant[0], secant[1], m.k_s.x.array)
            counts, n_frozen = self._record(it, status, changed, change, excess, t0, log)
            if changed == 0 and excess <= self.MAX_OUT_OF_BALANCE:
                return self._converged(it, status, jn, n_frozen, excess, change)
            if counts[0] + counts[1] == 0:
                raise SolveError("the interface separated everywhere: nothing holds the "
                                 "foundation (is the net load upward?)", self.history,
                                 code=Failure.SEPARATED)
            self._states[it] = m.status.copy()
            if (changed == 0 and secant is not None) or (changed and not moved) \
                    or (changed == 0 and it == 1 and self.carried_secant):
                # a change of law, not of state: the secant slips converge by the
                # out-of-balance force alone; new reversals (each carrier reverses once)
                # take the secant law; carried secant slips became plain ones (stopping
                # here, as at a lost accuracy, stopped a stage holding the same load). A
                # state that recurs after them is not a cycle
                self._seen = {self._state_key(): it}
                continue
            if changed == 0:
                raise SolveError(
                    f"the interface iteration stopped with no {m.carrier_name} changing state "
                    f"but an out-of-balance force of {excess:.1e} of the load (above "
                    f"{self.MAX_OUT_OF_BALANCE:g}): the linear solve lost accuracy",
                    self.history, code=Failure.LOST_ACCURACY)
            self._hold_a_cycle(it, log)
        raise SolveError(f"the interface iteration did not converge in {self.max_iterations} "
                         f"solves", self.history, code=Failure.MAX_ITERATIONS)

    def _traction_change(self, jn, jt, previous) -> tuple:
        """The tractions of the state just solved (what the structure actually felt) and
        their relative change from the last solve's (None after the first: JSON has no
        infinity)."""
        comm = self.interface.mesh.comm
        sigma, tau = self._applied_tractions(jn, jt)
        traction = np.concatenate([sigma[self.owned], tau[self.owned]])
        norm = np.sqrt(comm.allreduce(float(traction @ traction)))
        change = None if previous is None else np.sqrt(comm.allreduce(
            float((traction - previous) @ (traction - previous)))) / max(norm, 1e-300)
        return traction, change

    def _redecide(self, jn, jt) -> tuple:
        """The states the jumps ask for, the held carriers kept in theirs."""
        status, sign = self._decide(jn, jt)
        status = np.where(self._frozen, self._forced, status)
        if self.interface.node_states:
            # Nodes chatter a few at a time, in ever new combinations, so that the whole
            # active set seldom repeats (the cycle test): a node that has changed state
            # MAX_FLIPS times is held in the weaker of its last two states, as single_pass
            # holds them (demo tank, tan phi = 10: 10 nodes at the wall's foot held, 13
            # solves; without this no convergence in 200)
            hold, weaker = self._flip_holds(status, self._frozen)
            self._forced = np.where(hold, weaker, self._forced)
            self._frozen |= hold
            status = np.where(self._frozen, self._forced, status)
        return status, sign

    def _record(self, it, status, changed, change, excess, t0, log) -> tuple:
        """The iteration's row of the history (and its log line); returns the counts of
        stick, slip and separated carriers and of the held ones."""
        comm = self.interface.mesh.comm
        counts = [comm.allreduce(int(np.sum(status[self.owned] == k)))
                  for k in (law.STICK, law.SLIP, law.SEPARATED)]
        n_frozen = comm.allreduce(int(np.sum(self._frozen[self.owned])))
        row = {"iteration": it, "changed": changed, "stick": counts[0], "slip": counts[1],
               "separated": counts[2], "frozen": n_frozen, "traction_change": change,
               "out_of_balance": excess, "time_s": time.perf_counter() - t0}
        self.history.append(row)
        log.info("  %2d %8d %7d %7d %7d %7d %16s %14.3e %8.2f", it, changed, *counts,
                 n_frozen, "-" if change is None else f"{change:.3e}", excess,
                 row["time_s"])
        return counts, n_frozen

    def _converged(self, it, status, jn, n_frozen, excess, change) -> IterationStatus:
        """The record of a converged state (its held separated carriers checked)."""
        self._check_holds(self._frozen & (status == law.SEPARATED), jn)
        what = self.interface.carrier_name
        note = f"no {what} changed state; out-of-balance force {excess:.1e} of the load"
        if n_frozen:
            note += (f"; {n_frozen} {what}(s) at the edge of a contact or slip zone "
                     f"alternated between states and were held in the weaker one")
        if change is not None:
            note += f"; traction change {change:.1e}"
        return IterationStatus.of({"converged": True, "iterations": it,
                                   "history": self.history, "frozen_elements": n_frozen,
                                   "criterion": note, "reversed_slips": self.reversed_slips()})

    def _hold_a_cycle(self, it: int, log) -> None:
        """Where the states of this iteration repeat earlier ones (a cycle), the carriers
        whose state differs along it sit at the edge of a zone that falls inside one
        element, where no element state is consistent: hold them in the weaker state
        (separated, else slip) and go on; a second and third cycle get the same; more is a
        failure (as is any cycle with on_cycle = "stop")."""
        m, comm = self.interface, self.interface.mesh.comm
        key = self._state_key()
        seen = self._seen
        if key in seen:
            cycle = [self._states[k] for k in range(seen[key], it + 1)]
            differ = np.any([st_ != cycle[0] for st_ in cycle], axis=0)
            weaker = np.where(np.any([st_ == law.SEPARATED for st_ in cycle], axis=0),
                              law.SEPARATED, law.SLIP)
            n_new = comm.allreduce(int(np.sum(differ[self.owned] & ~self._frozen[self.owned])))
            what = m.carrier_name
            if m.settings.on_cycle == "stop":
                raise SolveError(
                    f"the interface's active set cycles: the {what} states of iteration "
                    f"{it} repeat those of iteration {seen[key]} ({n_new} {what}(s) "
                    f"alternate, at the edge of a contact or slip zone); "
                    f"interface.on_cycle = \"hold\" holds them in the weaker state and "
                    f"goes on, or refine the mesh there", self.history, code=Failure.CYCLES)
            self._freezes += 1
            log.info("  the %s states cycle (iteration %d repeats %d): holding %d "
                     "alternating %s(s) in the weaker state", what, it, seen[key], n_new,
                     what)
            if self._freezes > 3 or n_new == 0:
                raise SolveError(
                    f"the interface's active set cycles: the states of iteration {it} "
                    f"repeat those of iteration {seen[key]} and holding the alternating "
                    f"{what}s did not stop it (try a finer mesh at the contact zone's "
                    f"edge)", self.history, code=Failure.CYCLES)
            self._forced = np.where(differ & ~self._frozen, weaker, self._forced)
            self._frozen |= differ
            self._seen = {}
        self._seen[key] = it


#: solves of the Mohr-Coulomb iteration from a previous solution's states before it starts
#: again from stuck ones (see :meth:`ActiveSet.run`)
CARRIED_STATES_SOLVES = 20


class ActiveSet:
    """The Mohr-Coulomb interface's iteration of a stage, as the analysis composes it
    (:mod:`tankfx.iterations.stage`): ``run(inner, log)`` solves with ``inner()`` and
    re-decides the states until they settle (:class:`InterfaceIteration`), from the states
    so far and, where that fails, once more from stuck ones. With ``one_update`` (inside a
    soil iteration that converges both at once) each ``run`` is one solve and one state
    update, and its status says how many carriers still changed (``unsettled``).

    ``restarts``: the iterations of the analysis that started again from stuck states."""

    name = "interface"
    #: whether the iterations inside it log at debug level only
    quiet_inner = False

    def __init__(self, model: Model, block: InterfaceBlock, one_update: bool = False):
        self.model, self.block = model, block
        # node states are converged inside every soil iteration: updated once per soil
        # iteration they oscillate with the secant moduli (measured: a period-2 cycle,
        # no convergence in 40 iterations, where the nested loop takes 6 solves)
        self.one_update = one_update and not block.node_states
        self.restarts = 0
        #: the status of the stage's last run (None before it)
        self.last: IterationStatus | None = None
        self._passes: InterfaceIteration | None = None

    @classmethod
    def build(cls, model: Model, solver, how) -> "ActiveSet":
        """The stage's active set (``how``: :class:`tankfx.iterations.stage.Composition`)."""
        return cls(model, model.interface, one_update=how.one_update)

    @staticmethod
    def describe(scene) -> str:
        """The iteration in words (``tankfx check``)."""
        return "the Mohr-Coulomb active set"

    def begin_stage(self) -> None:
        """A new stage: its states so far are the starting guess; no pass made yet."""
        self.last = None
        self._passes = None

    def run(self, inner, log) -> IterationStatus:
        status = self._one_update(inner) if self.one_update else self._iterate(inner, log)
        self.last = replace(status, record={**status.record,
                                            "restarts_from_stuck": self.restarts})
        return self.last

    def _one_update(self, inner) -> IterationStatus:
        """One solve and one state update; UNSETTLED while carriers change state."""
        if self._passes is None:
            self._passes = InterfaceIteration(self.model, self.block)
        passes = self._passes
        changed = passes.single_pass(inner)
        return IterationStatus.of(
            {"converged": changed == 0, "iterations": len(passes.history),
             "history": passes.history, "frozen_elements": passes.history[-1]["frozen"],
             "reversed_slips": passes.reversed_slips(),
             "criterion": "one state update per soil iteration, until no element changes "
                          "state"}, unsettled=changed)

    def _iterate(self, inner, log) -> IterationStatus:
        """The Mohr-Coulomb iteration from the states so far (a load path's or a time
        step's last); where it fails from them, once more from the states of a fresh
        analysis (every carrier in contact stuck). The law holds no slip from one solution
        to the next (total loading), so the states so far are only a starting guess, and a
        poor one where the load fell: the small tank's consolidation emptied to 5 % of its
        load cycled its reversed slips for 50 solves from the full tank's states, and
        converged in 4 from stuck ones. The first try has CARRIED_STATES_SOLVES solves."""
        model, block = self.model, self.block
        # (a stuck carrier's coefficients are those of its state: the states say it all;
        # every rank takes the same branch, the iteration's solves being collective)
        fresh = np.all(block.status[block.in_contact] == law.STICK)
        if block.mesh.comm.allreduce(int(fresh), op=MPI.MIN):
            return InterfaceIteration(model, block).run(inner, log)
        carried = InterfaceIteration(model, block)
        # (from a good guess it takes a few solves; a fresh start, a handful more)
        carried.max_iterations = CARRIED_STATES_SOLVES
        try:
            return carried.run(inner, log)
        except SolveError as first:
            if block.settings.on_cycle == "stop" and first.code == Failure.CYCLES:
                raise
            log.info("Mohr-Coulomb interface: no converged state from the previous states "
                     "(%s); once more from every element stuck", first)
            block.set_stuck()
            try:
                result = InterfaceIteration(model, block).run(inner, log)
            except SolveError as second:
                raise SolveError(f"{second} (and from the previous states: {first})",
                                 first.history + second.history, code=second.code) from None
            self.restarts += 1
            return result
