"""The gmsh domains: every region and facet group is tagged, with the right size."""
import math

import numpy as np
import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI

from tankfx.mesh import CELL_TAGS, FACET_TAGS, build_domain
from tankfx.meshes.axisymmetric_domain import DomainGeometry


def _measure(domain, kind, names):
    msh = domain.mesh
    if kind == "dx":
        m = ufl.Measure("dx", domain=msh, subdomain_data=domain.cell_tags)
        tags = tuple(CELL_TAGS[n] for n in names)
    else:
        m = ufl.Measure(kind, domain=msh, subdomain_data=domain.facet_tags)
        tags = tuple(FACET_TAGS[n] for n in names)
    one = fem.Constant(msh, 1.0)
    return msh.comm.allreduce(fem.assemble_scalar(fem.form(one * m(tags))), op=MPI.SUM)


@pytest.mark.mpi
@pytest.mark.parametrize("D, at", [(0.0, None), (0.4, None), (0.0, 1.0), (0.4, 1.0), (0.4, 0.7)])
def test_regions_and_facets_are_tagged(D, at):
    a, R, Z, H = 1.0, 30.0, 25.0, 3.0
    geom = DomainGeometry(load_radius=a, domain_radius=R, domain_depth=Z, embedment=D,
                          wall_radius=at, wall_height=H, edge_size=0.1, growth=0.3)
    dom = build_domain(None, MPI.COMM_WORLD, geometry=geom)
    assert _measure(dom, "dx", ["soil"]) == pytest.approx(R * Z - a * D, rel=1e-12)
    ds = lambda *n: _measure(dom, "ds", n)  # noqa: E731
    dS = lambda *n: _measure(dom, "dS", n)  # noqa: E731
    assert ds("far_side") == pytest.approx(Z)
    assert ds("bottom") == pytest.approx(R)
    assert ds("axis") == pytest.approx(Z - D)
    assert ds("surface") == pytest.approx(R - a)
    # the contact facets are on the outside of the mesh unless the tank's void is above them
    assert ds("contact") + dS("contact") == pytest.approx(a)
    side = ds("embedded_face", "wall_embedded") + dS("embedded_face", "wall_embedded")
    assert side == pytest.approx(D)
    if at is None:
        assert _measure(dom, "dx", ["void"]) == 0.0
        assert ds("wall", "wall_embedded") == 0.0
    else:
        void_area = at * H + (a - at) * D
        assert _measure(dom, "dx", ["void"]) == pytest.approx(void_area, rel=1e-12)
        wall = ds("wall", "wall_embedded") + dS("wall", "wall_embedded")
        assert wall == pytest.approx(H)


def test_mesh_is_graded_towards_the_edge():
    geom = DomainGeometry(load_radius=1.0, domain_radius=1000.0, domain_depth=1000.0,
                          edge_size=0.05, growth=0.2)
    dom = build_domain(None, MPI.COMM_WORLD, geometry=geom)
    msh = dom.mesh
    h = msh.h(2, np.arange(msh.topology.index_map(2).size_local, dtype=np.int32))
    mid = msh.comm.allreduce(h.min(), op=MPI.MIN)
    big = msh.comm.allreduce(h.max(), op=MPI.MAX)
    assert mid < 0.1 and big > 50.0
    assert msh.topology.index_map(2).size_global < 20000
    assert math.isfinite(big)


def test_mesh_cache_reads_back_the_same_mesh(tmp_path, monkeypatch):
    """A generated mesh is cached by its geometry and read back bit for bit; another
    geometry gets its own file; TANKFX_MESH_CACHE=off writes nothing."""
    import numpy as np

    from tankfx.mesh import build_domain
    from conftest import flexible_scene

    monkeypatch.setenv("TANKFX_MESH_CACHE", str(tmp_path / "cache"))
    scene = flexible_scene(mesh={"edge_size": 0.05, "near_size": 0.4, "growth": 0.3})
    first, second = build_domain(scene), build_domain(scene)
    assert len(list((tmp_path / "cache").glob("*.msh"))) == 1
    np.testing.assert_array_equal(first.mesh.geometry.x, second.mesh.geometry.x)
    for a, b in ((first.cell_tags, second.cell_tags), (first.facet_tags, second.facet_tags)):
        np.testing.assert_array_equal(a.indices, b.indices)
        np.testing.assert_array_equal(a.values, b.values)
    build_domain(scene.with_changes(mesh={"edge_size": 0.04}))
    assert len(list((tmp_path / "cache").glob("*.msh"))) == 2
    monkeypatch.setenv("TANKFX_MESH_CACHE", "off")
    build_domain(scene.with_changes(mesh={"edge_size": 0.03}))
    assert len(list((tmp_path / "cache").glob("*.msh"))) == 2
