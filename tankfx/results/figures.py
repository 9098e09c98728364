"""The figures of a run: the section and the 3D views with PyVista, off screen to PNG (or on
screen when asked and a display is there); the line charts are matplotlib's
(:mod:`tankfx.results.charts`, re-exported here).

Every figure is built on rank 0 from data gathered across all ranks, never from one rank's
part of the mesh. Call these functions on all ranks; only rank 0 writes a file.
"""
from __future__ import annotations

import logging
import os
from pathlib import Path

import numpy as np
from dolfinx import fem, plot

from .charts import (  # noqa: F401  (the line charts, re-exported: one place to import figures)
    plot_bounds,
    plot_collapse,
    plot_contact,
    plot_curves,
    plot_fill,
    plot_settlement,
    plot_structure_profiles,
    plot_surface_settlement,
    plot_sweep,
)
from ..fem.evaluate import evaluate_at
from .fields import soil_cell_fields
from .figure_choices import FIGURES, SECTION_QUANTITIES, section_problem  # noqa: F401

#: an environment variable: where set (not "0"), a figure that cannot be drawn makes
#: write_figures raise once every figure has been tried, instead of warning (the test suite
#: sets it, so that a plotting error fails the test that draws the figure)
STRICT_FIGURES = "TANKFX_STRICT_FIGURES"

if not os.environ.get("DISPLAY"):
    # no X server: render through EGL rather than let VTK try (and warn about) X first
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def offscreen_pyvista():
    import pyvista

    pyvista.OFF_SCREEN = True
    return pyvista


def save_figure(plotter, path, section_view: bool = False) -> Path:
    """Write the plotter's image to ``path`` (PNG) and close it; a section view is seen
    from +z-normal with (r, z) axes."""
    if section_view:
        plotter.view_xy()
        plotter.show_bounds(xtitle="r [m]", ytitle="z [m]", location="outer", font_size=10)
    path = Path(path)
    plotter.screenshot(str(path))
    plotter.close()
    return path


def gather_grid(fields: dict[str, fem.Function], cells: np.ndarray | None = None,
                cell_fields: dict[str, fem.Function] | None = None):
    """A PyVista grid on rank 0 (None elsewhere) of the owned cells of all ranks, carrying the
    given fields interpolated to the mesh vertices (P1), and ``cell_fields`` (scalar DG0)
    as the cells' data."""
    first = next(iter(fields.values()))
    msh = first.function_space.mesh
    comm = msh.comm
    tdim = msh.topology.dim
    n_owned = msh.topology.index_map(tdim).size_local
    if cells is None:
        cells = np.arange(n_owned, dtype=np.int32)
    cells = cells[cells < n_owned]
    # the grid of a scalar P1 space: its points are the P1 dofs, so values need no mapping
    P1 = fem.functionspace(msh, ("Lagrange", 1))
    topology, cell_types, x = plot.vtk_mesh(P1, entities=cells)
    data = {}
    for name, f in fields.items():
        shape = f.function_space.value_shape
        V1 = fem.functionspace(msh, ("Lagrange", 1, shape) if shape else ("Lagrange", 1))
        g = fem.Function(V1)
        g.interpolate(f)
        data[name] = g.x.array.reshape(len(x), -1)
    per_cell = {name: f.x.array[f.function_space.dofmap.list[cells, 0]]
                for name, f in (cell_fields or {}).items()}
    parts = comm.gather((topology, cell_types, x, data, per_cell), root=0)
    if comm.rank != 0:
        return None
    pv = offscreen_pyvista()
    grids = []
    for topo, types, pts, vals, per_cell in parts:
        if len(types) == 0:
            continue
        grid = pv.UnstructuredGrid(topo, types, pts)
        for name, v in vals.items():
            grid.point_data[name] = v if v.shape[1] > 1 else v[:, 0]
        for name, v in per_cell.items():
            grid.cell_data[name] = v
        grids.append(grid)
    return grids[0].merge(grids[1:]) if len(grids) > 1 else grids[0]


def ringwall_outline(scene) -> list[np.ndarray]:
    """The ringwall's outline in the section, as a closed polyline, and its fill's bottom
    (none without)."""
    ring = scene.ringwall
    if ring is None:
        return []
    top, bottom = -scene.embedment, -scene.embedment - ring.depth
    lines = [np.array([[ring.inner_radius, top], [ring.inner_radius, bottom],
                       [ring.outer_radius, bottom], [ring.outer_radius, top],
                       [ring.inner_radius, top]])]
    if ring.fill_E is not None:          # the fill's bottom
        lines.append(np.array([[0.0, bottom], [ring.inner_radius, bottom]]))
    return lines


#: the section's colour range: these percentiles of the values weighted by the area they
#: cover (a node count would be ruled by the fine mesh at the foundation's edge, where the
#: stress is singular); the rest is marked over-range
COLOUR_PERCENTILES = (1.0, 99.0)
#: the section's colour bands (filled contours)
COLOUR_BANDS = 12


def colour_range(grid, name: str) -> tuple[float, float]:
    """The colour range of the point field ``name`` on a 2D grid: COLOUR_PERCENTILES of
    its cell averages weighted by the cells' areas."""
    cells = grid.point_data_to_cell_data(pass_point_data=False)
    values = np.asarray(cells.cell_data[name], dtype=float)
    areas = np.abs(grid.compute_cell_sizes(length=False, volume=False).cell_data["Area"])
    order = np.argsort(values)
    cumulative = np.cumsum(areas[order])
    cumulative /= cumulative[-1]
    lo, hi = (float(np.interp(q / 100.0, cumulative, values[order]))
              for q in COLOUR_PERCENTILES)
    return (lo, hi) if hi > lo else (lo, lo + 1.0)


def nice_ticks(lo: float, hi: float, n: int = 6) -> tuple[float, float, int]:
    """Bounds around [lo, hi] at a round step (1, 2, 2.5 or 5 times a power of ten) and
    the number of labels between them, about ``n``."""
    raw = max(hi - lo, 1e-12) / max(n - 1, 1)
    power = 10.0 ** np.floor(np.log10(raw))
    step = next(m * power for m in (1.0, 2.0, 2.5, 5.0, 10.0) if m * power >= raw * 0.999)
    lo, hi = np.floor(lo / step) * step, np.ceil(hi / step) * step
    return float(lo), float(hi), int(round((hi - lo) / step)) + 1


def plot_section(u: fem.Function, scalar: fem.Function, path: str | Path, *, extent: float,
                 depth_offset: float = 0.0, label: str = "sigma_zz [kPa]",
                 scalar_scale: float = 1e-3, title: str = "", soil_cells=None,
                 structure: dict | None = None, layer_depths=(), outlines=(),
                 r_min: float = 0.0, mesh_lines: bool = False,
                 marked: tuple[fem.Function, str] | None = None) -> Path | None:
    """The (r, z) section within ``extent`` of the foundation centre, deformed (the scale is
    printed on the figure) and coloured by ``scalar``; ``structure`` (a gathered
    results dict) adds the plate and wall as thick lines, ``layer_depths`` the soil layers'
    tops and ``outlines`` other lines in the soil (polylines of (r, z) vertices, e.g. a
    ringwall's) as white lines, deformed with the soil; ``r_min`` > 0 shows the window
    r_min <= r <= extent, as deep as it is wide, instead (e.g. around a wall's foot). The
    colours are COLOUR_BANDS filled bands over :func:`colour_range` (the singular peak at
    the foundation's edge marked over-range, not setting it); ``mesh_lines`` draws the
    cells' edges; ``marked`` = (a DG0 field, its words) dots the cells where the field is
    positive (an elastoplastic soil's yielding cells). The whole structure is in view, at
    equal scales, with ticks at round numbers. Returns the PNG path on rank 0."""
    grid = gather_grid({"u": u, "s": scalar}, soil_cells,
                       {"marked": marked[0]} if marked is not None else None)
    if grid is None:
        return None
    pv = offscreen_pyvista()
    near = grid.clip_box([r_min, extent, -depth_offset - (extent - r_min), 1e9, -1.0, 1.0],
                         invert=False)
    disp = np.zeros((near.n_points, 3))
    disp[:, :2] = near.point_data["u"]
    umax = float(np.abs(disp).max()) or 1.0
    scale = 0.1 * (extent - r_min) / umax
    members = []
    if structure is not None and "plate" in structure["profiles"]:
        # (undeformed points, displacements) of the plate and the wall
        pl, z0 = structure["profiles"]["plate"], -depth_offset
        members.append((np.column_stack([pl["r"], np.full(len(pl["r"]), z0)]),
                        np.column_stack([pl["u_r"], -np.asarray(pl["w"])])))
        if "wall" in structure["profiles"]:
            wa = structure["profiles"]["wall"]
            at = structure["scene"]["wall"]["radius"]
            members.append((np.column_stack([np.full(len(wa["z"]), at),
                                             z0 + np.asarray(wa["z"])]),
                            np.column_stack([wa["u_r"], wa["u_z"]])))
    tops = []
    polylines = [np.array([[r_min, -d], [extent, -d]]) for d in layer_depths] + \
        [np.asarray(o, dtype=float) for o in outlines]
    for vertices in polylines:
        # sampled from the undeformed section: the soil's displacement along the line
        t = np.linspace(0.0, 1.0, 400 // (len(vertices) - 1))
        pts = np.concatenate([a + t[:, None] * (b - a)
                              for a, b in zip(vertices[:-1], vertices[1:])])
        pts = np.column_stack([pts, np.zeros(len(pts))])
        line = pv.PolyData(pts).sample(near)
        valid = line.point_data["vtkValidPointMask"].astype(bool)
        if valid.sum() > 1:
            moved = pts[valid].copy()
            moved[:, :2] += scale * line.point_data["u"][valid]
            tops.append(moved)
    near.points = near.points + scale * disp
    near.point_data[label] = near.point_data["s"] * scalar_scale
    p = pv.Plotter(off_screen=True, window_size=(1100, 900))
    clim = colour_range(near, label)
    p.add_mesh(near, scalars=label, cmap="viridis", show_edges=mesh_lines, edge_color="grey",
               line_width=0.3, clim=clim, n_colors=COLOUR_BANDS, above_color="magenta",
               below_color="cyan",
               scalar_bar_args={"title": label, "vertical": True, "fmt": "%.3g",
                                "title_font_size": 16, "label_font_size": 14})
    points = [near.points[:, :2]]
    for line in members:
        # the plate and wall, displaced with the same scale (within a window: its part)
        x, d = line
        if r_min > 0.0:
            z0, half = -depth_offset, extent - r_min
            keep = (x[:, 0] >= r_min) & (x[:, 0] <= extent) & (x[:, 1] <= z0 + half)
            x, d = x[keep], d[keep]
            if len(x) < 2:
                continue
        pts = np.column_stack([x + scale * d, np.zeros(len(x))])
        points.append(pts[:, :2])
        p.add_mesh(pv.lines_from_points(pts), color="black", line_width=6)
    for pts in tops:
        p.add_mesh(pv.lines_from_points(pts), color="white", line_width=3)
    marks = ""
    if marked is not None:
        centres = near.cell_centers().points[near.cell_data["marked"] > 0.0]
        if len(centres):
            p.add_mesh(pv.PolyData(centres), color="red", point_size=4,
                       render_points_as_spheres=True)
        marks = f"; red dots: {marked[1]} ({len(centres)} cells in view)"
    p.add_text(f"{title}\ndisplacements x {scale:.3g}; colours: {COLOUR_PERCENTILES[0]:g}-"
               f"{COLOUR_PERCENTILES[1]:g} % of the area (magenta above, cyan below){marks}",
               font_size=11)
    return save_section(p, path, np.concatenate(points))


def save_section(plotter, path, xy: np.ndarray) -> Path:
    """Write a section view (r, z) that shows every point ``xy`` drawn, between round
    numbers on both axes, at equal scales."""
    # (r >= 0: a point a hair left of the axis is the axis's)
    span = float(np.ptp(xy[:, 0])) or 1.0
    x_min = float(xy[:, 0].min())
    x0, x1, nx = nice_ticks(0.0 if x_min > -1e-3 * span else x_min, float(xy[:, 0].max()))
    y0, y1, ny = nice_ticks(float(xy[:, 1].min()), float(xy[:, 1].max()))
    bounds = (x0, x1, y0, y1, 0.0, 0.0)
    plotter.view_xy()
    plotter.show_bounds(bounds=bounds, xtitle="r [m]", ytitle="z [m]", location="outer",
                        font_size=12, n_xlabels=nx, n_ylabels=ny, fmt="%g", use_2d=True)
    plotter.reset_camera(bounds=bounds)
    return save_figure(plotter, path)


def plot_cutaway(u: fem.Function, scalar: fem.Function, path: str | Path, *, extent: float,
                 depth_offset: float = 0.0, label: str = "sigma_zz [kPa]",
                 scalar_scale: float = 1e-3, title: str = "", soil_cells=None,
                 structure: dict | None = None, angle: float = 270.0) -> Path | None:
    """The near-field (r, z) section revolved about the axis through ``angle`` degrees: a 3D
    cut-away of the soil coloured by ``scalar`` (the cut faces show the section), with the
    plate and wall revolved as surfaces, undeformed. Built from the grid gathered over all
    ranks; rank 0 writes the PNG."""
    grid = gather_grid({"u": u, "s": scalar}, soil_cells)
    if grid is None:
        return None
    pv = offscreen_pyvista()
    near = grid.clip_box([0.0, extent, -depth_offset - extent, 1e9, -1.0, 1.0], invert=False)
    surf = near.extract_surface(algorithm="dataset_surface")
    # the meridian plane (r, z) becomes the plane y = 0 of the 3D view: (x, y, z) = (r, 0, z)
    surf.points = np.column_stack([surf.points[:, 0], np.zeros(surf.n_points),
                                   surf.points[:, 1]])
    surf.point_data[label] = surf.point_data["s"] * scalar_scale
    solid = surf.extrude_rotate(resolution=72, angle=angle, rotation_axis=(0.0, 0.0, 1.0),
                                capping=True)
    p = pv.Plotter(off_screen=True, window_size=(1100, 900))
    clim = np.percentile(surf.point_data[label], [0.5, 99.5])
    p.add_mesh(solid, scalars=label, cmap="viridis", clim=clim, ambient=0.35,
               scalar_bar_args={"title": label, "vertical": True})
    if structure is not None and "plate" in structure["profiles"]:
        z0 = -depth_offset
        sc = structure["scene"]
        lines = [np.array([[0.0, 0.0, z0], [sc["plate"]["radius"], 0.0, z0]])]
        if "wall" in sc:
            at = sc["wall"]["radius"]
            lines.append(np.array([[at, 0.0, z0], [at, 0.0, z0 + sc["wall"]["height"]]]))
        for pts in lines:
            shell = pv.lines_from_points(pts).extrude_rotate(
                resolution=72, angle=angle, rotation_axis=(0.0, 0.0, 1.0), capping=False)
            p.add_mesh(shell, color="lightgrey", opacity=0.85, show_edges=False)
    p.add_text(f"{title}\ncut-away, {angle:g} degrees of the axisymmetric solution",
               font_size=11)
    # look into the missing quarter (between `angle` and 360 degrees), from above
    e, zc = extent, -depth_offset - 0.5 * extent
    mid = np.radians(0.5 * (angle + 360.0))
    p.camera_position = [(2.6 * e * np.cos(mid), 2.6 * e * np.sin(mid), zc + 1.8 * e),
                         (0.0, 0.0, zc), (0.0, 0.0, 1.0)]
    p.reset_camera()                    # same direction, zoomed to fit everything
    return save_figure(p, path)


def _member_diagram(pv, base, direction, normal, s, values, scale, color_pos, color_neg):
    """Filled diagram of ``values`` along a member: base + s*direction, offset along normal."""
    pts_base = base[None, :] + s[:, None] * direction[None, :]
    pts_top = pts_base + (scale * values)[:, None] * normal[None, :]
    # one quad per segment, all in one mesh: base points 0..n-1, top points n..2n-1
    n = len(s)
    points = np.column_stack([np.concatenate([pts_base, pts_top]), np.zeros(2 * n)])
    i = np.arange(n - 1)
    faces = np.column_stack([np.full(n - 1, 4), i, i + 1, n + i + 1, n + i]).ravel()
    diagram = pv.PolyData(points, faces=faces)
    diagram.cell_data["sign"] = np.where(values[:-1] + values[1:] >= 0, 1.0, -1.0)
    outline = pv.lines_from_points(np.column_stack([pts_top, np.zeros(len(s))]))
    return diagram, outline


def plot_moment_diagrams(results: dict, path: str | Path, title: str = "") -> Path | None:
    """The engineer's moment diagram drawn on the structure: M_r along the plate (drawn below
    it when sagging) and M_z along the wall (drawn outside it when the outer face is in
    tension), from the gathered profiles of ``results``. Rank 0 writes the PNG."""
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank != 0:
        return None
    pv = offscreen_pyvista()
    sc = results["scene"]
    a, D = sc["plate"]["radius"], sc["plate"].get("embedment", 0.0)
    plate = results["profiles"]["plate"]
    wall = results["profiles"].get("wall")
    # each member at a scale of its own (a wall's moments may be a hundredth of the
    # plate's), stated on the figure
    scale = 0.25 * a / (np.abs(plate["M_r"]).max() or 1.0)
    wall_scale = 0.25 * a / (np.abs(wall["M_z"]).max() or 1.0) if wall else scale
    p = pv.Plotter(off_screen=True, window_size=(1200, 800))
    r = np.asarray(plate["r"])
    diag, outline = _member_diagram(pv, np.array([0.0, -D]), np.array([1.0, 0.0]),
                                    np.array([0.0, -1.0]), r, np.asarray(plate["M_r"]),
                                    scale, "tab:blue", "tab:red")
    p.add_mesh(diag, scalars="sign", cmap=["tab:red", "tab:blue"], show_scalar_bar=False,
               opacity=0.6)
    p.add_mesh(outline, color="black", line_width=2)
    members = [np.array([[0.0, -D, 0.0], [a, -D, 0.0]])]
    if wall is not None:
        at = sc["wall"]["radius"]
        z = np.asarray(wall["z"])
        diag, outline = _member_diagram(pv, np.array([at, -D]), np.array([0.0, 1.0]),
                                        np.array([1.0, 0.0]), z, np.asarray(wall["M_z"]),
                                        wall_scale, "tab:blue", "tab:red")
        p.add_mesh(diag, scalars="sign", cmap=["tab:red", "tab:blue"], show_scalar_bar=False,
                   opacity=0.6)
        p.add_mesh(outline, color="black", line_width=2)
        members.append(np.array([[at, -D, 0.0], [at, -D + z.max(), 0.0]]))
        p.add_point_labels(np.array([[at + 0.05 * a, -D + 0.05 * a, 0.0]]),
                           [f"M_z(base) = {wall['M_z'][0] / 1e3:.3g} kN m/m"], font_size=14,
                           shape_opacity=0.3)
    for m in members:
        p.add_mesh(pv.Line(m[0], m[1]), color="grey", line_width=8)
    p.add_point_labels(np.array([[0.0, -D - scale * plate["M_r"][0], 0.0]]),
                       [f"M0 = {plate['M_r'][0] / 1e3:.3g} kN m/m"], font_size=14,
                       shape_opacity=0.3)
    drawn = [np.array([[0.0, 0.0], [1.3 * a, 0.0]])] + [m[:, :2] for m in members] + \
        [np.asarray(mesh.points)[:, :2] for mesh in p.meshes]
    ground = pv.Line((0.0, 0.0, 0.0), (1.3 * a, 0.0, 0.0))
    p.add_mesh(ground, color="saddlebrown", line_width=2)
    p.add_text(f"{title}\nbending moments (blue: plate underside / wall outer face in "
               f"tension; red: the other face)\nscales: plate {1.0 / (scale * 1e3):.3g} kN m/m "
               f"per m" + (f", wall {1.0 / (wall_scale * 1e3):.3g} kN m/m per m" if wall else
                           ""), font_size=11)
    return save_section(p, path, np.concatenate(drawn))


def plot_load_path(results: dict, path: str | Path, title: str = "") -> Path | None:
    """A load path's settlements (and the plate's centre moment) against the applied
    vertical load, stage by stage (e.g. a tank's filling): from the last stage's results.
    Rank 0 writes the PNG."""
    stages = results.get("stages")
    if not stages:
        return None
    # from the unloaded state (before the first stage nothing is loaded; a soil with an
    # unloading modulus comes back along its unloading lines, not to the origin)
    x = np.array([0.0] + [st["applied_load"] for st in stages]) / 1e3

    def curve(key, scale):
        return [0.0] + [st[key] * scale for st in stages]

    panels = {"settlement [mm]": {"w0 (centre)": curve("w0", 1e3),
                                  "w_edge": curve("w_edge", 1e3)},
              "wd [mm]": {"differential": curve("wd", 1e3)}}
    if stages[-1].get("M0") is not None:
        panels["M0 [kN m/m]"] = {"centre moment": curve("M0", 1e-3)}
    return plot_curves(x, panels, path, "applied vertical load [kN]", title=title)


def plot_consolidation(results: dict, path: str | Path, title: str = "") -> Path | None:
    """A consolidation's settlements (and the plate's centre moment) and its excess pore
    pressure (on the axis, and the largest) against time (log scale, days), between the
    undrained start and the drained limit (dashed); along a load path, the load too. Rank 0
    writes the PNG."""
    c = results.get("consolidation")
    if not c:
        return None
    steps = c["history"][1:]           # t > 0 (the undrained start is a dashed level)
    x = np.array([s["t_days"] for s in steps])

    def curve(key, scale):
        return np.array([s[key] * scale for s in steps])

    # (the undrained start and the drained limit as dashed levels: those of the load, not
    # of a load path's, which starts from none and may end with none)
    on_path = "at_stages" in c
    levels = {} if on_path or c["drained"]["w0"] is None else {
        "w0 undrained": [1e3 * c["undrained"]["w0"]], "w0 drained": [1e3 * c["drained"]["w0"]]}
    panels = {"settlement [mm]": {"w0 (centre)": curve("w0", 1e3),
                                  "w_edge": curve("w_edge", 1e3), **levels},
              "excess pore pressure [kPa]": {
                  f"on the axis, {c['axis_depth']:.3g} m deep": curve("axis_pore_pressure",
                                                                       1e-3),
                  "largest": curve("max_pore_pressure", 1e-3)}}
    if steps[-1].get("M0") is not None:
        panels["M0 [kN m/m]"] = {"centre moment": curve("M0", 1e-3), **({} if not levels else {
            "undrained": [1e-3 * c["undrained"]["M0"]],
            "drained": [1e-3 * c["drained"]["M0"]]})}
    pressures = panels["excess pore pressure [kPa]"]
    for j, (r, depth) in enumerate(c.get("piezometers", {}).get("points", [])):
        pressures[f"piezometer {j + 1} (r = {r:g} m, {depth:g} m deep)"] = np.array(
            [s["piezometers"][j] * 1e-3 for s in steps])
    if on_path:
        milestones = {s["t_days"]: s["collapse"]["strength_factor"]
                      for s in c["at_stages"] if "collapse" in s}
    else:
        milestones = {s["t_days"]: s["collapse"]["strength_factor"]
                      for s in c["at_times"][1:] if "collapse" in s}
    if milestones:
        # (the factor at each milestone, the pore water held: NaN between them)
        panels["factor of safety on c', tan phi'"] = {
            "at each stage's end" if on_path else "at each reported time": np.array(
                [milestones.get(t, np.nan) for t in x]), "1": [1.0]}
    second = None
    if on_path and any(s.get("liquid_height") for s in steps):
        # (the fill against time, beside the settlement it causes)
        second = {"settlement [mm]": ("liquid height [m]", curve("liquid_height", 1.0))}
    elif on_path:                      # the load against time too
        panels["applied vertical load [MN]"] = {"load": curve("applied_load", 1e-6)}
    # (a load path reads in days from its start; a load applied at once in decades)
    return plot_curves(x, panels, path, "time [days]", title=title, log_x=not on_path,
                       legend_left=True, second=second)


def plot_isochrones(results: dict, path: str | Path, title: str = "") -> Path | None:
    """A consolidation's isochrones: the excess pore pressure down the axis at each
    reported time (depth below the ground surface along the horizontal axis). Rank 0
    writes the PNG."""
    c = results.get("consolidation")
    if not c or "isochrones" not in c:
        return None
    iso = c["isochrones"]
    curves = {f"t = {t:.4g} d": 1e-3 * np.asarray(p)
              for t, p in zip(iso["t_days"], iso["pore_pressure"])}
    return plot_curves(iso["z"], {"excess pore pressure on the axis [kPa]": curves}, path,
                       "depth below the ground surface [m]", title=title)


def plot_overturning(results: dict, path: str | Path, wall_path: str | Path | None = None,
                     title: str = "") -> list[Path]:
    """The overturning load's effect (the first harmonic superposed on the axisymmetric
    state): along the plate, the contact stress and the settlement without it, on the side
    pressed down (toe, theta = 0) and on the other (heel); along the wall (``wall_path``),
    its axial membrane stress N_z / t at toe and heel. Rank 0 writes the PNGs."""
    o = results.get("overturning")
    if o is None:
        return []
    plate0, plate1 = results["profiles"]["plate"], o["profiles"]["plate"]
    kpa = 1e-3
    panels = {"contact stress [kPa]": {
                  "axisymmetric": np.asarray(plate0["contact_normal"]) * kpa,
                  "toe (theta = 0)": np.asarray(plate1["contact_normal_toe"]) * kpa,
                  "heel (theta = 180 deg)": np.asarray(plate1["contact_normal_heel"]) * kpa,
                  "no tension": [0.0]},
              "settlement [mm]": {
                  "axisymmetric": np.asarray(plate0["w"]) * 1e3,
                  "toe": np.asarray(plate1["w_toe"]) * 1e3,
                  "heel": np.asarray(plate1["w_heel"]) * 1e3}}
    heading = f"{title}: overturning" if title else "overturning"
    out = [plot_curves(plate1["r"], panels, path, "r [m]", title=heading)]
    wall1 = o["profiles"].get("wall")
    if wall_path is not None and wall1 is not None and "axial_stress_toe" in wall1:
        t = np.asarray(results["profiles"]["wall"]["thickness"])
        mpa = 1e-6
        panels = {"axial stress N_z / t [MPa]": {
            "axisymmetric": np.asarray(results["profiles"]["wall"]["N_z"]) / t * mpa,
            "toe": np.asarray(wall1["axial_stress_toe"]) * mpa,
            "heel": np.asarray(wall1["axial_stress_heel"]) * mpa}}
        out.append(plot_curves(wall1["z"], panels, wall_path, "height above the wall's foot [m]",
                               title=heading))
    return [p for p in out if p is not None]


def plot_tilt(results: dict, path: str | Path, title: str = "",
              exaggeration: float | None = None) -> Path | None:
    """The plate and wall revolved in 3D, displaced by the overturning load alone (its first
    harmonic: u_r, u_z amplitudes times cos theta, u_theta times sin theta), exaggerated
    (by default so that the largest displacement is a tenth of the plate's radius), over
    the undeformed outline and coloured by that settlement: the tank tilting towards
    theta = 0 (+x). (The axisymmetric settlement, tens of times larger in a full tank,
    would hide the tilt.) Rank 0 writes the PNG."""
    from mpi4py import MPI

    o = results.get("overturning")
    if MPI.COMM_WORLD.rank != 0 or o is None:
        return None
    pv = offscreen_pyvista()
    theta = np.linspace(0.0, 2.0 * np.pi, 97)[None, :]
    c, s = np.cos(theta), np.sin(theta)
    members = []
    sc = results["scene"]
    depth = sc["plate"].get("embedment", 0.0)
    for name in ("plate", "wall"):
        if name not in o["profiles"]:
            continue
        p1 = o["profiles"][name]
        if name == "plate":
            r = np.asarray(p1["r"])[:, None]
            z = np.full_like(r, -depth)
            uz = -np.asarray(p1["w"])[:, None] * c
        else:
            z = np.asarray(p1["z"])[:, None] - depth
            r = np.full_like(z, sc["wall"]["radius"])
            uz = np.asarray(p1["u_z"])[:, None] * c
        members.append((r, z, np.asarray(p1["u_r"])[:, None] * c,
                        np.asarray(p1["u_theta"])[:, None] * s, uz))
    a = sc["plate"]["radius"]
    largest = max(np.max(np.abs([ur, ut, uz])) for _, _, ur, ut, uz in members)
    scale = exaggeration if exaggeration is not None else 0.1 * a / max(largest, 1e-300)
    p = pv.Plotter(off_screen=True, window_size=(1100, 850))
    lim = max(np.max(np.abs(uz)) for *_, uz in members) * 1e3
    for r, z, ur, ut, uz in members:
        # the undeformed outline: a few meridians' worth of lines
        k = max(len(r) // 12, 1)
        r_o, z_o = np.append(r[::k], r[-1:], axis=0), np.append(z[::k], z[-1:], axis=0)
        outline = pv.StructuredGrid(r_o * c[:, ::4], r_o * s[:, ::4], z_o + 0.0 * c[:, ::4])
        p.add_mesh(outline, style="wireframe", color="grey", opacity=0.3)
        rr = r + scale * ur
        grid = pv.StructuredGrid(rr * c - scale * ut * s, rr * s + scale * ut * c,
                                 z + scale * uz)
        grid.point_data["settlement [mm]"] = (-uz * 1e3).ravel(order="F")
        p.add_mesh(grid, scalars="settlement [mm]", cmap="coolwarm", clim=(-lim, lim),
                   show_edges=False,
                   scalar_bar_args={"title": "settlement [mm]", "vertical": True})
    p.add_text(f"{title}\nthe overturning's displacements alone (first harmonic), x "
               f"{scale:.3g}: tilt {1e3 * o['tilt']:.3g} mm/m towards +x", font_size=11)
    # from the side (theta = -90 deg) and above, to see the floor through the open top
    p.camera_position = [(0.0, -3.0 * a, 2.2 * a), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    p.reset_camera()
    return save_figure(p, path)


def magnitude(u: fem.Function) -> fem.Function:
    """|u| of a vector field, on its mesh's P1 space."""
    import ufl

    V1 = fem.functionspace(u.function_space.mesh, ("Lagrange", 1))
    out = fem.Function(V1, name="magnitude")
    out.interpolate(fem.Expression(ufl.sqrt(ufl.inner(u, u)),
                                   V1.element.interpolation_points))
    return out


def section_field(solution, quantity: str):
    """The field section.png shows (tankfx.results.fields for the cell fields)."""
    if quantity == "sigma_zz":
        return solution.sigma_zz
    if quantity == "pore_pressure":
        return solution.model.soil.pore_pressure
    return soil_cell_fields(solution.model, solution.statuses)[quantity]


def _consolidation_figures(solution, directory: Path, section: dict, title: str) -> list:
    """A consolidation's figures (as write_figures lists them): its history, its isochrones,
    and the excess pore pressure over the section at each reported time (t = 0 first), the
    yielding cells dotted where the skeleton is elastoplastic."""
    r = solution.results
    figures = [(plot_consolidation, (r, directory / "consolidation.png"), {"title": title}),
               (plot_isochrones, (r, directory / "isochrones.png"), {"title": title})]
    run = (solution.statuses or {}).get("consolidation")
    for k, (t, u_t, p_t, flag) in enumerate(getattr(run, "data", None) and
                                            run.data.fields or []):
        figures.append((plot_section, (u_t, p_t, directory / f"pore_pressure_{k}.png"),
                        section | {"label": "excess pore pressure [kPa]",
                                   "scalar_scale": 1e-3, "structure": None,
                                   "title": f"{title}: t = {t / 86400.0:.4g} days",
                                   **({"marked": (flag, "yielding cells")}
                                      if flag is not None else {})}))
    return figures


def write_figures(solution, directory: str | Path, section_quantity: str = "sigma_zz"
                  ) -> list[Path]:
    """A solved scene's figures in ``directory``: the deformed section coloured by
    ``section_quantity`` (SECTION_QUANTITIES; sigma_zz by default) and, for a nonlinear soil,
    by Kondner's stress level (how near each cell is to the ultimate deviator); the
    settlement profile; with a plate, the moment diagram, the plate's (and wall's) forces
    and the contact stresses; the load path's, consolidation's and overturning's charts
    where the scene has them. Collective; returns the paths written (on rank 0; an empty
    list elsewhere). A figure rank 0 cannot render (no EGL or display) is left out with a
    warning, and the others are still drawn: the other ranks
    take part in every section's gathering whatever rank 0's renderer does. With the
    environment variable STRICT_FIGURES set, such a figure raises RuntimeError after the
    others are drawn."""

    directory = Path(directory)
    r, scene = solution.results, solution.scene
    title = scene.title or ""
    section = {"extent": (1.6 if scene.plate is not None else 3.0) * scene.foundation_radius,
               "depth_offset": scene.embedment, "title": title,
               "soil_cells": solution.domain.cells("soil"), "structure": r,
               "layer_depths": [layer.depth for layer in scene.soil.layers],
               "outlines": ringwall_outline(scene)}
    label, factor = SECTION_QUANTITIES[section_quantity]
    if section_quantity == "stress_level":
        label = scene.soil.law.stress_level_label
    level_view = {"label": scene.soil.law.stress_level_label, "scalar_scale": 1.0}
    if "plastic" in scene.soil.law.reports:
        # (an elastoplastic soil: its yielding cells over its stress level)
        level_view["marked"] = (soil_cell_fields(solution.model, solution.statuses)["plastic"],
                                "yielding cells")
    figures = [(plot_section, (solution.u, section_field(solution, section_quantity),
                               directory / "section.png"),
                section | ({"label": label, "scalar_scale": factor}
                           if section_quantity != "stress_level" else level_view))]
    ring = scene.ringwall
    if ring is not None:
        # the ringwall is small beside the tank: a window around it too
        half = max(2.0 * (ring.outer_radius - ring.inner_radius), 1.5 * ring.depth)
        centre = 0.5 * (ring.inner_radius + ring.outer_radius)
        figures.append((plot_section, (solution.u, solution.sigma_zz,
                                       directory / "ringwall_section.png"),
                        {**section, "r_min": max(centre - half, 0.0), "extent": centre + half,
                         "title": f"{title}: the ringwall"}))
    if "stress_level" in scene.soil.law.reports and section_quantity != "stress_level":
        level = soil_cell_fields(solution.model, solution.statuses)["stress_level"]
        figures.append((plot_section, (solution.u, level, directory / "stress_level.png"),
                        section | level_view))
    if solution.collapse is not None:
        # the collapse: its curve, and its mechanism (the last increment) over the section
        figures.append((plot_collapse, (r, directory / "collapse.png"), {"title": title}))
        du = solution.collapse["increment"]
        if du is not None:
            figures.append((plot_section, (du, magnitude(du), directory / "mechanism.png"),
                            section | {"label": "|du| [mm]", "scalar_scale": 1e3,
                                       "structure": None,     # (drawn at the load's state)
                                       "title": f"{title}: the collapse mechanism (the last "
                                                f"increment)",
                                       "marked": (solution.collapse["plastic"],
                                                  "yielding cells at collapse")}))
    if solution.bounds is not None:
        # the limit analysis: the upper bound's mechanism beside the elastoplastic one (its
        # last increment at the same points: collective) and the bounds' refinement
        elastoplastic = None
        if solution.collapse is not None and solution.collapse["increment"] is not None:
            elastoplastic = evaluate_at(solution.collapse["increment"],
                                        solution.bounds["points"])
        figures.append((plot_bounds, (r, solution.bounds, directory / "bounds.png",
                                      section["extent"]),
                        {"title": title, "elastoplastic": elastoplastic}))
    if "stages" in r:
        figures.append((plot_load_path, (r, directory / "load_path.png"), {"title": title}))
    figures.append((plot_settlement, (r, directory / "settlement.png"), {"title": title}))
    if scene.plate is not None:
        figures += [(plot_moment_diagrams, (r, directory / "moments.png"), {"title": title}),
                    (plot_structure_profiles, (r, directory / "profiles.png"),
                     {"title": title}),
                    (plot_contact, (r, directory / "contact.png"), {"title": title})]
    if "consolidation" in r:
        figures += _consolidation_figures(solution, directory, section, title)
    if "fill" in r:
        figures.append((plot_fill, (r, directory / "fill.png"), {"title": title}))
    if "overturning" in r:
        figures += [(plot_overturning, (r, directory / "overturning.png",
                                        directory / "overturning_wall.png"),
                     {"title": title}),
                    (plot_tilt, (r, directory / "tilt.png"), {"title": title})]
    return _draw(figures)


def _draw(figures) -> list[Path]:
    """Each (plot function, its arguments, its keywords) of ``figures`` drawn: the paths
    written; one that raises is warned of and the others still drawn (STRICT_FIGURES:
    then raised)."""
    written, failed = [], []
    for plot_fn, args, kwargs in figures:
        try:
            path = plot_fn(*args, **kwargs)
        except Exception as e:      # rank 0's rendering, after the gathering
            logging.getLogger("tankfx").warning(
                "%s not written (%s: %s); --no-figures skips the figures", args[-1].name,
                type(e).__name__, e)
            failed.append(f"{args[-1].name} ({type(e).__name__}: {e})")
            continue
        if isinstance(path, list):
            written += path
        elif path is not None:
            written.append(path)
    if failed and os.environ.get(STRICT_FIGURES, "") not in ("", "0"):
        # (after every figure: the other ranks have left their gatherings)
        raise RuntimeError(f"figures not written ({STRICT_FIGURES} is set): "
                           + "; ".join(failed))
    return written
