"""Parametric gmsh geometry of the axisymmetric (r, z) tank-foundation-soil domain.

The meridian plane is drawn with r along x and z along y: the ground surface is z = 0 and
the soil occupies -depth <= z <= 0, 0 <= r <= radius. A foundation of radius ``load_radius``
(the plate, or a flexible load) sits at z = -embedment; an embedded foundation leaves an
excavated pit 0 <= r <= load_radius, -embedment <= z <= 0. Where there will be a tank wall,
the tank's interior (and the pit) is meshed as a *void* region, so that the wall's meridian
is a line of facets of the same mesh: the wall and plate can then live on facet submeshes of
one parent mesh. The soil equations are integrated over the soil cells only; the void's
degrees of freedom are pinned by the solver.

Mesh size grows linearly with the distance from the singular points (the foundation edge and
the wall foot), ``size = edge_size + growth * distance``, so a domain thousands of radii wide
costs only a few thousand cells more than a small one.

Run it on its own to look at a mesh in gmsh's window, or to write a ``.msh``::

    python meshes/axisymmetric_domain.py --load-radius 1 --embedment 0.3 \
        --wall-radius 1 --wall-height 3 --gui
"""
from __future__ import annotations

import argparse
from dataclasses import dataclass

#: Physical tags of the 2D regions.
CELL_TAGS = {"soil": 1, "void": 2}

#: Physical tags of the facets. Each facet carries exactly one tag; the parts of the wall
#: that also face the soil get their own tag so that no facet needs two.
FACET_TAGS = {
    "axis": 1,            # r = 0 in the soil
    "far_side": 2,        # r = domain radius
    "bottom": 3,          # z = -domain depth
    "surface": 4,         # free ground surface, z = 0, outside the foundation
    "contact": 5,         # foundation underside / loaded area, z = -embedment, r <= load_radius
    "embedded_face": 6,   # side of the pit, r = load_radius, -embedment < z < 0, no wall on it
    "wall": 7,            # wall meridian where it does not touch the soil
    "wall_embedded": 8,   # wall meridian on the side of the pit (both wall and embedded face)
    "void_axis": 9,       # r = 0 in the void
    "void_boundary": 10,  # the rest of the void's outline (its lid, the open pit top)
    "layer_top": 11,      # a soil layer's top, z = -layer depth, inside the soil
    "ringwall": 12,       # a ringwall's outline inside the soil (its top under the plate: contact)
}


@dataclass(frozen=True)
class DomainGeometry:
    """Lengths in metres. ``wall_radius`` None means no wall and no void region."""

    load_radius: float
    domain_radius: float
    domain_depth: float
    embedment: float = 0.0
    wall_radius: float | None = None
    wall_height: float = 0.0
    edge_size: float = 0.05
    growth: float = 0.2
    wall_size: float | None = None    #: element size at the wall foot
    near_size: float | None = None    #: size cap in the near field (soil stresses reported)
    near_radius: float = 0.0          #: extent of the near field around the foundation
    #: depths of the soil layers' tops (m below the ground): lines of the mesh, so that no
    #: cell straddles two layers
    layer_depths: tuple[float, ...] = ()
    #: the joints of a wall's courses: (height above the wall's foot, element size there);
    #: each is a mesh vertex with a bending boundary layer of its own
    wall_joints: tuple[tuple[float, float], ...] = ()
    #: radii on the foundation's underside where the plate's thickness steps (an annular
    #: ring's inner edge): mesh vertices
    plate_joints: tuple[float, ...] = ()
    #: a ringwall under the wall: (inner radius, outer radius, depth below the plate's
    #: underside); its outline is made of mesh lines, so that no cell straddles it
    ringwall: tuple[float, float, float] | None = None
    #: whether the inside of the ringwall is a fill of its own (its bottom a mesh line too)
    ringwall_fill: bool = False
    #: a soil whose modulus grows steeply from the surface, E_s (1 + lambda h): element
    #: sizes graded as (size at the surface, growth) x (1 / lambda + h), h the depth, out to
    #: ``surface_grading_radius`` (None: no such grading)
    surface_grading: tuple[float, float] | None = None
    surface_grading_radius: float = 0.0


def build_model(g: DomainGeometry, gmsh, name: str = "tankfx", order: int = 1) -> None:
    """Create the geometry, physical groups and mesh in the current gmsh model.

    ``gmsh`` is the imported (and initialised) gmsh module: it is passed in so that this file
    stays importable where gmsh is not installed.
    """
    a, D, R, Z = g.load_radius, g.embedment, g.domain_radius, g.domain_depth
    occ = gmsh.model.occ
    gmsh.model.add(name)

    soil = occ.addRectangle(0.0, -Z, 0.0, R, Z)
    if D > 0.0:
        pit = occ.addRectangle(0.0, -D, 0.0, a, D)
        (soil_dimtags, _) = occ.cut([(2, soil)], [(2, pit)])
        soil = soil_dimtags[0][1]

    pieces = [(2, soil)]
    wall_line = None
    if g.wall_radius is not None:
        at, H = g.wall_radius, g.wall_height
        void = occ.addRectangle(0.0, -D, 0.0, at, H)
        if D > 0.0 and at < a:
            pit = occ.addRectangle(0.0, -D, 0.0, a, D)
            (void_dimtags, _) = occ.fuse([(2, void)], [(2, pit)])
            void = void_dimtags[0][1]
        pieces.append((2, void))
        p0 = occ.addPoint(at, -D, 0.0)
        p1 = occ.addPoint(at, -D + H, 0.0)
        wall_line = occ.addLine(p0, p1)
        pieces.append((1, wall_line))
    if g.ringwall is not None:
        inner, outer, depth = g.ringwall
        pieces.append((2, occ.addRectangle(inner, -D - depth, 0.0, outer - inner, depth)))
        if g.ringwall_fill:
            pieces.append((2, occ.addRectangle(0.0, -D - depth, 0.0, inner, depth)))
    for d in g.layer_depths:
        # across the soil only: inside the pit there is none
        x0 = a if d <= D else 0.0
        pieces.append((1, occ.addLine(occ.addPoint(x0, -d, 0.0), occ.addPoint(R, -d, 0.0))))
    # Points where the mesh must have a vertex: the foundation edge and the wall foot.
    singular = [(a, -D)] + ([(a, 0.0)] if D > 0.0 else [])
    if g.wall_radius is not None:
        singular.append((g.wall_radius, -D))
    if g.ringwall is not None:
        # a stiff inclusion's corners concentrate the soil's stress as a foundation's edge
        inner, outer, depth = g.ringwall
        singular += [(x, y) for x in (inner, outer) for y in (-D, -D - depth)
                     if (x, y) not in singular and x > 0.0]
    # where a member's thickness steps: vertices too, so that no element straddles a step
    steps = [(g.wall_radius, -D + h) for h, _ in g.wall_joints] + \
        [(r, -D) for r in g.plate_joints]
    point_tags = [occ.addPoint(x, y, 0.0) for (x, y) in singular + steps]
    pieces += [(0, p) for p in point_tags]
    occ.fragment(pieces, [])
    occ.synchronize()

    _tag_entities(g, gmsh)
    _size_field(g, gmsh, singular)
    gmsh.option.setNumber("Mesh.Algorithm", mesh_algorithm(g))
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(2)
    if order > 1:
        gmsh.model.mesh.setOrder(order)


#: Above this ratio of the domain's extent to its finest element, gmsh's Frontal-Delaunay
#: (algorithm 6) leaves slivers in the near field (measured on the embedded demo tank's
#: coarse mesh: smallest quality 0.66 at 1e7, 0.084 at 1e9, 0.010 at 1e10; a sliver moved
#: M0 by 1 %), and MeshAdapt (algorithm 1) is used: its smallest quality stays 0.6-0.69
#: up to 1e10. Below it, Frontal-Delaunay's meshes are smaller by about a tenth.
FRONTAL_DELAUNAY_RATIO = 2e7


def mesh_algorithm(g: DomainGeometry) -> int:
    """gmsh's 2D algorithm for the geometry: Frontal-Delaunay (6), or MeshAdapt (1) where
    the domain is more than FRONTAL_DELAUNAY_RATIO of its finest elements across."""
    finest = min(s for s in (g.edge_size, g.wall_size, g.near_size,
                             *(size for _, size in g.wall_joints)) if s)
    return 6 if max(g.domain_radius, g.domain_depth) / finest <= FRONTAL_DELAUNAY_RATIO else 1


def _tag_entities(g: DomainGeometry, gmsh) -> None:
    a, D, R, Z = g.load_radius, g.embedment, g.domain_radius, g.domain_depth
    eps = 1e-9 * max(R, Z)
    near = lambda x, y: abs(x - y) <= eps  # noqa: E731

    def is_wall(x0, x1, y0, y1):
        return (g.wall_radius is not None and near(x0, g.wall_radius) and near(x1, g.wall_radius)
                and y0 >= -D - eps and y1 <= -D + g.wall_height + eps)

    cells: dict[str, list[int]] = {"soil": [], "void": []}
    for _, s in gmsh.model.getEntities(2):
        xm, ym, _ = gmsh.model.occ.getCenterOfMass(2, s)
        # the void is the only region above the ground or inside the pit
        in_void = ym > 0.0 or (D > 0 and xm < a and ym > -D)
        cells["void" if in_void else "soil"].append(s)

    facets: dict[str, list[int]] = {k: [] for k in FACET_TAGS}
    for _, c in gmsh.model.getEntities(1):
        # exact end points (OCC bounding boxes are padded by a tolerance)
        ends = [gmsh.model.getValue(0, p, []) for _, p in gmsh.model.getBoundary([(1, c)])]
        (x0, x1), (y0, y1) = sorted(e[0] for e in ends), sorted(e[1] for e in ends)
        xm, ym = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        if near(x0, 0.0) and near(x1, 0.0):
            facets["axis" if ym < -D else "void_axis"].append(c)
        elif near(x0, R) and near(x1, R):
            facets["far_side"].append(c)
        elif near(y0, -Z) and near(y1, -Z):
            facets["bottom"].append(c)
        elif near(y0, -D) and near(y1, -D) and x1 <= a + eps:
            facets["contact"].append(c)
        elif near(y0, 0.0) and near(y1, 0.0) and x0 >= a - eps:
            facets["surface"].append(c)
        elif is_wall(x0, x1, y0, y1):
            touches_soil = D > 0 and near(xm, a) and ym < 0.0
            facets["wall_embedded" if touches_soil else "wall"].append(c)
        elif D > 0 and near(x0, a) and near(x1, a) and -D - eps <= ym <= eps:
            facets["embedded_face"].append(c)
        elif g.ringwall is not None and _on_ringwall(g, x0, x1, y0, y1, eps):
            facets["ringwall"].append(c)
        elif near(y0, y1) and any(near(y0, -d) for d in g.layer_depths) and x0 >= -eps \
                and (y0 < -D - eps or x0 >= a - eps):
            facets["layer_top"].append(c)
        else:
            facets["void_boundary"].append(c)

    for name, ents in cells.items():
        if ents:
            gmsh.model.addPhysicalGroup(2, ents, CELL_TAGS[name], name=name)
    for name, ents in facets.items():
        if ents:
            gmsh.model.addPhysicalGroup(1, ents, FACET_TAGS[name], name=name)


def _on_ringwall(g: DomainGeometry, x0, x1, y0, y1, eps) -> bool:
    """Whether the curve from (x0, y0) to (x1, y1) lies on the ringwall's outline."""
    inner, outer, depth = g.ringwall
    top, bottom = -g.embedment, -g.embedment - depth
    vertical = abs(x0 - x1) <= eps and (abs(x0 - inner) <= eps or abs(x0 - outer) <= eps) \
        and bottom - eps <= y0 and y1 <= top + eps
    left = 0.0 if g.ringwall_fill else inner          # a fill's bottom too
    horizontal = abs(y0 - y1) <= eps and (abs(y0 - top) <= eps or abs(y0 - bottom) <= eps) \
        and left - eps <= x0 and x1 <= outer + eps
    return vertical or horizontal


def _distance_from(gmsh, x: float, y: float) -> int:
    """A size field of the distance from the point (x, y) (not part of the geometry)."""
    at = gmsh.model.occ.addPoint(x, y, 0.0)
    gmsh.model.occ.synchronize()
    d = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(d, "PointsList", [at])
    return d


def _size_field(g: DomainGeometry, gmsh, singular) -> None:
    """size = edge_size + growth * (distance to the nearest singular point)."""
    fields = gmsh.model.mesh.field
    points = [gmsh.model.occ.addPoint(x, y, 0.0) for (x, y) in singular]
    gmsh.model.occ.synchronize()  # the distance points are not part of the geometry's mesh
    dist = fields.add("Distance")
    fields.setNumbers(dist, "PointsList", points)
    f = fields.add("MathEval")
    fields.setString(f, "F", f"{g.edge_size!r} + {g.growth!r}*F{dist}")
    ids = [f]
    if g.wall_radius is not None and g.wall_size is not None:
        # the wall's bending boundary layers (decay length 1/beta) need their own
        # resolution, growing slowly: from the wall's foot and from each course joint,
        # where the thickness steps
        for h, size in ((0.0, g.wall_size), *g.wall_joints):
            d = _distance_from(gmsh, g.wall_radius, -g.embedment + h)
            w = fields.add("MathEval")
            fields.setString(w, "F", f"{size!r} + {min(g.growth, 0.1)!r}*F{d}")
            ids.append(w)
    if g.near_size is not None:
        # the near field, where soil stresses are reported, gets a uniform cap
        d0 = _distance_from(gmsh, 0.0, -g.embedment)
        n = fields.add("MathEval")
        fields.setString(n, "F", f"{g.near_size!r} + {g.growth!r}*max(0, F{d0}-{g.near_radius!r})")
        ids.append(n)
    if g.surface_grading is not None:
        # a modulus that doubles over 1/lambda near the surface: the strain is largest
        # there and falls as 1 / (1/lambda + h), so the elements grow in proportion
        inv_lam, rate = g.surface_grading
        grading = fields.add("MathEval")
        # (no finer than the foundation's edge: a modulus rising from almost nothing would
        # otherwise ask for millions of elements)
        fields.setString(grading, "F", f"max({g.edge_size!r}, {rate!r}*({inv_lam!r} + "
                                       f"max(0, -y))) + "
                                       f"1e3*max(0, x - {g.surface_grading_radius!r})")
        ids.append(grading)
    if g.near_size is not None:
        # a stratum thinner than the near field's elements (a layer, or the soil above a
        # shallow rigid base) gets elements no larger than its thickness there, not
        # slivers: the band of each, out to the near field's edge
        tops = [0.0, *g.layer_depths, g.domain_depth]
        for top, bottom in zip(tops[:-1], tops[1:]):
            if bottom - top < g.near_size:
                band = fields.add("Box")
                for key, value in (("VIn", bottom - top), ("VOut", 1e22), ("XMin", 0.0),
                                   ("XMax", max(g.near_radius, 2.0 * g.load_radius)),
                                   ("YMin", -bottom), ("YMax", -top)):
                    fields.setNumber(band, key, value)
                ids.append(band)
    m = fields.add("Min")
    fields.setNumbers(m, "FieldsList", ids)
    fields.setAsBackgroundMesh(m)


def _main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--load-radius", type=float, default=1.0)
    p.add_argument("--domain-radius", type=float, default=None)
    p.add_argument("--domain-depth", type=float, default=None)
    p.add_argument("--embedment", type=float, default=0.0)
    p.add_argument("--wall-radius", type=float, default=None)
    p.add_argument("--wall-height", type=float, default=0.0)
    p.add_argument("--edge-size", type=float, default=None)
    p.add_argument("--growth", type=float, default=0.2)
    p.add_argument("--output", default=None, help="write the mesh to this .msh file")
    p.add_argument("--gui", action="store_true", help="open the mesh in gmsh's window")
    args = p.parse_args()
    a = args.load_radius
    R = args.domain_radius or 20 * a
    geom = DomainGeometry(
        load_radius=a, domain_radius=R, domain_depth=args.domain_depth or R,
        embedment=args.embedment, wall_radius=args.wall_radius, wall_height=args.wall_height,
        edge_size=args.edge_size or 0.05 * a, growth=args.growth)
    import gmsh

    gmsh.initialize()
    build_model(geom, gmsh)
    if args.output:
        gmsh.write(args.output)
    if args.gui:
        gmsh.fltk.run()
    gmsh.finalize()
    print(f"{geom}: {'written to ' + args.output if args.output else 'meshed'}")


if __name__ == "__main__":
    _main()
