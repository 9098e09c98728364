"""From a scene to a distributed DOLFINx mesh with named cell and facet tags.

The geometry itself lives in ``meshes/axisymmetric_domain.py`` (installed as
``tankfx.meshes.axisymmetric_domain``) so that it can be opened in gmsh on its own. The mesh
is generated on rank 0 and distributed; interior-facet integrals (the interface on facets
that have soil on one side and the tank's void on the other) need the ``shared_facet`` ghost
mode, which is therefore always used.
"""
from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import logging
import os
import threading
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import dolfinx_solver  # noqa: F401  (loads MPI before dolfinx / petsc4py)
import numpy as np
from dolfinx import graph
from dolfinx import mesh as dmesh
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI

from .laws.shell import wall_beta
from .meshes import axisymmetric_domain
from .meshes.axisymmetric_domain import CELL_TAGS, FACET_TAGS, DomainGeometry, build_model
from .scene.scene import Scene

#: The near field, where soil stresses are reported, extends this many foundation radii
#: from the foundation centre.
NEAR_RADIUS = 6.0


#: A soil whose modulus doubles within a depth 1/lambda shorter than the near field's
#: elements gets elements of SURFACE_GRADING x (1/lambda + h) at depth h, out to
#: SURFACE_GRADING_RADIUS foundation radii (docs/theory/method.md, "Mesh").
SURFACE_GRADING = 0.25


SURFACE_GRADING_RADIUS = 2.0


#: Element size at the wall foot, as a fraction of the bending decay length 1/beta.
WALL_ELEMENTS_PER_DECAY = 0.25


log = logging.getLogger("tankfx")


def mesh_cache_dir() -> Path | None:
    """Where generated meshes are kept, keyed by their geometry: ``$TANKFX_MESH_CACHE``, or
    ``$XDG_CACHE_HOME/tankfx/meshes`` (``~/.cache/tankfx/meshes``); ``TANKFX_MESH_CACHE=off``
    turns the cache off. A scene that changes only materials, loads or the interface (most
    sweeps) then skips gmsh: meshing is a third of a linear analysis."""
    env = os.environ.get("TANKFX_MESH_CACHE")
    if env is not None and env.strip().lower() in ("", "0", "off", "no", "false"):
        return None
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "tankfx" / "meshes"


def _cache_file(geom: DomainGeometry, gmsh) -> Path | None:
    root = mesh_cache_dir()
    if root is None:
        return None

    # the key: the geometry, the gmsh version and the meshing code itself
    source = Path(axisymmetric_domain.__file__).read_bytes()
    key = hashlib.sha256(json.dumps(asdict(geom), sort_keys=True).encode() +
                         gmsh.__version__.encode() + source).hexdigest()[:32]
    return root / f"{key}.msh"


@contextlib.contextmanager
def heartbeat(what: str, every: float = 10.0):
    """Log "still <what>: N s" every ``every`` seconds while the body runs (gmsh and MUMPS
    release the GIL while they work, so the timer thread runs beside them)."""
    start = time.perf_counter()
    done = threading.Event()

    def beat():
        while not done.wait(every):
            log.info("still %s: %.0f s", what, time.perf_counter() - start)

    thread = threading.Thread(target=beat, daemon=True)
    thread.start()
    try:
        yield
    finally:
        done.set()
        thread.join()


@dataclass
class Domain:
    """The parent (r, z) mesh and its tags. ``geometry`` records what was meshed."""

    mesh: dmesh.Mesh
    cell_tags: dmesh.MeshTags
    facet_tags: dmesh.MeshTags
    geometry: DomainGeometry

    def facets(self, *names: str) -> np.ndarray:
        """Local indices of the facets carrying any of the named tags."""
        ids = [FACET_TAGS[n] for n in names]
        return np.sort(self.facet_tags.indices[np.isin(self.facet_tags.values, ids)])

    def cells(self, name: str) -> np.ndarray:
        return self.cell_tags.find(CELL_TAGS[name])

    @functools.cached_property
    def cell_midpoints(self) -> np.ndarray:
        """(r, z) of every local cell's midpoint (owned and ghost), in cell order."""
        imap = self.mesh.topology.index_map(2)
        cells = np.arange(imap.size_local + imap.num_ghosts, dtype=np.int32)
        return dmesh.compute_midpoints(self.mesh, 2, cells)[:, :2]

    @property
    def has_void(self) -> bool:
        return self.geometry.wall_radius is not None


def geometry_of(scene: Scene) -> DomainGeometry:
    """The meshed geometry a scene asks for."""
    wall, plate = scene.wall, scene.plate
    wall_size, joints = None, ()

    def resolving(t):
        """Element size that resolves a wall's bending boundary layer, decay length 1/beta."""
        return min(scene.mesh.edge_size,
                   WALL_ELEMENTS_PER_DECAY / wall_beta(wall.radius, t, wall.nu))

    if wall is not None:
        wall_size = resolving(wall.thickness)
        table = wall.course_table
        joints = tuple((top, resolving(min(t, t_next)))
                       for (_, top, t), (*_, t_next) in zip(table[:-1], table[1:]))
    lam, grading = scene.soil.E_gradient, None
    if lam > 0 and SURFACE_GRADING / lam < scene.mesh.near_size:
        grading = (1.0 / lam, SURFACE_GRADING)
    return DomainGeometry(
        load_radius=scene.foundation_radius,
        domain_radius=scene.domain.radius,
        domain_depth=scene.domain.depth,
        embedment=scene.embedment,
        wall_radius=None if wall is None else wall.radius,
        wall_height=0.0 if wall is None else wall.height,
        edge_size=scene.mesh.edge_size,
        growth=scene.mesh.growth,
        wall_size=wall_size,
        near_size=scene.mesh.near_size,
        near_radius=NEAR_RADIUS * scene.foundation_radius,
        layer_depths=tuple(layer.depth for layer in scene.soil.layers),
        wall_joints=joints,
        plate_joints=(plate.ring_inner_radius,) if plate is not None and plate.annular_width
        else (),
        ringwall=None if scene.ringwall is None else (
            scene.ringwall.inner_radius, scene.ringwall.outer_radius, scene.ringwall.depth),
        ringwall_fill=scene.ringwall is not None and scene.ringwall.fill_E is not None,
        surface_grading=grading,
        surface_grading_radius=SURFACE_GRADING_RADIUS * scene.foundation_radius,
    )


#: gmsh's triangles against the size field: cells = integral of dA / (CELL_AREA h^2);
#: calibrated on the demo scenes (an equilateral triangle of side h is 0.433 h^2)
CELL_AREA = 0.40


#: nodes per cell of a Lagrange space on a triangle mesh (vertices ~ cells / 2, edges ~
#: 3 cells / 2, one interior node per cell at degree 3)
NODES_PER_CELL = {1: 0.5, 2: 2.0, 3: 4.5, 4: 8.0}


#: bytes per unknown of a direct solve (MUMPS's factors, the matrix, the forms, Python):
#: MEMORY_BASE + MEMORY_PER_DOF x dofs x log10(dofs / 1e4 + 1) (nested dissection's fill of
#: a 2D mesh grows as N log N); calibrated on the embedded demo tank from 30k to 1.1M
#: unknowns (peak resident memory of `tankfx run`)
MEMORY_BASE, MEMORY_PER_DOF = 0.35e9, 1.1e3


@dataclass(frozen=True)
class Estimate:
    """What a scene's mesh and solve will cost, estimated before meshing: cells of the
    mesh, unknowns of the soil (the structure's are few), and the peak memory (bytes) of a
    direct solve, summed over the ranks."""

    cells: int
    unknowns: int
    memory: float

    def text(self) -> str:
        return (f"about {self.cells:,} cells, {self.unknowns:,} unknowns, "
                f"{self.memory / 1e9:.2g} GB of memory")


def size_at(g: DomainGeometry, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The element size the mesh's size field asks for at the points (x, y) (r and z up,
    m): meshes/axisymmetric_domain.py's fields, evaluated in numpy."""
    a, D = g.load_radius, g.embedment
    singular = [(a, -D)] + ([(a, 0.0)] if D > 0.0 else [])
    if g.wall_radius is not None:
        singular.append((g.wall_radius, -D))
    if g.ringwall is not None:
        inner, outer, depth = g.ringwall
        singular += [(px, py) for px in (inner, outer) for py in (-D, -D - depth) if px > 0]
    dist = np.min([np.hypot(x - px, y - py) for px, py in singular], axis=0)
    h = g.edge_size + g.growth * dist
    if g.wall_radius is not None and g.wall_size is not None:
        for z0, size in ((0.0, g.wall_size), *g.wall_joints):
            h = np.minimum(h, size + min(g.growth, 0.1) *
                           np.hypot(x - g.wall_radius, y - (-D + z0)))
    if g.near_size is not None:
        h = np.minimum(h, g.near_size + g.growth *
                       np.maximum(0.0, np.hypot(x, y + D) - g.near_radius))
    if g.surface_grading is not None:
        inv_lam, rate = g.surface_grading
        h = np.minimum(h, np.maximum(g.edge_size, rate * (inv_lam + np.maximum(0.0, -y)))
                       + 1e3 * np.maximum(0.0, x - g.surface_grading_radius))
    return h


def _breaks(lo: float, hi: float, centres, finest: float) -> np.ndarray:
    """Sample lines between lo and hi, geometrically graded about each centre."""
    span = hi - lo
    steps = np.geomspace(finest / 4.0, max(span, finest), 80)
    pts = [lo, hi] + [c + sgn * steps for c in centres for sgn in (-1.0, 1.0)]
    pts = np.concatenate([np.atleast_1d(p) for p in pts])
    return np.unique(np.clip(pts, lo, hi))


def available_memory() -> float:
    """Bytes of memory this machine has free now (Linux's MemAvailable), else its physical
    memory."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


#: a run whose estimated memory passes this fraction of the memory free is refused unless
#: allowed (``tankfx run --allow-large``, ``analyse(..., allow_large=True)``)
MEMORY_FRACTION = 0.8


def resource_problem(scene: Scene, est: Estimate,
                     override: str | None = "tankfx run --allow-large") -> str | None:
    """Why a scene is too large for this machine (its estimate ``est`` against the memory
    free), or None; the fix names ``override`` where the caller has one."""
    limit = MEMORY_FRACTION * available_memory()
    if est.memory <= limit:
        return None
    a = scene.foundation_radius
    return (f"the mesh would have {est.text()}, beyond the {limit / 1e9:.3g} GB this machine "
            f"has free ({MEMORY_FRACTION:.0%} of what is available): mesh.edge_size = "
            f"{scene.mesh.edge_size:.3g} m ({scene.mesh.edge_size / a:.2g} a) and mesh.near_size "
            f"= {scene.mesh.near_size:.3g} m; coarsen them (the defaults are 0.002 a and 0.1 a)"
            + (f", or ask for it anyway ({override})" if override else ""))


def estimate(scene: Scene, ranks: int = 1) -> Estimate:
    """The cells, unknowns and memory of a scene's analysis, from its size field alone (no
    meshing, a fraction of a second): within a factor 2 of the real cell count (tested on
    the demo scenes)."""
    cells = estimate_cells(geometry_of(scene))
    degree = scene.mesh.degree
    unknowns = 2.0 * NODES_PER_CELL[degree] * cells
    if scene.soil.mixed_strata or scene.consolidation is not None:
        unknowns += NODES_PER_CELL[max(degree - 1, 1)] * cells
    memory = MEMORY_BASE * ranks + MEMORY_PER_DOF * unknowns * np.log10(unknowns / 1e4 + 1.0)
    return Estimate(cells=int(cells), unknowns=int(unknowns), memory=float(memory))


def estimate_cells(g: DomainGeometry) -> float:
    """The cells gmsh will make of a geometry: its size field integrated over the soil and
    the tank's void, cells = integral of dA / (CELL_AREA h^2)."""
    a, D, R, Z = g.load_radius, g.embedment, g.domain_radius, g.domain_depth
    finest = min(s for s in (g.edge_size, g.wall_size, g.near_size,
                             *(size for _, size in g.wall_joints)) if s)
    xs_c = [0.0, a] + ([g.wall_radius] if g.wall_radius is not None else [])
    ys_c = [0.0, -D]
    H = g.wall_height - D if g.wall_radius is not None else 0.0
    cells = 0.0
    # the soil, and the tank's void above it (meshed too)
    regions = [(0.0, R, -Z, 0.0)] + ([(0.0, g.wall_radius, 0.0, H)] if H > 0.0 else [])
    for x0, x1, y0, y1 in regions:
        xb = _breaks(x0, x1, xs_c, finest)
        yb = _breaks(y0, y1, ys_c, finest)
        xm, ym = np.meshgrid(0.5 * (xb[1:] + xb[:-1]), 0.5 * (yb[1:] + yb[:-1]))
        area = np.outer(np.diff(yb), np.diff(xb))
        cells += float(np.sum(area / (CELL_AREA * size_at(g, xm, ym) ** 2)))
    return cells


def _mesh_on_rank0(geom: DomainGeometry, gmsh) -> None:
    """Generate the mesh in gmsh's current model, or read it from the cache; a newly
    generated mesh is written to the cache (binary, so that it reads back bit for bit)."""
    path = _cache_file(geom, gmsh)
    if path is not None and path.exists():
        gmsh.model.add(f"tankfx-cached-{id(geom)}")   # merge into a model of our own
        try:
            gmsh.merge(str(path))
            log.info("mesh: read from the cache %s", path)
            return
        except Exception as e:   # a damaged cache file: mesh anew
            log.info("mesh: cache file %s unreadable (%s); meshing anew", path, e)
            gmsh.model.remove()
    build_model(geom, gmsh, name=f"tankfx-{id(geom)}")
    if path is None:
        return
    binary = gmsh.option.getNumber("Mesh.Binary")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.tmp.msh")
        gmsh.option.setNumber("Mesh.Binary", 1)    # reads back bit for bit
        gmsh.write(str(tmp))
        os.replace(tmp, path)            # atomic: a concurrent reader sees all or nothing
    except Exception as e:   # a read-only or full disk must not stop the analysis
        log.info("mesh: not cached (%s)", e)
    finally:
        gmsh.option.setNumber("Mesh.Binary", binary)


def build_domain(scene: Scene, comm: MPI.Comm = MPI.COMM_WORLD,
                 geometry: DomainGeometry | None = None) -> Domain:
    """Mesh the scene on rank 0 with gmsh and distribute it over ``comm``."""
    import gmsh

    geom = geometry or geometry_of(scene)
    # gmsh keeps global state: initialise only if nobody (e.g. a user's script) did already
    owns_gmsh = not gmsh.isInitialized()
    if owns_gmsh:
        gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        if comm.rank == 0:
            with heartbeat(f"meshing (about {int(estimate_cells(geom)):,} cells)"):
                _mesh_on_rank0(geom, gmsh)
        partitioner = dmesh.create_cell_partitioner(graph.partitioner(),
                                                    dmesh.GhostMode.shared_facet, 2)
        data = dgmsh.model_to_mesh(gmsh.model, comm, 0, gdim=2, partitioner=partitioner)
        if comm.rank == 0:
            gmsh.model.remove()
    finally:
        if owns_gmsh:
            gmsh.finalize()
    msh = data.mesh
    msh.topology.create_connectivity(1, 2)
    return Domain(mesh=msh, cell_tags=data.cell_tags, facet_tags=data.facet_tags,
                  geometry=geom)
