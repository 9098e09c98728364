"""The figures read at a glance: the contact stresses' and the section's colour ranges are
not set by the singular peak at the plate's edge (checked against the 99th percentile of
the plotted values), no plotted point falls outside its axes, every axis has a unit, the
settlement profile is drawn with a plate too, and a sweep's charts show what its [charts]
table asks, in its units."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from matplotlib.lines import Line2D

from tankfx import load_scene
from tankfx.analysis import analyse
from tankfx.results import charts
from tankfx.results.figures import colour_range, gather_grid, write_figures

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def steel():
    """The steel tank (coarse): a thin plate whose edge carries a contact peak four times
    the mean bearing pressure."""
    return analyse(load_scene(ROOT / "demos" / "scenes" / "steel_tank.toml").with_coarse_mesh())


@pytest.fixture(scope="module")
def clay_path():
    """The tank on clay, filled along a load path (coarse)."""
    scene = load_scene(ROOT / "demos" / "scenes" / "embedded_tank.toml").with_coarse_mesh()
    stages = [{"liquid_height": h} for h in (3.0, 6.0, 9.0)]
    return analyse(scene.with_changes(stages=stages))


@pytest.fixture(scope="module")
def clay():
    """The tank on soft clay consolidating (coarse)."""
    return analyse(load_scene(ROOT / "demos" / "scenes" / "tank_on_clay.toml").with_coarse_mesh())


def _inside(fig) -> None:
    """Every point of every line of every axes lies within the axes' limits, and every axis
    of a visible panel has a label with a unit (or is a pure number)."""
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
        for line in ax.get_lines():
            assert isinstance(line, Line2D)
            x, y = (np.asarray(v, dtype=float) for v in line.get_data())
            if line.get_transform() != ax.transData:      # (axhline, axvline)
                continue
            ok = np.isfinite(x) & np.isfinite(y)
            tol = 1e-9 * max(x1 - x0, y1 - y0)
            assert np.all((x[ok] >= x0 - tol) & (x[ok] <= x1 + tol)), (ax.get_title(),
                                                                     line.get_label())
            assert np.all((y[ok] >= y0 - tol) & (y[ok] <= y1 + tol)), (ax.get_title(),
                                                                     line.get_label())
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            assert label and ("[" in label or "_bar" in label or label in ("Kp", "Kt")), label


def test_the_contact_range_is_not_set_by_the_edge_peak(steel):
    """The contact normal stress under the steel tank's plate: its axis stops at a stated
    level within 1.5 times the 99th percentile of the values (the peak is 4.6 times the
    mean bearing pressure), and the peak's value is written on the chart."""
    r = steel.results
    sn = np.asarray(r["profiles"]["plate"]["contact_normal"]) / 1e3
    limit, clipped = charts.robust_limit(sn)
    assert clipped and limit < sn.max() and limit <= 1.5 * np.percentile(sn, 99)
    fig = charts.contact_chart(r, "steel tank")
    top = fig.axes[0]
    assert top.get_ylim()[1] < sn.max()
    assert any(t.get_text().startswith(f"peak {sn.max():,.0f} kPa") for t in top.texts)
    _inside(fig)


def test_the_section_colours_are_not_set_by_the_edge_peak(steel):
    """The section's colour range: the 1st to 99th percentiles of the area, at most the
    99th percentile of the nodal values (which crowd at the edge), below their largest."""
    grid = gather_grid({"s": steel.sigma_zz}, steel.domain.cells("soil"))
    a = steel.scene.foundation_radius
    near = grid.clip_box([0.0, 1.6 * a, -1.6 * a, 1e9, -1.0, 1.0], invert=False)
    values = np.asarray(near.point_data["s"])
    lo, hi = colour_range(near, "s")
    assert hi <= np.percentile(values, 99) and hi < values.max()
    assert lo >= np.percentile(values, 1) - 1e-9 * abs(values).max()


def test_no_plotted_point_falls_outside_its_axes(steel, clay_path, clay):
    """The settlement profile (with the plate and the wall's foot, a curve per stage along a
    load path, per reported time of a consolidation: its heave beside the tank too), the
    contact stresses, the members' forces, and a consolidation's curves in time."""
    for r in (steel.results, clay_path.results, clay.results):
        for chart in (charts.settlement_chart, charts.contact_chart, charts.structure_chart):
            _inside(chart(r, "t"))
    fig = charts.settlement_chart(clay_path.results)
    labels = [line.get_label() for line in fig.axes[0].get_lines()]
    assert {"stage 1", "stage 2", "plate"} <= set(labels)
    assert any(label.startswith("wall's foot") for label in labels)
    labels = [line.get_label() for line in charts.settlement_chart(clay.results).axes[0]
              .get_lines()]
    assert {"t = 0 days", "t = 365 days", "drained limit"} <= set(labels)
    c = clay.results["consolidation"]
    steps = c["history"][1:]
    _inside(charts.curves_chart([s["t_days"] for s in steps],
                                {"settlement [mm]": {"w0": [1e3 * s["w0"] for s in steps],
                                                     "drained": [1e3 * c["drained"]["w0"]]}},
                                "time [days]", log_x=True))


def test_each_member_force_has_axes_of_its_own(steel):
    """The plate's moments, and the wall's moment, hoop force, hoop stress (courses) and
    shear, each on its own axes, with its unit."""
    fig = charts.structure_chart(steel.results)
    labels = [ax.get_xlabel() for ax in fig.axes if ax.get_visible()]
    assert labels[0] == "r [m]"
    assert labels[1:] == ["M_z [kN m/m] (outer face in tension +)",
                          "N_theta [kN/m] (tension +)", "hoop stress N_theta / t [MPa]",
                          "Q [kN/m]"]


def test_a_sweep_charts_what_its_table_asks_in_units():
    rows = [{"case": k, "soil.E": E, "interface.condition": c, "converged": True,
             "w0": 0.1 * 1e7 / E, "M0": 1e5 * (1 + k), "nondim.w0": 1.5}
            for k, (E, c) in enumerate([(1e7, "bonded"), (3e7, "bonded"), (1e7, "smooth"),
                                        (3e7, "smooth")])]
    axes = {"soil.E": [1e7, 3e7], "interface.condition": ["bonded", "smooth"]}
    fig = charts.sweep_chart(rows, axes, "soil.E", ["w0", "M0"], "Pa")
    assert [ax.get_xlabel() for ax in fig.axes] == ["soil.E [MPa]"] * 2
    assert [ax.get_ylabel() for ax in fig.axes] == ["centre settlement w0 [mm]",
                                                    "centre moment M0 [kN m/m]"]
    x, y = fig.axes[0].get_lines()[0].get_data()
    np.testing.assert_allclose(x, [10.0, 30.0])
    np.testing.assert_allclose(y, [100.0, 100.0 / 3.0])
    _inside(fig)


def test_a_sweep_file_names_its_charts(tmp_path):
    from tankfx import SceneError, load_sweep

    base = ROOT / "demos" / "scenes" / "flexible_load.toml"
    good = tmp_path / "good.toml"
    good.write_text(f'base = "{base}"\n[axes]\n"soil.E" = [1e7, 2e7]\n'
                    '[charts]\nx = "soil.E"\ny = ["w0", "nondim.w0"]\n')
    sweep = load_sweep(good)
    assert sweep.chart_x == "soil.E" and sweep.chart_y == ("w0", "nondim.w0")
    bad = tmp_path / "bad.toml"
    bad.write_text(f'base = "{base}"\n[axes]\n"soil.E" = [1e7, 2e7]\n'
                   '[charts]\nx = "soil.nu"\ny = ["w00"]\n')
    with pytest.raises(SceneError) as e:
        load_sweep(bad)
    assert "charts.x = 'soil.nu': must be a numeric axis" in str(e.value)
    assert "charts.y: 'w00' is not a result a chart can show (did you mean 'w0'?)" in \
        str(e.value)


def test_the_figures_of_a_tank_are_written(steel, tmp_path):
    written = write_figures(steel, tmp_path)
    assert [p.name for p in written] == ["section.png", "settlement.png", "moments.png",
                                         "profiles.png", "contact.png"]
    assert all(p.stat().st_size > 20_000 for p in written)
    assert not math.isnan(steel.results["bearing_pressure"]["largest"])


def test_the_section_shows_the_quantity_asked(tmp_path):
    """`tankfx run --section deviator` draws it; a quantity the scene has not (a stress
    level of a linear soil) is refused before any work."""
    import subprocess
    import sys

    scene = ROOT / "demos" / "scenes" / "flexible_load.toml"
    run = [sys.executable, "-m", "tankfx", "run", str(scene), "--coarse", "--no-fields"]
    ok = subprocess.run([*run, "--out", str(tmp_path / "a"), "--section", "deviator"],
                        capture_output=True, text=True, timeout=300)
    assert ok.returncode == 0 and (tmp_path / "a" / "section.png").exists()
    bad = subprocess.run([*run, "--out", str(tmp_path / "b"), "--section", "stress_level"],
                         capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and "a stress level is a nonlinear soil's" in bad.stderr
    assert not (tmp_path / "b").exists()


def test_a_figure_that_fails_to_draw_fails(steel, tmp_path, monkeypatch):
    """In the suite (TANKFX_STRICT_FIGURES, set by conftest.py) a plotting error is no
    warning: every other figure is still drawn, then write_figures raises naming the one
    that failed, so that no figure can break silently."""
    from tankfx.results import figures as plots

    def broken(r, path, **kwargs):
        raise KeyError("w_edge")

    monkeypatch.setattr(plots, "plot_contact", broken)
    with pytest.raises(RuntimeError, match=r"contact.png \(KeyError: 'w_edge'\)"):
        plots.write_figures(steel, tmp_path)
    assert (tmp_path / "moments.png").exists()
