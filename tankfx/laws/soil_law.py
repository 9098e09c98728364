"""What a soil law is to the rest of tankfx: one class per law, its properties declared as
class attributes, so that the scene, the model, the iterations and the results ask the law
instead of branching on the scene's ``soil.model`` word (which
:data:`tankfx.laws.soil_laws.SOIL_LAWS` looks up, once).

A law's numerics (its moduli, its update, what it reports cell by cell) are functions of its
own module (:mod:`tankfx.laws.kondner`, :mod:`tankfx.laws.duncan_chang`). This module, the
registry and those modules import numpy and nothing of UFL or DOLFINx, so that the scene
layer, which is checked before any mesh, can read them.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

#: gamma_w, N/m^3: the pore water's unit weight
WATER_UNIT_WEIGHT = 9810.0
#: the atmospheric pressure, Pa: Duncan & Chang's reference p_a by default
ATMOSPHERIC_PRESSURE = 101325.0


class SoilLaw:
    """The base of every soil law: a linear elastic law's answers, which a law overrides
    where it differs.

    Attributes
    ----------
    word : str
        ``soil.model`` of a scene that takes this law.
    title : str
        The law in words ("Duncan & Chang's soil").
    iteration : str or None
        The iteration that solves a stage of this soil (``"secant"``: Picard on the secant
        modulus, :mod:`tankfx.iterations.secant`); None: one linear solve a stage.
    max_iterations : int or None
        That iteration's default limit (``soil.max_iterations``).
    keys, layer_keys : tuple of str
        The ``[soil]`` and ``[[soil.layers]]`` keys this law uses.
    own_keys : dict of str to dict
        Keys no other law has, declared here: name -> ``type``, ``default`` and the scene
        key's attributes (``unit``, ``meaning``, ``choices``, ``limit``:
        :class:`tankfx.scene.keys.Key`); the scene's sections take them as fields.
    iteration_keys : tuple of str
        The ``[soil]`` keys of its iteration (``tolerance``, ``max_iterations``).
    E_keys : tuple of str
        The keys that set the soil's E (1/a, K p_a): a change of one drops an E resolved
        from the old value.
    all_mixed : str or None
        Why every stratum is solved in the mixed u-p form whatever its nu (None: a stratum's
        nu decides).
    displacement_form_only : bool
        Every stratum is solved in the displacement form, whatever its nu (the law has no
        mixed form; its checks bound nu).
    keeps_permanent_strain : bool
        Unloaded, it keeps a permanent strain of its own (plastic flow): a stage of a load
        path may take every load off.
    consolidates : bool
        The law takes a ``[consolidation]`` (its E and nu are the drained skeleton's).
    remembers : bool
        ``unloading_modulus_ratio`` applies: a cell below its most loaded state unloads
        along a line.
    unloads_on_curve : bool
        Without that memory, a cell unloads along its loading curve (nonlinear elastic).
    reports : tuple of str
        The cell fields it reports beyond the stresses (``"stress_level"``).
    state_fields : tuple of str
        The soil's fields its iteration changes cell by cell (``"E"``, ``"nu"``), which a
        failed stage restores.
    fixed_constants : bool
        Its constants are the stratum's, not the stress's (a derivative with respect to one
        of them is defined: :mod:`tankfx.studies.excess`).
    at_points : bool
        Its state lives at the quadrature points of the soil's forms (an elastoplastic
        law): :meth:`point_law` gives it there (:class:`tankfx.laws.point_law.PointLaw`).
    has_bounds : bool
        Its strength is one the limit analysis bounds (Mohr-Coulomb's cones, what
        :meth:`limit_strength` gives); else ``why_no_bounds`` says why not.
    """

    word: ClassVar[str] = "linear"
    title: ClassVar[str] = "a linear elastic soil"
    iteration: ClassVar[str | None] = None
    iteration_keys: ClassVar[tuple[str, ...]] = ()
    max_iterations: ClassVar[int | None] = None
    keys: ClassVar[tuple[str, ...]] = ()
    layer_keys: ClassVar[tuple[str, ...]] = ()
    own_keys: ClassVar[dict[str, dict]] = {}
    E_keys: ClassVar[tuple[str, ...]] = ()
    all_mixed: ClassVar[str | None] = None
    displacement_form_only: ClassVar[bool] = False
    keeps_permanent_strain: ClassVar[bool] = False
    consolidates: ClassVar[bool] = False
    remembers: ClassVar[bool] = False
    unloads_on_curve: ClassVar[bool] = False
    reports: ClassVar[tuple[str, ...]] = ()
    #: the stress level's label in the figures (its ratio of what to what)
    stress_level_label: ClassVar[str] = "q / q_ult"
    state_fields: ClassVar[tuple[str, ...]] = ()
    fixed_constants: ClassVar[bool] = True
    at_points: ClassVar[bool] = False
    has_bounds: ClassVar[bool] = False
    why_no_bounds: ClassVar[str] = "the limit analysis takes Mohr-Coulomb's strength"
    #: the domain's default size in foundation radii where the law needs its own (None:
    #: the scene's, a half-space of 10000 a)
    domain_factor: ClassVar[float | None] = None

    @classmethod
    def stratum_text(cls, st: Mapping[str, Any]) -> str:
        """A stratum's constants of this law in words, after its E and nu (``st``: a
        :class:`tankfx.scene.sections.Layer` as a dict, or a stratum of results.json's
        scene); nothing for a linear soil."""
        return ""

    # -- the scene's rules and defaults, on the tables as read (plain dicts) --------------

    @classmethod
    def check(cls, table: dict, given: Mapping, name: str, p_a: float | None = None
              ) -> list[str]:
        """The law's problems with a ``[soil]`` table (``name`` "soil") or a layer's
        (``given``: its keys as written; ``p_a``: the soil's reference pressure, where the
        law has one): a linear stratum needs its E."""
        if "E" in given:
            return []
        if name == "soil":
            return ["soil.E: missing; add 'E = ...' under [soil] (Pa)"]
        return [f"{name}.E: missing; add 'E = ...' (Pa, the modulus at the layer's top)"]

    @classmethod
    def check_ground(cls, soil: dict, layers: list[dict]) -> list[str]:
        """The law's problems with the ground as a whole (its strata, top down)."""
        return []

    @classmethod
    def resolve_ground(cls, soil: dict) -> dict[str, Any]:
        """The law's values of the whole ground, defaults resolved (``Soil`` fields)."""
        return {}

    @classmethod
    def resolve_stratum(cls, table: dict, ground: Mapping[str, Any]) -> dict[str, Any]:
        """A stratum's E and the law's constants of it, defaults resolved (``Layer``
        fields), from its checked table and the ground's values."""
        return {"E": table["E"]}

    @classmethod
    def written(cls, table: dict) -> dict:
        """A resolved stratum's table (``[soil]`` or a layer's, plain) as a scene file would
        give it: without what the law derives itself (its E from the stress), so that the
        scene re-read derives it again; by default as it is."""
        return table

    @classmethod
    def finish(cls, soil):
        """The resolved [soil] (:class:`tankfx.scene.sections.Soil`, its layers read) with
        what the law derives from the whole ground (a modulus that follows the stress at
        rest); by default as it is."""
        return soil

    # -- the numerics ---------------------------------------------------------------------

    @classmethod
    def scene_problems(cls, scene) -> list[str]:
        """What of a resolved scene this law cannot take (messages naming the key, the
        value and the fix); none for a linear soil."""
        return []

    @classmethod
    def symmetric_tangent(cls, soil) -> bool:
        """Whether its stiffness (or tangent) matrix is symmetric for this ``soil``."""
        return True

    @classmethod
    def point_law(cls, soil, depth):
        """The law at points at ``depth`` (m, N) of a resolved [soil]: a
        :class:`tankfx.laws.point_law.PointLaw` where ``at_points``."""
        raise NotImplementedError(f"{cls.title} has no state at points")

    @classmethod
    def limit_strength(cls, soil, depth) -> dict:
        """Its strength for the bounds where ``has_bounds``, per depth (m, N): Mohr-Coulomb's
        ``c_top`` (Pa, the cohesion's line in z = -depth at z = 0), ``dc_dz`` (Pa/m),
        ``phi`` (radians) and the unit weight ``gamma`` (N/m^3)."""
        raise NotImplementedError(f"{cls.title}: {cls.why_no_bounds}")

    @classmethod
    def limit_strata(cls, soil, top: float, bottom: float):
        """Rows (z, c, phi, gamma) at the depth ``top`` (m) and at each stratum's top below
        it, above ``bottom`` (inf: the half-space): where the bounds' far field under an
        open box is checked."""
        raise NotImplementedError(f"{cls.title}: {cls.why_no_bounds}")

    @classmethod
    def limit_notes(cls, soil) -> tuple[list[str], bool]:
        """What of the soil the bounds do not take, in words, and whether its flow is
        associated (the bounds are then its own)."""
        return [], True

    @classmethod
    def undrained_strength(cls, soil, depth: float) -> float | None:
        """s_u at ``depth`` (m) where the soil is Tresca's (undrained, phi = 0 in every
        stratum), else None: what a bearing capacity factor N_c = q / s_u divides by."""
        return None

    #: whether the ground it makes can fail (a collapse load or a strength factor is its to
    #: compute), and if not, why, in words
    fails = False
    why_it_cannot_fail = "it is elastic without limit: its ground never fails"

    @classmethod
    def initial_modulus(cls, soil, depth, st):
        """Each cell's initial modulus where it is not its stratum's E(h) (a numpy array at
        the cells' ``depth``, ``st`` their strata's constants); None: E(h), interpolated."""
        return None

    @classmethod
    def cell_reports(cls, soil, eps_min, eps_max, deviator, depth, converged=None,
                     unloading=None) -> dict:
        """The cell fields it reports (``reports``), by name, from each cell's principal
        strains, deviator stress (Pa) and depth (m), the constants its iteration converged
        on (``converged``, its status's data; None: its strata's) and which cells unload
        (None without a memory)."""
        return {}

    # -- the scene in words -------------------------------------------------------------

    @classmethod
    def ground_text(cls, soil) -> str:
        """The law's constants of the whole ground in words, after the surface stratum's
        (``soil``: the scene's :class:`tankfx.scene.sections.Soil`)."""
        return ""

    @classmethod
    def ground_warnings(cls, soil, bottom: float) -> list[str]:
        """What the law changed of the ground at rest down to ``bottom`` (m), for the
        analysis's warnings; none by default."""
        return []

    @classmethod
    def ground_lines(cls, soil) -> list[str]:
        """Lines of their own on the ground's state (a water table), for `tankfx check`."""
        return []


class LinearElastic(SoilLaw):
    """Hooke's law with E(h) = E_s (1 + lambda h) (Eq. 3), per stratum: one linear solve a
    stage; the only law a consolidation takes."""

    word = "linear"
    title = "a linear soil"
    consolidates = True


class ElastoplasticSoil(SoilLaw):
    """What every elastoplastic law shares (its state at the points, Newton's iteration in
    load steps, its permanent strain, a ground that fails), and its cell reports."""

    iteration = "newton"
    #: with a [consolidation], an effective-stress skeleton
    consolidates = True
    iteration_keys = ("max_iterations",)
    #: Newton iterations of a load step before it is halved
    max_iterations = 25
    reports = ("plastic", "stress_level")
    #: its state (stress, plastic strain, its own) lives at the forms' quadrature points
    at_points = True
    #: its ground fails: a collapse load and a strength factor are its to compute
    fails = True
    #: the displacement form only (its checks bound nu)
    displacement_form_only = True
    #: its plastic strain stays when the load comes off
    keeps_permanent_strain = True

    @classmethod
    def cell_reports(cls, soil, eps_min, eps_max, deviator, depth, converged=None,
                     unloading=None):
        """``plastic``: the share of a cell's points that yield (1: all); ``stress_level``:
        the law's mobilised strength of its mean stress, 1 at the strength. From the Newton
        iteration's status (zeros before it has run)."""
        if converged is None:
            return {"plastic": np.zeros_like(depth), "stress_level": np.zeros_like(depth)}
        return {"plastic": converged["plastic"], "stress_level": converged["stress_level"]}


def words(laws, test) -> str:
    """The words of the laws that pass ``test``, as a message lists them ('"a" or "b"')."""
    return " or ".join(f'"{law.word}"' for law in laws if test(law))
