"""Finite-element limit analysis: a lower and an upper bound on the collapse load by conic
optimisation (Clarabel), refined where they differ. ``lower`` and ``upper`` are the two
programs, ``adapt`` the refinement, ``scene_bounds`` what a scene asks of them."""
