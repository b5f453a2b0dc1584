"""Link geometry: meshes found beside the RSXML file, placed in the world at the zero position;
the link frames (``frames``) and the mass model built on them (``mass``, ``inertia``); convex
pieces for the exports (``convex``), box trees for the collision kernels (``bvh``) and a cable's
rest shape (``cable``)."""

from .mass import DEFAULT_DENSITY, mass_properties
from .meshes import MESH_EXTENSIONS, METRIC_EXTENSIONS, find_mesh, link_mesh, mesh_candidates, part_mesh, part_mesh_path

__all__ = ["DEFAULT_DENSITY", "MESH_EXTENSIONS", "METRIC_EXTENSIONS", "find_mesh", "link_mesh", "mass_properties",
           "mesh_candidates", "part_mesh", "part_mesh_path"]
