"""The collapse study a scene asks for (``[analysis] collapse``): one object owns its kind
(:class:`tankfx.scene.sections.CollapseKind`: the search by load or by strength, and the
limit analysis' bounds beside a search by load), the state the search by load starts from
(the ground before the load), the searches (:class:`tankfx.iterations.collapse.CollapseSearch`),
the bounds (:func:`tankfx.bounds.scene_bounds.scene_bounds`) and their results.json sections
(built by :mod:`tankfx.results.collapse`); the scene's own converged state is given back
after every search, so that its results and figures are of the scene's load."""
from __future__ import annotations

from dataclasses import dataclass

from .bounds.scene_bounds import scene_bounds
from .fem.blocks import cell_field
from .iterations.collapse import CollapseSearch
from .iterations.status import SoilFailure
from .mesh import heartbeat
from .results.collapse import bounds_record, bounds_words, collapse_record, collapse_words


@dataclass(frozen=True)
class CollapseFindings:
    """A study's results: ``collapse`` (results.json's section) and its fields (the
    mechanism's ``increment`` and each cell's share of yielding points, ``plastic``); with
    the bounds, ``bounds`` (results.json's section) and the upper bound's mechanism
    (``bounds_mechanism``: its triangles' points and cells, the velocity at their
    vertices), else None."""

    collapse: dict
    fields: dict
    bounds: dict | None = None
    bounds_mechanism: dict | None = None


class CollapseStudy:
    """The collapse of a scene's ground, after (or instead of) its own analysis. Built
    before the first load, where it keeps the ground before the load."""

    def __init__(self, scene, model, iterations, solver, comm, log):
        self.kind = scene.analysis.collapse_kind
        self.scene, self.model, self.iterations = scene, model, iterations
        self.solver, self.comm, self.log = solver, comm, log
        # (the state a collapse by load starts from: the ground before the load)
        self.before = self._search().snapshot()
        self._last = None

    @classmethod
    def of(cls, scene, model, iterations, solver, comm, log) -> "CollapseStudy | None":
        """The scene's study, None where it asks none."""
        if scene.analysis.collapse_kind is None:
            return None
        return cls(scene, model, iterations, solver, comm, log)

    def _search(self) -> CollapseSearch:
        return CollapseSearch(self.model, self.iterations, self.solver, self.log)

    def failed(self, e: SoilFailure, load) -> None:
        """The scene's load is not carried: a search by load finds from the ground before
        it the factor (below 1) at which the ground fails, kept in the error
        (``e.kept["collapse"]``); a search by strength has nothing to search from (the
        factor of safety on the strength is below 1), which the message says."""
        if self.kind.search == "load":
            record, _ = self._collapse(load)
            e.kept["collapse"] = record
            e.args = (f"{e}; the collapse search (settlement-controlled, to where the "
                      f"load-settlement curve flattens): {collapse_words(record)}",)
        else:
            e.args = (f"{e}; the factor of safety on the strength is below 1: the ground "
                      f"does not carry the load with its full strength (collapse = "
                      f"\"load\" brackets the share of it that it carries)",)

    def at_milestone(self, bracket: float | None = None,
                     through: float | None = None) -> dict:
        """The search by strength on the state now: a consolidation's milestone (each
        stage's end; without stages t = 0 and every reported time), the pore water held by
        the time stepping (the factor a sudden failure would find). Its record joins the
        milestone's state (``{"collapse": record}``); the last one's is the study's
        :meth:`findings`. ``through``: a check at that factor and the factor in one search
        (:meth:`CollapseSearch.by_strength`)."""
        self._last = self._collapse(self.model.scene.load, bracket, through)
        self.log.info("collapse: %s", collapse_words(self._last[0]))
        return {"collapse": self._last[0]}

    def findings(self) -> CollapseFindings | None:
        """The last milestone's search (:meth:`at_milestone`), or the one :meth:`keep`
        chose; None where there is none."""
        return None if self._last is None else CollapseFindings(*self._last)

    def keep(self, findings: CollapseFindings | None) -> None:
        """The findings the study reports (a fill schedule's last accepted state's, not
        those of the last search it tried)."""
        self._last = None if findings is None else (findings.collapse, findings.fields)

    def run(self, load) -> CollapseFindings:
        """The study after the scene's own analysis of ``load``: the search, and the bounds
        beside a search by load."""
        record, fields = self._collapse(load)
        self.log.info("collapse: %s", collapse_words(record))
        if not self.kind.bounds:
            return CollapseFindings(record, fields)
        with heartbeat("bounding the collapse load (limit analysis)"):
            run, mechanism = scene_bounds(self.scene, self.comm, self.log)
        bounds = bounds_record(self.scene, run, record)
        self.log.info("bounds: %s", bounds_words(bounds))
        return CollapseFindings(record, fields, bounds, mechanism)

    def _collapse(self, load, bracket: float | None = None,
                  through: float | None = None) -> tuple[dict, dict]:
        """The search of the study's kind: by load from the ground before the load, by
        strength from the load's converged state; that state given back afterwards: (its
        record for results.json, its mechanism's fields)."""
        search = self._search()
        end = search.snapshot()
        try:
            with heartbeat(f"searching the collapse by {self.kind.search}"):
                if self.kind.search == "load":
                    search.restore(self.before)
                    outcome = search.by_load(load)
                else:
                    outcome = search.by_strength(*([bracket] if bracket else []),
                                                 through=through)
            p = self.model.soil.plastic
            fields = {"increment": outcome.increment,
                      "plastic": cell_field(self.model.domain.mesh,
                                            p.cell_average(p.plastic, 1)[:, 0],
                                            "plastic_at_collapse")}
            record = collapse_record(outcome, self.model.scene)
        finally:
            search.restore(end)
        return record, fields
