"""What the figures can show, checked before any work is done: the files a run may draw, the
quantities its section may be coloured by, and the results a sweep's chart may plot.

No plotting library is imported here (nor by anything this imports): the command line and the
sweeps check a user's choices of figures with it, and import the drawing modules
(:mod:`tankfx.results.figures`, :mod:`tankfx.results.charts`, with PyVista and matplotlib)
only where a figure is drawn, so that ``import tankfx`` and ``tankfx run --no-figures`` stay
free of them.
"""
from __future__ import annotations

from ..laws.soil_law import words
from ..laws.soil_laws import SOIL_LAWS

#: The figures ``write_figures`` may write (which ones depends on the scene).
FIGURES = ("section.png", "stress_level.png", "settlement.png", "moments.png", "profiles.png",
           "contact.png", "load_path.png", "overturning.png", "overturning_wall.png",
           "tilt.png", "consolidation.png", "isochrones.png", "collapse.png", "mechanism.png",
           "bounds.png")


#: the quantities section.png can show: name -> (its label, the factor to its unit)
SECTION_QUANTITIES = {"sigma_zz": ("sigma_zz [kPa]", 1e-3),
                      "deviator": ("s1 - s3 [kPa]", 1e-3),
                      "stress_level": ("q / q_ult", 1.0),
                      "pore_pressure": ("excess p [kPa]", 1e-3)}


def section_problem(scene, quantity: str) -> str | None:
    """Why section.png cannot show ``quantity`` for this scene (None if it can)."""
    if quantity not in SECTION_QUANTITIES:
        return (f"--section {quantity}: one of {', '.join(SECTION_QUANTITIES)}")
    if quantity == "stress_level" and "stress_level" not in scene.soil.law.reports:
        return (f"--section stress_level: a stress level is a nonlinear soil's (soil.model = "
                f"{words(SOIL_LAWS.values(), lambda law: 'stress_level' in law.reports)}); "
                f"choose sigma_zz or deviator")
    if quantity == "pore_pressure" and scene.consolidation is None:
        return ("--section pore_pressure: an excess pore pressure needs a [consolidation]; "
                "choose sigma_zz or deviator")
    return None


#: the results a sweep's charts can show: key (dotted, as in table.csv) -> (what it is,
#: factor to the shown unit, the unit)
CHARTABLE: dict[str, tuple[str, float, str]] = {
    "w0": ("centre settlement w0", 1e3, "mm"),
    "w_edge": ("edge settlement w_edge", 1e3, "mm"),
    "wd": ("differential settlement wd", 1e3, "mm"),
    "w_mean": ("mean settlement", 1e3, "mm"),
    "M0": ("centre moment M0", 1e-3, "kN m/m"),
    "junction.M_wall": ("wall base moment", 1e-3, "kN m/m"),
    "junction.M_plate": ("plate moment at the joint", 1e-3, "kN m/m"),
    "bearing_pressure.mean": ("mean bearing pressure", 1e-3, "kPa"),
    "bearing_pressure.largest": ("largest bearing pressure", 1e-3, "kPa"),
    "nondim.w0": ("w0_bar = w0 E_s / (p a)", 1.0, ""),
    "nondim.wd": ("wd_bar = wd E_s / (p a)", 1.0, ""),
    "nondim.M0": ("M0_bar = M0 / (p a^2)", 1.0, ""),
    "nondim.Kp": ("Kp", 1.0, ""),
    "nondim.Kt": ("Kt", 1.0, ""),
    "overturning.tilt": ("tilt", 1e3, "mm/m"),
    "overturning.rocking_stiffness": ("rocking stiffness", 1e-9, "GN m/rad"),
    "consolidation.degree": ("degree of consolidation", 1.0, ""),
    "consolidation.undrained.w0": ("undrained w0", 1e3, "mm"),
    "consolidation.drained.w0": ("drained w0", 1e3, "mm"),
    "collapse.load_factor": ("factor of safety on the loads", 1.0, ""),
    "collapse.strength_factor": ("factor of safety on the strength", 1.0, ""),
    "collapse.N_c": ("N_c = q_ult / s_u", 1.0, ""),
    "collapse.bearing_pressure": ("bearing pressure at collapse", 1e-3, "kPa"),
    "bounds.lower": ("collapse factor, lower bound", 1.0, ""),
    "bounds.upper": ("collapse factor, upper bound", 1.0, ""),
}
#: the charts of a sweep without a [charts] table: dimensional
DEFAULT_CHARTS = ("w0", "wd", "M0")


def numeric_axes(axes: dict) -> list[str]:
    """A sweep's axes whose values are all numbers (the ones a chart can plot against)."""
    return [k for k, v in axes.items() if isinstance(v, list) and v and all(
        isinstance(e, (int, float)) and not isinstance(e, bool) for e in v)]
