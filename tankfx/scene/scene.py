"""The scene: one validated description of a tank-foundation-soil problem.

A scene is read from a TOML file (every key: ``docs/scene-keys.md``) into frozen dataclasses.
All checks happen here, before any mesh is built, and all problems found are reported in one
:class:`SceneError` whose message names each offending key and how to fix it.

Units are SI throughout: metres, pascals, newtons per cubic metre.
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ..laws.rigidity import Kp_from_thickness
from .checks import (
    check_analysis,
    check_consolidation,
    check_fill,
    check_discretisation,
    check_domain,
    check_interface,
    check_load,
    check_plate,
    check_ringwall,
    check_soil,
    check_top,
    check_wall,
    stage_times_of,
)
from .reader import SPEC, Reader
from .resolve import (
    domain_of,
    given,
    interface_of,
    load_of,
    mesh_of,
    plate_of,
    soil_of,
    solver_of,
    wall_of,
)
from .sections import (
    E_FROM_KEYS,
    Analysis,
    Consolidation,
    DomainSize,
    Fill,
    Interface,
    Load,
    MeshOptions,
    Plate,
    Ringwall,
    SceneError,
    Soil,
    SolverOptions,
    Wall,
    plain,
    toml_value,
    vertical_load,
)


@dataclass(frozen=True)
class Scene:
    """A validated scene: one tank, its foundation, the soil and the loads, in SI units.

    Frozen: a changed scene is a new one (:meth:`with_changes`), validated again. Read one
    with :func:`load_scene` or :meth:`from_dict`; every key, its unit, default and range is
    in docs/scene-keys.md.

    Attributes
    ----------
    soil : Soil
        The ground: its law (linear, hyperbolic, Duncan & Chang), moduli and layers.
    load : Load
        The loads: pressure, liquid, gas, roof, self-weight, overturning moment and shear.
    domain : DomainSize
        The soil domain's radius and depth, and its far side's and base's conditions.
    mesh : MeshOptions
        Element degree and sizes (defaults from the foundation's radius).
    plate : Plate or None
        The foundation plate (None: a flexible load).
    wall : Wall or None
        The tank wall (None: a plate alone).
    interface : Interface
        Bonded, smooth or Mohr-Coulomb contact between structure and soil.
    ringwall : Ringwall or None
        A concrete ringwall under the wall.
    solver : SolverOptions
        Direct (MUMPS) or iterative solver.
    consolidation : Consolidation or None
        A saturated soil's settlement in time (None: the soil answers at once).
    title : str
        The scene's name, in the log and the report.
    stages : tuple of Load
        A load path's total loads (``[[stages]]``), solved in order; empty for one load.
    stage_times : tuple of float
        With a consolidation, when each stage's load is reached, s.
    accept : tuple of str
        The keys whose values outside their plausible range the scene means.
    accepted : tuple of str
        What each accepted value is, in words (recorded in the results).
    """

    soil: Soil
    load: Load
    domain: DomainSize
    mesh: MeshOptions
    plate: Plate | None = None
    wall: Wall | None = None
    interface: Interface = field(default_factory=Interface)
    ringwall: Ringwall | None = None
    solver: SolverOptions = field(default_factory=SolverOptions)
    #: time-dependent settlement of a saturated soil (None: the soil answers at once)
    consolidation: Consolidation | None = None
    title: str = "tankfx scene"
    #: a load path: the total loads analysed in order on one mesh, the interface's states
    #: carried from each to the next (``[[stages]]`` tables of a scene file, each the
    #: [load] keys that change); empty: the one load of [load]
    stages: tuple[Load, ...] = ()
    #: with [consolidation]: the time (s) at which each stage's load is reached, linearly
    #: from the stage before's (from no load at t = 0 for the first; a time equal to the
    #: one before: at once); empty without stages or without a consolidation
    stage_times: tuple[float, ...] = ()
    #: the keys whose values outside their plausible range the scene means (its top-level
    #: ``accept``; tankfx.scene.plausible), and what each of them is, in words
    accept: tuple[str, ...] = ()
    accepted: tuple[str, ...] = field(default=(), compare=False)
    #: what is asked beyond the response to the load: the ground's collapse
    analysis: Analysis = field(default_factory=Analysis)
    #: the safe filling of the tank in time (None: the [load] or the [[stages]] as given)
    fill: Fill | None = None

    @property
    def foundation_radius(self) -> float:
        """Radius of the plate, or of the flexible load where there is no plate, m."""
        return self.plate.radius if self.plate is not None else self.load.load_radius

    @property
    def embedment(self) -> float:
        return self.plate.embedment if self.plate is not None else 0.0

    @property
    def Kp(self) -> float | None:
        """Relative rigidity of the plate-soil system, Eq. 21 (surface soil modulus)."""
        if self.plate is None:
            return None
        return Kp_from_thickness(self.plate.thickness, self.plate.radius, self.plate.E,
                                 self.soil.E, self.soil.nu)

    @property
    def Kt(self) -> float | None:
        """Relative rigidity of the wall-soil system, Eq. 22 (surface soil modulus)."""
        if self.wall is None:
            return None
        return Kp_from_thickness(self.wall.thickness, self.wall.radius, self.wall.E,
                                 self.soil.E, self.soil.nu)

    def unloading_stages(self) -> list[int]:
        """The load stages (counted from 1) whose vertical load is less than the largest of
        the stages before them: unloading."""
        loads = [vertical_load(ld, self.plate, self.wall, self.ringwall)
                 for ld in self.stages]
        return [k + 1 for k in range(1, len(loads)) if loads[k] < max(loads[:k]) * (1 - 1e-12)]

    def with_coarse_mesh(self) -> "Scene":
        """The same scene on a coarse mesh (edge 0.01 a, near field 0.25 a, growth 0.3):
        a quick look, as the demos' ``--coarse`` and the tests use it; a few tenths of a
        per cent on w0, a few per cent on the edge moments."""
        a = self.foundation_radius
        return self.with_changes(mesh={"edge_size": 0.01 * a, "near_size": 0.25 * a,
                                       "growth": 0.3})

    def with_changes(self, **sections: dict[str, Any]) -> "Scene":
        """A new scene with some keys of some sections changed, validated again.

        Parameters
        ----------
        **sections : dict
            Per section, the keys to change: ``scene.with_changes(soil={"E": 80e6},
            mesh={"degree": 3})``. A key changed to None is removed, back to its default
            (``plate={"annular_width": None, "annular_thickness": None}``). A plate or wall
            given by Kp or Kt keeps that rigidity when the soil changes; a ``thickness``
            replaces it.

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
            The changed scene has problems (every one listed).
        """
        d = self.to_dict()
        if self.plate is not None and "load_radius" not in sections.get("load", {}):
            # (the plate's radius, resolved into the load: not the user's, and not to be
            # checked again as theirs: an accepted small plate would be refused by it)
            d.get("load", {}).pop("load_radius", None)
        for sec, changes in sections.items():
            if isinstance(changes, dict):
                if sec == "soil" and "E" not in changes and set(E_FROM_KEYS) & set(changes):
                    d["soil"].pop("E", None)      # 1/a or K p_a: the new one's
                for K in ("Kp", "Kt"):            # a thickness replaces a rigidity, and back
                    if sec in d and "thickness" in changes:
                        d[sec].pop(K, None)
                    if sec in d and K in changes:
                        d[sec].pop("thickness", None)
                d.setdefault(sec, {}).update(changes)
                d[sec] = {k: v for k, v in d[sec].items() if v is not None}
            else:
                d[sec] = changes
        return Scene.from_dict(d)

    def to_dict(self, resolved: bool = False) -> dict[str, Any]:
        """The scene as a plain dict, re-readable by :meth:`from_dict` (resolved values; a
        plate or wall given by Kp or Kt as that, so that its rigidity is held when the soil
        changes). ``resolved``: with the thickness of such a member too (what the results
        record; not re-readable)."""
        out: dict[str, Any] = {"title": self.title}
        if self.accept:
            out["accept"] = list(self.accept)
        for name in ("soil", "plate", "wall", "ringwall", "interface", "load", "domain",
                     "mesh", "solver", "consolidation", "analysis", "fill"):
            part = getattr(self, name)
            if part is not None:
                out[name] = plain(part)
        if not out["analysis"] or self.fill is not None:
            # (a fill's collapse = "strength" is its own, not the user's)
            del out["analysis"]
        if self.consolidation is not None and not self.consolidation.times:
            del out["consolidation"]["times"]
        if self.fill is not None:
            # (the fill's height, resolved into the load: a changed fill.height is the
            # load's too)
            out["load"].pop("liquid_height", None)
        # (re-readable: without what the soil's law derives itself; resolved: with it)
        written = (lambda t: t) if resolved else self.soil.law.written
        out["soil"] = written(out["soil"])
        if self.soil.layers:
            out["soil"]["layers"] = [written(plain(layer)) for layer in self.soil.layers]
        else:
            out["soil"].pop("layers", None)
        if self.plate is not None and not self.plate.annular_width:
            out["plate"].pop("annular_width")
        for name, K in (("plate", "Kp"), ("wall", "Kt")):
            if name in out and K in out[name] and not resolved:
                del out[name]["thickness"]          # the rigidity decides it
        if self.ringwall is not None and self.ringwall.fill_E is None:
            out["ringwall"].pop("fill_nu")          # no fill
        if self.wall is not None:
            if self.wall.courses:       # the courses replace the one thickness
                del out["wall"]["thickness"]
                out["wall"]["courses"] = [{"height": h, "thickness": t}
                                          for h, t in self.wall.courses]
            else:
                del out["wall"]["courses"]
        if self.plate is None:
            del out["interface"]
        elif not self.interface.has_states:
            for key in ("cohesion", "tan_phi", "on_cycle", "states"):
                out["interface"].pop(key, None)
        if self.stages:
            # each stage as the [load] keys it changes, as written in a scene file: a
            # change of [load] (a sweep's axis, with_changes) then reaches every stage
            # that does not set that key itself
            out["stages"] = [{k: v for k, v in plain(ld).items() if out["load"].get(k) != v}
                             for ld in self.stages]
            for stage, t in zip(out["stages"], self.stage_times):
                stage["time"] = t
        return out

    def to_toml(self) -> str:
        """The scene as a scene file with every value resolved (the defaults written out,
        the thickness a Kp gives as a comment); :func:`load_scene` reads it back to an equal
        scene."""
        d = self.to_dict()
        lines = [f"title = {toml_value(d.pop('title'))}",
                 *([f"accept = {toml_value(d.pop('accept'))}"] if "accept" in d else []), ""]
        stages = d.pop("stages", [])
        for name, values in d.items():
            layers = values.pop("layers", []) if name == "soil" else []
            lines += [f"[{name}]", *(f"{k} = {toml_value(v)}" for k, v in values.items())]
            member = getattr(self, name) if name in ("plate", "wall") else None
            if member is not None and ("Kp" in values or "Kt" in values):
                lines.append(f"# (thickness = {member.thickness!r} m, from the rigidity)")
            lines.append("")
            for layer in layers:
                lines += ["[[soil.layers]]",
                          *(f"{k} = {toml_value(v)}" for k, v in layer.items()), ""]
        for stage in stages:
            lines += ["[[stages]]", *(f"{k} = {toml_value(v)}" for k, v in stage.items()), ""]
        return "\n".join(lines)

    @staticmethod
    def from_dict(data: dict[str, Any]) -> "Scene":
        return _parse_scene(data)

    @staticmethod
    def from_toml(path: str | Path) -> "Scene":
        return load_scene(path)


def _parse(data: dict[str, Any], empty_load: bool = False) -> Scene:
    """The scene of a dict, checked; ``empty_load``: a [load] without any load is allowed
    (a stage of a consolidation's load path: the tank emptied). Every problem is found
    first (each section's keys, then the rules between them), then the scene is built."""
    if not isinstance(data, dict):
        raise SceneError([f"a scene must be a table of sections, got {type(data).__name__}"])
    if "stages" in data:
        if "fill" in data:
            raise SceneError(["[[stages]] with [fill]: the schedule makes the load path itself "
                              "(its steps and holds); remove the [[stages]] or the [fill]"])
        return _parse_path(data)
    data = _filled(data)
    soil_raw, raw_layers = data.get("soil"), None
    if isinstance(soil_raw, dict) and "layers" in soil_raw:
        raw_layers = soil_raw["layers"]
        data = {**data, "soil": {k: v for k, v in soil_raw.items() if k != "layers"}}
    rd = Reader(data)
    check_top(rd, data)
    secs = {name: rd.section(name) for name in SPEC}
    soil, plate, wall, load = secs["soil"], secs["plate"], secs["wall"], secs["load"]
    layers = check_soil(rd, soil, raw_layers, "consolidation" in data)
    check_plate(rd, plate, wall)
    check_wall(rd, wall, plate, data)
    interface = secs["interface"] or {}
    choices = check_interface(rd, interface, data)
    check_load(rd, load, plate, wall, data, empty_load)
    flexible = "plate" not in data
    mesh, domain = secs["mesh"] or {}, secs["domain"] or {}
    deg, method = check_discretisation(rd, mesh, secs["solver"] or {}, soil or {}, layers,
                                       flexible)
    # sizes relative to the foundation, where the foundation's size is known
    a = (load or {}).get("load_radius") if flexible else (plate or {}).get("radius")
    check_domain(rd, domain, mesh, a, 0.0 if flexible else (plate or {}).get("embedment", 0.0),
                 layers)
    if secs["ringwall"] is not None:
        check_ringwall(rd, secs["ringwall"], plate, wall, domain, a)
    if secs["analysis"] is not None:
        check_analysis(rd, secs["analysis"], soil or {}, load or {}, plate, secs["wall"],
                       layers, secs["ringwall"])
    if secs["consolidation"] is not None:
        check_consolidation(rd, secs["consolidation"], data, soil or {}, layers, deg, method)
    else:
        for k, layer in enumerate(layers, start=1):
            if "permeability" in layer:
                rd.bad(f"soil.layers[{k}].permeability: only used with a [consolidation] "
                       f"table; remove it or add [consolidation]")
    if secs["fill"] is not None:
        check_fill(rd, secs["fill"], data, soil or {})
    if rd.problems:
        raise SceneError(rd.problems)
    scene = _build(data, secs, layers, choices, deg)
    if scene.consolidation is not None and (bad := _piezometers_outside(scene)):
        raise SceneError(bad)
    return replace(scene, accept=tuple(data.get("accept", ())),
                   accepted=tuple(rd.accepted_outside))


def _filled(data: dict[str, Any]) -> dict[str, Any]:
    """A [fill]'s scene with its [load] at the fill's end (``liquid_height`` = fill.height),
    so that every load rule checks the full tank."""
    fill, load = data.get("fill"), data.get("load", {})
    if not (isinstance(fill, dict) and isinstance(load, dict)) or load.get("liquid_height"):
        return data
    height = fill.get("height")
    if isinstance(height, (int, float)) and not isinstance(height, bool):
        return {**data, "load": {**load, "liquid_height": height}}
    return data


def _piezometers_outside(scene: Scene) -> list[str]:
    """The piezometers that are not in the ground: above its surface, beyond the domain, or
    in an embedded foundation's pit."""
    R, H = scene.domain.radius, scene.domain.depth
    a, D = scene.foundation_radius, scene.embedment
    out = []
    for k, (r, depth) in enumerate(scene.consolidation.piezometers, start=1):
        where = ("beyond the domain's radius" if r > R else "behind the axis" if r < 0.0
                 else "above the ground surface" if depth < 0.0
                 else "below the domain's base" if depth > H
                 else "in the foundation's pit" if r < a and depth < D else None)
        if where is not None:
            out.append(f"consolidation.piezometers[{k}] = [{r:g}, {depth:g}]: {where} (r "
                       f"from 0 to {R:g} m, depth from 0 to {H:g} m below the ground surface"
                       + (f", and below {D:g} m within r < {a:g} m" if D > 0.0 else "")
                       + "); move it into the ground")
    return out


def _parse_path(data: dict[str, Any]) -> Scene:
    """A scene with a load path: the scene of its [load], then each stage as that [load]
    with its keys changed, and a consolidation's times along the path."""
    rest = {k: v for k, v in data.items() if k != "stages"}
    collapse = (data.get("analysis") or {}).get("collapse") \
        if isinstance(data.get("analysis"), dict) else None
    in_time = "consolidation" in data and collapse == "strength"
    if collapse is not None and not in_time:
        raise SceneError([f"analysis.collapse = {collapse!r} with [[stages]]: the collapse "
                          f"is sought for one load, the [load]; remove the [[stages]] (or "
                          f"analyse the path without a collapse; a consolidation's path "
                          f"takes collapse = \"strength\": the factor of safety at the end "
                          f"of every stage)"])
    raw, times = stage_times_of(data["stages"], "consolidation" in data)
    scene = _parse(rest)
    stages = _parse_stages(rest, raw, scene)
    if times and max(scene.consolidation.times) < times[-1]:
        raise SceneError([f"consolidation.times: the last, {max(scene.consolidation.times)!r}"
                          f" s, is before the load path's end (the last stage's time, "
                          f"{times[-1]!r} s); report at least to the end of the path"])
    if times and len({ld.self_weight for ld in stages}) > 1:
        raise SceneError(["stages: self_weight changes along a consolidation's load "
                          "path; the structure's own weight acts from t = 0 (it is built "
                          "before it is loaded): give every stage the same self_weight"])
    return replace(scene, stages=stages, stage_times=times)


def _build(data: dict[str, Any], secs: dict, layers: list, choices: dict[str, str],
           degree: int) -> Scene:
    """The scene of checked sections, every default resolved (:mod:`tankfx.scene.resolve`).
    A Mohr-Coulomb interface under a net uplift is refused here: the net load needs the
    resolved structure."""
    soil = soil_of(secs["soil"], layers)
    plate = plate_of(secs["plate"], soil)
    wall = wall_of(secs["wall"], soil)
    interface = interface_of(secs["interface"] or {}, choices)
    a = plate.radius if plate is not None else secs["load"]["load_radius"]
    load = load_of(secs["load"], a)
    if interface.has_states:
        net = vertical_load(load, plate, wall)
        if net <= 0.0:
            raise SceneError([f"[load]: the net vertical load is {net:.4g} N, upward (uplift): "
                              f"a Mohr-Coulomb interface takes no tension, so nothing would "
                              f"hold the foundation down; use condition = \"bonded\" for an "
                              f"anchored foundation, or add downward load"])
    ring, cons = secs["ringwall"], secs["consolidation"]
    return Scene(soil=soil, load=load,
                 domain=domain_of(secs["domain"] or {}, a, soil.law.domain_factor),
                 mesh=mesh_of(secs["mesh"] or {}, degree, a,
                              plate.embedment if plate is not None else 0.0, plate is None),
                 plate=plate, wall=wall, interface=interface,
                 solver=solver_of(secs["solver"] or {}),
                 ringwall=None if ring is None else Ringwall(**ring),
                 consolidation=None if cons is None else Consolidation(
                     **{**cons, "times": tuple(float(t) for t in cons.get("times", ())),
                        "piezometers": tuple((float(r), float(d)) for r, d in
                                             cons.get("piezometers", ()))}),
                 title=data.get("title", Scene.title),
                 # (a fill's steps are checked by the factor of safety on the strength)
                 analysis=given(Analysis, (secs["analysis"] or {}) | (
                     {"collapse": "strength"} if secs["fill"] is not None else {})),
                 fill=None if secs["fill"] is None else given(Fill, secs["fill"]))


def _parse_stages(data: dict[str, Any], raw, scene: Scene) -> tuple[Load, ...]:
    """Each stage is the scene with its [load] keys changed, and checked as such (every
    load rule applies to every stage)."""
    if not isinstance(raw, list) or not raw or not all(isinstance(st, dict) for st in raw):
        raise SceneError(["stages: a list of load tables, one '[[stages]]' header each, "
                          "followed by the [load] keys that change (e.g. 'pressure = 2e5'); "
                          "an empty table is the [load] itself"])
    problems, loads = [], []
    for k, stage in enumerate(raw, start=1):
        try:
            # (a stage may have no load along a consolidation's path, and where the soil
            # remembers: the tank emptied, the soil keeping what it keeps, by its memory or
            # its plastic strain)
            remembers = isinstance(data.get("soil"), dict) and (
                data["soil"].get("unloading_modulus_ratio") is not None
                or scene.soil.law.keeps_permanent_strain)
            load = _parse({**data, "load": {**data.get("load", {}), **stage}},
                          empty_load="consolidation" in data or remembers).load
        except SceneError as e:
            problems += [f"stages[{k}] (the [load] with its keys changed): {p}"
                         for p in e.problems]
            continue
        if scene.plate is None and load.load_radius != scene.load.load_radius:
            problems.append(f"stages[{k}].load_radius = {load.load_radius!r}: a flexible "
                            f"load's circle is meshed once ({scene.load.load_radius!r} m in "
                            f"[load]); analyse another radius as another scene")
        loads.append(load)
    if not problems and "consolidation" not in data and all(ld.nothing for ld in loads):
        problems.append("stages: no stage applies any load (the path is the [[stages]] "
                        "alone, each the [load] with its keys changed); begin it with an "
                        "empty '[[stages]]' table, which is the [load] itself")
    if problems:
        raise SceneError(problems)
    return tuple(loads)


def read_toml(path: str | Path, what: str = "scene") -> dict[str, Any]:
    """A TOML file's tables, read as UTF-8 (a byte-order mark is skipped): a file of another
    encoding, or not TOML, is refused with the encoding it seems to be in, or the TOML
    error."""
    p = Path(path)
    if not p.is_file():
        raise SceneError([f"{p}: no such {what} file"])
    raw = p.read_bytes()
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise SceneError([f"{p}: a UTF-16 file (it starts with UTF-16's byte-order mark); "
                          f"save it as UTF-8"])
    try:
        text = raw.decode("utf-8-sig")          # (a UTF-8 byte-order mark is accepted)
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        seems = "Windows-1252 or Latin-1" if _is_text(raw, "cp1252") else "not text"
        raise SceneError([f"{p}: not UTF-8 (byte 0x{raw[e.start]:02x} on line {line}; the file "
                          f"seems {seems}); save it as UTF-8 (tankfx reads scene files as "
                          f"UTF-8, as TOML requires)"]) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise SceneError([f"{p}: not valid TOML: {e}"]) from None


def _is_text(raw: bytes, encoding: str) -> bool:
    try:
        text = raw.decode(encoding)
    except UnicodeDecodeError:
        return False
    return all(c.isprintable() or c in "\r\n\t" for c in text)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a TOML scene file.

    Parameters
    ----------
    path : str or pathlib.Path
        The scene file, TOML in UTF-8 (a byte-order mark is skipped).

    Returns
    -------
    Scene
        The validated scene.

    Raises
    ------
    SceneError
        The file cannot be read, or the scene has problems: every one of them is listed,
        each with its key, its value and the fix, before any mesh is built.
    """
    return _parse_scene(read_toml(path))


def _parse_scene(data: dict[str, Any]) -> Scene:
    """A whole scene (:func:`_parse`), with the checks that need its load path."""
    scene = _parse(data)
    problems = scene.soil.law.scene_problems(scene)
    if problems:
        raise SceneError(problems)
    ratio = scene.soil.unloading_modulus_ratio
    if ratio is not None and len(scene.stages) < 2:
        raise SceneError([f"soil.unloading_modulus_ratio = {ratio!r}: acts only along a load "
                          f"path of two stages or more (one load never unloads); add "
                          f"[[stages]] or remove the key"])
    return scene
