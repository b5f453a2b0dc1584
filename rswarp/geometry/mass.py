"""Mass properties of a link from its meshes: volume x density, about the link's frame."""

from __future__ import annotations

import numpy as np

DEFAULT_DENSITY = 2700.0  # kg/m^3, cast aluminium: robot arm castings


def mass_properties(meshes, origin: np.ndarray, density: float = DEFAULT_DENSITY):
    """Mass (kg), centre of mass and inertia about it (link frame at ``origin``, world-aligned) of
    a link's meshes; a mesh that is not watertight is replaced by its convex hull (second result
    False). Returns (mass, com, inertia 3x3, watertight)."""
    import trimesh

    meshes = list(meshes)
    mesh = meshes[0] if len(meshes) == 1 else trimesh.util.concatenate(meshes)
    watertight = closed(np.asarray(mesh.faces), len(mesh.vertices))
    if not watertight:
        mesh = mesh.convex_hull
    mesh = trimesh.Trimesh(np.asarray(mesh.vertices) - np.asarray(origin, float), mesh.faces, process=False,
                           validate=False)
    mesh.density = density
    return float(mesh.mass), np.asarray(mesh.center_mass, float), np.asarray(mesh.moment_inertia, float), watertight


def closed(faces: np.ndarray, n_vertices: int) -> bool:
    """Whether every edge is shared by exactly two triangles (a closed surface), computed on packed
    integer edge keys: light on memory for meshes of millions of triangles."""
    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1).astype(np.int64)
    keys = np.sort(edges[:, 0] * n_vertices + edges[:, 1])
    if len(keys) % 2:
        return False
    return bool(np.all(keys[0::2] == keys[1::2]) and np.all(keys[1:-1:2] != keys[2::2]))
