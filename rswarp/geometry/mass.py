"""Mass properties of a link from its meshes: volume x density, about the link's frame."""

from __future__ import annotations

import numpy as np

DEFAULT_DENSITY = 2700.0  # kg/m^3, cast aluminium: robot arm castings


def mass_properties(meshes, origin: np.ndarray, density: float = DEFAULT_DENSITY):
    """Mass (kg), centre of mass and inertia about it (link frame at ``origin``, world-aligned) of
    a link's meshes; a mesh that is not watertight is replaced by its convex hull (second result
    False). Returns (mass, com, inertia 3x3, watertight)."""
    import trimesh

    mesh = trimesh.util.concatenate(list(meshes))
    watertight = bool(mesh.is_watertight)
    if not watertight:
        mesh = mesh.convex_hull
    mesh = mesh.copy()
    mesh.apply_translation(-np.asarray(origin, float))
    mesh.density = density
    return float(mesh.mass), np.asarray(mesh.center_mass, float), np.asarray(mesh.moment_inertia, float), watertight
