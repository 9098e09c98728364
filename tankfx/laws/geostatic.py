"""The ground at rest: its geostatic stress from the strata's unit weights, the water table
and K0 (numpy; the scene's checks read it before any mesh)."""
from __future__ import annotations

import math

import numpy as np


def geostatic_stress(soil, depth):
    """(sigma_v, sigma_h), Pa, compression positive, of the ground at rest at ``depth`` (m;
    none above the ground): the weight of the strata above, sum of gamma_i times the part of
    each above the depth, less the pore pressure gamma_w (h - water table) below a water
    table (effective stress), and K0 of the depth's stratum times it."""
    h = np.maximum(np.asarray(depth, dtype=float), 0.0)
    strata = soil.strata
    tops = [st.depth for st in strata]
    bottoms = tops[1:] + [np.inf]
    sigma_v = sum(st.unit_weight * np.clip(h - top, 0.0, bottom - top)
                  for st, top, bottom in zip(strata, tops, bottoms))
    if soil.water_table is not None:
        # effective: less the hydrostatic pore pressure below the water table
        sigma_v = sigma_v - soil.water_unit_weight * np.maximum(h - soil.water_table, 0.0)
    return sigma_v, soil.at_depth(h)["K0"] * sigma_v


def lighter_than_water(soil: dict, layers: list[dict], gamma_w: float,
                       weightless: bool = False) -> list[str]:
    """The strata below a water table that are not heavier than water (their effective
    weight gamma - gamma_w carries the stress at rest), on the tables as read; with
    ``weightless`` a weightless stratum (0) is taken."""
    wt = soil.get("water_table")
    if wt is None:
        return []
    tops = [0.0] + [x.get("depth", 0.0) for x in layers]
    if not all(isinstance(t, (int, float)) for t in tops):
        return []
    bottoms = tops[1:] + [math.inf]
    out = []
    for k, (part, bottom) in enumerate(zip([soil, *layers], bottoms)):
        g = part.get("unit_weight")
        if not isinstance(g, float) or bottom <= wt or g > gamma_w or (weightless and g == 0):
            continue
        where = "soil" if k == 0 else f"soil.layers[{k}]"
        out.append(f"{where}.unit_weight = {g!r}: below the water table (soil.water_table = "
                   f"{wt!r} m) a stratum's unit weight must exceed water's ({gamma_w:g} "
                   f"N/m^3); give its saturated unit weight")
    return out
