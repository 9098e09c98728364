"""Command line: ``tankfx run SCENE.toml --out DIR`` (also ``python -m tankfx run ...``).

Writes ``DIR/results.json``, ``DIR/tankfx.log``, ``DIR/report.html`` (the calculation
report: one self-contained page, figures inline) and ``DIR/report.md`` (the same in
Markdown), the profiles as CSV files (``DIR/profiles/``: surface, axis, plate,
wall), the figures (``DIR/section.png``;
``stress_level.png`` for a hyperbolic soil; ``moments.png``, ``profiles.png``,
``contact.png`` with a plate, ``settlement.png`` without) and the fields for ParaView
(``DIR/fields/``: soil.pvd, plate.vtp, wall.vtp); ``--no-figures`` and ``--no-fields``
leave them out; ``--force`` replaces them (and removes those of ours the new run would not
write, so that none of an earlier run is left beside the new results).
A bad scene, an existing output that would be overwritten, or a failed solve ends with a
one-paragraph message and a non-zero exit code, never a Python traceback.

``tankfx check FILE`` validates a scene (or a sweep and every case it makes) without
solving: it prints what the scene resolves to and which parts an analysis would build and
iterate; ``--resolved`` prints the scene file with every default written out, ``--mesh``
meshes it and counts the unknowns.
"""
from __future__ import annotations

import argparse
import logging
import os
import sys
from pathlib import Path

from . import __version__
from .analysis import analyse, mesh_grading_warning
from .fem.solvers import SolveError
from .iterations.stage import stage_plan
from .laws.biot import stratum_coefficients
from .mesh import build_domain, estimate, geometry_of, resource_problem
from .model.build import build_model
from .results.fields import FIELD_FILES, PROFILE_FILES, write_fields, write_profiles
from .results.figure_choices import FIGURES, SECTION_QUANTITIES, section_problem
from .results.html import write_report_html
from .results.io import write_json
from .results.report import summary_table, write_report
from .scene.plausible import geometry_warnings
from .scene.scene import load_scene, read_toml
from .scene.sections import SceneError
from .scene.text import member_text, ringwall_text, stratum_constants
from .studies.sweep import case_text, load_sweep, run_sweep

#: the exit codes of ``tankfx run`` (and ``check``, ``sweep``): 0 the results are valid; 2
#: the input is refused (nothing is written); 3 the analysis failed (results.json says what
#: and where, with what converged); 4 it ran, but a part of the results lies outside its
#: model's range (results.json's ``validity`` says which)
EXIT_OK, EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_NOT_VALID = 0, 2, 3, 4


#: where ``tankfx run`` writes the fields for ParaView, and its report, under --out
FIELDS = Path("fields")


#: and the profiles as CSV files
PROFILES = Path("profiles")


REPORT, REPORT_HTML = "report.md", "report.html"


def setup_logging(out: Path | None, rank: int, append: bool = False) -> None:
    logger = logging.getLogger("tankfx")
    logger.setLevel(logging.INFO)
    logger.handlers.clear()
    logger.propagate = False
    if rank != 0:
        logger.addHandler(logging.NullHandler())
        return
    console = logging.StreamHandler(sys.stdout)
    console.setFormatter(logging.Formatter("tankfx: %(message)s"))
    logger.addHandler(console)
    if out is not None:
        fh = logging.FileHandler(out / "tankfx.log", mode="a" if append else "w")
        fh.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
        logger.addHandler(fh)


def _fail(msg: str, code: int, label: str = "error") -> int:
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank == 0:         # every rank fails alike: one message is enough
        print(f"tankfx: {label}: {msg}", file=sys.stderr)
    return code


def _make_out(out: Path, comm, subdirs=()) -> str | None:
    """Create the output directory and the ``subdirs`` the run will write into on rank 0,
    each checked writable; the reason one cannot be, the same on every rank (None when all
    are there), before any work is done."""
    problem = None
    if comm.rank == 0:
        for d in (out, *(out / s for s in subdirs)):
            try:
                if d.exists() and not d.is_dir():
                    raise NotADirectoryError(0, "a file, not a directory")
                d.mkdir(parents=True, exist_ok=True)
                if not os.access(d, os.W_OK | os.X_OK):
                    raise PermissionError(0, "not writable")
            except OSError as e:             # a file of that name, a read-only place, ...
                problem = (f"{'--out ' if d == out else ''}{d}: cannot write there "
                           f"({e.strerror or e}); choose another --out"
                           + ("" if d == out else " or make it writable"))
                break
    return comm.bcast(problem)


def cmd_run(args) -> int:
    from mpi4py import MPI


    comm = MPI.COMM_WORLD
    out = Path(args.out)
    # every check that can refuse happens before any work, identically on all ranks
    try:
        scene = load_scene(args.scene)
    except SceneError as e:
        return _fail(f"{args.scene}: {e}", EXIT_BAD_INPUT)
    if args.coarse:
        scene = scene.with_coarse_mesh()
    if args.figures and (problem := section_problem(scene, args.section)):
        return _fail(f"{args.scene}: {problem}", EXIT_BAD_INPUT)
    if not args.allow_large:
        # (rank 0's answer for all, as analyse's)
        problem = comm.bcast(resource_problem(scene, estimate(scene, comm.size))
                             if comm.rank == 0 else None)
        if problem:
            return _fail(f"{args.scene}: {problem}", EXIT_BAD_INPUT)
    target = out / "results.json"

    ours = [target, out / REPORT, out / REPORT_HTML,
            *(out / PROFILES / f for f in PROFILE_FILES),
            *([out / f for f in FIGURES] if args.figures else []),
            *([out / FIELDS / f for f in FIELD_FILES] if args.fields else [])]
    existing = [str(p) for p in ours if p.exists()]
    if existing and not args.force:
        return _fail(f"{', '.join(existing)} exist(s); choose another --out or add --force to "
                     "overwrite", EXIT_BAD_INPUT)
    subdirs = [PROFILES] + ([FIELDS] if args.fields else [])
    if (problem := _make_out(out, comm, subdirs)) is not None:
        return _fail(problem, EXIT_BAD_INPUT)
    if args.force and comm.rank == 0:
        # only files of ours: a stress-level figure or a field piece of an earlier run
        # must not stay beside results it does not belong to
        for p in [*ours, *(out / FIELDS).glob("soil*.*vtu")]:
            p.unlink(missing_ok=True)
    comm.barrier()
    setup_logging(out, comm.rank)


    try:
        # (the machine's memory was checked above, before --out was made)
        solution = analyse(scene, comm, allow_large=True)
    except SolveError as e:
        if comm.rank == 0:
            write_json(target, failure_record(scene, e))
        logging.getLogger("tankfx").error("not converged: %s", e)
        return _fail(f"the analysis did not converge: {e}", EXIT_NOT_CONVERGED)
    r = solution.results
    log = logging.getLogger("tankfx")
    log.info("w0 = %.6g m, w_edge = %.6g m, wd = %.6g m", r["w0"], r["w_edge"], r["wd"])
    eq = r["equilibrium"]
    log.info("equilibrium: reaction %.6g N for %.6g N applied%s (relative error %.1e)",
             eq["reaction"], eq["applied_load"],
             f" less {eq['excavation_relief']:.6g} N the pit's excavation relieved"
             if "excavation_relief" in eq else "", eq["relative_error"])
    log.info("summary:\n%s", summary_table(r))
    # results.json is written last but the report: a run stopped before it leaves nothing
    # that reads as a finished analysis
    if comm.rank == 0:
        log.info("profiles (CSV): %s", ", ".join(map(str, write_profiles(r, out / PROFILES))))
    if args.fields:
        log.info("fields for ParaView: %s",
                 ", ".join(map(str, write_fields(solution, out / FIELDS))))
    figures = []
    if args.figures:
        # (PyVista and matplotlib are imported here, where figures are drawn: a run with
        # --no-figures never loads them)
        from .results.figures import write_figures

        figures = write_figures(solution, out, args.section)
        log.info("figures: %s", ", ".join(map(str, figures)))
    if comm.rank == 0:
        write_json(target, r)
        log.info("results: %s; log: %s", target, out / "tankfx.log")
        log.info("report: %s, %s", write_report_html(r, figures, out / REPORT_HTML),
                 write_report(r, figures, out / REPORT))
    valid = r["validity"]["valid"] and all(st.get("valid", True) for st in r.get("stages", []))
    if not valid:
        return _fail("the analysis ran, but its results lie outside the model's range: "
                     + "; ".join(r["validity"]["notes"] or ["an earlier load stage's (see "
                                                            "results.json's stages)"]),
                     EXIT_NOT_VALID, label="not valid")
    return EXIT_OK


def failure_record(scene, e: SolveError) -> dict:
    """results.json of a failed analysis: what failed (the message), the iteration
    history, and what converged before (a load path's converged stages, in full)."""
    record = {"title": scene.title, "converged": False, "error": str(e),
              "history": e.history, "scene": scene.to_dict(resolved=True)}
    # (what the analysis kept: largest_load_carried, collapse, converged_stages)
    record |= e.kept
    if e.kept.get("converged_stages"):
        record["failed_stage"] = len(e.kept["converged_stages"]) + 1
    return record


def describe(scene) -> list[str]:
    """What a scene resolves to and what an analysis of it builds and iterates, in lines."""
    from dataclasses import asdict


    s, a = scene.soil, scene.foundation_radius
    out = [f"scene: {scene.title}"]
    if scene.consolidation is not None:
        permeability, c_v = stratum_coefficients(scene.consolidation, scene.soil.strata)
    for k, st in enumerate(s.strata):
        where = "from the surface" if k == 0 else f"from {st.depth:g} m"
        form = "mixed u-p form" if k in s.mixed_strata else "displacement form"
        consts = stratum_constants(s.model, asdict(st))
        if scene.consolidation is not None:
            form = (f"drained constants; k = {permeability[k]:g} m/s, c_v = {c_v[k]:.3g} "
                    f"m^2/s")
        if k == 0:
            consts += s.law.ground_text(s)
        out.append(f"  soil {where}: E = {st.E:.4g} Pa, nu = {st.nu:g}, E_gradient = "
                   f"{st.E_gradient:g} /m{consts} ({form})")
    if s.unloading_modulus_ratio is not None:
        out.append(f"  unloading along the load path: E_ur = {s.unloading_modulus_ratio:g} x "
                   f"each cell's initial modulus, below its most loaded state")
    out += [f"  {line}" for line in s.law.ground_lines(s)]
    members = scene.to_dict(resolved=True)
    if scene.plate is not None:
        out.append(f"  plate: {member_text('plate', members['plate'], scene.Kp)}")
    else:
        out.append(f"  flexible load on r <= {a:g} m (no structure)")
    if scene.wall is not None:
        out.append(f"  wall: {member_text('wall', members['wall'], scene.Kt)}")
    if scene.ringwall is not None:
        out.append(f"  ringwall: {ringwall_text(members['ringwall'])}")
    if scene.plate is not None:
        ifc = scene.interface
        law = ifc.condition + (f" (tan phi = {ifc.tan_phi:.4g}, c = {ifc.cohesion:g} Pa, "
                               f"states per {ifc.states})" if ifc.has_states
                               else "")
        out.append(f"  interface: {law}")
    ld = scene.load
    loads = [f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {str(v).lower()}"
             for k, v in vars(ld).items() if v not in (0.0, False, None) and k != "load_radius"]
    out.append(f"  load: {', '.join(loads)}"
               + (f"; {len(scene.stages)} load stages" if scene.stages else ""))
    for k, (t, st) in enumerate(zip(scene.stage_times, scene.stages), start=1):
        # a consolidation's load path: what each stage reaches, and when
        changed = [f"{key} = {v:g}" for key, v in vars(st).items()
                   if isinstance(v, float) and v != getattr(ld, key) and key != "load_radius"]
        out.append(f"    stage {k} reached at t = {t / 86400:.4g} days"
                   + (f": {', '.join(changed)}" if changed else " ([load])"))
    m, d = scene.mesh, scene.domain
    out.append(f"  mesh: soil P{m.degree}, edge {m.edge_size:.4g} m ({m.edge_size / a:.3g} a), "
               f"near field {m.near_size:.4g} m, growth {m.growth:g}; domain {d.radius:g} x "
               f"{d.depth:g} m ({d.side} side, {d.base} base); solver {scene.solver.method}")
    grading = geometry_of(scene).surface_grading
    if grading is not None:
        inv_lam, rate = grading
        out.append(f"  mesh graded near the surface as {rate:g} (1/lambda + h), from "
                   f"{max(rate * inv_lam, m.edge_size):.3g} m (the modulus doubles within "
                   f"{inv_lam:.3g} m)")
    warning = mesh_grading_warning(scene)
    if warning:
        out.append(f"  warning: {warning}")
    out += [f"  warning: {w}" for w in geometry_warnings(scene)]
    # the chain that solves a stage, outermost first (the last, a linear solve, in every
    # one)
    iterations = [it.describe(scene) for it in stage_plan(scene)[:-1]]
    parts = ["soil"] + [p for p in ("ringwall", "plate", "wall")
                        if getattr(scene, p) is not None]
    if scene.plate is not None:
        parts.append(f"{scene.interface.condition} interface")
    if any(ld.overturning for ld in (scene.load, *scene.stages)):
        parts.append("the first harmonic (overturning: one more linear solve where a stage "
                     "has it)")
    c = scene.consolidation
    if c is not None:
        parts.append(f"the excess pore pressure (Biot's consolidation, k = "
                     f"{c.permeability:g} m/s, drained at the {c.drainage.replace('_', ' ')})")
    out.append(f"  builds: {', '.join(parts)}; iterates: "
               f"{', '.join(iterations) if iterations else 'nothing (one linear solve a stage)'}")
    kind = scene.analysis.collapse_kind
    if kind is not None and kind.search == "load":
        out.append("  then: the collapse by load (the variable loads raised from the ground "
                   "before them under control of the mean settlement, bracketed to 0.5 %)")
    if kind is not None and kind.bounds:
        a = scene.analysis
        out.append(f"  then: the limit analysis' lower and upper bound on the variable loads' "
                   f"factor (conic programs, Clarabel, on rank 0), refined to a gap of "
                   f"{100 * a.bounds_gap:g} % or {a.bounds_cells} triangles")
    elif kind is not None and kind.search == "strength" and c is not None:
        when = "each stage's end" if scene.stages else "t = 0 and each reported time"
        out.append(f"  and at {when}: the factor of safety (c' and tan phi' divided by a "
                   f"factor under the load then, the pore water held, bisected to 0.5 %)")
    elif kind is not None and kind.search == "strength":
        out.append("  then: the collapse by strength (c and tan phi divided by a factor under "
                   "the load, bisected to 0.5 %)")
    return out


def cmd_check(args) -> int:
    from mpi4py import MPI


    comm = MPI.COMM_WORLD
    say = print if comm.rank == 0 else (lambda *a, **k: None)
    sweep = None
    try:
        if "axes" in read_toml(args.file):
            sweep = load_sweep(args.file)
            say(f"{args.file}: a sweep of {len(sweep.scenes)} cases over "
                f"{', '.join(sweep.axes)}; every case is valid")
            scene = sweep.base
        else:
            scene = load_scene(args.file)
            say(f"{args.file}: valid")
    except SceneError as e:
        return _fail(f"{args.file}: {e}", EXIT_BAD_INPUT)
    for line in describe(scene):
        say(line)
    est = estimate(scene, comm.size)
    say(f"  estimate: {est.text()} (a direct solve on {comm.size} rank(s))")
    # what `tankfx run` refuses as too large for this machine: rank 0's answer for all, as
    # run's. A sweep runs each case on one rank, and fails one too large (it has no
    # --allow-large): each case is estimated.
    if sweep is None:
        problem = comm.bcast(resource_problem(scene, est) if comm.rank == 0 else None)
        if problem and not args.allow_large:
            # a script that checks its scenes before a batch must not be told "valid" for one
            # that `tankfx run` refuses: the same refusal, the same exit code
            return _fail(f"{args.file}: refused by tankfx run: {problem}", EXIT_BAD_INPUT)
        if problem:
            say(f"  beyond this machine's free memory, run with --allow-large: {problem}")
    else:
        large = [f"case {k + 1} ({case_text(case)}): {why}"
                 for k, (case, s) in enumerate(zip(sweep.cases, sweep.scenes))
                 if (why := resource_problem(s, estimate(s), override=None))] \
            if comm.rank == 0 else None
        if large := comm.bcast(large):
            return _fail(f"{args.file}: {len(large)} case(s) too large for this machine, which "
                         f"tankfx sweep would fail: {large[0]}", EXIT_BAD_INPUT)
    if args.mesh:
        domain = build_domain(scene, comm)
        dofs = build_model(scene, domain).dofs()
        cells = domain.mesh.topology.index_map(2).size_global
        say(f"  mesh: {cells} cells; unknowns: "
            + ", ".join(f"{k} {v}" for k, v in dofs.items()) + f", total {sum(dofs.values())}")
    if args.resolved:
        say("\n# the scene resolved, every default written out:\n" + scene.to_toml())
    return 0


def cmd_sweep(args) -> int:
    from mpi4py import MPI


    comm = MPI.COMM_WORLD
    try:
        sweep = load_sweep(args.sweep)      # every case validated before any runs
    except SceneError as e:
        return _fail(f"{args.sweep}: {e}", EXIT_BAD_INPUT)
    out = Path(args.out)
    if (problem := _make_out(out, comm)) is not None:
        return _fail(problem, EXIT_BAD_INPUT)
    if comm.rank == 0:
        if args.force:
            # only what a sweep writes: the case files, the table and the chart
            for f in [*(out / "cases").glob("[0-9][0-9][0-9][0-9].json"),
                      out / "table.csv", out / "charts.png"]:
                f.unlink(missing_ok=True)
    comm.barrier()
    setup_logging(out, comm.rank, append=True)     # a resumed sweep adds to its log
    try:
        run_sweep(sweep, out, comm)
    except SceneError as e:
        return _fail(f"{args.sweep}: {e}", EXIT_BAD_INPUT)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The command line: `tankfx run`, `tankfx check`, `tankfx sweep` (and the site's help
    pages, docs/guide/cli.md, generated from it)."""
    parser = argparse.ArgumentParser(prog="tankfx", description="Axisymmetric tank-foundation-"
                                     "soil analysis (Zaman & Mahmood's method on FEniCSx).",
                                     epilog="exit codes: 0 the results are valid; 2 refused "
                                     "before any work (nothing written); 3 the analysis "
                                     "failed (results.json says what and where); 4 it ran, "
                                     "but a part of the results lies outside its model's "
                                     "range (results.json's validity)")

    parser.add_argument("--version", action="version", version=f"tankfx {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="analyse one scene file")
    run.add_argument("scene", help="scene file (TOML)")
    run.add_argument("--out", required=True, help="directory for results.json and the log")
    run.add_argument("--force", action="store_true",
                     help="overwrite an existing DIR/results.json, figures and fields")
    run.add_argument("--coarse", action="store_true",
                     help="a quick look on a coarse mesh (edge 0.01 a, near field 0.25 a), "
                     "as the demos' --coarse: a few tenths of a per cent on w0")
    run.add_argument("--no-figures", dest="figures", action="store_false",
                     help="do not draw the figures (PNG)")
    run.add_argument("--no-fields", dest="fields", action="store_false",
                     help="do not write the fields for ParaView (DIR/fields/)")
    run.add_argument("--section", default="sigma_zz", choices=list(SECTION_QUANTITIES),
                     help="what section.png shows (default sigma_zz; stress_level for a "
                     "nonlinear soil, pore_pressure with a consolidation)")
    run.add_argument("--allow-large", action="store_true",
                     help="run a scene whose estimated memory exceeds what this machine has "
                     "free (refused otherwise, before meshing)")
    sweep = sub.add_parser("sweep", help="run a parametric study (resumes where it stopped)")
    sweep.add_argument("sweep", help="sweep file (TOML): base scene and axes")
    sweep.add_argument("--out", required=True, help="directory for cases/, table.csv, log")
    sweep.add_argument("--force", action="store_true",
                       help="discard the case files already in --out and start afresh")
    check = sub.add_parser("check", help="validate a scene or sweep file without solving")
    check.add_argument("file", help="scene or sweep file (TOML)")
    check.add_argument("--resolved", action="store_true",
                       help="print the scene with every default written out")
    check.add_argument("--mesh", action="store_true",
                       help="also mesh the scene and count its unknowns")
    check.add_argument("--allow-large", action="store_true",
                       help="check a scene as `tankfx run --allow-large` would: one beyond "
                       "this machine's free memory is reported, not refused (exit 2 otherwise)")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return {"run": cmd_run, "sweep": cmd_sweep, "check": cmd_check}[args.command](args)


if __name__ == "__main__":
    sys.exit(main())
