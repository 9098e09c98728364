"""Parametric gmsh geometries of tankfx (installed as ``tankfx.meshes``)."""
