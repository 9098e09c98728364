"""From a scene to a distributed DOLFINx mesh with named cell and facet tags.

The geometry itself lives in ``meshes/axisymmetric_domain.py`` (installed as
``tankfx.meshes.axisymmetric_domain``) so that it can be opened in gmsh on its own. The mesh
is generated on rank 0 and distributed; interior-facet integrals (the interface on facets
that have soil on one side and the tank's void on the other) need the ``shared_facet`` ghost
mode, which is therefore always used.
"""
from __future__ import annotations

import functools
import hashlib
import json
import logging
import os
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
#: SURFACE_GRADING_RADIUS foundation radii (README "Mesh defaults").
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
