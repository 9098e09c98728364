"""PyVista figures, off screen to PNG (or on screen when asked and a display is there).

Every figure is built on rank 0 from data gathered across all ranks, never from one rank's
part of the mesh. Call these functions on all ranks; only rank 0 writes a file.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from dolfinx import fem, plot

__all__ = ["gather_grid", "plot_section", "plot_surface_settlement"]

if not os.environ.get("DISPLAY"):
    # no X server: render through EGL rather than let VTK try (and warn about) X first
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def _pyvista():
    import pyvista

    pyvista.OFF_SCREEN = True
    return pyvista


def gather_grid(fields: dict[str, fem.Function], cells: np.ndarray | None = None):
    """A PyVista grid on rank 0 (None elsewhere) of the owned cells of all ranks, carrying the
    given fields interpolated to the mesh vertices (P1)."""
    first = next(iter(fields.values()))
    msh = first.function_space.mesh
    comm = msh.comm
    tdim = msh.topology.dim
    n_owned = msh.topology.index_map(tdim).size_local
    if cells is None:
        cells = np.arange(n_owned, dtype=np.int32)
    cells = cells[cells < n_owned]
    topology, cell_types, x = plot.vtk_mesh(msh, tdim, cells)
    data = {}
    for name, f in fields.items():
        shape = f.function_space.value_shape
        V1 = fem.functionspace(msh, ("Lagrange", 1, shape) if shape else ("Lagrange", 1))
        g = fem.Function(V1)
        g.interpolate(f)
        data[name] = _vertex_values(g, msh)
    parts = comm.gather((topology, cell_types, x, data), root=0)
    if comm.rank != 0:
        return None
    pv = _pyvista()
    grids = []
    for topo, types, pts, vals in parts:
        if len(types) == 0:
            continue
        grid = pv.UnstructuredGrid(topo, types, pts)
        for name, v in vals.items():
            grid.point_data[name] = v if v.shape[1] > 1 else v[:, 0]
        grids.append(grid)
    return grids[0].merge(grids[1:]) if len(grids) > 1 else grids[0]


def _vertex_values(g: fem.Function, msh) -> np.ndarray:
    """Values of a P1 function at the geometry nodes (the points of vtk_mesh)."""
    V = g.function_space
    bs = V.dofmap.index_map_bs
    dofs = V.dofmap.list
    geom = msh.geometry.dofmap
    out = np.zeros((msh.geometry.x.shape[0], bs))
    vals = g.x.array.reshape(-1, bs)
    out[geom.ravel()] = vals[dofs.ravel()]
    return out


def plot_section(u: fem.Function, scalar: fem.Function, path: str | Path, *, extent: float,
                 depth_offset: float = 0.0, label: str = "sigma_zz [kPa]",
                 scalar_scale: float = 1e-3, title: str = "", soil_cells=None) -> Path | None:
    """The (r, z) section within ``extent`` of the foundation centre, deformed (the scale is
    printed on the figure) and coloured by ``scalar``. Returns the PNG path on rank 0."""
    grid = gather_grid({"u": u, "s": scalar}, soil_cells)
    if grid is None:
        return None
    pv = _pyvista()
    near = grid.clip_box([0.0, extent, -depth_offset - extent, 1e9, -1.0, 1.0], invert=False)
    disp = np.zeros((near.n_points, 3))
    disp[:, :2] = near.point_data["u"]
    umax = float(np.abs(disp).max()) or 1.0
    scale = 0.1 * extent / umax
    near.points = near.points + scale * disp
    near.point_data[label] = near.point_data["s"] * scalar_scale
    p = pv.Plotter(off_screen=True, window_size=(1100, 900))
    p.add_mesh(near, scalars=label, cmap="viridis", show_edges=True, edge_color="grey",
               line_width=0.3, scalar_bar_args={"title": label, "vertical": True})
    p.add_text(f"{title}\ndisplacements x {scale:.3g}", font_size=11)
    p.view_xy()
    p.show_bounds(xtitle="r [m]", ytitle="z [m]", location="outer", font_size=10)
    path = Path(path)
    p.screenshot(str(path))
    p.close()
    return path


def plot_surface_settlement(results: dict, path: str | Path, *, reference=None,
                            title: str = "") -> Path | None:
    """Non-dimensional settlement w E_s / (p a) along the ground surface against r / a, with an
    optional reference curve ``reference(r) -> w`` (same units as results). Rank 0 only."""
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank != 0:
        return None
    pv = _pyvista()
    scene = results["scene"]
    a = scene["load"]["load_radius"]
    scale = scene["load"]["pressure"] * a / scene["soil"]["E"]
    r = np.asarray(results["profiles"]["surface"]["r"])
    w = np.asarray(results["profiles"]["surface"]["w"])
    chart = pv.Chart2D(x_label="r / a", y_label="w E_s / (p a)")
    chart.title = title
    chart.line(r / a, w / scale, width=3, color="tab:blue", label="tankfx")
    if reference is not None:
        rr = np.linspace(0.0, r.max(), 60)
        chart.scatter(rr / a, reference(rr) / scale, color="tab:red", size=8,
                      label="closed form")
    p = pv.Plotter(off_screen=True, window_size=(900, 600))
    p.add_chart(chart)
    path = Path(path)
    p.screenshot(str(path))
    p.close()
    return path
