"""Whether a solved stage lies within its model's range, part by part: small strains (the
settlement and the rotations small beside the foundation), and an overturning load that
keeps the heel in contact (the first harmonic is superposed on a linearised contact). A
result outside is still reported, but marked not valid (``results["validity"]``), said in
the summary, and ``tankfx run`` ends with exit code 4.
"""
from __future__ import annotations

import numpy as np

#: small-strain theory: the largest settlement over the foundation's radius, and the
#: largest rotation of the plate's or wall's meridian (rad), beyond which the geometry's
#: change is no longer negligible (the equilibrium is written on the undeformed shape; a
#: plate-load test calls a settlement of a tenth of the diameter failure: a fifth of the
#: radius; half of that is the bound here)
SMALL_STRAIN_SETTLEMENT = 0.1
SMALL_STRAIN_ROTATION = 0.05


def validity(results: dict, foundation_radius: float) -> dict:
    """``{"valid": bool, "parts": {part: bool}, "notes": [why a part is not valid]}`` of a
    stage's results (with its overturning, where it has one)."""
    parts, notes = {}, []
    prof = results["profiles"]
    w = np.abs(np.concatenate([prof["surface"]["w"], prof.get("plate", {}).get("w", [])]))
    w_max = float(w.max(initial=0.0))
    rotations = [np.abs(prof[m]["rotation"]).max(initial=0.0) for m in ("plate", "wall")
                 if m in prof]
    rot = float(max(rotations, default=0.0))
    parts["small_strain"] = bool(w_max <= SMALL_STRAIN_SETTLEMENT * foundation_radius
                                 and rot <= SMALL_STRAIN_ROTATION)
    if not parts["small_strain"]:
        notes.append(f"small strains: the largest settlement is {w_max:.4g} m "
                     f"({w_max / foundation_radius:.3g} of the foundation's radius) and the "
                     f"largest rotation {rot:.3g} rad; beyond {SMALL_STRAIN_SETTLEMENT:g} a and "
                     f"{SMALL_STRAIN_ROTATION:g} rad the geometry's change is not negligible and "
                     f"the soil's strains leave the range of its law: check the soil's modulus "
                     f"and the loads")
    if "overturning" in results:
        uplift = results["overturning"]["uplift"]
        parts["overturning"] = not uplift["lifts"]
        if uplift["lifts"]:
            notes.append(f"overturning: the heel lifts at {uplift['onset_factor']:.3g} x the "
                         f"overturning load; the superposed results there do not hold")
    return {"valid": all(parts.values()), "parts": parts, "notes": notes}
