"""The model protocol: what every model (the tank, a flexible load) offers the iterations,
the analysis and the results, and nothing more. A new model implements it; an iteration
reads and changes a model only through it and the block it works on."""
from __future__ import annotations

from typing import Protocol

from ..mesh import Domain
from ..scene.scene import Scene
from ..scene.sections import Load
from .interface import InterfaceBlock
from .soil import SoilBlock

__all__ = ["Model"]


class Model(Protocol):
    """A block system of the soil and what it carries.

    ``a``, ``L``, ``bcs`` and ``unknowns`` are the block forms, supports and fields a solver
    takes (``entity_maps`` for the blocks on a submesh); ``a_split`` the (fixed, varying)
    parts of ``a`` a direct solver may keep (None: assemble the whole at every solve).
    ``soil`` is the soil block (its secant modulus, memory and pore pressure are what the
    soil's iterations change); ``interface`` the interface block (None without a plate), the
    Mohr-Coulomb iteration's. ``scene`` follows the load set last (:meth:`set_loads`)."""

    scene: Scene
    domain: Domain
    soil: SoilBlock
    interface: InterfaceBlock | None
    a: list
    L: list
    bcs: list
    unknowns: list
    entity_maps: list | None
    a_split: tuple | None
    #: warnings the model's set-up found (the interface's penalty, say)
    warnings: list[str]
    #: the largest load scale of a load path so far, N (0 outside one)
    path_load_scale: float

    @property
    def reference_pressure(self) -> float:
        """p of Eq. 23, Pa."""

    @property
    def applied_load(self) -> float:
        """The downward resultant of the applied loads, N."""

    @property
    def load_scale(self) -> float:
        """The size of the vertical loads, N, for relative equilibrium errors."""

    def dofs(self) -> dict[str, int]:
        """The unknowns of each block (global counts)."""

    def set_loads(self, load: Load) -> None:
        """Apply another load (the forms stay; their constants change)."""

    def begin_stage(self) -> None:
        """Start a load stage (the interface's states so far become the starting guess)."""

    def commit(self) -> None:
        """The state of every block's history now is the one to go on from
        (:class:`tankfx.model.history.History`)."""

    def rollback(self) -> None:
        """Every block's history back to its last committed state."""

    def out_of_balance(self) -> float:
        """||A u - f|| / ||f|| of the current fields under the current coefficients."""

    def block_residuals(self) -> tuple[list[str], "np.ndarray", "np.ndarray"]:
        """Per block (the soil's equilibrium, its flow, the structure): its name, the norm
        of its out-of-balance vector and of its largest term, in its own units."""

    def block_vectors(self, values=None) -> list:
        """Per block, its out-of-balance vector on this rank's dofs, or the current
        coefficients' action on ``values`` (one array per unknown)."""

    def soil_residual(self):
        """The soil's unconstrained residual form a(u, v) - L(v) (its supports' reactions)."""

    def foundation_results(self) -> dict:
        """w0, w_edge, wd, w_mean and M0 (None without a plate) of the current solution."""
