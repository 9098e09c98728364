"""The ground at rest: its geostatic stress from the strata's unit weights, the water table
and K0 (numpy; the scene's checks read it before any mesh)."""
from __future__ import annotations

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
