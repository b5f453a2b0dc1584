"""Link geometry: meshes found beside the RSXML file, placed in the world at the zero position,
and the mass properties computed from them."""

from .mass import DEFAULT_DENSITY, mass_properties
from .meshes import MESH_EXTENSIONS, METRIC_EXTENSIONS, find_mesh, link_mesh, mesh_candidates, part_mesh, part_mesh_path

__all__ = ["DEFAULT_DENSITY", "MESH_EXTENSIONS", "METRIC_EXTENSIONS", "find_mesh", "link_mesh", "mass_properties",
           "mesh_candidates", "part_mesh", "part_mesh_path"]
